//! The summary of the sweep: per variant and family, the solve time needed to
//! reach a profile error (interpolated log-log on the family's Pareto front),
//! and the ratio "peer time / axijoint time at equal profile error" (the
//! peer's error against axijoint's reference, axijoint's time interpolated
//! on the variant's front over all its methods). Wall and CPU times each
//! have their own front.

use crate::pareto::{cost_at_error, front};
use crate::sweep::Row;
use anyhow::Result;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Errors whose cost the summary reports.
pub const TARGETS: [f64; 2] = [1e-2, 1e-3];

/// The goal for the peer's finest level: peer time / axijoint time.
pub const RATIO_GOAL: f64 = 1000.0;

/// One line of `accuracy_summary.csv`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SummaryRow {
    /// "time_to_error" or "peer_ratio".
    pub kind: String,
    /// Scene P variant.
    pub variant: String,
    /// Family ("paper", "anderson", "newton", "linear", "all": every
    /// axijoint method) or, for a ratio, "calculix size S".
    pub family: String,
    /// The error: a target, or the peer run's error vs axijoint's reference.
    pub error: f64,
    /// axijoint solve wall time at that error (s) (empty: not reached).
    pub axijoint_wall_s: Option<f64>,
    /// axijoint solve CPU time at that error (s).
    pub axijoint_cpu_s: Option<f64>,
    /// True when even the cheapest run was below the error: the time is an
    /// upper bound.
    pub upper_bound: bool,
    /// The peer's solve wall time (mesh + ccx) (s).
    pub peer_wall_s: Option<f64>,
    /// The peer's solve CPU time (s).
    pub peer_cpu_s: Option<f64>,
    /// peer_wall_s / axijoint_wall_s.
    pub ratio_wall: Option<f64>,
    /// peer_cpu_s / axijoint_cpu_s.
    pub ratio_cpu: Option<f64>,
    /// True for the ratio of the peer's finest level of the variant.
    #[serde(default)]
    pub peer_finest: bool,
    /// The peer's ccx wall time alone (no meshing) (s).
    #[serde(default)]
    pub peer_warm_wall_s: Option<f64>,
    /// axijoint solve wall time with the mesh cache warm at that error (s).
    #[serde(default)]
    pub axijoint_warm_wall_s: Option<f64>,
    /// peer_warm_wall_s / axijoint_warm_wall_s.
    #[serde(default)]
    pub ratio_warm_wall: Option<f64>,
}

/// The front of `rows` in (time, error), time read by `t`.
fn front_of(rows: &[&Row], t: impl Fn(&Row) -> Option<f64>) -> Vec<(f64, f64)> {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.ok())
        .filter_map(|r| Some((t(r)?, r.err_vs_axijoint_ref?)))
        .collect();
    front(&pts).into_iter().map(|i| pts[i]).collect()
}

/// The summary rows of a sweep.
pub fn summarize(rows: &[Row]) -> Vec<SummaryRow> {
    let mut variants: Vec<&str> = Vec::new();
    for r in rows {
        if !variants.contains(&r.variant.as_str()) {
            variants.push(&r.variant);
        }
    }
    let mut out = Vec::new();
    for v in variants {
        let ax: Vec<&Row> = rows
            .iter()
            .filter(|r| r.variant == v && r.tool == "axijoint")
            .collect();
        let mut families: Vec<String> = Vec::new();
        for r in &ax {
            if !families.contains(&r.family()) {
                families.push(r.family());
            }
        }
        if families.len() > 1 {
            families.push("all".into());
        }
        for fam in &families {
            let sel: Vec<&Row> = ax
                .iter()
                .copied()
                .filter(|r| fam == "all" || r.family() == *fam)
                .collect();
            let fw = front_of(&sel, |r| r.solve_wall_s);
            let fc = front_of(&sel, |r| r.solve_cpu_s);
            for target in TARGETS {
                let w = cost_at_error(&fw, target);
                let c = cost_at_error(&fc, target);
                out.push(SummaryRow {
                    kind: "time_to_error".into(),
                    variant: v.into(),
                    family: fam.clone(),
                    error: target,
                    axijoint_wall_s: w.map(|x| x.0),
                    axijoint_cpu_s: c.map(|x| x.0),
                    upper_bound: w.is_some_and(|x| x.1) || c.is_some_and(|x| x.1),
                    ..SummaryRow::default()
                });
            }
        }
        let fw = front_of(&ax, |r| r.solve_wall_s);
        let fc = front_of(&ax, |r| r.solve_cpu_s);
        let fwarm = front_of(&ax, |r| r.solve_warm_wall_s);
        let peers: Vec<&Row> = rows
            .iter()
            .filter(|r| r.variant == v && r.tool == "calculix" && r.ok())
            .collect();
        let finest = peers.iter().map(|r| r.size).min_by(f64::total_cmp);
        for p in peers {
            let Some(e) = p.err_vs_axijoint_ref else { continue };
            let w = cost_at_error(&fw, e);
            let c = cost_at_error(&fc, e);
            let warm = cost_at_error(&fwarm, e);
            let ratio = |peer: Option<f64>, ax: Option<(f64, bool)>| Some(peer? / ax?.0);
            out.push(SummaryRow {
                kind: "peer_ratio".into(),
                variant: v.into(),
                family: format!("calculix size {}", p.size),
                error: e,
                axijoint_wall_s: w.map(|x| x.0),
                axijoint_cpu_s: c.map(|x| x.0),
                upper_bound: [w, c, warm].iter().any(|x| x.is_some_and(|x| x.1)),
                peer_wall_s: p.solve_wall_s,
                peer_cpu_s: p.solve_cpu_s,
                ratio_wall: ratio(p.solve_wall_s, w),
                ratio_cpu: ratio(p.solve_cpu_s, c),
                peer_finest: Some(p.size) == finest,
                peer_warm_wall_s: p.solve_warm_wall_s,
                axijoint_warm_wall_s: warm.map(|x| x.0),
                ratio_warm_wall: ratio(p.solve_warm_wall_s, warm),
            });
        }
    }
    out
}

