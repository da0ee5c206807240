//! The shipped example `geo/pile_soil_gravity.json` (a pile in soil with
//! gravity, issue 12 item 5), run by the `axijoint` binary.
//!
//! | claim | reference | tolerance |
//! |---|---|---|
//! | the initial state far from the pile (cut r = 8) is geostatic: `sigma_z = gamma z`, `sigma_r = K0 sigma_z` | closed form | 1 % of `gamma` x the cut's depth |
//! | the head load is carried: reactions balance the applied load | equilibrium | 1e-6 |
//! | the initial phase's weight (summary.json) | soil and pile volumes x unit weights | 1e-9 |
//! | the whole load is reached with stepped loading and with the paper's one-shot iteration, which without the in-situ stress ends in "no equilibrium" (exit 3) | - | - |

mod common;

use common::{axijoint, geo, text};
use serde_json::Value;
use std::path::Path;

const GAMMA: f64 = 0.018;
const K0: f64 = 0.5;

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Rows of a numeric CSV (the `body` column read as NaN).
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(str::to_string).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap_or(f64::NAN)).collect())
        .collect();
    (header, rows)
}

fn column(header: &[String], prefix: &str) -> usize {
    header.iter().position(|h| h.starts_with(prefix)).unwrap()
}

#[test]
fn pile_in_soil_with_gravity_starts_from_the_geostatic_state() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let scene = geo("pile_soil_gravity.json");
    let o = axijoint(&["run", scene.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("initial phase: weight"), "{stdout}");
    let summary = read_json(&out.join("summary.json"));
    let w = summary["initial"]["balance"]["weight"].as_f64().unwrap();
    // Soil cylinder R = 10, H = 20 (less the pile) at 0.018, the pile at 0.024.
    let (a, l) = (0.5, 10.0);
    let pi = std::f64::consts::PI;
    let exact = GAMMA * (pi * 100.0 * 20.0 - pi * a * a * l) + 0.024 * pi * a * a * l;
    assert!((w / exact - 1.0).abs() < 1e-9, "{w} vs {exact}");
    assert!(out.join("initial_displacement.f64").is_file());

    // The initial state at r = 8, away from the pile.
    let (header, rows) = read_csv(&out.join("cut_far-r8_theta0_initial.csv"));
    let (z, sr, sz) = (
        column(&header, "z "),
        column(&header, "sigma_r "),
        column(&header, "sigma_z "),
    );
    let depth = rows.iter().fold(0.0f64, |a, r| a.max(-r[z]));
    let scale = GAMMA * depth;
    let mut worst = 0.0f64;
    for r in &rows {
        let exact = GAMMA * r[z];
        worst = worst.max((r[sz] - exact).abs()).max((r[sr] - K0 * exact).abs());
    }
    println!(
        "initial state at r = 8: worst difference {:.3e} of gamma depth",
        worst / scale
    );
    assert!(worst < 0.01 * scale, "{worst} vs {scale}");

    // Equilibrium of the head load, and the whole load reached.
    let solution = read_json(&out.join("solution.json"));
    let vec = |v: &Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let applied = vec(&solution["applied"]["force"]);
    let mut sum = applied.clone();
    for r in solution["reactions"].as_array().unwrap() {
        for (s, f) in sum.iter_mut().zip(vec(&r["force"])) {
            *s += f;
        }
    }
    let size = applied.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    assert!(sum.iter().all(|s| s.abs() < 1e-6 * size), "{sum:?}");
    assert_eq!(solution["extra"]["load_factor"].as_f64(), Some(1.0));
}

/// The paper's one-shot iteration: with the in-situ stress the shaft has
/// friction and it converges; `geo/pile_soil.json` (no gravity) does not.
#[test]
fn one_shot_converges_with_the_in_situ_stress_only() {
    let dir = tempfile::tempdir().unwrap();
    for (file, expect) in [("pile_soil_gravity.json", 0), ("pile_soil.json", 3)] {
        let mut scene = read_json(&geo(file));
        scene["solver"]["loading"] = "one_shot".into();
        scene["mesh"]["file"] = geo("pile_soil.geo").to_str().unwrap().into();
        scene["outputs"] =
            serde_json::json!({"csv": false, "plots": false, "vtu": false, "gmsh_views": false});
        let path = dir.path().join(file);
        std::fs::write(&path, serde_json::to_string(&scene).unwrap()).unwrap();
        let out = dir.path().join(format!("{file}.out"));
        let o = axijoint(&["solve", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        let (stdout, stderr) = text(&o);
        println!("{file}: exit {:?}", o.status.code());
        assert_eq!(o.status.code(), Some(expect), "{file}\n{stdout}\n{stderr}");
    }
}
