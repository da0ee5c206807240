//! End-to-end tests of the exit statuses (the table in
//! `crates/cli/src/main.rs`, docs/outputs.md and docs/loading.md), one
//! class at a time, through the real binary and gmsh:
//!
//! - 1 input error: a malformed scene JSON, a missing scene file, a scene
//!   naming a physical group the mesh lacks, a model without enough
//!   supports (singular stiffness);
//! - 4 gmsh failure: a `.geo` with a syntax error, gmsh not found or not
//!   executable;
//! - 5 I/O error: an output folder under a regular file, a scene path that
//!   is a folder (exists, cannot be read);
//! - 6 numerical failure: a one-shot run of the paper's method that stalls
//!   on a stiff joint, a stepped run that stops short of the whole load
//!   for a reason other than capacity;
//! - 0 with a closed or full stdout: the console is best effort, the files
//!   are written;
//! - 3 beyond capacity is tested in `load_path_e2e.rs`
//!   (`beyond_capacity_stops_at_the_limit_load_factor`,
//!   `one_shot_beyond_capacity_finds_no_equilibrium`), 2 (clap) needs no
//!   test of ours.
//!
//! Each run takes well under a second (coarse meshes, no plots).

mod common;

use common::*;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Writes `scene` (a JSON value) as `dir/NAME.json`.
fn write_scene(dir: &Path, name: &str, scene: &Value) -> PathBuf {
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, serde_json::to_string_pretty(scene).unwrap()).unwrap();
    path
}

/// A repository scene as JSON, its mesh file made absolute and no report
/// outputs (plots, VTU) asked for.
fn repo_scene(name: &str) -> Value {
    let text = std::fs::read_to_string(geo(name)).unwrap();
    let mut scene: Value = serde_json::from_str(&text).unwrap();
    let mesh = scene["mesh"]["file"].as_str().unwrap().to_string();
    scene["mesh"]["file"] = json!(geo(&mesh).to_str().unwrap());
    scene["outputs"] = json!({"csv": false, "plots": false, "vtu": false, "gmsh_views": false});
    scene
}

/// `axijoint solve SCENE -o OUT -q EXTRA...`.
fn solve(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "solve",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
    ];
    args.extend_from_slice(extra);
    axijoint(&args)
}

/// Asserts the exit status is exactly `status` and the message contains
/// every one of `needles`; returns stderr.
fn assert_status(run: &Output, status: i32, needles: &[&str]) -> String {
    let (stdout, stderr) = text(run);
    assert_eq!(
        run.status.code(),
        Some(status),
        "exit status exactly {status}\n{stdout}\n{stderr}"
    );
    for n in needles {
        assert!(stderr.contains(n), "the message names {n:?}: {stderr}");
    }
    stderr
}

fn read_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

/// 1: a scene that is not JSON, one that does not exist, one naming a
/// physical group the mesh lacks, one whose supports leave a mechanism,
/// one with a modulus in another unit.
#[test]
fn input_errors_exit_1() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");

    let malformed = dir.path().join("malformed.json");
    std::fs::write(&malformed, "{\"title\": \"cut short\",\n \"mesh\": {").unwrap();
    assert_status(&solve(&malformed, &out, &[]), 1, &["malformed.json", "line 2"]);

    let missing = dir.path().join("no_such_scene.json");
    let stderr = assert_status(&solve(&missing, &out, &[]), 1, &["no_such_scene.json"]);
    assert_eq!(
        stderr.matches("os error").count(),
        1,
        "the OS error said once: {stderr}"
    );

    let mut scene = repo_scene("pile_footing_bonded.json");
    scene["supports"][0]["on"] = json!("no_such_group");
    let path = write_scene(dir.path(), "missing_group", &scene);
    assert_status(
        &solve(&path, &out, &["--set", "size=0.5"]),
        1,
        &["missing_group.json", "no_such_group", "footing_outer"],
    );

    // Only z fixed: the model turns and slides freely in harmonic 1.
    let mut scene = repo_scene("pile_footing_bonded.json");
    scene["supports"] = json!([{"on": "footing_outer", "fix": ["z"]}]);
    let path = write_scene(dir.path(), "no_supports", &scene);
    assert_status(
        &solve(&path, &out, &["--set", "size=0.5"]),
        1,
        &["singular", "check the supports"],
    );

    // The pile's modulus typed in another unit (x 1e9): the factorization
    // fails on the contrast, and the message says so, not "the supports".
    let mut scene = repo_scene("pile_footing_bonded.json");
    scene["materials"]["pile"]["E"] = json!(2.0e13);
    let path = write_scene(dir.path(), "modulus_unit", &scene);
    assert_status(
        &solve(&path, &out, &["--set", "size=0.5"]),
        1,
        &["singular", "range from 2.000e4 to 2.000e13", "another unit"],
    );
    assert!(!out.exists(), "no input error writes an output folder");
}

