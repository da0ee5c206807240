//! `axijoint solve` and `axijoint run`.

mod adapt;

use anyhow::{Context, Result};
use axijoint_report::cuts::profile_values;
use axijoint_solver::driver::{
    solution_header, solve_scene_auto, solve_scene_with, InitialState, LinearRun, Run,
};
use axijoint_solver::iteration::{IterationError, IterationRecord};
use axijoint_solver::results::{read_solution, write_solution, JointFieldFile, SolutionHeader};
use axijoint_solver::scene::{Harmonics, Scene};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::path::{Path, PathBuf};
use std::time::Duration;

#[derive(Args)]
pub struct SolveArgs {
    /// The scene file (JSON, see docs/scene-format.md).
    pub scene: PathBuf,
    #[command(flatten)]
    pub common: CommonArgs,
}

#[derive(Args)]
pub struct RunArgs {
    /// The scene file [default: the repository's geo/pile_footing.json, Scene P].
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub common: CommonArgs,
}

#[derive(Args)]
pub struct CommonArgs {
    /// Output folder [default: out/SCENE-NAME in the current folder].
    #[arg(short, long, value_name = "DIR")]
    pub output: Option<PathBuf>,
    /// Override a gmsh parameter of the scene's mesh, NAME=VALUE; repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Override the scene's highest harmonic M.
    #[arg(long, value_name = "M")]
    pub harmonics: Option<u32>,
    /// Override the convergence tolerance of the iteration.
    #[arg(long, value_name = "EPS")]
    pub epsilon: Option<f64>,
    /// No progress display.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Reads the scene and applies the command-line overrides.
pub fn load_scene(path: &Path, common: &CommonArgs) -> Result<Scene> {
    let mut scene = Scene::from_path(path)?;
    for (name, value) in crate::mesh_cmd::parse_parameters(&common.set)? {
        scene.mesh.parameters.insert(name, value);
    }
    if let Some(m) = common.harmonics {
        scene.harmonics = m.into();
    }
    if let Some(e) = common.epsilon {
        anyhow::ensure!(e > 0.0 && e < 1.0, "--epsilon {e}: must lie in (0, 1)");
        scene.solver.epsilon = e;
    }
    Ok(scene)
}

/// The default output folder of a scene: `out/<stem>` under the current folder.
pub fn default_output(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    PathBuf::from("out").join(stem)
}

/// The repository's Scene P: `geo/pile_footing.json` under the current
/// folder, else next to the sources this binary was built from.
pub fn default_scene() -> Result<PathBuf> {
    let here = PathBuf::from("geo/pile_footing.json");
    if here.is_file() {
        return Ok(here);
    }
    let built = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../geo/pile_footing.json");
    anyhow::ensure!(
        built.is_file(),
        "no scene given and the default geo/pile_footing.json was not found; pass a scene file"
    );
    Ok(built)
}

/// Solves, writes the solution folder, prints a summary; returns the header.
pub fn solve_and_write(scene_path: &Path, common: &CommonArgs) -> Result<(Scene, PathBuf, SolutionHeader)> {
    solve_and_write_then(scene_path, common, &|| {})
}

/// [`solve_and_write`], calling `iterating` at every iteration record (the
/// factors are made: the rest of the solve keeps about one core busy).
pub fn solve_and_write_then(
    scene_path: &Path,
    common: &CommonArgs,
    iterating: &dyn Fn(),
) -> Result<(Scene, PathBuf, SolutionHeader)> {
    let scene = load_scene(scene_path, common)?;
    let out = common
        .output
        .clone()
        .unwrap_or_else(|| default_output(scene_path));
    let header = if scene.mesh.adapt.is_some() {
        adapt::solve_adaptive(&scene, &out, common.quiet, iterating)?
    } else {
        solve_to_then(&scene, &out, common.quiet, iterating)?
    };
    print_summary(scene_path, &scene, &header, &out);
    Ok((scene, out, header))
}

/// The `.msh` a run of `scene` solves: gmsh's output in `tmp` for a `.geo`,
/// else the scene's own `.msh`.
pub fn solved_msh(scene: &Scene, tmp: &Path) -> PathBuf {
    let is_geo = scene
        .mesh_path()
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("geo"));
    if is_geo {
        tmp.join("mesh.msh")
    } else {
        scene.mesh_path()
    }
}

