//! Why an iteration stopped: no equilibrium, a joint too stiff for the
//! iteration, or the iteration limit.

use super::eval::Eval;
use super::setup::Setup;
use super::types::{solves, IterationError, IterationRecord, IterationSettings};
use crate::joint_law::JointState;

/// The end at the iteration limit: `NotConverged`, or `StiffJoint` when the
/// joint with the largest residual `f` is much stiffer than its elements.
pub(super) fn not_converged(
    setup: &Setup,
    f: &[f64],
    settings: &IterationSettings,
    history: Vec<IterationRecord>,
) -> IterationError {
    let last = history.last().copied();
    let ratio = last.map_or(f64::NAN, |r| r.ratio);
    let worst = worst_joint(setup, f);
    let stiffness = joint_stiffness_ratio(setup, worst);
    if stiffness > STIFF_JOINT && !softened(setup, worst) {
        return IterationError::StiffJoint {
            last: None,
            joint: joint_name(setup, worst),
            stiffness,
            reason: format!(
                "the iteration limit ({}) was reached at residual ratio {ratio:.3e} > epsilon {:.1e}",
                settings.max_iterations, settings.epsilon
            ),
            iteration: last.map_or(0, |r| r.iteration),
            history,
        };
    }
    IterationError::NotConverged {
        last: None,
        iterations: history.len() as u32,
        solves: solves(&history),
        limit: settings.max_iterations,
        ratio,
        epsilon: settings.epsilon,
        history,
    }
}

/// The name of joint `j` (`?` if there is none).
fn joint_name(setup: &Setup, j: usize) -> String {
    setup
        .model
        .mesh
        .joints
        .get(j)
        .map_or_else(|| "?".into(), |j| j.name.clone())
}

/// Whether the plastic bodies' part of a section-force residual `f` is
/// larger than the joints' (always, without joints).
fn bodies_carry_most(setup: &Setup, f: &[f64]) -> bool {
    if setup.bodies.is_none() {
        return false;
    }
    let (m, start) = (setup.per_section(), setup.transfer.body_start());
    let (mut joints, mut bodies) = (0.0, 0.0);
    for chunk in f.chunks(m) {
        joints += chunk[..start].iter().map(|v| v * v).sum::<f64>();
        bodies += chunk[start..].iter().map(|v| v * v).sum::<f64>();
    }
    bodies >= joints
}

/// The joint that carries most of a section-force residual `f`.
fn worst_joint(setup: &Setup, f: &[f64]) -> usize {
    let n_j = setup.joint_nodes.len();
    let mut per_joint = vec![0.0f64; setup.model.mesh.joints.len()];
    for (i, info) in setup.points.iter().enumerate() {
        for &j in &setup.local[i] {
            for s in 0..setup.sections().len() {
                for c in 0..3 {
                    per_joint[info.joint] += f.get(s * 3 * n_j + 3 * j + c).map_or(0.0, |v| v * v);
                }
            }
        }
    }
    per_joint
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |(j, _)| j)
}

/// The no-equilibrium reason when the released forces x have grown so far
/// that rounding hides a residual ratio of epsilon: `Psi(x) - x` is a
/// difference of numbers of size |x|, so below `64 eps_mach max_s |x_s|` a
/// "converged" ratio (even an exact 0) is noise. An extrapolating method
/// (Anderson, Newton) chasing an equilibrium that does not exist reaches
/// this; a solution that exists has released forces of the order of the
/// joint forces.
pub(super) fn unresolved(setup: &Setup, x: &[f64], psi0: f64, epsilon: f64) -> Option<String> {
    let x_max = setup.section_max(x);
    (64.0 * f64::EPSILON * x_max > epsilon * psi0).then(|| {
        format!(
            "the released forces grew to {:.1e} times the first release, where rounding hides a residual ratio of epsilon = {epsilon:.0e}: they grow without bound (the joints cannot carry the load), or epsilon is below what the arithmetic resolves",
            x_max / psi0
        )
    })
}

