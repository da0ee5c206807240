//! Meridional solid elements of harmonic m: B matrix, stiffness, strain and
//! stress.
//!
//! Strains of harmonic m (amplitudes; symmetric family `u cos, v cos, w sin`:
//! the first four carry `cos m.th`, the last two `sin m.th`):
//!
//! ```text
//! e_r   = du/dr                 e_z   = dv/dz            e_th  = (u + m w) / r
//! g_rz  = du/dz + dv/dr         g_rth = dw/dr - (w + m u) / r
//! g_zth = dw/dz - m v / r
//! ```
//!
//! so for node i (shape value `N`, derivatives `N_r`, `N_z`) the columns
//! `(u_i, v_i, w_i)` of `B` are
//!
//! ```text
//!         e_r   | N_r       0         0          |
//!         e_z   | 0         N_z       0          |
//!   B_i = e_th  | N/r       0         m N/r      |
//!         g_rz  | N_z       N_r       0          |
//!         g_rth | -m N/r    0         N_r - N/r  |
//!         g_zth | 0         -m N/r    N_z        |
//! ```
//!
//! m = 0 is the axisymmetric problem (u, v) plus torsion (w): the same
//! formulas with m = 0.
//!
//! Every Gauss loop here runs over a [`CellValues`] (`N`, `dN`, `r`, `det J`
//! at the rule's points, mapped once per cell); [`StrainPoint`] is the same
//! per-point step at one arbitrary point.

use crate::elements::cell_values::{cell_extent, map_point, CellValues};
use crate::elements::{c_m, zero_matrix, DOF_PER_NODE};
use crate::material::Elastic;
use axijoint_mesh::quadrature::Rule2D;
use axijoint_mesh::shapes::MAX_CELL_NODES;
use axijoint_mesh::CellKind;
use nalgebra::DMatrix;
#[cfg(doc)]
use {crate::elements::CellError, axijoint_mesh::quadrature::default_rule};

/// Points closer to the axis than `AXIS_TOL` times the element size are
/// treated as on the axis by [`strain_at`].
pub const AXIS_TOL: f64 = 1e-9;

/// Fills the 6 x 3n matrix `B` with hoop factor `h_i` standing for `N_i / r`.
fn fill_b(m: u32, dn_drz: &[[f64; 2]], hoop: impl Fn(usize) -> f64, out: &mut DMatrix<f64>) {
    let n = dn_drz.len();
    zero_matrix(out, 6, DOF_PER_NODE * n);
    let mf = f64::from(m);
    for (i, &[nr, nz]) in dn_drz.iter().enumerate() {
        let (c, h) = (DOF_PER_NODE * i, hoop(i));
        out[(0, c)] = nr;
        out[(1, c + 1)] = nz;
        out[(2, c)] = h;
        out[(2, c + 2)] = mf * h;
        out[(3, c)] = nz;
        out[(3, c + 1)] = nr;
        out[(4, c)] = -mf * h;
        out[(4, c + 2)] = nr - h;
        out[(5, c + 1)] = -mf * h;
        out[(5, c + 2)] = nz;
    }
}

/// Strain-displacement matrix `B` (6 x 3n, `eps = B u_elem`) of harmonic `m`
/// at a point of radius `r > 0`, from the shape values `n` and the physical
/// derivatives `dn_drz = [dN/dr, dN/dz]` (see the module doc for its rows).
///
/// `out` is resized to 6 x 3n if needed.
pub fn b_matrix(m: u32, n: &[f64], dn_drz: &[[f64; 2]], r: f64, out: &mut DMatrix<f64>) {
    let inv_r = 1.0 / r;
    fill_b(m, &dn_drz[..n.len()], |i| n[i] * inv_r, out);
}

