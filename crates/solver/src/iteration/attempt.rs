//! One run of a method at one load state: where it starts ([`Start`]) and
//! how it ends ([`Converged`], [`Failure`]).

use super::eval::Eval;
use super::setup::Setup;
use super::types::{IterationError, IterationRecord};

/// Where an iteration starts: the released section forces `x0` (zero for
/// a one-shot run, the last converged step's in a stepped one) and the
/// unknowns of Newton's formulation there (`y0`, from the same run), the
/// reference `Psi_0` of the residual ratio (`None`: the first residual);
/// `u_s`, the section displacements at `x0` and
/// the current load when a converged evaluation gave them (a new debonding
/// round, the rest of a loose solve: Newton starts without a sweep);
/// `predicted`, a second candidate for `x0` (the released forces of the
/// last two converged steps extrapolated to this load; with plastic bodies
/// only), which Newton on the section forces starts from when its residual
/// is the smaller.
pub(super) struct Start {
    pub(super) x0: Vec<f64>,
    pub(super) y0: Option<Vec<f64>>,
    pub(super) psi_ref: Option<f64>,
    pub(super) u_s: Option<Vec<f64>>,
    pub(super) predicted: Option<Vec<f64>>,
}

impl Start {
    /// From zero, relative to the first residual (the paper's iteration).
    pub(super) fn zero(setup: &Setup) -> Start {
        Start {
            x0: vec![0.0; setup.len()],
            y0: None,
            psi_ref: None,
            u_s: None,
            predicted: None,
        }
    }

    /// From converged `conv` at the same load (a new debonding round, the
    /// rest of a loose solve): its forces, unknowns and section
    /// displacements.
    pub(super) fn resume(conv: Converged, psi_ref: Option<f64>) -> Start {
        Start {
            x0: conv.x,
            y0: Some(conv.y),
            psi_ref,
            u_s: Some(conv.ev.u_s),
            predicted: None,
        }
    }
}

/// A stopped iteration: why, and its last iterate (released forces and
/// their evaluation).
pub(super) struct Failure {
    pub(super) error: IterationError,
    pub(super) x: Vec<f64>,
    pub(super) ev: Eval,
}

impl Failure {
    pub(super) fn new(error: IterationError, x: Vec<f64>, ev: Eval) -> Box<Self> {
        Box::new(Failure { error, x, ev })
    }
}

/// A converged iteration: the released forces, the unknowns of the
/// method's formulation (`y`, the same as x but for Newton's traction
/// form), their evaluation, the history.
pub(super) struct Converged {
    pub(super) x: Vec<f64>,
    pub(super) y: Vec<f64>,
    pub(super) ev: Eval,
    pub(super) history: Vec<IterationRecord>,
}

impl Converged {
    pub(super) fn new(x: Vec<f64>, y: Vec<f64>, ev: Eval, history: Vec<IterationRecord>) -> Self {
        Converged { x, y, ev, history }
    }
}
