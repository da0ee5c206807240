//! End-to-end tests of the report stage: cut CSVs against the closed form of
//! pure bending, the stress jump at Scene P's joint, CSVs read back by a CSV
//! parser with their headers checked, and `axijoint report` regenerating the
//! same files without solving.

mod common;

use common::*;
use std::path::Path;

/// Reads a CSV: (header, rows).
fn read_csv(path: &Path) -> (Vec<String>, Vec<csv::StringRecord>) {
    let mut r = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r.records().map(|x| x.unwrap()).collect();
    (header, rows)
}

const CUT_HEADER: [&str; 11] = [
    "s [m]",
    "r [m]",
    "z [m]",
    "theta [deg]",
    "body",
    "sigma_r [MPa]",
    "sigma_z [MPa]",
    "sigma_theta [MPa]",
    "tau_rz [MPa]",
    "tau_rtheta [MPa]",
    "tau_ztheta [MPa]",
];

/// Pure bending of a solid cylinder (docs/theory.md section 15): t_z = s r cos(theta)
/// on z = L, v = 0 on z = 0, u = 0 at the origin. Exact: sigma_z = s r cos,
/// all other stresses 0; quadratic elements reproduce it, so every sampled
/// point of the cut matches to 1e-6 relative (of s a) at theta = 0 and pi.
#[test]
fn pure_bending_cut_is_exact() {
    let dir = tempfile::tempdir().unwrap();
    let s = 3.0;
    let scene = format!(
        r#"{{
  "title": "pure bending",
  "units": {{"length": "m", "force": "MN", "stress": "MPa"}},
  "mesh": {{"file": {geo:?}, "parameters": {{"a": 0.5, "L": 2.0, "size": 0.3, "order": 2, "quads": 1}}}},
  "materials": {{"body": {{"E": 2.0e4, "nu": 0.17}}}},
  "supports": [{{"on": "bottom", "fix": ["z"]}}, {{"on": "origin", "fix": ["r"]}}],
  "loads": [{{"type": "traction", "on": "top", "harmonic": 1, "t_z": {{"c": 0, "r": {s}, "z": 0}}}}],
  "harmonics": 1,
  "cuts": [{{"name": "mid", "from": [0, 1.0], "to": [0.5, 1.0], "spacing": 0.03, "theta_deg": [0, 180]}},
           {{"name": "slant", "from": [0, 0.1], "to": [0.5, 1.9], "spacing": 0.07, "theta_deg": [0, 180]}}]
}}"#,
        geo = geo("cylinder.geo").to_str().unwrap()
    );
    let path = dir.path().join("bending.json");
    std::fs::write(&path, scene).unwrap();
    let out = dir.path().join("out");
    let run = axijoint(&["run", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"]);
    assert!(run.status.success(), "{}", text(&run).1);
    let scale = s * 0.5;
    let mut checked = 0;
    for cut in ["mid", "slant"] {
        for theta in [0.0f64, 180.0] {
            let (header, rows) = read_csv(&out.join(format!("cut_{cut}_theta{theta}.csv")));
            assert_eq!(header, CUT_HEADER);
            assert!(rows.len() > 10);
            for row in &rows {
                let v = |i: usize| row[i].parse::<f64>().unwrap();
                let (r, t) = (v(1), v(3).to_radians());
                assert_eq!(&row[4], "body");
                let exact = [0.0, s * r * t.cos(), 0.0, 0.0, 0.0, 0.0];
                for (k, e) in exact.iter().enumerate() {
                    let err = (v(5 + k) - e).abs();
                    assert!(
                        err < 1e-6 * scale,
                        "{cut} theta {theta} r {r}: component {k} {} vs {e}",
                        v(5 + k)
                    );
                }
                checked += 1;
            }
        }
    }
    assert!(checked > 60);
}

fn sigma_z_at_pile_side(path: &Path) -> Vec<(String, f64)> {
    let (header, rows) = read_csv(path);
    assert_eq!(header, CUT_HEADER);
    rows.iter()
        .filter(|r| (r[1].parse::<f64>().unwrap() - 0.5).abs() < 1e-12)
        .map(|r| (r[4].to_string(), r[6].parse::<f64>().unwrap()))
        .collect()
}

fn max_abs_sigma_z(path: &Path) -> f64 {
    let (_, rows) = read_csv(path);
    rows.iter()
        .map(|r| r[6].parse::<f64>().unwrap().abs())
        .fold(0.0, f64::max)
}

/// Scene P: on a-a at theta = pi the joint opens and the two sides of r = a
/// carry different sigma_z (the paper's Fig. 6 jump); bonded, the pile and
/// the footing agree there to the discretisation error (measured 0.3 % of the
/// peak on this mesh; asserted 2 %). `axijoint report` rewrites the same
/// CSV bytes from the saved solution.
#[test]
fn scene_p_jump_and_report_regeneration() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p");
    let scene = geo("pile_footing.json");
    let run = axijoint(&["run", scene.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"]);
    let (stdout, stderr) = text(&run);
    assert!(run.status.success(), "{stdout}\n{stderr}");

    let joint = out.join("cut_a-a_theta180.csv");
    let rows = sigma_z_at_pile_side(&joint);
    let bodies: Vec<&str> = rows.iter().map(|r| r.0.as_str()).collect();
    assert_eq!(bodies, ["pile", "footing"], "two rows at r = a, one per body");
    let peak = max_abs_sigma_z(&joint);
    assert!(
        (rows[0].1 - rows[1].1).abs() > 0.5 * peak,
        "jump {rows:?}, peak {peak}"
    );

    let bonded = out.join("without_joints");
    let report = axijoint(&["report", bonded.to_str().unwrap()]);
    assert!(report.status.success(), "{}", text(&report).1);
    let b = bonded.join("cut_a-a_theta180.csv");
    let rows = sigma_z_at_pile_side(&b);
    assert_eq!(rows.len(), 2);
    let peak = max_abs_sigma_z(&b);
    assert!(
        (rows[0].1 - rows[1].1).abs() < 0.02 * peak,
        "bonded {rows:?}, peak {peak}"
    );

    // The joint CSV: header, states, and opening only where open.
    let (header, jrows) = read_csv(&out.join("joint_pile_side.csv"));
    assert_eq!(header[0], "s [m]");
    assert_eq!(header.last().unwrap(), "state");
    for r in &jrows {
        let opening: f64 = r[10].parse().unwrap();
        assert!(["open", "slip", "stick"].contains(&&r[12]));
        assert_eq!(opening > 0.0, &r[12] == "open" && opening > 0.0);
    }
    let (header, hist) = read_csv(&out.join("convergence.csv"));
    assert_eq!(header[..2], ["iteration", "residual_ratio"]);
    assert!(hist.last().unwrap()[1].parse::<f64>().unwrap() < 1e-6);

    // Regenerate from the saved solution: identical bytes.
    let before = std::fs::read(&joint).unwrap();
    std::fs::remove_file(&joint).unwrap();
    let report = axijoint(&["report", out.to_str().unwrap()]);
    assert!(report.status.success(), "{}", text(&report).1);
    assert_eq!(std::fs::read(&joint).unwrap(), before);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for f in summary["files"].as_array().unwrap() {
        assert!(out.join(f.as_str().unwrap()).is_file(), "{f} listed but missing");
    }
    let j = &summary["joints"]["pile_side"];
    let total: f64 = ["open_area", "slip_area", "stick_area"]
        .iter()
        .map(|k| j[k].as_f64().unwrap())
        .sum();
    // The swept joint area is 2 pi a L = pi.
    assert!((total - std::f64::consts::PI).abs() < 1e-9, "{total}");
    assert!(j["open_area"].as_f64().unwrap() > 0.0);
}

/// `axijoint run` with no scene runs the repository's Scene P.
#[test]
fn run_without_argument_runs_scene_p() {
    let dir = tempfile::tempdir().unwrap();
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_axijoint"))
        .args(["run", "-q", "--set", "size=0.5"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    let (stdout, stderr) = text(&run);
    assert!(run.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("Scene P"), "{stdout}");
    assert!(dir.path().join("out/pile_footing/summary.json").is_file());
}