/// `B` at a point on the axis (r = 0): the limit of [`b_matrix`] for
/// `r -> 0`, each `N_i / r` replaced by `dN_i/dr`.
///
/// Exact for displacements that satisfy the axis conditions (m = 0:
/// `u = w = 0`; m = 1: `v = 0`, `u + w = 0`; m >= 2: `u = v = w = 0`), because
/// then `u + m w`, `w + m u` and `m v` vanish along r = 0 and
/// `f / r -> df/dr` (l'Hopital):
/// `e_th = d(u + m w)/dr`, `g_rth = -m du/dr`, `g_zth = dw/dz - m dv/dr`.
pub fn b_matrix_on_axis(m: u32, dn_drz: &[[f64; 2]], out: &mut DMatrix<f64>) {
    fill_b(m, dn_drz, |i| dn_drz[i][0], out);
}

/// Workspace of [`solid_stiffness`]: the [`CellValues`] of the kind's
/// [`default_rule`]. Build it once and reuse it for every element; nothing
/// is allocated per element or per Gauss point (a change of kind reuses the
/// buffers, growing them if needed).
#[derive(Clone, Debug)]
pub struct SolidScratch {
    values: CellValues,
}

impl SolidScratch {
    /// Workspace for `kind` with its [`default_rule`].
    pub fn new(kind: CellKind) -> Self {
        SolidScratch {
            values: CellValues::with_default_rule(kind),
        }
    }

    /// The element kind this workspace is for.
    pub fn kind(&self) -> CellKind {
        self.values.kind()
    }

    /// The integration rule.
    pub fn rule(&self) -> Rule2D {
        self.values.rule()
    }

    /// The values of the last cell.
    pub fn values(&self) -> &CellValues {
        &self.values
    }
}

/// Maps `values` onto a cell. The element routines' callers hand them
/// validated meshes (which refuse degenerate and folded cells); a refused
/// cell ([`CellError`]) keeps the values as computed, and a result that is
/// not finite is caught where the solution is written, as before.
fn reinit<'a>(values: &'a mut CellValues, kind: CellKind, coords: &[[f64; 2]]) -> &'a CellValues {
    let _refused = values.reinit(kind, coords);
    values
}

/// The ring weight `c r |det J| w_q` of point `q` (in this product order:
/// the matrices and vectors are bit for bit those of the Gauss loops it
/// replaced).
fn ring_weight(values: &CellValues, q: usize, c: f64) -> f64 {
    c * values.r(q) * values.det(q).abs() * values.w_gauss(q)
}

/// Stiffness of a solid element for harmonic `m` (kernel `B^T D B r`):
///
/// ```text
/// K = c_m * sum_q B(q)^T D B(q) r(q) |det J(q)| w_q
/// ```
///
/// with the rule of [`default_rule`] (no point on the axis, so elements
/// touching the axis integrate as any other; the axis conditions are
/// constraints imposed at assembly). `coords` are the `kind.n_nodes()` nodes
/// in gmsh order; `|det J|` makes either orientation work. `out` is
/// resized to 3n x 3n if needed and overwritten; the result is exactly
/// symmetric. If `scratch` is for another kind it is switched. The products
/// are taken node block by node block in closed form (`each_point_block`).
///
/// A degenerate or folded cell ([`CellError`]; validation refuses them)
/// gives values that are not finite or wrong, as the Gauss loop always did.
pub fn solid_stiffness(
    kind: CellKind,
    coords: &[[f64; 2]],
    mat: &Elastic,
    m: u32,
    scratch: &mut SolidScratch,
    out: &mut DMatrix<f64>,
) {
    let values = reinit(&mut scratch.values, kind, coords);
    zero_matrix(out, DOF_PER_NODE * kind.n_nodes(), DOF_PER_NODE * kind.n_nodes());
    let mf = f64::from(m);
    each_point_block(values, mat, c_m(m), |f, a, b, t| {
        let mut k = [[0.0; 3]; 3];
        for (i, row) in k.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = f * (t[0][i][j] + mf * (t[1][i][j] + mf * t[2][i][j]));
            }
        }
        add_block(out, a, b, &k);
    });
    symmetrize(out);
}

