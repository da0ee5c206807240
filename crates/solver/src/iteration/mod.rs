//! The stress-transfer iteration (docs/theory.md sections 8-11, the paper's
//! steps (1)-(5)): the joints stay elastic in every K_m (the harmonics stay
//! decoupled), and the inadmissible part of their traction is released as
//! unbalanced nodal forces, analysed back into harmonics and solved again
//! with the same factors.
//!
//! With `G(u)` the released forces, each iteration solves
//! `K_m u_m = F_m + G_m(u_prev)`; the residual at section s is the change of
//! the released nodal forces there, `rho_s = g_s(u_k) - g_s(u_{k-1})`, and
//! `Psi_k = max_s |rho_s|`, `Psi_0 = max_s |g_s(u_0)|` (the paper's Eq. 12:
//! converged when `Psi_k / Psi_0 < epsilon`).
//!
//! Written as a fixed point on the released section forces x:
//! `Psi(x) = release(u_F + W x)`, `W = S K^-1 A` (A the analysis into
//! harmonics, K^-1 the back-substitution of every harmonic with its factor,
//! S the synthesis of the joint-node displacements at the sections,
//! `u_F = S K^-1 F`). One evaluation of `Psi` (`Setup::evaluate`, shared
//! by every method) costs one back-substitution sweep. The paper iterates
//! `x <- Psi(x)` (and then `rho_s = Psi(x)_s - x_s`), [`Method::Anderson`]
//! mixes the last iterates, [`Method::Newton`] solves `R(x) = Psi(x) - x = 0`
//! by a semi-smooth Newton-Krylov method (see the private `newton` module).
//! Only back-substitutions are ever repeated: no coupled system is factorized.
//!
//! The private submodules: `setup` (the fixed data of a run, synthesis and
//! analysis, one evaluation of `Psi`), `release` (the joint law at the
//! sections and its tangent), `fixed_point` (the paper's and Anderson's
//! iterations), `formulation` (what Newton iterates on), `newton`
//! (Newton-Krylov, and its nodal form), `traction` (its traction form, for
//! joints stiffer than their elements), `precondition` and `interface`
//! (the interface-tangent preconditioner and its fixed data), `steps` (the
//! load path), `diagnosis` (why a run stopped) and `probe` ([`FixedPoint`],
//! for tests).

mod diagnosis;
mod fixed_point;
mod formulation;
mod interface;
mod newton;
mod precondition;
mod probe;
mod release;
mod setup;
mod steps;
mod traction;

pub use probe::FixedPoint;
pub use setup::OBSERVED_UP_TO;
pub use steps::{
    stress_transfer_stepped, LimitLoad, LoadStep, StepControl, Stepped, BRACKET, EASY_ITERATIONS,
    MAX_CUTBACKS, MAX_ROUNDS, MIN_INCREMENT, PATH_MIN, PATH_TOL,
};

use crate::elements::JointPoint;
use crate::fourier::Sections;
use crate::joint_law::JointState;
use crate::linear::{HarmonicFactor, Model};
use crate::loads::HarmonicLoads;
use crate::scene::JointLaw;
use crate::solution::Displacements;
use fixed_point::fixed_point;
use newton::newton;
use serde::{Deserialize, Serialize};
use setup::Setup;

/// How the next released forces are chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// The paper's plain iteration: `x_{k+1} = Psi(x_k)`.
    Plain,
    /// Anderson mixing over the last `depth` iterates (type II).
    Anderson {
        /// History length.
        depth: usize,
    },
    /// Semi-smooth Newton-Krylov on `R(x) = Psi(x) - x = 0`: the
    /// generalized Jacobian `J = D(x) W - I` (D the joint tangent of the
    /// release at the states of x, W the elastic back-substitution chain),
    /// solved by a minimal-residual Krylov method (GCR, equivalent to GMRES)
    /// whose directions are recycled across Newton steps, and a backtracking
    /// line search on `|R|` with a fallback to the plain step. See the private `newton` module.
    Newton,
}

/// Convergence settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IterationSettings {
    /// Update rule.
    pub method: Method,
    /// Converged when `Psi_k / Psi_0 < epsilon`.
    pub epsilon: f64,
    /// Iteration limit: iterations of the fixed-point methods (one sweep
    /// each); for [`Method::Newton`] both its steps and its sweeps.
    pub max_iterations: u32,
    /// No equilibrium when the residual ratio makes no new minimum (by 0.1 %)
    /// within this many iterations (fixed-point methods).
    pub stall_window: u32,
}

