//! `mesh.adapt` end to end (docs/accuracy.md), through the binary:
//!
//! - the Lame tube with a small bore (r in [0.1, 1], plane strain, internal
//!   pressure, T6, `geo/thick_cylinder.geo` unstructured): adaptation
//!   reaches a 1 % estimate on the `sigma_theta` profile along r with fewer
//!   unknowns than uniform refinement (size halved until the estimate is
//!   below 1 %), and the true error of the adapted profile is below 2 %;
//! - Scene P bonded (`geo/pile_footing_bonded.json`) with target 1 %: the
//!   b-b profile moves by less than 1 % of its max |sigma_r| against the
//!   mesh adapted to 0.4 %; the cycle table is in summary.json and
//!   adapt.csv;
//! - the issue's check: Scene P bonded with target 1 %, the b-b profile
//!   moves by less than 1 % of its max |sigma_r| between the last two
//!   cycles, read from the cut CSVs of the run and of the same run stopped
//!   one cycle earlier (the run's own stop rule asks for that change too,
//!   measured on its samples: this checks it from the written profiles).

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn geo(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../geo").join(name)
}

/// Runs `axijoint run scene -o out`, returns summary.json.
fn run(scene: &Path, out: &Path) -> Value {
    let o = Command::new(env!("CARGO_BIN_EXE_axijoint"))
        .args(["--no-cache", "run"])
        .arg(scene)
        .arg("-o")
        .arg(out)
        .arg("-q")
        .output()
        .expect("axijoint runs");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{}\n{stdout}",
        String::from_utf8_lossy(&o.stderr)
    );
    println!("{stdout}");
    serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap()
}

/// `(s, body, value of column `col`)` rows of a cut CSV.
fn cut_rows(path: &Path, col: &str) -> Vec<(f64, String, f64, f64)> {
    let mut rd = csv::Reader::from_path(path).unwrap();
    let h = rd.headers().unwrap().clone();
    let idx = |name: &str| h.iter().position(|c| c.starts_with(name)).unwrap();
    let (s, r, b, c) = (idx("s"), idx("r"), idx("body"), idx(col));
    rd.records()
        .map(|rec| {
            let rec = rec.unwrap();
            (
                rec[s].parse().unwrap(),
                rec[b].to_string(),
                rec[r].parse().unwrap(),
                rec[c].parse().unwrap(),
            )
        })
        .collect()
}

fn lame_scene(dir: &Path, name: &str, size: f64, adapt: Option<f64>) -> PathBuf {
    let adapt = adapt.map_or(String::new(), |t| {
        format!(r#", "adapt": {{"target": {t}, "max_cycles": 8}}"#)
    });
    let text = format!(
        r#"{{
      "title": "Lame tube, small bore",
      "mesh": {{"file": "{}", "parameters": {{"a": 1.0, "hole": 0.1, "L": 0.2, "size": {size},
               "order": 2, "quads": 0, "transfinite": 0}}{adapt}}},
      "materials": {{"body": {{"E": 1000.0, "nu": 0.3}}}},
      "supports": [{{"on": "bottom", "fix": ["z", "theta"]}}, {{"on": "top", "fix": ["z"]}}],
      "loads": [{{"type": "traction", "on": "inner", "harmonic": 0, "t_r": 1.0}}],
      "harmonics": 0,
      "cuts": [{{"name": "bore", "from": [0.1, 0.1], "to": [1.0, 0.1], "spacing": 0.005, "theta_deg": [0], "component": "sigma_theta"}}],
      "outputs": {{"csv": true, "plots": false, "vtu": false, "gmsh_views": false}}
    }}"#,
        geo("thick_cylinder.geo").display()
    );
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, text).unwrap();
    path
}

/// The profile's true error: max |sigma_theta - Lame| / max |sigma_theta|.
fn lame_profile_error(out: &Path) -> f64 {
    let a = 0.01 / (1.0 - 0.01);
    let (mut e, mut m) = (0.0f64, 0.0f64);
    for (_, _, r, s) in cut_rows(&out.join("cut_bore_theta0.csv"), "sigma_theta") {
        e = e.max((s - (a + a / (r * r))).abs());
        m = m.max(s.abs());
    }
    e / m
}

