//! Geometry of mapped elements: Jacobians, physical derivatives, areas,
//! edge lengths and the Jacobian checks used by mesh validation
//! ([`jacobian_range`]: the sign of `det J` over the whole element).
//!
//! The isoparametric map is `x(xi) = sum_i N_i(xi) x_i` with `x = (r, z)`;
//! the Jacobian is `J[a][b] = dx_a / dxi_b = sum_i x_i[a] dN_i/dxi_b`, so
//! `J = [[dr/dxi, dr/deta], [dz/dxi, dz/deta]]` and `dA = det J dxi deta`.

use crate::quadrature::{default_rule, gauss_legendre};
use crate::shapes::{Qua4, Tri6, MAX_CELL_NODES, MAX_EDGE_NODES};
use crate::{CellKind, EdgeKind};
use std::sync::OnceLock;

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
/// (check with [`jacobian_range`]).
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
/// `max < 0`; mixed signs mean an inverted (folded) element. The converse
/// does not hold for the quadratic families: a T6 whose mid-side nodes sit
/// on the wrong edges can be positive at these points and negative at its
/// centroid. Validation uses [`jacobian_range`], which covers every point.
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

/// Range of `det J` over the whole element, every point of the reference
/// cell and not only sampled ones: `(lo, hi)`.
///
/// - If `det J` keeps a strict sign on the element, `lo` and `hi` have that
///   sign (`lo > 0` counter-clockwise, `hi < 0` clockwise) and bound it:
///   `lo <= min det J`, `hi >= max det J` (equal for T3, Q4 and T6).
/// - If `det J` vanishes or changes sign somewhere, `lo <= 0 <= hi` and both
///   are values `det J` takes at points of the element (the witnesses).
///
/// How, per family (`det J` is a polynomial in the reference coordinates):
///
/// | family | `det J` | extremes |
/// |---|---|---|
/// | T3 | constant | one evaluation |
/// | Q4 | affine (the `xi eta` terms cancel) | the 4 corners, exact |
/// | T6 | quadratic | exact: the 3 vertices, the stationary point of each edge, the interior stationary point |
/// | Q8, Q9 | bicubic (degree 3 in each of xi, eta) | Bernstein bound, refined by subdivision |
///
/// Q8 and Q9: the values at a 4 x 4 lattice (`xi, eta` in -1, -1/3, 1/3, 1)
/// give the 16 coefficients of `det J` in the tensor Bernstein basis of
/// degree 3; the polynomial lies in the convex hull of its coefficients, so
/// coefficients all of one sign prove that sign everywhere, and a corner
/// coefficient (a value) of the other sign proves a sign change. Otherwise
/// the patch is split in four by de Casteljau and each quarter decided the
/// same way (gmsh's curved-mesh validity check bounds the Jacobian with
/// Bezier coefficients and subdivides likewise). After [`MAX_SUBDIVISIONS`]
/// levels (patches 1/64 of the element wide) an undecided patch is judged
/// by its corner values.
///
/// Bounds rather than dense sampling because they are a proof, not a
/// sample, and cheap: 16 evaluations of `det J` for a Q8/Q9, 6 for a T6, 4
/// for a Q4, 1 for a T3 (the corner and Gauss point check,
/// [`corner_and_gauss_dets`], took 13, 9, 8 and 6), from reference
/// derivatives tabulated once per family; subdivision happens only near a
/// zero of `det J` (never on the gmsh meshes of `geo/`). On 1e5-node meshes
/// of Scene P this pass takes 0.4 (T3, Q4) to 0.95 (Q9) times the time of
/// the old one (`examples/validate_cost.rs`).
pub fn jacobian_range(kind: CellKind, coords: &[[f64; 2]]) -> (f64, f64) {
    let n = kind.n_nodes();
    let det = |dn: &[[f64; 2]; MAX_CELL_NODES]| {
        let mut j = [0.0; 4];
        for (x, d) in coords[..n].iter().zip(&dn[..n]) {
            j[0] += x[0] * d[0];
            j[1] += x[0] * d[1];
            j[2] += x[1] * d[0];
            j[3] += x[1] * d[1];
        }
        j[0] * j[3] - j[1] * j[2]
    };
    let at = sample_derivatives(kind);
    match kind {
        CellKind::Tri3 => {
            let d = det(&at[0]);
            (d, d)
        }
        CellKind::Quad4 => min_max(at.iter().map(det)),
        CellKind::Tri6 => tri6_range(std::array::from_fn(|i| det(&at[i]))),
        CellKind::Quad8 | CellKind::Quad9 => {
            let values: Patch = std::array::from_fn(|j| std::array::from_fn(|i| det(&at[4 * j + i])));
            bicubic_range(&values)
        }
    }
}

