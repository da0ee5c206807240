//! Element matrices and vectors against closed forms.
//!
//! Layer 2 of the verification: solids (symmetry, rigid-body modes per
//! harmonic, rank, uniform axial strain and pure bending reproduced to
//! round-off, strains on the axis), joints (resultants and energies against
//! `c_m k delta Integral(r ds)`, the paper's Eq. 7 entries, consistency of the
//! per-point forces with the stiffness) and edge loads (resultants and first
//! moments of linear tractions on slanted edges).
//!
//! Geometry used throughout, in the meridional (r, z) plane, off the axis:
//!
//! ```text
//!   z                    distorted quad          distorted triangle
//!   ^   (0.9,1.1) 3 ____ 2 (2.0,1.4)          (1.4,1.3) 2
//!   |            /        \                            /  \
//!   |  (1.0,0.2) 0 ------- 1 (2.3,-0.1)      (1.0,0.2) 0 -- 1 (2.3,-0.1)
//!   +----------------------> r
//! ```
//!
//! Quadratic elements get straight sides (mid-side nodes at the midpoints).

use axijoint_mesh::geometry::interpolate;
use axijoint_mesh::{CellKind, EdgeKind, JointKind};
use axijoint_solver::elements::{
    add_traction_forces, b_matrix, c_m, edge_load, joint_points, joint_stiffness, relative_displacement,
    solid_stiffness, solid_stiffness_terms, strain_at, stress_at, JointError, JointRule, JointSprings,
    SolidScratch,
};
use axijoint_solver::material::{Elastic, MaterialError};
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use std::f64::consts::PI;

const CELLS: [CellKind; 5] = [
    CellKind::Tri3,
    CellKind::Tri6,
    CellKind::Quad4,
    CellKind::Quad8,
    CellKind::Quad9,
];
const QUADRATIC: [CellKind; 3] = [CellKind::Tri6, CellKind::Quad8, CellKind::Quad9];
const QUAD: [[f64; 2]; 4] = [[1.0, 0.2], [2.3, -0.1], [2.0, 1.4], [0.9, 1.1]];
const TRI: [[f64; 2]; 3] = [[1.0, 0.2], [2.3, -0.1], [1.4, 1.3]];
/// A parallelogram: the serendipity Q8 reproduces quadratic fields only on
/// affine maps (it lacks xi^2 eta^2), Q9 on any bilinear map.
const PARALLELOGRAM: [[f64; 2]; 4] = [[1.0, 0.2], [2.3, -0.1], [2.2, 1.2], [0.9, 1.5]];

fn mat() -> Elastic {
    Elastic::new(2.0e4, 0.17).unwrap()
}

/// Nodes of a straight-sided element from its corners (mid-sides at the
/// midpoints, the Q9 centre at the bilinear centre).
fn straight(kind: CellKind, corners: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let c = kind.n_corners();
    let mut x = corners[..c].to_vec();
    if kind.is_quadratic() {
        for e in 0..c {
            let (a, b) = (corners[e], corners[(e + 1) % c]);
            x.push([0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]);
        }
    }
    if kind == CellKind::Quad9 {
        let s = corners.iter().fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]]);
        x.push([0.25 * s[0], 0.25 * s[1]]);
    }
    x
}

fn element(kind: CellKind) -> Vec<[f64; 2]> {
    straight(kind, if kind.is_triangle() { &TRI } else { &QUAD })
}

fn stiffness(kind: CellKind, x: &[[f64; 2]], m: u32) -> DMatrix<f64> {
    let mut scratch = SolidScratch::new(kind);
    let mut k = DMatrix::zeros(0, 0);
    solid_stiffness(kind, x, &mat(), m, &mut scratch, &mut k);
    k
}

/// Nodal vector of a displacement field `(u, v, w)(r, z)`.
fn nodal(x: &[[f64; 2]], f: impl Fn(f64, f64) -> [f64; 3]) -> DVector<f64> {
    DVector::from_iterator(3 * x.len(), x.iter().flat_map(|p| f(p[0], p[1])))
}

/// Consistent loads of the boundary tractions of a stress field
/// `sigma(r, z)` (amplitudes, order s_r, s_z, s_th, t_rz, t_rth, t_zth) on
/// all edges of a straight-sided element: t = sigma . n with the outward
/// normal n of the counter-clockwise edge.
fn boundary_loads(
    kind: CellKind,
    x: &[[f64; 2]],
    m: u32,
    sigma: impl Fn(f64, f64) -> [f64; 6],
) -> DVector<f64> {
    let mut f = DVector::zeros(3 * kind.n_nodes());
    for e in 0..kind.n_corners() {
        let nodes = kind.edge_nodes(e);
        let ex: Vec<[f64; 2]> = nodes.iter().map(|&i| x[i]).collect();
        let (a, b) = (ex[0], ex[1]);
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let n = [(b[1] - a[1]) / len, -(b[0] - a[0]) / len];
        let t = |r: f64, z: f64| {
            let s = sigma(r, z);
            [
                s[0] * n[0] + s[3] * n[1],
                s[3] * n[0] + s[1] * n[1],
                s[4] * n[0] + s[5] * n[1],
            ]
        };
        let mut fe = [0.0; 9];
        edge_load(kind.edge_kind(), &ex, m, &t, &mut fe);
        for (k, &i) in nodes.iter().enumerate() {
            for c in 0..3 {
                f[3 * i + c] += fe[3 * k + c];
            }
        }
    }
    f
}

