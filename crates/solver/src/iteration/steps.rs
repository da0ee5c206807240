//! Proportional loading `lambda F` in steps with the history law
//! ([`crate::joint_law::history_response`]), and the step control.
//!
//! Each step is solved by the scene's method on the elastic factors (no
//! factorization per step), warm-started from the released forces of the
//! last converged step. Within a step the law is continuous
//! ([`crate::joint_law::history_response`]: tension capped at the strength
//! left, the shear strength of an opening pair fading with its opening);
//! once the step has converged, every intact point whose trial normal
//! stress exceeds its tensile strength debonds (loses it; the cohesion
//! stays), and where that strength was not 0 the step is solved again
//! ("rounds", at most [`MAX_ROUNDS`]: the debonded set only grows). A
//! converged step commits the history (plastic slip, debonding); a failed
//! attempt leaves the committed state as it was.
//!
//! Step control: the first increment is the whole load ([`crate::scene::Loading::Auto`]) or
//! `1 / N`; a step that does not converge is cut back by half (the failed
//! load is remembered); after an easy converged step the increment doubles
//! (up to its cap), but never past a load that failed; a failed load is
//! retried once the increment reaches it. The run ends at `lambda = 1`, or
//! when a load fails at most [`BRACKET`] (relative) or [`MIN_INCREMENT`]
//! (absolute) above the last converged one: that load factor is the limit
//! load factor, bracketed by the failed one; or after [`MAX_CUTBACKS`]
//! failures in a row (a load that ran out of its iteration budget is first
//! tried once more with [`CLASSIFY_BUDGET`] times it). With
//! [`StepControl::check_path`] (`"auto"`) a step is first solved only to
//! the accuracy of the path check ([`PATH_ACCURACY`]); if points lost
//! strength in it, it is solved again as two halves and retried at half
//! size when they end more than [`PATH_TOL`] away from it (the first half
//! is that attempt), else the halves are kept; if none did, it is
//! converged the rest of the way.
//!
//! The residual ratio of every step is relative to the same reference
//! ([`reference_release`]: the released forces of the elastic
//! solution of the whole load under the paper's law, the `Psi_0` of a
//! one-shot run), so a step is converged to the same absolute accuracy
//! whatever its size.

use super::attempt::{Converged, Start};
use super::diagnosis::{runaway, unbalanced};
use super::method;
use super::release::reference_release;
use super::setup::Setup;
use super::state::History;
use super::state::LoadState;
use super::sweep::{Sweep, IMBALANCE_TOL, OBSERVED_UP_TO};
use super::types::StepBodies;
use super::types::{
    solves, IterationError, IterationRecord, IterationSettings, JointField, Outcome, StageEnd,
};
use crate::joint_law::{commit, exceeds_tensile_strength, state_counts, PointHistory};
use crate::scene::JointLaw;
use crate::solution::Displacements;
use serde::{Deserialize, Serialize};

/// Relative width of the bracket on the limit load factor.
pub const BRACKET: f64 = 0.01;
/// The smallest load increment (absolute, a fraction of the load).
pub const MIN_INCREMENT: f64 = 1e-4;
/// Consecutive failed attempts after which the run stops where it is (a
/// limit load only if the last failure found no equilibrium).
pub const MAX_CUTBACKS: u32 = 12;
/// Debonding rounds within one step before the step counts as failed.
pub const MAX_ROUNDS: u32 = 50;
/// A converged step with at most this many iterations (Newton steps or
/// fixed-point iterations, summed over its rounds) lets the increment grow.
pub const EASY_ITERATIONS: usize = 12;

/// A run about to stop on a load whose iteration ran out of its budget
/// while still converging tries that load once more with this many times
/// the budget: near the capacity Newton creeps, and the longer run either
/// converges or shows the stall of no equilibrium (an anchor pulled at an
/// angle: "not converged" at 500 sweeps, the stall at 1000).
pub const CLASSIFY_BUDGET: u32 = 4;

/// Largest change of the joint nodes' displacements at the sections
/// (relative, L2) between one step and its two halves that `"auto"`
/// accepts (the path check).
pub const PATH_TOL: f64 = 0.01;
/// Steps at most this long (a fraction of the load) are not path-checked.
pub const PATH_MIN: f64 = 1.0 / 64.0;
/// A checked step is first converged to `epsilon` no tighter than this
/// times [`PATH_TOL`]: enough to compare it with its halves; kept only
/// after converging the rest of the way.
pub const PATH_ACCURACY: f64 = 0.1;

