//! Body forces (issue 12, item 1): the self-weight of a material
//! (`unit_weight`) and the pseudo-static seismic coefficient, against
//! closed forms on a column (`geo/cylinder.geo`, a = 0.5, L = 5 = 10 a,
//! Q9).
//!
//! | test | claim | tolerance |
//! |---|---|---|
//! | self-weight | base reaction = weight `gamma pi a^2 L`; sigma_z = `-gamma (L - z)` in the middle third (uniaxial column on a roller base) | 1e-10; 1e-4 of gamma L |
//! | seismic | base shear = `k_h` x weight, applied overturning moment `k_h W L / 2` | 1e-10 |
//!
//! The uniaxial field `sigma_z = -gamma (L - z)`, `sigma_r = sigma_theta = 0`
//! is exact away from the base (its displacement `u_z` has a term
//! `nu gamma r^2 / (2E)` that a roller base, `u_z = 0`, does not allow; the
//! difference decays within about a radius); Q9 reproduces it (quadratic u).

use axijoint_mesh::geometry::interpolate;
use axijoint_solver::elements::stress_at;
use axijoint_solver::run::{solve_scene, Run};
use axijoint_solver::scene::Scene;
use std::f64::consts::PI;
use std::path::PathBuf;

const A: f64 = 0.5;
const L: f64 = 5.0;
const GAMMA: f64 = 0.02;

fn geo(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../geo")
        .join(name)
}

fn column(k_h: f64, fix: &str, harmonics: u32) -> Run {
    let text = format!(
        r#"{{
      "mesh": {{"file": "cylinder.geo", "parameters": {{"a": {A}, "L": {L}, "size": 0.125, "order": 2, "quads": 1}}}},
      "materials": {{"body": {{"E": 1000, "nu": 0.3, "unit_weight": {GAMMA}}}}},
      "supports": [{{"on": "bottom", "fix": {fix}}}],
      "seismic_coefficient": {k_h},
      "harmonics": {harmonics}
    }}"#
    );
    let scene = Scene::from_str(&text, geo("column.json")).unwrap_or_else(|e| panic!("{e}"));
    solve_scene(&scene, None, |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

fn weight() -> f64 {
    GAMMA * PI * A * A * L
}

#[test]
fn self_weight_of_a_column_is_uniaxial_and_carried_by_the_base() {
    let run = column(0.0, r#"["z", "theta"]"#, 0);
    let fz: f64 = run.reactions.iter().map(|r| r.force[2]).sum();
    println!("base reaction {fz:.12e}, weight {:.12e}", weight());
    assert!((fz / weight() - 1.0).abs() < 1e-10, "{fz}");
    assert!((run.applied.force[2] / weight() + 1.0).abs() < 1e-10);

    let mesh = &run.problem.model.mesh;
    let mat = run.problem.model.materials[0];
    let u = &run.displacements.harmonics[0].symmetric;
    let mut worst = 0.0f64;
    let mut checked = 0;
    for cell in &mesh.cells {
        let coords: Vec<[f64; 2]> = cell.nodes.iter().map(|&k| mesh.nodes[k]).collect();
        let nn = cell.kind.n_nodes();
        let mut n = vec![0.0; nn];
        cell.kind.eval_n([0.0, 0.0], &mut n);
        let [_, z] = interpolate(&coords, &n);
        if !(L / 3.0..=2.0 * L / 3.0).contains(&z) {
            continue;
        }
        let ue: Vec<f64> = cell
            .nodes
            .iter()
            .flat_map(|&k| u[3 * k..3 * k + 3].to_vec())
            .collect();
        let s = stress_at(cell.kind, &coords, &mat, 0, &ue, [0.0, 0.0]);
        let exact = [0.0, -GAMMA * (L - z), 0.0, 0.0];
        for c in 0..4 {
            worst = worst.max((s[c] - exact[c]).abs() / (GAMMA * L));
        }
        checked += 1;
    }
    println!("{checked} cells in the middle third: largest stress error {worst:.2e} of gamma L");
    assert!(checked > 10);
    assert!(worst < 1e-4, "{worst}");
}

#[test]
fn seismic_coefficient_gives_the_base_shear_and_overturning_moment() {
    let k_h = 0.15;
    let run = column(k_h, r#"["r", "z", "theta"]"#, 1);
    let fx: f64 = run.reactions.iter().map(|r| r.force[0]).sum();
    let applied = &run.applied;
    println!(
        "base shear {fx:.12e}, k_h W {:.12e}; applied My {:.12e}, k_h W L / 2 {:.12e}",
        k_h * weight(),
        applied.moment[1],
        k_h * weight() * L / 2.0
    );
    assert!((fx / (k_h * weight()) + 1.0).abs() < 1e-10, "{fx}");
    assert!((applied.force[0] / (k_h * weight()) - 1.0).abs() < 1e-10);
    assert!((applied.moment[1] / (k_h * weight() * L / 2.0) - 1.0).abs() < 1e-10);
}

#[test]
fn a_negative_unit_weight_is_refused_naming_the_key() {
    let text = format!(
        r#"{{
      "mesh": {{"file": "cylinder.geo", "parameters": {{"a": {A}, "L": {L}, "size": 0.5}}}},
      "materials": {{"body": {{"E": 1000, "nu": 0.3, "unit_weight": -1}}}},
      "supports": [{{"on": "bottom", "fix": "all"}}],
      "harmonics": 0
    }}"#
    );
    let scene = Scene::from_str(&text, geo("column.json")).unwrap_or_else(|e| panic!("{e}"));
    let err = solve_scene(&scene, None, |_| {})
        .err()
        .expect("refused")
        .to_string();
    assert!(err.contains("materials.body.unit_weight"), "{err}");
}