fn max_abs(k: &DMatrix<f64>) -> f64 {
    k.iter().fold(0.0f64, |a, v| a.max(v.abs()))
}

/// `c_m sum_q B^T D B r |det J| w` with the dense `B` of `b_matrix` and
/// `D` of the material: the definition, term by term.
fn stiffness_by_definition(kind: CellKind, x: &[[f64; 2]], m: u32) -> DMatrix<f64> {
    use axijoint_mesh::geometry::{derivatives_rz, jacobian};
    let nn = kind.n_nodes();
    let d = mat().d_matrix();
    let mut k = DMatrix::zeros(3 * nn, 3 * nn);
    let (mut n, mut dn, mut drz) = (vec![0.0; nn], vec![[0.0; 2]; nn], vec![[0.0; 2]; nn]);
    let mut b = DMatrix::zeros(6, 3 * nn);
    let rule = axijoint_mesh::quadrature::default_rule(kind);
    for (xi, w) in rule.points.iter().zip(rule.weights) {
        kind.eval_n(*xi, &mut n);
        kind.eval_dn(*xi, &mut dn);
        let (jac, det) = jacobian(kind, x, &dn);
        derivatives_rz(&jac, det, &dn, &mut drz);
        let r = interpolate(x, &n)[0];
        b_matrix(m, &n, &drz, r, &mut b);
        let dm = DMatrix::from_fn(6, 6, |i, j| d[(i, j)]);
        k += b.transpose() * dm * &b * (c_m(m) * r * det.abs() * w);
    }
    k
}

#[test]
fn stiffness_and_its_three_terms_are_the_quadrature_of_btdb() {
    // solid_stiffness takes the products node block by node block in closed
    // form; the definition multiplies the dense B and D.
    for kind in CELLS {
        let x = element(kind);
        let mut terms = [DMatrix::zeros(0, 0), DMatrix::zeros(0, 0), DMatrix::zeros(0, 0)];
        solid_stiffness_terms(kind, &x, &mat(), &mut SolidScratch::new(kind), &mut terms);
        for m in 0..4 {
            let reference = stiffness_by_definition(kind, &x, m);
            let scale = max_abs(&reference);
            let diff = max_abs(&(stiffness(kind, &x, m) - &reference));
            assert!(
                diff <= 1e-13 * scale,
                "{kind:?} m = {m}: {diff:.2e} of {scale:.2e}"
            );
            let mf = f64::from(m);
            let from_terms = (&terms[0] + &terms[1] * mf + &terms[2] * (mf * mf)) * c_m(m);
            let diff = max_abs(&(from_terms - &reference));
            assert!(
                diff <= 1e-13 * scale,
                "{kind:?} m = {m} (terms): {diff:.2e} of {scale:.2e}"
            );
        }
    }
}

#[test]
fn element_matrices_are_symmetric() {
    for kind in CELLS {
        for m in 0..4 {
            let k = stiffness(kind, &element(kind), m);
            let asym = max_abs(&(&k - k.transpose()));
            assert!(asym <= 1e-12 * max_abs(&k), "{kind:?} m = {m}: asymmetry {asym}");
        }
    }
    let springs = JointSprings::new(1.0e4, 2.0e4, 1.5e4).unwrap();
    let curved = [[1.0, 0.0], [1.5, 0.9], [1.4, 0.4]];
    for (kind, x) in [(JointKind::Lin4, &curved[..2]), (JointKind::Lin6, &curved[..])] {
        for rule in [JointRule::Paper, JointRule::Gauss(3), JointRule::Lobatto(3)] {
            let mut k = DMatrix::zeros(0, 0);
            joint_stiffness(kind, x, &springs, 1, rule, &mut k);
            let asym = max_abs(&(&k - k.transpose()));
            assert!(asym <= 1e-12 * max_abs(&k), "{kind:?} {rule:?}: asymmetry {asym}");
        }
    }
}