/// A converged step whose loaded model moved this many times faster with
/// the load than in the path's first step is a mechanism, not an
/// equilibrium: the joints (or the yielding soil) carry their strength
/// whatever the motion along it, so the residual converges and the
/// displacement is arbitrary (a plate anchor pulled at an angle, all its
/// interface points open or sliding: about twice the first step's rate one
/// step before its capacity, 2.1e9 times at it; docs/loading.md).
pub const RUNAWAY: f64 = 1e6;

/// How the load is raised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepControl {
    /// The first increment.
    pub first: f64,
    /// The largest increment.
    pub max: f64,
    /// Whether a step that debonded points (more than one round) is
    /// compared with its two halves and cut back when they differ by more
    /// than [`PATH_TOL`] (the history law is path-dependent).
    pub check_path: bool,
}

impl StepControl {
    /// The whole load first, growth up to the whole load, the path check.
    pub const AUTO: StepControl = StepControl {
        first: 1.0,
        max: 1.0,
        check_path: true,
    };

    /// Increments of at most `1 / n` (no path check: the user's steps).
    pub fn steps(n: u32) -> StepControl {
        let d = 1.0 / n.max(1) as f64;
        StepControl {
            first: d,
            max: d,
            check_path: false,
        }
    }
}

/// One converged load step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LoadStep<T> {
    /// Load factor lambda at the end of the step.
    pub lambda: f64,
    /// Iterations (Newton steps or fixed-point iterations) over its rounds.
    pub iterations: usize,
    /// Back-substitution sweeps it cost (failed attempts before it included).
    pub solves: u32,
    /// Debonding rounds.
    pub rounds: u32,
    /// Attempts that failed before it converged.
    pub cutbacks: u32,
    /// Open, slipping and sticking (point, section) pairs.
    pub open: usize,
    /// Slipping pairs.
    pub slip: usize,
    /// Sticking pairs.
    pub stick: usize,
    /// What the caller measured at this step.
    pub observed: T,
}

/// Where the load could not be raised further.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LimitLoad {
    /// The last converged load factor (the limit load factor).
    pub factor: f64,
    /// The smallest load factor that failed from it.
    pub failed_at: f64,
    /// Why the failed step did not converge.
    pub reason: String,
    /// Whether the failure shows that the load exceeds what the joints
    /// carry (the iteration found no equilibrium). `false`: it stopped for
    /// another reason (a joint much stiffer than its elements, the iteration
    /// limit), and the factor is only how far the run got.
    pub beyond_capacity: bool,
}

/// The load path of a stepped run.
#[derive(Clone, Debug)]
pub struct Stepped<T> {
    /// The converged steps.
    pub steps: Vec<LoadStep<T>>,
    /// Set when the whole load could not be reached.
    pub limit: Option<LimitLoad>,
}

