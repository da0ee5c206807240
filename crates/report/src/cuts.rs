//! Stress profiles along cuts: samples along a polyline in (r, z), at chosen
//! theta, each body reporting its own stress (two rows where a cut crosses
//! an interface, one per body); where a cut crosses the joints
//! ([`joint_crossings`]).

use crate::field::{Field, Locator};
use crate::recovery::PlasticStress;
use axijoint_mesh::Mesh;

/// One row of a profile.
#[derive(Clone, Debug, PartialEq)]
pub struct CutRow {
    /// Distance along the cut.
    pub s: f64,
    /// Position.
    pub r: f64,
    /// Position.
    pub z: f64,
    /// Angle in degrees.
    pub theta_deg: f64,
    /// Body name.
    pub body: String,
    /// `(sigma_r, sigma_z, sigma_theta, tau_rz, tau_rtheta, tau_ztheta)`,
    /// total.
    pub stress: [f64; 6],
    /// The pore pressure (compression positive) with ground water; none
    /// without.
    pub pore_pressure: Option<f64>,
}

/// Sample positions along the polyline `points`: every `spacing`, the
/// vertices, and the crossings with joints and with body boundaries.
pub fn sample_positions(mesh: &Mesh, points: &[[f64; 2]], spacing: f64) -> Vec<(f64, [f64; 2])> {
    let mut out: Vec<(f64, [f64; 2])> = Vec::new();
    let mut s0 = 0.0;
    let segments = interface_segments(mesh);
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        if len == 0.0 {
            continue;
        }
        let mut ts: Vec<f64> = Vec::new();
        let n = (len / spacing).floor() as usize;
        ts.extend((0..=n).map(|k| (k as f64 * spacing / len).min(1.0)));
        ts.push(1.0);
        for (p, q) in &segments {
            if let Some(t) = crossing(a, b, *p, *q) {
                ts.push(t);
            }
        }
        ts.sort_by(f64::total_cmp);
        ts.dedup_by(|x, y| (*x - *y).abs() * len < 1e-9 * len.max(1.0));
        for t in ts {
            out.push((s0 + t * len, [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]));
        }
        s0 += len;
    }
    out.dedup_by(|x, y| (x.0 - y.0).abs() < 1e-12);
    out
}

/// Segments (corner to corner) of joint faces and of edges between bodies.
fn interface_segments(mesh: &Mesh) -> Vec<([f64; 2], [f64; 2])> {
    let mut segs: Vec<([f64; 2], [f64; 2])> = mesh
        .joints
        .iter()
        .flat_map(|j| j.elements.iter())
        .map(|e| (mesh.nodes[e.bottom[0]], mesh.nodes[e.bottom[1]]))
        .collect();
    let mut edges: std::collections::HashMap<(usize, usize), usize> = std::collections::HashMap::new();
    for cell in &mesh.cells {
        for e in 0..cell.kind.n_corners() {
            let l = cell.kind.edge_nodes(e);
            let (a, b) = (cell.nodes[l[0]], cell.nodes[l[1]]);
            let key = (a.min(b), a.max(b));
            match edges.get(&key) {
                Some(&body) if body != cell.body => segs.push((mesh.nodes[a], mesh.nodes[b])),
                _ => {
                    edges.insert(key, cell.body);
                }
            }
        }
    }
    segs
}

/// Parameter t in [0, 1] on a -> b where it meets segment p -> q.
fn crossing(a: [f64; 2], b: [f64; 2], p: [f64; 2], q: [f64; 2]) -> Option<f64> {
    let d = [b[0] - a[0], b[1] - a[1]];
    let e = [q[0] - p[0], q[1] - p[1]];
    let den = d[0] * e[1] - d[1] * e[0];
    if den.abs() < 1e-14 * (d[0].hypot(d[1]) * e[0].hypot(e[1])) {
        return None;
    }
    let w = [p[0] - a[0], p[1] - a[1]];
    let t = (w[0] * e[1] - w[1] * e[0]) / den;
    let u = (w[0] * d[1] - w[1] * d[0]) / den;
    let eps = 1e-12;
    ((-eps..=1.0 + eps).contains(&t) && (-eps..=1.0 + eps).contains(&u)).then_some(t.clamp(0.0, 1.0))
}

/// Where a cut meets a joint: a point where it crosses it, or a stretch
/// where it runs along it.
#[derive(Clone, Debug, PartialEq)]
pub struct JointCrossing {
    /// The joint's name.
    pub joint: String,
    /// Distance along the cut where the meeting starts and ends (equal
    /// for a crossing).
    pub s: (f64, f64),
    /// `(r, z)` at `s.0` and at `s.1`.
    pub at: ([f64; 2], [f64; 2]),
}