#[test]
fn rigid_body_modes_have_zero_energy() {
    // m = 0: axial translation v = 1, torsion w = r.
    // m = 1: translation along x: u_r = cos, u_theta = -sin -> (u, v, w) = (1, 0, -1);
    //        rotation about y (u_x = z, u_z = -x): (u, v, w) = (z, -r, -z).
    type Mode = fn(f64, f64) -> [f64; 3];
    let modes: [(u32, &str, Mode); 4] = [
        (0, "axial translation", |_, _| [0.0, 1.0, 0.0]),
        (0, "torsion", |r, _| [0.0, 0.0, r]),
        (1, "lateral translation", |_, _| [1.0, 0.0, -1.0]),
        (1, "rotation about y", |r, z| [z, -r, -z]),
    ];
    for kind in CELLS {
        let x = element(kind);
        for (m, name, mode) in modes {
            let k = stiffness(kind, &x, m);
            let phi = nodal(&x, mode);
            let res = (&k * &phi).norm();
            assert!(
                res <= 1e-10 * k.norm() * phi.norm(),
                "{kind:?} m = {m} {name}: |K phi| = {res}"
            );
        }
        // The rotation with the wrong sign of v is not a rigid mode.
        let k = stiffness(kind, &x, 1);
        let wrong = nodal(&x, |r, z| [z, r, -z]);
        assert!(
            (&k * &wrong).norm() > 1e-3 * k.norm() * wrong.norm(),
            "{kind:?}: wrong sign passes"
        );
    }
}

#[test]
fn zero_energy_modes_are_exactly_the_rigid_ones() {
    // Off the axis: 2 zero eigenvalues for m = 0 and m = 1, none for m >= 2
    // (smallest eigenvalue > 1e-6 of the largest).
    for kind in CELLS {
        let x = element(kind);
        for (m, expected) in [(0, 2), (1, 2), (2, 0), (3, 0)] {
            let eig = SymmetricEigen::new(stiffness(kind, &x, m)).eigenvalues;
            let max = eig.max();
            let zeros = eig.iter().filter(|&&l| l.abs() < 1e-10 * max).count();
            assert_eq!(zeros, expected, "{kind:?} m = {m}: eigenvalues {eig}");
            let nonzero_min = eig
                .iter()
                .filter(|&&l| l.abs() >= 1e-10 * max)
                .fold(f64::INFINITY, |a, &l| a.min(l));
            assert!(
                nonzero_min > 1e-6 * max,
                "{kind:?} m = {m}: smallest non-zero eigenvalue {nonzero_min}"
            );
        }
    }
}

#[test]
fn q4_ring_under_uniform_axial_strain_matches_the_hand_integral() {
    // Ring r in [r1, r2], z in [0, h], m = 0, uniaxial stress sigma_z = E eps:
    // u = -nu eps r, v = eps z. K u = the consistent loads of sigma_z on the
    // top and bottom faces: node at r1 gets 2 pi E eps L (2 r1 + r2) / 6, the
    // node at r2 2 pi E eps L (r1 + 2 r2) / 6 (L = r2 - r1); no radial force.
    let (r1, r2, h, eps) = (1.0, 1.8, 0.7, 1e-3);
    let e = mat();
    let x = [[r1, 0.0], [r2, 0.0], [r2, h], [r1, h]];
    let u = nodal(&x, |r, z| [-e.nu * eps * r, eps * z, 0.0]);
    let f = stiffness(CellKind::Quad4, &x, 0) * u;
    let l = r2 - r1;
    let f1 = 2.0 * PI * e.e * eps * l * (2.0 * r1 + r2) / 6.0;
    let f2 = 2.0 * PI * e.e * eps * l * (r1 + 2.0 * r2) / 6.0;
    let expected = [0.0, -f1, 0.0, 0.0, -f2, 0.0, 0.0, f2, 0.0, 0.0, f1, 0.0];
    for (i, (a, b)) in f.iter().zip(expected).enumerate() {
        assert!((a - b).abs() <= 1e-10 * f2, "dof {i}: {a} vs {b}");
    }
}

#[test]
fn uniform_axial_strain_is_reproduced_by_every_element() {
    // m = 0, u = -nu eps r, v = eps z on a distorted straight-sided element:
    // K u equals the consistent loads of t = sigma . n with sigma_z = E eps,
    // and the recovered stress is (0, E eps, 0, 0, 0, 0) everywhere.
    let e = mat();
    let eps = 1e-3;
    for kind in CELLS {
        let x = element(kind);
        let u = nodal(&x, |r, z| [-e.nu * eps * r, eps * z, 0.0]);
        let f = stiffness(kind, &x, 0) * &u;
        let g = boundary_loads(kind, &x, 0, |_, _| [0.0, e.e * eps, 0.0, 0.0, 0.0, 0.0]);
        assert!(
            (&f - &g).amax() <= 1e-10 * g.amax(),
            "{kind:?}: K u {f} vs loads {g}"
        );
        let s = stress_at(kind, &x, &e, 0, u.as_slice(), kind.ref_centre());
        let expected = [0.0, e.e * eps, 0.0, 0.0, 0.0, 0.0];
        for (a, b) in s.iter().zip(expected) {
            assert!((a - b).abs() <= 1e-9 * e.e * eps, "{kind:?}: stress {s:?}");
        }
    }
}

