//! Equilibrium of the solved models in every harmonic, and singular
//! (unsupported) models.
//!
//! Source: docs/theory.md sections 1-4 (families, c_m, axis conditions) and the
//! definition of the nodal loads f_m = c_m * (force per radian amplitude).
//! A node ring at (r, z) with nodal forces (f_r, f_z, f_theta) of harmonic m
//! carries per radian F(theta) = (f_r g_r, f_z g_z, f_theta g_theta) / c_m
//! with the angular factors g of its family; in Cartesian components
//! F_x = F_r cos - F_theta sin, F_y = F_r sin + F_theta cos, at the point
//! (r cos, r sin, z). Integrating over one turn (Integral(cos^2) =
//! Integral(sin^2) = pi = c_m for m >= 1, Integral(1) = 2 pi = c_0):
//!
//! | m, family | resultants (sums over the nodes) |
//! |---|---|
//! | 0 | Fz = f_z, Mz = Integral(x F_y - y F_x) = r f_theta |
//! | 1 Sym (cos, cos, sin) | Fx = f_r - f_theta, My = Integral(z F_x - x F_z) = z (f_r - f_theta) - r f_z |
//! | 1 Anti (sin, sin, -cos) | Fy = f_r - f_theta, Mx = Integral(y F_z - z F_y) = r f_z - z (f_r - f_theta) |
//! | >= 2 | all six vanish (every integrand carries a harmonic >= 1) |
//!
//! The table is `common::resultants`; the test checks it against a brute
//! force integration over theta (`common::resultants_by_quadrature`) on the
//! very load vectors used, so a sign slip in the table fails there.
//!
//! Goal: the support reactions R = K u - f (on supported DOFs only) balance
//! the applied loads: sum of resultants zero to 1e-9 relative; K u - f = 0
//! at every free DOF (at axis nodes: the free combinations of the axis
//! variables, docs/theory.md section 4); and Clapeyron's u . f = u . K u. The tolerance
//! 1e-9 is round-off of a sparse Cholesky on ~1e3-1e4 unknowns (measured
//! ~1e-13), with room to spare; a missing element contribution, a wrong
//! axis treatment or a load on the wrong DOF gives O(1).
//!
//! Mesh and supports: `geo/stacked_cylinders.geo` with a linear joint on
//! "interface" (so that the joint's forces take part), and the tubes of
//! `geo/cylinder.geo` / the stacked pair for the singular cases:
//!
//! ```text
//!   z = 2  +-------+  top: t = (0.3 + r, 0.5 r^2 - 1, 0.7 r)
//!          | upper |  side_upper: t = (1 - 0.2 z, 0.4 z, 0.1 z - 0.6)
//!   z = 1  +=======+  interface: joint (k_xi, k_eta, k_theta) = (300, 500, 200)
//!          | lower |  side_lower: r, theta fixed; t = (0, 0.8, 0) (partly
//!   z = 0  +-------+  bottom: z fixed          on supported DOFs)
//! ```
//!
//! The same amplitude functions serve every harmonic and family.
//! Parameters: a = 0.5, L1 = L2 = 1, E = 1000, nu = 0.25, size 0.25; T3 and
//! Q8 (Lin4 and Lin6 joints); harmonics 0, 1, 2, 3.

mod common;

use axijoint_mesh::{CellKind, Mesh};
use axijoint_solver::assembly::JointModel;
use axijoint_solver::elements::{JointRule, JointSprings};
use axijoint_solver::linear::{Model, SolveError};
use axijoint_solver::material::Elastic;
use common::*;

/// The jointed stacked cylinders with their springs (`k` for all three).
fn jointed(kind: CellKind, k: [f64; 3]) -> (Mesh, Vec<JointModel>) {
    let mesh = mesh(
        "stacked_cylinders.geo",
        kind,
        &[("a", 0.5), ("L1", 1.0), ("L2", 1.0), ("size", 0.25)],
        &["interface:lower/upper"],
    );
    let joints = mesh
        .joints
        .iter()
        .map(|j| {
            JointModel::new(
                JointSprings::new(k[0], k[1], k[2]).unwrap(),
                JointRule::default_for(j.elements[0].kind),
            )
        })
        .collect();
    (mesh, joints)
}

/// The load vector of the header (any harmonic, either family).
fn loads(mesh: &Mesh, m: u32) -> Vec<f64> {
    let mut f = traction(mesh, "top", m, &|r, _z| [0.3 + r, 0.5 * r * r - 1.0, 0.7 * r]);
    add_traction(
        mesh,
        "side_upper",
        m,
        &|_r, z| [1.0 - 0.2 * z, 0.4 * z, 0.1 * z - 0.6],
        &mut f,
    );
    add_traction(mesh, "side_lower", m, &|_r, _z| [0.0, 0.8, 0.0], &mut f);
    f
}

