//! What an iteration of a run starts from ([`Start`]).

use super::elastic::Problem;
use super::initial::InitialState;
use crate::loads::HarmonicLoads;
use crate::solution::Displacements;

/// What an iteration starts from: a problem, a load on it and its elastic
/// solution, and the initial state.
#[derive(Clone, Copy)]
pub(super) struct Start<'a> {
    /// The factored model.
    pub problem: &'a Problem,
    /// The loads, every harmonic of the run.
    pub loads: &'a [HarmonicLoads],
    /// Their elastic displacements.
    pub elastic: &'a Displacements,
    /// The end of the initial phase, if any.
    pub initial: Option<&'a InitialState>,
}

/// What a caller of `run::nonlinear::iterate` asks beyond the solution.
#[derive(Clone, Copy, Default)]
pub(super) struct Asked<'c> {
    /// The highest harmonic with whole displacements (`None`: every one).
    pub(super) whole_up_to: Option<u32>,
    /// Set to stop the iteration ([`IterationError::Cancelled`](crate::iteration::IterationError::Cancelled)).
    pub(super) cancel: Option<&'c std::sync::atomic::AtomicBool>,
}
