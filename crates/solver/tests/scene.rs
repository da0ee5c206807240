//! Scene files: the shipped scenes parse and check against the real Scene P
//! mesh, and every error path names the key path (or the missing name).
//!
//! Mesh: `geo/pile_footing.geo` meshed by gmsh with the scene's parameters
//! (size 0.25, quadratic Q9), before joint insertion unless a test says
//! otherwise. Error cases start from `geo/pile_footing.json` and change one
//! thing.

use axijoint_mesh::{prepare, JointKind, Mesh};
use axijoint_solver::elements::{JointRule, JointSprings};
use axijoint_solver::scene::{
    Family, Fix, JointLaw, JointStiffness, Load, RuleKind, Scene, SceneError, ShearCheck, StiffnessSpec,
    VtuSections,
};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

fn geo_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../geo")
}

fn scene_p_path() -> PathBuf {
    geo_dir().join("pile_footing.json")
}

fn scene_p_text() -> String {
    std::fs::read_to_string(scene_p_path()).expect("geo/pile_footing.json is shipped")
}

/// Scene P's mesh (no joints), meshed once per test binary.
fn mesh_p() -> &'static Mesh {
    static MESH: OnceLock<Mesh> = OnceLock::new();
    MESH.get_or_init(|| {
        let scene = Scene::from_path(scene_p_path()).expect("Scene P parses");
        prepare(&scene.mesh_path(), &scene.gmsh_parameters(), &[], None)
            .expect("gmsh meshes Scene P")
            .0
    })
}

/// Parses `text` as if it were `geo/pile_footing.json`.
fn parse(text: &str) -> Result<Scene, SceneError> {
    Scene::from_str(text, scene_p_path())
}

/// Scene P with `from` replaced by `to` (which must occur).
fn edited(from: &str, to: &str) -> String {
    let text = scene_p_text();
    assert!(
        text.contains(from),
        "pile_footing.json no longer contains {from:?}"
    );
    text.replacen(from, to, 1)
}

/// Parses and checks an edited Scene P, expecting an error.
fn error_of(text: &str) -> SceneError {
    match parse(text) {
        Err(e) => e,
        Ok(scene) => scene.check(mesh_p()).expect_err("the scene should be refused"),
    }
}

#[test]
fn every_shipped_scene_parses_and_checks_against_its_mesh() {
    let (mut found, mut scene_p_variants) = (0, 0);
    for entry in std::fs::read_dir(geo_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "json") {
            continue;
        }
        found += 1;
        let scene = Scene::from_path(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(scene.mesh_path().is_file(), "{}", path.display());
        // Check before and after joint insertion (the joint specs must fit the mesh).
        let params = scene.gmsh_parameters();
        let (plain, _) = prepare(&scene.mesh_path(), &params, &[], None).unwrap();
        scene.check(&plain).unwrap_or_else(|e| panic!("{e}"));
        let (jointed, _) = prepare(&scene.mesh_path(), &params, &scene.joint_specs(), None).unwrap();
        scene.check(&jointed).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(jointed.joints.len(), scene.joints.len(), "{}", path.display());
        // The Scene P variants: H = 0.5 MN at 1.5 m below the end, M = 4.
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("");
        if stem.starts_with("pile_footing") {
            scene_p_variants += 1;
            assert_eq!(scene.harmonics(), 4, "{}", path.display());
            match &scene.loads[..] {
                [Load::Resultant(l)] => assert_eq!((l.force, l.at_z), ([0.5, 0.0, 0.0], Some(-3.0))),
                other => panic!("{}: unexpected loads {other:?}", path.display()),
            }
        }
    }
    assert!(found >= 4, "found {found} scenes");
    assert_eq!(
        scene_p_variants, 6,
        "table1, bonded, noslip, frictionless, linear, coulomb"
    );
}