impl Default for IterationSettings {
    fn default() -> Self {
        IterationSettings {
            method: Method::Anderson { depth: 8 },
            epsilon: 1e-6,
            max_iterations: 500,
            stall_window: 40,
        }
    }
}

/// One line of the convergence history.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct IterationRecord {
    /// Iteration (1 = the elastic solve); a Newton step for [`Method::Newton`].
    pub iteration: u32,
    /// `Psi_k / Psi_0` (0 for the first iteration when nothing is released).
    pub ratio: f64,
    /// Open (point, section) pairs.
    pub open: usize,
    /// Slipping pairs.
    pub slip: usize,
    /// Sticking pairs.
    pub stick: usize,
    /// Seconds since the iteration started.
    pub seconds: f64,
    /// Back-substitution sweeps (a solve of every harmonic) this record
    /// cost: 1 per iteration of the fixed-point methods, the Krylov
    /// directions plus any plain-step or verification evaluations of a
    /// Newton step. Their sum over the history is the run's cost in solves.
    #[serde(default)]
    pub solves: u32,
    /// The load factor lambda of the step this iteration belongs to (1 for
    /// a one-shot run).
    #[serde(default = "one")]
    pub load_factor: f64,
}

fn one() -> f64 {
    1.0
}
/// Where a joint integration point is.
#[derive(Clone, Debug, PartialEq)]
pub struct PointInfo {
    /// Joint index (as `mesh.joints`).
    pub joint: usize,
    /// Element index within the joint.
    pub element: usize,
    /// The integration point.
    pub point: JointPoint,
    /// Element nodes, bottom then top.
    pub nodes: Vec<usize>,
}

/// The integration points of every joint of `model`, in the order of the
/// joint fields (joints, then elements, then points).
pub fn joint_point_infos(model: &Model) -> Vec<PointInfo> {
    let mesh = &model.mesh;
    let mut points = Vec::new();
    for (j, joint) in mesh.joints.iter().enumerate() {
        let rule = model.joints[j].rule;
        for (e, el) in joint.elements.iter().enumerate() {
            let coords: Vec<[f64; 2]> = el.bottom.iter().map(|&k| mesh.nodes[k]).collect();
            let nodes: Vec<usize> = el.bottom.iter().chain(&el.top).copied().collect();
            for point in crate::elements::joint_points(el.kind, &coords, rule) {
                points.push(PointInfo {
                    joint: j,
                    element: e,
                    point,
                    nodes: nodes.clone(),
                });
            }
        }
    }
    points
}

/// Joint relative displacements, admissible tractions and states at every
/// point and section: index `s * n_points + p`.
#[derive(Clone, Debug, PartialEq)]
pub struct JointField {
    /// The sections.
    pub sections: Sections,
    /// The points.
    pub points: Vec<PointInfo>,
    /// Relative displacement `(d_xi, d_eta, d_theta)`.
    pub d: Vec<[f64; 3]>,
    /// Admissible traction `(tau_xi, sigma, tau_theta)`.
    pub p: Vec<[f64; 3]>,
    /// State.
    pub state: Vec<JointState>,
    /// Debonded (no cohesion, no tensile strength left).
    pub debonded: Vec<bool>,
}

/// The joint state an iteration starts from (the end of an initial phase),
/// per (section, point) pair, index `s * n_points + p`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JointStart {
    /// Traction `(tau_xi, sigma, tau_theta)` carried at zero displacement.
    pub traction: Vec<[f64; 3]>,
    /// Debonded pairs.
    pub debonded: Vec<bool>,
}

/// A converged nonlinear solution.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// Displacement amplitudes.
    pub displacements: Displacements,
    /// Size of each harmonic of the released traction at the solution,
    /// `|f_m| / c_m` over the joint nodes, for m up to what the sections
    /// resolve: content above the solved M shows what the truncation drops.
    pub released_spectrum: Vec<f64>,
    /// Convergence history.
    pub history: Vec<IterationRecord>,
    /// Joint field at the solution.
    pub field: JointField,
}

