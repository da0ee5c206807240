//! The stiffness of harmonic m from three stored arrays,
//! `K_m = c_m (A + m B + m^2 C)` ([`Model::assemble_from_terms`]), against
//! the element-by-element assembly ([`Model::assemble`]).
//!
//! Source: algebra. A solid's strain-displacement matrix is
//! `B(m) = B(0) + m B_m` (docs/theory.md; the module doc of
//! `elements::solid`), so `B^T D B` is a quadratic polynomial in m at every
//! Gauss point, and a joint's stiffness is `c_m` times a constant: the two
//! routes differ by rounding only. Tolerance: every entry within
//! `1e-13 sqrt(|K_ii K_jj|)` (rounding of sums of a few hundred terms is
//! ~1e-15 of that), the pinned axis equations (identity rows scaled by the
//! mean free diagonal) included.
//!
//! Meshes (real gmsh runs): `geo/stacked_cylinders.geo` in every element
//! family (T3, T6, Q4, Q8, Q9) with a joint between two bodies of different
//! materials, on the axis (so harmonics 0, 1 and >= 2 pin different axis
//! variables); `geo/joint_junctions_loaded.geo` (T6, three joints, one of
//! them starting on the axis). Harmonics 0, 1, 2 and 5.

mod common;

use axijoint_mesh::{CellKind, Mesh};
use axijoint_solver::assembly::JointModel;
use axijoint_solver::elements::{JointRule, JointSprings};
use axijoint_solver::linear::Model;
use axijoint_solver::material::Elastic;
use common::*;

const HARMONICS: [u32; 4] = [0, 1, 2, 5];

/// Largest `|direct - terms| / sqrt(|K_ii K_jj|)` over the stored entries
/// of harmonic `m`; panics if the pinned equations differ or none is pinned.
fn worst_difference(model: &Model, m: u32) -> f64 {
    let (direct, pinned) = model.assemble(m);
    let (terms, pinned_terms) = model.assemble_from_terms(m);
    assert_eq!(pinned, pinned_terms, "m = {m}: pinned equations");
    assert!(pinned.iter().any(|&p| p), "m = {m}: no axis equation pinned");
    let p = model.pattern();
    let diag: Vec<f64> = (0..p.n).map(|e| direct[p.slot(e, e)].abs()).collect();
    assert!(diag.iter().all(|&d| d > 0.0), "m = {m}: a zero diagonal");
    let mut worst = 0.0f64;
    for col in 0..p.n {
        for k in p.col_ptr[col]..p.col_ptr[col + 1] {
            let row = p.row_idx[k];
            let scale = (diag[row] * diag[col]).sqrt();
            worst = worst.max((direct[k] - terms[k]).abs() / scale);
        }
    }
    worst
}

fn check(label: &str, model: &Model) {
    for m in HARMONICS {
        let worst = worst_difference(model, m);
        println!("{label}, m = {m}: max difference {worst:.1e} of sqrt(|K_ii K_jj|)");
        assert!(
            worst <= 1e-13,
            "{label}, m = {m}: three-term K_m differs by {worst:.2e}"
        );
    }
}

fn model(mesh: Mesh, materials: &[(&str, Elastic)], rule: Option<JointRule>, fixed: Vec<bool>) -> Model {
    let materials = mesh
        .bodies
        .iter()
        .map(|b| materials.iter().find(|(n, _)| *n == b.name).expect("material").1)
        .collect();
    let joints = mesh
        .joints
        .iter()
        .enumerate()
        .map(|(j, joint)| {
            let k = JointSprings::new(300.0 + 50.0 * j as f64, 500.0, 200.0).unwrap();
            JointModel::new(k, rule.unwrap_or(JointRule::default_for(joint.elements[0].kind)))
        })
        .collect();
    Model::new(mesh, materials, joints, fixed).expect("model")
}

#[test]
fn three_terms_equal_direct_assembly_in_every_family() {
    for kind in FAMILIES {
        let mesh = mesh(
            "stacked_cylinders.geo",
            kind,
            &[("size", 0.25)],
            &["interface:lower/upper"],
        );
        assert!(!mesh.joints[0].elements.is_empty());
        let fixed = Supports::new(&mesh)
            .curve("bottom", &[Z])
            .point("origin", &[R])
            .done();
        let materials = [
            ("lower", Elastic::new(1000.0, 0.25).unwrap()),
            ("upper", Elastic::new(3000.0, 0.3).unwrap()),
        ];
        // The paper's one-point rule on T3, the default full rules elsewhere.
        let rule = (kind == CellKind::Tri3).then_some(JointRule::Paper);
        check(&format!("{kind:?}"), &model(mesh, &materials, rule, fixed));
    }
}

#[test]
fn three_terms_equal_direct_assembly_at_joint_junctions() {
    let mesh = mesh(
        "joint_junctions_loaded.geo",
        CellKind::Tri6,
        &[("size", 0.25)],
        &["ab", "top", "crack"],
    );
    assert_eq!(mesh.joints.len(), 3);
    let fixed = Supports::new(&mesh).curve("bottom", &[R, Z, TH]).done();
    let materials = [
        ("A", Elastic::new(2e4, 0.2).unwrap()),
        ("B", Elastic::new(1e4, 0.3).unwrap()),
        ("C", Elastic::new(3e4, 0.25).unwrap()),
    ];
    check("junctions", &model(mesh, &materials, None, fixed));
}

/// `factorize_all` (from the terms) and `factorize` of a fresh model
/// (element by element) solve alike: relative 1e-10 (conditioning).
#[test]
fn factorize_all_from_terms_solves_as_direct_factors() {
    let build = || {
        let mesh = mesh(
            "stacked_cylinders.geo",
            CellKind::Quad8,
            &[("size", 0.25)],
            &["interface:lower/upper"],
        );
        let fixed = Supports::new(&mesh).curve("bottom", &[R, Z, TH]).done();
        let materials = [
            ("lower", Elastic::new(1000.0, 0.25).unwrap()),
            ("upper", Elastic::new(3000.0, 0.3).unwrap()),
        ];
        model(mesh, &materials, None, fixed)
    };
    let (fresh, pooled) = (build(), build());
    let factors = pooled.factorize_all(&HARMONICS).expect("factorize_all");
    for (factor, m) in factors.iter().zip(HARMONICS) {
        let load = traction(&fresh.mesh, "top", m, &|r, _| [0.1 * r, -1.0, 0.2]);
        let direct = fresh.solve(&fresh.factorize(m).expect("factorize"), &[&load]);
        let terms = pooled.solve(factor, &[&load]);
        let scale = direct[0].iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let worst = direct[0]
            .iter()
            .zip(&terms[0])
            .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
        assert!(
            scale > 0.0 && worst <= 1e-10 * scale,
            "m = {m}: {worst:e} of {scale:e}"
        );
    }
}
