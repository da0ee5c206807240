//! The shipped scene `geo/pile_layered.json`: a pile through soft clay
//! into stiff clay, its side one joint against each layer, run by the
//! `axijoint` binary (coarse: `size = 0.5`, harmonics 0..=4).
//!
//! | claim | reference | tolerance |
//! |---|---|---|
//! | one joint along both layers is refused, naming the element, the bodies and what to do | - | - |
//! | each side joint's rigid penalty follows its own layer: stiff / soft = 60 / 10 | `RIGID_STIFFNESS E / h`, same h | 1e-9 |
//! | shaft and base carry the head load | equilibrium of the member | 1e-6 of the load |
//! | the shaft carries at most its adhesion, `c 2 pi a L` | Mohr-Coulomb with phi = 0 | bound |

mod common;

use common::{geo, solve_coarse};
use serde_json::Value;

#[test]
fn a_pile_through_two_layers_takes_one_joint_per_layer() {
    let dir = tempfile::tempdir().unwrap();
    // One physical curve and joint along both layers: refused.
    let geo_text = std::fs::read_to_string(geo("pile_layered.geo")).unwrap().replace(
        "Physical Curve(\"pile_side_stiff\") = {2};\nPhysical Curve(\"pile_side_soft\") = {3};",
        "Physical Curve(\"pile_side\") = {2, 3};",
    );
    assert!(geo_text.contains("\"pile_side\""));
    std::fs::write(dir.path().join("pile_layered.geo"), geo_text).unwrap();
    let mut scene: Value =
        serde_json::from_str(&std::fs::read_to_string(geo("pile_layered.json")).unwrap()).unwrap();
    let joints = scene["joints"].as_object_mut().unwrap();
    let mut side = joints.remove("pile_side_soft").unwrap();
    joints.remove("pile_side_stiff");
    joints.insert("pile_side".into(), side.take());
    let one = dir.path().join("one_joint.json");
    std::fs::write(&one, scene.to_string()).unwrap();
    let (ok, stdout, stderr) = solve_coarse(&one, &dir.path().join("one"), 0.5, 4);
    let said = stdout + &stderr;
    assert!(!ok, "{said}");
    assert!(
        said.contains("joint 'pile_side': line element")
            && said.contains("lies between bodies 'pile' and 'clay_stiff'")
            && said.contains("one physical curve and one joint for each pair of bodies"),
        "{said}"
    );

    // As shipped.
    let out = dir.path().join("out");
    let (ok, stdout, stderr) = solve_coarse(&geo("pile_layered.json"), &out, 0.5, 4);
    assert!(ok, "{stdout}\n{stderr}");
    let solution: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("solution.json")).unwrap()).unwrap();
    let springs = &solution["extra"]["joint_springs"];
    let k = |j: &str| springs[j]["k_eta"].as_f64().unwrap();
    assert_eq!(springs["pile_side_soft"]["source"], "rigid");
    assert!(
        (k("pile_side_stiff") / k("pile_side_soft") / 6.0 - 1.0).abs() < 1e-9,
        "{springs}"
    );

    let split = &solution["members"][0]["split"];
    let v = |key: &str, c: usize| split[key][c].as_f64().unwrap();
    for c in [0, 2] {
        let carried = v("shaft", c) + v("base", c);
        assert!(
            (carried + v("applied", c)).abs() <= 1e-6,
            "component {c}: {split}"
        );
    }
    let adhesion = 0.02 * 2.0 * std::f64::consts::PI * 0.5 * 15.0;
    assert!(
        v("shaft", 2) > 0.0 && v("shaft", 2) <= adhesion,
        "{split} against {adhesion}"
    );
}
