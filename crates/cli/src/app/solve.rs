//! One scene solved into a solution folder: the solve with a progress
//! display, the folder of a finished run or of a stopped run's last
//! iterate, and the check that the whole load was reached.

use super::console::{progress_bar, progress_message};
use anyhow::{Context, Result};
use axijoint_report::cuts::profile_values;
use axijoint_solver::error::SolverError;
use axijoint_solver::iteration::IterationError;
use axijoint_solver::results::{write_solution, JointFieldFile, PlasticFieldFile, SolutionHeader};
use axijoint_solver::run::{
    last_iterate_header, solution_header, solve_scene, solve_scene_auto, Run, Stopped,
};
use axijoint_solver::scene::{Harmonics, Scene};
use std::path::{Path, PathBuf};

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

/// [`solve_to`], calling `iterating` at every iteration record (the
/// factors are made: the rest of the solve keeps about one core busy). A
/// one-shot run that stops writes its last iterate, marked, and fails.
pub fn solve_to_then(scene: &Scene, out: &Path, quiet: bool, iterating: &dyn Fn()) -> Result<SolutionHeader> {
    let mut scene = scene.clone();
    scene.output = Some(out.to_path_buf());
    let scene = &scene;
    let tmp = super::stale::tempdir().context("creating a temporary folder")?;
    let msh = solved_msh(scene, tmp.path());
    let bar = progress_bar(quiet);
    let progress = |r: &_| {
        iterating();
        bar.set_message(progress_message(r));
    };
    let result = if scene.harmonics == Harmonics::Auto {
        solve_scene_auto(
            scene,
            Some(&msh),
            scene.solver.harmonics_tolerance,
            scene.solver.max_harmonics,
            |model, o| profile_values(scene, &model.mesh, &o.displacements, o.body.as_ref()),
            progress,
        )
    } else {
        solve_scene(scene, Some(&msh), progress).map(|run| (scene.clone(), run))
    };
    bar.finish_and_clear();
    match result {
        Ok((solved, run)) => {
            // No more solves: the factors' rest on disk is freed behind the outputs.
            run.problem.model.release_disk();
            let header = write_run(&solved, &run, &msh, out)?;
            write_stage_ends(&solved, &run, &msh, out)?;
            Ok(header)
        }
        Err(stopped) => Err(write_stopped(scene, *stopped, &msh, out)),
    }
}

/// The folder of the states at the end of each leg of a staged run
/// (`outputs.stages: "each"`), inside the output.
pub const STAGES_DIR: &str = "stages";

/// The folder of a leg's end: `NNN-stage` or `NNN-stage-cC-lL`.
fn stage_folder(mark: &axijoint_solver::results::StageMark) -> String {
    if mark.cycle == 0 {
        format!("{:03}-{}", mark.leg, mark.stage)
    } else {
        format!("{:03}-{}-c{}-l{}", mark.leg, mark.stage, mark.cycle, mark.level)
    }
}

/// With `outputs.stages: "each"`: a solution folder for the end of every
/// leg but the last (the run's own), in `out/stages/`.
fn write_stage_ends(solved: &Scene, run: &Run, msh: &Path, out: &Path) -> Result<()> {
    if run.stage_ends.is_empty() {
        return Ok(());
    }
    let dir = out.join(STAGES_DIR);
    std::fs::create_dir_all(&dir).with_context(|| format!("{}: cannot make the folder", dir.display()))?;
    let mesh = &run.problem.model.mesh;
    for s in &run.stage_ends {
        let displacements = s.outcome.displacements.clone();
        let state = Run {
            problem: run.problem.clone(),
            applied: axijoint_solver::loads::load_resultants(&s.loads, mesh, 0.0),
            reactions: axijoint_solver::run::reactions(solved, &run.problem.model, &s.loads, &displacements),
            loads: s.loads.clone(),
            displacements,
            timings: run.timings.clone(),
            outcome: Some(s.outcome.clone()),
            harmonic_check: None,
            auto_steps: Vec::new(),
            load_path: None,
            initial: run.initial.clone(),
            stage_ends: Vec::new(),
        };
        write_run(solved, &state, msh, &dir.join(stage_folder(&s.mark)))?;
    }
    Ok(())
}

/// The error of a stopped run, after writing its last iterate (if any) to
/// `out`.
pub fn write_stopped(scene: &Scene, stopped: Stopped, msh: &Path, out: &Path) -> anyhow::Error {
    let Stopped { error, last } = stopped;
    let (Some(last), SolverError::Iteration(e)) = (last, &error) else {
        return error.into();
    };
    match write_last_iterate(scene, &last, e, msh, out) {
        Ok(()) => anyhow::Error::new(error).context(format!(
            "the last iterate is written to {} (marked \"converged\": false; not an equilibrium)",
            out.display()
        )),
        Err(w) => anyhow::Error::new(error).context(format!("writing the last iterate failed too: {w:#}")),
    }
}