#[test]
fn pure_bending_is_reproduced_by_quadratic_elements() {
    // DESIGN section 6, harmonic 1: sigma_z = s r cos(theta) from
    // u_r = -s/(2E) (z^2 + nu r^2), u_z = s r z / E, u_theta = s/(2E) (z^2 - nu r^2).
    // Quadratic fields: T6, Q8 (on a parallelogram), Q9 reproduce K u = loads
    // and the stress to round-off.
    let e = mat();
    let s = 3.0;
    let field = |r: f64, z: f64| {
        [
            -s / (2.0 * e.e) * (z * z + e.nu * r * r),
            s * r * z / e.e,
            s / (2.0 * e.e) * (z * z - e.nu * r * r),
        ]
    };
    for kind in QUADRATIC {
        let x = if kind == CellKind::Quad8 {
            straight(kind, &PARALLELOGRAM)
        } else {
            element(kind)
        };
        let u = nodal(&x, field);
        let f = stiffness(kind, &x, 1) * &u;
        let g = boundary_loads(kind, &x, 1, |r, _| [0.0, s * r, 0.0, 0.0, 0.0, 0.0]);
        assert!(
            (&f - &g).amax() <= 1e-10 * g.amax(),
            "{kind:?}: K u {f} vs loads {g}"
        );
        for xi in [kind.ref_centre(), [0.1, 0.2], [0.3, 0.6]] {
            let mut n = [0.0; 9];
            kind.eval_n(xi, &mut n);
            let r = interpolate(&x, &n[..kind.n_nodes()])[0];
            let st = stress_at(kind, &x, &e, 1, u.as_slice(), xi);
            let expected = [0.0, s * r, 0.0, 0.0, 0.0, 0.0];
            for (a, b) in st.iter().zip(expected) {
                assert!((a - b).abs() <= 1e-10 * s, "{kind:?} at {xi:?}: stress {st:?}");
            }
        }
    }
}

#[test]
fn strain_on_the_axis_is_the_exact_limit() {
    // Quadratic fields satisfying the axis conditions of each harmonic, on
    // elements with an edge on r = 0. Closed-form strains at r = 0:
    //   m = 0: u = a r + b r z, v = z^2 + r^2, w = c r
    //          e = (a + b z, 2 z, a + b z, b r + 2 r = 0 + 0, 0, 0)
    //   m = 1: u = a r + z^2, v = c r + k r z, w = b r - z^2
    //          e = (a, 0, a + b, 2 z + c + k z, -a, -2 z - c - k z)
    //   m = 2: u = a r, v = c r, w = b r
    //          e = (a, 0, a + 2 b, c, -2 a, -2 c)
    let (a, b, c, k) = (0.3, -0.7, 0.45, 1.3);
    type Field = fn(f64, f64, [f64; 4]) -> [f64; 3];
    type Exact = fn(f64, [f64; 4]) -> [f64; 6];
    let cases: [(u32, Field, Exact); 3] = [
        (
            0,
            |r, z, [a, b, c, _]| [a * r + b * r * z, z * z + r * r, c * r],
            |z, [a, b, _, _]| [a + b * z, 2.0 * z, a + b * z, 0.0, 0.0, 0.0],
        ),
        (
            1,
            |r, z, [a, b, c, k]| [a * r + z * z, c * r + k * r * z, b * r - z * z],
            |z, [a, b, c, k]| [a, 0.0, a + b, 2.0 * z + c + k * z, -a, -2.0 * z - c - k * z],
        ),
        (
            2,
            |r, _, [a, b, c, _]| [a * r, c * r, b * r],
            |_, [a, b, c, _]| [a, 0.0, a + 2.0 * b, c, -2.0 * a, -2.0 * c],
        ),
    ];
    let p = [a, b, c, k];
    // Axis edges: Q (edge 3-0, xi = -1) and T (edge 2-0, xi = 0); Q9 on a
    // general quadrilateral, Q8 on a parallelogram.
    let quad = [[0.0, 0.0], [1.1, 0.1], [0.9, 1.2], [0.0, 1.0]];
    let parallelogram = [[0.0, 0.0], [1.1, 0.3], [1.1, 1.3], [0.0, 1.0]];
    let tri = [[0.0, 0.0], [1.2, 0.1], [0.0, 1.0]];
    for kind in QUADRATIC {
        let corners: &[[f64; 2]] = match kind {
            CellKind::Tri6 => &tri,
            CellKind::Quad8 => &parallelogram,
            _ => &quad,
        };
        let x = straight(kind, corners);
        for (m, field, exact) in cases {
            let u = nodal(&x, |r, z| field(r, z, p));
            for t in [0.25, 0.5, 0.8] {
                let xi = if kind.is_triangle() {
                    [0.0, t]
                } else {
                    [-1.0, 2.0 * t - 1.0]
                };
                let mut n = [0.0; 9];
                kind.eval_n(xi, &mut n);
                let [r, z] = interpolate(&x, &n[..kind.n_nodes()]);
                assert_eq!(r, 0.0);
                let e = strain_at(kind, &x, m, u.as_slice(), xi);
                let ex = exact(z, p);
                for (i, (s, t)) in e.iter().zip(ex).enumerate() {
                    assert!(
                        (s - t).abs() < 1e-12,
                        "{kind:?} m = {m} z = {z}: strain {i}: {s} vs {t}"
                    );
                }
                // Continuous with the off-axis formula (error O(r) = 1e-6).
                let near = if kind.is_triangle() {
                    [1e-6, t]
                } else {
                    [-1.0 + 1e-6, 2.0 * t - 1.0]
                };
                let e2 = strain_at(kind, &x, m, u.as_slice(), near);
                for (s, t) in e.iter().zip(e2) {
                    assert!((s - t).abs() < 1e-5, "{kind:?} m = {m}: {e:?} vs near {e2:?}");
                }
            }
        }
    }
}