/// The Gauss loop of the stiffness: `f(weight, a, b, t)` for every point
/// and node pair `a <= b`, the weight [`ring_weight`] with factor `c`, `t`
/// the parts `t[0] + m t[1] + m^2 t[2]` of the 3 x 3 block `B_a^T D B_b`
/// there (`N`, `dN/dr`, `dN/dz`, `h = N / r`), in closed form for the
/// isotropic `D` (lambda, G, A = lambda + 2 G) and the `B` of the module
/// doc: a fifth of the products of `B^T (D B)`.
fn each_point_block(
    values: &CellValues,
    mat: &Elastic,
    c: f64,
    mut f: impl FnMut(f64, usize, usize, &[[[f64; 3]; 3]; 3]),
) {
    let (l, g) = (mat.lame_lambda(), mat.shear_modulus());
    let a2 = l + 2.0 * g;
    for q in 0..values.n_points() {
        let weight = ring_weight(values, q, c);
        let (n, dn_rz, r) = (values.n(q), values.dn(q), values.r(q));
        let nn = n.len();
        // h_i = N_i / r, divided once per node rather than once per pair
        let mut h = [0.0; MAX_CELL_NODES];
        for (hi, ni) in h.iter_mut().zip(n) {
            *hi = ni / r;
        }
        for a in 0..nn {
            let ([ra, za], ha) = (dn_rz[a], h[a]);
            for b in a..nn {
                let ([rb, zb], hb) = (dn_rz[b], h[b]);
                let hh = ha * hb;
                let t = [
                    [
                        [
                            ra * (a2 * rb + l * hb) + ha * (l * rb + a2 * hb) + g * za * zb,
                            l * (ra + ha) * zb + g * za * rb,
                            0.0,
                        ],
                        [l * za * (rb + hb) + g * ra * zb, a2 * za * zb + g * ra * rb, 0.0],
                        [0.0, 0.0, g * ((ra - ha) * (rb - hb) + za * zb)],
                    ],
                    [
                        [0.0, 0.0, l * ra * hb + a2 * hh - g * ha * (rb - hb)],
                        [0.0, 0.0, l * za * hb - g * ha * zb],
                        [
                            l * ha * rb + a2 * hh - g * hb * (ra - ha),
                            l * ha * zb - g * za * hb,
                            0.0,
                        ],
                    ],
                    [[g * hh, 0.0, 0.0], [0.0, g * hh, 0.0], [0.0, 0.0, a2 * hh]],
                ];
                f(weight, a, b, &t);
            }
        }
    }
}

/// Adds block `k` at nodes `(a, b)` of `out`, and its transpose at `(b, a)`
/// when `a != b`.
fn add_block(out: &mut DMatrix<f64>, a: usize, b: usize, k: &[[f64; 3]; 3]) {
    let (ia, ib) = (DOF_PER_NODE * a, DOF_PER_NODE * b);
    for (i, row) in k.iter().enumerate() {
        for (j, &v) in row.iter().enumerate() {
            out[(ia + i, ib + j)] += v;
            if a != b {
                out[(ib + j, ia + i)] += v;
            }
        }
    }
}

/// B^T (D B) is symmetric up to rounding: make it exactly so.
fn symmetrize(out: &mut DMatrix<f64>) {
    for i in 0..out.nrows() {
        for j in i + 1..out.ncols() {
            let s = 0.5 * (out[(i, j)] + out[(j, i)]);
            out[(i, j)] = s;
            out[(j, i)] = s;
        }
    }
}

/// The three m-independent parts of [`solid_stiffness`]:
/// `K(m) = c_m (out[0] + m out[1] + m^2 out[2])`. `B = B(0) + m B_m`
/// (module doc), where column j of `B_m` has one entry `beta_j` in row
/// `rho_j`: `-N/r` in g_rth for u, `-N/r` in g_zth for v, `N/r` in e_th for
/// w. Summed over the points with weight `f = r |det J| w_q`:
///
/// ```text
/// out[0] = B(0)^T D B(0) f
/// out[1][a][b] = ((D B(0))[rho_b][a] beta_b + (D B(0))[rho_a][b] beta_a) f
/// out[2][a][b] = beta_a beta_b D[rho_a][rho_b] f
/// ```
pub fn solid_stiffness_terms(
    kind: CellKind,
    coords: &[[f64; 2]],
    mat: &Elastic,
    scratch: &mut SolidScratch,
    out: &mut [DMatrix<f64>; 3],
) {
    let values = reinit(&mut scratch.values, kind, coords);
    let nn = kind.n_nodes();
    for o in out.iter_mut() {
        zero_matrix(o, DOF_PER_NODE * nn, DOF_PER_NODE * nn);
    }
    // c = 1: `1 r` is `r` exactly.
    each_point_block(values, mat, 1.0, |f, a, b, t| {
        for (o, tk) in out.iter_mut().zip(t) {
            add_block(o, a, b, &tk.map(|row| row.map(|v| f * v)));
        }
    });
    for o in out.iter_mut() {
        symmetrize(o);
    }
}

