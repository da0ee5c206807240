//! Load cases (`load_cases`): one model, one set of factors (every harmonic
//! 0..=M, factorized once) and one initial phase; each case solved from the
//! same initial state.

use super::elastic::{elastic, ElasticLoad, Problem};
use super::factors::solve_loads;
use super::initial::{initial_phase, InitialState};
use super::nonlinear::finish;
use super::{Run, Stopped};
use crate::error::SolverError;
use crate::iteration::IterationRecord;
use crate::loads::assemble_loads;
use crate::scene::Scene;
use crate::solution::Timings;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// The load cases of a scene, ready to solve one by one
/// ([`Cases::solve`]).
pub struct Cases<'s> {
    scene: &'s Scene,
    problem: Arc<Problem>,
    initial: Option<InitialState>,
    timings: Timings,
}

/// Meshes and factorizes `scene` for its load cases ([`Scene::load_cases`])
/// and solves its initial phase; a failure there stops every case.
pub fn solve_cases<'s>(
    scene: &'s Scene,
    keep_msh: Option<&Path>,
    progress: impl FnMut(&IterationRecord),
) -> Result<Cases<'s>, SolverError> {
    let e = elastic(scene, keep_msh, true)?;
    let initial = if scene.has_initial_phase() {
        Some(initial_phase(scene, &e.problem, &e.load.loads, progress)?)
    } else {
        None
    };
    let timings = Timings {
        solve: 0.0,
        ..e.load.timings
    };
    Ok(Cases {
        scene,
        problem: Arc::new(e.problem),
        initial,
        timings,
    })
}

impl Cases<'_> {
    /// The number of cases.
    pub fn len(&self) -> usize {
        self.scene.load_cases.len()
    }

    /// Whether the scene has no load case.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Solves case `k` ([`Scene::case`]): its scene and its run, or why it
    /// stopped (a case that stops does not stop the others).
    pub fn solve(
        &self,
        k: usize,
        progress: impl FnMut(&IterationRecord),
    ) -> (Scene, Result<Run, Box<Stopped>>) {
        let case = self.scene.case(k);
        let t = Instant::now();
        let model = &self.problem.model;
        let loads = match assemble_loads(&case, &model.mesh, self.scene.harmonics()) {
            Ok(loads) => loads,
            Err(e) => return (case, Err(SolverError::Scene(e.in_case(k)).into())),
        };
        let u = solve_loads(model, &self.problem.factors, &loads);
        let load = ElasticLoad {
            loads,
            u,
            timings: self.timings.clone(),
        };
        let run = finish(
            &case,
            Arc::clone(&self.problem),
            load,
            self.initial.clone(),
            t,
            progress,
        );
        (case, run)
    }
}