fn springs() -> JointSprings {
    JointSprings::new(1.0e4, 2.0e4, 1.5e4).unwrap()
}

/// Straight joint from `a` at angle `alpha` with length `l`: Lin4 or Lin6 nodes.
fn joint_line(kind: JointKind, a: [f64; 2], alpha: f64, l: f64) -> Vec<[f64; 2]> {
    let b = [a[0] + l * alpha.cos(), a[1] + l * alpha.sin()];
    match kind {
        JointKind::Lin4 => vec![a, b],
        JointKind::Lin6 => vec![a, b, [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]],
    }
}

fn all_rules(kind: JointKind) -> Vec<JointRule> {
    match kind {
        JointKind::Lin4 => vec![
            JointRule::Paper,
            JointRule::Gauss(2),
            JointRule::Gauss(3),
            JointRule::Lobatto(2),
        ],
        JointKind::Lin6 => vec![
            JointRule::Paper,
            JointRule::Gauss(3),
            JointRule::Gauss(5),
            JointRule::Lobatto(3),
        ],
    }
}

fn joint_k(kind: JointKind, x: &[[f64; 2]], m: u32, rule: JointRule) -> DMatrix<f64> {
    let mut k = DMatrix::zeros(0, 0);
    joint_stiffness(kind, x, &springs(), m, rule, &mut k);
    k
}

/// Element vector with the top face displaced by the global vector `g`.
fn top_shift(nf: usize, g: [f64; 3]) -> DVector<f64> {
    DVector::from_iterator(
        6 * nf,
        (0..2 * nf).flat_map(|i| if i < nf { [0.0; 3] } else { g }),
    )
}

#[test]
fn uniform_normal_opening_gives_c_m_k_delta_integral_of_r() {
    // Slanted joint (alpha = 30 deg), r from 1.0: the top face opened by delta
    // along eta. Forces on the top face sum to c_m k_eta delta r_bar L eta, on
    // the bottom face to minus that, for every rule.
    let (alpha, l, delta) = (PI / 6.0, 0.8, 1e-3);
    let eta = [-alpha.sin(), alpha.cos()];
    for kind in [JointKind::Lin4, JointKind::Lin6] {
        let nf = if kind == JointKind::Lin4 { 2 } else { 3 };
        let x = joint_line(kind, [1.0, 0.5], alpha, l);
        let r_bar = 1.0 + 0.5 * l * alpha.cos();
        let u = top_shift(nf, [delta * eta[0], delta * eta[1], 0.0]);
        for m in [0, 1] {
            let total = c_m(m) * springs().k_eta * delta * r_bar * l;
            for rule in all_rules(kind) {
                let f = joint_k(kind, &x, m, rule) * &u;
                for c in 0..2 {
                    let top: f64 = (nf..2 * nf).map(|i| f[3 * i + c]).sum();
                    let bottom: f64 = (0..nf).map(|i| f[3 * i + c]).sum();
                    assert!(
                        (top - total * eta[c]).abs() <= 1e-12 * total,
                        "{kind:?} {rule:?} m={m} c={c}: {top}"
                    );
                    assert!(
                        (bottom + total * eta[c]).abs() <= 1e-12 * total,
                        "{kind:?} {rule:?} m={m}: {bottom}"
                    );
                }
                let theta: f64 = (0..2 * nf).map(|i| f[3 * i + 2]).sum();
                assert!(theta.abs() <= 1e-12 * total);
            }
        }
    }
}

