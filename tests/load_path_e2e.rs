//! End-to-end tests of the load path (`solver.loading`, docs/loading.md)
//! through the real binary and gmsh, on copies of `geo/block_torsion.json`:
//! a cohesive joint (C = 0.1 MPa, phi = 0) under a torque T on a block of
//! radius a = 0.5 m, whose full-slip capacity is T_max = 2 pi C a^3 / 3.
//!
//! - 1.1 T_max, stepped (default `{"steps": "auto"}`): exit status 3, the
//!   limit load factor ~ 1 / 1.1, every output of the last converged step;
//! - 0.9 T_max, stepped: exit 0, load factor 1;
//! - 1.1 T_max, `"one_shot"`: exit 3, "no equilibrium", the last iterate
//!   written and marked `"converged": false`;
//! - a malformed `solver.loading`: exit 1, the message names the key path.

mod common;

use common::*;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::Output;

/// Cohesion C (MPa) and radius a (m) of `geo/block_torsion.json`.
const COHESION: f64 = 0.1;
const RADIUS: f64 = 0.5;

/// The torque of full slip of the rigid-block closed form, 2 pi C a^3 / 3.
fn t_max() -> f64 {
    2.0 * std::f64::consts::PI * COHESION * RADIUS.powi(3) / 3.0
}

/// Writes a copy of `geo/block_torsion.json` into `dir` as `NAME.json`:
/// the mesh file is the repository's `geo/block_on_base.geo` (absolute),
/// `solver` is replaced by `solver`, the torque is `factor * T_max`, CSV
/// and plots are written (and the VTU when `vtu`).
fn block_scene(dir: &Path, name: &str, factor: f64, solver: Value, vtu: bool) -> PathBuf {
    let text = std::fs::read_to_string(geo("block_torsion.json")).unwrap();
    let mut scene: Value = serde_json::from_str(&text).unwrap();
    scene["mesh"]["file"] = json!(geo("block_on_base.geo").to_str().unwrap());
    scene["solver"] = solver;
    let loads = scene["loads"].as_array_mut().unwrap();
    assert_eq!(loads.len(), 1, "block_torsion.json has one load");
    loads[0]["torque"] = json!(factor * t_max());
    scene["outputs"] = json!({"csv": true, "plots": true, "png": true, "vtu": vtu, "gmsh_views": false});
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, serde_json::to_string_pretty(&scene).unwrap()).unwrap();
    path
}

/// `axijoint COMMAND SCENE -o OUT -q`: the output, stdout and stderr.
fn axijoint_on(command: &str, scene: &Path, out: &Path) -> (Output, String, String) {
    let run = axijoint(&[
        command,
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    let (stdout, stderr) = text(&run);
    (run, stdout, stderr)
}

fn read_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

/// Reads a CSV: (header, rows of numbers). Every cell must parse as a number.
fn read_numeric_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut r = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r
        .records()
        .map(|rec| {
            rec.unwrap()
                .iter()
                .map(|cell| {
                    cell.parse::<f64>()
                        .unwrap_or_else(|e| panic!("{}: cell {cell:?}: {e}", path.display()))
                })
                .collect()
        })
        .collect();
    (header, rows)
}

/// The column of `header` named exactly `name`.
fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name:?} in {header:?}"))
}

/// Every path under `dir` (recursively) whose name contains `.partial` or
/// `.old-` (the temporary names of the atomic writes).
fn leftovers(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if name.contains(".partial") || name.contains(".old-") {
            found.push(path.clone());
        }
        if path.is_dir() {
            found.extend(leftovers(&path));
        }
    }
    found
}

