//! The iteration's public types: its settings ([`IterationSettings`]), the
//! problem it solves ([`Problem`]), where the joints start ([`JointStart`]),
//! what it gives ([`Outcome`], [`JointField`], [`IterationRecord`]) and why
//! it stops ([`IterationError`]).

use crate::elements::JointPoint;
use crate::fourier::Sections;
use crate::joint_law::JointState;
use crate::linear::{HarmonicFactor, Model};
use crate::loads::HarmonicLoads;
use crate::scene::JointLaw;
use crate::solution::Displacements;
use serde::{Deserialize, Serialize};
use std::sync::atomic::AtomicBool;

/// The problem an iteration solves: the loads of `model` (every harmonic
/// factorized in `factors`), `laws[j]` the law of `model.joints[j]`,
/// evaluated at `sections`.
#[derive(Clone, Copy)]
pub struct Problem<'a> {
    /// The model.
    pub model: &'a Model,
    /// The factors of (at least) every harmonic of `loads`.
    pub factors: &'a [HarmonicFactor],
    /// The loads, per harmonic.
    pub loads: &'a [HarmonicLoads],
    /// The law of each joint of the model.
    pub laws: &'a [JointLaw],
    /// Where the joints are evaluated around the turn.
    pub sections: &'a Sections,
    /// The elastic solution `K^-1 F` of (some of) the harmonics of `loads`,
    /// if known: those cost no solve.
    pub elastic: Option<&'a Displacements>,
    /// The highest harmonic whose whole displacements the outcome needs
    /// (`None`: every one); the outcome's displacements of the others are
    /// zero. A harmonic whose factor keeps only its joint block is
    /// factorized again for them, so a caller that reads only the loaded
    /// faces' mean motion asks for harmonics 0 and 1.
    pub whole_up_to: Option<u32>,
    /// The stage of loading this one follows (none: the first, from no
    /// load): then `loads` are the increment over the stage, `F(lambda) =
    /// F_start + lambda loads`, and `elastic` is the increment's.
    pub from: Option<StageStart<'a>>,
    /// Set by the caller to stop the iteration early (it then ends with
    /// [`IterationError::Cancelled`] within a Newton step or an iteration).
    pub cancel: Option<&'a AtomicBool>,
}

/// Where a stage of loading starts ([`Problem::from`]).
#[derive(Clone, Copy)]
pub struct StageStart<'a> {
    /// The loads reached (harmonics as the problem's `loads`; a missing
    /// one is zero).
    pub loads: &'a [HarmonicLoads],
    /// Their elastic solution `K^-1 F_start` (some harmonics at least).
    pub elastic: &'a Displacements,
    /// The converged state there: the released forces and the committed
    /// joint history.
    pub end: &'a StageEnd,
}

/// The converged state at the end of a stepped run ([`super::Solved::end`]):
/// where the next stage of loading starts.
#[derive(Clone)]
pub struct StageEnd {
    /// The converged step's released forces, tractions (Newton's `y`),
    /// evaluation and iteration records.
    pub(super) x: Vec<f64>,
    pub(super) y: Vec<f64>,
    pub(super) ev: super::eval::Eval,
    pub(super) records: Vec<IterationRecord>,
    /// The committed history of every (section, point) pair.
    pub(super) history: super::state::History,
}

impl std::fmt::Debug for StageEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StageEnd")
            .field("pairs", &self.history.joints.len())
            .finish_non_exhaustive()
    }
}

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
    /// How the stiff-joint preconditioner solves its coupled interface
    /// system (docs/stability.md).
    pub interface_solve: InterfaceSolve,
    /// Whether Newton on a softened joint's tractions breaks a crawl of
    /// short line-search steps with a whole step under a watchdog
    /// (docs/theory.md, "The three methods"); `false`: the monotone line
    /// search alone (the reference).
    pub watchdog: bool,
    /// The smallest `R = k_a / k` that Newton's traction form linearizes
    /// with (its residual keeps the joint's own R; 0: the exact Jacobian).
    /// Default [`TANGENT_RHO_FLOOR`].
    pub tangent_rho_floor: f64,
}

/// The default [`IterationSettings::tangent_rho_floor`]. On a stuck point
/// the traction form's Jacobian weighs the point tractions that no node
/// sees (Gauss points beyond the face nodes, sections beyond the
/// harmonics) by `R = k_a / k` alone, so with `k > 1e4 k_a` their Newton
/// step, `1 / R` times a small residual, opened and slipped the points
/// around them: the pile in soil at `k h / E` = 1e6 crawled for minutes,
/// and with this floor converges in 59 Newton steps (a floor of 1e-3 took
/// 439 at 1e5 against 127; docs/stability.md, item 12).
pub const TANGENT_RHO_FLOOR: f64 = 1e-4;

/// How the stiff-joint preconditioner of Newton's traction form solves the
/// interface system that couples the harmonics (module `precondition`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum InterfaceSolve {
    /// GMRES on its Schur form, preconditioned by the sparse LU of its
    /// element-banded part (the joint's tangent whole, the bodies' coupling
    /// of the pairs of one joint point): about ten iterations at every
    /// stiffness, a cost that grows with the interface, not its cube.
    #[default]
    Banded,
    /// The dense LU of the whole system (order: harmonics x families x
    /// pair unknowns) at every Newton step: the exact reference.
    Dense,
}

