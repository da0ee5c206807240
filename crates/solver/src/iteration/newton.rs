//! Semi-smooth Newton-Krylov ([`newton`]) on one of two formulations
//! ([`Formulation`]): the released section forces x, `R(x) = Psi(x) - x = 0`
//! ([`Nodal`]), or, where a joint is assembled softer than its law
//! (`k h / E > 1`), the released tractions per (section, point)
//! ([`Traction`]); and its Krylov solver
//! ([`Krylov`]).

use super::attempt::{Converged, Failure, Start};
use super::diagnosis::{no_equilibrium, not_converged, unresolved};
use super::eval::Eval;
use super::formulation::{Formulation, NEWTON_HALVINGS};
use super::release::Tangent;
use super::sweep::Sweep;
use super::traction::Traction;
use super::transfer::JointAmplitudes;
use super::types::{IterationRecord, IterationSettings};
use std::collections::VecDeque;
use std::time::Instant;

/// Newton steps without a 1 % decrease of `|R|` before no equilibrium is
/// reported (measured on the block torsion beyond capacity: 10 to 22 steps,
/// 15 to 25 sweeps from 1.01 to 2 T_max).
const NEWTON_STALL: u32 = 8;

/// The range of the Eisenstat-Walker forcing term (measured on Scene P:
/// an upper bound of 0.5 or 0.1 instead of 0.3 costs 0 to 3 more sweeps).
const NEWTON_ETA_MIN: f64 = 1e-3;
const NEWTON_ETA_MAX: f64 = 0.3;

/// Newton on the released section forces: `R(x) = Psi(x) - x`,
/// `J = D W - I` (D the release tangent,
/// [`release_tangent`](super::release::release_tangent)), unpreconditioned:
/// every joint is assembled as it is (`k h / E <= 1`), where the identity
/// is as good as the harmonic-block preconditioner (measured on Scene P at
/// k_eta h / E = 0.125 to 1).
pub(super) struct Nodal<'s, 'a> {
    sweep: Sweep<'s, 'a>,
    tangents: Vec<Tangent>,
}

impl<'s, 'a> Nodal<'s, 'a> {
    pub(super) fn new(sweep: Sweep<'s, 'a>) -> Self {
        Nodal {
            sweep,
            tangents: vec![None; sweep.setup.n_pairs()],
        }
    }
}

impl Formulation for Nodal<'_, '_> {
    fn sweep(&self) -> &Sweep<'_, '_> {
        &self.sweep
    }

    fn len(&self) -> usize {
        self.sweep.setup.len()
    }

    fn forces(&self, y: &[f64], x: &mut [f64]) {
        x.copy_from_slice(y);
    }

    fn residual(&self, y: &[f64], ev: &mut Eval, res: &mut [f64]) {
        self.sweep.release_all(ev);
        for ((r, g), x) in res.iter_mut().zip(&ev.g).zip(y) {
            *r = g - x;
        }
    }

    fn section_residual(&self, res: &[f64], out: &mut [f64]) {
        out.copy_from_slice(res);
    }

    fn linearize(&mut self, _y: &[f64], ev: &Eval) {
        self.sweep.tangents(ev, &mut self.tangents);
    }

    fn apply_j(&self, z: &[f64], wz: &[f64], out: &mut [f64]) {
        self.sweep.apply_tangent(&self.tangents, wz, out);
        axpy(-1.0, z, out);
    }

    fn precondition(&mut self, _r: &[f64], _released: &mut JointAmplitudes, _out: &mut [f64]) -> bool {
        false
    }

    fn halvings(&self) -> u32 {
        NEWTON_HALVINGS
    }
}

/// Pairs `(z, W G z)` the Newton iteration has paid a sweep for, kept
/// across its steps (W does not depend on the joint states), and the
/// scratch of the Krylov solve. Memory: `3 (KEEP + INNER)` vectors of y's
/// length.
struct Krylov {
    /// Directions z (oldest first) and their images `W G z`.
    z: VecDeque<Vec<f64>>,
    w: VecDeque<Vec<f64>>,
    /// Orthonormal `J p` of this step and their raw coefficients
    /// (`p_j = sum_i t_j[i] z_i`).
    q: Vec<Vec<f64>>,
    t: Vec<Vec<f64>>,
    /// Buffers to reuse.
    spare: Vec<Vec<f64>>,
}