#[test]
fn scene_p_table1_values() {
    let scene = Scene::from_path(scene_p_path()).unwrap();
    assert_eq!(scene.mesh_path(), geo_dir().join("pile_footing.geo"));
    assert_eq!(
        scene.gmsh_parameters(),
        vec![
            ("order".to_string(), 2.0),
            ("quads".to_string(), 1.0),
            ("refine".to_string(), 2.0),
            ("serendipity".to_string(), 0.0),
            ("size".to_string(), 0.25),
        ]
    );
    for body in ["pile", "footing"] {
        let e = scene.materials[body].elastic();
        assert_eq!((e.e, e.nu), (2.0e4, 0.17));
    }
    let joint = &scene.joints["pile_side"];
    assert_eq!(
        joint.stiffness(),
        Ok(JointStiffness::Given(
            JointSprings::new(1.0e4, 2.0e4, 1.0e4).unwrap()
        ))
    );
    assert_eq!(joint.rule(JointKind::Lin6), JointRule::Gauss(3));
    assert_eq!(joint.rule(JointKind::Lin4), JointRule::Gauss(2));
    match joint.law {
        JointLaw::MohrCoulomb(mc) => {
            assert_eq!(
                (mc.cohesion, mc.friction_deg, mc.tensile_strength),
                (0.5, 30.0, 0.0)
            );
            assert_eq!(mc.shear_check, ShearCheck::Resultant);
            assert!((mc.tan_phi() - 1.0 / 3f64.sqrt()).abs() < 1e-15);
        }
        JointLaw::Linear => panic!("table1 is Mohr-Coulomb"),
    }
    let specs = scene.joint_specs();
    assert_eq!(specs, vec!["pile_side:pile/footing".parse().unwrap()]);
    assert_eq!(scene.supports[0].fix, Fix::ALL);
    // The paper's sections 0, pi/4, ..., pi, given explicitly; by default the
    // dealiased 2M + 1 = 9 over the half turn (4M = 16 over the full turn).
    let expected: Vec<f64> = (0..5).map(|k| PI * k as f64 / 4.0).collect();
    let given = scene.theta_sections(true).unwrap();
    assert!(given.half);
    assert_eq!(given.theta.len(), 5);
    for (a, b) in given.theta.iter().zip(&expected) {
        assert!((a - b).abs() < 1e-15);
    }
    let default = Scene {
        sections: None,
        ..scene.clone()
    };
    let half = default.theta_sections(true).unwrap();
    assert_eq!(half.theta.len(), 9);
    assert!((half.theta[1] - PI / 8.0).abs() < 1e-15);
    assert_eq!(default.theta_sections(false).unwrap().theta.len(), 16);
    assert_eq!(scene.solver.epsilon, 1e-6);
    assert_eq!(scene.solver.max_iterations, 500);
    assert_eq!(scene.cuts.len(), 2);
    assert_eq!(
        (scene.cuts[0].name.as_str(), scene.cuts[0].from[1]),
        ("a-a", 0.75)
    );
    assert_eq!(
        (scene.cuts[1].name.as_str(), scene.cuts[1].from[1]),
        ("b-b", 0.25)
    );
    assert_eq!(scene.cuts[0].theta_deg, vec![0.0, 180.0]);
}

#[test]
fn variants_differ_from_table1_only_in_the_joint() {
    let table1 = Scene::from_path(scene_p_path()).unwrap();
    let law = |file: &str| {
        let s = Scene::from_path(geo_dir().join(file)).unwrap();
        assert_eq!(
            (&s.materials, &s.loads, &s.supports),
            (&table1.materials, &table1.loads, &table1.supports)
        );
        s.joints.get("pile_side").map(|j| match j.law {
            JointLaw::MohrCoulomb(mc) => (mc.cohesion, mc.friction_deg),
            JointLaw::Linear => panic!("{file}: linear law"),
        })
    };
    assert_eq!(law("pile_footing_bonded.json"), None);
    assert_eq!(law("pile_footing_noslip.json"), Some((2.0, 30.0)));
    assert_eq!(law("pile_footing_frictionless.json"), Some((0.0, 0.0)));
}

