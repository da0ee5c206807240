//! `field.vtu` and `field_joints.vtu` read by meshio (the interpreter of
//! `target/venv`, made by `scripts/setup`), a reader that shares nothing
//! with ours: Scene P run with the default outputs (raw appended data,
//! "auto" sections, the default point arrays), and again with
//! `outputs.vtu_compress` (zlib blocks). meshio's points, cells and every
//! array equal `vtu::read_vtu`'s bit for bit in both, the two encodings hold
//! the same values, and the largest |u| on the rings of the 16 sections
//! equals `solution.json`'s `max_displacement` (the solver's, over the same
//! 16 sections).

mod common;

use axijoint_report::vtu::read_vtu;
use common::*;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The Python of `scripts/setup`'s virtual environment.
fn python() -> PathBuf {
    root().join("target/venv/bin/python3")
}

/// Reads `argv[1]/{field,field_joints}.vtu` with meshio; writes every
/// array as little-endian f64 to `argv[1]/meshio.<file>.<array>.f64`
/// (`points`, `connectivity`, `point.<name>`, `cell.<name>`); prints one
/// JSON object. argv[2]: sections of the turn.
const SCRIPT: &str = r#"
import json, sys
import numpy as np
import meshio

d, n = sys.argv[1], int(sys.argv[2])
report = {}
for stem in ["field", "field_joints"]:
    m = meshio.read(f"{d}/{stem}.vtu")
    def save(name, a):
        np.ascontiguousarray(a, dtype="<f8").tofile(f"{d}/meshio.{stem}.{name}.f64")
    save("points", m.points)
    save("connectivity", np.concatenate([c.data.ravel() for c in m.cells]))
    for k, a in m.point_data.items():
        save(f"point.{k}", a)
    for k, blocks in m.cell_data.items():
        save(f"cell.{k}", np.concatenate(blocks))
    report[stem] = {
        "points": len(m.points),
        "cells": [[c.type, len(c.data)] for c in m.cells],
        "point_data": sorted(m.point_data),
        "cell_data": sorted(m.cell_data),
    }
# |u| at the points on the rings theta_k = 2 pi k / n (and on the axis).
m = meshio.read(f"{d}/field.vtu")
p, u = m.points, m.point_data["displacement"]
k = np.arctan2(p[:, 1], p[:, 0]) / (2 * np.pi / n)
on = (np.abs(k - np.round(k)) < 1e-9) | (np.hypot(p[:, 0], p[:, 1]) < 1e-12)
report["ring_points"] = int(on.sum())
report["max_displacement"] = float(np.linalg.norm(u[on], axis=1).max())
print(json.dumps(report))
"#;