/// Why the iteration stopped without a solution.
#[derive(Debug, thiserror::Error)]
pub enum IterationError {
    /// The load exceeds what the joints can carry (the residual stalls or grows).
    #[error("no equilibrium: {reason}; joint '{joint}' carries most of the unbalanced force (all joints: {open} open and {slip} slipping of {total} point-sections at iteration {iteration})")]
    NoEquilibrium {
        /// The joint with the largest residual.
        joint: String,
        /// What was detected.
        reason: String,
        /// Counts at the last iteration.
        open: usize,
        /// Slipping count.
        slip: usize,
        /// Point-sections.
        total: usize,
        /// Last iteration.
        iteration: u32,
        /// The history so far.
        history: Vec<IterationRecord>,
        /// The last iterate of a one-shot run (joint states, displacements),
        /// for diagnosis; not an equilibrium.
        last: Option<Box<Outcome>>,
    },
    /// The iteration stalled on a joint much stiffer than its elements:
    /// whether an equilibrium exists cannot be told.
    #[error("not converged: {reason}; joint '{joint}' is much stiffer than the elements along it (k h / E = {stiffness:.1}): the paper and anderson methods keep the elastic joint stiffness in K_m, so a released traction comes back through the same stiff spring and the iteration crawls; newton (the default, with load steps) iterates on the released tractions there and converged up to k h / E = 1e6 on the measured cases with the default sections (docs/stability.md), slower where the interface has more than 6000 pair unknowns over the harmonics. This does not show that the load exceeds what the joint can carry; use newton with load steps and the default sections, soften the joint (k h / E of about 1 suffices for every method), or refine the mesh along it (iteration {iteration})")]
    StiffJoint {
        /// The joint with the largest residual.
        joint: String,
        /// `k h / E` of that joint (largest spring, mean element length,
        /// stiffer neighbouring body).
        stiffness: f64,
        /// What was detected.
        reason: String,
        /// Last iteration.
        iteration: u32,
        /// The history so far.
        history: Vec<IterationRecord>,
        /// The last iterate of a one-shot run (joint states, displacements),
        /// for diagnosis; not an equilibrium.
        last: Option<Box<Outcome>>,
    },
    /// The iteration limit was reached while still converging.
    #[error("not converged within the iteration limit {limit} ({iterations} iterations, {solves} solves): residual ratio {ratio:.3e} > epsilon {epsilon:.1e}; it was still decreasing: raise solver.max_iterations (if it decreases ever more slowly, the load may be close to what the joints can carry)")]
    NotConverged {
        /// Iterations done.
        iterations: u32,
        /// Back-substitution sweeps done (Newton: its Krylov solves too).
        solves: u32,
        /// The limit: `solver.max_iterations` (newton: on its steps and its
        /// solves), 4 times it on the retry before a stop.
        limit: u32,
        /// Last ratio.
        ratio: f64,
        /// The target.
        epsilon: f64,
        /// The history.
        history: Vec<IterationRecord>,
        /// The last iterate of a one-shot run (joint states, displacements),
        /// for diagnosis; not an equilibrium.
        last: Option<Box<Outcome>>,
    },
    /// Debonding did not settle within a load step.
    #[error("the debonded points did not settle in {rounds} rounds of one load step")]
    Rounds {
        /// Rounds done.
        rounds: u32,
        /// The history.
        history: Vec<IterationRecord>,
    },
    /// A harmonic or section setting that cannot work.
    #[error("{0}")]
    Setup(String),
}

impl IterationError {
    /// The history up to the stop, if any.
    pub fn history(&self) -> &[IterationRecord] {
        match self {
            IterationError::NoEquilibrium { history, .. }
            | IterationError::NotConverged { history, .. }
            | IterationError::StiffJoint { history, .. }
            | IterationError::Rounds { history, .. } => history,
            IterationError::Setup(_) => &[],
        }
    }

    /// The last iterate, if the error carries one.
    pub fn last(&self) -> Option<&Outcome> {
        match self {
            IterationError::NoEquilibrium { last, .. }
            | IterationError::NotConverged { last, .. }
            | IterationError::StiffJoint { last, .. } => last.as_deref(),
            _ => None,
        }
    }

    /// With the last iterate `outcome`.
    fn with_last(mut self, outcome: Outcome) -> Self {
        if let IterationError::NoEquilibrium { last, .. }
        | IterationError::NotConverged { last, .. }
        | IterationError::StiffJoint { last, .. } = &mut self
        {
            *last = Some(Box::new(outcome));
        }
        self
    }

    /// Puts `earlier` records (e.g. earlier rounds of a step) before the history.
    fn prepend_history(&mut self, earlier: &[IterationRecord]) {
        if let IterationError::NoEquilibrium { history, .. }
        | IterationError::NotConverged { history, .. }
        | IterationError::StiffJoint { history, .. }
        | IterationError::Rounds { history, .. } = self
        {
            history.splice(0..0, earlier.iter().copied());
        }
    }
}