/// Writes the summary CSV atomically.
pub fn write_summary_csv(path: &Path, rows: &[SummaryRow]) -> Result<()> {
    crate::csv_io::write_rows(path, rows)
}

/// The summary as a console table.
pub fn format_table(rows: &[SummaryRow]) -> String {
    let f = |x: Option<f64>| x.map_or("-".to_owned(), |v| format!("{v:.3}"));
    let mut s = String::new();
    s.push_str("solve time to reach a profile error (log-log on the Pareto front; '<=': the cheapest run is already below it)\n");
    s.push_str(&format!(
        "{:<10} {:<10} {:>8} {:>12} {:>12}\n",
        "variant", "family", "error", "wall [s]", "CPU [s]"
    ));
    for r in rows.iter().filter(|r| r.kind == "time_to_error") {
        let b = if r.upper_bound { "<=" } else { "" };
        s.push_str(&format!(
            "{:<10} {:<10} {:>8} {:>12} {:>12}\n",
            r.variant,
            r.family,
            format!("{}", r.error),
            format!("{b}{}", f(r.axijoint_wall_s)),
            format!("{b}{}", f(r.axijoint_cpu_s))
        ));
    }
    let ratios: Vec<&SummaryRow> = rows.iter().filter(|r| r.kind == "peer_ratio").collect();
    if !ratios.is_empty() {
        s.push_str(
            "\nCalculiX 3D peer against axijoint at equal profile error (peer error vs axijoint reference)\n",
        );
        s.push_str(&format!(
            "{:<10} {:<22} {:>9} {:>10} {:>10} {:>9} {:>10} {:>10} {:>9}\n",
            "variant", "peer", "error", "peer wall", "axi wall", "ratio", "peer CPU", "axi CPU", "ratio"
        ));
        for r in ratios {
            s.push_str(&format!(
                "{:<10} {:<22} {:>9.4} {:>10} {:>10} {:>9} {:>10} {:>10} {:>9}\n",
                r.variant,
                r.family,
                r.error,
                f(r.peer_wall_s),
                f(r.axijoint_wall_s),
                f(r.ratio_wall),
                f(r.peer_cpu_s),
                f(r.axijoint_cpu_s),
                f(r.ratio_cpu)
            ));
        }
    }
    s
}

/// Per variant, the peer's finest level against axijoint at its profile
/// error, and whether the ratio reaches [`RATIO_GOAL`]: with meshing (peer
/// gmsh + ccx, `axijoint solve --no-cache`) and without (ccx alone,
/// `axijoint solve` with the mesh cache warm).
pub fn format_ratio_table(rows: &[SummaryRow]) -> String {
    let f = |x: Option<f64>| x.map_or("-".to_owned(), |v| format!("{v:.4}"));
    let r0 = |x: Option<f64>| x.map_or("-".to_owned(), |v| format!("{v:.0}"));
    let goal = |x: Option<f64>| match x {
        Some(v) if v >= RATIO_GOAL => "yes",
        Some(_) => "no",
        None => "-",
    };
    let mut s = format!(
        "peer's finest level / axijoint at the same profile error (goal >= {RATIO_GOAL}; '<=': axijoint's cheapest run is already below the error)\n"
    );
    s.push_str(&format!(
        "{:<13} {:<19} {:>8} {:>9} {:>10} {:>7} {:>4} {:>9} {:>10} {:>7} {:>4}\n",
        "variant",
        "peer",
        "error",
        "peer [s]",
        "axi [s]",
        "ratio",
        "goal",
        "ccx [s]",
        "axi warm",
        "ratio",
        "goal"
    ));
    for r in rows.iter().filter(|r| r.kind == "peer_ratio" && r.peer_finest) {
        let b = if r.upper_bound { "<=" } else { "" };
        s.push_str(&format!(
            "{:<13} {:<19} {:>7.2}% {:>9.2} {:>10} {:>7} {:>4} {:>9.2} {:>10} {:>7} {:>4}\n",
            r.variant,
            r.family,
            100.0 * r.error,
            r.peer_wall_s.unwrap_or(f64::NAN),
            format!("{b}{}", f(r.axijoint_wall_s)),
            r0(r.ratio_wall),
            goal(r.ratio_wall),
            r.peer_warm_wall_s.unwrap_or(f64::NAN),
            format!("{b}{}", f(r.axijoint_warm_wall_s)),
            r0(r.ratio_warm_wall),
            goal(r.ratio_warm_wall),
        ));
    }
    s
}