#[test]
fn rotated_joint_has_the_energy_of_an_axis_aligned_one() {
    // Same centre (1.5, 0) and length 1, alpha = 0 and alpha = 30 deg; the
    // same uniform local relative displacement d gives the same energy
    // c_m / 2 (k_xi d_xi^2 + k_eta d_eta^2 + k_theta d_theta^2) r_bar L.
    let d = [0.3e-3, -0.2e-3, 0.5e-3];
    let k = springs();
    for kind in [JointKind::Lin4, JointKind::Lin6] {
        let nf = if kind == JointKind::Lin4 { 2 } else { 3 };
        for m in [0, 1, 2] {
            let exact =
                0.5 * c_m(m) * (k.k_xi * d[0] * d[0] + k.k_eta * d[1] * d[1] + k.k_theta * d[2] * d[2]) * 1.5;
            for rule in all_rules(kind) {
                for alpha in [0.0, PI / 6.0] {
                    let (c, s) = (alpha.cos(), alpha.sin());
                    let x = joint_line(kind, [1.5 - 0.5 * c, -0.5 * s], alpha, 1.0);
                    // global = T^T local
                    let u = top_shift(nf, [c * d[0] - s * d[1], s * d[0] + c * d[1], d[2]]);
                    let energy = 0.5 * u.dot(&(joint_k(kind, &x, m, rule) * &u));
                    assert!(
                        (energy - exact).abs() <= 1e-12 * exact,
                        "{kind:?} {rule:?} alpha {alpha} m={m}: {energy} vs {exact}"
                    );
                }
            }
        }
    }
}

#[test]
fn paper_rule_gives_the_entries_of_eq_7() {
    // Horizontal Lin4 from r = 1 to r = 3 (r_bar = 2, L = 2), m = 1:
    // every non-zero entry is +-pi r_bar L k / 4, + within a face, - across.
    let k = springs();
    let x = [[1.0, 0.4], [3.0, 0.4]];
    let kp = joint_k(JointKind::Lin4, &x, 1, JointRule::Paper);
    let unit = PI * 2.0 * 2.0 / 4.0;
    for a in 0..4 {
        for b in 0..4 {
            let sign = if (a < 2) == (b < 2) { 1.0 } else { -1.0 };
            for (i, ki) in [k.k_xi, k.k_eta, k.k_theta].into_iter().enumerate() {
                for j in 0..3 {
                    let expected = if i == j { sign * unit * ki } else { 0.0 };
                    let got = kp[(3 * a + i, 3 * b + j)];
                    assert!(
                        (got - expected).abs() <= 1e-12 * unit * k.k_eta,
                        "({a},{b}) [{i}{j}]: {got} vs {expected}"
                    );
                }
            }
        }
    }
    // m = 0 doubles it (c_0 = 2 pi); for Lin4 the paper's rule is Gauss(1).
    let k0 = joint_k(JointKind::Lin4, &x, 0, JointRule::Paper);
    assert!((k0[(0, 0)] - 2.0 * unit * k.k_xi).abs() <= 1e-12 * unit * k.k_xi);
    let slanted = [[1.0, 0.4], [2.2, 1.3]];
    let diff = joint_k(JointKind::Lin4, &slanted, 1, JointRule::Paper)
        - joint_k(JointKind::Lin4, &slanted, 1, JointRule::Gauss(1));
    assert!(max_abs(&diff) <= 1e-12 * unit * k.k_eta);
}

#[test]
fn lobatto_rule_lumps_the_joint_at_its_nodes() {
    // Horizontal Lin4 r = 1..3, Lobatto(2): node pairs decouple, K(b0, b0) =
    // c_m k r_0 L / 2 (weight L/2 at each end).
    let k = springs();
    let x = [[1.0, 0.0], [3.0, 0.0]];
    let kl = joint_k(JointKind::Lin4, &x, 1, JointRule::Lobatto(2));
    assert!((kl[(0, 0)] - PI * k.k_xi * 1.0 * 1.0).abs() <= 1e-12 * kl[(0, 0)]);
    assert!((kl[(3, 3)] - PI * k.k_xi * 3.0 * 1.0).abs() <= 1e-12 * kl[(3, 3)]);
    for (a, b) in [(0, 1), (0, 3), (1, 2), (2, 3)] {
        for i in 0..3 {
            assert_eq!(kl[(3 * a + i, 3 * b + i)], 0.0, "nodes {a}, {b} coupled");
        }
    }
}

#[test]
fn point_forces_reproduce_the_joint_stiffness() {
    // sum_q add_traction_forces(q, k d(q), c_m) = K u for any u, on a curved
    // Lin6 and a slanted Lin4, every rule: the per-point interface the
    // stress-transfer iteration uses is consistent with K.
    let curved = [[1.0, 0.0], [1.5, 0.9], [1.4, 0.4]];
    let k = springs();
    for (kind, x) in [(JointKind::Lin4, &curved[..2]), (JointKind::Lin6, &curved[..])] {
        let nf = x.len();
        let u = DVector::from_iterator(
            6 * nf,
            (0..6 * nf).map(|i| ((i * 7 + 3) % 11) as f64 * 1e-4 - 5e-4),
        );
        for rule in all_rules(kind) {
            for m in [0, 2] {
                let ku = joint_k(kind, x, m, rule) * &u;
                let mut f = vec![0.0; 6 * nf];
                for q in joint_points(kind, x, rule) {
                    let d = relative_displacement(&q, u.as_slice());
                    add_traction_forces(&q, k.traction(d), c_m(m), &mut f);
                }
                let err = ku.iter().zip(&f).fold(0.0f64, |a, (p, q)| a.max((p - q).abs()));
                assert!(err <= 1e-12 * ku.amax(), "{kind:?} {rule:?} m={m}: {err}");
            }
        }
    }
}

