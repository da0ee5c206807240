//! The joint-block solve of the iteration ([`Model::solve_joint`]) against
//! the full solve.
//!
//! Source: linear algebra. With the joint equations ordered last, `K = L L^T`
//! and a right-hand side zero outside the joint block, the forward solve
//! leaves the other unknowns zero and the joint block of the backward solve
//! needs no others: `K^-1 b` restricted to the joint block is exact, not an
//! approximation. So the two answers must agree to round-off (tolerance
//! 1e-10 relative to the largest displacement; measured ~1e-15).
//!
//! Meshes (real gmsh runs): Scene P (Q9, one joint along the pile side,
//! bonded at the pile head), and `geo/joint_junctions_loaded.geo` (T6,
//! three joints: a T-junction, a joint from the axis, where the axis
//! variables (p, v, q) mix the node DOFs, and an embedded crack), for
//! harmonics 0..=3 (every axis pinning pattern) and both families at once.
//! A factor reduced to its joint block ([`Model::joint_block`]) gives the
//! same joint solves and full solves, value for value (the rest of its
//! values read back from disk where there is one, else factorized again).
//! The stiff joints' `Z_m = [K_m^-1]` on the joint nodes
//! ([`Model::joint_inverse`], kept with its factor) applied to a load is
//! the joint-block solve of it, in narrow passes and in wide ones.

use axijoint_solver::linear::{HarmonicFactor, Model};
use axijoint_solver::run::{build_model, mesh_scene};
use axijoint_solver::scene::Scene;
use std::path::PathBuf;
use std::sync::Arc;

fn geo(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../geo")
        .join(name)
}

fn check(scene: &Scene, label: &str, reduced: bool) {
    let (mesh, _) = mesh_scene(scene, None).expect("mesh");
    let model = build_model(scene, mesh).expect("model");
    let joint_nodes = model.joint_nodes().to_vec();
    assert!(!joint_nodes.is_empty(), "{label}: no joint nodes");
    let n = 3 * model.mesh.nodes.len();
    let nj = 3 * joint_nodes.len();
    for m in 0..=3u32 {
        let factor = model.factorize(m).expect("factorize");
        let g: [Vec<f64>; 2] = [
            (0..nj).map(|i| ((i * 7 % 11) as f64 - 5.0) * 0.1).collect(),
            (0..nj).map(|i| (i as f64 * 0.37).cos()).collect(),
        ];
        let mut full_loads = [vec![0.0; n], vec![0.0; n]];
        for (j, &k) in joint_nodes.iter().enumerate() {
            for (fl, gl) in full_loads.iter_mut().zip(&g) {
                fl[3 * k..3 * k + 3].copy_from_slice(&gl[3 * j..3 * j + 3]);
            }
        }
        let full = model.solve(&factor, &[&full_loads[0], &full_loads[1]]);
        let joint = model.solve_joint(&factor, &[&g[0], &g[1]]);
        check_inverse(&model, &factor, &g, &joint, &format!("{label} m = {m}"));
        // The factor reduced to its joint block: the same joint solve value
        // for value, and a full solve (factorized again) equal to the whole
        // factor's.
        let lean = model.joint_block(model.factorize(m).expect("factorize"));
        // (A small factor is simplicial, or one supernode: kept whole.)
        assert_eq!(
            !lean.is_full() && lean.stored_bytes() < factor.stored_bytes(),
            reduced,
            "{label}: reduced"
        );
        assert_eq!(lean.stored_bytes(), 8 * model.joint_block_len(), "{label}");
        // The first reduced factor of a model always tries the disk.
        if reduced && m == 0 {
            assert_eq!(
                lean.on_disk(),
                axijoint_solver::spill::usable(),
                "{label}: on disk"
            );
        }
        assert_eq!(
            model.solve_joint(&lean, &[&g[0], &g[1]]),
            joint,
            "{label} m = {m}: joint block"
        );
        assert_eq!(
            model.solve(&lean, &[&full_loads[0], &full_loads[1]]),
            full,
            "{label} m = {m}: full solve from the joint block"
        );
        for f in 0..2 {
            let scale = full[f].iter().fold(0.0f64, |a, v| a.max(v.abs()));
            assert!(scale > 0.0, "{label} m = {m}: no response");
            let mut worst = 0.0f64;
            for (j, &k) in joint_nodes.iter().enumerate() {
                for c in 0..3 {
                    worst = worst.max((full[f][3 * k + c] - joint[f][3 * j + c]).abs());
                }
            }
            assert!(
                worst <= 1e-10 * scale,
                "{label} m = {m} family {f}: joint-block solve differs by {:.2e} (relative)",
                worst / scale
            );
        }
    }
}

