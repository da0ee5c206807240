//! Ground water and effective stress (issue 26, item 3), against closed
//! forms (the drained pile shaft is in initial_state.rs).
//!
//! | test | claim | tolerance |
//! |---|---|---|
//! | geostatic column with water | a geostatic state from the buoyant weight below the water table is in balance with it: out-of-balance and phase displacement at round-off, the weight resultant buoyant | 1e-10 of the weight; 1e-9 of the gravity settlement |
//! | water above the ground | the same with the table 3 above the top (the seabed): the whole column buoyant | 1e-10 |
//! | gravity loading to the active state | an oedometer column of Mohr-Coulomb soil (c = 0, phi = 30, nu = 0.1: `nu / (1 - nu) < K_a`) loaded by its buoyant weight ends at `sigma'_h = K_a sigma'_v`, `sigma'_v` the buoyant overburden, at every Gauss point | 1e-10 of the largest stress |
//! | an elastic contrast | with nu = 0.3 (`nu / (1 - nu) > K_a`) no point yields and `sigma'_h = nu / (1 - nu) sigma'_v` | 1e-10 |
//! | mistakes | a water unit weight <= 0, a geostatic soil lighter than water, a missing or unknown key: refused naming the key | exact |
//!
//! Column: `geo/cylinder.geo`, a = 0.5, L = 5, Q9, split at the water
//! table z = 2.5, the side on rollers (`u_r = 0`), the base on rollers.

use axijoint_solver::iteration::plastic_points;
use axijoint_solver::run::{solve_scene, Run};
use axijoint_solver::scene::Scene;
use std::f64::consts::PI;
use std::path::PathBuf;

const A: f64 = 0.5;
const L: f64 = 5.0;
const GAMMA: f64 = 0.02;
const GAMMA_W: f64 = 0.01;
const E: f64 = 1000.0;

fn geo(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../geo")
        .join(name)
}

/// The effective vertical stress at height z of the column with its top at
/// L and the water table at `z_w`: the overburden of the soil above, each
/// part below the table buoyant.
fn sigma_v(z: f64, z_w: f64) -> f64 {
    let submerged = (z_w.min(L) - z).max(0.0);
    -GAMMA * (L - z) + GAMMA_W * submerged
}

