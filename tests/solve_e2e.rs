//! End-to-end tests of `axijoint solve` on Scene P (docs/theory.md section 14):
//! the bonded and linear-joint variants, the solution folder, its safety
//! rules, and reading it back.

mod common;

use axijoint_solver::results::read_solution;
use common::*;
use serde_json::Value;
use std::path::Path;

fn solve(scene: &str, out: &Path, extra: &[&str]) -> Value {
    let scene = geo(scene);
    let mut args = vec!["solve", scene.to_str().unwrap(), "-o", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let run = axijoint(&args);
    let (stdout, stderr) = text(&run);
    assert!(run.status.success(), "{stdout}\n{stderr}");
    serde_json::from_str(&std::fs::read_to_string(out.join("solution.json")).unwrap()).unwrap()
}

/// The joint adds compliance: the pile end moves more with it than bonded.
/// Both runs balance the load: reaction = -applied to 1e-9 relative.
#[test]
fn scene_p_bonded_and_linear_joint() {
    let dir = tempfile::tempdir().unwrap();
    let bonded = solve(
        "pile_footing_bonded.json",
        &dir.path().join("bonded"),
        &["--set", "size=0.3"],
    );
    let joint = solve(
        "pile_footing.json",
        &dir.path().join("joint"),
        &["--set", "size=0.3"],
    );
    let ux = |v: &Value| v["loaded_faces"]["pile_end"][0].as_f64().unwrap();
    assert!(ux(&bonded) > 0.0, "the pile end moves with H (+x)");
    assert!(
        ux(&joint) > 1.05 * ux(&bonded),
        "joint {} vs bonded {}",
        ux(&joint),
        ux(&bonded)
    );
    for v in [&bonded, &joint] {
        let applied: Vec<f64> = ["force", "moment"]
            .iter()
            .flat_map(|k| {
                v["applied"][k]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap())
            })
            .collect();
        let reaction: Vec<f64> = ["force", "moment"]
            .iter()
            .flat_map(|k| {
                v["reactions"][0][k]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap())
            })
            .collect();
        // Fx = 0.5 MN at z = -3: My about the origin = z Fx = -1.5 MN m.
        assert!(
            (applied[0] - 0.5).abs() < 1e-12 && (applied[4] + 1.5).abs() < 1e-12,
            "{applied:?}"
        );
        for (a, r) in applied.iter().zip(&reaction) {
            assert!(
                (a + r).abs() <= 1e-9 * 1.5,
                "applied {applied:?} reaction {reaction:?}"
            );
        }
    }
}

#[test]
fn solution_reads_back_identically() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p");
    let v = solve(
        "pile_footing.json",
        &out,
        &["--set", "size=0.4", "--harmonics", "2"],
    );
    let saved = read_solution(&out).unwrap();
    assert_eq!(
        saved.mesh.nodes.len() as u64,
        v["mesh"]["nodes"].as_u64().unwrap()
    );
    assert_eq!(saved.displacements.harmonics.len(), 3);
    // The face average recomputed from the saved amplitudes equals the
    // header's (to rounding: the saved mesh's coordinates are read back from
    // the text of mesh.msh).
    let d = axijoint_solver::run::face_displacement(&saved.mesh, "pile_end", &saved.displacements).unwrap();
    let header = v["loaded_faces"]["pile_end"][0].as_f64().unwrap();
    assert!((d[0] / header - 1.0).abs() < 1e-12, "{} vs {header}", d[0]);
    // A truncated displacement file is refused, naming it.
    let bin = out.join("displacement.f64");
    let bytes = std::fs::read(&bin).unwrap();
    std::fs::write(&bin, &bytes[..bytes.len() - 8]).unwrap();
    let e = read_solution(&out).err().unwrap().to_string();
    assert!(e.contains("displacement.f64") && e.contains("truncated"), "{e}");
}

/// An existing folder that is not a solution is never replaced; an earlier
/// solution is, and only when the new one is complete.
#[test]
fn output_folder_rules() {
    let dir = tempfile::tempdir().unwrap();
    let precious = dir.path().join("mine");
    std::fs::create_dir(&precious).unwrap();
    std::fs::write(precious.join("notes.txt"), "keep me").unwrap();
    let scene = geo("pile_footing_bonded.json");
    let run = axijoint(&[
        "solve",
        scene.to_str().unwrap(),
        "-o",
        precious.to_str().unwrap(),
        "--set",
        "size=0.5",
    ]);
    let (_, err) = text(&run);
    assert_eq!(run.status.code(), Some(5), "an output folder that cannot be used");
    assert!(
        err.contains("mine") && err.contains("not an axijoint solution folder"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_to_string(precious.join("notes.txt")).unwrap(),
        "keep me"
    );

    let out = dir.path().join("sol");
    let first = solve("pile_footing_bonded.json", &out, &["--set", "size=0.5"]);
    let second = solve("pile_footing_bonded.json", &out, &["--set", "size=0.4"]);
    assert!(second["mesh"]["nodes"].as_u64() > first["mesh"]["nodes"].as_u64());
    // A failing run leaves the earlier solution as it was.
    let run = axijoint(&[
        "solve",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--set",
        "size=-1",
    ]);
    assert_eq!(run.status.code(), Some(4), "gmsh rejects the size");
    let kept: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("solution.json")).unwrap()).unwrap();
    assert_eq!(kept["mesh"]["nodes"], second["mesh"]["nodes"]);
    // No staging folders are left behind.
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.contains("partial")), "{names:?}");
}

#[test]
fn bad_scene_names_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read_to_string(geo("pile_footing_bonded.json")).unwrap();
    let bad = good.replace("\"nu\": 0.17", "\"nu\": 0.5");
    assert_ne!(bad, good);
    let path = dir.path().join("bad.json");
    // The mesh file is relative to the scene: point it back to geo/.
    let bad = bad.replace(
        "\"pile_footing.geo\"",
        &format!("{:?}", geo("pile_footing.geo").to_str().unwrap()),
    );
    std::fs::write(&path, bad).unwrap();
    let run = axijoint(&[
        "solve",
        path.to_str().unwrap(),
        "-o",
        dir.path().join("o").to_str().unwrap(),
    ]);
    let (_, err) = text(&run);
    assert_eq!(run.status.code(), Some(1));
    assert!(err.contains("bad.json") && err.contains("nu"), "{err}");
    assert!(!dir.path().join("o").exists());
}