/// 4: gmsh rejects the `.geo` (syntax error), through `mesh` and through a
/// scene; gmsh is not there (`AXIJOINT_GMSH` names a missing program) or
/// cannot be started (a file that is not executable).
#[test]
fn gmsh_failures_exit_4() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.geo");
    std::fs::write(&bad, "Point(1) = {0, 0, 0;\n").unwrap();
    assert_status(
        &axijoint(&["mesh", bad.to_str().unwrap()]),
        4,
        &["bad.geo", "gmsh failed", "syntax error"],
    );

    let mut scene = repo_scene("pile_footing_bonded.json");
    scene["mesh"] = json!({"file": bad.to_str().unwrap()});
    let path = write_scene(dir.path(), "bad_geo", &scene);
    let out = dir.path().join("out");
    assert_status(&solve(&path, &out, &[]), 4, &["bad.geo", "syntax error"]);
    assert!(!out.exists());

    let with_gmsh = |program: &Path| {
        Command::new(env!("CARGO_BIN_EXE_axijoint"))
            .args(["mesh", geo("cylinder.geo").to_str().unwrap()])
            .env("AXIJOINT_GMSH", program)
            .env("AXIJOINT_CACHE", test_cache())
            .output()
            .expect("axijoint runs")
    };
    let run = with_gmsh(&dir.path().join("no_such_gmsh"));
    assert_status(&run, 4, &["gmsh not found", "cylinder.geo"]);
    // A file without execute permission (refused even to root).
    let not_a_program = dir.path().join("gmsh.txt");
    std::fs::write(&not_a_program, "not a program").unwrap();
    let run = with_gmsh(&not_a_program);
    assert_status(&run, 4, &["cylinder.geo", "could not be started"]);
}

/// 4 as well: gmsh stopped at its CPU time bound (a mesh size 125 times
/// too small) or at its memory bound, in bounded time, the message naming
/// the bound, its variable and the parameters.
#[test]
fn gmsh_runs_under_a_time_and_a_memory_bound() {
    let bounded = |var: &str, value: &str, size: &str| {
        let start = std::time::Instant::now();
        let out = Command::new(env!("CARGO_BIN_EXE_axijoint"))
            .args([
                "mesh",
                geo("pile_soil.geo").to_str().unwrap(),
                "--no-cache",
                "--set",
            ])
            .arg(format!("size={size}"))
            .env(var, value)
            .output()
            .expect("axijoint runs");
        (out, start.elapsed().as_secs_f64())
    };
    let (run, seconds) = bounded("AXIJOINT_GMSH_SECONDS", "2", "0.002");
    assert_status(
        &run,
        4,
        &[
            "pile_soil.geo",
            "bound of 2 s of CPU time",
            "AXIJOINT_GMSH_SECONDS",
            "size = 0.002",
        ],
    );
    assert!(seconds < 30.0, "{seconds} s");
    let (run, seconds) = bounded("AXIJOINT_GMSH_MEMORY", "300M", "0.005");
    assert_status(
        &run,
        4,
        &[
            "pile_soil.geo",
            "memory bound of 300 MiB",
            "AXIJOINT_GMSH_MEMORY",
            "size = 0.005",
        ],
    );
    assert!(seconds < 60.0, "{seconds} s");
    let (run, _) = bounded("AXIJOINT_GMSH_MEMORY", "lots", "0.25");
    assert_status(&run, 4, &["AXIJOINT_GMSH_MEMORY=lots", "K, M or G"]);
}