/// Solves `scene` into the solution folder `out`.
pub fn solve_to(scene: &Scene, out: &Path, quiet: bool) -> Result<SolutionHeader> {
    solve_to_then(scene, out, quiet, &|| {})
}

/// [`solve_to`], calling `iterating` at every iteration record.
pub fn solve_to_then(scene: &Scene, out: &Path, quiet: bool, iterating: &dyn Fn()) -> Result<SolutionHeader> {
    let tmp = tempfile::tempdir().context("creating a temporary folder")?;
    let msh = solved_msh(scene, tmp.path());

    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        let b = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        b.set_style(ProgressStyle::with_template("{spinner} {elapsed} {msg}").expect("valid template"));
        b.enable_steady_tick(Duration::from_millis(200));
        b.set_message("meshing and factorizing");
        b
    };
    let progress = |r: &IterationRecord| {
        iterating();
        bar.set_message(format!(
            "load factor {:.4}  iteration {:>4}  residual ratio {:.3e}  open {}  slip {}",
            r.load_factor, r.iteration, r.ratio, r.open, r.slip
        ));
    };
    let result = if scene.harmonics == Harmonics::Auto {
        solve_scene_auto(
            scene,
            Some(&msh),
            scene.solver.harmonics_tolerance,
            scene.solver.max_harmonics,
            |model, u| profile_values(scene, &model.mesh, u),
            progress,
        )
    } else {
        // A one-shot run that stops writes its last iterate, marked.
        let written = std::cell::RefCell::new(None);
        let on_failure = |linear: &LinearRun, initial: Option<&InitialState>, e: &IterationError| {
            *written.borrow_mut() = Some(write_last_iterate(scene, linear, initial, e, &msh, out));
        };
        match solve_scene_with(scene, Some(&msh), progress, on_failure) {
            Ok(run) => Ok((scene.clone(), run)),
            Err(e) => {
                bar.finish_and_clear();
                return Err(match written.into_inner() {
                    Some(Ok(())) => anyhow::Error::new(e).context(format!(
                        "the last iterate is written to {} (marked \"converged\": false; not an equilibrium)",
                        out.display()
                    )),
                    Some(Err(w)) => {
                        anyhow::Error::new(e).context(format!("writing the last iterate failed too: {w:#}"))
                    }
                    None => e.into(),
                });
            }
        }
    };
    bar.finish_and_clear();
    let (solved, run): (Scene, Run) = result?;
    write_run(scene, &solved, &run, &msh, out)
}

/// The header of a finished run of `scene` (`solved`: the scene as run, its
/// harmonics chosen) and its solution folder at `out`.
pub fn write_run(scene: &Scene, solved: &Scene, run: &Run, msh: &Path, out: &Path) -> Result<SolutionHeader> {
    let mut header = solution_header(solved, &run.linear);
    header.initial = run.initial.as_ref().map(axijoint_solver::driver::initial_info);
    if let Some(outcome) = &run.outcome {
        header.extra = serde_json::json!({
            "iterations": outcome.history.len(),
            "sections_deg": outcome.field.sections.theta.iter().map(|t| t.to_degrees()).collect::<Vec<_>>(),
            "history": outcome.history,
            "released_spectrum": outcome.released_spectrum,
            "harmonic_check": run.harmonic_check,
            // Every nonlinear run says how its load was applied (a one-shot
            // run has no load path but is one).
            "loading": scene.solver.loading,
        });
    }
    if let Some(path) = &run.load_path {
        header.extra["load_path"] = serde_json::to_value(path)?;
        header.extra["load_factor"] = serde_json::json!(path.reached());
        if let Some(limit) = &path.limit {
            // Like every other output, `applied` is that of the last
            // converged step (the reactions balance `lambda F`, not `F`).
            let a = &mut header.applied;
            for v in a.force.iter_mut().chain(a.moment.iter_mut()) {
                *v *= limit.factor;
            }
            if limit.beyond_capacity {
                header.extra["limit_load_factor"] = serde_json::json!(limit.factor);
            }
            header.extra["complete"] = serde_json::json!(false);
            header.extra["note"] = serde_json::json!(format!(
                "the whole load was not reached: every result is that of the last converged load factor {:.6}",
                limit.factor
            ));
        }
    }
    if !run.auto_steps.is_empty() {
        header.extra["auto_harmonics"] = serde_json::json!({
            "chosen": solved.harmonics(),
            "tolerance": scene.solver.harmonics_tolerance,
            "steps": run.auto_steps,
        });
    }
    // Every joint's field, linear ones included (`t0 + k d`, stick).
    let springs: Vec<_> = run.linear.model.joints.iter().map(|j| j.springs).collect();
    let joints = run
        .joint_field(solved)?
        .map(|f| JointFieldFile::new(&run.linear.model.mesh, &springs, &f));
    write_solution(
        out,
        &header,
        &run.linear.displacements,
        run.initial.as_ref().map(|i| &i.displacements),
        msh,
        &run.linear.model.mesh,
        joints.as_ref(),
    )?;
    Ok(header)
}