fn column(nu: f64, z_w: f64, initial: &str, plasticity: &str) -> Run {
    let split = if z_w < L { z_w } else { 0.0 };
    let text = format!(
        r#"{{
      "mesh": {{"file": "cylinder.geo", "parameters": {{"a": {A}, "L": {L}, "size": 0.25, "order": 2, "quads": 1, "split": {split}}}}},
      "materials": {{"body": {{"E": {E}, "nu": {nu}, "unit_weight": {GAMMA}, "initial_stress": {initial}{plasticity}}}}},
      "water": {{"surface_z": {z_w}, "unit_weight": {GAMMA_W}}},
      "supports": [{{"on": "bottom", "fix": ["z", "theta"]}}, {{"on": "side", "fix": ["r", "theta"]}}],
      "harmonics": 0
    }}"#
    );
    let scene = Scene::from_str(&text, geo("column.json")).unwrap_or_else(|e| panic!("{e}"));
    solve_scene(&scene, None, |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

fn geostatic(nu: f64) -> String {
    let k0 = nu / (1.0 - nu);
    format!(r#"{{"type": "geostatic", "surface_z": {L}, "K0": {k0}}}"#)
}

#[test]
fn geostatic_column_with_water_is_in_balance() {
    for z_w in [L / 2.0, L + 3.0] {
        let run = column(0.3, z_w, &geostatic(0.3), "");
        let init = run.initial.as_ref().expect("an initial phase");
        let buoyant = PI * A * A * (GAMMA * L - GAMMA_W * z_w.min(L));
        println!("z_w = {z_w}: {:?}, buoyant weight {buoyant}", init.balance);
        assert!((init.balance.weight / buoyant - 1.0).abs() < 1e-10);
        assert!(init.balance.max_force < 1e-10 * buoyant, "{:?}", init.balance);
        let m_oed = E * 0.7 / (1.3 * 0.4);
        let settlement = GAMMA * L * L / (2.0 * m_oed);
        assert!(
            init.max_displacement < 1e-9 * settlement,
            "{}",
            init.max_displacement
        );
    }
}

/// The effective stresses at the plastic body points of `run`'s initial
/// phase against `sigma'_h = k sigma'_v`; returns the largest error over
/// the largest stress.
fn oedometric_error(run: &Run, z_w: f64, k: f64) -> f64 {
    let init = run.initial.as_ref().expect("an initial phase");
    let points = plastic_points(&run.problem.model).unwrap();
    assert_eq!(points.len(), init.body_stress.len());
    let scale = sigma_v(0.0, z_w).abs();
    let mut worst = 0.0f64;
    for ((_, p), s) in points.iter().zip(&init.body_stress) {
        let v = sigma_v(p[1], z_w);
        let exact = [k * v, v, k * v, 0.0, 0.0, 0.0];
        for c in 0..6 {
            worst = worst.max((s[c] - exact[c]).abs() / scale);
        }
    }
    worst
}

#[test]
fn gravity_loading_brings_mohr_coulomb_soil_to_the_active_state() {
    let phi = 30.0f64.to_radians();
    let k_a = (1.0 - phi.sin()) / (1.0 + phi.sin());
    let mc = r#", "plasticity": {"type": "mohr_coulomb", "cohesion": 0, "friction_deg": 30}"#;
    let z_w = L / 2.0;
    let run = column(0.1, z_w, r#"{"type": "gravity"}"#, mc);
    let init = run.initial.as_ref().unwrap();
    let worst = oedometric_error(&run, z_w, k_a);
    let yielding = init.body_plastic.iter().filter(|e| e[1] != 0.0).count();
    println!(
        "K_a = {k_a:.6}: worst error {worst:.3e} of the largest stress, {} of {} points with plastic strain, {} iterations",
        yielding,
        init.body_plastic.len(),
        init.iterations
    );
    assert!(worst < 1e-10, "{worst}");
    assert!(yielding > init.body_plastic.len() / 2, "{yielding}");
    // nu = 0.3: the at-rest ratio is above K_a, nothing yields.
    let run = column(0.3, z_w, r#"{"type": "gravity"}"#, mc);
    let init = run.initial.as_ref().unwrap();
    let worst = oedometric_error(&run, z_w, 0.3 / 0.7);
    println!("nu = 0.3: worst error {worst:.3e}");
    assert!(worst < 1e-10, "{worst}");
    assert!(init.body_plastic.iter().all(|e| *e == [0.0; 6]));
}

#[test]
fn mistakes_with_water_are_refused_naming_the_key() {
    let scene = |water: &str, gamma: f64| {
        let text = format!(
            r#"{{
          "mesh": {{"file": "cylinder.geo", "parameters": {{"a": {A}, "L": {L}}}}},
          "materials": {{"body": {{"E": {E}, "nu": 0.3, "unit_weight": {gamma}, "initial_stress": {}}}}},
          "water": {water},
          "harmonics": 0
        }}"#,
            geostatic(0.3)
        );
        Scene::from_str(&text, geo("column.json")).and_then(|s| s.check_values().map(|()| s))
    };
    for (water, gamma, key, words) in [
        (
            r#"{"surface_z": 2, "unit_weight": 0}"#,
            GAMMA,
            "water.unit_weight",
            "> 0",
        ),
        (
            r#"{"surface_z": 2, "unit_weight": -10}"#,
            GAMMA,
            "water.unit_weight",
            "> 0",
        ),
        (
            r#"{"surface_z": 2, "unit_weight": 0.03}"#,
            GAMMA,
            "materials.body.unit_weight",
            "lighter than water",
        ),
        (r#"{"surface_z": 2}"#, GAMMA, "unit_weight", "missing field"),
        (
            r#"{"surface_z": 2, "unit_weight": 0.01, "level": 3}"#,
            GAMMA,
            "level",
            "unknown field",
        ),
    ] {
        let e = scene(water, gamma).expect_err(water).to_string();
        println!("{water}: {e}");
        assert!(e.contains(key) && e.contains(words), "{water}: {e}");
    }
    // A weightless material is not buoyant: accepted.
    assert!(scene(r#"{"surface_z": 2, "unit_weight": 0.01}"#, 0.0).is_ok());
}
