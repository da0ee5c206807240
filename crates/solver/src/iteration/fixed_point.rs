//! The fixed-point iteration `x <- Psi(x)`: the paper's plain iteration and
//! Anderson mixing.

use super::attempt::{Converged, Failure, Start};
use super::diagnosis::{no_equilibrium, not_converged, residual_limit, unresolved};
use super::sweep::Sweep;
use super::types::{IterationError, IterationRecord, IterationSettings};
use std::time::Instant;

/// Anderson mixing (type II) of a fixed point `x = Psi(x)` from the
/// residuals `f = Psi(x) - x`: `x+ = x + f - (dX + dF) gamma` with `gamma`
/// the least-squares fit of `f` by the residual differences `dF`, and the
/// relaxation beta: `x+ = x + beta f - (dX + beta dF) gamma`. Depth 0 is the
/// (relaxed) plain iteration `x+ = x + beta f`.
struct Anderson {
    depth: usize,
    dx: std::collections::VecDeque<Vec<f64>>,
    df: std::collections::VecDeque<Vec<f64>>,
    last: Option<(Vec<f64>, Vec<f64>)>,
}

impl Anderson {
    fn new(depth: usize) -> Self {
        Anderson {
            depth,
            dx: Default::default(),
            df: Default::default(),
            last: None,
        }
    }

    fn reset(&mut self) {
        self.dx.clear();
        self.df.clear();
        self.last = None;
    }

    fn next(&mut self, x: &[f64], f: &[f64], beta: f64) -> Vec<f64> {
        let plain: Vec<f64> = x.iter().zip(f).map(|(a, b)| a + beta * b).collect();
        if self.depth == 0 {
            return plain;
        }
        if let Some((xp, fp)) = self.last.take() {
            self.dx.push_back(x.iter().zip(&xp).map(|(a, b)| a - b).collect());
            self.df.push_back(f.iter().zip(&fp).map(|(a, b)| a - b).collect());
            if self.dx.len() > self.depth {
                self.dx.pop_front();
                self.df.pop_front();
            }
        }
        self.last = Some((x.to_vec(), f.to_vec()));
        let k = self.df.len();
        if k == 0 {
            return plain;
        }
        // Normal equations of min |f - dF gamma|, lightly regularised.
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let mut a = nalgebra::DMatrix::<f64>::zeros(k, k);
        let mut rhs = nalgebra::DVector::<f64>::zeros(k);
        for i in 0..k {
            for j in 0..=i {
                let v = dot(&self.df[i], &self.df[j]);
                a[(i, j)] = v;
                a[(j, i)] = v;
            }
            rhs[i] = dot(&self.df[i], f);
        }
        let trace: f64 = (0..k).map(|i| a[(i, i)]).sum();
        for i in 0..k {
            a[(i, i)] += 1e-12 * trace.max(f64::MIN_POSITIVE);
        }
        let Some(gamma) = a.cholesky().map(|c| c.solve(&rhs)) else {
            self.reset();
            return plain;
        };
        let mut out = plain;
        for (j, g) in gamma.iter().enumerate() {
            for ((o, dx), df) in out.iter_mut().zip(&self.dx[j]).zip(&self.df[j]) {
                *o -= g * (dx + beta * df);
            }
        }
        out
    }
}