#[test]
fn joint_points_follow_a_curved_face() {
    // Lin6 on a parabolic arc: unit tangents, normal eta = (-t_z, t_r),
    // weights summing to the arc length (5-point Gauss, converged to 1e-6).
    let x = [[1.0, 0.0], [1.0, 1.0], [1.2, 0.5]];
    let (length, _) = axijoint_mesh::geometry::edge_length_and_lateral(EdgeKind::Lin3, &x);
    let pts = joint_points(JointKind::Lin6, &x, JointRule::Gauss(5));
    let total: f64 = pts.iter().map(|p| p.weight).sum();
    assert!((total - length).abs() < 1e-12);
    for p in &pts {
        assert!((p.tangent[0].hypot(p.tangent[1]) - 1.0).abs() < 1e-15);
        assert!((p.alpha.cos() - p.tangent[0]).abs() < 1e-15 && (p.alpha.sin() - p.tangent[1]).abs() < 1e-15);
        // x(s) = (1.2 - 0.2 s^2, (1 + s)/2): tangent along (-0.4 s, 0.5)
        let t = [-0.4 * p.s, 0.5];
        let tn = t[0].hypot(t[1]);
        assert!((p.tangent[0] - t[0] / tn).abs() < 1e-14 && (p.tangent[1] - t[1] / tn).abs() < 1e-14);
        // Opening along the local normal reads as d_eta.
        let g = [-p.tangent[1], p.tangent[0], 0.0];
        let mut u = vec![0.0; 18];
        for i in 3..6 {
            u[3 * i..3 * i + 3].copy_from_slice(&g);
        }
        let d = relative_displacement(p, &u);
        assert!(d[0].abs() < 1e-15 && (d[1] - 1.0).abs() < 1e-15 && d[2] == 0.0);
    }
}

#[test]
fn joint_input_errors_name_the_bad_value() {
    let e = JointSprings::new(1.0, -2.0, 1.0).unwrap_err();
    assert_eq!(
        e,
        JointError::Stiffness {
            name: "k_eta",
            value: -2.0
        }
    );
    assert!(e.to_string().contains("k_eta = -2"), "{e}");
    assert!(JointSprings::new(f64::NAN, 1.0, 1.0).is_err());
    assert!(JointSprings::new(0.0, 0.0, 0.0).is_ok());
    for bad in [
        JointRule::Gauss(0),
        JointRule::Gauss(6),
        JointRule::Lobatto(1),
        JointRule::Lobatto(6),
    ] {
        let e = bad.validate().unwrap_err();
        assert!(e.to_string().contains("not available"), "{e}");
    }
    for good in [JointRule::Paper, JointRule::Gauss(1), JointRule::Lobatto(5)] {
        assert!(good.validate().is_ok());
    }
    assert_eq!(JointRule::default_for(JointKind::Lin4), JointRule::Gauss(2));
    assert_eq!(JointRule::default_for(JointKind::Lin6), JointRule::Gauss(3));
}