/// Writes the last iterate of a one-shot run that stopped: the solution
/// folder with `extra.converged = false`, the error, the history and the
/// joint field of that iterate.
pub fn write_last_iterate(
    scene: &Scene,
    linear: &LinearRun,
    initial: Option<&InitialState>,
    e: &IterationError,
    msh: &Path,
    out: &Path,
) -> Result<()> {
    let Some(last) = e.last() else {
        return Ok(());
    };
    let mut header = solution_header(scene, linear);
    header.initial = initial.map(axijoint_solver::driver::initial_info);
    header.extra = serde_json::json!({
        "converged": false,
        "complete": false,
        "error": e.to_string(),
        "iterations": last.history.len(),
        "sections_deg": last.field.sections.theta.iter().map(|t| t.to_degrees()).collect::<Vec<_>>(),
        "history": last.history,
        "loading": scene.solver.loading,
        "note": "not converged: the displacements and joint states are those of the last iterate, not an equilibrium",
    });
    let springs: Vec<_> = linear.model.joints.iter().map(|j| j.springs).collect();
    let joints = JointFieldFile::new(&linear.model.mesh, &springs, &last.field);
    write_solution(
        out,
        &header,
        &linear.displacements,
        initial.map(|i| &i.displacements),
        msh,
        &linear.model.mesh,
        Some(&joints),
    )?;
    Ok(())
}

/// The folder of the comparison run without joints, inside a solution folder.
pub const WITHOUT_JOINTS: &str = "without_joints";

/// `scene` without its joints (the bodies bonded): the comparison of
/// `axijoint run`, solved into [`WITHOUT_JOINTS`].
pub fn without_joints(scene: &Scene) -> Scene {
    let mut bonded = scene.clone();
    bonded.joints.clear();
    bonded.title = format!("{} (without joints)", scene.title);
    bonded
}

