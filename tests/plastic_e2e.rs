//! End to end, a plastic soil through the real binary and gmsh: the shipped
//! `geo/footing_clay.json` (a rough rigid footing pushed 5 cm into Tresca
//! clay, c_u = 0.05 MPa) at a coarser mesh (`--set size=0.1`):
//!
//! - exit 0; `plastic.json` written and listed in `summary.json`;
//! - the footing's reaction over `pi R^2 c_u` is Cox's N_c = 6.05 within 5 %
//!   above and 1 % below (the bound of crates/solver/tests/plasticity.rs);
//! - `load_path.csv` has the plastic volume, growing with the settlement;
//! - the console says that the energy-norm estimate is the elastic stress's.

mod common;

use common::*;
use serde_json::Value;

#[test]
fn a_footing_on_clay_runs_end_to_end_with_its_plastic_field() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("out");
    let scene = geo("footing_clay.json");
    let out = axijoint(&[
        "run",
        scene.to_str().unwrap(),
        "-o",
        out_dir.to_str().unwrap(),
        "--set",
        "size=0.1",
    ]);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(
        stdout.contains("of the elastic stress: where the soil yields"),
        "{stdout}"
    );
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap()).unwrap();
    let files: Vec<&str> = summary["files"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(Value::as_str)
        .collect();
    assert!(
        files.contains(&"plastic.json") && out_dir.join("plastic.json").is_file(),
        "{files:?}"
    );
    let solution: Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("solution.json")).unwrap()).unwrap();
    let footing = solution["reactions"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["on"] == "footing")
        .expect("the footing's reaction");
    let n_c = -footing["force"][2].as_f64().unwrap() / (std::f64::consts::PI * 0.05);
    println!(
        "N_c = {n_c:.4} (Cox 1962: 6.05, {:+.2} %)",
        100.0 * (n_c / 6.05 - 1.0)
    );
    assert!(n_c / 6.05 - 1.0 < 0.05 && n_c / 6.05 - 1.0 > -0.01, "{n_c}");
    let csv = std::fs::read_to_string(out_dir.join("load_path.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|h| h.starts_with("plastic_volume"))
        .expect("a plastic_volume column");
    let volumes: Vec<f64> = lines
        .map(|l| l.split(',').nth(col).unwrap().parse().unwrap())
        .collect();
    println!("plastic volume per step {volumes:?}");
    assert_eq!(volumes.len(), 10);
    // It grows with the settlement to the plateau, where a few points unload
    // (measured: -0.3 % over the last step).
    assert!(volumes[0] > 0.0 && volumes[9] > 5.0 * volumes[0]);
    assert!(volumes.windows(2).all(|w| w[1] >= 0.99 * w[0]), "{volumes:?}");
}
