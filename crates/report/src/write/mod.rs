//! [`write_report`]: every output of a solution folder, each made by its
//! own module (`cuts`, `joints`, `convergence`, `load_path`, `members`,
//! `views`) from
//! what they share (`context`), the outputs written in parallel.

mod context;
mod convergence;
mod cuts;
mod joints;
mod load_path;
mod members;
mod views;

pub use context::fmt_angle;

use crate::error::ReportError;
use crate::estimate::{self, Estimate};
use crate::field::{Field, Initial, Locator};
use crate::record::{history, load_path, materials};
use crate::recovery::PlasticStress;
use axijoint_solver::iteration::IterationRecord;
use axijoint_solver::results::{read_joint_field, read_plastic_field, SavedSolution};
use context::Ctx;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Files written by [`write_report`], relative to the solution folder.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Written {
    /// Paths written.
    pub files: Vec<PathBuf>,
    /// The estimated error of every cut profile: `(cut, theta in degrees,
    /// fraction of the profile's max |stress|)` ([`estimate::cut_error`]).
    pub estimated_error: Vec<(String, f64, f64)>,
    /// The estimated relative error of the whole field in the energy norm.
    pub energy_error: f64,
}

/// One output of the report: writes its files and returns their names.
type Task<'a> = Box<dyn FnOnce() -> Result<Vec<String>, ReportError> + Send + 'a>;

/// Writes every report output of a saved solution into `dir` (the solution
/// folder itself), as the scene's `outputs` asks: cut, joint and
/// convergence CSVs; plots of the cuts (with `companion`, the run without
/// joints, dashed), of the joint states and of the convergence (with the
/// `compare` runs' histories on the same axis, this run's labelled `label`,
/// default its scene's title), PNG copies with `outputs.png`; the revolved
/// `.vtu` and the gmsh view. The outputs are independent and written in
/// parallel (rayon), the error estimate alongside; the file list keeps the
/// order above.
pub fn write_report(
    dir: &Path,
    saved: &SavedSolution,
    companion: Option<&SavedSolution>,
    label: Option<&str>,
    compare: &[(String, Vec<IterationRecord>)],
) -> Result<Written, ReportError> {
    let ctx = Ctx::new(dir, saved);
    let (scene, outputs) = (ctx.scene, ctx.outputs);
    let mats = materials(saved)?;
    let field = Field {
        mesh: &saved.mesh,
        materials: &mats,
        u: &saved.displacements,
        initial: Initial::of(saved),
    };
    // The initial state alone (its own cut files).
    let no_displacement = axijoint_solver::solution::Displacements {
        harmonics: Vec::new(),
    };
    let initial_field = field
        .initial
        .as_ref()
        .filter(|_| saved.header.initial.is_some())
        .map(|init| Field {
            mesh: &saved.mesh,
            materials: &mats,
            u: init.u.unwrap_or(&no_displacement),
            initial: Some(Initial {
                stress: init.stress.clone(),
                u: None,
                water: init.water,
            }),
        });
    let locator = Locator::new(&saved.mesh);
    let joints = read_joint_field(dir).map_err(|e| ReportError::Input(e.to_string()))?;
    let plastic = read_plastic_field(dir).map_err(|e| ReportError::Input(e.to_string()))?;
    let recovery = plastic
        .as_ref()
        .map(|pf| PlasticStress::new(&saved.mesh, pf))
        .transpose()
        .map_err(|e| ReportError::Input(format!("{}: plastic field: {e}", dir.display())))?;
    let history = history(saved);
    let path = load_path(saved);
    // One estimate for the cut errors and the `.vtu`'s cell errors.
    let estimate = OnceLock::new();
    let mut tasks: Vec<Task> = Vec::new();
    if let Some(jf) = &joints {
        for j in &saved.mesh.joints {
            tasks.push(Box::new(move || joints::write(ctx, jf, j)));
        }
    }
    if let Some(history) = &history {
        tasks.push(Box::new(move || convergence::write(ctx, history, label, compare)));
    }
    if let Some(path) = &path {
        tasks.push(Box::new(move || load_path::write(ctx, path)));
    }
    for member in &saved.header.members {
        tasks.push(Box::new(move || members::write(ctx, member, path)));
    }
    let views = tasks.len();
    if outputs.vtu {
        let (field, joints, plastic, estimate) = (&field, joints.as_ref(), plastic.as_ref(), &estimate);
        tasks.push(Box::new(move || {
            views::write_vtu(ctx, field, joints, plastic, estimate)
        }));
    }
    if outputs.gmsh_views {
        let (field, recovery) = (&field, recovery.as_ref());
        tasks.push(Box::new(move || views::write_gmsh(ctx, field, recovery)));
    }
    let cuts = cuts::Cuts {
        ctx,
        field: &field,
        initial: initial_field.as_ref(),
        locator: &locator,
        plastic: recovery.as_ref(),
    };
    let estimated = || {
        let estimate = estimate.get_or_init(|| Estimate::new(&field));
        (
            estimate::cut_errors(&field, estimate, &locator, &scene.cuts),
            estimate.relative(),
        )
    };
    run(tasks, views, || cuts.write_all(companion), estimated)
}

/// Runs the outputs: the revolved views (tasks from `views` on) take
/// longest and are spawned first, then the cuts, the other tasks, and the
/// estimate's cut errors last (the `.vtu` makes the estimate); every worker
/// takes the oldest task left. The files: the cuts', then each task's in
/// order.
fn run<'a>(
    tasks: Vec<Task<'a>>,
    views: usize,
    cuts: impl FnOnce() -> Result<Vec<String>, ReportError> + Send,
    estimated: impl FnOnce() -> (Vec<(String, f64, f64)>, f64) + Send,
) -> Result<Written, ReportError> {
    let slots: Vec<OnceLock<Result<Vec<String>, ReportError>>> =
        tasks.iter().map(|_| OnceLock::new()).collect();
    let (cut_files, estimates) = (OnceLock::new(), OnceLock::new());
    rayon::scope_fifo(|s| {
        let mut tasks: Vec<Option<Task>> = tasks.into_iter().map(Some).collect();
        let mut spawn = |k: usize| {
            if let Some(t) = tasks[k].take() {
                let slot = &slots[k];
                s.spawn_fifo(move |_| {
                    let _ = slot.set(t());
                });
            }
        };
        (views..slots.len()).for_each(&mut spawn);
        let cut_files = &cut_files;
        s.spawn_fifo(move |_| {
            let _ = cut_files.set(cuts());
        });
        (0..views).for_each(spawn);
        let estimates = &estimates;
        s.spawn_fifo(move |_| {
            let _ = estimates.set(estimated());
        });
    });
    let cut_files = cut_files.into_inner().expect("the cuts were written")?;
    let (estimated_error, energy_error) = estimates.into_inner().expect("the estimate ran");
    let mut written = Written {
        files: cut_files.into_iter().map(PathBuf::from).collect(),
        estimated_error,
        energy_error,
    };
    for slot in slots {
        let files = slot.into_inner().expect("every task ran")?;
        written.files.extend(files.into_iter().map(PathBuf::from));
    }
    Ok(written)
}
