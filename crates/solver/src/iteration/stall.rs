//! The Newton iteration's watch for no equilibrium ([`Stall`]).

use std::collections::VecDeque;

/// The watch for no equilibrium: the smallest `|R|` so far and where, and
/// whether each of the last steps fell back to the plain step.
pub(super) struct Stall {
    /// Steps without a new minimum before no equilibrium is reported.
    window: u32,
    best: f64,
    best_at: u32,
    fallbacks: VecDeque<bool>,
}

impl Stall {
    /// Watching from step `at` on, where `|R| = r_norm`.
    pub(super) fn new(r_norm: f64, window: u32, at: u32) -> Self {
        Stall {
            window,
            best: r_norm,
            best_at: at,
            fallbacks: VecDeque::new(),
        }
    }

    /// Lets `steps` more steps pass before a stall.
    pub(super) fn pause(&mut self, steps: u32) {
        self.best_at += steps;
    }

    /// Notes whether this step fell back to the plain step.
    pub(super) fn fell_back(&mut self, yes: bool) {
        self.fallbacks.push_back(yes);
        if self.fallbacks.len() > self.window as usize {
            self.fallbacks.pop_front();
        }
    }

    /// Why step `step` (`|R| = r_norm`, residual ratio `ratio`) shows no
    /// equilibrium, if it does.
    pub(super) fn reason(&mut self, step: u32, r_norm: f64, ratio: f64) -> Option<String> {
        let reason = if r_norm < 0.99 * self.best {
            self.best = r_norm;
            self.best_at = step;
            None
        } else if step.saturating_sub(self.best_at) >= self.window {
            Some(format!(
                "the Newton residual stalls at ratio {ratio:.3e} (|R| made no new minimum by 1 % in {} steps, {} of which fell back to the plain step: the joint tangent has (almost) no stiffness left along the unbalanced force, and the step the linearization asks for does not reduce the residual)",
                self.window,
                self.fallbacks.iter().filter(|&&f| f).count()
            ))
        } else {
            None
        };
        reason.or_else(|| (ratio > 1e6).then(|| format!("the residual grows (ratio {ratio:.3e})")))
    }
}