/// 1, before the work: more than 512 harmonics (before gmsh), and factors
/// beyond the memory a run may use (`AXIJOINT_MEMORY`, before any
/// factorization); `--force` goes on past the first.
#[test]
fn cost_limits_are_refused_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let scene = geo("pile_soil.json");
    let out = dir.path().join("out");
    let run = |extra: &[&str], memory: &str| {
        let start = std::time::Instant::now();
        let done = Command::new(env!("CARGO_BIN_EXE_axijoint"))
            .args([
                "solve",
                scene.to_str().unwrap(),
                "-q",
                "-o",
                out.to_str().unwrap(),
            ])
            .args(extra)
            .env("AXIJOINT_MEMORY", memory)
            .env("AXIJOINT_CACHE", test_cache())
            .output()
            .expect("axijoint runs");
        (done, start.elapsed().as_secs_f64())
    };
    let (done, seconds) = run(&["--harmonics", "600"], "");
    assert_status(&done, 1, &["pile_soil.json", "harmonics: 600", "512", "--force"]);
    assert!(seconds < 5.0 && !out.exists(), "{seconds} s");
    // 9 harmonics of the shipped mesh within 1 MiB: refused before any
    // factorization, naming the estimate.
    let (done, _) = run(&["--harmonics", "8"], "1M");
    assert_status(
        &done,
        1,
        &[
            "pile_soil.json",
            "9 harmonics",
            "GiB",
            "AXIJOINT_MEMORY",
            "--force",
        ],
    );
    assert!(!out.exists());
    let (done, _) = run(&["--harmonics", "8", "--force"], "1M");
    assert_eq!(done.status.code(), Some(0), "{}", text(&done).1);
}

/// Outputs beyond the free space of the output's disk are refused after
/// meshing, before any factorization (10^7 sections of `field.vtu`: about
/// 2 TB); the estimate against the files a run writes (Scene P bonded at
/// M = 4 and 12, default sections): within 25 %.
#[test]
fn outputs_beyond_the_disk_are_refused_and_the_estimate_holds() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = repo_scene("pile_footing_bonded.json");
    scene["mesh"]["parameters"]["size"] = json!(0.5);
    scene["outputs"] =
        json!({"csv": false, "plots": false, "vtu": true, "gmsh_views": true, "vtu_sections": 10_000_000});
    let huge = write_scene(dir.path(), "huge", &scene);
    let out = dir.path().join("out");
    let start = std::time::Instant::now();
    assert_status(
        &solve(&huge, &out, &[]),
        1,
        &[
            "huge.json",
            "the outputs of 5 harmonics",
            "GiB",
            "outputs.vtu",
            "--force",
        ],
    );
    assert!(start.elapsed().as_secs_f64() < 10.0 && !out.exists());
    scene["outputs"]["vtu_sections"] = json!("auto");
    for m in [4, 12] {
        scene["harmonics"] = json!(m);
        let path = write_scene(dir.path(), &format!("m{m}"), &scene);
        let out = dir.path().join(format!("m{m}"));
        let run = axijoint(&["run", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"]);
        assert_eq!(run.status.code(), Some(0), "{}", text(&run).1);
        let size = |f: &str| std::fs::metadata(out.join(f)).unwrap().len() as f64;
        let written = size("displacement.f64") + size("field.vtu") + size("field_views.msh");
        let solution: Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("solution.json")).unwrap()).unwrap();
        let nodes = solution["mesh"]["nodes"].as_u64().unwrap() as usize;
        let parsed = axijoint_solver::scene::Scene::from_path(&path).unwrap();
        let estimate = axijoint_solver::run::output_bytes(&parsed, nodes) as f64;
        assert!(
            (0.75..=1.25).contains(&(estimate / written)),
            "M = {m}: estimate {estimate} bytes, written {written}"
        );
    }
}