/// The fixed-point iteration `x <- Psi(x)`, Anderson-mixed over `depth`
/// iterates (0: the paper's plain iteration), relaxed on cycles.
pub(super) fn fixed_point(
    sweep: &Sweep,
    depth: usize,
    settings: &IterationSettings,
    from: Start,
    progress: &mut dyn FnMut(&IterationRecord),
) -> Result<Converged, Box<Failure>> {
    let start = Instant::now();
    let setup = sweep.setup;
    // x: the released section forces applied; ev.g: those released by the
    // current solution.
    let mut ev = setup.new_eval();
    let warm = from.psi_ref.is_some();
    let mut x = from.x0;
    let mut released = setup.transfer.zeros();
    let mut history = Vec::new();
    let mut mixer = Anderson::new(depth);
    let mut last_f = Vec::new();
    let (mut psi0, mut psi_prev, mut best, mut best_at) = (0.0f64, f64::INFINITY, f64::INFINITY, 0u32);
    // Relaxation of the update, halved on each stall; history start of the
    // current relaxation level (for the limit estimate).
    let (mut damping, mut since) = (1.0f64, 0usize);
    let load_scale = setup.load_scale();

    for it in 1..=settings.max_iterations {
        if setup.cancelled() {
            return Err(Failure::new(IterationError::Cancelled, x, ev));
        }
        // (3) analyse x, (1) solve every harmonic for F + A x, (2) synthesize
        // at the sections, evaluate the law, release: g = Psi(x).
        let u = sweep.evaluate(&x, &mut released, &mut ev);

        // (4) Residual rho = Psi(x) - x per section, and the history.
        let f: Vec<f64> = ev.g.iter().zip(&x).map(|(a, b)| a - b).collect();
        let psi = setup.section_max(&f);
        if it == 1 {
            psi0 = from.psi_ref.unwrap_or(psi);
        }
        let nothing_released = psi0 <= 1e-14 * load_scale.max(f64::MIN_POSITIVE);
        let ratio = if nothing_released { 0.0 } else { psi / psi0 };
        let record = sweep.record(it, ratio, &ev, start, 1);
        progress(&record);
        history.push(record);
        if !ratio.is_finite() || u.iter().flatten().flatten().any(|v| !v.is_finite()) {
            return Err(Failure::new(
                no_equilibrium(setup, &f, "the solution is not finite", record, history),
                x,
                ev,
            ));
        }
        if !nothing_released {
            if let Some(reason) = unresolved(setup, &x, psi0, settings.epsilon) {
                return Err(Failure::new(
                    no_equilibrium(setup, &f, &reason, record, history),
                    x,
                    ev,
                ));
            }
        }
        if nothing_released || ((it > 1 || warm) && ratio < settings.epsilon) {
            return Ok(Converged::new(x.clone(), x, ev, history));
        }
        if it > 1 {
            let stalled = if ratio < best * 0.999 {
                best = ratio;
                best_at = it;
                None
            } else if it - best_at >= settings.stall_window {
                Some(format!(
                    "the residual ratio stalls at {ratio:.3e} (no decrease in {} iterations)",
                    settings.stall_window
                ))
            } else {
                residual_limit(&history[since..], settings.stall_window / 2)
                    .filter(|&limit| limit > settings.epsilon && limit > 0.75 * ratio)
                    .map(|limit| format!("the residual ratio tends to {limit:.3e} > epsilon, not to zero (it is {ratio:.3e})"))
            };
            if let Some(reason) = stalled {
                // A stall whose ratio oscillates is a cycle between joint
                // states (the law with friction is not a projection, and the
                // shear strength drops from C to 0 on opening): relax the
                // update first. A smooth approach to a positive limit is the
                // signature of a load the joints cannot carry.
                let window = &history[history.len().saturating_sub(settings.stall_window as usize)..];
                let (lo, hi) = window.iter().fold((f64::INFINITY, 0.0f64), |(l, h), r| {
                    (l.min(r.ratio), h.max(r.ratio))
                });
                let cycling = hi > 2.0 * lo;
                if cycling && damping > 0.125 {
                    damping *= 0.5;
                    mixer.reset();
                    since = history.len();
                    best = ratio;
                    best_at = it;
                } else {
                    let reason = if cycling {
                        format!("{reason}, also with the update relaxed to 1/8; the ratio oscillates: the iteration cycles between joint states (try more harmonics or sections)")
                    } else {
                        reason
                    };
                    return Err(Failure::new(
                        no_equilibrium(setup, &f, &reason, record, history),
                        x,
                        ev,
                    ));
                }
            }
            if ratio > 1e6 {
                let reason = format!("the residual grows (ratio {ratio:.3e})");
                return Err(Failure::new(
                    no_equilibrium(setup, &f, &reason, record, history),
                    x,
                    ev,
                ));
            }
        }
        // A jump of the residual restarts the mixing from a plain step.
        if psi > 2.0 * psi_prev {
            mixer.reset();
        }
        psi_prev = psi;
        x = mixer.next(&x, &f, damping);
        last_f = f;
    }
    Err(Failure::new(
        not_converged(setup, &last_f, settings, history),
        x,
        ev,
    ))
}
