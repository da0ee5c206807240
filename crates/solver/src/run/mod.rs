//! From a scene to a solved run: the entry points.
//!
//! ```text
//! scene -> model (model.rs) -> factors (factors.rs) -> elastic run (elastic.rs)
//!       -> initial phase (initial.rs) -> iteration (nonlinear.rs, check.rs)
//!       -> measures (measures.rs) -> Run -> warnings (plausible.rs)
//!       -> header and record (header.rs)
//! ```
//!
//! [`solve_scene`] solves a scene's loads, [`solve_cases`] each of its load
//! cases on one set of factors, [`solve_scene_auto`] chooses M. Each returns
//! values: a [`Run`], or a [`Stopped`] run with its error and, when a
//! one-shot iteration stopped, its last iterate.

mod auto;
mod cases;
mod check;
mod elastic;
mod factors;
mod header;
mod initial;
mod measures;
mod model;
mod motion;
mod nonlinear;
mod plausible;
mod sections;
mod stages;
mod start;

pub use auto::solve_scene_auto;
pub use cases::{solve_cases, Cases};
pub use elastic::{solve_linear, Problem};
pub use factors::{
    factor_memory_budget, least_factor_memory, output_bytes, solve_loads, FACTOR_MEMORY_ENV, MEMORY_ENV,
};
pub use header::{last_iterate_header, record, solution_header};
pub use initial::{initial_phase, InitialState};
pub use measures::{
    face_displacement, joint_relative_displacements, linear_joint_field, max_displacement, reactions,
};
pub use model::{
    build_model, iteration_settings, joint_springs, mesh_scene, support_flags, support_nodes,
    REFERENCE_STIFFNESS,
};
pub use plausible::{
    warnings, LARGE_DISPLACEMENT, MANY_HARMONICS, MODULUS_CONTRAST, SAME_AREAS, SAME_FACES, WEIGHT_STRAIN,
};
pub use sections::scene_sections;

use crate::error::SolverError;
use crate::iteration::{IterationRecord, JointField, Outcome};
use crate::loads::{load_resultants, HarmonicLoads, Resultants};
use crate::results::{AutoStep, HarmonicCheck, LoadPath};
use crate::scene::Scene;
use crate::solution::{Displacements, SupportReaction, Timings};
use elastic::ElasticLoad;
use std::borrow::Cow;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// A solved load on a problem.
pub struct Run {
    /// The factored model (shared by the load cases of a scene).
    pub problem: Arc<Problem>,
    /// Loads per harmonic (the whole load: `lambda` of a load path scales them).
    pub loads: Vec<HarmonicLoads>,
    /// Applied load resultants about the origin (of the whole load).
    pub applied: Resultants,
    /// The solution's displacement amplitudes (the last iterate's, in a
    /// [`Stopped`] run).
    pub displacements: Displacements,
    /// Reactions per support (none for a last iterate: not an equilibrium).
    pub reactions: Vec<SupportReaction>,
    /// Times.
    pub timings: Timings,
    /// The iteration, if a joint is nonlinear.
    pub outcome: Option<Outcome>,
    /// Key results with harmonics 0..=M/2 against 0..=M (nonlinear, M >= 2).
    pub harmonic_check: Option<HarmonicCheck>,
    /// The steps of an automatic choice of M.
    pub auto_steps: Vec<AutoStep>,
    /// The load path of a stepped run (`solver.loading` not `"one_shot"`).
    pub load_path: Option<LoadPath>,
    /// The initial phase, if the scene has one; the displacements of the
    /// run are relative to its end.
    pub initial: Option<InitialState>,
    /// With `outputs.stages: "each"`: the state at the end of every leg
    /// but the last (the run's own).
    pub stage_ends: Vec<StageSnapshot>,
}

/// The state at the end of a leg of a staged run ([`Run::stage_ends`]).
#[derive(Clone, Debug)]
pub struct StageSnapshot {
    /// The leg.
    pub mark: crate::results::StageMark,
    /// The loads applied there, every harmonic of the run.
    pub loads: Vec<HarmonicLoads>,
    /// The solution there (whole displacements).
    pub outcome: Outcome,
}

impl Run {
    /// The elastic run of `load` on `problem` (no reactions yet).
    fn new(problem: Arc<Problem>, load: ElasticLoad) -> Run {
        let applied = load_resultants(&load.loads, &problem.model.mesh, 0.0);
        Run {
            problem,
            loads: load.loads,
            applied,
            displacements: load.u,
            reactions: Vec::new(),
            timings: load.timings,
            outcome: None,
            harmonic_check: None,
            auto_steps: Vec::new(),
            load_path: None,
            initial: None,
            stage_ends: Vec::new(),
        }
    }

    /// The joint field of the run: the iteration's, or when every joint is
    /// linear [`linear_joint_field`] of the displacements on the sections
    /// of `scene` (the solved scene); `None` without joints.
    pub fn joint_field(&self, scene: &Scene) -> Result<Option<Cow<'_, JointField>>, SolverError> {
        if let Some(outcome) = &self.outcome {
            return Ok(Some(Cow::Borrowed(&outcome.field)));
        }
        let model = &self.problem.model;
        if model.mesh.joints.is_empty() {
            return Ok(None);
        }
        let sections = scene_sections(scene, model, &self.loads)?;
        let t0 = self.initial.as_ref().map(|i| i.traction.as_slice());
        Ok(Some(Cow::Owned(linear_joint_field(
            model,
            &self.displacements,
            &sections,
            t0,
        ))))
    }
}

/// A run that stopped without a solution: why, and, when a one-shot
/// iteration stopped, its last iterate (not an equilibrium: no reactions).
pub struct Stopped {
    /// Why it stopped.
    pub error: SolverError,
    /// The last iterate.
    pub last: Option<Box<Run>>,
}

impl From<SolverError> for Box<Stopped> {
    fn from(error: SolverError) -> Self {
        Box::new(Stopped { error, last: None })
    }
}

impl std::fmt::Debug for Stopped {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Stopped")
            .field("error", &self.error)
            .field("last_iterate", &self.last.is_some())
            .finish()
    }
}

impl std::fmt::Display for Stopped {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.error.fmt(f)
    }
}

/// Transparent: the error of [`Stopped::error`].
impl std::error::Error for Stopped {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.error.source()
    }
}

/// Solves a scene: the elastic run, the initial phase if any, then the
/// stress-transfer iteration when a joint can open or slip, and the M/2
/// check. `progress` sees each iteration.
pub fn solve_scene(
    scene: &Scene,
    keep_msh: Option<&Path>,
    mut progress: impl FnMut(&IterationRecord),
) -> Result<Run, Box<Stopped>> {
    let e = elastic::elastic(scene, keep_msh, scene.is_nonlinear())?;
    let t = Instant::now();
    let initial = if scene.has_initial_phase() {
        Some(initial_phase(scene, &e.problem, &e.load.loads, &mut progress)?)
    } else {
        None
    };
    nonlinear::finish(scene, Arc::new(e.problem), e.load, initial, t, progress)
}