/// The volumetric projection of a cell's Gauss points (the B-bar method,
/// Hughes 1980): `P = Phi (Phi^T W Phi)^-1 Phi^T W`, `Phi` the pressure
/// basis at the points (1, and r and z for cells of 6 nodes or more) and
/// `W` their weights `r |det J| w_q`. It is self-adjoint in the weighted
/// product, so the strain it projects and the mean stress it projects are
/// each other's transposes.
pub fn volumetric_projection(values: &CellValues) -> DMatrix<f64> {
    let nq = values.n_points();
    let np = if values.n(0).len() >= 6 { 3 } else { 1 };
    let w: Vec<f64> = (0..nq).map(|q| values.r(q) * values.weight(q)).collect();
    let total: f64 = w.iter().sum();
    let centre = (0..nq).fold([0.0; 2], |c, q| {
        let x = values.position(q);
        [c[0] + w[q] * x[0] / total, c[1] + w[q] * x[1] / total]
    });
    let size = values.size().max(f64::MIN_POSITIVE);
    let phi = DMatrix::from_fn(nq, np, |q, k| match k {
        0 => 1.0,
        1 => (values.position(q)[0] - centre[0]) / size,
        _ => (values.position(q)[1] - centre[1]) / size,
    });
    let mut phi_w = phi.transpose();
    for (q, wq) in w.iter().enumerate() {
        phi_w.column_mut(q).scale_mut(*wq);
    }
    let gram = &phi_w * &phi;
    let inverse = gram.try_inverse().unwrap_or_else(|| DMatrix::zeros(np, np));
    &phi * inverse * phi_w
}

/// The two parts of the strain operator at point `q`, `B = B0 + m B1`
/// (module doc), `6 x 3n` each.
fn strain_parts(values: &CellValues, q: usize) -> [DMatrix<f64>; 2] {
    let (n, dn, r) = (values.n(q), values.dn(q), values.r(q));
    let nd = DOF_PER_NODE * n.len();
    let mut b0 = DMatrix::zeros(6, nd);
    let mut b1 = DMatrix::zeros(6, nd);
    for (i, (ni, di)) in n.iter().zip(dn).enumerate() {
        let (nr, nz, h) = (di[0], di[1], ni / r);
        let (u, v, w) = (3 * i, 3 * i + 1, 3 * i + 2);
        b0[(0, u)] = nr;
        b0[(1, v)] = nz;
        b0[(2, u)] = h;
        b0[(3, u)] = nz;
        b0[(3, v)] = nr;
        b0[(4, w)] = nr - h;
        b0[(5, w)] = nz;
        b1[(2, w)] = h;
        b1[(4, u)] = -h;
        b1[(5, v)] = -h;
    }
    [b0, b1]
}

/// Replaces the volumetric part of the strain operators `ops[q]` (6 rows
/// each, one per point) by its projection `P` ([`volumetric_projection`]).
pub fn project_volumetric(p: &DMatrix<f64>, ops: &mut [DMatrix<f64>]) {
    let vol: Vec<nalgebra::RowDVector<f64>> = ops.iter().map(|b| b.row(0) + b.row(1) + b.row(2)).collect();
    for (q, b) in ops.iter_mut().enumerate() {
        let mut bar = -vol[q].clone();
        for (k, v) in vol.iter().enumerate() {
            bar += p[(q, k)] * v;
        }
        for row in 0..3 {
            let mut r = b.row_mut(row);
            r += &bar / 3.0;
        }
    }
}