#[test]
fn defaults_of_a_minimal_scene() {
    let text = r#"{"mesh": {"file": "pile_footing.geo"},
                   "materials": {"pile": {"E": 1, "nu": 0}, "footing": {"E": 1, "nu": 0}},
                   "loads": [{"type": "traction", "on": "pile_end", "harmonic": 0, "t_z": 1}],
                   "harmonics": 0}"#;
    let scene = parse(text).unwrap();
    scene.check(mesh_p()).unwrap();
    assert_eq!(scene.units.stress, "MPa");
    assert_eq!(scene.solver.epsilon, 1e-6);
    assert_eq!(scene.solver.max_iterations, 500);
    assert!(scene.outputs.csv && scene.outputs.plots && scene.outputs.vtu && scene.outputs.gmsh_views);
    assert_eq!(scene.outputs.vtu_sections, VtuSections::Auto);
    assert_eq!(
        scene.outputs.vtu_fields,
        ["displacement", "sigma_cyl", "von_mises"]
    );
    assert_eq!(scene.theta_sections(false).unwrap().theta, vec![0.0]);
    match &scene.loads[0] {
        Load::Traction(t) => {
            assert_eq!(t.family, Family::Symmetric);
            assert_eq!([t.t[0].c, t.t[1].c, t.t[2].c], [0.0, 1.0, 0.0]);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn serialization_round_trips() {
    let text = edited(
        r#""loads": ["#,
        r#""loads": [{"type": "traction", "on": "pile_side", "harmonic": 2, "family": "antisymmetric", "t_r": {"c": 1, "z": -0.5}, "t_theta": 3},
                     {"type": "ring", "on": "tip", "harmonic": 1, "f_z": 2},
                     {"type": "point", "on": "apex", "force": [1, 2, 3]},"#,
    );
    let scene = parse(&text).unwrap();
    let again = parse(&serde_json::to_string_pretty(&scene).unwrap()).unwrap();
    assert_eq!(again, scene);
    assert_eq!(scene.loads.len(), 4);
}

#[test]
fn joint_rules_and_linear_law() {
    let text = edited(
        r#""law": {"type": "mohr_coulomb", "cohesion": 0.5, "friction_deg": 30, "tensile_strength": 0, "shear_check": "resultant"},
      "rule": "gauss""#,
        r#""law": {"type": "linear"}, "rule": "lobatto""#,
    );
    let scene = parse(&text).unwrap();
    scene.check(mesh_p()).unwrap();
    let j = &scene.joints["pile_side"];
    assert_eq!(j.law, JointLaw::Linear);
    assert_eq!(j.rule, RuleKind::Lobatto);
    assert_eq!(j.rule(JointKind::Lin4), JointRule::Lobatto(2));
    assert_eq!(j.rule(JointKind::Lin6), JointRule::Lobatto(3));
    let paper = parse(&text.replace(r#""rule": "lobatto""#, r#""rule": "paper""#)).unwrap();
    assert_eq!(paper.joints["pile_side"].rule(JointKind::Lin6), JointRule::Paper);
    let five = parse(&text.replace(r#""rule": "lobatto""#, r#""rule": "gauss", "points": 5"#)).unwrap();
    five.check(mesh_p()).unwrap();
    assert_eq!(
        five.joints["pile_side"].rule(JointKind::Lin4),
        JointRule::Gauss(5)
    );
}

// ---- errors: each names the key path or the missing name ----

/// Asserts the error's key and that its message contains each of `words`.
fn assert_error(e: &SceneError, key: &str, words: &[&str]) {
    let text = e.to_string();
    assert_eq!(e.key(), Some(key), "{text}");
    assert!(text.contains(key), "{text}");
    assert!(text.contains("pile_footing.json"), "the file is named: {text}");
    for w in words {
        assert!(text.contains(w), "{text:?} should contain {w:?}");
    }
}

#[test]
fn unknown_key_is_named_with_its_path() {
    let e = error_of(&edited(
        r#""pile": {"E": 2.0e4"#,
        r#""pile": {"E_modulus": 2.0e4"#,
    ));
    assert_error(
        &e,
        "materials.pile.E_modulus",
        &["unknown field `E_modulus`", "line 10"],
    );
    let e = error_of(&edited(r#""harmonics": 4"#, r#""harmonic": 4"#));
    assert_error(&e, "harmonic", &["unknown field `harmonic`"]);
}

#[test]
fn vtu_sections_and_fields_are_checked() {
    let with = |extra: &str| {
        edited(
            r#""outputs": {"csv": true, "plots": true, "vtu": true, "gmsh_views": true}"#,
            &format!(r#""outputs": {{"vtu": true, {extra}}}"#),
        )
    };
    let scene = parse(&with(r#""vtu_sections": "auto""#)).unwrap();
    assert_eq!(scene.outputs.vtu_sections, VtuSections::Auto);
    let scene = parse(&with(r#""vtu_sections": 12, "vtu_fields": ["stress"]"#)).unwrap();
    scene.check(mesh_p()).unwrap();
    assert_eq!(scene.outputs.vtu_sections, VtuSections::Count(12));
    assert_eq!(scene.outputs.vtu_fields, ["stress"]);
    let text = serde_json::to_string(&scene.outputs).unwrap();
    assert!(text.contains(r#""vtu_sections":12"#), "{text}");
    let auto = serde_json::to_string(&VtuSections::Auto).unwrap();
    assert_eq!(auto, r#""auto""#);
    let e = error_of(&with(r#""vtu_sections": 2"#));
    assert_error(&e, "outputs.vtu_sections", &["at least 3", "auto"]);
    let e = error_of(&with(r#""vtu_sections": "fine""#));
    assert_error(&e, "outputs.vtu_sections", &["fine", "\"auto\""]);
    let e = error_of(&with(r#""vtu_fields": ["stress", "sigma_zz"]"#));
    assert_error(&e, "outputs.vtu_fields", &["'sigma_zz'", "von_mises"]);
}

#[test]
fn wrong_shape_is_named_with_its_path() {
    let e = error_of(&edited(r#""force": [0.5, 0, 0]"#, r#""force": [1, 2]"#));
    assert_error(
        &e,
        "loads[0].force",
        &["2 numbers given, give three: [Fx, Fy, Fz]"],
    );
    let e = error_of(&edited(r#""from": [0, 0.75]"#, r#""from": 0.75"#));
    assert_error(&e, "cuts[0].from", &["invalid type"]);
    let e = error_of(&edited(r#""harmonics": 4"#, r#""harmonics": -1"#));
    assert_error(&e, "harmonics", &["-1"]);
    let e = error_of(&edited(r#""fix": ["r", "z", "theta"]"#, r#""fix": ["r", "x"]"#));
    assert_error(&e, "supports[0].fix", &["`x`"]);
    let e = error_of(&edited(r#""E": 2.0e4"#, r#""E": "20 GPa""#));
    assert_error(&e, "materials.pile.E", &["invalid type: string"]);
}

#[test]
fn keys_of_the_wrong_load_type_or_law_are_refused() {
    let e = error_of(&edited(r#""torque": 0"#, r#""torque": 0, "t_r": 1"#));
    assert_error(&e, "loads[0]", &["`t_r`", "resultant"]);
    let e = error_of(&edited(r#""type": "resultant""#, r#""type": "pressure""#));
    assert_error(&e, "loads[0].type", &["pressure"]);
    let e = error_of(&edited(
        r#""type": "resultant", "on": "pile_end","#,
        r#""type": "traction", "on": "pile_end","#,
    ));
    assert_error(&e, "loads[0]", &["`force`", "traction"]);
    let e = error_of(&edited(
        r#""type": "resultant", "on": "pile_end", "force": [0.5, 0, 0], "at_z": -3.0, "torque": 0"#,
        r#""type": "traction", "on": "pile_end", "harmonic": 1, "t_r": {"c": 1, "rr": 2}"#,
    ));
    assert_error(&e, "loads[0].t_r.rr", &["`rr`"]);
    let e = error_of(&edited(r#""cohesion": 0.5, "#, ""));
    assert_error(&e, "joints.pile_side.law", &["`cohesion`"]);
    let e = error_of(&edited(r#""type": "mohr_coulomb""#, r#""type": "linear""#));
    assert_error(&e, "joints.pile_side.law", &["`cohesion`", "linear"]);
    let e = error_of(&edited(
        r#""shear_check": "resultant""#,
        r#""shear_check": "max""#,
    ));
    assert_error(&e, "joints.pile_side.law.shear_check", &["max"]);
}

#[test]
fn duplicate_names_and_trailing_text_are_refused() {
    let e = error_of(&edited(
        r#""footing": {"E": 2.0e4, "nu": 0.17}"#,
        r#""footing": {"E": 2.0e4, "nu": 0.17}, "pile": {"E": 1.0, "nu": 0.1}"#,
    ));
    assert_error(&e, "materials", &["`pile` is given twice"]);
    let e = error_of(&format!("{} {{}}", scene_p_text()));
    assert_error(&e, ".", &["trailing characters"]);
    let e = error_of(&edited(r#""name": "b-b""#, r#""name": "a-a""#));
    assert_error(&e, "cuts[1].name", &["named twice"]);
}

#[test]
fn missing_material_for_a_body() {
    let e = error_of(&edited(
        r#",
    "footing": {"E": 2.0e4, "nu": 0.17}"#,
        "",
    ));
    assert_error(&e, "materials", &["'footing' has no material"]);
    let e = error_of(&edited(r#""footing": {"E""#, r#""footings": {"E""#));
    assert_error(
        &e,
        "materials.footings",
        &["'footings'", "pile, footing", "did you mean 'footing'?"],
    );
}

#[test]
fn support_on_a_missing_curve_lists_the_names() {
    let e = error_of(&edited(r#""on": "footing_outer""#, r#""on": "footing_out""#));
    assert_error(
        &e,
        "supports[0].on",
        &[
            "'footing_out'",
            "footing_outer",
            "pile_end",
            "axis",
            "did you mean 'footing_outer'?",
        ],
    );
    // Nothing near: no suggestion.
    let e = error_of(&edited(r#""on": "pile_end""#, r#""on": "pile_tip""#));
    assert_error(&e, "loads[0].on", &["curve named 'pile_tip'", "pile_end"]);
    assert!(!e.to_string().contains("did you mean"), "{e}");
    let e = error_of(&edited(r#""on": "pile_end""#, r#""on": "pile_edn""#));
    assert_error(&e, "loads[0].on", &["did you mean 'pile_end'?"]);
    let e = error_of(&edited(r#""bottom": "pile""#, r#""bottom": "piles""#));
    assert_error(
        &e,
        "joints.pile_side.bottom",
        &["surface named 'piles'", "did you mean 'pile'?"],
    );
    let e = error_of(&edited(r#""pile_side": {"#, r#""pile_sides": {"#));
    assert_error(&e, "joints.pile_sides", &["'pile_sides'", "pile_side"]);
}

#[test]
fn the_nearest_name_is_suggested_only_when_near() {
    use axijoint_solver::scene::nearest;
    let known = ["shaft", "base", "pile_head", "footing_outer"];
    assert_eq!(nearest("shatf", known), Some("shaft"), "a transposition");
    assert_eq!(nearest("pile_hed", known), Some("pile_head"));
    assert_eq!(nearest("bsae", known), Some("base"));
    assert_eq!(nearest("footing_out", known), Some("footing_outer"));
    assert_eq!(nearest("toe", known), None);
    assert_eq!(nearest("shaft", known), None, "an exact name is not a suggestion");
}

#[test]
fn material_values() {
    let e = error_of(&edited(r#""nu": 0.17"#, r#""nu": 0.5"#));
    assert_error(&e, "materials.pile.nu", &["0.5"]);
    let e = error_of(&edited(r#""E": 2.0e4"#, r#""E": -1"#));
    assert_error(&e, "materials.pile.E", &["-1"]);
}

#[test]
fn resultant_on_a_face_that_is_not_flat() {
    for curve in ["axis", "pile_side", "footing_outer"] {
        let e = error_of(&edited(r#""on": "pile_end""#, &format!(r#""on": "{curve}""#)));
        assert_error(&e, "loads[0].on", &["flat face perpendicular to the axis", curve]);
    }
    // An annulus (footing_bottom, r = 0.5 .. 3 at z = 0) is a flat face.
    let scene = parse(&edited(r#""on": "pile_end""#, r#""on": "footing_bottom""#)).unwrap();
    scene.check(mesh_p()).unwrap();
}

#[test]
fn joint_values() {
    let cases = [
        (
            r#""k_eta": 2.0e4"#,
            r#""k_eta": -2.0e4"#,
            "joints.pile_side.k_eta",
            "-20000",
        ),
        (
            r#""friction_deg": 30"#,
            r#""friction_deg": 90"#,
            "joints.pile_side.law.friction_deg",
            "90",
        ),
        (
            r#""cohesion": 0.5"#,
            r#""cohesion": -0.5"#,
            "joints.pile_side.law.cohesion",
            "-0.5",
        ),
        (
            r#""tensile_strength": 0"#,
            r#""tensile_strength": 1"#,
            "joints.pile_side.law.tensile_strength",
            "apex",
        ),
        (r#""top": "footing","#, "", "joints.pile_side.top", "both"),
        (
            r#""rule": "gauss""#,
            r#""rule": "paper", "points": 2"#,
            "joints.pile_side.points",
            "paper",
        ),
        (
            r#""rule": "gauss""#,
            r#""rule": "lobatto", "points": 1"#,
            "joints.pile_side.points",
            "Lobatto",
        ),
        (
            r#""rule": "gauss""#,
            r#""rule": "simpson""#,
            "joints.pile_side.rule",
            "simpson",
        ),
    ];
    for (from, to, key, word) in cases {
        assert_error(&error_of(&edited(from, to)), key, &[word]);
    }
}

/// Scene P's three springs, as written.
const SCENE_P_SPRINGS: &str = r#""k_xi": 1.0e4,
      "k_eta": 2.0e4,
      "k_theta": 1.0e4,"#;

/// A joint's stiffness is one of three forms: the three springs, `"rigid"`
/// (also by default) or a layer's thickness. Both forms, some of the
/// springs, a thickness <= 0 or another string are refused at a key naming
/// the joint, saying what to give.
#[test]
fn joint_stiffness_forms() {
    let forms = [
        ("", JointStiffness::Rigid, None),
        (
            r#""stiffness": "rigid","#,
            JointStiffness::Rigid,
            Some(StiffnessSpec::Rigid),
        ),
        (
            r#""stiffness": {"thickness": 0.05},"#,
            JointStiffness::Thickness(0.05),
            Some(StiffnessSpec::Thickness(0.05)),
        ),
    ];
    for (to, form, spec) in forms {
        let scene = parse(&edited(SCENE_P_SPRINGS, to)).unwrap();
        let joint = &scene.joints["pile_side"];
        assert_eq!(joint.stiffness, spec);
        assert_eq!(joint.stiffness(), Ok(form));
        let mut scene = scene.clone();
        if form == JointStiffness::Rigid {
            // Scene P's method is the paper's: a rigid nonlinear joint needs newton.
            match scene.check(mesh_p()) {
                Err(SceneError::Invalid { key, message, .. }) => {
                    assert_eq!(key, "joints.pile_side.stiffness");
                    assert!(message.contains("needs `solver.method` \"newton\""), "{message}");
                }
                other => panic!("expected the method error, got {other:?}"),
            }
            scene.solver.method = axijoint_solver::scene::SolverMethod::Newton;
        }
        scene.check(mesh_p()).unwrap();
        let joint = &scene.joints["pile_side"];
        // Written back, the form reads back as it was.
        let again: Scene = serde_json::from_str(&serde_json::to_string(&scene).unwrap()).unwrap();
        assert_eq!(again.joints["pile_side"], *joint);
    }
    let cases: [(&str, &str, &[&str]); 7] = [
        (
            r#""k_xi": 1.0e4, "k_eta": 2.0e4, "k_theta": 1.0e4, "stiffness": "rigid","#,
            "joints.pile_side.stiffness",
            &["give either `stiffness` or the springs k_xi, k_eta and k_theta, not both (also given: k_xi, k_eta, k_theta)"],
        ),
        (
            r#""k_eta": 2.0e4, "stiffness": {"thickness": 0.1},"#,
            "joints.pile_side.stiffness",
            &["not both (also given: k_eta)"],
        ),
        (
            r#""k_xi": 1.0e4, "k_eta": 2.0e4,"#,
            "joints.pile_side.k_theta",
            &["k_xi, k_eta given but not k_theta: give all three springs k_xi, k_eta and k_theta, or none of them and `\"stiffness\": \"rigid\"` (the default) or `{\"thickness\": t}`"],
        ),
        (
            r#""k_eta": 2.0e4,"#,
            "joints.pile_side.k_xi",
            &["k_eta given but not k_xi, k_theta: give all three springs"],
        ),
        (
            r#""stiffness": {"thickness": 0},"#,
            "joints.pile_side.stiffness.thickness",
            &["0 is not allowed: the interface layer's thickness is a length > 0"],
        ),
        (
            r#""stiffness": {"thickness": -0.1},"#,
            "joints.pile_side.stiffness.thickness",
            &["-0.1 is not allowed", "length > 0"],
        ),
        (
            r#""stiffness": "stiff","#,
            "joints.pile_side.stiffness",
            &["'stiff' is not a stiffness: give \"rigid\", {\"thickness\": t} (t a length > 0), or leave out `stiffness` and give k_xi, k_eta and k_theta"],
        ),
    ];
    for (to, key, words) in cases {
        assert_error(&error_of(&edited(SCENE_P_SPRINGS, to)), key, words);
    }
    // The layer's object takes `thickness` only.
    let e = error_of(&edited(SCENE_P_SPRINGS, r#""stiffness": {"thicknes": 0.1},"#));
    assert_error(
        &e,
        "joints.pile_side.stiffness.thicknes",
        &["unknown field `thicknes`"],
    );
}

#[test]
fn load_values() {
    let cases = [
        (
            r#""torque": 0"#,
            r#""torque": 0}, {"type": "traction", "on": "pile_end", "harmonic": 5, "t_z": 1"#,
            "loads[1].harmonic",
            "harmonic 5",
        ),
        (
            r#""torque": 0"#,
            r#""torque": 0}, {"type": "traction", "on": "pile_end", "harmonic": 0, "family": "antisymmetric", "t_z": 1"#,
            "loads[1].family",
            "harmonic 0",
        ),
        (
            r#""torque": 0"#,
            r#""torque": 0}, {"type": "traction", "on": "pile_end", "t_z": 1"#,
            "loads[1]",
            "`harmonic`",
        ),
        (
            r#""torque": 0"#,
            r#""torque": 0}, {"type": "ring", "on": "pile_end", "harmonic": 0, "f_z": 1"#,
            "loads[1].on",
            "point named 'pile_end'",
        ),
        (
            r#""harmonics": 4"#,
            r#""harmonics": 0"#,
            "loads[0].force",
            "harmonic 1",
        ),
    ];
    for (from, to, key, word) in cases {
        assert_error(&error_of(&edited(from, to)), key, &[word]);
    }
}

#[test]
fn settings_values() {
    let cases = [
        (
            r#""size": 0.25"#,
            r#""sise": 0.25"#,
            "mesh.parameters.sise",
            "does not use a parameter named 'sise'",
        ),
        (
            r#""file": "pile_footing.geo""#,
            r#""file": "pile_footing.step""#,
            "mesh.file",
            "neither a .geo nor a .msh",
        ),
        (
            r#""file": "pile_footing.geo""#,
            r#""file": "pile_footing.msh""#,
            "mesh.parameters",
            ".geo only",
        ),
        (r#""force": "MN""#, r#""force": "kN""#, "units", "kN"),
        (
            r#""epsilon": 1e-6"#,
            r#""epsilon": 0"#,
            "solver.epsilon",
            "between 0 and 1",
        ),
        (
            r#""max_iterations": 500"#,
            r#""max_iterations": 0"#,
            "solver.max_iterations",
            "at least 1",
        ),
        (
            r#""method": "paper""#,
            r#""method": "multigrid""#,
            "solver.method",
            "multigrid",
        ),
        (
            r#"[0, 45, 90, 135, 180]"#,
            r#"[0, 90, 45]"#,
            "sections.theta_deg",
            "increasing",
        ),
        (r#""spacing": 0.05"#, r#""spacing": 0"#, "cuts[0].spacing", "> 0"),
        // Lists of the wrong length say what they take.
        (
            r#""force": [0.5, 0, 0]"#,
            r#""force": [0.5, 0]"#,
            "loads[0].force",
            "give three: [Fx, Fy, Fz]",
        ),
        (
            r#""torque": 0"#,
            r#""torque": 0, "moment": [0, 1, 0]"#,
            "loads[0].moment",
            "give two: [Mx, My] (the moment about z is `torque`)",
        ),
        // A spacing in the wrong unit: millions of samples, refused.
        (
            r#""spacing": 0.05"#,
            r#""spacing": 5e-8"#,
            "cuts[0].spacing",
            "at most 100000",
        ),
        (
            r#""to": [3.0, 0.75]"#,
            r#""to": [3000000.0, 0.75]"#,
            "cuts[0].spacing",
            "samples",
        ),
        (r#""name": "a-a""#, r#""name": "a/a""#, "cuts[0].name", "a/a"),
        (
            r#""to": [3.0, 0.75]"#,
            r#""to": [-3.0, 0.75]"#,
            "cuts[0].to",
            "r >= 0",
        ),
        (
            r#""fix": ["r", "z", "theta"]"#,
            r#""fix": []"#,
            "supports[0].fix",
            "fixes nothing",
        ),
    ];
    for (from, to, key, word) in cases {
        assert_error(&error_of(&edited(from, to)), key, &[word]);
    }
}

#[test]
fn unreadable_files() {
    let missing = geo_dir().join("no_such_scene.json");
    let e = Scene::from_path(&missing).unwrap_err();
    assert!(matches!(e, SceneError::Io { .. }));
    assert!(e.to_string().contains("no_such_scene.json"), "{e}");
    let e = error_of(&edited(
        r#""file": "pile_footing.geo""#,
        r#""file": "no_such.geo""#,
    ));
    assert!(
        matches!(e, SceneError::Io { .. }) && e.to_string().contains("no_such.geo"),
        "{e}"
    );
    let e = parse("{\"mesh\": ").unwrap_err();
    assert!(matches!(e, SceneError::Parse { line: 1, .. }), "{e}");
}

#[test]
fn an_error_in_text_changed_by_overrides_is_located_in_the_file() {
    // The file's text, and the same scene as an override tool writes it
    // again (one line, `nu` replaced by a string).
    let file = std::fs::read_to_string(geo_dir().join("pile_footing.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&file).unwrap();
    v["materials"]["pile"]["nu"] = serde_json::json!("abc");
    let again = serde_json::to_string(&v).unwrap();
    let e = Scene::from_str(&again, geo_dir().join("pile_footing.json")).unwrap_err();
    assert!(matches!(e, SceneError::Parse { line: 1, .. }), "{e}");
    let (line, column) = file
        .lines()
        .enumerate()
        .find_map(|(i, l)| l.find("\"nu\": 0.17").map(|c| (i + 1, c + 7)))
        .unwrap();
    let e = e.located_in(&file);
    let SceneError::Parse {
        line: l,
        column: c,
        overridden,
        ..
    } = e
    else {
        panic!("{e}")
    };
    assert_eq!((l, c, overridden), (line, column, false));
    // A key the file lacks: the value holding it, marked.
    v["materials"]["pile"]["nu"] = serde_json::json!(0.2);
    v["materials"]["pile"]["poisson"] = serde_json::json!(0.2);
    let e = Scene::from_str(&serde_json::to_string(&v).unwrap(), "p.json")
        .unwrap_err()
        .located_in(&file);
    assert!(
        e.to_string().contains(&format!(
            "a value an override set, within the value at line {line}"
        )),
        "{e}"
    );
}
