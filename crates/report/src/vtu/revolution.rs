//! The revolution: VTK cell types, sections, rings of points and the node
//! lists of revolved cells.

use axijoint_mesh::{CellKind, Mesh};
use axijoint_solver::fourier::Sections;
use std::f64::consts::PI;

/// VTK cell type numbers used here.
pub mod cell_type {
    /// Linear wedge (6 nodes).
    pub const WEDGE: u8 = 13;
    /// Linear hexahedron (8 nodes).
    pub const HEXAHEDRON: u8 = 12;
    /// Quadratic wedge (15 nodes).
    pub const QUADRATIC_WEDGE: u8 = 26;
    /// Quadratic (serendipity) hexahedron (20 nodes).
    pub const QUADRATIC_HEXAHEDRON: u8 = 25;
    /// Triquadratic hexahedron (27 nodes).
    pub const TRIQUADRATIC_HEXAHEDRON: u8 = 29;
    /// Linear quadrilateral (4 nodes).
    pub const QUAD: u8 = 9;
    /// Biquadratic quadrilateral (9 nodes).
    pub const BIQUADRATIC_QUAD: u8 = 28;
}

/// The VTK cell a meridional cell becomes when revolved: `(type, nodes)`.
pub fn revolved_cell_type(kind: CellKind) -> (u8, usize) {
    match kind {
        CellKind::Tri3 => (cell_type::WEDGE, 6),
        CellKind::Tri6 => (cell_type::QUADRATIC_WEDGE, 15),
        CellKind::Quad4 => (cell_type::HEXAHEDRON, 8),
        CellKind::Quad8 => (cell_type::QUADRATIC_HEXAHEDRON, 20),
        CellKind::Quad9 => (cell_type::TRIQUADRATIC_HEXAHEDRON, 27),
    }
}

/// Samples of the turn (points on a ring) that resolve harmonic `m_max`:
/// 8 per period of the highest harmonic (4 times the 2 of Nyquist's
/// criterion), 16 at least.
fn samples_per_turn(m_max: usize) -> usize {
    (8 * m_max).max(16)
}

/// The sections `outputs.vtu_sections = "auto"` gives for a field whose
/// highest harmonic is `m_max`: 8 samples of the turn per period of
/// harmonic `m_max`, 16 at least, i.e. `max(16, 8 M)` sections for linear
/// cells and half as many, `max(8, 4 M)`, when every cell is quadratic
/// (each section then has a ring at its mid angle too).
pub fn auto_sections(mesh: &Mesh, m_max: usize) -> usize {
    let quadratic = mesh.cells.iter().all(|c| !mid_ring_nodes(c.kind).is_empty());
    samples_per_turn(m_max) / if quadratic { 2 } else { 1 }
}

/// Point numbering of revolved meridional nodes: `n` rings at theta_k, then
/// (for the nodes that need one) `n` rings at theta_{k+1/2}.
pub(super) struct Rings {
    n: usize,
    pub(super) base: usize,
    /// Meridional nodes with a full ring, in point order.
    pub(super) nodes: Vec<usize>,
    /// Meridional nodes with a mid-angle ring, in point order.
    mids: Vec<usize>,
    /// Mesh node -> position in `nodes`.
    pub(super) local: Vec<usize>,
    /// Mesh node -> position in `mids`.
    local_mid: Vec<usize>,
}

impl Rings {
    pub(super) fn new(
        n: usize,
        base: usize,
        n_mesh_nodes: usize,
        nodes: Vec<usize>,
        mids: Vec<usize>,
    ) -> Rings {
        let mut local = vec![usize::MAX; n_mesh_nodes];
        let mut local_mid = vec![usize::MAX; n_mesh_nodes];
        for (i, &m) in nodes.iter().enumerate() {
            local[m] = i;
        }
        for (i, &m) in mids.iter().enumerate() {
            local_mid[m] = i;
        }
        Rings {
            n,
            base,
            nodes,
            mids,
            local,
            local_mid,
        }
    }

    /// Point of mesh node `node` at theta_k (k taken modulo n).
    pub(super) fn at(&self, node: usize, k: usize) -> usize {
        self.base + (k % self.n) * self.nodes.len() + self.local[node]
    }

    /// Point of mesh node `node` at theta_{k+1/2}.
    pub(super) fn mid(&self, node: usize, k: usize) -> usize {
        self.base + self.n * self.nodes.len() + k * self.mids.len() + self.local_mid[node]
    }

    pub(super) fn len(&self) -> usize {
        self.n * (self.nodes.len() + self.mids.len())
    }

    /// `(theta, mesh nodes)` of every ring, in point order.
    pub(super) fn by_angle(&self) -> impl Iterator<Item = (f64, &[usize])> + '_ {
        let n = self.n;
        let full = (0..n).map(move |k| (ring_angle(k, n), self.nodes.as_slice()));
        let half = (0..n).map(move |k| (mid_angle(k, n), self.mids.as_slice()));
        full.chain(half)
    }

    /// `(mesh node, theta)` of every point, in point order.
    pub(super) fn points(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        let n = self.n;
        let full = (0..n).flat_map(move |k| self.nodes.iter().map(move |&m| (m, ring_angle(k, n))));
        let half = (0..n).flat_map(move |k| self.mids.iter().map(move |&m| (m, mid_angle(k, n))));
        full.chain(half)
    }
}