impl Krylov {
    /// Pairs kept from one Newton step to the next.
    const KEEP: usize = 30;
    /// New directions per step at most (GMRES(30)-like memory).
    const INNER: usize = 30;

    fn new() -> Self {
        Krylov {
            z: VecDeque::new(),
            w: VecDeque::new(),
            q: Vec::new(),
            t: Vec::new(),
            spare: Vec::new(),
        }
    }

    fn buffer(&mut self, n: usize) -> Vec<f64> {
        let mut v = self.spare.pop().unwrap_or_default();
        v.clear();
        v.resize(n, 0.0);
        v
    }

    /// Adds a pair paid for elsewhere (e.g. a plain step's sweep).
    fn push(&mut self, z: Vec<f64>, w: Vec<f64>) {
        self.z.push_back(z);
        self.w.push_back(w);
    }

    /// Adds raw direction `i` to the orthonormal set of this step:
    /// `q = J z_i` from its `W G z_i` (no sweep) orthogonalized (modified
    /// Gram-Schmidt, twice) against the previous q; returns whether it was
    /// independent.
    fn orthogonalize(&mut self, form: &dyn Formulation, i: usize, r: &mut [f64], c: &mut [f64]) -> bool {
        let n = r.len();
        let width = Self::KEEP + Self::INNER + 1;
        let mut q = self.buffer(n);
        form.apply_j(&self.z[i], &self.w[i], &mut q);
        let mut t = self.buffer(width);
        t[i] = 1.0;
        let before = norm(&q);
        for _ in 0..2 {
            for (qj, tj) in self.q.iter().zip(&self.t) {
                let h = dot(qj, &q);
                axpy(-h, qj, &mut q);
                axpy(-h, tj, &mut t);
            }
        }
        let nq = norm(&q);
        if nq <= 1e-10 * before || !nq.is_finite() {
            self.spare.push(q);
            self.spare.push(t);
            return false;
        }
        for v in q.iter_mut().chain(t.iter_mut()) {
            *v /= nq;
        }
        let alpha = dot(&q, r);
        axpy(-alpha, &q, r);
        axpy(alpha, &t, c);
        self.q.push(q);
        self.t.push(t);
        true
    }

    /// Solves `J delta = -R` to `|R + J delta| <= eta |R|` by GCR (minimal
    /// residual; in exact arithmetic GMRES) over the kept directions (free:
    /// their `W G z` is known) and at most [`Krylov::INNER`] new ones
    /// `z = M r / |M r|` (one sweep each, at most `budget`; M the
    /// formulation's preconditioner when it has one, else I: flexible GCR).
    /// Writes `delta` and `W G delta`; returns the sweeps paid.
    #[allow(clippy::too_many_arguments)]
    fn solve(
        &mut self,
        form: &mut dyn Formulation,
        residual: &[f64],
        eta: f64,
        budget: u32,
        released: &mut JointAmplitudes,
        x: &mut [f64],
        delta: &mut [f64],
        w_delta: &mut [f64],
    ) -> u32 {
        let n = residual.len();
        while self.z.len() > Self::KEEP {
            if let (Some(z), Some(w)) = (self.z.pop_front(), self.w.pop_front()) {
                self.spare.push(z);
                self.spare.push(w);
            }
        }
        let (q, t) = (std::mem::take(&mut self.q), std::mem::take(&mut self.t));
        self.spare.extend(q.into_iter().chain(t));
        let mut r = self.buffer(n);
        for (ri, v) in r.iter_mut().zip(residual) {
            *ri = -v;
        }
        let target = eta * norm(residual);
        let mut c = vec![0.0; Self::KEEP + Self::INNER + 1];
        for i in 0..self.z.len() {
            self.orthogonalize(form, i, &mut r, &mut c);
        }
        let mut sweeps = 0;
        while norm(&r) > target && sweeps < Self::INNER.min(budget as usize) as u32 {
            let mut z = self.buffer(n);
            if !form.precondition(&r, released, &mut z) {
                z.copy_from_slice(&r);
            }
            let nz = norm(&z);
            if !(nz > 0.0 && nz.is_finite()) {
                self.spare.push(z);
                break;
            }
            for zi in z.iter_mut() {
                *zi /= nz;
            }
            let mut w = self.buffer(w_delta.len());
            form.forces(&z, x);
            form.sweep().apply_w(x, released, &mut w);
            sweeps += 1;
            self.push(z, w);
            if !self.orthogonalize(form, self.z.len() - 1, &mut r, &mut c) {
                break;
            }
        }
        delta.fill(0.0);
        w_delta.fill(0.0);
        for (i, (z, w)) in self.z.iter().zip(&self.w).enumerate() {
            if c[i] != 0.0 {
                axpy(c[i], z, delta);
                axpy(c[i], w, w_delta);
            }
        }
        self.spare.push(r);
        sweeps
    }
}

