//! Plausibility warnings (`run::warnings`): a run that is legal but looks
//! like a slip of units or scale, or that models more harmonics than its
//! answer needs, is solved and warned about; the scene as shipped is not.
//!
//! | case (bonded Scene P, coarse) | expected |
//! |---|---|
//! | as shipped (M = 4, a lateral load: harmonic 1) | no warning |
//! | M = 12 | harmonics 2..=12 are zero: "harmonics": 1 |
//! | both moduli in MPa typed as 1e-6 of their value | the displacement is far beyond 5 % of the model's size |
//! | the footing's modulus 1e7 times smaller | moduli 1e7 apart |
//! | a unit weight 1e4 (MN/m^3) | gamma L / E above 1 |
//! | water of 9.81 (kN/m^3) beside unit weights of 0.024 (MN/m^3); 0.00981 | unit weights out of scale with the water's; no warning |
//! | Scene P (newton) with its joint's springs 1e6 times table1's | k h / E far above 10 x the rigid penalty; as shipped, and rigid, no warning |

use axijoint_solver::run::{solve_scene, warnings};
use axijoint_solver::scene::Scene;
use std::path::PathBuf;

/// Bonded Scene P at mesh size 0.5, edited by `edit`.
fn scene(edit: impl FnOnce(&mut serde_json::Value)) -> Scene {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../geo/pile_footing_bonded.json");
    let mut v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    v["mesh"]["parameters"]["size"] = 0.5.into();
    edit(&mut v);
    Scene::from_str(&v.to_string(), &path).unwrap()
}

fn warned(sc: &Scene) -> Vec<String> {
    let run = solve_scene(sc, None, |_| {}).unwrap();
    warnings(sc, &run)
}

#[test]
fn implausible_runs_are_warned_about_and_the_shipped_scene_is_not() {
    assert_eq!(warned(&scene(|_| {})), Vec::<String>::new(), "as shipped");

    let w = warned(&scene(|v| v["harmonics"] = 12.into()));
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("harmonics 2..=12 are zero") && w[0].contains("\"harmonics\": 1"),
        "{w:?}"
    );

    let w = warned(&scene(|v| {
        v["materials"]["pile"]["E"] = 2e-2.into();
        v["materials"]["footing"]["E"] = 2e-2.into();
    }));
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("times the model's size") && w[0].contains("slip of units"),
        "{w:?}"
    );
    // Computed numbers in short form (not 17 digits).
    let digits = w[0].split(|c: char| !c.is_ascii_digit()).map(str::len).max();
    assert!(digits <= Some(4), "{w:?}");

    let w = warned(&scene(|v| v["materials"]["footing"]["E"] = 2e-3.into()));
    assert!(
        w.iter()
            .any(|w| w.contains("E of 'pile' (20000) is 10000000 times that of 'footing' (0.002)")),
        "{w:?}"
    );

    let w = warned(&scene(|v| v["materials"]["footing"]["unit_weight"] = 1e4.into()));
    assert!(
        w.iter()
            .any(|w| w.contains("materials.footing") && w.contains("gamma L / E")),
        "{w:?}"
    );

    // Water in kN/m^3 beside unit weights in MN/m^3; in MN/m^3 no warning.
    let wet = |gamma_w: f64| {
        scene(move |v| {
            v["materials"]["pile"]["unit_weight"] = 0.024.into();
            v["materials"]["footing"]["unit_weight"] = 0.024.into();
            v["water"] = serde_json::json!({"surface_z": 10.0, "unit_weight": gamma_w});
        })
    };
    let w = warned(&wet(9.81));
    assert!(
        w.iter()
            .any(|w| w.contains("water.unit_weight 9.81") && w.contains("another unit")),
        "{w:?}"
    );
    let w = warned(&wet(0.00981));
    assert!(!w.iter().any(|w| w.contains("water")), "{w:?}");
}

/// A nonlinear run at M = 32 whose M/2 check changes nothing measurable
/// (the eccentric block: its loads have harmonics 0 and 1) is told that
/// M/2 may do; at M = 16 (the scene as shipped) it is not.
#[test]
fn a_nonlinear_run_with_far_more_harmonics_than_it_needs_is_told() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../geo/block_uplift.json");
    let mut sc = Scene::from_path(&path).unwrap();
    assert_eq!(warned(&sc), Vec::<String>::new(), "as shipped");
    sc.harmonics = 32.into();
    let w = warned(&sc);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("harmonics: 0..=16 change the loaded faces by"),
        "{w:?}"
    );
}

/// Scene P's Mohr-Coulomb joint with given springs far stiffer than rigid
/// (1e6 times table1's: k_xi h / E about 6e4 at its shortest element) is
/// told that `"rigid"` gives the same answer; with table1's springs and
/// with `"rigid"` it is not.
#[test]
fn a_joint_far_stiffer_than_rigid_is_told() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../geo/pile_footing.json");
    let mut sc = Scene::from_path(&path).unwrap();
    sc.mesh.parameters.insert("size".into(), 0.5);
    sc.solver = Default::default();
    sc.sections = None;
    assert_eq!(warned(&sc), Vec::<String>::new(), "table1's springs");
    let j = sc.joints.get_mut("pile_side").unwrap();
    for k in [&mut j.k_xi, &mut j.k_eta, &mut j.k_theta] {
        *k = k.map(|v| 1e6 * v);
    }
    let w = warned(&sc);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("joints.pile_side: k_eta h / E = ")
            && w[0].contains("\"stiffness\": \"rigid\" gives the same answer"),
        "{w:?}"
    );
    let j = sc.joints.get_mut("pile_side").unwrap();
    (j.k_xi, j.k_eta, j.k_theta) = (None, None, None);
    assert_eq!(warned(&sc), Vec::<String>::new(), "rigid");
}
