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

    /// Notes the line search's accepted step (`None`: none accepted). The
    /// watched steps do not count: after a return the checkpoint's next
    /// step is the line search's (the same whole step again from there
    /// would repeat the watch forever, as it did on the pile in soil at
    /// k h / E = 1e6).
    pub(super) fn note(&mut self, lambda: Option<f64>) {
        if self.saved.is_some() {
            return;
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn checkpoint(r_norm: f64) -> Checkpoint {
        let acc = Eval {
            u_s: Vec::new(),
            g: Vec::new(),
            d: Vec::new(),
            p: Vec::new(),
            state: Vec::new(),
            broken: Vec::new(),
            sigma: Vec::new(),
            plastic: Vec::new(),
            yielding: Vec::new(),
        };
        Checkpoint {
            y: Vec::new(),
            acc,
            res: Vec::new(),
            r_norm,
        }
    }

    /// Three short steps relax the next one; a watch whose steps crawl and
    /// stay above the checkpoint returns there after `WATCH_STEPS`; from
    /// there the line search again, until three new short steps (before,
    /// the watched steps' own short steps relaxed the first step after the
    /// return: the same whole step from the same checkpoint, forever).
    #[test]
    fn a_failed_watch_returns_to_the_line_search() {
        let mut w = Watchdog::new(true);
        for _ in 0..CRAWL_STEPS {
            assert!(!w.relax());
            w.note(Some(CRAWL_LAMBDA));
        }
        assert!(w.relax());
        w.watch(checkpoint(1.0));
        for left in (1..=WATCH_STEPS).rev() {
            assert!(w.watching() && !w.relax());
            w.note(Some(CRAWL_LAMBDA / 4.0));
            match w.verdict(2.0, false) {
                Verdict::Go => assert!(left > 1),
                Verdict::Return(c) => assert_eq!((left, c.r_norm), (1, 1.0)),
            }
        }
        assert!(!w.watching());
        for _ in 0..CRAWL_STEPS {
            assert!(!w.relax());
            w.note(Some(CRAWL_LAMBDA));
        }
        assert!(w.relax());
        // A whole step ends a crawl; a watch that gets below its
        // checkpoint stands.
        w.note(Some(1.0));
        assert!(!w.relax());
        w.watch(checkpoint(1.0));
        assert!(matches!(w.verdict(0.5, false), Verdict::Go));
        assert!(!w.watching());
    }
}