#[test]
fn edge_load_of_a_linear_traction_on_a_slanted_edge() {
    // Edge from (r1, z1) to (r2, z2), x(tau) = a + tau (b - a), ds = L dtau,
    // traction t_c = p_c + q_c r + s_c z. Closed forms:
    //   Integral(r dtau) = (r1 + r2)/2, Integral(r^2 dtau) = (r1^2 + r1 r2 + r2^2)/3,
    //   Integral(r z dtau) = (2 r1 z1 + r1 z2 + r2 z1 + 2 r2 z2)/6,
    //   Integral(r^2 z dtau), Integral(r z^2 dtau) for the first moments.
    let (a, b): ([f64; 2], [f64; 2]) = ([0.6, -0.4], [1.9, 0.8]);
    let l = (b[0] - a[0]).hypot(b[1] - a[1]);
    let coef = [[1.0, 0.5, -0.3], [-2.0, 0.7, 0.4], [0.3, -0.2, 1.1]];
    let traction = |r: f64, z: f64| coef.map(|[p, q, s]| p + q * r + s * z);
    // Exact integrals over tau in [0, 1] of products of the linear functions r, z.
    let (r1, r2, z1, z2) = (a[0], b[0], a[1], b[1]);
    let i_r = (r1 + r2) / 2.0;
    let i_rr = (r1 * r1 + r1 * r2 + r2 * r2) / 3.0;
    let i_rz = (2.0 * r1 * z1 + r1 * z2 + r2 * z1 + 2.0 * r2 * z2) / 6.0;
    // Integral of f g h over [0, 1] for linear f, g, h (endpoint values).
    let triple = |f: [f64; 2], g: [f64; 2], h: [f64; 2]| {
        (3.0 * f[0] * g[0] * h[0]
            + f[0] * g[0] * h[1]
            + f[0] * g[1] * h[0]
            + f[1] * g[0] * h[0]
            + f[0] * g[1] * h[1]
            + f[1] * g[0] * h[1]
            + f[1] * g[1] * h[0]
            + 3.0 * f[1] * g[1] * h[1])
            / 12.0
    };
    let (rr, zz) = ([r1, r2], [z1, z2]);
    let i_rrr = triple(rr, rr, rr);
    let i_rrz = triple(rr, rr, zz);
    let i_rzz = triple(rr, zz, zz);
    let mid = [0.5 * (r1 + r2), 0.5 * (z1 + z2)];
    let off = [r1 + 0.35 * (r2 - r1), z1 + 0.35 * (z2 - z1)];
    for (kind, x) in [
        (EdgeKind::Lin2, vec![a, b]),
        (EdgeKind::Lin3, vec![a, b, mid]),
        (EdgeKind::Lin3, vec![a, b, off]),
    ] {
        for m in [0, 1] {
            let mut f = [0.0; 9];
            edge_load(kind, &x, m, &traction, &mut f);
            let cm = c_m(m);
            for (c, [p, q, s]) in coef.into_iter().enumerate() {
                let sum: f64 = (0..x.len()).map(|i| f[3 * i + c]).sum();
                let exact = cm * l * (p * i_r + q * i_rr + s * i_rz);
                assert!(
                    (sum - exact).abs() <= 1e-13 * exact.abs().max(1.0),
                    "{kind:?} m={m} c={c}: {sum} vs {exact}"
                );
                // First moments: sum_i f_i r_i = c_m Integral(t r r ds) (sum N_i r_i = r).
                let mom: f64 = (0..x.len()).map(|i| f[3 * i + c] * x[i][0]).sum();
                let exact = cm * l * (p * i_rr + q * i_rrr + s * i_rrz);
                assert!(
                    (mom - exact).abs() <= 1e-13 * exact.abs().max(1.0),
                    "{kind:?} m={m} c={c}: moment {mom}"
                );
                let mom_z: f64 = (0..x.len()).map(|i| f[3 * i + c] * x[i][1]).sum();
                let exact = cm * l * (p * i_rz + q * i_rrz + s * i_rzz);
                assert!(
                    (mom_z - exact).abs() <= 1e-13 * exact.abs().max(1.0),
                    "{kind:?} m={m} c={c}: z-moment {mom_z}"
                );
            }
        }
    }
}

#[test]
fn constant_traction_on_a_cylindrical_face_splits_one_four_one() {
    // Lin3 on r = R, z in [0, h], t_r = p: the nodes get c_m p R h (1, 1, 4)/6.
    let (r, h, p) = (2.0, 0.9, 5.0);
    let mut f = [0.0; 9];
    edge_load(
        EdgeKind::Lin3,
        &[[r, 0.0], [r, h], [r, 0.5 * h]],
        1,
        &|_, _| [p, 0.0, 0.0],
        &mut f,
    );
    let total = PI * p * r * h;
    for (i, w) in [1.0, 1.0, 4.0].into_iter().enumerate() {
        assert!(
            (f[3 * i] - total * w / 6.0).abs() <= 1e-13 * total,
            "node {i}: {}",
            f[3 * i]
        );
        assert_eq!((f[3 * i + 1], f[3 * i + 2]), (0.0, 0.0));
    }
}

#[test]
fn material_checks_and_d_matrix() {
    assert_eq!(
        Elastic::new(0.0, 0.2).unwrap_err(),
        MaterialError::Modulus { e: 0.0 }
    );
    assert!(Elastic::new(f64::INFINITY, 0.2).is_err());
    for nu in [0.5, -1.0, 0.7, f64::NAN] {
        let e = Elastic::new(1.0, nu).unwrap_err();
        assert!(e.to_string().contains("Poisson's ratio"), "{e}");
    }
    let e = mat();
    let d = e.d_matrix();
    // Uniaxial stress: eps = (-nu, 1, -nu, 0, 0, 0) gives sigma = (0, E, 0, 0, 0, 0).
    let s = d * nalgebra::SVector::<f64, 6>::from([-e.nu, 1.0, -e.nu, 0.0, 0.0, 0.0]);
    let expected = [0.0, e.e, 0.0, 0.0, 0.0, 0.0];
    for (a, b) in s.iter().zip(expected) {
        assert!((a - b).abs() <= 1e-12 * e.e, "{s}");
    }
    for i in 3..6 {
        assert!((d[(i, i)] - e.e / (2.0 * (1.0 + e.nu))).abs() <= 1e-12 * e.e);
    }
}
