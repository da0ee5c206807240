//! Shared helpers of the end-to-end tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap()
}

/// A file of `geo/`.
pub fn geo(name: &str) -> PathBuf {
    root().join("geo").join(name)
}

/// The mesh cache folder of the end-to-end tests (`AXIJOINT_CACHE`), under
/// the build folder: the tests neither read nor fill the user's cache.
pub fn test_cache() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("mesh-cache")
}

/// Runs the `axijoint` binary.
pub fn axijoint(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_axijoint"))
        .args(args)
        .env("AXIJOINT_CACHE", test_cache())
        .output()
        .expect("axijoint runs")
}

/// `axijoint solve -q SCENE --set size=SIZE --harmonics M -o OUT`: whether
/// it succeeded, and its stdout and stderr.
pub fn solve_coarse(scene: &Path, out: &Path, size: f64, m: u32) -> (bool, String, String) {
    let (size, m) = (format!("size={size}"), m.to_string());
    let run = axijoint(&[
        "solve",
        "-q",
        scene.to_str().unwrap(),
        "--set",
        &size,
        "--harmonics",
        &m,
        "-o",
        out.to_str().unwrap(),
    ]);
    let (stdout, stderr) = text(&run);
    (run.status.success(), stdout, stderr)
}

/// stdout and stderr of a run, as text.
pub fn text(out: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// gmsh parameters of Scene P for one element family.
pub fn family_params(family: &str, size: f64) -> Vec<(String, f64)> {
    let (order, quads, serendipity) = match family {
        "T3" => (1.0, 0.0, 0.0),
        "T6" => (2.0, 0.0, 0.0),
        "Q4" => (1.0, 1.0, 0.0),
        "Q8" => (2.0, 1.0, 1.0),
        "Q9" => (2.0, 1.0, 0.0),
        _ => panic!("unknown family {family}"),
    };
    vec![
        ("size".into(), size),
        ("order".into(), order),
        ("quads".into(), quads),
        ("serendipity".into(), serendipity),
    ]
}