pub fn print_summary(path: &Path, scene: &Scene, header: &SolutionHeader, out: &Path) {
    crate::say!("{}: {}", path.display(), scene.title);
    crate::say!(
        "  {} nodes, {} elements, {} unknowns per harmonic, harmonics 0..={}",
        header.mesh.nodes,
        header.mesh.elements,
        header.dofs_per_harmonic,
        header.harmonics.last().copied().unwrap_or(0)
    );
    let t = &header.timings;
    crate::say!(
        "  time: setup {:.3} s, assembly + factorization {:.3} s, solve {:.3} s",
        t.setup,
        t.factorize,
        t.solve
    );
    if let Some(i) = &header.initial {
        let b = &i.balance;
        crate::say!(
            "  initial phase: weight {:.6e} {f}, out-of-balance {:.3e} {f} ({:.2e} of the largest nodal force), {} iterations, max |u| {:.6e} {l} (displacements below are from its end)",
            b.weight,
            b.max_force,
            b.relative,
            i.iterations,
            i.max_displacement,
            f = scene.units.force,
            l = scene.units.length,
        );
        if b.relative > 0.01 {
            crate::say!(
                "  note: the initial stresses are not in balance with the weight and supports (above 1 %); the initial phase moved the model to balance them"
            );
        }
    }
    if let Some(h) = header.extra.get("history").and_then(|h| h.as_array()) {
        if let Some(last) = h.last() {
            crate::say!(
                "  iteration: {} iterations, residual ratio {:.3e} (epsilon {:.1e}); open {}, slip {}, stick {} point-sections",
                h.len(),
                last["ratio"].as_f64().unwrap_or(f64::NAN),
                scene.solver.epsilon,
                last["open"],
                last["slip"],
                last["stick"]
            );
        }
    }
    if let Some(steps) = header.extra["load_path"]["steps"].as_array() {
        let solves: u64 = steps.iter().filter_map(|s| s["solves"].as_u64()).sum();
        let cutbacks: u64 = steps.iter().filter_map(|s| s["cutbacks"].as_u64()).sum();
        crate::say!(
            "  load path: {} converged steps to load factor {:.4} ({} solves, {} cut-backs)",
            steps.len(),
            header.extra["load_factor"].as_f64().unwrap_or(f64::NAN),
            solves,
            cutbacks
        );
    }
    if let Some(limit) = header.extra["load_path"].get("limit").filter(|l| !l.is_null()) {
        let what = if limit["beyond_capacity"].as_bool() == Some(true) {
            "LIMIT LOAD FACTOR"
        } else {
            "STOPPED (not a limit load) at load factor"
        };
        crate::say!(
            "  {what} {:.4}: the load factor {:.4} failed ({}); every result below is that of the last converged step",
            limit["factor"].as_f64().unwrap_or(f64::NAN),
            limit["failed_at"].as_f64().unwrap_or(f64::NAN),
            limit["reason"].as_str().unwrap_or("")
        );
    }
    if let Some(c) = header.extra.get("harmonic_check").filter(|c| !c.is_null()) {
        match (c["face_change"].as_f64(), c["area_change"].as_f64()) {
            (Some(f), Some(a)) => crate::say!(
                "  harmonics: 0..={} against 0..={}: {} changes {f:.2e}, joint open/slip area {a:.2e} (relative)",
                c["m"],
                c["m_half"],
                if c["note"].is_null() {
                    "loaded-face displacement"
                } else {
                    "the displacement field"
                }
            ),
            _ => crate::say!(
                "  harmonics: no comparison with 0..={}: that run did not converge (reason in solution.json, extra.harmonic_check)",
                c["m_half"]
            ),
        }
    }
    if let Some(a) = header.extra.get("auto_harmonics") {
        let steps: Vec<String> = a["steps"]
            .as_array()
            .map(|v| {
                v.iter()
                    .map(|s| match s["change"].as_f64() {
                        Some(c) => format!("M={} ({:.1e})", s["m"], c),
                        None => format!("M={}", s["m"]),
                    })
                    .collect()
            })
            .unwrap_or_default();
        crate::say!(
            "  harmonics chosen automatically: M = {} (profile change < {} ; steps {})",
            a["chosen"],
            a["tolerance"],
            steps.join(", ")
        );
    }
    let u = &scene.units;
    for (face, d) in &header.loaded_faces {
        crate::say!(
            "  {face}: mean displacement (ux, uy, uz) = ({:.6e}, {:.6e}, {:.6e}) {}",
            d[0],
            d[1],
            d[2],
            u.length
        );
    }
    crate::say!("  max |u| = {:.6e} {}", header.max_displacement, u.length);
    let a = &header.applied;
    crate::say!(
        "  applied   F = ({:+.6e}, {:+.6e}, {:+.6e})  M = ({:+.6e}, {:+.6e}, {:+.6e})",
        a.force[0],
        a.force[1],
        a.force[2],
        a.moment[0],
        a.moment[1],
        a.moment[2]
    );
    for r in &header.reactions {
        crate::say!(
            "  reaction  F = ({:+.6e}, {:+.6e}, {:+.6e})  M = ({:+.6e}, {:+.6e}, {:+.6e})  on {}",
            r.force[0],
            r.force[1],
            r.force[2],
            r.moment[0],
            r.moment[1],
            r.moment[2],
            r.on
        );
    }
    crate::say!("  written to {}", out.display());
}

/// The load could not be raised to the whole load: every output was
/// written for the last converged load factor.
#[derive(Debug, thiserror::Error)]
#[error("{}", self.message())]
pub struct LimitReached {
    pub factor: f64,
    pub failed_at: f64,
    /// The failed step found no equilibrium (else it stopped for another reason).
    pub beyond_capacity: bool,
    pub reason: String,
    pub dir: String,
}

