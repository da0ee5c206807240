//! The application: what `axijoint solve` and `axijoint run` do, shared by
//! the binary and the Python package.
//!
//! ```text
//! console.rs  progress display, the summary of a solution folder
//! solve.rs    one scene into a solution folder (or its last iterate)
//! adapt.rs    mesh.adapt: solve, estimate, re-mesh, until the target
//! report.rs   every output of a solution folder and summary.json
//! cases.rs    load cases: one folder per case and cases.json
//! stale.rs    the leftovers of killed runs (pid-tagged temporary folders) removed
//! mod.rs      run: the scene or its cases, the comparison without joints, the report
//! ```

pub mod adapt;
pub mod cases;
pub mod console;
pub mod report;
pub mod solve;
mod stale;

use anyhow::{Context, Result};
use axijoint_solver::results::{read_solution, SolutionHeader};
use axijoint_solver::scene::Scene;
use solve::{check_limit, solve_to, solve_to_then, without_joints, WITHOUT_JOINTS};
use std::path::{Path, PathBuf};

/// What a run writes and prints.
#[derive(Clone, Debug)]
pub struct Options {
    /// The output folder.
    pub output: PathBuf,
    /// No progress display, no summary of each load case.
    pub quiet: bool,
    /// Solve the scene without its joints into `output/without_joints`
    /// (when it has joints).
    pub compare: bool,
    /// Write the report and `summary.json`.
    pub report: bool,
    /// Print the summary of each solution folder and its report on the
    /// console (stdout).
    pub print: bool,
}

/// Solves `scene` (read from `path`) into `options.output`: its load cases
/// if it has some, else the scene (adaptively with `mesh.adapt`), with the
/// comparison without joints and the report as `options` ask. Fails, after
/// writing every output, when the whole load was not reached.
pub fn run(path: &Path, scene: &Scene, options: &Options) -> Result<()> {
    stale::clean_for(&options.output);
    if !scene.load_cases.is_empty() {
        return cases::run_cases(path, scene, options);
    }
    let out = &options.output;
    let bonded = (options.compare && !scene.joints.is_empty()).then(|| without_joints(scene));
    let (solved, comparison) = match &bonded {
        Some(bonded) => with_comparison(path, scene, bonded, options)?,
        None => (solve_and_print(path, scene, options, &|| {}), None),
    };
    let header = match solved {
        Ok(header) => header,
        Err(e) => {
            // A stopped one-shot run wrote its last iterate: report it too.
            let last = read_solution(out).is_ok_and(|s| s.header.record.is_some_and(|r| !r.converged()));
            if options.report && last {
                report::write(out, options.print)?;
            }
            return Err(e);
        }
    };
    if let Some(side) = comparison {
        let dir = out.join(WITHOUT_JOINTS);
        std::fs::rename(side.path().join(WITHOUT_JOINTS), &dir)?;
        if options.report {
            report::write_comparison_summary(&dir)?;
        }
        if options.print {
            crate::say!("  comparison without joints: {}", dir.display());
        }
    }
    if options.report {
        report::write(out, options.print)?;
        // The states at the end of each leg (`outputs.stages: "each"`).
        let stages = out.join(solve::STAGES_DIR);
        if let Ok(entries) = std::fs::read_dir(&stages) {
            let mut dirs: Vec<_> = entries
                .flatten()
                .map(|e| e.path())
                .filter(|p| p.is_dir())
                .collect();
            dirs.sort();
            for dir in dirs {
                report::write(&dir, false)?;
            }
        }
    }
    check_limit(&header, out)
}

/// Solves the scene (adaptively with `mesh.adapt`) and prints its summary.
fn solve_and_print(
    path: &Path,
    scene: &Scene,
    options: &Options,
    iterating: &dyn Fn(),
) -> Result<SolutionHeader> {
    let out = &options.output;
    let header = if scene.mesh.adapt.is_some() {
        adapt::solve_adaptive(scene, out, options.quiet, iterating)?
    } else {
        solve_to_then(scene, out, options.quiet, iterating)?
    };
    if options.print {
        console::print_summary(path, scene, &header, out);
    }
    Ok(header)
}

/// The paper's comparison (its dashed lines): `bonded` solved on a thread
/// of its own into a folder beside the output, to be moved in after. It
/// starts once the scene's own factors are made (its first iteration
/// record): from there the scene's solve keeps about one core busy, before
/// it both compete for the cores. Returns the scene's result and, when the
/// comparison was solved, its folder.
fn with_comparison(
    path: &Path,
    scene: &Scene,
    bonded: &Scene,
    options: &Options,
) -> Result<(Result<SolutionHeader>, Option<tempfile::TempDir>)> {
    let parent = axijoint_solver::results::output_parent(&options.output)?;
    let side = tempfile::Builder::new()
        .prefix(&stale::tagged(stale::WITHOUT_JOINTS_PREFIX))
        .tempdir_in(&parent)
        .with_context(|| format!("creating a folder in {}", parent.display()))?;
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
        let target = side.path().join(WITHOUT_JOINTS);
        let comparison = s.spawn(move || {
            let _ = ready.recv();
            solve_to(bonded, &target, true)
        });
        let solved = solve_and_print(path, scene, options, &start_comparison);
        start_comparison();
        let comparison = comparison.join().unwrap_or_else(|p| std::panic::resume_unwind(p));
        (solved, comparison)
    });
    if solved.is_ok() {
        comparison?;
    }
    Ok((solved, Some(side)))
}