/// [`solid_stiffness_terms`] of the B-bar cell: the volumetric strain
/// projected onto the pressure basis of [`volumetric_projection`] (no
/// locking where the plastic flow keeps the volume), `K(m) = c_m (out[0] +
/// m out[1] + m^2 out[2])`.
pub fn solid_stiffness_terms_bbar(
    kind: CellKind,
    coords: &[[f64; 2]],
    mat: &Elastic,
    scratch: &mut SolidScratch,
    out: &mut [DMatrix<f64>; 3],
) {
    let values = reinit(&mut scratch.values, kind, coords);
    let nd = DOF_PER_NODE * kind.n_nodes();
    for o in out.iter_mut() {
        zero_matrix(o, nd, nd);
    }
    let p = volumetric_projection(values);
    let nq = values.n_points();
    let (mut b0, mut b1): (Vec<_>, Vec<_>) = (0..nq)
        .map(|q| {
            let [a, b] = strain_parts(values, q);
            (a, b)
        })
        .unzip();
    project_volumetric(&p, &mut b0);
    project_volumetric(&p, &mut b1);
    let d = DMatrix::from_column_slice(6, 6, mat.d_matrix().as_slice());
    for q in 0..nq {
        let f = values.r(q) * values.weight(q);
        let (db0, db1) = (&d * &b0[q], &d * &b1[q]);
        out[0] += f * b0[q].transpose() * &db0;
        out[1] += f * (b0[q].transpose() * &db1 + b1[q].transpose() * &db0);
        out[2] += f * b1[q].transpose() * &db1;
    }
    for o in out.iter_mut() {
        symmetrize(o);
    }
}

/// [`solid_stiffness`] of the B-bar cell of [`solid_stiffness_terms_bbar`].
pub fn solid_stiffness_bbar(
    kind: CellKind,
    coords: &[[f64; 2]],
    mat: &Elastic,
    m: u32,
    scratch: &mut SolidScratch,
    out: &mut DMatrix<f64>,
) {
    let mut terms = [DMatrix::zeros(0, 0), DMatrix::zeros(0, 0), DMatrix::zeros(0, 0)];
    solid_stiffness_terms_bbar(kind, coords, mat, scratch, &mut terms);
    let (mf, c) = (f64::from(m), c_m(m));
    let [a, b, cc] = terms;
    *out = c * (a + mf * b + mf * mf * cc);
}

/// Consistent nodal forces of a body force of harmonic `m` with amplitudes
/// `b(r, z) = (b_r, b_z, b_theta)` (force / length^3, the families' cos /
/// sin factors as for tractions) on one cell, added to `out` (node-major,
/// `3 n`):
///
/// ```text
/// f_i += c_m * sum_q N_i(q) b(x_q) r(q) |det J(q)| w_q
/// ```
///
/// with the rule of `values` (exact for a constant b on straight cells up to
/// quadratic ones with [`default_rule`], the rule of
/// [`CellValues::with_default_rule`] and of a switch of kind).
///
/// A degenerate or folded cell ([`CellError`]; validation refuses them)
/// gives values that are not finite or wrong, as the Gauss loop always did.
pub fn body_force_load(
    values: &mut CellValues,
    kind: CellKind,
    coords: &[[f64; 2]],
    m: u32,
    b: impl Fn([f64; 2]) -> [f64; 3],
    out: &mut [f64],
) {
    let values = reinit(values, kind, coords);
    let cm = c_m(m);
    for q in 0..values.n_points() {
        let scale = ring_weight(values, q, cm);
        let b = b(values.position(q));
        for (i, ni) in values.n(q).iter().enumerate() {
            for c in 0..DOF_PER_NODE {
                out[DOF_PER_NODE * i + c] += scale * ni * b[c];
            }
        }
    }
}