/// Solves the problem of `setup` by proportional loading with the history
/// law: the solution at the last converged load factor (the whole load if
/// the path has no limit; its history is that step's) and the path.
/// `observe` sees the displacements, joint field and (with plastic bodies)
/// the released nodal forces of every converged step: the displacements of harmonics
/// 0..=[`OBSERVED_UP_TO`](super::sweep::OBSERVED_UP_TO) (the others are
/// absent), and of every harmonic at the step that reaches the whole load.
pub(super) fn stepped<T>(
    setup: &Setup,
    control: StepControl,
    settings: &IterationSettings,
    progress: &mut dyn FnMut(&IterationRecord),
    mut observe: impl FnMut(f64, &Displacements, &JointField, &StepBodies) -> T,
) -> Result<(Outcome, Stepped<T>, StageEnd), IterationError> {
    // The reference Psi_0: the paper-law release of the elastic solution.
    let mut run = Run {
        setup,
        psi_ref: reference_release(setup),
        progress,
    };
    let mut path = Path::new(setup);
    let mut delta = control.first.clamp(MIN_INCREMENT, 1.0);
    let mut failed_at: Option<f64> = None;
    let mut reuse: Option<Accepted> = None;
    // Whether this attempt is the retry with the larger budget.
    let mut classify = false;
    let limit = loop {
        let lam_c = path.lam_c;
        // Within rounding of the whole load: the whole load (N steps of 1 / N
        // add up to 1 - 1e-16, and a step of that size is noise).
        let target = if lam_c + delta >= 1.0 - 1e-9 {
            1.0
        } else {
            lam_c + delta
        };
        // A step the path check already solved (the first half of a
        // rejected one) is not solved again (but checked).
        let solved = reuse.take().filter(|step| (step.0 - target).abs() <= 1e-12);
        let budget = IterationSettings {
            max_iterations: settings.max_iterations.saturating_mul(CLASSIFY_BUDGET),
            ..*settings
        };
        let base = Base {
            history: &path.committed,
            conv: path.last.as_ref().map(|(c, _)| c),
            before: path.before.as_ref().map(|(lam, x)| (*lam, x.as_slice())),
        };
        let attempt = run.take_step(
            base,
            (lam_c, target),
            control.check_path && target - lam_c > PATH_MIN,
            solved,
            if classify { &budget } else { settings },
            &mut path.spent,
        );
        let retried = std::mem::take(&mut classify);
        let failure = match attempt {
            Ok(Taken::Rejected(first)) => {
                delta = 0.5 * (target - lam_c);
                reuse = Some(*first);
                None
            }
            Ok(Taken::Steps(accepted)) => {
                let (easy, failed) = path.accept(setup, accepted, &mut observe);
                let lam_c = path.lam_c;
                if failed.is_none() {
                    if lam_c >= 1.0 {
                        break None;
                    }
                    if failed_at.is_some_and(|f| f <= lam_c) {
                        failed_at = None;
                    }
                    if failed_at.is_none() && easy {
                        delta = (2.0 * delta).min(control.max);
                    }
                    if let Some(f) = failed_at {
                        delta = delta.min(f - lam_c);
                    }
                }
                failed
            }
            Err(IterationError::Setup(e)) => return Err(IterationError::Setup(e)),
            Err(IterationError::Cancelled) => return Err(IterationError::Cancelled),
            Err(e) => Some((target, e)),
        };
        if let Some((target, e)) = failure {
            let lam_c = path.lam_c;
            path.cutbacks += 1;
            path.spent += solves(e.history());
            failed_at = Some(failed_at.map_or(target, |f| f.min(target)));
            let gap = target - lam_c;
            if gap <= (BRACKET * lam_c).max(MIN_INCREMENT) || path.cutbacks > MAX_CUTBACKS {
                if !retried && matches!(e, IterationError::NotConverged { .. }) {
                    classify = true;
                    delta = gap;
                    continue;
                }
                break Some(LimitLoad {
                    factor: lam_c,
                    failed_at: target,
                    reason: e.to_string(),
                    beyond_capacity: matches!(e, IterationError::NoEquilibrium { .. }),
                });
            }
            delta = (0.5 * gap).max(MIN_INCREMENT);
        }
    };
    Ok(path.finish(setup, limit))
}

/// The committed state of a stepped run: the history, released forces and
/// load factor of the last converged step, that step (and its
/// displacements if they hold every harmonic), the load factor and
/// released forces of the one before, the steps so far, and the failed
/// attempts since the last converged step and their solves.
struct Path<T> {
    committed: History,
    x_c: Vec<f64>,
    lam_c: f64,
    last: Option<(Converged, Option<Displacements>)>,
    before: Option<(f64, Vec<f64>)>,
    steps: Vec<LoadStep<T>>,
    cutbacks: u32,
    spent: u32,
    /// Harmonics 0..=[`OBSERVED_UP_TO`] of the last converged step (`None`
    /// with `u_known`: zero, the unloaded start).
    u_c: Option<Displacements>,
    /// Whether the displacements at `lam_c` are known (not at the start of
    /// a stage after another).
    u_known: bool,
    /// The displacement rate (max |du| / dlambda) of the first step whose
    /// start is known.
    rate_ref: Option<f64>,
}