impl Default for IterationSettings {
    fn default() -> Self {
        IterationSettings {
            method: Method::Anderson { depth: 8 },
            epsilon: 1e-6,
            max_iterations: 500,
            stall_window: 40,
            interface_solve: InterfaceSolve::Banded,
            watchdog: true,
            tangent_rho_floor: TANGENT_RHO_FLOOR,
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

/// The state an iteration starts from (the end of an initial phase): the
/// joints' per (section, point) pair, index `s * n_points + p`, and the
/// plastic bodies' per Gauss point (axisymmetric: the same at every
/// section; empty: unstressed).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JointStart {
    /// Traction `(tau_xi, sigma, tau_theta)` carried at zero displacement.
    pub traction: Vec<[f64; 3]>,
    /// Debonded pairs.
    pub debonded: Vec<bool>,
    /// The stress of each plastic body point at zero displacement.
    pub body_stress: Vec<[f64; 6]>,
    /// The plastic strain each plastic body point starts with (reported
    /// with the field's; the return counts from `body_stress`).
    pub body_plastic: Vec<[f64; 6]>,
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
    /// The plastic bodies' field at the solution (none: every body elastic).
    pub body: Option<BodyField>,
    /// With plastic bodies, the released forces `A x` at the solution as
    /// nodal loads per harmonic (empty without): the reactions are `K u -
    /// f - A x` at the supports.
    pub released: Vec<crate::loads::HarmonicLoads>,
}

/// What a converged load step's `observe` sees of the plastic bodies
/// (nothing without them).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepBodies {
    /// The released forces `A x` as nodal loads per harmonic (empty
    /// without plastic bodies): the reactions are `K u - f - A x` at the
    /// supports.
    pub released: Vec<crate::loads::HarmonicLoads>,
    /// The volume of the yielding Gauss points (none without plastic
    /// bodies).
    pub plastic_volume: Option<f64>,
}

/// The field of the plastic bodies at every (section, Gauss point) pair
/// (index `s * points + q`, the points cell by cell).
#[derive(Clone, Debug, PartialEq)]
pub struct BodyField {
    /// The sections.
    pub sections: Sections,
    /// Each point's position `(r, z)`.
    pub points: Vec<[f64; 2]>,
    /// Each point's cell (index into the mesh's cells).
    pub cells: Vec<usize>,
    /// The stress `(s_r, s_z, s_th, t_rz, t_rth, t_zth)` (with the initial
    /// stress).
    pub sigma: Vec<[f64; 6]>,
    /// The plastic strain (engineering shears).
    pub plastic: Vec<[f64; 6]>,
    /// Whether the point yields.
    pub yielding: Vec<bool>,
}

/// The `joint` of [`IterationError::NoEquilibrium`] when the plastic bodies
/// carry most of the unbalanced force.
pub const PLASTIC_BODIES: &str = "(plastic bodies)";

/// Who carries most of an unbalanced force: `joint 'name'`, or the plastic
/// bodies ([`PLASTIC_BODIES`]).
fn blame(joint: &str) -> String {
    if joint == PLASTIC_BODIES {
        "the yielding soil (the plastic bodies)".into()
    } else {
        format!("joint '{joint}'")
    }
}

/// Why the iteration stopped without a solution.
#[derive(Debug, thiserror::Error)]
pub enum IterationError {
    /// The load exceeds what the joints can carry (the residual stalls or grows).
    #[error("no equilibrium: {reason}; {} carries most of the unbalanced force (all joints: {open} open and {slip} slipping of {total} point-sections at iteration {iteration})", blame(joint))]
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
    #[error("not converged: {reason}; joint '{joint}' is much stiffer than the elements along it (k h / E = {stiffness:.1}): the paper and anderson methods keep the elastic joint stiffness in K_m, so a released traction comes back through the same stiff spring and the iteration crawls; newton (the default, with load steps) iterates on the released tractions there and converged up to k h / E = 1e6 on the measured cases with the default sections (docs/stability.md). This does not show that the load exceeds what the joint can carry; use newton with load steps and the default sections, soften the joint (k h / E of about 1 suffices for every method), or refine the mesh along it (iteration {iteration})")]
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
    /// Stopped by its caller ([`Problem::cancel`]): the M/2 check of a run
    /// that ended at a limit load, where the check is not made.
    #[error("cancelled")]
    Cancelled,
}

impl IterationError {
    /// The history up to the stop, if any.
    pub fn history(&self) -> &[IterationRecord] {
        match self {
            IterationError::NoEquilibrium { history, .. }
            | IterationError::NotConverged { history, .. }
            | IterationError::StiffJoint { history, .. }
            | IterationError::Rounds { history, .. } => history,
            IterationError::Setup(_) | IterationError::Cancelled => &[],
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
    pub(super) fn with_last(mut self, outcome: Outcome) -> Self {
        if let IterationError::NoEquilibrium { last, .. }
        | IterationError::NotConverged { last, .. }
        | IterationError::StiffJoint { last, .. } = &mut self
        {
            *last = Some(Box::new(outcome));
        }
        self
    }

    /// Puts `earlier` records (e.g. earlier rounds of a step) before the history.
    pub(super) fn prepend_history(&mut self, earlier: &[IterationRecord]) {
        if let IterationError::NoEquilibrium { history, .. }
        | IterationError::NotConverged { history, .. }
        | IterationError::StiffJoint { history, .. }
        | IterationError::Rounds { history, .. } = self
        {
            history.splice(0..0, earlier.iter().copied());
        }
    }
}

/// The back-substitution sweeps of `history` (all harmonics' solves).
pub(super) fn solves(history: &[IterationRecord]) -> u32 {
    history.iter().map(|r| r.solves).sum()
}