/// `applied` and the (single) support's reaction balance, each component to
/// `tol` times the largest applied component.
fn assert_balanced(solution: &Value, tol: f64) {
    let get = |v: &Value, k: &str| -> Vec<f64> {
        v[k].as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let reactions = solution["reactions"].as_array().unwrap();
    assert_eq!(reactions.len(), 1, "one support (base_bottom)");
    let applied: Vec<f64> = [
        get(&solution["applied"], "force"),
        get(&solution["applied"], "moment"),
    ]
    .concat();
    let reaction: Vec<f64> = [get(&reactions[0], "force"), get(&reactions[0], "moment")].concat();
    let scale = applied.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(scale > 0.0);
    for (a, r) in applied.iter().zip(&reaction) {
        assert!(
            (a + r).abs() <= tol * scale,
            "applied {applied:?} and reaction {reaction:?} do not balance to {tol:e} relative"
        );
    }
}

/// 1.1 T_max with the default loading: the run climbs to the limit load
/// factor ~ 1 / 1.1, writes every output for that step, and exits with 3.
#[test]
fn beyond_capacity_stops_at_the_limit_load_factor() {
    let dir = tempfile::tempdir().unwrap();
    let scene = block_scene(dir.path(), "over", 1.1, json!({}), true);
    let out = dir.path().join("over");
    let (run, stdout, stderr) = axijoint_on("run", &scene, &out);
    let all = format!("{stdout}\n{stderr}");
    assert_eq!(run.status.code(), Some(3), "exit status exactly 3\n{all}");
    assert!(stdout.contains("LIMIT LOAD FACTOR"), "{all}");
    assert!(stderr.contains("limit load factor"), "{all}");
    assert!(
        stdout.contains("last converged step"),
        "the console says whose results these are\n{all}"
    );

    // solution.json: the limit load factor is 1 / 1.1 to 1 % (the bracket
    // of the step control is 1 %, the discrete joint's capacity is within
    // a fraction of a percent of the closed form).
    let solution = read_json(&out.join("solution.json"));
    let extra = &solution["extra"];
    let expected = 1.0 / 1.1;
    let limit = extra["limit_load_factor"]
        .as_f64()
        .unwrap_or_else(|| panic!("extra.limit_load_factor: {extra}"));
    assert!(
        (limit / expected - 1.0).abs() < 0.01,
        "limit load factor {limit} vs 1/1.1 = {expected} (1 %)"
    );
    assert_eq!(extra["complete"], json!(false));
    assert_eq!(extra["loading"], json!({"steps": "auto"}), "the default");
    assert_eq!(
        extra["load_factor"].as_f64(),
        Some(limit),
        "the factor reached (exact)"
    );
    assert!(extra["note"].as_str().is_some_and(|n| !n.is_empty()), "{extra}");
    let bracket = &extra["load_path"]["limit"];
    assert_eq!(bracket["factor"].as_f64(), Some(limit), "exact");
    assert_eq!(bracket["beyond_capacity"], json!(true));
    let failed_at = bracket["failed_at"].as_f64().unwrap();
    // lambda_max <= capacity < failed_at: the failed factor lies above the
    // limit by at most 1 % relative (1e-4 absolute at least), and above
    // 1 / 1.1 (the closed-form capacity; the discrete one is not larger by
    // more than the 1 % tolerance).
    assert!(
        failed_at > limit && failed_at - limit <= (0.01 * limit).max(1e-4) + 1e-12,
        "bracket [{limit}, {failed_at}] wider than 1 %"
    );
    assert!(failed_at > expected * 0.99, "failed at {failed_at} < 1/1.1 - 1 %");
    assert!(
        bracket["reason"]
            .as_str()
            .is_some_and(|r| r.contains("no equilibrium")),
        "{bracket}"
    );
    let steps = extra["load_path"]["steps"].as_array().unwrap();
    assert!(!steps.is_empty());
    // `applied` is that of the last converged step, lambda F: it balances
    // the reactions to 1e-5 relative (the default epsilon is 1e-6).
    assert_balanced(&solution, 1e-5);

    // summary.json: the same numbers, exactly.
    let summary = read_json(&out.join("summary.json"));
    assert_eq!(summary["limit_load_factor"].as_f64(), Some(limit));
    assert_eq!(summary["load_factor"].as_f64(), Some(limit));
    assert_eq!(summary["complete"], json!(false));
    assert_eq!(summary["loading"], json!({"steps": "auto"}));
    assert!(summary["note"].as_str().is_some_and(|n| !n.is_empty()));
    let load_steps = summary["load_steps"].as_array().unwrap();
    assert!(!load_steps.is_empty());
    assert_eq!(load_steps.len(), steps.len());

    // load_path.csv: units on every column, one row per converged step, the
    // last row at the limit (to 1e-9: printed with 10 significant digits),
    // lambda strictly increasing, every value finite.
    let (header, rows) = read_numeric_csv(&out.join("load_path.csv"));
    assert_eq!(header[0], "lambda [-]");
    for h in &header {
        let unit = h
            .split_once(" [")
            .and_then(|(_, u)| u.strip_suffix(']'))
            .filter(|u| !u.is_empty());
        assert!(unit.is_some(), "column {h:?} has no unit in brackets: {header:?}");
    }
    assert_eq!(rows.len(), steps.len(), "one row per step");
    for row in &rows {
        assert_eq!(row.len(), header.len());
        assert!(row.iter().all(|v| v.is_finite()), "{row:?}");
    }
    for (row, step) in rows.iter().zip(steps) {
        let lambda = step["lambda"].as_f64().unwrap();
        assert!((row[0] - lambda).abs() <= 1e-9, "{} vs {lambda}", row[0]);
    }
    for w in rows.windows(2) {
        assert!(
            w[1][0] > w[0][0],
            "lambda not increasing: {} then {}",
            w[0][0],
            w[1][0]
        );
    }
    let last = rows.last().unwrap();
    assert!(
        (last[0] - limit).abs() <= 1e-9,
        "last lambda {} vs {limit}",
        last[0]
    );
    assert!(last[0] > 0.0 && last[0] < 1.0);

    // The outputs are those of the last converged step: the face motion of
    // the last CSV row is solution.json's loaded_faces, and its joint areas
    // are summary.json's (both to 1e-8 relative of the largest: the CSV
    // prints 10 significant digits).
    let face = &solution["loaded_faces"]["block_top"];
    let face: Vec<f64> = (0..3).map(|i| face[i].as_f64().unwrap()).collect();
    let scale = face.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (i, c) in ["ux", "uy", "uz"].iter().enumerate() {
        let v = last[column(&header, &format!("block_top_{c} [m]"))];
        assert!(
            (v - face[i]).abs() <= 1e-8 * scale,
            "block_top {c}: CSV {v} vs solution.json {}",
            face[i]
        );
    }
    let areas = &summary["joints"]["contact"];
    let total: f64 = ["open", "slip", "stick"]
        .iter()
        .map(|s| areas[format!("{s}_area")].as_f64().unwrap())
        .sum();
    // The joint's area: the annulus swept by the block's bottom, pi a^2, to
    // 1e-9 (exact for straight edges).
    assert!(
        (total / (std::f64::consts::PI * RADIUS * RADIUS) - 1.0).abs() < 1e-9,
        "{areas}"
    );
    for s in ["open", "slip", "stick"] {
        let v = last[column(&header, &format!("contact_{s}_area [m^2]"))];
        let w = areas[format!("{s}_area")].as_f64().unwrap();
        assert!((v - w).abs() <= 1e-8 * total, "{s} area: CSV {v} vs summary {w}");
    }
    assert!(
        areas["slip_area"].as_f64().unwrap() > 0.5 * total,
        "near its capacity most of the joint slips: {areas}"
    );

    // Every output is written; no temporary file is left.
    for f in [
        "load_path.svg",
        "load_path.png",
        "field.vtu",
        "convergence.csv",
        "joint_contact.csv",
        "joints.json",
        "displacement.f64",
        "mesh.msh",
    ] {
        let len = std::fs::metadata(out.join(f))
            .unwrap_or_else(|e| panic!("{f}: {e}"))
            .len();
        assert!(len > 0, "{f} is empty");
    }
    let files: Vec<&str> = summary["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    for f in ["load_path.csv", "load_path.svg", "load_path.png", "field.vtu"] {
        assert!(files.contains(&f), "summary.json files lacks {f}: {files:?}");
    }
    let left = leftovers(dir.path());
    assert!(left.is_empty(), "temporary files left: {left:?}");

    // `axijoint solve` stops the same way with the same status.
    let solved = dir.path().join("over_solve");
    let (run, stdout, stderr) = axijoint_on("solve", &scene, &solved);
    assert_eq!(run.status.code(), Some(3), "{stdout}\n{stderr}");
    let again = read_json(&solved.join("solution.json"));
    assert_eq!(
        again["extra"]["limit_load_factor"].as_f64(),
        Some(limit),
        "the same run, the same factor (exact)"
    );
}

/// 0.9 T_max: the whole load is reached; no limit.
#[test]
fn below_capacity_reaches_the_whole_load() {
    let dir = tempfile::tempdir().unwrap();
    let scene = block_scene(dir.path(), "under", 0.9, json!({}), false);
    let out = dir.path().join("under");
    let (run, stdout, stderr) = axijoint_on("run", &scene, &out);
    assert_eq!(run.status.code(), Some(0), "{stdout}\n{stderr}");
    assert!(!stdout.contains("LIMIT LOAD FACTOR"), "{stdout}");

    let solution = read_json(&out.join("solution.json"));
    let extra = &solution["extra"];
    assert_eq!(extra["load_factor"].as_f64(), Some(1.0), "exactly 1");
    assert!(extra["limit_load_factor"].is_null(), "{extra}");
    assert!(extra["load_path"]["limit"].is_null(), "{extra}");
    assert!(
        extra["complete"].is_null() || extra["complete"] == json!(true),
        "{extra}"
    );
    assert_balanced(&solution, 1e-5);

    let summary = read_json(&out.join("summary.json"));
    assert_eq!(summary["load_factor"].as_f64(), Some(1.0));
    assert!(summary["limit_load_factor"].is_null());
    assert_eq!(summary["complete"], json!(true));
    assert!(!summary["load_steps"].as_array().unwrap().is_empty());

    let (header, rows) = read_numeric_csv(&out.join("load_path.csv"));
    assert_eq!(header[0], "lambda [-]");
    assert!(!rows.is_empty());
    assert!(rows.iter().flatten().all(|v| v.is_finite()));
    let last = rows.last().unwrap()[0];
    assert!((last - 1.0).abs() <= 1e-9, "last lambda {last}");
    for f in ["load_path.svg", "load_path.png"] {
        assert!(std::fs::metadata(out.join(f)).unwrap().len() > 0, "{f}");
    }
    let left = leftovers(dir.path());
    assert!(left.is_empty(), "temporary files left: {left:?}");
}

/// 1.1 T_max in one shot (the paper's iteration): no equilibrium, exit 3,
/// the last iterate written for diagnosis and marked not converged (its
/// history ends where the error says, the joint states are there); 0.9
/// T_max in one shot converges without a load path.
#[test]
fn one_shot_beyond_capacity_finds_no_equilibrium() {
    let dir = tempfile::tempdir().unwrap();
    let scene = block_scene(dir.path(), "one_shot", 1.1, json!({"loading": "one_shot"}), false);
    let out = dir.path().join("one_shot");
    let (run, stdout, stderr) = axijoint_on("run", &scene, &out);
    assert_eq!(
        run.status.code(),
        Some(3),
        "exit status exactly 3\n{stdout}\n{stderr}"
    );
    assert!(stderr.contains("no equilibrium"), "{stderr}");
    assert!(stderr.contains("last iterate is written"), "{stderr}");
    let extra = read_json(&out.join("solution.json"))["extra"].clone();
    assert_eq!(extra["converged"], json!(false));
    assert!(extra["error"]
        .as_str()
        .unwrap_or_default()
        .contains("no equilibrium"));
    let history = extra["history"].as_array().expect("history");
    assert!(!history.is_empty());
    let summary = read_json(&out.join("summary.json"));
    assert_eq!(summary["converged"], json!(false));
    assert!(out.join("joint_contact.csv").is_file() && out.join("convergence.csv").is_file());
    // The written iterate is the one the error names.
    let last = history.last().unwrap();
    let at = format!("at iteration {})", last["iteration"]);
    assert!(
        extra["error"].as_str().unwrap_or_default().contains(&at),
        "{at}: {}",
        extra["error"]
    );
    let left = leftovers(dir.path());
    assert!(left.is_empty(), "temporary files left: {left:?}");

    // Below capacity the one-shot run converges: it says how it was loaded
    // and has no load path (no load_path.csv, no load factor).
    let scene = block_scene(
        dir.path(),
        "one_shot_under",
        0.9,
        json!({"loading": "one_shot"}),
        false,
    );
    let out = dir.path().join("one_shot_under");
    let (run, stdout, stderr) = axijoint_on("run", &scene, &out);
    assert_eq!(run.status.code(), Some(0), "{stdout}\n{stderr}");
    let extra = &read_json(&out.join("solution.json"))["extra"];
    assert_eq!(extra["loading"], json!("one_shot"));
    assert!(
        extra["load_path"].is_null() && extra["load_factor"].is_null(),
        "{extra}"
    );
    let summary = read_json(&out.join("summary.json"));
    assert_eq!(summary["loading"], json!("one_shot"));
    assert_eq!(summary["complete"], json!(true));
    assert!(!out.join("load_path.csv").exists());
}

/// A malformed `solver.loading` is refused before meshing, naming the key
/// path and the accepted forms.
#[test]
fn bad_loading_values_are_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    for (name, loading) in [
        ("steps_zero", json!({"steps": 0})),
        ("two_shots", json!("two_shots")),
    ] {
        let scene = block_scene(dir.path(), name, 0.9, json!({"loading": loading}), false);
        let out = dir.path().join(name);
        let (run, stdout, stderr) = axijoint_on("run", &scene, &out);
        assert_eq!(run.status.code(), Some(1), "{name}: {stdout}\n{stderr}");
        assert!(stderr.contains("solver.loading"), "{name}: {stderr}");
        assert!(
            stderr.contains(&format!("{name}.json")),
            "{name}: names the file: {stderr}"
        );
        assert!(
            stderr.contains("one_shot"),
            "{name}: says what is accepted: {stderr}"
        );
        assert!(!out.exists(), "{name}: nothing written");
    }
}

