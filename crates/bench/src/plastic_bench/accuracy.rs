//! Equal accuracy: the reference reaction at 0.1 D, every run's error
//! against it, and the peer's wall time against axijoint's at equal error.

use super::PlasticRow;

/// The reference reaction at 0.1 D and how it was found.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    /// R_ref (MN).
    pub reaction: f64,
    /// How: "peer extrapolated (p = ...)" or "finest peer (h = ...)".
    pub how: String,
}

/// R(h) = R_0 + C h^p through three points (h1 > h2 > h3), if the
/// differences have one sign and shrink: (R_0, p).
pub fn extrapolate(points: [(f64, f64); 3]) -> Option<(f64, f64)> {
    let [(h1, r1), (h2, r2), (h3, r3)] = points;
    if !(h1 > h2 && h2 > h3 && h3 > 0.0) {
        return None;
    }
    let (d12, d23) = (r1 - r2, r2 - r3);
    if d12 * d23 <= 0.0 {
        return None;
    }
    let target = d12 / d23;
    let g = |p: f64| (h1.powf(p) - h2.powf(p)) / (h2.powf(p) - h3.powf(p));
    let (mut lo, mut hi) = (0.05, 8.0);
    if !(g(lo) <= target && target <= g(hi)) {
        return None;
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if g(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let p = 0.5 * (lo + hi);
    let r0 = r3 - d23 * h3.powf(p) / (h2.powf(p) - h3.powf(p));
    Some((r0, p))
}

/// The successful runs of `code` and `law` with a reaction, coarse to fine.
fn runs<'a>(rows: &'a [PlasticRow], code: &str, law: &str) -> Vec<&'a PlasticRow> {
    let mut v: Vec<&PlasticRow> = rows
        .iter()
        .filter(|r| r.code == code && r.law == law && r.ok() && r.reaction_mn.is_some())
        .collect();
    v.sort_by(|a, b| b.size.total_cmp(&a.size));
    v
}

/// [`extrapolate`] of the three finest runs of `code` and `law`: (R_0, p,
/// the three sizes).
pub fn extrapolated(rows: &[PlasticRow], code: &str, law: &str) -> Option<(f64, f64, [f64; 3])> {
    let v = runs(rows, code, law);
    let n = v.len();
    if n < 3 {
        return None;
    }
    let pts = [n - 3, n - 2, n - 1].map(|i| (v[i].size, v[i].reaction_mn.unwrap_or(f64::NAN)));
    extrapolate(pts).map(|(r0, p)| (r0, p, pts.map(|x| x.0)))
}

/// The peer's two finest runs extrapolated with the order `p`:
/// R_0 = R_2 - (R_1 - R_2) h_2^p / (h_1^p - h_2^p); (R_0, h_1, h_2).
pub fn peer_two_point(rows: &[PlasticRow], p: f64) -> Option<(f64, f64, f64)> {
    let v = runs(rows, "calculix", "mises");
    let n = v.len();
    if n < 2 {
        return None;
    }
    let (h1, r1, h2, r2) = (
        v[n - 2].size,
        v[n - 2].reaction_mn?,
        v[n - 1].size,
        v[n - 1].reaction_mn?,
    );
    Some((r2 - (r1 - r2) * h2.powf(p) / (h1.powf(p) - h2.powf(p)), h1, h2))
}

/// The references, the one the errors are measured against first: the
/// peer extrapolated to h -> 0 from its three finest sizes ([`extrapolate`])
/// if it has them and they converge monotonically; else axijoint's
/// von_mises runs so extrapolated (the same continuum problem); else the
/// finest peer run. The finest peer run follows as an alternative.
pub fn references(rows: &[PlasticRow]) -> Vec<Reference> {
    let mut out = Vec::new();
    let fmt = |who: &str, p: f64, h: [f64; 3]| {
        format!(
            "{who} extrapolated to h -> 0 from h = {}, {}, {} (R = R_0 + C h^p, p = {p:.2})",
            h[0], h[1], h[2]
        )
    };
    if let Some((r0, p, h)) = extrapolated(rows, "calculix", "mises") {
        out.push(Reference {
            reaction: r0,
            how: fmt("CalculiX", p, h),
        });
    } else if let Some((r0, p, h)) = extrapolated(rows, "axijoint", "von_mises") {
        out.push(Reference {
            reaction: r0,
            how: fmt("axijoint von_mises", p, h),
        });
    }
    if let Some(f) = runs(rows, "calculix", "mises").last() {
        out.push(Reference {
            reaction: f.reaction_mn.unwrap_or(f64::NAN),
            how: format!("the finest CalculiX run (h = {})", f.size),
        });
    }
    out
}

/// The first of [`references`].
pub fn reference(rows: &[PlasticRow]) -> Option<Reference> {
    references(rows).into_iter().next()
}

/// Fills [`PlasticRow::error_vs_reference`].
pub fn set_errors(rows: &mut [PlasticRow], r: &Reference) {
    for row in rows.iter_mut() {
        row.error_vs_reference = row
            .reaction_mn
            .filter(|_| row.ok())
            .map(|x| (x - r.reaction) / r.reaction);
    }
}