#[test]
fn adaptation_reaches_the_target_with_fewer_unknowns_than_uniform_refinement() {
    let tmp = tempfile::tempdir().unwrap();
    let target = 0.01;
    let adapted = tmp.path().join("adapted");
    let summary = run(&lame_scene(tmp.path(), "adapt", 0.1, Some(target)), &adapted);
    let table = &summary["adapt"];
    assert_eq!(table["reached"], Value::Bool(true), "{table}");
    let cycles = table["cycles"].as_array().unwrap();
    let last = cycles.last().unwrap();
    let dof_adapted = last["dofs_per_harmonic"].as_u64().unwrap();
    let est = last["estimated_error"]["bore"]["0"].as_f64().unwrap();
    assert!(est <= target);
    let true_adapted = lame_profile_error(&adapted);
    // Uniform refinement from the same size until the estimate is below target.
    let mut size = 0.1;
    let (dof_uniform, true_uniform) = loop {
        let out = tmp.path().join(format!("uniform_{size}"));
        let s = run(&lame_scene(tmp.path(), "uniform", size, None), &out);
        let e = s["estimated_error"]["bore"]["0"].as_f64().unwrap();
        if e <= target {
            break (s["dofs_per_harmonic"].as_u64().unwrap(), lame_profile_error(&out));
        }
        assert!(size > 0.005, "uniform refinement did not reach {target}");
        size /= 2.0;
    };
    let ratio = dof_adapted as f64 / dof_uniform as f64;
    println!(
        "adapted: {} cycles, {dof_adapted} unknowns, true profile error {true_adapted:.2e}; uniform: size {size}, {dof_uniform} unknowns, true error {true_uniform:.2e}; ratio {ratio:.3}",
        cycles.len() - 1
    );
    assert!(ratio < 0.5, "adapted / uniform unknowns = {ratio}");
    assert!(
        true_adapted < 2.0 * target,
        "true error of the adapted profile {true_adapted}"
    );
    let csv = std::fs::read_to_string(adapted.join("adapt.csv")).unwrap();
    assert_eq!(csv.lines().count(), cycles.len() + 1);
    assert!(
        csv.starts_with("cycle,nodes,dofs_per_harmonic,bore_theta0,energy_norm,seconds,bore_theta0_change\n")
    );
    // Reached: the last cycle moved the profile by at most the target.
    let moved = last["change"]["bore"]["0"].as_f64().unwrap();
    assert!(moved <= target, "last change {moved}");
}

/// Scene P bonded with `mesh.adapt` {target, max_cycles} into `tmp`;
/// returns the output folder and summary.json.
fn scene_p_adapted(tmp: &Path, target: f64, max_cycles: u64) -> (PathBuf, Value) {
    let mut scene: Value =
        serde_json::from_str(&std::fs::read_to_string(geo("pile_footing_bonded.json")).unwrap()).unwrap();
    scene["mesh"]["file"] = Value::String(geo("pile_footing.geo").display().to_string());
    scene["mesh"]["adapt"] = serde_json::json!({"target": target, "max_cycles": max_cycles});
    scene["outputs"] = serde_json::json!({"csv": true, "plots": false, "vtu": false, "gmsh_views": false});
    let name = format!("p_{target}_{max_cycles}");
    let path = tmp.join(format!("{name}.json"));
    std::fs::write(&path, scene.to_string()).unwrap();
    let out = tmp.join(name);
    let summary = run(&path, &out);
    (out, summary)
}

/// The largest change of the b-b `sigma_r` profiles from `a` to `b`, as a
/// fraction of `b`'s max |sigma_r|, for theta 0 and 180.
fn b_b_changes(a: &Path, b: &Path) -> Vec<f64> {
    ["0", "180"]
        .iter()
        .map(|theta| {
            let name = format!("cut_b-b_theta{theta}.csv");
            let ra = cut_rows(&a.join(&name), "sigma_r");
            let rb = cut_rows(&b.join(&name), "sigma_r");
            assert_eq!(ra.len(), rb.len());
            let max = rb.iter().map(|r| r.3.abs()).fold(0.0, f64::max);
            let change = ra
                .iter()
                .zip(&rb)
                .map(|(x, y)| {
                    assert!((x.0 - y.0).abs() < 1e-9 && x.1 == y.1);
                    (x.3 - y.3).abs()
                })
                .fold(0.0, f64::max);
            println!(
                "b-b theta {theta}: change {:.3e} of max |sigma_r| {max:.3e}",
                change / max
            );
            change / max
        })
        .collect()
}

#[test]
fn scene_p_bonded_adapted_to_one_percent_is_close_to_a_finer_adaptation() {
    let tmp = tempfile::tempdir().unwrap();
    let mut outs = Vec::new();
    for target in [0.01, 0.004] {
        let (out, summary) = scene_p_adapted(tmp.path(), target, 6);
        assert_eq!(
            summary["adapt"]["reached"],
            Value::Bool(true),
            "{}",
            summary["adapt"]
        );
        assert!(summary["files"]
            .as_array()
            .unwrap()
            .iter()
            .any(|f| f == "adapt.csv"));
        outs.push(out);
    }
    for change in b_b_changes(&outs[0], &outs[1]) {
        assert!(change < 0.01, "b-b change {change} of max");
    }
}

/// The issue's check: the b-b profile of the last cycle against the cycle
/// before it (the same run stopped one cycle earlier by max_cycles; gmsh
/// meshes the same views alike), at target 1 %.
#[test]
fn scene_p_bonded_last_two_cycles_differ_by_less_than_one_percent() {
    let tmp = tempfile::tempdir().unwrap();
    let target = 0.01;
    let (last, summary) = scene_p_adapted(tmp.path(), target, 6);
    assert_eq!(
        summary["adapt"]["reached"],
        Value::Bool(true),
        "{}",
        summary["adapt"]
    );
    let cycles = summary["adapt"]["cycles"].as_array().unwrap().len() as u64 - 1;
    assert!(cycles >= 2, "{}", summary["adapt"]);
    let (before, s) = scene_p_adapted(tmp.path(), target, cycles - 1);
    assert_eq!(
        s["adapt"]["cycles"].as_array().unwrap().last().unwrap()["dofs_per_harmonic"],
        summary["adapt"]["cycles"][(cycles - 1) as usize]["dofs_per_harmonic"]
    );
    for change in b_b_changes(&before, &last) {
        assert!(
            change < 0.01,
            "b-b change {change} of max between the last two cycles"
        );
    }
}