/// Stages through the binary (docs/scene-format.md, "stages"): the block's
/// top moved sideways by `motion` loads past its sliding displacement and
/// back, with `outputs.stages: "each"`: a solution folder with its report
/// at the end of every leg but the last, whose loaded face sits where the
/// run's load path says it was at that leg's end (1e-12); `stages.csv`,
/// `hysteresis.svg` and the stage columns of `load_path.csv` in the run's
/// own folder.
#[test]
fn stages_each_write_every_legs_end() {
    let dir = tempfile::tempdir().unwrap();
    let source = std::fs::read_to_string(geo("block_torsion.json")).unwrap();
    let mut scene: Value = serde_json::from_str(&source).unwrap();
    scene["mesh"]["file"] = json!(geo("block_on_base.geo").to_str().unwrap());
    scene.as_object_mut().unwrap().remove("loads");
    scene["harmonics"] = json!(1);
    scene["joints"]["contact"]["law"]["tensile_strength"] = json!(10.0);
    scene["solver"] = json!({"method": "newton", "epsilon": 1e-8});
    let push = |u: f64| json!([{"type": "motion", "on": "block_top", "displacement": [u, 0, 0]}]);
    scene["stages"] = json!([
        {"name": "push", "loads": push(0.003), "loading": {"steps": 3}},
        {"name": "back", "loads": push(-0.003), "loading": {"steps": 6}},
        {"name": "home", "loads": [], "loading": {"steps": 3}}
    ]);
    scene["outputs"] =
        json!({"csv": true, "plots": true, "vtu": false, "gmsh_views": false, "stages": "each"});
    let path = dir.path().join("staged.json");
    std::fs::write(&path, serde_json::to_string_pretty(&scene).unwrap()).unwrap();
    let out = dir.path().join("out");
    let run = axijoint(&["run", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"]);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run).1);
    for f in ["stages.csv", "hysteresis.svg", "load_path.csv", "summary.json"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let header = std::fs::read_to_string(out.join("load_path.csv")).unwrap();
    assert!(
        header.starts_with("leg [-],stage,cycle [-],level [-],lambda [-]"),
        "{header}"
    );
    let solution: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("solution.json")).unwrap()).unwrap();
    let steps = solution["extra"]["load_path"]["steps"].as_array().unwrap();
    let mut folders: Vec<String> = std::fs::read_dir(out.join("stages"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    folders.sort();
    assert_eq!(folders, ["000-push", "001-back"]);
    for (leg, folder) in folders.iter().enumerate() {
        let summary: Value = serde_json::from_str(
            &std::fs::read_to_string(out.join("stages").join(folder).join("summary.json")).unwrap(),
        )
        .unwrap();
        let at = summary["loaded_faces"]["block_top"][0].as_f64().unwrap();
        let end = steps
            .iter()
            .rfind(|s| s["observed"]["stage"]["leg"] == json!(leg))
            .unwrap();
        let expected = end["observed"]["faces"][0]["mean"][0].as_f64().unwrap();
        assert!(
            (at - expected).abs() < 1e-12 * 0.003,
            "{folder}: {at} vs {expected}"
        );
        assert!((at.abs() - 0.003).abs() < 1e-12 * 0.003, "{folder}: {at}");
    }
}
