//! Profile errors: axijoint's cut CSVs read into [`Profile`]s, and the
//! relative L2 difference of a set of profiles against a reference set.
//!
//! The error of a run against a reference is
//!
//! ```text
//! e = sqrt( sum_p sum_b Integral (s - s_ref)^2 dr  /  sum_p sum_b Integral s_ref^2 dr )
//! ```
//!
//! over the profiles p (a-a and b-b at theta 0 and 180) and the bodies b of
//! each profile. Each body is interpolated linearly in r on its own samples
//! (a profile has two samples at the interface r = a, one per body: values
//! are never interpolated across it), both sides are evaluated on the union
//! of the two sample sets within the r range they share, and the integrals
//! use the trapezoid rule on those points.

use crate::profile::{Profile, Sample};
use anyhow::{bail, Context, Result};
use std::path::Path;

/// The cuts and angles of Scene P compared by the study: (cut, theta, component).
pub const SCENE_P_PROFILES: [(&str, f64, &str); 4] = [
    ("a-a", 0.0, "sigma_z"),
    ("a-a", 180.0, "sigma_z"),
    ("b-b", 0.0, "sigma_r"),
    ("b-b", 180.0, "sigma_r"),
];

/// Reads one of axijoint's cut CSVs (`cut_<name>_theta<deg>.csv`, see
/// docs/outputs.md) into a profile of `component` (a column name without its
/// unit, e.g. `sigma_z`). The cut name is `cut`; the angle is read from the
/// file. Samples keep the file's order.
pub fn read_cut_csv(path: &Path, cut: &str, component: &str) -> Result<Profile> {
    let mut rdr = csv::Reader::from_path(path).with_context(|| format!("cannot read {}", path.display()))?;
    let headers = rdr
        .headers()
        .with_context(|| format!("{}: no header", path.display()))?
        .clone();
    let col = |name: &str| -> Result<usize> {
        headers
            .iter()
            .position(|h| h == name || h.split(" [").next() == Some(name))
            .with_context(|| format!("{}: no column '{name}' in the header", path.display()))
    };
    let (ir, itheta, ibody, ivalue) = (col("r")?, col("theta")?, col("body")?, col(component)?);
    let mut samples = Vec::new();
    let mut theta = None;
    for (line, rec) in rdr.records().enumerate() {
        let rec = rec.with_context(|| format!("{}: record {}", path.display(), line + 1))?;
        let num = |i: usize| -> Result<f64> {
            let s = rec.get(i).unwrap_or("");
            s.trim()
                .parse::<f64>()
                .with_context(|| format!("{}: record {}: '{s}' is not a number", path.display(), line + 1))
        };
        let t = num(itheta)?;
        match theta {
            None => theta = Some(t),
            Some(t0) if t0 != t => bail!("{}: more than one angle ({t0} and {t})", path.display()),
            _ => {}
        }
        samples.push(Sample {
            r: num(ir)?,
            body: rec.get(ibody).unwrap_or("").to_owned(),
            value: num(ivalue)?,
        });
    }
    let Some(theta_deg) = theta else {
        bail!("{}: no samples", path.display());
    };
    Ok(Profile {
        cut: cut.to_owned(),
        theta_deg,
        component: component.to_owned(),
        samples,
    })
}

/// Reads the four Scene P profiles ([`SCENE_P_PROFILES`]) from an axijoint
/// output folder (`cut_a-a_theta0.csv`, ...).
pub fn read_scene_p_profiles(dir: &Path) -> Result<Vec<Profile>> {
    SCENE_P_PROFILES
        .iter()
        .map(|&(cut, theta, component)| {
            read_cut_csv(&dir.join(format!("cut_{cut}_theta{theta}.csv")), cut, component)
        })
        .collect()
}

/// The integrals of one profile against its reference: `(Integral (s -
/// s_ref)^2 dr, Integral s_ref^2 dr)`, summed over the reference's bodies.
/// A body of the reference missing from `run`, or with no common r range,
/// is an error.
pub fn profile_integrals(run: &Profile, reference: &Profile) -> Result<(f64, f64)> {
    let mut num = 0.0;
    let mut den = 0.0;
    for body in bodies(reference) {
        let a = body_curve(run, &body);
        let b = body_curve(reference, &body);
        if a.is_empty() {
            bail!(
                "profile {} theta {}: body '{body}' has no samples in the run",
                reference.cut,
                reference.theta_deg
            );
        }
        let lo = a[0].0.max(b[0].0);
        let hi = a[a.len() - 1].0.min(b[b.len() - 1].0);
        if hi <= lo {
            bail!(
                "profile {} theta {}: body '{body}' covers r in [{}, {}] in the run and [{}, {}] in the reference: no common range",
                reference.cut,
                reference.theta_deg,
                a[0].0,
                a[a.len() - 1].0,
                b[0].0,
                b[b.len() - 1].0
            );
        }
        let mut rs: Vec<f64> = a
            .iter()
            .chain(b.iter())
            .map(|p| p.0)
            .filter(|&r| r >= lo && r <= hi)
            .collect();
        rs.push(lo);
        rs.push(hi);
        rs.sort_by(f64::total_cmp);
        rs.dedup_by(|x, y| (*x - *y).abs() <= 1e-12 * (1.0 + y.abs()));
        let d2: Vec<f64> = rs
            .iter()
            .map(|&r| (interp(&a, r) - interp(&b, r)).powi(2))
            .collect();
        let s2: Vec<f64> = rs.iter().map(|&r| interp(&b, r).powi(2)).collect();
        num += trapezoid(&rs, &d2);
        den += trapezoid(&rs, &s2);
    }
    Ok((num, den))
}

