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
        w[0].contains("of the model's size") && w[0].contains("slip of units"),
        "{w:?}"
    );

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
