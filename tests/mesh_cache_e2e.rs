//! The mesh cache through the `axijoint` binary: gmsh is a wrapper script
//! that counts its runs, and `AXIJOINT_CACHE` names a temporary folder (the
//! user's cache is neither read nor written). A second run of the same
//! scene does not start gmsh and writes the same solution (displacements
//! and `mesh.msh` byte for byte, `solution.json` but for its timings); a
//! changed `--set` value, `--no-cache`, and a damaged entry mesh again.

mod common;

use common::*;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

struct Setup {
    dir: tempfile::TempDir,
    gmsh: PathBuf,
    count: PathBuf,
}

impl Setup {
    fn new() -> Setup {
        let dir = tempfile::tempdir().unwrap();
        let count = dir.path().join("gmsh_runs");
        let real = std::env::var("AXIJOINT_GMSH").unwrap_or_else(|_| "gmsh".into());
        let gmsh = dir.path().join("gmsh");
        std::fs::write(
            &gmsh,
            format!(
                "#!/bin/sh\necho run >> '{}'\nexec '{real}' \"$@\"\n",
                count.display()
            ),
        )
        .unwrap();
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&gmsh, std::fs::Permissions::from_mode(0o755)).unwrap();
        }
        Setup { dir, gmsh, count }
    }

    fn cache(&self) -> PathBuf {
        self.dir.path().join("cache")
    }

    /// How many times gmsh ran.
    fn runs(&self) -> usize {
        std::fs::read_to_string(&self.count).map_or(0, |s| s.lines().count())
    }

    fn entries(&self) -> Vec<PathBuf> {
        std::fs::read_dir(self.cache().join("meshes"))
            .map(|rd| rd.map(|e| e.unwrap().path()).collect())
            .unwrap_or_default()
    }

    /// `axijoint ARGS` with the counting gmsh and the temporary cache.
    fn axijoint(&self, args: &[&str]) {
        let out = Command::new(env!("CARGO_BIN_EXE_axijoint"))
            .args(args)
            .env("AXIJOINT_GMSH", &self.gmsh)
            .env("AXIJOINT_CACHE", self.cache())
            .output()
            .expect("axijoint runs");
        let (stdout, stderr) = text(&out);
        assert!(out.status.success(), "{args:?}\n{stdout}\n{stderr}");
    }

    /// Solves the bonded Scene P into `name` with `extra` arguments.
    fn solve(&self, name: &str, extra: &[&str]) -> PathBuf {
        let out = self.dir.path().join(name);
        let scene = geo("pile_footing_bonded.json");
        let mut args = vec![
            "solve",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q",
        ];
        args.extend_from_slice(extra);
        self.axijoint(&args);
        out
    }
}

/// The solution of a folder: displacements and `mesh.msh` bytes, and
/// `solution.json` without its timings.
fn solution(dir: &Path) -> (Vec<u8>, Vec<u8>, Value) {
    let mut json: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("solution.json")).unwrap()).unwrap();
    json.as_object_mut().unwrap().remove("timings");
    (
        std::fs::read(dir.join("displacement.f64")).unwrap(),
        std::fs::read(dir.join("mesh.msh")).unwrap(),
        json,
    )
}

#[test]
fn a_repeated_run_reuses_the_mesh() {
    let s = Setup::new();
    let first = s.solve("first", &["--set", "size=0.4"]);
    assert_eq!(s.runs(), 1);
    assert_eq!(s.entries().len(), 1);

    let second = s.solve("second", &["--set", "size=0.4"]);
    assert_eq!(s.runs(), 1, "the second run started gmsh");
    assert!(
        solution(&second) == solution(&first),
        "a cached mesh changed the solution"
    );

    // `axijoint mesh` of the same scene reads the same entry.
    s.axijoint(&[
        "mesh",
        geo("pile_footing_bonded.json").to_str().unwrap(),
        "--set",
        "size=0.4",
    ]);
    assert_eq!(s.runs(), 1);

    // Another value of a parameter: gmsh again, a second entry.
    s.solve("coarser", &["--set", "size=0.45"]);
    assert_eq!(s.runs(), 2);
    assert_eq!(s.entries().len(), 2);

    // --no-cache: gmsh again, nothing read or written.
    let uncached = s.solve("uncached", &["--set", "size=0.4", "--no-cache"]);
    assert_eq!(s.runs(), 3);
    assert_eq!(s.entries().len(), 2);
    assert!(solution(&uncached) == solution(&first));
}

#[test]
fn a_damaged_entry_is_not_used() {
    let s = Setup::new();
    let first = s.solve("first", &["--set", "size=0.4"]);
    assert_eq!(s.runs(), 1);
    let entry = s.entries().pop().unwrap();
    let whole = std::fs::read(&entry).unwrap();
    // One byte of the last node coordinates changed (still a readable .msh).
    let text = String::from_utf8(whole.clone()).unwrap();
    let at = text.find("$EndNodes").unwrap() - 2;
    assert!(whole[at].is_ascii_digit());
    let mut bad = whole.clone();
    bad[at] = if bad[at] == b'1' { b'2' } else { b'1' };
    std::fs::write(&entry, &bad).unwrap();

    let again = s.solve("again", &["--set", "size=0.4"]);
    assert_eq!(s.runs(), 2, "a damaged entry was read");
    assert!(solution(&again) == solution(&first));
    assert_eq!(std::fs::read(&entry).unwrap(), whole, "the entry is rewritten");
    s.solve("third", &["--set", "size=0.4"]);
    assert_eq!(s.runs(), 2);
}

/// `axijoint run` of a scene with joints meshes once for the scene and its
/// comparison without joints when the cache cannot help: under
/// `--no-cache`, and with a cache folder that cannot be written (a regular
/// file in its place), which is said once on stderr.
#[test]
fn a_run_and_its_comparison_mesh_once_without_a_cache() {
    let s = Setup::new();
    let scene = geo("pile_footing.json");
    let run = |name: &str, extra: &[&str], cache: &Path| {
        let out = s.dir.path().join(name);
        let mut args = vec!["run", scene.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"];
        args.extend_from_slice(&["--set", "size=0.5"]);
        args.extend_from_slice(extra);
        let done = Command::new(env!("CARGO_BIN_EXE_axijoint"))
            .args(&args)
            .env("AXIJOINT_GMSH", &s.gmsh)
            .env("AXIJOINT_CACHE", cache)
            .output()
            .expect("axijoint runs");
        let (stdout, stderr) = text(&done);
        assert!(done.status.success(), "{stdout}\n{stderr}");
        assert!(out.join("without_joints/solution.json").is_file());
        stderr
    };
    let stderr = run("uncached", &["--no-cache"], &s.cache());
    assert_eq!(s.runs(), 1, "gmsh ran for the comparison too");
    assert!(!stderr.contains("cannot be written"), "{stderr}");

    let blocked = s.dir.path().join("not_a_folder");
    std::fs::write(&blocked, "a file where the cache should be").unwrap();
    let stderr = run("unwritable", &[], &blocked);
    assert_eq!(s.runs(), 2, "gmsh ran for the comparison too");
    assert_eq!(stderr.matches("cannot be written").count(), 1, "{stderr}");
    assert!(
        stderr.contains("not_a_folder") && stderr.contains("AXIJOINT_CACHE"),
        "{stderr}"
    );
}