impl<T> Path<T> {
    /// Before the first step: the joints as they start, no load; or the
    /// state a stage of loading starts from.
    fn new(setup: &Setup) -> Self {
        if let Some(end) = setup.resume {
            let conv = Converged::new(end.x.clone(), end.y.clone(), end.ev.clone(), end.records.clone());
            return Path {
                committed: end.history.clone(),
                x_c: end.x.clone(),
                lam_c: 0.0,
                last: Some((conv, None)),
                before: None,
                steps: Vec::new(),
                cutbacks: 0,
                spent: 0,
                u_c: None,
                u_known: false,
                rate_ref: None,
            };
        }
        let committed = History {
            joints: (0..setup.n_pairs())
                .map(|k| PointHistory {
                    debonded: setup.start.debonded.get(k).copied().unwrap_or(false),
                    ..PointHistory::default()
                })
                .collect(),
            plastic: vec![[0.0; 6]; setup.sections().len() * setup.body_points()],
        };
        Path {
            committed,
            x_c: vec![0.0; setup.len()],
            lam_c: 0.0,
            last: None,
            before: None,
            steps: Vec::new(),
            cutbacks: 0,
            spent: 0,
            u_c: None,
            u_known: true,
            rate_ref: None,
        }
    }

    /// Commits the converged steps `accepted` in order while their
    /// displacements balance the load; `observe` sees each. Returns whether
    /// every committed step was easy, and the load factor whose step left
    /// the load unbalanced, with that error.
    fn accept(
        &mut self,
        setup: &Setup,
        accepted: Vec<Accepted>,
        observe: &mut impl FnMut(f64, &Displacements, &JointField, &StepBodies) -> T,
    ) -> (bool, Option<(f64, IterationError)>) {
        let mut easy = true;
        for (target, conv, rounds, hist) in accepted {
            let sweep = Sweep::new(setup, LoadState::stepped(target, &hist));
            // Every harmonic at the whole load (the outcome's), the loaded
            // faces' ones before.
            let displacements = if target >= 1.0 {
                sweep.full_displacements(&conv.x)
            } else {
                sweep.observed_displacements(&conv.x)
            };
            // A converged residual is not yet an equilibrium.
            let imbalance = sweep.imbalance(&conv.x, &displacements);
            if imbalance > IMBALANCE_TOL {
                let e = unbalanced(setup, &conv.ev, imbalance, conv.history);
                return (easy, Some((target, e)));
            }
            // Nor is a converged residual a bounded motion (RUNAWAY).
            if self.u_known {
                let rate = largest_change(&displacements, self.u_c.as_ref()) / (target - self.lam_c).abs();
                match self.rate_ref {
                    Some(r) if rate > RUNAWAY * r => {
                        let e = runaway(setup, &conv.ev, rate / r, conv.history);
                        return (easy, Some((target, e)));
                    }
                    None if rate > 0.0 && rate.is_finite() => self.rate_ref = Some(rate),
                    _ => {}
                }
            }
            self.u_c = Some(observed_part(&displacements));
            self.u_known = true;
            let field = sweep.field(&conv.ev);
            let bodies = StepBodies {
                released: sweep.released_loads(&conv.x),
                plastic_volume: sweep.plastic_volume(&conv.ev),
            };
            self.committed = hist;
            self.before = Some((self.lam_c, std::mem::replace(&mut self.x_c, conv.x.clone())));
            self.lam_c = target;
            let observed = observe(self.lam_c, &displacements, &field, &bodies);
            let (open, slip, stick) = state_counts(&conv.ev.state);
            let iterations = conv.history.len();
            easy &= iterations <= EASY_ITERATIONS;
            self.steps.push(LoadStep {
                lambda: self.lam_c,
                iterations,
                solves: self.spent + solves(&conv.history),
                rounds,
                cutbacks: self.cutbacks,
                open,
                slip,
                stick,
                observed,
            });
            self.last = Some((conv, (target >= 1.0).then_some(displacements)));
            (self.cutbacks, self.spent) = (0, 0);
        }
        (easy, None)
    }

