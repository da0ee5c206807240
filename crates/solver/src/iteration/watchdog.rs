//! The watchdog of Newton's line search (Chamberlain, Powell, Lemarechal
//! and Pedersen 1982): where the line search has accepted only short
//! steps several times in a row, the whole Newton step is taken from a
//! checkpoint even though `|R|` grows; if `|R|` has not fallen below the
//! checkpoint's within [`WATCH_STEPS`] steps, the run goes back there.
//!
//! Why: with a joint much stiffer than the springs assembled in K (the
//! traction form), a point that has just started to slip can turn its
//! traction almost freely (the tangent's stiffness along the turn is
//! `k_a / k` plus the slip over the strength), so the Newton step turns
//! such tractions by tens of degrees where the residual is tiny. `|R|`
//! then grows as the square of the step (the traction leaves the circle
//! of its strength by `r theta^2 / 2`) and the monotone line search keeps
//! a fraction of a percent of each step; the whole step lands next to the
//! solution's states, and the next steps converge from there (the
//! Maratos effect of constrained optimization).

use super::eval::Eval;
use super::formulation::{CRAWL_LAMBDA, CRAWL_STEPS, WATCH_STEPS};

/// An iterate to return to: `y`, its evaluation, residual and `|R|`.
pub(super) struct Checkpoint {
    pub(super) y: Vec<f64>,
    pub(super) acc: Eval,
    pub(super) res: Vec<f64>,
    pub(super) r_norm: f64,
}

/// What the watchdog says after a step.
pub(super) enum Verdict {
    /// Nothing to do.
    Go,
    /// Go back to the checkpoint.
    Return(Box<Checkpoint>),
}

/// The watchdog's state over one Newton solve.
pub(super) struct Watchdog {
    on: bool,
    /// Accepted line-search steps in a row at `lambda <= CRAWL_LAMBDA`.
    short: u32,
    /// The checkpoint while a relaxed step is watched, and the steps left.
    saved: Option<(Box<Checkpoint>, u32)>,
}

impl Watchdog {
    pub(super) fn new(on: bool) -> Self {
        Watchdog {
            on,
            short: 0,
            saved: None,
        }
    }

    /// Whether this step is to be the whole Newton step.
    pub(super) fn relax(&self) -> bool {
        self.on && self.saved.is_none() && self.short >= CRAWL_STEPS
    }

    /// Watches the relaxed step taken from `from`.
    pub(super) fn watch(&mut self, from: Checkpoint) {
        self.saved = Some((Box::new(from), WATCH_STEPS));
        self.short = 0;
    }

    /// Notes the line search's accepted step (`None`: none accepted).
    pub(super) fn note(&mut self, lambda: Option<f64>) {
        match lambda {
            Some(l) if l <= CRAWL_LAMBDA => self.short += 1,
            _ => self.short = 0,
        }
    }

    /// After a step to `|R| = r_norm` (`bad`: not finite, or the released
    /// forces beyond what the residual resolves): whether to go back.
    pub(super) fn verdict(&mut self, r_norm: f64, bad: bool) -> Verdict {
        let Some((saved, left)) = self.saved.take() else {
            return Verdict::Go;
        };
        if !bad && r_norm <= (1.0 - 1e-4) * saved.r_norm {
            return Verdict::Go;
        }
        if bad || left <= 1 {
            return Verdict::Return(saved);
        }
        self.saved = Some((saved, left - 1));
        Verdict::Go
    }

    /// Whether a relaxed step is being watched (the stall and
    /// unresolved-force checks wait for the verdict).
    pub(super) fn watching(&self) -> bool {
        self.saved.is_some()
    }
}