/// The joints the polyline `points` crosses or runs along, from the joint
/// elements' faces (corner to corner) of `mesh`, sorted by distance along
/// the cut. Meetings of one joint closer than `1e-9` of the cut's length
/// are merged (a crossing through a node shared by two joint elements is
/// one crossing).
pub fn joint_crossings(mesh: &Mesh, points: &[[f64; 2]]) -> Vec<JointCrossing> {
    let total: f64 = points
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .sum();
    let tol = 1e-9 * total.max(f64::MIN_POSITIVE);
    let mut out = Vec::new();
    for joint in &mesh.joints {
        let mut spans: Vec<(f64, f64)> = Vec::new();
        let mut s0 = 0.0;
        for w in points.windows(2) {
            let (a, b) = (w[0], w[1]);
            let len = (b[0] - a[0]).hypot(b[1] - a[1]);
            if len == 0.0 {
                continue;
            }
            for e in &joint.elements {
                let (p, q) = (mesh.nodes[e.bottom[0]], mesh.nodes[e.bottom[1]]);
                let span = crossing(a, b, p, q)
                    .map(|t| (t, t))
                    .or_else(|| overlap(a, b, p, q));
                if let Some((t0, t1)) = span {
                    spans.push((s0 + t0 * len, s0 + t1 * len));
                }
            }
            s0 += len;
        }
        spans.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut merged: Vec<(f64, f64)> = Vec::new();
        for (lo, hi) in spans {
            match merged.last_mut() {
                Some(last) if lo <= last.1 + tol => last.1 = last.1.max(hi),
                _ => merged.push((lo, hi)),
            }
        }
        out.extend(merged.into_iter().map(|s| JointCrossing {
            joint: joint.name.clone(),
            s,
            at: (point_at(points, s.0), point_at(points, s.1)),
        }));
    }
    out.sort_by(|x, y| x.s.0.total_cmp(&y.s.0));
    out
}

/// The parameters `(t0, t1)` on a -> b of the stretch where segment p -> q
/// lies on it (collinear within `1e-9` of the longer one), if any.
fn overlap(a: [f64; 2], b: [f64; 2], p: [f64; 2], q: [f64; 2]) -> Option<(f64, f64)> {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let len = len2.sqrt();
    let tol = 1e-9 * len.max((q[0] - p[0]).hypot(q[1] - p[1]));
    let off = |x: [f64; 2]| (d[0] * (x[1] - a[1]) - d[1] * (x[0] - a[0])).abs() / len;
    if len == 0.0 || off(p) > tol || off(q) > tol {
        return None;
    }
    let t = |x: [f64; 2]| (d[0] * (x[0] - a[0]) + d[1] * (x[1] - a[1])) / len2;
    let (tp, tq) = (t(p), t(q));
    let (lo, hi) = (tp.min(tq).max(0.0), tp.max(tq).min(1.0));
    (hi - lo >= -tol / len).then_some((lo.min(hi), hi))
}