    /// The outcome at the last converged load (lambda = 0: the unloaded
    /// state), and the path to it (`limit`: where it stopped short).
    fn finish(self, setup: &Setup, limit: Option<LimitLoad>) -> (Outcome, Stepped<T>, StageEnd) {
        let Path {
            committed,
            x_c,
            lam_c,
            last,
            steps,
            ..
        } = self;
        let sweep = Sweep::new(setup, LoadState::stepped(lam_c, &committed));
        let (conv, displacements) = match last {
            // Joint blocks only: the whole displacements once, at the end.
            Some((conv, displacements)) => {
                let displacements = displacements.unwrap_or_else(|| sweep.full_displacements(&x_c));
                (conv, displacements)
            }
            None => {
                let mut released = setup.transfer.zeros();
                let mut ev = setup.new_eval();
                sweep.evaluate(&x_c, &mut released, &mut ev);
                let displacements = sweep.full_displacements(&x_c);
                (Converged::new(x_c, Vec::new(), ev, Vec::new()), displacements)
            }
        };
        let end = StageEnd {
            x: conv.x.clone(),
            y: conv.y.clone(),
            ev: conv.ev.clone(),
            records: conv.history.clone(),
            history: committed.clone(),
        };
        (
            sweep.finish_with(conv, displacements),
            Stepped { steps, limit },
            end,
        )
    }
}

/// The committed history after converged step `conv` from its trial
/// history `hist` (the committed one with the step's debonded points),
/// with the step's plastic slip.
fn commit_history(setup: &Setup, mut hist: History, conv: &Converged) -> History {
    hist.plastic.clone_from(&conv.ev.plastic);
    for (i, h) in hist.joints.iter_mut().enumerate() {
        let springs = setup.springs(i);
        commit(
            &springs,
            conv.ev.d[i],
            setup.t0(i),
            conv.ev.p[i],
            conv.ev.state[i],
            h,
        );
    }
    hist
}

/// Where a step starts: the released forces and Newton's unknowns of the
/// last converged step `conv`; before the first, zero forces.
fn start_after(setup: &Setup, conv: Option<&Converged>, psi_ref: f64) -> Start {
    Start {
        x0: conv.map_or_else(|| vec![0.0; setup.len()], |c| c.x.clone()),
        y0: conv.map(|c| c.y.clone()),
        psi_ref: Some(psi_ref),
        u_s: None,
        predicted: None,
    }
}

/// The step from `base` to load factor `target`, with plastic bodies also
/// the released forces of `base`'s last two converged steps extrapolated
/// linearly to `target` (plastic flow goes on as it went: on the
/// tutorial's pile in clay the prediction halves the Newton steps of a
/// load step).
fn predicted_start(setup: &Setup, base: Base, lam_c: f64, target: f64, psi_ref: f64) -> Start {
    let mut start = start_after(setup, base.conv, psi_ref);
    if setup.bodies.is_none() {
        return start;
    }
    if let (Some(conv), Some((lam_b, x_b))) = (base.conv, base.before) {
        if lam_c > lam_b && x_b.len() == conv.x.len() {
            let f = (target - lam_c) / (lam_c - lam_b);
            start.predicted = Some(conv.x.iter().zip(x_b).map(|(c, b)| c + f * (c - b)).collect());
        }
    }
    start
}

/// A converged step: its load factor, solution, rounds, committed history.
type Accepted = (f64, Converged, u32, History);

/// What an attempt at a step gave.
enum Taken {
    /// Converged steps to commit in order (the step, or its two halves).
    Steps(Vec<Accepted>),
    /// The path check found the step too long: its first half (converged),
    /// the next attempt.
    Rejected(Box<Accepted>),
}

/// Where a step starts: the committed history and the last converged step
/// (none before the first), and the load factor and released forces of the
/// converged step before that.
#[derive(Clone, Copy)]
struct Base<'p> {
    history: &'p History,
    conv: Option<&'p Converged>,
    before: Option<(f64, &'p [f64])>,
}

/// What every step of a run shares: the fixed data, the reference `Psi_0`
/// of the residual ratio, and the progress callback.
struct Run<'r, 's, 'a> {
    setup: &'s Setup<'a>,
    psi_ref: f64,
    progress: &'r mut dyn FnMut(&IterationRecord),
}

