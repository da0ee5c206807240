//! End to end, ground water through the real binary and gmsh: the shipped
//! `geo/column_water.json` (a Mohr-Coulomb column, geostatic from the
//! buoyant weight below the water table at z = 2.5, then a 10 kPa surface
//! load, carried oedometrically):
//!
//! - the cut gives total stresses, `sigma = sigma' - p`, with the pore
//!   pressure `p = gamma_w (2.5 - z)` beside them, at every sample within
//!   1e-9 of the largest stress, before the load (`_initial.csv`) and after;
//! - `plastic.json` gives each Gauss point's pore pressure and total stress
//!   (the same closed form); `field.vtu` has a `pore_pressure` array.
//!
//! Closed form: `sigma'_z0 = -gamma (5 - z)` above the table, `-gamma 2.5 -
//! (gamma - gamma_w)(2.5 - z)` below; `sigma'_h0 = K0 sigma'_z0`; the load
//! adds `-q` to `sigma_z` and `-q nu / (1 - nu)` to `sigma_r`, `sigma_theta`.

mod common;

use common::*;
use serde_json::Value;

const GAMMA: f64 = 20.0;
const GAMMA_W: f64 = 9.81;
const Z_W: f64 = 2.5;
const K0: f64 = 0.5;
const NU: f64 = 0.3;
const Q: f64 = 10.0;

/// The total `(sigma_r, sigma_z, sigma_theta)` and the pore pressure at
/// height z, with the surface load `q` (0 or Q).
fn exact(z: f64, q: f64) -> ([f64; 3], f64) {
    let v = -GAMMA * (5.0 - z) + GAMMA_W * (Z_W - z).max(0.0);
    let p = GAMMA_W * (Z_W - z).max(0.0);
    let h = K0 * v - q * NU / (1.0 - NU) - p;
    ([h, v - q - p, h], p)
}

/// The largest error of a cut CSV against [`exact`], over 110 kPa.
fn cut_error(path: &std::path::Path, q: f64) -> (f64, usize) {
    let mut reader = csv::Reader::from_path(path).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h.starts_with(&format!("{name} [")))
            .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
    };
    let (z, sr, sz, st, pp) = (
        col("z"),
        col("sigma_r"),
        col("sigma_z"),
        col("sigma_theta"),
        col("pore_pressure"),
    );
    let mut worst = 0.0f64;
    let mut rows = 0;
    for row in reader.records() {
        let row = row.unwrap();
        let v = |i: usize| row[i].parse::<f64>().unwrap();
        let (s, p) = exact(v(z), q);
        for (got, want) in [(v(sr), s[0]), (v(sz), s[1]), (v(st), s[2]), (v(pp), p)] {
            worst = worst.max((got - want).abs() / 110.0);
        }
        rows += 1;
    }
    (worst, rows)
}

#[test]
fn a_column_under_water_gives_total_stresses_with_the_pore_pressure() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("out");
    let scene = geo("column_water.json");
    let out = axijoint(&["run", scene.to_str().unwrap(), "-o", out_dir.to_str().unwrap()]);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    for (file, q) in [("cut_depth_theta0.csv", Q), ("cut_depth_theta0_initial.csv", 0.0)] {
        let (worst, rows) = cut_error(&out_dir.join(file), q);
        println!("{file}: {rows} rows, worst error {worst:.2e} of 110 kPa");
        assert!(rows >= 11, "{rows}");
        assert!(worst < 1e-9, "{file}: {worst}");
    }
    let plastic: Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("plastic.json")).unwrap()).unwrap();
    let points = plastic["points"].as_array().unwrap();
    let values = plastic["values"][0].as_array().unwrap();
    let mut worst = 0.0f64;
    for (p, v) in points.iter().zip(values) {
        let z = p["z"].as_f64().unwrap();
        let (s, pp) = exact(z, Q);
        let got_p = p.get("pore_pressure").and_then(Value::as_f64).unwrap_or(0.0);
        worst = worst.max((got_p - pp).abs() / 110.0);
        for c in 0..3 {
            worst = worst.max((v["sigma"][c].as_f64().unwrap() - s[c]).abs() / 110.0);
        }
    }
    println!("plastic.json: {} points, worst error {worst:.2e}", points.len());
    assert!(worst < 1e-9, "{worst}");
    let vtu = std::fs::read(out_dir.join("field.vtu")).unwrap();
    let needle = b"Name=\"pore_pressure\"";
    assert!(
        vtu.windows(needle.len()).any(|w| w == needle),
        "no pore_pressure in field.vtu"
    );
}