/// 5: the output folder cannot be made (its parent is a regular file); an
/// input that exists but cannot be read (the scene path is a folder).
/// (A read-only folder would not do: the tests may run as root.)
#[test]
fn io_errors_exit_5() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a_file");
    std::fs::write(&file, "not a folder").unwrap();
    let scene = write_scene(dir.path(), "bonded", &repo_scene("pile_footing_bonded.json"));
    assert_status(
        &solve(&scene, &file.join("out"), &["--set", "size=0.5"]),
        5,
        &["a_file/out", "a_file is a file, not a folder"],
    );
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "not a folder");
    // `run` (with the comparison without joints beside the output) names
    // the path too.
    let jointed = write_scene(dir.path(), "jointed", &repo_scene("pile_footing.json"));
    let out = file.join("out");
    let run = axijoint(&[
        "run",
        jointed.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert_status(&run, 5, &["a_file/out", "is a file, not a folder"]);

    let folder = dir.path().join("folder.json");
    std::fs::create_dir(&folder).unwrap();
    assert_status(
        &solve(&folder, &dir.path().join("out"), &[]),
        5,
        &["folder.json", "cannot read"],
    );
}

/// Scene P with the joint's stiffnesses scaled so that `k_eta h / E` is
/// `kh_over_e` (h = 0.125 the joint element length, E = 2e4; table1 has
/// 0.125), the default sections, the paper's method and `loading`, as in
/// `stiff_scene_p` of crates/solver/tests/stability.rs.
fn stiff_scene_p(kh_over_e: f64, loading: Value) -> Value {
    let mut scene = repo_scene("pile_footing.json");
    let p = &scene["mesh"]["parameters"];
    let h = p["size"].as_f64().unwrap() / p["refine"].as_f64().unwrap();
    assert_eq!(h, 0.125);
    let e = scene["materials"]["pile"]["E"].as_f64().unwrap();
    let joint = &mut scene["joints"]["pile_side"];
    let f = kh_over_e * e / h / joint["k_eta"].as_f64().unwrap();
    for k in ["k_xi", "k_eta", "k_theta"] {
        joint[k] = json!(f * joint[k].as_f64().unwrap());
    }
    scene.as_object_mut().unwrap().remove("sections");
    scene["solver"]["method"] = json!("paper");
    scene["solver"]["loading"] = loading;
    scene
}

/// 6: the paper's one-shot iteration stalls on a stiff joint
/// (`k_eta h / E` = 12.5): not a "no equilibrium" (the pile head is bonded,
/// an equilibrium exists), so not 3; the last iterate is written, marked.
/// A stepped run of the paper's method at `k_eta h / E` = 1e4 stops at
/// lambda = 0, "not a limit load": 6 too, its outputs written.
#[test]
fn numerical_failures_exit_6() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_scene(dir.path(), "stiff", &stiff_scene_p(12.5, json!("one_shot")));
    let out = dir.path().join("stiff");
    let stderr = assert_status(
        &solve(&path, &out, &[]),
        6,
        &["not converged", "k h / E = 12.5", "last iterate is written"],
    );
    assert!(!stderr.contains("no equilibrium"), "{stderr}");
    let extra = &read_json(&out.join("solution.json"))["extra"];
    assert_eq!(extra["converged"], json!(false), "{extra}");

    let path = write_scene(
        dir.path(),
        "stiff_stepped",
        &stiff_scene_p(1e4, json!({"steps": "auto"})),
    );
    let out = dir.path().join("stiff_stepped");
    assert_status(
        &solve(&path, &out, &[]),
        6,
        &[
            "short of the whole load",
            "does not show the load exceeds",
            "pile_side",
        ],
    );
    let limit = &read_json(&out.join("solution.json"))["extra"]["load_path"]["limit"];
    assert_eq!(limit["beyond_capacity"], json!(false), "{limit}");
}

/// The rows `| status | class | when |` of the exit-status table in
/// `text`, each line stripped of `prefix` first.
fn status_rows(text: &str, prefix: &str) -> Vec<(u8, String, String)> {
    text.lines()
        .filter_map(|l| l.strip_prefix(prefix))
        .filter_map(|l| {
            let cells: Vec<&str> = l.trim().trim_matches('|').split('|').map(str::trim).collect();
            let status = cells.first()?.parse().ok()?;
            Some((status, cells.get(1)?.to_string(), cells.get(2)?.to_string()))
        })
        .collect()
}