impl Run<'_, '_, '_> {
    /// One attempt at the step `at` = (from, to) load factor from `base`;
    /// `solved` is the step if the path check already solved it (the
    /// first half of a rejected one). With `check` (the path check) a new
    /// step is first solved only to the accuracy the comparison needs
    /// ([`PATH_ACCURACY`]); if points lost strength in it
    /// ([`lost_strength`]) it is compared with its two halves (solved to
    /// the full accuracy, and kept when they agree), else converged the
    /// rest of the way. `spent` adds the solves of what is not kept.
    fn take_step(
        &mut self,
        base: Base,
        at: (f64, f64),
        check: bool,
        solved: Option<Accepted>,
        settings: &IterationSettings,
        spent: &mut u32,
    ) -> Result<Taken, IterationError> {
        let (lam_c, target) = at;
        // The whole step, and its trial history if it is solved loosely.
        let (whole, loose) = match solved {
            Some(step) => (step, None),
            None => {
                let loose = IterationSettings {
                    epsilon: settings.epsilon.max(PATH_ACCURACY * PATH_TOL),
                    ..*settings
                };
                let mut trial = base.history.clone();
                let start = predicted_start(self.setup, base, lam_c, target, self.psi_ref);
                let (conv, rounds) =
                    self.solve_step(target, &mut trial, start, if check { &loose } else { settings })?;
                let loose_trial = check.then(|| trial.clone());
                let hist = commit_history(self.setup, trial, &conv);
                ((target, conv, rounds, hist), loose_trial)
            }
        };
        if !check || !lost_strength(self.setup, base.history, &whole.3) {
            return self.keep(whole, loose, settings);
        }
        let mid = lam_c + 0.5 * (target - lam_c);
        match self.halves(base, (mid, target), settings) {
            Ok((first, second)) => {
                *spent += solves(&whole.1.history);
                if path_change(&whole.1.ev.u_s, &second.1.ev.u_s) > PATH_TOL {
                    *spent += solves(&second.1.history);
                    return Ok(Taken::Rejected(Box::new(first)));
                }
                Ok(Taken::Steps(vec![first, second]))
            }
            // The halves failed where the whole step converged: the whole step.
            Err(e) => {
                *spent += solves(e.history());
                self.keep(whole, loose, settings)
            }
        }
    }

    /// The whole step kept: converged the rest of the way if it was solved
    /// loosely (`loose`: its trial history) and is short of epsilon.
    fn keep(
        &mut self,
        whole: Accepted,
        loose: Option<History>,
        settings: &IterationSettings,
    ) -> Result<Taken, IterationError> {
        let (lambda, conv, rounds, hist) = whole;
        let short = conv.history.last().is_some_and(|r| r.ratio >= settings.epsilon);
        match loose.filter(|_| short) {
            Some(trial) => {
                let step = self.polish(lambda, trial, conv, rounds, settings)?;
                Ok(Taken::Steps(vec![step]))
            }
            None => Ok(Taken::Steps(vec![(lambda, conv, rounds, hist)])),
        }
    }

    /// Converges step `conv` (at load factor `lambda`, solved to a looser
    /// epsilon in `rounds` debonding rounds, leaving the `trial` history)
    /// to the accuracy of `settings`, from where it is; its history holds
    /// both.
    fn polish(
        &mut self,
        lambda: f64,
        mut trial: History,
        mut conv: Converged,
        rounds: u32,
        settings: &IterationSettings,
    ) -> Result<Accepted, IterationError> {
        let mut records = std::mem::take(&mut conv.history);
        let start = Start::resume(conv, Some(self.psi_ref));
        let (mut conv, more) = self
            .solve_step(lambda, &mut trial, start, settings)
            .map_err(|mut e| {
                e.prepend_history(&records);
                e
            })?;
        records.append(&mut conv.history);
        conv.history = records;
        let hist = commit_history(self.setup, trial, &conv);
        Ok((lambda, conv, rounds + more - 1, hist))
    }

    /// The two halves of a step from `base` to `at` = (mid, end).
    fn halves(
        &mut self,
        base: Base,
        at: (f64, f64),
        settings: &IterationSettings,
    ) -> Result<(Accepted, Accepted), IterationError> {
        let mut h1 = base.history.clone();
        let start = start_after(self.setup, base.conv, self.psi_ref);
        let (c1, r1) = self.solve_step(at.0, &mut h1, start, settings)?;
        let h1 = commit_history(self.setup, h1, &c1);
        let mut h2 = h1.clone();
        let start = start_after(self.setup, Some(&c1), self.psi_ref);
        let (c2, r2) = self.solve_step(at.1, &mut h2, start, settings)?;
        let h2 = commit_history(self.setup, h2, &c2);
        Ok(((at.0, c1, r1, h1), (at.1, c2, r2, h2)))
    }

    /// One step at load factor `lambda` from `history`: the method's
    /// solve, then debonding rounds. Adds the new debonded points to
    /// `history` (the step's trial history).
    fn solve_step(
        &mut self,
        lambda: f64,
        history: &mut History,
        mut start: Start,
        settings: &IterationSettings,
    ) -> Result<(Converged, u32), IterationError> {
        let setup = self.setup;
        let psi_ref = start.psi_ref;
        let mut records = Vec::new();
        for round in 1..=MAX_ROUNDS {
            let sweep = Sweep::new(setup, LoadState::stepped(lambda, history));
            let mut conv = method::run(&sweep, settings, start, self.progress).map_err(|f| {
                let mut e = f.error;
                e.prepend_history(&records);
                e
            })?;
            // The intact pairs above their tensile strength.
            let n_p = setup.points.len().max(1);
            let joints = &history.joints;
            let breaking: Vec<usize> = (0..joints.len())
                .filter(|&i| {
                    let info = &setup.points[i % n_p];
                    let t = setup.trial(info.joint, conv.ev.d[i], Some(&joints[i]), setup.t0(i));
                    exceeds_tensile_strength(&setup.laws[info.joint], t[1], &joints[i])
                })
                .collect();
            // Debonding takes only the tensile strength: where it is 0 the law
            // is the same before and after, and the step need not be solved again.
            let debonded = breaking
                .iter()
                .filter(|&&i| has_tensile_strength(&setup.laws[setup.points[i % n_p].joint]))
                .count();
            for i in breaking {
                history.joints[i].debonded = true;
            }
            records.append(&mut conv.history);
            if debonded == 0 {
                conv.history = records;
                return Ok((conv, round));
            }
            start = Start::resume(conv, psi_ref);
        }
        Err(IterationError::Rounds {
            rounds: MAX_ROUNDS,
            history: records,
        })
    }
}