impl LimitReached {
    fn message(&self) -> String {
        if self.beyond_capacity {
            format!(
                "limit load factor {:.4}: the scene's load exceeds what the joints can carry (the load factor {:.4} found no equilibrium); the outputs in {} are those of the load factor {:.4}",
                self.factor, self.failed_at, self.dir, self.factor
            )
        } else {
            format!(
                "the run stopped at the load factor {:.4}, short of the whole load, for a reason that does not show the load exceeds the joints' capacity: {}; the outputs in {} are those of the load factor {:.4}",
                self.factor, self.reason, self.dir, self.factor
            )
        }
    }
}

/// `Err(LimitReached)` when the header says the whole load was not reached.
pub fn check_limit(header: &SolutionHeader, out: &Path) -> Result<()> {
    let limit = &header.extra["load_path"]["limit"];
    match (limit["factor"].as_f64(), limit["failed_at"].as_f64()) {
        (Some(factor), Some(failed_at)) => Err(LimitReached {
            factor,
            failed_at,
            beyond_capacity: limit["beyond_capacity"].as_bool() == Some(true),
            reason: limit["reason"].as_str().unwrap_or_default().to_string(),
            dir: out.display().to_string(),
        }
        .into()),
        _ => Ok(()),
    }
}

pub fn run_solve(args: &SolveArgs) -> Result<()> {
    let scene = load_scene(&args.scene, &args.common)?;
    if !scene.load_cases.is_empty() {
        return crate::cases_cmd::run(&args.scene, &scene, &args.common, false);
    }
    let (_, out, header) = solve_and_write(&args.scene, &args.common)?;
    check_limit(&header, &out)
}

pub fn run_run(args: &RunArgs) -> Result<()> {
    let scene = match &args.scene {
        Some(s) => s.clone(),
        None => default_scene()?,
    };
    let loaded = load_scene(&scene, &args.common)?;
    if !loaded.load_cases.is_empty() {
        return crate::cases_cmd::run(&scene, &loaded, &args.common, true);
    }
    // The paper's comparison (its dashed lines): the same scene bonded,
    // solved on a thread of its own into a folder beside the output and
    // moved in after. It starts once the scene's own factors are made (its
    // first iteration record): from there the scene's solve keeps about one
    // core busy, before it both compete for the cores.
    let bonded =
        (!loaded.joints.is_empty() && loaded.outputs.compare_without_joints).then(|| without_joints(&loaded));
    let side = match &bonded {
        Some(_) => {
            let out = args
                .common
                .output
                .clone()
                .unwrap_or_else(|| default_output(&scene));
            let parent = match out.parent() {
                Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
                _ => PathBuf::from("."),
            };
            std::fs::create_dir_all(&parent)?;
            Some(
                tempfile::Builder::new()
                    .prefix(".without_joints")
                    .tempdir_in(&parent)?,
            )
        }
        None => None,
    };
    let (solved, comparison) = std::thread::scope(|s| {
        // Owned by this body, so that the waiting thread is let go even if
        // the solve unwinds.
        let (go, ready) = std::sync::mpsc::channel::<()>();
        let once = std::sync::Once::new();
        let start_comparison = || {
            once.call_once(|| {
                let _ = go.send(());
            })
        };
        let comparison = bonded.as_ref().zip(side.as_ref()).map(|(b, side)| {
            s.spawn(move || {
                let _ = ready.recv();
                solve_to(b, &side.path().join(WITHOUT_JOINTS), true)
            })
        });
        let solved = solve_and_write_then(&scene, &args.common, &start_comparison);
        start_comparison();
        let comparison = comparison.map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)));
        (solved, comparison)
    });
    let (_, out, header) = match solved {
        Ok(v) => v,
        Err(e) => {
            // A stopped one-shot run wrote its last iterate: report it too.
            let out = args
                .common
                .output
                .clone()
                .unwrap_or_else(|| default_output(&scene));
            if read_solution(&out).is_ok_and(|s| s.header.extra["converged"] == serde_json::json!(false)) {
                crate::report_cmd::report(&out, &[])?;
            }
            return Err(e);
        }
    };
    if let (Some(comparison), Some(side)) = (comparison, &side) {
        comparison?;
        let dir = out.join(WITHOUT_JOINTS);
        std::fs::rename(side.path().join(WITHOUT_JOINTS), &dir)?;
        crate::say!("  comparison without joints: {}", dir.display());
    }
    crate::report_cmd::report(&out, &[])?;
    check_limit(&header, &out)
}