fn ring_angle(k: usize, n: usize) -> f64 {
    2.0 * PI * k as f64 / n as f64
}

pub(super) fn mid_angle(k: usize, n: usize) -> f64 {
    2.0 * PI * (k as f64 + 0.5) / n as f64
}

/// Maps an angle to the nearest section of a field known at sections (the
/// joint field, the plastic bodies' field): `(section, mirrored)`.
pub(crate) struct SectionMap {
    theta: Vec<f64>,
    half: bool,
}

impl SectionMap {
    /// The sections at `sections_deg` with quadrature `weights`.
    pub(crate) fn new(sections_deg: &[f64], weights: &[f64]) -> SectionMap {
        let theta: Vec<f64> = sections_deg.iter().map(|d| d.to_radians()).collect();
        // A half-circle set is recognised by its weights (each interior
        // section stands for +theta and -theta).
        let half = Sections::half_circle(theta.clone()).is_ok_and(|s| {
            s.weight.len() == weights.len()
                && s.weight
                    .iter()
                    .zip(weights)
                    .all(|(a, b)| (a - b).abs() <= 1e-9 * (1.0 + b.abs()))
        });
        SectionMap { theta, half }
    }

    /// The section nearest `t`, and whether it stands for `t` mirrored
    /// (`2 pi - t`, a half-circle set with `t > pi`).
    pub(crate) fn nearest(&self, t: f64) -> (usize, bool) {
        let t = t.rem_euclid(2.0 * PI);
        let (t, mirrored) = if self.half && t > PI {
            (2.0 * PI - t, true)
        } else {
            (t, false)
        };
        let dist = |a: f64| {
            if self.half {
                (a - t).abs()
            } else {
                let d = (a - t).rem_euclid(2.0 * PI);
                d.min(2.0 * PI - d)
            }
        };
        let best = (0..self.theta.len())
            .min_by(|&a, &b| dist(self.theta[a]).total_cmp(&dist(self.theta[b])))
            .unwrap_or(0);
        (best, mirrored)
    }
}

/// VTK node list of meridional cell `nodes` revolved over slot k.
pub(super) fn revolve(kind: CellKind, nodes: &[usize], k: usize, rings: &Rings) -> Vec<usize> {
    let lo = |i: usize| rings.at(nodes[i], k);
    let hi = |i: usize| rings.at(nodes[i], k + 1);
    let mid = |i: usize| rings.mid(nodes[i], k);
    let mut v = Vec::with_capacity(27);
    match kind {
        CellKind::Tri3 => {
            v.extend((0..3).map(hi));
            v.extend((0..3).map(lo));
        }
        CellKind::Tri6 => {
            v.extend((0..3).map(hi));
            v.extend((0..3).map(lo));
            v.extend((3..6).map(hi));
            v.extend((3..6).map(lo));
            v.extend((0..3).map(mid));
        }
        CellKind::Quad4 => {
            v.extend((0..4).map(hi));
            v.extend((0..4).map(lo));
        }
        CellKind::Quad8 | CellKind::Quad9 => {
            v.extend((0..4).map(hi));
            v.extend((0..4).map(lo));
            v.extend((4..8).map(hi));
            v.extend((4..8).map(lo));
            v.extend((0..4).map(mid));
            if kind == CellKind::Quad9 {
                // Face centres: faces (0,4,7,3), (1,2,6,5), (0,1,5,4),
                // (3,2,6,7) hold meridional edges 3-0, 1-2, 0-1, 2-3; then
                // base (ring k+1) and top (ring k); then the centre.
                v.extend([7, 5, 4, 6].map(mid));
                v.push(hi(8));
                v.push(lo(8));
                v.push(mid(8));
            }
        }
    }
    v
}

/// Local nodes of a cell that need a mid-angle ring.
pub(super) fn mid_ring_nodes(kind: CellKind) -> std::ops::Range<usize> {
    match kind {
        CellKind::Tri3 | CellKind::Quad4 => 0..0,
        CellKind::Tri6 | CellKind::Quad8 => 0..kind.n_corners(),
        CellKind::Quad9 => 0..9,
    }
}

/// Cartesian position of `(r, z)` at `theta`.
pub(super) fn position(p: [f64; 2], theta: f64) -> [f64; 3] {
    let (s, c) = theta.sin_cos();
    [p[0] * c, p[0] * s, p[1]]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sections for the highest harmonic: 8 samples of the turn per period
    /// of harmonic M, 16 at least.
    #[test]
    fn automatic_sections() {
        assert_eq!(samples_per_turn(0), 16);
        assert_eq!(samples_per_turn(1), 16);
        assert_eq!(samples_per_turn(2), 16);
        assert_eq!(samples_per_turn(4), 32);
        assert_eq!(samples_per_turn(5), 40);
    }
}