/// Whether a pair debonded from `committed` to `trial` whose law had a
/// tensile strength to lose: only then does the answer depend on where in
/// the step it debonded (debonding takes nothing else, so a pair without
/// one behaves the same intact or debonded).
fn lost_strength(setup: &Setup, committed: &History, trial: &History) -> bool {
    let n_p = setup.points.len().max(1);
    committed
        .joints
        .iter()
        .zip(&trial.joints)
        .enumerate()
        .any(|(i, (c, t))| {
            t.debonded && !c.debonded && has_tensile_strength(&setup.laws[setup.points[i % n_p].joint])
        })
}

/// Whether a law has a tensile strength to lose.
fn has_tensile_strength(law: &JointLaw) -> bool {
    matches!(law, JointLaw::MohrCoulomb(mc) if mc.tensile_strength > 0.0)
}

/// `|a - b| / |b|` (L2) of two section displacements of the joint nodes.
fn path_change(a: &[f64], b: &[f64]) -> f64 {
    let (mut diff, mut norm) = (0.0, 0.0);
    for (va, vb) in a.iter().zip(b) {
        diff += (va - vb) * (va - vb);
        norm += vb * vb;
    }
    if norm > 0.0 {
        (diff / norm).sqrt()
    } else {
        0.0
    }
}

/// Harmonics 0..=[`OBSERVED_UP_TO`] of `u` (what every step has).
fn observed_part(u: &Displacements) -> Displacements {
    Displacements {
        harmonics: u
            .harmonics
            .iter()
            .filter(|d| d.m <= OBSERVED_UP_TO)
            .cloned()
            .collect(),
    }
}

/// The largest change of a node-DOF amplitude of harmonics
/// 0..=[`OBSERVED_UP_TO`] from `before` (`None`: zero) to `u`.
fn largest_change(u: &Displacements, before: Option<&Displacements>) -> f64 {
    let mut out = 0.0f64;
    for d in u.harmonics.iter().filter(|d| d.m <= OBSERVED_UP_TO) {
        let b = before.and_then(|b| b.harmonics.iter().find(|e| e.m == d.m));
        for (k, now) in [&d.symmetric, &d.antisymmetric].into_iter().enumerate() {
            let was = b.map(|e| if k == 0 { &e.symmetric } else { &e.antisymmetric });
            for (i, v) in now.iter().enumerate() {
                let w = was.and_then(|w| w.get(i)).copied().unwrap_or(0.0);
                out = out.max((v - w).abs());
            }
        }
    }
    out
}