fn f64s(path: &Path) -> Vec<f64> {
    std::fs::read(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

#[test]
fn meshio_reads_the_vtu_files() {
    let dir = tempfile::tempdir().unwrap();
    let scene = geo("pile_footing.json");
    // The same scene with the compressed encoding (its mesh path absolute).
    let mut compressed: Value = serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    compressed["mesh"]["file"] = Value::from(geo("pile_footing.geo").to_str().unwrap());
    compressed["outputs"]["vtu_compress"] = Value::from(true);
    let zlib_scene = dir.path().join("zlib.json");
    std::fs::write(&zlib_scene, compressed.to_string()).unwrap();
    let mut files = Vec::new();
    for (name, scene, zlib) in [("raw", &scene, false), ("zlib", &zlib_scene, true)] {
        let out = dir.path().join(name);
        check_with_meshio(scene, &out);
        let field = std::fs::read(out.join("field.vtu")).unwrap();
        let named = field.windows(21).any(|w| w == b"vtkZLibDataCompressor");
        assert_eq!(named, zlib, "{name}: the compressor attribute");
        files.push(read_vtu(&out.join("field.vtu")).unwrap());
    }
    // Both encodings hold the same values.
    let (raw, zlib) = (&files[0], &files[1]);
    assert_eq!(raw.arrays.len(), zlib.arrays.len());
    for (a, b) in raw.arrays.iter().zip(&zlib.arrays) {
        assert_eq!(
            (&a.parent, &a.name, &a.type_name),
            (&b.parent, &b.name, &b.type_name)
        );
        assert_eq!(a.bytes, b.bytes, "{}", a.name);
    }
}

/// Runs `scene` into `out` and compares meshio's reading of its `.vtu`
/// files with ours.
fn check_with_meshio(scene: &Path, out: &Path) {
    let run = axijoint(&[
        "run",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--set",
        "size=0.5",
        "--quiet",
    ]);
    let (stdout, stderr) = text(&run);
    assert!(run.status.success(), "{stdout}\n{stderr}");
    let header: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("solution.json")).unwrap()).unwrap();
    // Scene P: M = 4, Q9 cells: "auto" gives max(8, 4 M) = 16 sections.
    let n = 16;
    let elements = header["mesh"]["elements"].as_u64().unwrap() as usize;

    let py = python();
    let script = Command::new(&py)
        .arg("-c")
        .arg(SCRIPT)
        .arg(out)
        .arg(n.to_string())
        .output()
        .unwrap_or_else(|e| {
            panic!(
                "cannot run {} ({e}): run scripts/setup (it makes target/venv with meshio)",
                py.display()
            )
        });
    let (stdout, stderr) = text(&script);
    assert!(
        script.status.success(),
        "the meshio script failed (if meshio is missing, run scripts/setup):\n{stderr}"
    );
    let m: Value = serde_json::from_str(&stdout).unwrap_or_else(|e| panic!("{e}: {stdout}"));
    eprintln!("{m}");

    for (stem, cell_type) in [("field", "hexahedron27"), ("field_joints", "quad9")] {
        let ours = read_vtu(&out.join(format!("{stem}.vtu"))).unwrap();
        let theirs = &m[stem];
        assert_eq!(
            theirs["points"].as_u64().unwrap() as usize,
            ours.n_points,
            "{stem}"
        );
        assert_eq!(
            theirs["cells"],
            serde_json::json!([[cell_type, ours.n_cells]]),
            "{stem}"
        );
        let meshio = |name: &str| f64s(&out.join(format!("meshio.{stem}.{name}.f64")));
        let values = |parent: &str, name: &str| ours.array(parent, name).unwrap().values().unwrap();
        assert_eq!(meshio("points"), values("Points", "Points"), "{stem} points");
        assert_eq!(
            meshio("connectivity"),
            values("Cells", "connectivity"),
            "{stem} connectivity"
        );
        for (parent, prefix, key) in [
            ("PointData", "point", "point_data"),
            ("CellData", "cell", "cell_data"),
        ] {
            let mut names: Vec<&str> = ours
                .arrays
                .iter()
                .filter(|a| a.parent == parent)
                .map(|a| a.name.as_str())
                .collect();
            names.sort();
            assert_eq!(theirs[key], serde_json::json!(names), "{stem} {parent}");
            for name in names {
                assert_eq!(
                    meshio(&format!("{prefix}.{name}")),
                    values(parent, name),
                    "{stem} {name}"
                );
            }
        }
    }
    // The default point arrays, and n sections of every meridional cell.
    assert_eq!(
        m["field"]["point_data"],
        serde_json::json!(["displacement", "sigma_cyl", "von_mises"])
    );
    assert_eq!(m["field"]["cells"][0][1], n * elements);
    // The solver's largest |u| (its 16 sections) on the rings of the file.
    let (ours, solver) = (
        m["max_displacement"].as_f64().unwrap(),
        header["max_displacement"].as_f64().unwrap(),
    );
    assert!(m["ring_points"].as_u64().unwrap() > 0);
    assert!(
        solver > 0.0 && (ours - solver).abs() <= 1e-12 * solver,
        "{ours} vs {solver}"
    );
}