/// Semi-smooth Newton-Krylov on `R(y) = 0` of the formulation the run
/// needs: [`Traction`] where a joint is assembled softer than its law, else
/// [`Nodal`].
///
/// With `u_s(y) = u_F + W G y` the section displacements (W = S K^-1 A,
/// linear and the same for every joint state) and the law acting point by
/// point, the generalized Jacobian of the nodal form is `J = D(x) W - I`, D
/// the joint tangent per (section, point) at the states of x
/// ([`release_tangent`](super::release::release_tangent): open releases the
/// whole trial-traction increment, stick nothing, slip the tangent of the
/// radial return). It is the coupled tangent stiffness `K - A D S`
/// right-preconditioned by the elastic block-diagonal K:
/// `(K - A D S) K^-1 = I - A (D S K^-1)` and `-J = I - (D S K^-1) A` have
/// the same eigenvalues apart from 1s: the joint tangent couples the
/// harmonics, only the elastic factors are ever used.
///
/// Each step: (1) solve `J delta = -R` by GCR
/// to the Eisenstat-Walker tolerance eta (choice 2,
/// `eta_k = 0.9 (|R_k| / |R_{k-1}|)^2`, safeguarded, in `[1e-3, 0.3]`, no
/// tighter than the target needs); every `W G z` the solve pays a sweep
/// for is kept, and the kept pairs span the next step's first directions
/// at no cost; (2) backtrack `y + lambda delta` (lambda = 1, 1/2, ...,
/// 1/32) until `|R|_2` decreases by the Armijo factor `1 - 1e-4 lambda`:
/// since `u_s(y + lambda delta) = u_s(y) + lambda W G delta` with
/// `W G delta` known, these trial evaluations cost no sweep; (3) if none
/// decreases `|R|` (a joint point switches state just ahead: the law is
/// only piecewise smooth, and discontinuous where a cohesive joint opens),
/// take the plain step `y + R` with a true evaluation (one sweep; its pair
/// is kept too). A ratio below epsilon is confirmed by a true evaluation
/// (one sweep), which also gives the displacement amplitudes.
///
/// No equilibrium: when the load exceeds what the joints carry, the points
/// along the unbalanced force all slip or open, the tangent releases the
/// whole increment along it (J is singular there), the Newton step the
/// linearization asks for does not reduce `|R|`, and the plain fallback
/// steps leave the unbalanced part of R unchanged. Reported when `|R|` has
/// made no new minimum by 1 % within [`NEWTON_STALL`] steps, when the
/// released forces outgrow what the residual can resolve ([`unresolved`]),
/// or when the residual grows past 1e6 Psi_0.
pub(super) fn newton(
    sweep: &Sweep,
    settings: &IterationSettings,
    from: Start,
    progress: &mut dyn FnMut(&IterationRecord),
) -> Result<Converged, Box<Failure>> {
    if sweep.setup.softened() {
        let mut form = Traction::new(*sweep);
        let y0 = form.start(&from);
        solve(sweep, &mut form, y0, settings, from, progress)
    } else {
        let y0 = from.x0.clone();
        solve(sweep, &mut Nodal::new(*sweep), y0, settings, from, progress)
    }
}