/// A peer run against the fastest axijoint run at least as accurate.
#[derive(Clone, Debug, PartialEq)]
pub struct Ratio {
    /// The peer's size.
    pub peer_size: f64,
    /// The peer's |error|.
    pub peer_error: f64,
    /// The peer's wall time (s).
    pub peer_wall_s: f64,
    /// The matched axijoint run: (h, |error|, wall s), or None when no
    /// axijoint run of `law` is as accurate.
    pub axijoint: Option<(f64, f64, f64)>,
}

impl Ratio {
    /// Peer wall time / axijoint wall time.
    pub fn ratio(&self) -> Option<f64> {
        self.axijoint.map(|(_, _, t)| self.peer_wall_s / t)
    }
}

/// Each successful peer run (error set) against the fastest successful
/// axijoint run of `law` whose |error| is at most the peer's.
pub fn ratios(rows: &[PlasticRow], law: &str) -> Vec<Ratio> {
    let ax: Vec<&PlasticRow> = rows
        .iter()
        .filter(|r| r.code == "axijoint" && r.law == law && r.ok())
        .collect();
    let mut out = Vec::new();
    for p in rows.iter().filter(|r| r.code == "calculix" && r.ok()) {
        let (Some(e), Some(t)) = (p.error_vs_reference, p.wall_s) else {
            continue;
        };
        let best = ax
            .iter()
            .filter_map(|a| Some((a.size, a.error_vs_reference?.abs(), a.wall_s?)))
            .filter(|a| a.1 <= e.abs())
            .min_by(|a, b| a.2.total_cmp(&b.2));
        out.push(Ratio {
            peer_size: p.size,
            peer_error: e.abs(),
            peer_wall_s: t,
            axijoint: best,
        });
    }
    out
}

/// The summary printed at the end: each run's reaction and error against
/// the first reference, then for every reference the ratios of `law`
/// against the peer, and the peer's two finest runs extrapolated with
/// axijoint's order of convergence.
pub fn format_summary(rows: &[PlasticRow], law: &str) -> String {
    let mut s = String::new();
    let refs = references(rows);
    let Some(first) = refs.first() else {
        return "no reference (no successful peer run, no three axijoint von_mises runs): no ratio\n".into();
    };
    let mut rows = rows.to_vec();
    set_errors(&mut rows, first);
    s.push_str(&format!(
        "reference R(0.1 D) = {:.4} MN: {}\n",
        first.reaction, first.how
    ));
    s.push_str("code      law        h      unknowns  wall s   MiB  other  R(0.1 D) MN  error\n");
    for row in &rows {
        s.push_str(&format!(
            "{:<9} {:<10} {:<6} {:>9} {:>7} {:>5} {:>6} {:>10} {:>9}\n",
            row.code,
            row.law,
            row.size,
            row.unknowns.map_or("-".into(), |u| u.to_string()),
            row.wall_s.map_or("-".into(), |v| format!("{v:.1}")),
            row.peak_rss_mib.map_or("-".into(), |v| format!("{v:.0}")),
            row.other_load.map_or("-".into(), |v| format!("{v:.2}")),
            row.reaction_mn.map_or("-".into(), |v| format!("{v:.4}")),
            row.error_vs_reference
                .map_or(row.status.clone(), |v| format!("{:+.2} %", 100.0 * v)),
        ));
    }
    if let Some((r0, p, _)) = extrapolated(&rows, "axijoint", law) {
        if let Some((q0, h1, h2)) = peer_two_point(&rows, p) {
            s.push_str(&format!(
                "CalculiX h = {h1}, {h2} extrapolated with axijoint {law}'s p = {p:.2}: {q0:.4} MN \
                 ({:+.2} % from axijoint's {r0:.4})\n",
                100.0 * (q0 - r0) / r0
            ));
        }
    }
    for r in &refs {
        let mut rows = rows.clone();
        set_errors(&mut rows, r);
        s.push_str(&format!(
            "wall time at equal accuracy against {:.4} MN ({}): peer / the fastest axijoint {law} run at least as close:\n",
            r.reaction, r.how
        ));
        for q in ratios(&rows, law) {
            match (q.axijoint, q.ratio()) {
                (Some((h, e, t)), Some(x)) => {
                    s.push_str(&format!(
                    "  CalculiX h {} ({:.2} %, {:.1} s) / axijoint h {h} ({:.2} %, {t:.1} s) = {x:.1}{}\n",
                    q.peer_size,
                    100.0 * q.peer_error,
                    q.peer_wall_s,
                    100.0 * e,
                    if x >= 100.0 { " (>= 100: goal met)" } else { " (< 100)" }
                ))
                }
                _ => s.push_str(&format!(
                    "  CalculiX h {} ({:.2} %, {:.1} s): no axijoint {law} run as close\n",
                    q.peer_size,
                    100.0 * q.peer_error,
                    q.peer_wall_s
                )),
            }
        }
    }
    s
}