/// Reference derivatives at the points where [`jacobian_range`] evaluates
/// `det J`, computed once per family: T3 its centroid, Q4 its corners, T6
/// its nodes, Q8 and Q9 the 4 x 4 lattice (`xi` fastest).
fn sample_derivatives(kind: CellKind) -> &'static [[[f64; 2]; MAX_CELL_NODES]] {
    type Table = Vec<[[f64; 2]; MAX_CELL_NODES]>;
    static TABLES: [OnceLock<Table>; 5] = [const { OnceLock::new() }; 5];
    let slot = match kind {
        CellKind::Tri3 => 0,
        CellKind::Quad4 => 1,
        CellKind::Tri6 => 2,
        CellKind::Quad8 => 3,
        CellKind::Quad9 => 4,
    };
    TABLES[slot].get_or_init(|| {
        const T: [f64; 4] = [-1.0, -1.0 / 3.0, 1.0 / 3.0, 1.0];
        let points: Vec<[f64; 2]> = match kind {
            CellKind::Tri3 => vec![[1.0 / 3.0, 1.0 / 3.0]],
            CellKind::Quad4 => Qua4::REF_COORDS.to_vec(),
            CellKind::Tri6 => Tri6::REF_COORDS.to_vec(),
            CellKind::Quad8 | CellKind::Quad9 => T.iter().flat_map(|&eta| T.map(|xi| [xi, eta])).collect(),
        };
        points
            .iter()
            .map(|&xi| {
                let mut dn = [[0.0; 2]; MAX_CELL_NODES];
                kind.eval_dn(xi, &mut dn);
                dn
            })
            .collect()
    })
}

/// Levels of subdivision of [`jacobian_range`] for Q8/Q9 before an
/// undecided patch is judged by its corner values.
pub const MAX_SUBDIVISIONS: u32 = 6;

fn min_max(v: impl Iterator<Item = f64>) -> (f64, f64) {
    v.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
        (lo.min(x), hi.max(x))
    })
}

/// Exact range of the quadratic with values `f` at the T6 nodes.
fn tri6_range(f: [f64; 6]) -> (f64, f64) {
    // f = a + b xi + c eta + d xi^2 + e xi eta + g eta^2, fitted to the
    // values at (0,0), (1,0), (0,1), (1/2,0), (1/2,1/2), (0,1/2).
    let a = f[0];
    let d = 2.0 * (f[0] + f[1] - 2.0 * f[3]);
    let b = f[1] - f[0] - d;
    let g = 2.0 * (f[0] + f[2] - 2.0 * f[5]);
    let c = f[2] - f[0] - g;
    let e = 4.0 * (f[4] - a - (b + c) / 2.0 - (d + g) / 4.0);
    let p = |x: f64, y: f64| a + b * x + c * y + d * x * x + e * x * y + g * y * y;
    let mut points: Vec<[f64; 2]> = vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    // Stationary point t = -p1 / (2 p2) of a parabola p0 + p1 t + p2 t^2 on (0, 1).
    let vertex = |p1: f64, p2: f64| {
        let t = -p1 / (2.0 * p2);
        (t > 0.0 && t < 1.0).then_some(t)
    };
    if let Some(t) = vertex(b, d) {
        points.push([t, 0.0]); // eta = 0
    }
    if let Some(t) = vertex(c, g) {
        points.push([0.0, t]); // xi = 0
    }
    if let Some(t) = vertex(b - c + e - 2.0 * g, d - e + g) {
        points.push([t, 1.0 - t]); // xi + eta = 1
    }
    // grad f = 0: [2d e; e 2g] x = -[b; c].
    let h = 4.0 * d * g - e * e;
    if h.abs() > 1e-12 * (4.0 * d * g).abs().max(e * e) {
        let (x, y) = ((-b * 2.0 * g + c * e) / h, (-c * 2.0 * d + b * e) / h);
        if x > 0.0 && y > 0.0 && x + y < 1.0 {
            points.push([x, y]);
        }
    }
    min_max(points.iter().map(|&[x, y]| p(x, y)))
}