/// Relative L2 error of the profiles `run` against `reference` (matched by
/// cut and angle; every reference profile must have a partner in `run`).
pub fn relative_error(run: &[Profile], reference: &[Profile]) -> Result<f64> {
    if reference.is_empty() {
        bail!("no reference profiles");
    }
    let mut num = 0.0;
    let mut den = 0.0;
    for r in reference {
        let p = run
            .iter()
            .find(|p| p.cut == r.cut && p.theta_deg == r.theta_deg)
            .with_context(|| format!("the run has no profile {} at theta {}", r.cut, r.theta_deg))?;
        let (n, d) = profile_integrals(p, r)?;
        num += n;
        den += d;
    }
    if den <= 0.0 {
        bail!("the reference profiles are zero");
    }
    Ok((num / den).sqrt())
}

/// Bodies of a profile in order of first appearance.
fn bodies(p: &Profile) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for s in &p.samples {
        if !out.contains(&s.body) {
            out.push(s.body.clone());
        }
    }
    out
}

/// `(r, value)` of one body, sorted by r.
fn body_curve(p: &Profile, body: &str) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64)> = p
        .samples
        .iter()
        .filter(|s| s.body == body)
        .map(|s| (s.r, s.value))
        .collect();
    v.sort_by(|x, y| x.0.total_cmp(&y.0));
    v
}

/// Piecewise-linear interpolation of sorted `(r, value)` at `r`, clamped at
/// the ends.
fn interp(curve: &[(f64, f64)], r: f64) -> f64 {
    let i = curve.partition_point(|p| p.0 < r);
    if i == 0 {
        return curve[0].1;
    }
    if i == curve.len() {
        return curve[curve.len() - 1].1;
    }
    let (r0, v0) = curve[i - 1];
    let (r1, v1) = curve[i];
    if r1 == r0 {
        return v1;
    }
    v0 + (v1 - v0) * (r - r0) / (r1 - r0)
}

/// Trapezoid rule of `y` over sorted `x`.
fn trapezoid(x: &[f64], y: &[f64]) -> f64 {
    x.windows(2)
        .zip(y.windows(2))
        .map(|(x, y)| 0.5 * (x[1] - x[0]) * (y[0] + y[1]))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn profile(body_points: &[(&str, &[(f64, f64)])]) -> Profile {
        Profile::from_bodies("a-a", 0.0, "sigma_z", body_points)
    }

    #[test]
    fn shifted_line_has_the_trapezoid_closed_form() {
        // s_ref = r on {0, 0.5, 1}, s = r + 0.1: Integral 0.01 dr = 0.01 and
        // the trapezoid rule gives Integral r^2 dr = 0.0625 + 0.3125 = 0.375.
        let reference = profile(&[("pile", &[(0.0, 0.0), (0.5, 0.5), (1.0, 1.0)])]);
        let run = profile(&[("pile", &[(0.0, 0.1), (0.5, 0.6), (1.0, 1.1)])]);
        let e = relative_error(&[run], &[reference]).unwrap();
        assert!((e - (0.01f64 / 0.375).sqrt()).abs() < 1e-14, "{e}");
    }

    #[test]
    fn no_interpolation_across_the_interface() {
        // Pile 1 on [0, 0.5], footing 3 on [0.5, 1]: a run equal to it has
        // error 0, although interpolating across r = 0.5 would not.
        let reference = profile(&[
            ("pile", &[(0.0, 1.0), (0.5, 1.0)]),
            ("footing", &[(0.5, 3.0), (1.0, 3.0)]),
        ]);
        let run = profile(&[
            ("pile", &[(0.0, 1.0), (0.25, 1.0), (0.5, 1.0)]),
            ("footing", &[(0.5, 3.0), (0.75, 3.0), (1.0, 3.0)]),
        ]);
        assert_eq!(relative_error(&[run], &[reference]).unwrap(), 0.0);
    }
}
