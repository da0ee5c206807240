//! The one entry into the iteration ([`solve`]): the problem, its settings,
//! where the joints start and how the load is applied; one-shot or stepped
//! is chosen here.

use super::attempt::Start;
use super::diagnosis::{one_shot_verdict, unbalanced};
use super::method;
use super::release::reference_release;
use super::setup::Setup;
use super::state::LoadState;
use super::steps::{stepped, StepControl, Stepped};
use super::sweep::{Sweep, IMBALANCE_TOL};
use super::types::{
    IterationError, IterationRecord, IterationSettings, JointField, JointStart, Outcome, Problem,
};
use crate::fourier::Sections;
use crate::linear::{HarmonicFactor, Model};
use crate::loads::HarmonicLoads;
use crate::scene::{JointLaw, Loading};
use crate::solution::Displacements;

/// How the load is applied.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stepping {
    /// The whole load at once under the paper's law.
    OneShot,
    /// Proportional loading in steps with the history law.
    Steps(StepControl),
}

impl From<Loading> for Stepping {
    /// The scene's `solver.loading`.
    fn from(loading: Loading) -> Self {
        match loading {
            Loading::OneShot => Stepping::OneShot,
            Loading::Steps(n) => Stepping::Steps(StepControl::steps(n)),
            Loading::Auto => Stepping::Steps(StepControl::AUTO),
        }
    }
}

/// A solved problem.
#[derive(Clone, Debug)]
pub struct Solved<T> {
    /// The solution: at the whole load, or at the last converged load
    /// factor of a stepped run that stopped short (`stepped.limit`).
    pub outcome: Outcome,
    /// The load path of a stepped run (`None`: one-shot).
    pub stepped: Option<Stepped<T>>,
    /// The converged state at its end, for a next stage of loading
    /// ([`super::Problem::from`]; `None`: one-shot).
    pub end: Option<super::StageEnd>,
}

/// Solves `problem` with `settings` from the joints' `start` state (none:
/// unstressed and intact), the load applied as `stepping` says. `observe`
/// sees every converged load step ([`Stepping::Steps`]: the displacements
/// of harmonics 0..=[`OBSERVED_UP_TO`](super::sweep::OBSERVED_UP_TO), of
/// every harmonic at the whole load, and the joint field); `progress`
/// sees each record.
pub fn solve<T>(
    problem: &Problem,
    settings: &IterationSettings,
    start: Option<&JointStart>,
    stepping: Stepping,
    observe: impl FnMut(f64, &Displacements, &JointField, &super::types::StepBodies) -> T,
    mut progress: impl FnMut(&IterationRecord),
) -> Result<Solved<T>, IterationError> {
    let setup = Setup::new(problem, start)?;
    match stepping {
        Stepping::OneShot if problem.from.is_some() => Err(IterationError::Setup(
            "a stage of loading after another is stepped (the history law carries the state), not one-shot"
                .into(),
        )),
        Stepping::OneShot => Ok(Solved {
            outcome: one_shot(&setup, settings, &mut progress)?,
            stepped: None,
            end: None,
        }),
        Stepping::Steps(control) => {
            let (outcome, path, end) = stepped(&setup, control, settings, &mut progress, observe)?;
            Ok(Solved {
                outcome,
                stepped: Some(path),
                end: Some(end),
            })
        }
    }
}

/// Runs the iteration one-shot from unstressed, intact joints. `factors`
/// must hold every harmonic of `loads`; `laws[j]` is the law of
/// `model.joints[j]`. `progress` sees each record.
pub fn stress_transfer(
    model: &Model,
    factors: &[HarmonicFactor],
    loads: &[HarmonicLoads],
    laws: &[JointLaw],
    sections: &Sections,
    settings: &IterationSettings,
    progress: impl FnMut(&IterationRecord),
) -> Result<Outcome, IterationError> {
    let problem = Problem {
        model,
        factors,
        loads,
        laws,
        sections,
        elastic: None,
        whole_up_to: None,
        from: None,
        cancel: None,
    };
    solve(
        &problem,
        settings,
        None,
        Stepping::OneShot,
        |_, _, _, _| (),
        progress,
    )
    .map(|s| s.outcome)
}

/// The whole load at once under the paper's law; a stop carries its last
/// iterate.
fn one_shot(
    setup: &Setup,
    settings: &IterationSettings,
    progress: &mut dyn FnMut(&IterationRecord),
) -> Result<Outcome, IterationError> {
    let mut start = Start::zero(setup);
    if setup.softened() {
        start.psi_ref = Some(reference_release(setup));
    }
    let sweep = Sweep::new(setup, LoadState::WHOLE);
    match method::run(&sweep, settings, start, progress) {
        Ok(conv) => {
            let displacements = sweep.full_displacements(&conv.x);
            // A converged residual is not yet an equilibrium.
            let imbalance = sweep.imbalance(&conv.x, &displacements);
            if imbalance > IMBALANCE_TOL {
                let e = unbalanced(setup, &conv.ev, imbalance, conv.history.clone());
                return Err(e.with_last(sweep.finish_with(conv, displacements)));
            }
            Ok(sweep.finish_with(conv, displacements))
        }
        // The last iterate, for the user to see where it stopped (one full
        // solve).
        Err(f) => {
            let history = f.error.history().to_vec();
            let last = sweep.finish(&f.x, f.ev, history);
            Err(one_shot_verdict(setup, f.error).with_last(last))
        }
    }
}