/// Nodal forces of an axisymmetric stress field `sigma(r, z)` (harmonic 0,
/// the order of [`STRESS_NAMES`]) on one cell, added to `out` (node-major,
/// `3 n`): the internal forces it exerts,
///
/// ```text
/// f += c_0 * sum_q B_0(q)^T sigma(q) r(q) |det J(q)| w_q
/// ```
///
/// with the rule of `values` (as for [`body_force_load`]). Equal to `K_0 u`
/// when `sigma` is the stress of the displacements u and the rule is the
/// [`default_rule`].
///
/// A degenerate or folded cell ([`CellError`]; validation refuses them)
/// gives values that are not finite or wrong, as the Gauss loop always did.
pub fn stress_forces(
    values: &mut CellValues,
    kind: CellKind,
    coords: &[[f64; 2]],
    sigma: impl Fn([f64; 2]) -> [f64; 6],
    out: &mut [f64],
) {
    let values = reinit(values, kind, coords);
    let nn = kind.n_nodes();
    let mut b = DMatrix::zeros(6, DOF_PER_NODE * nn);
    for q in 0..values.n_points() {
        let x = values.position(q);
        b_matrix(0, values.n(q), values.dn(q), x[0], &mut b);
        let s = sigma(x);
        let scale = ring_weight(values, q, c_m(0));
        for col in 0..DOF_PER_NODE * nn {
            let v: f64 = (0..6).map(|row| b[(row, col)] * s[row]).sum();
            out[col] += scale * v;
        }
    }
}

/// Names of the stress components in the order of [`stress_at`] (and of
/// every output).
pub const STRESS_NAMES: [&str; 6] = [
    "sigma_r",
    "sigma_z",
    "sigma_theta",
    "tau_rz",
    "tau_rtheta",
    "tau_ztheta",
];

/// Strain amplitudes `(e_r, e_z, e_th, g_rz, g_rth, g_zth)` of harmonic `m`
/// at the reference point `xi` of an element with nodal displacements
/// `u_elem = [u0, v0, w0, u1, ...]`.
///
/// On the axis (`r <= AXIS_TOL * h`, h the element's bounding-box diagonal)
/// the `1/r` terms are replaced by their exact limits (see
/// [`b_matrix_on_axis`]): `e_th = d(u + m w)/dr`, `g_rth = -m du/dr`,
/// `g_zth = dw/dz - m dv/dr`. These are the true limits when `u_elem`
/// satisfies the axis conditions, as every solution of the solver does.
/// For m = 0 they give `e_th = du/dr` (equal to `e_r` on the axis) and
/// `g_rth = 0`, as symmetry requires.
pub fn strain_at(kind: CellKind, coords: &[[f64; 2]], m: u32, u_elem: &[f64], xi: [f64; 2]) -> [f64; 6] {
    StrainPoint::new(kind, coords, xi).strain(m, u_elem)
}

/// One reference point of a cell, prepared for the strains and stresses of
/// many displacement fields there (harmonics, families, load cases):
/// [`strain_at`] without evaluating the shape functions and the Jacobian
/// again for each. The one-point, allocation-free counterpart of
/// [`CellValues`] (same per-point arithmetic); at the points of a rule use
/// [`point_strain`] and [`point_stress`].
#[derive(Clone, Copy, Debug)]
pub struct StrainPoint {
    nn: usize,
    n: [f64; MAX_CELL_NODES],
    drz: [[f64; 2]; MAX_CELL_NODES],
    x: [f64; 2],
    det: f64,
    on_axis: bool,
}

impl StrainPoint {
    /// The point `xi` of the cell `kind` with nodes at `coords`.
    pub fn new(kind: CellKind, coords: &[[f64; 2]], xi: [f64; 2]) -> StrainPoint {
        let nn = kind.n_nodes();
        let (mut n, mut dn, mut drz) = (
            [0.0; MAX_CELL_NODES],
            [[0.0; 2]; MAX_CELL_NODES],
            [[0.0; 2]; MAX_CELL_NODES],
        );
        kind.eval_n(xi, &mut n);
        kind.eval_dn(xi, &mut dn);
        let coords = &coords[..nn];
        let (x, det) = map_point(kind, coords, &n[..nn], &dn[..nn], &mut drz[..nn]);
        let extent = cell_extent(coords);
        StrainPoint {
            nn,
            n,
            drz,
            x,
            det,
            on_axis: on_axis(x[0], extent[0].hypot(extent[1])),
        }
    }

