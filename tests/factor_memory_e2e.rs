//! Factors kept whole against joint blocks (`AXIJOINT_FACTOR_MEMORY`,
//! crates/solver/src/run/factors.rs): Scene P coulomb at a coarse mesh,
//! solved with every factor whole, with joint blocks only (`0`) and with
//! budgets that keep some harmonics whole, must give the same displacements
//! and the same reported results (load path, M/2 check) to 1e-12 relative:
//! the joint blocks read the same values of L, and a full solve reads the
//! rest back from disk (`AXIJOINT_FACTOR_DISK`, crates/solver/src/spill.rs)
//! or, with `off`, factorizes the harmonic again from the same matrix.
//! Stepped (the default), one-shot, and `"harmonics": "auto"` (M grows 4, 8).

mod common;

use common::*;
use serde_json::{json, Value};
use std::path::Path;

/// Scene P coulomb with the default sections (M > 4), no plot outputs.
fn scene(dir: &Path, name: &str, edit: impl FnOnce(&mut Value)) -> std::path::PathBuf {
    let mut s: Value =
        serde_json::from_str(&std::fs::read_to_string(geo("pile_footing_coulomb.json")).unwrap()).unwrap();
    let obj = s.as_object_mut().unwrap();
    obj.remove("sections");
    obj.insert("harmonics".into(), json!(8));
    s["mesh"]["file"] = json!(geo("pile_footing.geo").to_str().unwrap());
    s["mesh"]["parameters"]["size"] = json!(0.3);
    s["outputs"] = json!({"csv": false, "plots": false, "vtu": false, "gmsh_views": false});
    edit(&mut s);
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, serde_json::to_string_pretty(&s).unwrap()).unwrap();
    path
}

fn run(scene: &Path, out: &Path, budget: &str, disk: &str) -> (Vec<f64>, Value) {
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_axijoint"))
        .args([
            "solve",
            "-q",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .env("AXIJOINT_CACHE", test_cache())
        .env("AXIJOINT_FACTOR_MEMORY", budget)
        .env("AXIJOINT_FACTOR_DISK", disk)
        .output()
        .expect("axijoint runs");
    let (stdout, stderr) = text(&run);
    assert!(run.status.success(), "budget {budget}: {stdout}\n{stderr}");
    let u = std::fs::read(out.join("displacement.f64"))
        .unwrap()
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let header = serde_json::from_str(&std::fs::read_to_string(out.join("solution.json")).unwrap()).unwrap();
    (u, header)
}

/// Every number of `a` and `b` equal to 1e-12 relative, times and paths aside.
fn same(a: &Value, b: &Value, at: &str) {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            for (k, v) in x {
                if ["timings", "seconds", "scene_file", "file"].contains(&k.as_str()) {
                    continue;
                }
                same(v, &y[k], &format!("{at}/{k}"));
            }
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{at}: lengths");
            for (i, (u, v)) in x.iter().zip(y).enumerate() {
                same(u, v, &format!("{at}[{i}]"));
            }
        }
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            assert!((x - y).abs() <= 1e-12 * x.abs().max(y.abs()), "{at}: {x} vs {y}");
        }
        _ => assert_eq!(a, b, "{at}"),
    }
}

fn check(name: &str, edit: impl FnOnce(&mut Value)) {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene(dir.path(), name, edit);
    let (u, header) = run(&scene, &dir.path().join("whole"), "1024G", "off");
    let scale = u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    assert!(scale > 0.0, "{name}: no displacement");
    // One factor is about 1.3 MB here: 0 and 2M solve one harmonic's whole
    // factor at a time, 3M two; 6M keeps harmonics 0 and 1 whole and 10M
    // 0..=4 (with "auto": all of M = 4, then joint blocks from 5 at M = 8).
    // The rest of each reduced factor on disk (the system's folder), and
    // factorized again (`off`).
    let disk = dir.path().join("disk");
    std::fs::create_dir(&disk).unwrap();
    for (budget, disk) in [
        ("0", disk.to_str().unwrap()),
        ("0", "off"),
        ("2M", ""),
        ("3M", "off"),
        ("6M", ""),
        ("10M", "off"),
    ] {
        let (v, h) = run(
            &scene,
            &dir.path().join(format!("b{budget}{disk}").replace('/', "_")),
            budget,
            disk,
        );
        let budget = format!("{budget} (disk '{disk}')");
        assert_eq!(u.len(), v.len(), "{name}, budget {budget}");
        let worst = u.iter().zip(&v).fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
        assert!(
            worst <= 1e-12 * scale,
            "{name}, budget {budget}: displacements differ by {:.2e} (relative)",
            worst / scale
        );
        same(&header, &h, &format!("{name}, budget {budget}"));
    }
}

#[test]
fn stepped_joint_blocks_equal_whole_factors() {
    check("stepped", |_| {});
}

#[test]
fn one_shot_joint_blocks_equal_whole_factors() {
    check("one_shot", |s| s["solver"]["loading"] = json!("one_shot"));
}

#[test]
fn auto_harmonics_joint_blocks_equal_whole_factors() {
    check("auto", |s| {
        s["harmonics"] = json!("auto");
        s["solver"]["max_harmonics"] = json!(8);
    });
}

#[test]
fn a_malformed_budget_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene(dir.path(), "bad", |_| {});
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_axijoint"))
        .args(["solve", "-q", scene.to_str().unwrap(), "-o"])
        .arg(dir.path().join("out"))
        .env("AXIJOINT_CACHE", test_cache())
        .env("AXIJOINT_FACTOR_MEMORY", "lots")
        .output()
        .expect("axijoint runs");
    let (_, stderr) = text(&run);
    assert!(!run.status.success());
    assert!(stderr.contains("AXIJOINT_FACTOR_MEMORY=lots"), "{stderr}");
}