/// The table in main.rs's module doc and docs/outputs.md's are the same,
/// with every status 0..=6, and docs/loading.md's "Exit status" names each
/// status with its class.
#[test]
fn the_documented_tables_agree() {
    let read = |p: &str| std::fs::read_to_string(root().join(p)).unwrap();
    let code = status_rows(&read("crates/cli/src/main.rs"), "//! ");
    let outputs = status_rows(&read("docs/outputs.md"), "");
    let statuses: Vec<u8> = code.iter().map(|r| r.0).collect();
    assert_eq!(statuses, (0..=6).collect::<Vec<u8>>(), "{code:?}");
    assert_eq!(code, outputs, "main.rs and docs/outputs.md");
    let loading = read("docs/loading.md");
    let section = &loading[loading.find("## Exit status").expect("section")..];
    let section = section[3..]
        .find("\n## ")
        .map_or(section, |end| &section[..end + 3]);
    let section = section.split_whitespace().collect::<Vec<_>>().join(" ");
    for (status, class, _) in &code {
        assert!(
            section.contains(&format!("{status} ({class}")),
            "docs/loading.md's Exit status says \"{status} ({class}\""
        );
    }
}

/// A closed stdout (`axijoint run ... | head -1`) or a full one (`>
/// /dev/full`) neither panics nor stops the run before its files are
/// written: the console is best effort, the files are the result (exit 0,
/// `summary.json` complete). `println!` panicked there (exit 101, no report).
#[test]
fn a_closed_or_full_stdout_does_not_stop_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_scene(dir.path(), "bonded", &repo_scene("pile_footing_bonded.json"));
    let run = |name: &str, stdout: std::process::Stdio| {
        let out = dir.path().join(name);
        let mut child = Command::new(env!("CARGO_BIN_EXE_axijoint"))
            .args(["run", path.to_str().unwrap(), "-o", out.to_str().unwrap()])
            .args(["--set", "size=0.5"])
            .env("AXIJOINT_CACHE", test_cache())
            .stdout(stdout)
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("axijoint runs");
        // A closed pipe: its reading end dropped before the run prints.
        drop(child.stdout.take());
        let output = child.wait_with_output().unwrap();
        let summary = read_json(&out.join("summary.json"));
        (output, summary)
    };
    let (closed, summary) = run("closed", std::process::Stdio::piped());
    assert_eq!(closed.status.code(), Some(0), "{}", text(&closed).1);
    assert_eq!(summary["complete"], json!(true), "{summary}");
    let full = std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
    let (full, summary) = run("full", full.into());
    assert_eq!(full.status.code(), Some(0), "{}", text(&full).1);
    assert_eq!(summary["complete"], json!(true), "{summary}");
}

/// A killed run's leftovers beside the output (the comparison's folder,
/// a partial solution folder) and in the temporary folder go with the next
/// run; a live process's stay.
#[test]
fn a_run_removes_the_leftovers_of_killed_runs() {
    let dir = tempfile::tempdir().unwrap();
    // A process id above the kernel's largest is never alive.
    let dead = 4_194_305 + 11;
    let leftovers = [
        dir.path().join(format!(".without_joints-{dead}-x")),
        dir.path().join(format!(".out.partial-{dead}")),
        std::env::temp_dir().join(format!("axijoint-{dead}-y")),
    ];
    let live = dir
        .path()
        .join(format!(".without_joints-{}-z", std::process::id()));
    for d in leftovers.iter().chain([&live]) {
        std::fs::create_dir_all(d.join("inner")).unwrap();
    }
    let path = write_scene(dir.path(), "p", &repo_scene("pile_footing_bonded.json"));
    let run = solve(&path, &dir.path().join("out"), &[]);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run).1);
    for d in &leftovers {
        assert!(!d.exists(), "{} is left", d.display());
    }
    assert!(live.exists());
}
