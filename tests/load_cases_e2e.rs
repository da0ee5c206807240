//! Load cases (issue 14 item 6): several named load sets in one scene,
//! solved on one set of factors, each from the initial state, one
//! sub-folder per case.
//!
//! | claim | reference | tolerance |
//! |---|---|---|
//! | a case's displacements are those of a separate run of its loads (linear joints; nonlinear joints with an initial phase) | the separate run | 1e-12 / 1e-9 of the largest |
//! | linear: twice the load, twice the displacements | linearity | 1e-12 |
//! | a case beyond capacity stops at its limit (exit 3) while the other cases are written complete | - | - |
//! | `loads` and `load_cases` together, or `"harmonics": "auto"`, are refused naming the key | - | - |

mod common;

use common::{axijoint, geo, text};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn displacement(dir: &Path) -> Vec<f64> {
    std::fs::read(dir.join("displacement.f64"))
        .unwrap()
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

/// `base` (a shipped scene) with its mesh path absolute, outputs off and
/// `edit` applied, written to `dir/name.json`.
fn scene(dir: &Path, base: &str, name: &str, edit: impl FnOnce(&mut Value)) -> PathBuf {
    let mut v = read_json(&geo(base));
    let file = v["mesh"]["file"].as_str().unwrap().to_string();
    v["mesh"]["file"] = geo(&file).to_str().unwrap().into();
    v["outputs"] = json!({"csv": false, "plots": false, "vtu": false, "gmsh_views": false});
    edit(&mut v);
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, v.to_string()).unwrap();
    path
}

fn max_diff(a: &[f64], b: &[f64]) -> (f64, f64) {
    assert_eq!(a.len(), b.len());
    let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    (diff, scale)
}

#[test]
fn linear_cases_equal_separate_runs() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let h = json!({"type": "resultant", "on": "pile_end", "force": [0.5, 0, 0], "at_z": -3.0, "torque": 0});
    let h2 = json!({"type": "resultant", "on": "pile_end", "force": [1.0, 0, 0], "at_z": -3.0, "torque": 0});
    let n = json!({"type": "resultant", "on": "pile_end", "force": [0, 0, -1.0], "torque": 0.2});
    let cases = scene(d, "pile_footing_linear.json", "cases", |v| {
        v["loads"] = json!([]);
        v["load_cases"] = json!([
            {"name": "H", "loads": [h]},
            {"name": "2H", "loads": [h2]},
            {"name": "N_T", "loads": [n]},
        ]);
    });
    let out = d.join("cases.out");
    let o = axijoint(&[
        "solve",
        cases.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--set",
        "size=0.5",
    ]);
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    let index = read_json(&out.join("cases.json"));
    assert_eq!(index["cases"].as_array().unwrap().len(), 3);
    let u_h = displacement(&out.join("H"));
    let u_2h = displacement(&out.join("2H"));
    let twice: Vec<f64> = u_h.iter().map(|v| 2.0 * v).collect();
    let (diff, scale) = max_diff(&u_2h, &twice);
    println!("2H against 2 x H: {:.3e} of {scale:.3e}", diff);
    assert!(diff <= 1e-12 * scale);
    for (name, load) in [("H", &h), ("N_T", &n)] {
        let single = scene(d, "pile_footing_linear.json", name, |v| {
            v["loads"] = json!([load])
        });
        let sout = d.join(format!("{name}.single"));
        let o = axijoint(&[
            "solve",
            single.to_str().unwrap(),
            "-o",
            sout.to_str().unwrap(),
            "--set",
            "size=0.5",
        ]);
        assert!(o.status.success(), "{:?}", text(&o));
        let (diff, scale) = max_diff(&displacement(&out.join(name)), &displacement(&sout));
        println!("case {name} against its own run: {diff:.3e} of {scale:.3e}");
        assert!(diff <= 1e-12 * scale, "{name}");
    }
}

#[test]
fn nonlinear_cases_start_from_the_initial_state() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let axial = json!({"type": "resultant", "on": "pile_head", "force": [0, 0, -0.3]});
    let lateral = json!({"type": "resultant", "on": "pile_head", "force": [0.5, 0, 0]});
    let uplift = json!({"type": "resultant", "on": "pile_head", "force": [0, 0, 2.5]});
    let cases = scene(d, "pile_soil_gravity.json", "cases", |v| {
        v["loads"] = json!([]);
        v["load_cases"] = json!([
            {"name": "axial", "loads": [axial]},
            {"name": "uplift", "loads": [uplift]},
            {"name": "lateral", "loads": [lateral]},
        ]);
    });
    let out = d.join("cases.out");
    let o = axijoint(&["solve", cases.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let (stdout, stderr) = text(&o);
    // The uplift case exceeds the shaft: exit 3, the others complete.
    assert_eq!(o.status.code(), Some(3), "{stdout}\n{stderr}");
    assert!(stderr.contains("load case uplift"), "{stderr}");
    let index = read_json(&out.join("cases.json"));
    let cases = index["cases"].as_array().unwrap();
    assert_eq!(cases[0]["complete"], json!(true));
    assert!(cases[1]["limit_load_factor"].as_f64().unwrap() < 1.0);
    assert_eq!(cases[2]["complete"], json!(true));
    for (name, load) in [("axial", &axial), ("lateral", &lateral)] {
        let single = scene(d, "pile_soil_gravity.json", name, |v| v["loads"] = json!([load]));
        let sout = d.join(format!("{name}.single"));
        let o = axijoint(&["solve", single.to_str().unwrap(), "-o", sout.to_str().unwrap()]);
        assert!(o.status.success(), "{:?}", text(&o));
        let (diff, scale) = max_diff(&displacement(&out.join(name)), &displacement(&sout));
        println!("case {name} against its own run: {diff:.3e} of {scale:.3e}");
        assert!(diff <= 1e-9 * scale, "{name}");
    }
}

#[test]
fn load_cases_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let load =
        json!({"type": "resultant", "on": "pile_end", "force": [0.5, 0, 0], "at_z": -3.0, "torque": 0});
    let both = scene(d, "pile_footing_linear.json", "both", |v| {
        v["load_cases"] = json!([{"name": "a", "loads": [load]}]);
    });
    let auto = scene(d, "pile_footing_linear.json", "auto", |v| {
        v["loads"] = json!([]);
        v["harmonics"] = json!("auto");
        v["load_cases"] = json!([{"name": "a", "loads": [load]}]);
    });
    let unknown = scene(d, "pile_footing_linear.json", "unknown", |v| {
        v["loads"] = json!([]);
        v["load_cases"] = json!([{"name": "a", "loads": [load]}, {"name": "b", "loads": [{"type": "resultant", "on": "nowhere", "force": [1, 0, 0]}]}]);
    });
    for (path, key) in [
        (both, "load_cases"),
        (auto, "harmonics"),
        (unknown, "load_cases[1].loads[0].on"),
    ] {
        let o = axijoint(&[
            "solve",
            path.to_str().unwrap(),
            "-o",
            d.join("x").to_str().unwrap(),
        ]);
        let (_, stderr) = text(&o);
        assert_eq!(o.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains(key), "{key}: {stderr}");
    }
}