/// The limit of the residual-ratio sequence predicted from its decrease over
/// the last two windows of `w` iterations (geometric fit): 0 for geometric
/// convergence, about half the current ratio for the slow hyperbolic
/// convergence the paper reports, and the positive limit the ratio settles
/// to when no equilibrium exists. `None` until there are 3w + 1 values or
/// while the ratio does not decrease steadily.
pub(super) fn residual_limit(history: &[IterationRecord], w: u32) -> Option<f64> {
    let w = w.max(2) as usize;
    let n = history.len();
    if n < 3 * w + 1 {
        return None;
    }
    // Window minima damp the oscillations of the accelerated iteration.
    let min = |a: usize, b: usize| {
        history[a..b]
            .iter()
            .map(|r| r.ratio)
            .fold(f64::INFINITY, f64::min)
    };
    let (r0, r1, r2) = (min(n - 3 * w, n - 2 * w), min(n - 2 * w, n - w), min(n - w, n));
    let (d1, d2) = (r0 - r1, r1 - r2);
    if !(d1 > 0.0 && d2 > 0.0 && d2 < d1) {
        return None;
    }
    let q = d2 / d1;
    Some(r2 - d2 * q / (1.0 - q))
}

/// Largest `k h / E` of joint `j`: its largest spring stiffness times its
/// mean element length over the smallest Young's modulus of its bodies.
pub(super) fn joint_stiffness_ratio(setup: &Setup, j: usize) -> f64 {
    let model = setup.model;
    let (Some(joint), Some(props)) = (model.mesh.joints.get(j), model.joints.get(j)) else {
        return 0.0;
    };
    let k = props
        .springs
        .k_xi
        .max(props.springs.k_eta)
        .max(props.springs.k_theta);
    let n = joint.elements.len().max(1) as f64;
    let h: f64 = joint
        .elements
        .iter()
        .map(|e| {
            let (a, b) = (model.mesh.nodes[e.bottom[0]], model.mesh.nodes[e.bottom[1]]);
            (b[0] - a[0]).hypot(b[1] - a[1])
        })
        .sum::<f64>()
        / n;
    let e = crate::material::softer_side(joint, &model.materials).map_or(f64::INFINITY, |m| m.e);
    if e.is_finite() && e > 0.0 {
        k * h / e
    } else {
        0.0
    }
}

/// The verdict on a one-shot run's stop: a stall on a joint Newton
/// assembles softer is reported as a stiff joint there. The whole load in
/// one step can stall on a stiff joint where an equilibrium exists (Scene P
/// at k h / E = 1e6, crates/solver/tests/stability.rs case 3); a stepped
/// run tells a limit by halving its step down to 1 % (`steps`).
pub(super) fn one_shot_verdict(setup: &Setup, e: IterationError) -> IterationError {
    let IterationError::NoEquilibrium { joint, .. } = &e else {
        return e;
    };
    let Some(j) = setup.model.mesh.joints.iter().position(|x| &x.name == joint) else {
        return e;
    };
    let stiffness = joint_stiffness_ratio(setup, j);
    if !(stiffness > STIFF_JOINT && softened(setup, j)) {
        return e;
    }
    match e {
        IterationError::NoEquilibrium {
            joint,
            reason,
            iteration,
            history,
            last,
            ..
        } => IterationError::StiffJoint {
            joint,
            stiffness,
            reason,
            iteration,
            history,
            last,
        },
        other => other,
    }
}

/// Whether joint `j` is assembled softer than its law (Newton's traction
/// form carries its stiffness).
fn softened(setup: &Setup, j: usize) -> bool {
    setup
        .model
        .joints
        .get(j)
        .is_some_and(|p| p.assembled != p.springs)
}

/// `k h / E` above which a stall is blamed on the joint's stiffness: every
/// method converged on Scene P up to 1 and stalled at 12.5 (case 3 of
/// crates/solver/tests/stability.rs).
const STIFF_JOINT: f64 = 5.0;

