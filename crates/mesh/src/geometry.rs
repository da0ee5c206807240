//! Geometry of mapped elements: Jacobians, physical derivatives, areas,
//! edge lengths and the Jacobian checks used by mesh validation.
//!
//! The isoparametric map is `x(xi) = sum_i N_i(xi) x_i` with `x = (r, z)`;
//! the Jacobian is `J[a][b] = dx_a / dxi_b = sum_i x_i[a] dN_i/dxi_b`, so
//! `J = [[dr/dxi, dr/deta], [dz/dxi, dz/deta]]` and `dA = det J dxi deta`.

use crate::quadrature::{default_rule, gauss_legendre};
use crate::shapes::{MAX_CELL_NODES, MAX_EDGE_NODES};
use crate::{CellKind, EdgeKind};

/// Jacobian `J = dx/dxi` and its determinant at the point where the
/// reference derivatives `dn` were evaluated.
///
/// `J[a][b] = sum_i coords[i][a] dn[i][b]`, `det = J00 J11 - J01 J10`
/// (positive for counter-clockwise nodes).
pub fn jacobian(kind: CellKind, coords: &[[f64; 2]], dn: &[[f64; 2]]) -> ([[f64; 2]; 2], f64) {
    let n = kind.n_nodes();
    let mut j = [[0.0; 2]; 2];
    for (x, d) in coords[..n].iter().zip(&dn[..n]) {
        j[0][0] += x[0] * d[0];
        j[0][1] += x[0] * d[1];
        j[1][0] += x[1] * d[0];
        j[1][1] += x[1] * d[1];
    }
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    (j, det)
}

/// Physical derivatives `[dN_i/dr, dN_i/dz]` into `out[..n]` from the
/// reference derivatives `dn` and the Jacobian of [`jacobian`]:
/// `[dN/dr, dN/dz] = [dN/dxi, dN/deta] J^-1`.
///
/// `det` must be non-zero (check it first).
pub fn derivatives_rz(jac: &[[f64; 2]; 2], det: f64, dn: &[[f64; 2]], out: &mut [[f64; 2]]) {
    let inv = 1.0 / det;
    // J^-1 = [[J11, -J01], [-J10, J00]] / det
    let (i00, i01, i10, i11) = (
        jac[1][1] * inv,
        -jac[0][1] * inv,
        -jac[1][0] * inv,
        jac[0][0] * inv,
    );
    for (o, d) in out.iter_mut().zip(dn) {
        *o = [d[0] * i00 + d[1] * i10, d[0] * i01 + d[1] * i11];
    }
}

/// Physical coordinates `x = sum_i N_i x_i` of the point with shape values `n`.
pub fn interpolate(coords: &[[f64; 2]], n: &[f64]) -> [f64; 2] {
    coords.iter().zip(n).fold([0.0, 0.0], |acc, (x, ni)| {
        [acc[0] + ni * x[0], acc[1] + ni * x[1]]
    })
}

/// Area `Integral(dA) = Integral(|det J| dxi deta)` of a cell, positive for
/// either node orientation.
///
/// Uses [`default_rule`], exact for any straight-sided element and for any
/// curved T6 (det J of degree 2), Q8 or Q9 (det J of degree at most 3 in
/// each direction, 3 x 3 Gauss exact to 5). Assumes det J keeps its sign
/// (check with [`corner_and_gauss_dets`]).
pub fn cell_area(kind: CellKind, coords: &[[f64; 2]]) -> f64 {
    let mut dn = [[0.0; 2]; MAX_CELL_NODES];
    let mut area = 0.0;
    for (xi, w) in default_rule(kind).iter() {
        kind.eval_dn(xi, &mut dn);
        area += w * jacobian(kind, coords, &dn).1;
    }
    area.abs()
}

/// Length `Integral(ds)` and lateral integral `Integral(r ds)` of an edge
/// (nodes: ends, then middle), `ds = |dx/ds| ds`.
///
/// `2 pi` times the lateral integral is the area of the surface of
/// revolution swept by the edge. Five Gauss points: exact for straight edges
/// (also with an off-centre middle node); curved L3 edges to quadrature
/// accuracy.
pub fn edge_length_and_lateral(kind: EdgeKind, coords: &[[f64; 2]]) -> (f64, f64) {
    let n_nodes = kind.n_nodes();
    let (mut n, mut dn) = ([0.0; MAX_EDGE_NODES], [0.0; MAX_EDGE_NODES]);
    let (mut length, mut lateral) = (0.0, 0.0);
    for (s, w) in gauss_legendre(5).expect("5-point rule exists").iter() {
        kind.eval_n(s, &mut n);
        kind.eval_dn(s, &mut dn);
        let (mut x, mut t) = ([0.0; 2], [0.0; 2]);
        for i in 0..n_nodes {
            for a in 0..2 {
                x[a] += n[i] * coords[i][a];
                t[a] += dn[i] * coords[i][a];
            }
        }
        let ds = w * t[0].hypot(t[1]);
        length += ds;
        lateral += x[0] * ds;
    }
    (length, lateral)
}

/// Smallest and largest `det J` over the corners and the points of
/// [`default_rule`]: `(min, max)`.
///
/// A valid counter-clockwise element has `min > 0`; a clockwise one
/// `max < 0`; mixed signs mean an inverted (folded) element, typically a
/// badly placed mid-side node (the corners show it first).
pub fn corner_and_gauss_dets(kind: CellKind, coords: &[[f64; 2]]) -> (f64, f64) {
    let mut dn = [[0.0; 2]; MAX_CELL_NODES];
    let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
    let corners = kind.ref_coords()[..kind.n_corners()].iter().copied();
    for xi in corners.chain(default_rule(kind).points.iter().copied()) {
        kind.eval_dn(xi, &mut dn);
        let det = jacobian(kind, coords, &dn).1;
        min = min.min(det);
        max = max.max(det);
    }
    (min, max)
}