/// [`newton`] on formulation `form` from `y`.
fn solve(
    sweep: &Sweep,
    form: &mut dyn Formulation,
    mut y: Vec<f64>,
    settings: &IterationSettings,
    from: Start,
    progress: &mut dyn FnMut(&IterationRecord),
) -> Result<Converged, Box<Failure>> {
    let start = Instant::now();
    let setup = sweep.setup;
    let (ny, nx) = (form.len(), setup.len());
    let mut released = setup.transfer.zeros();
    let mut acc = setup.new_eval();
    let mut trial = setup.new_eval();
    let mut y_trial = vec![0.0; ny];
    let mut delta = vec![0.0; ny];
    let mut w_delta = vec![0.0; nx];
    let mut x = vec![0.0; nx];
    let mut rx = vec![0.0; nx];
    let mut krylov = Krylov::new();

    // A true evaluation at y (one sweep); `x` and `rx` hold G y and G R.
    let evaluate = |form: &dyn Formulation,
                    y: &[f64],
                    released: &mut JointAmplitudes,
                    ev: &mut Eval,
                    res: &mut [f64],
                    x: &mut [f64]| {
        form.forces(y, x);
        form.sweep().displace(x, released, &mut ev.u_s);
        form.residual(y, ev, res);
    };
    let mut res = vec![0.0; ny];
    // The section displacements at the start, if known (no sweep).
    let known = from.u_s.as_ref().filter(|u| u.len() == acc.u_s.len());
    let first_solves = match known {
        Some(u) => {
            form.forces(&y, &mut x);
            acc.u_s.copy_from_slice(u);
            form.residual(&y, &mut acc, &mut res);
            0
        }
        None => {
            evaluate(form, &y, &mut released, &mut acc, &mut res, &mut x);
            1
        }
    };
    // Whether `acc` is a true evaluation at y (not a linearized trial).
    let mut evaluated;
    let mut res_trial = vec![0.0; ny];
    let mut rhs = vec![0.0; ny];
    form.section_residual(&res, &mut rx);
    let psi_first = setup.section_max(&rx);
    let psi0 = from.psi_ref.unwrap_or(psi_first);
    let nothing_released = psi0 <= 1e-14 * setup.load_scale().max(f64::MIN_POSITIVE);
    let first_ratio = if nothing_released { 0.0 } else { psi_first / psi0 };
    let record = sweep.record(1, first_ratio, &acc, start, first_solves);
    progress(&record);
    let mut history = vec![record];
    if !psi_first.is_finite() {
        return Err(Failure::new(
            no_equilibrium(setup, &rx, "the solution is not finite", record, history),
            x,
            acc,
        ));
    }
    if nothing_released || (from.psi_ref.is_some() && first_ratio < settings.epsilon) {
        return Ok(Converged::new(x, y, acc, history));
    }

    let mut total = first_solves;
    let mut r_norm = norm(&res);
    let (mut r_prev, mut eta) = (r_norm, 0.5f64);
    let (mut best, mut best_at) = (r_norm, 1u32);
    let eta_floor = 0.5 * settings.epsilon * psi0;
    // Whether each of the last steps fell back to the plain step.
    let mut fallbacks = VecDeque::new();
    for step in 2..=settings.max_iterations {
        // (1) The Newton direction at y.
        rhs.copy_from_slice(&res);
        form.linearize(&y, &acc);
        if step > 2 {
            let ew = 0.9 * (r_norm / r_prev).powi(2);
            let safe = 0.9 * eta * eta;
            eta = if safe > 0.1 { ew.max(safe) } else { ew };
        }
        eta = eta.clamp(NEWTON_ETA_MIN, NEWTON_ETA_MAX).max(eta_floor / r_norm);
        let budget = settings.max_iterations.saturating_sub(total + 1);
        let mut sweeps = krylov.solve(
            form,
            &rhs,
            eta,
            budget,
            &mut released,
            &mut x,
            &mut delta,
            &mut w_delta,
        );

        // (2) Backtracking on |R|, the trial evaluations without a sweep.
        let mut lambda = 1.0;
        let mut accepted = false;
        for _ in 0..=form.halvings() {
            for ((t, a), d) in y_trial.iter_mut().zip(&y).zip(&delta) {
                *t = a + lambda * d;
            }
            for ((t, a), w) in trial.u_s.iter_mut().zip(&acc.u_s).zip(&w_delta) {
                *t = a + lambda * w;
            }
            trial.broken.copy_from_slice(&acc.broken);
            form.residual(&y_trial, &mut trial, &mut res_trial);
            if norm(&res_trial) <= (1.0 - 1e-4 * lambda) * r_norm {
                accepted = true;
                break;
            }
            lambda *= 0.5;
        }
        fallbacks.push_back(!accepted);
        if fallbacks.len() > NEWTON_STALL as usize {
            fallbacks.pop_front();
        }
        if accepted {
            evaluated = false;
        } else {
            // (3) The plain step, evaluated for real; its pair is kept.
            for i in 0..ny {
                y_trial[i] = y[i] + res[i];
            }
            trial.broken.copy_from_slice(&acc.broken);
            evaluate(form, &y_trial, &mut released, &mut trial, &mut res_trial, &mut x);
            evaluated = true;
            sweeps += 1;
            let mut w = krylov.buffer(nx);
            for ((wi, a), b) in w.iter_mut().zip(&trial.u_s).zip(&acc.u_s) {
                *wi = a - b;
            }
            let mut z = krylov.buffer(ny);
            z.copy_from_slice(&res);
            krylov.push(z, w);
        }
        std::mem::swap(&mut acc, &mut trial);
        std::mem::swap(&mut y, &mut y_trial);
        std::mem::swap(&mut res, &mut res_trial);
        r_prev = r_norm;
        r_norm = norm(&res);
        form.section_residual(&res, &mut rx);
        let mut ratio = setup.section_max(&rx) / psi0;
        if ratio < settings.epsilon && !evaluated {
            // Confirm with a true evaluation.
            evaluate(form, &y, &mut released, &mut acc, &mut res, &mut x);
            evaluated = true;
            sweeps += 1;
            r_norm = norm(&res);
            form.section_residual(&res, &mut rx);
            ratio = setup.section_max(&rx) / psi0;
        }
        total += sweeps;
        let record = sweep.record(step, ratio, &acc, start, sweeps);
        progress(&record);
        history.push(record);
        form.forces(&y, &mut x);
        if !ratio.is_finite() || !r_norm.is_finite() {
            return Err(Failure::new(
                no_equilibrium(setup, &rx, "the solution is not finite", record, history),
                x,
                acc,
            ));
        }
        if let Some(reason) = unresolved(setup, &x, psi0, settings.epsilon) {
            return Err(Failure::new(
                no_equilibrium(setup, &rx, &reason, record, history),
                x,
                acc,
            ));
        }
        if ratio < settings.epsilon && evaluated {
            return Ok(Converged::new(x, y, acc, history));
        }

        // No equilibrium.
        let reason = if r_norm < 0.99 * best {
            best = r_norm;
            best_at = step;
            None
        } else if step - best_at >= NEWTON_STALL {
            Some(format!(
                "the Newton residual stalls at ratio {ratio:.3e} (|R| made no new minimum by 1 % in {NEWTON_STALL} steps, {} of which fell back to the plain step: the joint tangent has (almost) no stiffness left along the unbalanced force, and the step the linearization asks for does not reduce the residual)",
                fallbacks.iter().filter(|&&f| f).count()
            ))
        } else {
            None
        };
        let reason =
            reason.or_else(|| (ratio > 1e6).then(|| format!("the residual grows (ratio {ratio:.3e})")));
        if let Some(reason) = reason {
            return Err(Failure::new(
                no_equilibrium(setup, &rx, &reason, record, history),
                x,
                acc,
            ));
        }
        if total >= settings.max_iterations {
            break;
        }
    }
    Err(Failure::new(not_converged(setup, &rx, settings, history), x, acc))
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