/// Where an iteration starts: the released section forces `x0` (zero for
/// a one-shot run, the last converged step's in a stepped one) and the
/// unknowns of Newton's formulation there (`y0`, from the same run), the
/// reference `Psi_0` of the residual ratio (`None`: the first residual);
/// `u_s`, the section displacements at `x0` and
/// the current load when a converged evaluation gave them (a new debonding
/// round, the rest of a loose solve: Newton starts without a sweep).
pub(super) struct Start {
    x0: Vec<f64>,
    y0: Option<Vec<f64>>,
    psi_ref: Option<f64>,
    u_s: Option<Vec<f64>>,
}

impl Start {
    /// From zero, relative to the first residual (the paper's iteration).
    fn zero(setup: &Setup) -> Start {
        Start {
            x0: vec![0.0; setup.len()],
            y0: None,
            psi_ref: None,
            u_s: None,
        }
    }

    /// From converged `conv` at the same load (a new debonding round, the
    /// rest of a loose solve): its forces, unknowns and section
    /// displacements.
    fn resume(conv: Converged, psi_ref: Option<f64>) -> Start {
        Start {
            x0: conv.x,
            y0: Some(conv.y),
            psi_ref,
            u_s: Some(conv.ev.u_s),
        }
    }
}

/// The back-substitution sweeps of `history` (all harmonics' solves).
fn solves(history: &[IterationRecord]) -> u32 {
    history.iter().map(|r| r.solves).sum()
}

/// A stopped iteration: why, and its last iterate (released forces and
/// their evaluation).
pub(super) struct Failure {
    error: IterationError,
    x: Vec<f64>,
    ev: release::Eval,
}

impl Failure {
    fn new(error: IterationError, x: Vec<f64>, ev: release::Eval) -> Box<Self> {
        Box::new(Failure { error, x, ev })
    }
}

/// A converged iteration: the released forces, the unknowns of the
/// method's formulation (`y`, the same as x but for Newton's traction
/// form), their evaluation, the history.
pub(super) struct Converged {
    x: Vec<f64>,
    y: Vec<f64>,
    ev: release::Eval,
    history: Vec<IterationRecord>,
}

impl Converged {
    fn new(x: Vec<f64>, y: Vec<f64>, ev: release::Eval, history: Vec<IterationRecord>) -> Self {
        Converged { x, y, ev, history }
    }
}

/// Runs the iteration. `factors` must hold every harmonic of `loads`;
/// `laws[j]` is the law of `model.joints[j]`. `progress` sees each record.
pub fn stress_transfer(
    model: &Model,
    factors: &[HarmonicFactor],
    loads: &[HarmonicLoads],
    laws: &[JointLaw],
    sections: &Sections,
    settings: &IterationSettings,
    progress: impl FnMut(&IterationRecord),
) -> Result<Outcome, IterationError> {
    stress_transfer_from(
        model, factors, loads, laws, sections, settings, None, None, progress,
    )
}

/// [`stress_transfer`] given the elastic solution `K^-1 F` of (some of) the
/// harmonics of `loads`, which then cost no solve, and the joints' `start`
/// state (none: unstressed and intact).
#[allow(clippy::too_many_arguments)]
pub fn stress_transfer_from(
    model: &Model,
    factors: &[HarmonicFactor],
    loads: &[HarmonicLoads],
    laws: &[JointLaw],
    sections: &Sections,
    settings: &IterationSettings,
    elastic: Option<&Displacements>,
    start: Option<&JointStart>,
    mut progress: impl FnMut(&IterationRecord),
) -> Result<Outcome, IterationError> {
    let mut setup = Setup::new(model, factors, loads, laws, sections, elastic, start)?;
    let mut start = Start::zero(&setup);
    if setup.softened() {
        start.psi_ref = Some(setup.reference_release());
    }
    let result = match settings.method {
        Method::Plain => fixed_point(&setup, 0, settings, start, &mut progress),
        Method::Anderson { depth } => fixed_point(&setup, depth, settings, start, &mut progress),
        Method::Newton => newton(&setup, settings, start, &mut progress),
    };
    match result {
        Ok(conv) => {
            let displacements = setup.full_displacements(&conv.x);
            // A converged residual is not yet an equilibrium.
            let imbalance = setup.imbalance(&conv.x, &displacements);
            if imbalance > setup::IMBALANCE_TOL {
                let e = diagnosis::unbalanced(&setup, &conv.ev, imbalance, conv.history.clone());
                return Err(e.with_last(setup.finish_with(conv, displacements)));
            }
            Ok(setup.finish_with(conv, displacements))
        }
        // The last iterate, for the user to see where it stopped (one full
        // solve).
        Err(f) => {
            let history = f.error.history().to_vec();
            let last = setup.finish(&f.x, f.ev, history);
            Err(f.error.with_last(last))
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// `y += alpha x`.
fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += alpha * xi;
    }
}
