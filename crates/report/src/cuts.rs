//! Stress profiles along cuts: samples along a polyline in (r, z), at chosen
//! theta, each body reporting its own stress (two rows where a cut crosses
//! an interface, one per body).

use crate::field::{Field, Locator};
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
    /// `(sigma_r, sigma_z, sigma_theta, tau_rz, tau_rtheta, tau_ztheta)`.
    pub stress: [f64; 6],
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

/// The profile along `points` at each of `theta_deg`: rows by theta, then
/// position, then body (cell order). Points outside the mesh give no row.
pub fn profile(
    field: &Field,
    locator: &Locator,
    points: &[[f64; 2]],
    spacing: f64,
    theta_deg: &[f64],
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
                    stress: field.stress(l.cell, l.xi, t.to_radians()),
                });
            }
        }
    }
    rows
}

/// Every stress of every cut of `scene` at its angles, as one vector (the
/// measure of the automatic choice of harmonics: same mesh, same samples).
pub fn profile_values(
    scene: &axijoint_solver::scene::Scene,
    mesh: &Mesh,
    u: &axijoint_solver::driver::Displacements,
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
    };
    let locator = Locator::new(mesh);
    scene
        .cuts
        .iter()
        .flat_map(|c| profile(&field, &locator, &[c.from, c.to], c.spacing, &c.theta_deg))
        .flat_map(|r| r.stress)
        .collect()
}