/// `Z_m = [K_m^-1]` on the joint nodes ([`Model::joint_inverse`]) applied
/// to `g` gives the joint-block solve `joint` (both exact: agreement to
/// 1e-12 of the largest displacement, round-off of a sum of `3 n_j`
/// products), and a second call returns the same matrix, not a new one.
fn check_inverse(
    model: &Model,
    factor: &HarmonicFactor,
    g: &[Vec<f64>; 2],
    joint: &[Vec<f64>; 2],
    label: &str,
) {
    let z = model.joint_inverse(factor);
    assert_eq!(z.nrows(), g[0].len(), "{label}");
    for f in 0..2 {
        let zg = &*z * nalgebra::DVector::from_column_slice(&g[f]);
        let scale = joint[f].iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let worst = zg
            .iter()
            .zip(&joint[f])
            .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
        assert!(
            worst <= 1e-12 * scale,
            "{label} family {f}: Z g differs from the joint solve by {:.2e} (relative)",
            worst / scale
        );
    }
    assert!(
        Arc::ptr_eq(&z, &model.joint_inverse(factor)),
        "{label}: formed again"
    );
}

/// A joint with `3 n_j >= 1024` (the pile in soil at size 0.1): `Z_m` is
/// formed 128 unit loads a pass there, 16 below (the other tests).
#[test]
fn joint_inverse_in_wide_passes_equals_the_joint_solve() {
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(geo("pile_soil.json")).expect("read")).expect("json");
    json["mesh"]["parameters"]["size"] = serde_json::json!(0.1);
    let scene = Scene::from_str(&json.to_string(), geo("pile_soil.json")).expect("scene");
    let (mesh, _) = mesh_scene(&scene, None).expect("mesh");
    let model = build_model(&scene, mesh).expect("model");
    let nj = 3 * model.joint_nodes().len();
    assert!(nj >= 1024, "3 n_j = {nj}: below the wide passes");
    for m in [0u32, 1] {
        let factor = model.factorize(m).expect("factorize");
        let g: [Vec<f64>; 2] = [
            (0..nj).map(|i| ((i * 7 % 11) as f64 - 5.0) * 0.1).collect(),
            (0..nj).map(|i| (i as f64 * 0.37).cos()).collect(),
        ];
        let joint = model.solve_joint(&factor, &[&g[0], &g[1]]);
        check_inverse(&model, &factor, &g, &joint, &format!("pile in soil m = {m}"));
    }
}

#[test]
fn joint_block_solve_equals_the_full_solve_on_scene_p() {
    let scene = Scene::from_path(geo("pile_footing.json")).expect("scene");
    check(&scene, "Scene P", true);
}

#[test]
fn joint_block_solve_equals_the_full_solve_at_junctions_and_the_axis() {
    let joint = r#"{"k_xi": 1e4, "k_eta": 1e4, "k_theta": 1e4, "law": {"type": "linear"}}"#;
    let text = format!(
        r#"{{
      "mesh": {{"file": "joint_junctions_loaded.geo", "parameters": {{"size": 0.25, "order": 2, "quads": 0}}}},
      "materials": {{"A": {{"E": 2e4, "nu": 0.2}}, "B": {{"E": 2e4, "nu": 0.2}}, "C": {{"E": 2e4, "nu": 0.2}}}},
      "joints": {{"ab": {joint}, "top": {joint}, "crack": {joint}}},
      "supports": [{{"on": "bottom", "fix": "all"}}],
      "loads": [{{"type": "resultant", "on": "c_top", "force": [1.0, 0, -10.0], "moment": [0, 6.0]}}],
      "harmonics": 3
    }}"#
    );
    // Read as if it sat in geo/ (nothing is written there).
    let scene = Scene::from_str(&text, geo("joint_block_junctions.json")).expect("scene");
    check(&scene, "junctions", false);
}