/// The point at distance `s` along the polyline `points`.
fn point_at(points: &[[f64; 2]], s: f64) -> [f64; 2] {
    let mut s0 = 0.0;
    for w in points.windows(2) {
        let len = (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
        if len > 0.0 && s <= s0 + len {
            let t = ((s - s0) / len).clamp(0.0, 1.0);
            return [
                w[0][0] + t * (w[1][0] - w[0][0]),
                w[0][1] + t * (w[1][1] - w[0][1]),
            ];
        }
        s0 += len;
    }
    points.last().copied().unwrap_or([0.0, 0.0])
}

/// The profile along `points` at each of `theta_deg`: rows by theta, then
/// position, then body (cell order). Points outside the mesh give no row.
/// The stress is the field's (elastic D of the displacements): see
/// [`profile_with`] for the plastic bodies'.
pub fn profile(
    field: &Field,
    locator: &Locator,
    points: &[[f64; 2]],
    spacing: f64,
    theta_deg: &[f64],
) -> Vec<CutRow> {
    profile_with(field, locator, points, spacing, theta_deg, None)
}

/// [`profile`], the stress of a point in a cell of a plastic body from
/// `plastic` (`plastic.json`, [`PlasticStress::at`]) when given.
pub fn profile_with(
    field: &Field,
    locator: &Locator,
    points: &[[f64; 2]],
    spacing: f64,
    theta_deg: &[f64],
    plastic: Option<&PlasticStress>,
) -> Vec<CutRow> {
    let samples = sample_positions(field.mesh, points, spacing);
    let located: Vec<Vec<crate::field::Location>> = samples
        .iter()
        .map(|(_, p)| {
            let mut per_body: Vec<crate::field::Location> = Vec::new();
            for l in locator.locate_all(field.mesh, *p) {
                let body = field.mesh.cells[l.cell].body;
                if !per_body.iter().any(|q| field.mesh.cells[q.cell].body == body) {
                    per_body.push(l);
                }
            }
            per_body
        })
        .collect();
    let mut rows = Vec::new();
    for &t in theta_deg {
        for ((s, p), locs) in samples.iter().zip(&located) {
            for l in locs {
                let cell = &field.mesh.cells[l.cell];
                rows.push(CutRow {
                    s: *s,
                    r: p[0],
                    z: p[1],
                    theta_deg: t,
                    body: field.mesh.bodies[cell.body].name.clone(),
                    stress: plastic
                        .and_then(|ps| ps.at(l.cell, *p, t.to_radians()))
                        .unwrap_or_else(|| field.stress(l.cell, l.xi, t.to_radians())),
                    pore_pressure: field.water().map(|w| w.pressure(p[1])),
                });
            }
        }
    }
    rows
}

/// Every stress of every cut of `scene` at its angles, as one vector (the
/// measure of the automatic choice of harmonics: same mesh, same samples);
/// in a plastic body the returned stress of `body`.
pub fn profile_values(
    scene: &axijoint_solver::scene::Scene,
    mesh: &Mesh,
    u: &axijoint_solver::solution::Displacements,
    body: Option<&axijoint_solver::iteration::BodyField>,
) -> Vec<f64> {
    let materials: Vec<_> = mesh
        .bodies
        .iter()
        .map(|b| scene.materials.get(&b.name).map(|m| m.elastic()))
        .collect::<Option<_>>()
        .unwrap_or_default();
    if materials.len() != mesh.bodies.len() {
        return Vec::new();
    }
    let field = Field {
        mesh,
        materials: &materials,
        u,
        initial: None,
    };
    let locator = Locator::new(mesh);
    let file = body.map(|b| axijoint_solver::results::PlasticFieldFile::new(mesh, b, None));
    let plastic = file.as_ref().and_then(|f| PlasticStress::new(mesh, f).ok());
    scene
        .cuts
        .iter()
        .flat_map(|c| {
            profile_with(
                &field,
                &locator,
                &[c.from, c.to],
                c.spacing,
                &c.theta_deg,
                plastic.as_ref(),
            )
        })
        .flat_map(|r| r.stress)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use axijoint_mesh::{Joint, JointElement, JointKind};

    /// Joints `side` on r = 0.5, z 0..1 (4 elements) and `toe` on z = 0,
    /// r 0..0.5 (2 elements).
    fn mesh() -> Mesh {
        let mut nodes = Vec::new();
        let mut joint = |name: &str, pts: &[[f64; 2]]| {
            let first = nodes.len();
            nodes.extend_from_slice(pts);
            Joint {
                name: name.into(),
                bottom_bodies: vec![],
                top_bodies: vec![],
                elements: (0..pts.len() - 1)
                    .map(|k| JointElement {
                        kind: JointKind::Lin4,
                        bottom: vec![first + k, first + k + 1],
                        top: vec![first + k, first + k + 1],
                        edge_tag: 0,
                        bottom_cell: 0,
                        top_cell: 0,
                    })
                    .collect(),
                duplicated: vec![],
            }
        };
        let side = joint(
            "side",
            &[[0.5, 0.0], [0.5, 0.25], [0.5, 0.5], [0.5, 0.75], [0.5, 1.0]],
        );
        let toe = joint("toe", &[[0.0, 0.0], [0.25, 0.0], [0.5, 0.0]]);
        Mesh {
            nodes,
            joints: vec![side, toe],
            ..Mesh::default()
        }
    }

    /// `(joint, s0, s1)` of each crossing, to compare with exact values.
    fn found(from: [f64; 2], to: [f64; 2]) -> Vec<(String, f64, f64)> {
        joint_crossings(&mesh(), &[from, to])
            .into_iter()
            .map(|c| (c.joint, c.s.0, c.s.1))
            .collect()
    }

    fn assert_near(got: &[(String, f64, f64)], want: &[(&str, f64, f64)]) {
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (g, w) in got.iter().zip(want) {
            assert_eq!(g.0, w.0, "{got:?}");
            assert!(
                (g.1 - w.1).abs() < 1e-12 && (g.2 - w.2).abs() < 1e-12,
                "{got:?} vs {want:?}"
            );
        }
    }

    #[test]
    fn crossings_of_joints() {
        // Across the side joint inside an element, and through a node two elements share.
        assert_near(&found([0.0, 0.6], [3.0, 0.6]), &[("side", 0.5, 0.5)]);
        assert_near(&found([0.0, 0.5], [1.0, 0.5]), &[("side", 0.5, 0.5)]);
        // Slanted, z = 2 r - 0.5: the toe at r = 0.25, the side at z = 0.5.
        let k = 5f64.sqrt();
        assert_near(
            &found([0.0, -0.5], [1.0, 1.5]),
            &[("toe", 0.25 * k, 0.25 * k), ("side", 0.5 * k, 0.5 * k)],
        );
        // Along the side joint from z = 0 to 1 (s = 1 to 2); the toe ends on the cut at s = 1.
        let along = joint_crossings(&mesh(), &[[0.5, -1.0], [0.5, 2.0]]);
        let mut got: Vec<(String, f64, f64)> =
            along.iter().map(|c| (c.joint.clone(), c.s.0, c.s.1)).collect();
        got.sort_by(|a, b| a.0.cmp(&b.0));
        assert_near(&got, &[("side", 1.0, 2.0), ("toe", 1.0, 1.0)]);
        let side = along.iter().find(|c| c.joint == "side").unwrap();
        assert_eq!(side.at, ([0.5, 0.0], [0.5, 1.0]));
        // Beyond the toe's end and parallel to it: nothing.
        assert!(found([1.0, 0.0], [2.0, 0.0]).is_empty());
        assert!(found([0.0, -0.1], [2.0, -0.1]).is_empty());
    }
}