/// A bicubic on a patch: values or Bernstein coefficients, `[eta][xi]`.
type Patch = [[f64; 4]; 4];

/// Cubic Bernstein coefficients from the values at t = 0, 1/3, 2/3, 1.
fn bernstein4(f: [f64; 4]) -> [f64; 4] {
    [
        f[0],
        (-5.0 * f[0] + 18.0 * f[1] - 9.0 * f[2] + 2.0 * f[3]) / 6.0,
        (2.0 * f[0] - 9.0 * f[1] + 18.0 * f[2] - 5.0 * f[3]) / 6.0,
        f[3],
    ]
}

/// The two halves of a cubic in Bernstein form (de Casteljau at t = 1/2).
fn halves(b: [f64; 4]) -> ([f64; 4], [f64; 4]) {
    let m01 = (b[0] + b[1]) / 2.0;
    let m12 = (b[1] + b[2]) / 2.0;
    let m23 = (b[2] + b[3]) / 2.0;
    let (l2, r1) = ((m01 + m12) / 2.0, (m12 + m23) / 2.0);
    let mid = (l2 + r1) / 2.0;
    ([b[0], m01, l2, mid], [mid, r1, m23, b[3]])
}

/// Applies a cubic map to every row and then to every column of a patch.
fn tensor(p: &Patch, mut f: impl FnMut([f64; 4]) -> [f64; 4]) -> Patch {
    let rows = p.map(&mut f);
    let mut out = [[0.0; 4]; 4];
    for i in 0..4 {
        let col = f([rows[0][i], rows[1][i], rows[2][i], rows[3][i]]);
        for (j, v) in col.into_iter().enumerate() {
            out[j][i] = v;
        }
    }
    out
}

/// The four quarters of a patch in Bernstein form.
fn quarters(p: &Patch) -> [Patch; 4] {
    let (mut left, mut right) = ([[0.0; 4]; 4], [[0.0; 4]; 4]);
    for j in 0..4 {
        (left[j], right[j]) = halves(p[j]);
    }
    let split = |q: &Patch| {
        let (mut lo, mut hi) = ([[0.0; 4]; 4], [[0.0; 4]; 4]);
        for i in 0..4 {
            let (a, b) = halves([q[0][i], q[1][i], q[2][i], q[3][i]]);
            for j in 0..4 {
                lo[j][i] = a[j];
                hi[j][i] = b[j];
            }
        }
        (lo, hi)
    };
    let ((a, b), (c, d)) = (split(&left), split(&right));
    [a, b, c, d]
}

/// Search state of [`bicubic_range`]: the proven bounds, or a witness.
struct Search {
    sign: f64,
    lo: f64,
    hi: f64,
    witness: Option<f64>,
}

impl Search {
    fn refine(&mut self, p: &Patch, depth: u32) {
        let corners = [p[0][0], p[0][3], p[3][0], p[3][3]];
        if let Some(&w) = corners.iter().find(|&&v| v * self.sign <= 0.0 || v.is_nan()) {
            self.witness = Some(w);
            return;
        }
        let (lo, hi) = min_max(p.iter().flatten().copied());
        let (lo, hi) = if lo * self.sign > 0.0 && hi * self.sign > 0.0 {
            (lo, hi)
        } else if depth >= MAX_SUBDIVISIONS {
            min_max(corners.into_iter())
        } else {
            for q in quarters(p) {
                self.refine(&q, depth + 1);
                if self.witness.is_some() {
                    return;
                }
            }
            return;
        };
        self.lo = self.lo.min(lo);
        self.hi = self.hi.max(hi);
    }
}

/// Range of a bicubic from its values on the 4 x 4 lattice (see
/// [`jacobian_range`]).
fn bicubic_range(values: &Patch) -> (f64, f64) {
    let (vlo, vhi) = min_max(values.iter().flatten().copied());
    if vlo * vhi <= 0.0 || vlo.is_nan() || vhi.is_nan() {
        return (vlo, vhi);
    }
    let mut search = Search {
        sign: vlo.signum(),
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
        witness: None,
    };
    search.refine(&tensor(values, bernstein4), 0);
    match search.witness {
        Some(w) => (vlo.min(w), vhi.max(w)),
        None => (search.lo, search.hi),
    }
}