/// Euclidean norm of a resultant vector.
fn norm(v: &[f64; 6]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

#[test]
fn reactions_balance_the_loads_in_every_harmonic() {
    for kind in [CellKind::Tri3, CellKind::Quad8] {
        let (mesh, joints) = jointed(kind, [300.0, 500.0, 200.0]);
        let mut fixed = Supports::new(&mesh)
            .curve("bottom", &[Z])
            .curve("side_lower", &[R, TH])
            .done();
        // At an axis node a support on r or theta holds both (the lateral
        // displacement): mark both as supported for the reaction sums.
        for (k, p) in mesh.nodes.iter().enumerate() {
            if p[0] == 0.0 && (fixed[3 * k] || fixed[3 * k + 2]) {
                fixed[3 * k] = true;
                fixed[3 * k + 2] = true;
            }
        }
        let model = Model::new(
            mesh,
            vec![Elastic::new(1000.0, 0.25).unwrap(); 2],
            joints,
            fixed.clone(),
        )
        .unwrap();
        let mesh = &model.mesh;
        let on_axis: Vec<bool> = mesh.nodes.iter().map(|p| p[0] == 0.0).collect();
        for m in 0..=3u32 {
            let factor = model
                .factorize(m)
                .unwrap_or_else(|e| panic!("{kind:?} m = {m}: {e}"));
            let f = loads(mesh, m);
            let families: &[Family] = if m == 0 {
                &[Family::Sym]
            } else {
                &[Family::Sym, Family::Anti]
            };
            let rhs: Vec<&[f64]> = families.iter().map(|_| f.as_slice()).collect();
            let solutions = model.solve(&factor, &rhs);
            let f_scale = max_abs(&f);
            for (&family, u) in families.iter().zip(&solutions) {
                let label = format!("{kind:?} m = {m} {family:?}");
                let ku = model.internal_forces(m, u);
                let res: Vec<f64> = ku.iter().zip(&f).map(|(a, b)| a - b).collect();
                // 1. K u - f = 0 at the free DOFs.
                let mut free_res = 0.0f64;
                for (k, &axis) in on_axis.iter().enumerate() {
                    let (rr, rz, rt) = (res[3 * k], res[3 * k + 1], res[3 * k + 2]);
                    let lateral_free = !fixed[3 * k] && !fixed[3 * k + 2];
                    let z_free = !fixed[3 * k + 1];
                    let free: Vec<f64> = match (axis, m) {
                        (false, _) => (0..3)
                            .filter(|&c| !fixed[3 * k + c])
                            .map(|c| res[3 * k + c])
                            .collect(),
                        // m = 0: u = w = 0 on the axis, v free.
                        (true, 0) => {
                            if z_free {
                                vec![rz]
                            } else {
                                vec![]
                            }
                        }
                        // m = 1: v = 0, u + w = 0; the free variable moves u = -w.
                        (true, 1) => {
                            if lateral_free {
                                vec![rr - rt]
                            } else {
                                vec![]
                            }
                        }
                        (true, _) => vec![],
                    };
                    free_res = free.iter().fold(free_res, |a, b| a.max(b.abs()));
                }
                // 2. Resultants: loads + reactions (supported DOFs only) = 0.
                let reactions: Vec<f64> = res
                    .iter()
                    .zip(&fixed)
                    .map(|(r, &s)| if s { *r } else { 0.0 })
                    .collect();
                let all = |_k: usize| true;
                let load_res = resultants(mesh, &f, m, family, &all);
                let reac_res = resultants(mesh, &reactions, m, family, &all);
                let balance: [f64; 6] = std::array::from_fn(|i| load_res[i] + reac_res[i]);
                // The table against brute force, on both vectors.
                let load_quad = resultants_by_quadrature(mesh, &f, m, family);
                let reac_quad = resultants_by_quadrature(mesh, &reactions, m, family);
                let table_err = (0..6)
                    .map(|i| {
                        (load_quad[i] - load_res[i])
                            .abs()
                            .max((reac_quad[i] - reac_res[i]).abs())
                    })
                    .fold(0.0, f64::max);
                // 3. Clapeyron: u . f = u . K u.
                let uf: f64 = u.iter().zip(&f).map(|(a, b)| a * b).sum();
                let uku: f64 = u.iter().zip(&ku).map(|(a, b)| a * b).sum();
                let size_scale = f.iter().map(|x| x.abs()).sum::<f64>() * 2.0;
                println!(
                    "{label}: loads {}\n    free residual {:.2e}, balance {:.2e}, table vs quadrature {:.2e}, \
                     Clapeyron {:.2e}",
                    sci(&load_res),
                    free_res / f_scale,
                    norm(&balance) / norm(&load_res).max(f64::MIN_POSITIVE),
                    table_err / size_scale,
                    (uf - uku).abs() / uf.abs()
                );
                assert!(
                    free_res <= 1e-9 * f_scale,
                    "{label}: free residual {free_res:.3e}"
                );
                assert!(
                    table_err <= 1e-12 * size_scale,
                    "{label}: table vs quadrature {table_err:.3e}"
                );
                assert!(
                    (uf - uku).abs() <= 1e-9 * uf.abs(),
                    "{label}: u.f {uf:e} vs u.Ku {uku:e}"
                );
                if m <= 1 {
                    let n = norm(&load_res);
                    assert!(
                        n > 0.1,
                        "{label}: the loads have no resultant ({n:e}): the test would be empty"
                    );
                    assert!(
                        norm(&balance) <= 1e-9 * n,
                        "{label}: balance {balance:?} of loads {load_res:?}"
                    );
                } else {
                    // Nothing to balance: both vanish, checked by brute force.
                    assert!(
                        norm(&load_quad) <= 1e-12 * size_scale,
                        "{label}: loads {load_quad:?}"
                    );
                    assert!(
                        norm(&reac_quad) <= 1e-12 * size_scale,
                        "{label}: reactions {reac_quad:?}"
                    );
                }
            }
        }
    }
}

/// Asserts that `result` is the singular-stiffness error of harmonic `m`
/// and that its message says so; returns the message.
fn expect_singular(result: Result<impl Sized, SolveError>, m: u32, what: &str) -> String {
    match result {
        Err(e @ SolveError::Singular { .. }) => {
            let SolveError::Singular { m: got, .. } = &e else {
                unreachable!()
            };
            let message = e.to_string();
            println!("{what}, m = {m}: {message}");
            assert_eq!(*got, m, "{what}: wrong harmonic in {message}");
            assert!(message.contains(&format!("harmonic {m}")), "{what}: {message}");
            assert!(message.contains("singular"), "{what}: {message}");
            message
        }
        Err(e) => panic!("{what}, m = {m}: expected a singular-stiffness error, got {e}"),
        Ok(_) => panic!("{what}, m = {m}: expected a singular-stiffness error, got a factor"),
    }
}

/// Factorizes harmonic `m` and solves a load: a regular system gives finite
/// displacements.
fn expect_regular(model: &Model, m: u32, what: &str) {
    let factor = model
        .factorize(m)
        .unwrap_or_else(|e| panic!("{what}, m = {m}: expected a regular system, got {e}"));
    let f = traction(&model.mesh, "top", m, &|r, _z| [1.0, r, 0.5]);
    let u = &model.solve(&factor, &[&f])[0];
    assert!(
        u.iter().all(|x| x.is_finite()) && max_abs(u) > 0.0,
        "{what}, m = {m}"
    );
}

/// A cylinder with no supports at all: harmonics 0 and 1 hold the rigid
/// motions (0: translation along z, rotation about z; 1: translations in
/// x and y, rotations about x and y), so K_0 and K_1 are singular and
/// `factorize` must say so, naming the harmonic. Harmonics m >= 2 contain no
/// rigid motion: K_2 is regular even without supports.
///
/// With z fixed on the bottom only (no lateral restraint), harmonic 1 still
/// has the lateral translation (and harmonic 0 the rotation about the axis):
/// singular again.
#[test]
fn unsupported_cylinder_is_singular_in_the_harmonics_of_its_rigid_motions() {
    let material = vec![Elastic::new(1000.0, 0.25).unwrap()];
    let mesh = mesh("cylinder.geo", CellKind::Quad8, &[("size", 0.25)], &[]);
    let n = mesh.nodes.len();
    let free = Model::new(mesh.clone(), material.clone(), Vec::new(), vec![false; 3 * n]).unwrap();
    for m in [0, 1] {
        expect_singular(free.factorize(m), m, "no supports");
    }
    expect_regular(&free, 2, "no supports");

    let fixed = Supports::new(&mesh).curve("bottom", &[Z]).done();
    let sliding = Model::new(mesh, material, Vec::new(), fixed).unwrap();
    for m in [0, 1] {
        expect_singular(sliding.factorize(m), m, "bottom z only");
    }
    expect_regular(&sliding, 2, "bottom z only");
}

/// A joint with zero springs transmits nothing: with the lower cylinder
/// clamped, the upper one floats, and the error names that body.
#[test]
fn floating_body_behind_an_empty_joint_is_named() {
    let (mesh, joints) = jointed(CellKind::Quad8, [0.0, 0.0, 0.0]);
    let fixed = Supports::new(&mesh).curve("bottom", &[R, Z, TH]).done();
    let model = Model::new(mesh, vec![Elastic::new(1000.0, 0.25).unwrap(); 2], joints, fixed).unwrap();
    for m in [0, 1] {
        let message = expect_singular(model.factorize(m), m, "empty joint");
        assert!(
            message.contains("upper"),
            "the floating body is not named: {message}"
        );
        assert!(!message.contains("lower"), "the clamped body is named: {message}");
    }
    expect_regular(&model, 2, "empty joint");
}