    /// Strain amplitudes of harmonic `m` of the nodal displacements
    /// `u_elem` (as [`strain_at`]).
    pub fn strain(&self, m: u32, u_elem: &[f64]) -> [f64; 6] {
        let nn = self.nn;
        strain_kernel(&self.n[..nn], &self.drz[..nn], self.x[0], self.on_axis, m, u_elem)
    }

    /// Stress amplitudes `D eps` (as [`stress_at`]).
    pub fn stress(&self, mat: &Elastic, m: u32, u_elem: &[f64]) -> [f64; 6] {
        stress_of(mat, self.strain(m, u_elem))
    }

    /// The shape values `N_i` there.
    pub fn n(&self) -> &[f64] {
        &self.n[..self.nn]
    }

    /// The point's `(r, z)`.
    pub fn position(&self) -> [f64; 2] {
        self.x
    }

    /// The Jacobian determinant of the cell's map there.
    pub fn det(&self) -> f64 {
        self.det
    }
}

/// Strain amplitudes of harmonic `m` of the nodal displacements `u_elem` at
/// point `q` of `values` (after [`CellValues::reinit`]); as [`strain_at`]
/// there, to the bit.
pub fn point_strain(values: &CellValues, q: usize, m: u32, u_elem: &[f64]) -> [f64; 6] {
    let r = values.r(q);
    let axis = on_axis(r, values.size());
    strain_kernel(values.n(q), values.dn(q), r, axis, m, u_elem)
}

/// Stress amplitudes `D eps` at point `q` of `values` (as [`point_strain`]).
pub fn point_stress(values: &CellValues, q: usize, mat: &Elastic, m: u32, u_elem: &[f64]) -> [f64; 6] {
    stress_of(mat, point_strain(values, q, m, u_elem))
}

/// True for a point of radius `r` on the axis of a cell of size `h` (see
/// [`strain_at`]).
fn on_axis(r: f64, h: f64) -> bool {
    r.abs() <= AXIS_TOL * h
}

/// `D eps`.
fn stress_of(mat: &Elastic, eps: [f64; 6]) -> [f64; 6] {
    (mat.d_matrix() * nalgebra::SVector::<f64, 6>::from(eps)).into()
}

/// The strains of [`strain_at`] from the shape values `n`, gradients
/// `drz` and radius `r` of a point.
fn strain_kernel(n: &[f64], drz: &[[f64; 2]], r: f64, on_axis: bool, m: u32, u_elem: &[f64]) -> [f64; 6] {
    // f[c] = [value, d/dr, d/dz] of component c = u, v, w
    let mut f = [[0.0; 3]; 3];
    for (i, (ni, di)) in n.iter().zip(drz).enumerate() {
        for (c, fc) in f.iter_mut().enumerate() {
            let ui = u_elem[DOF_PER_NODE * i + c];
            fc[0] += ni * ui;
            fc[1] += di[0] * ui;
            fc[2] += di[1] * ui;
        }
    }
    let [[u, u_r, u_z], [v, v_r, v_z], [w, w_r, w_z]] = f;
    let mf = f64::from(m);
    // (u + m w)/r, (w + m u)/r, m v / r
    let (hoop_u, hoop_w, hoop_v) = if on_axis {
        (u_r + mf * w_r, w_r + mf * u_r, mf * v_r)
    } else {
        ((u + mf * w) / r, (w + mf * u) / r, mf * v / r)
    };
    [u_r, v_z, hoop_u, u_z + v_r, w_r - hoop_w, w_z - hoop_v]
}

/// Stress amplitudes `D eps` in the order `(s_r, s_z, s_th, t_rz, t_rth,
/// t_zth)` at the reference point `xi`; see [`strain_at`] (also for points
/// on the axis).
pub fn stress_at(
    kind: CellKind,
    coords: &[[f64; 2]],
    mat: &Elastic,
    m: u32,
    u_elem: &[f64],
    xi: [f64; 2],
) -> [f64; 6] {
    StrainPoint::new(kind, coords, xi).stress(mat, m, u_elem)
}