/// Writes the solution folder of a finished run of `solved` (the scene as
/// run, its harmonics chosen) at `out`; returns its header.
pub fn write_run(solved: &Scene, run: &Run, msh: &Path, out: &Path) -> Result<SolutionHeader> {
    let header = solution_header(solved, run);
    // Every joint's field, linear ones included (`t0 + k d`, stick).
    let model = &run.problem.model;
    let springs: Vec<_> = model.joints.iter().map(|j| j.springs).collect();
    let joints = run
        .joint_field(solved)?
        .map(|f| JointFieldFile::new(&model.mesh, &springs, &f));
    let plastic = run
        .outcome
        .as_ref()
        .and_then(|o| o.body.as_ref())
        .map(|b| PlasticFieldFile::new(&model.mesh, b, solved.water.as_ref()));
    write_solution(
        out,
        &header,
        &run.displacements,
        run.initial.as_ref().map(|i| &i.displacements),
        msh,
        &model.mesh,
        joints.as_ref(),
        plastic.as_ref(),
    )?;
    Ok(header)
}

/// Writes the last iterate `last` of a one-shot run that stopped with `e`:
/// the solution folder marked `"converged": false`, with the error, the
/// history, the joint field and the plastic bodies' field of that iterate.
pub fn write_last_iterate(
    scene: &Scene,
    last: &Run,
    e: &IterationError,
    msh: &Path,
    out: &Path,
) -> Result<()> {
    let Some(outcome) = &last.outcome else {
        return Ok(());
    };
    let header = last_iterate_header(scene, last, e);
    let model = &last.problem.model;
    let springs: Vec<_> = model.joints.iter().map(|j| j.springs).collect();
    let joints = JointFieldFile::new(&model.mesh, &springs, &outcome.field);
    let plastic = outcome
        .body
        .as_ref()
        .map(|b| PlasticFieldFile::new(&model.mesh, b, scene.water.as_ref()));
    write_solution(
        out,
        &header,
        &last.displacements,
        last.initial.as_ref().map(|i| &i.displacements),
        msh,
        &model.mesh,
        Some(&joints),
        plastic.as_ref(),
    )?;
    Ok(())
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
    /// With stages: the stage it stopped in (the factor is within it).
    pub stage: Option<String>,
    /// What carries the load: "the joints", "the yielding soil" or both.
    pub carriers: &'static str,
}

impl LimitReached {
    fn message(&self) -> String {
        let of = self.stage.as_ref().map_or(String::new(), |s| format!(" of {s}"));
        if self.beyond_capacity {
            format!(
                "limit load factor {:.4}{of}: the scene's load exceeds what {} can carry (the load factor {:.4} found no equilibrium); the outputs in {} are those of the load factor {:.4}",
                self.factor, self.carriers, self.failed_at, self.dir, self.factor
            )
        } else {
            format!(
                "the run stopped at the load factor {:.4}{of}, short of the whole load, for a reason that does not show the load exceeds what {} can carry: {}; the outputs in {} are those of the load factor {:.4}",
                self.factor, self.carriers, self.reason, self.dir, self.factor
            )
        }
    }
}

/// What carries a scene's load beyond its elastic part: its nonlinear
/// joints, its plastic bodies, or both.
fn carriers(scene: &Scene) -> &'static str {
    let plastic = scene.materials.values().any(|m| m.plasticity.is_some());
    match (scene.has_nonlinear_joints(), plastic) {
        (true, true) => "the joints and the yielding soil",
        (false, true) => "the yielding soil",
        _ => "the joints",
    }
}

/// `Err(LimitReached)` when the header says the whole load was not reached.
pub fn check_limit(header: &SolutionHeader, out: &Path) -> Result<()> {
    match header.record.as_ref().and_then(|r| r.limit()) {
        Some(limit) => Err(LimitReached {
            factor: limit.factor,
            failed_at: limit.failed_at,
            beyond_capacity: limit.beyond_capacity,
            reason: limit.reason.clone(),
            dir: out.display().to_string(),
            stage: header
                .record
                .as_ref()
                .and_then(|r| r.load_path.as_ref())
                .and_then(|p| p.stopped_in.as_ref())
                .map(|m| m.label()),
            carriers: carriers(&header.scene),
        }
        .into()),
        None => Ok(()),
    }
}