/// The no-equilibrium error, naming the joint with the largest residual `f`.
pub(super) fn no_equilibrium(
    setup: &Setup,
    f: &[f64],
    reason: &str,
    last: IterationRecord,
    history: Vec<IterationRecord>,
) -> IterationError {
    let worst = worst_joint(setup, f);
    let joint = if bodies_carry_most(setup, f) {
        super::types::PLASTIC_BODIES.to_string()
    } else {
        joint_name(setup, worst)
    };
    // A joint much stiffer than its bodies (k h / E >> 1) makes every
    // method that keeps it in K_m crawl (docs/stability.md, case 3), which
    // looks like no equilibrium: not reported as one. Newton assembles it
    // softer and iterates on its tractions: there a stall of a load step
    // is what it is for a soft joint (the blocks beyond capacity at
    // k h / E = 10 to 1e4, crates/solver/tests/stiff_limits.rs); a
    // one-shot run's is judged by `one_shot_verdict`.
    let stiffness = joint_stiffness_ratio(setup, worst);
    if stiffness > STIFF_JOINT && !softened(setup, worst) && joint != super::types::PLASTIC_BODIES {
        return IterationError::StiffJoint {
            last: None,
            joint,
            stiffness,
            reason: reason.to_string(),
            iteration: last.iteration,
            history,
        };
    }
    IterationError::NoEquilibrium {
        last: None,
        joint,
        reason: reason.to_string(),
        open: last.open,
        slip: last.slip,
        total: last.open + last.slip + last.stick,
        iteration: last.iteration,
        history,
    }
}

/// A converged state whose displacements leave `imbalance` of the load
/// unbalanced (the sweep's `imbalance`): no equilibrium (the joints'
/// states make a mechanism), naming the joint with the most open or
/// sliding pairs in `ev`.
pub(super) fn unbalanced(
    setup: &Setup,
    ev: &Eval,
    imbalance: f64,
    history: Vec<IterationRecord>,
) -> IterationError {
    let reason = format!(
        "the residual converged, but the reactions miss {:.1} % of the load: the open and sliding joints or the yielding soil leave a body free to move (a mechanism), and the displacements grew until rounding made them meaningless",
        100.0 * imbalance
    );
    mechanism(setup, ev, reason, history)
}

/// A converged step whose displacements grew `ratio` times faster with
/// the load than in the path's first step: no equilibrium, a mechanism
/// the residual cannot see (the joints carry their strength whatever the
/// motion along it).
pub(super) fn runaway(setup: &Setup, ev: &Eval, ratio: f64, history: Vec<IterationRecord>) -> IterationError {
    let reason = format!(
        "the residual converged, but the displacements grew {ratio:.1e} times faster with the load than in the first step: the open and sliding joints or the yielding soil leave a body free to move (a mechanism), so the displacements are arbitrary"
    );
    mechanism(setup, ev, reason, history)
}

/// No equilibrium for `reason`, naming the joint with the most open or
/// sliding pairs in `ev`.
fn mechanism(setup: &Setup, ev: &Eval, reason: String, history: Vec<IterationRecord>) -> IterationError {
    let n_p = setup.points.len().max(1);
    let mut yielded = vec![0usize; setup.model.mesh.joints.len()];
    let (mut open, mut slip) = (0, 0);
    for (i, state) in ev.state.iter().enumerate() {
        match state {
            JointState::Open => open += 1,
            JointState::Slip => slip += 1,
            JointState::Stick => continue,
        }
        if let Some(y) = yielded.get_mut(setup.points[i % n_p].joint) {
            *y += 1;
        }
    }
    let worst = (0..yielded.len()).max_by_key(|&j| yielded[j]).unwrap_or(0);
    let yielding = ev.yielding.iter().filter(|&&y| y).count();
    let joint = if yielding > 0 && yielded.get(worst).is_none_or(|&n| n == 0) {
        super::types::PLASTIC_BODIES.to_string()
    } else {
        joint_name(setup, worst)
    };
    IterationError::NoEquilibrium {
        last: None,
        joint,
        reason,
        open,
        slip,
        total: ev.state.len(),
        iteration: history.last().map_or(0, |r| r.iteration),
        history,
    }
}
