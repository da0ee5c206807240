//! Semi-smooth Newton-Krylov ([`newton`]) on one of two formulations
//! ([`Formulation`]): the released section forces x, `R(x) = Psi(x) - x = 0`
//! ([`Nodal`]), or, where a joint is assembled softer than its law
//! (`k h / E > 1`), the released tractions per (section, point)
//! ([`Traction`]); and its Krylov solver
//! ([`Krylov`]).

use super::attempt::{Converged, Failure, Start};
use super::body::SectionBasis;
use super::diagnosis::{no_equilibrium, not_converged, unresolved};
use super::eval::Eval;
use super::formulation::{Formulation, NEWTON_HALVINGS, SMOOTH_AFTER, WATCH_STEPS};
use super::release::Tangents;
use super::stall::Stall;
use super::sweep::Sweep;
use super::traction::Traction;
use super::transfer::JointAmplitudes;
use super::types::{IterationError, IterationRecord, IterationSettings};
use super::vector::{axpy, dot, norm};
use super::watchdog::{Checkpoint, Verdict, Watchdog};
use crate::fourier::{basis_derivative, Family};
use crate::linear::HarmonicFactor;
use rayon::prelude::*;
use std::collections::VecDeque;
use std::time::Instant;

/// Newton steps without a 1 % decrease of `|R|` before no equilibrium is
/// reported with joints as assembled (measured on the block torsion beyond
/// capacity: 10 to 22 steps, 15 to 25 sweeps from 1.01 to 2 T_max); the
/// traction form's is [`NEWTON_STALL_STIFF`](super::formulation::NEWTON_STALL_STIFF).
const NEWTON_STALL: u32 = 8;

/// A Newton solve whose residual stalls (no new minimum by 1 % in its
/// window) below this many times epsilon ends converged: it is at the
/// round-off floor of its residual, not short of an equilibrium. Measured:
/// the pile in soil at k h / E = 1e6 (M = 8) stalled at a ratio of 1.5e-6
/// for an epsilon of 1e-6 at the load factor 0.131 (a false limit load,
/// the load carried at every other stiffness); a load beyond a capacity
/// stalls at ratios of 2e-4 to 5e-3 (crates/solver/tests/stiff_limits.rs).
const FLOOR_FACTOR: f64 = 10.0;

/// The smallest Eisenstat-Walker forcing term (the largest:
/// [`Formulation::eta_max`]).
const NEWTON_ETA_MIN: f64 = 1e-3;

/// Newton on the released section forces: `R(x) = Psi(x) - x`,
/// `J = D W - I` (D the release tangent,
/// [`release_tangent`](super::release::release_tangent)), unpreconditioned:
/// every joint is assembled as it is (`k h / E <= 1`), where the identity
/// is as good as the harmonic-block preconditioner (measured on Scene P at
/// k_eta h / E = 0.125 to 1).
///
/// With plastic bodies it is preconditioned by
/// `M = -(I + T S K_t^-1 A)`, `K_t = K - (A T S)_mm` the tangent
/// stiffness of each harmonic and family with the bodies' tangents
/// (refactorized at every linearization): `J^-1` exactly where the
/// harmonics do not couple (an axisymmetric plastic zone), by Woodbury's
/// identity `(I - T W)^-1 = I + T S (K - A T S)^-1 A`.
pub(super) struct Nodal<'s, 'a> {
    sweep: Sweep<'s, 'a>,
    tangents: Tangents,
    /// Per harmonic index and family, the factor of `K_t` (none: not
    /// positive definite, or no plastic point).
    tangent_factors: Vec<[Option<HarmonicFactor>; 2]>,
}

impl<'s, 'a> Nodal<'s, 'a> {
    pub(super) fn new(sweep: Sweep<'s, 'a>) -> Self {
        Nodal {
            sweep,
            tangents: Tangents::new(sweep.setup),
            tangent_factors: Vec::new(),
        }
    }

    /// Factorizes the tangent stiffness of every harmonic and family at the
    /// bodies' tangents (nothing without a yielding point).
    fn factor_tangents(&mut self) {
        self.tangent_factors.clear();
        let setup = self.sweep.setup;
        let Some(bodies) = &setup.bodies else { return };
        if self.tangents.bodies.iter().all(Option::is_none) {
            return;
        }
        let sections = setup.sections();
        let model = setup.model;
        let operators = bodies.tangent_operators(&self.tangents.bodies);
        let jobs: Vec<(usize, usize)> = (0..setup.loads.len())
            .flat_map(|h| {
                (0..2)
                    .filter(move |&k| k == 0 || setup.transfer.both[h])
                    .map(move |k| (h, k))
            })
            .collect();
        let factors: Vec<Option<HarmonicFactor>> = jobs
            .par_iter()
            .map(|&(h, k)| {
                let m = setup.loads[h].m;
                let family = if k == 0 {
                    Family::Symmetric
                } else {
                    Family::Antisymmetric
                };
                let basis = SectionBasis::new(m, &sections.theta, &sections.weight, |t| {
                    let ((a, b), (da, db)) = (sections.phi(m, family, t), basis_derivative(m, family, t));
                    [a, b, da, db]
                });
                let (mut values, pinned) = model.assemble_from_terms(m);
                bodies.subtract_tangent(
                    model,
                    &basis,
                    &self.tangents.bodies,
                    &operators,
                    &pinned,
                    &mut values,
                );
                model.factorize_preconditioner(m, &values, pinned)
            })
            .collect();
        self.tangent_factors = (0..setup.loads.len()).map(|_| [None, None]).collect();
        for ((h, k), f) in jobs.into_iter().zip(factors) {
            self.tangent_factors[h][k] = f;
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
        // (Kept for more than one linearization while the plastic zone held
        // its size to 5 %, the footing of crates/solver/tests/plasticity.rs
        // took 7 times the solves.)
        self.factor_tangents();
    }

    fn apply_j(&self, z: &[f64], wz: &[f64], out: &mut [f64]) {
        self.sweep.apply_tangent(&self.tangents, wz, out);
        axpy(-1.0, z, out);
    }

    fn precondition(&mut self, r: &[f64], released: &mut JointAmplitudes, out: &mut [f64]) -> bool {
        if self.tangent_factors.is_empty() {
            return false;
        }
        let setup = self.sweep.setup;
        setup.transfer.analyse(r, released);
        // K_t^-1 A r per harmonic and family (K^-1 where K_t is not positive
        // definite), at the release nodes.
        let u: JointAmplitudes = released
            .par_iter()
            .enumerate()
            .map(|(h, g)| {
                std::array::from_fn(|k| {
                    if k == 1 && !setup.transfer.both[h] {
                        return vec![0.0; g[k].len()];
                    }
                    let factor = self.tangent_factors[h][k].as_ref().unwrap_or(setup.factor_of[h]);
                    let [u] = setup.solve_release(factor, &[&g[k]]);
                    u
                })
            })
            .collect();
        let mut u_s = vec![0.0; r.len()];
        setup.transfer.synthesize(&u, &mut u_s);
        self.sweep.apply_tangent(&self.tangents, &u_s, out);
        for (o, ri) in out.iter_mut().zip(r) {
            *o = -(ri + *o);
        }
        true
    }

    fn halvings(&self) -> u32 {
        NEWTON_HALVINGS
    }

    fn stall_window(&self) -> u32 {
        NEWTON_STALL
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
/// is kept too); after three plain steps in a row the formulation may
/// switch to a smoothed residual with the same solutions
/// ([`Formulation::smooth`]). A ratio below epsilon is confirmed by a true
/// evaluation (one sweep), which also gives the displacement amplitudes.
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
    // (Plastic bodies are released as section forces: the nodal form.)
    if sweep.setup.softened() && sweep.setup.bodies.is_none() {
        let mut form = Traction::new(*sweep, settings);
        let y0 = form.start(&from);
        let from = Start {
            predicted: None,
            ..from
        };
        solve(sweep, &mut form, y0, settings, from, progress)
    } else {
        let y0 = from.x0.clone();
        solve(sweep, &mut Nodal::new(*sweep), y0, settings, from, progress)
    }
}

/// The iterate of [`solve`] and its scratch: the unknowns y, their
/// evaluation `acc` and residual `res`; the trial iterate of a step; the
/// Newton direction `delta` and `W G delta`; `x = G y`, `rx = G R`, the
/// right-hand side, the analysis buffer and the Krylov directions.
struct Iterate {
    y: Vec<f64>,
    acc: Eval,
    res: Vec<f64>,
    y_trial: Vec<f64>,
    trial: Eval,
    res_trial: Vec<f64>,
    delta: Vec<f64>,
    w_delta: Vec<f64>,
    x: Vec<f64>,
    rx: Vec<f64>,
    rhs: Vec<f64>,
    released: JointAmplitudes,
    krylov: Krylov,
}

impl Iterate {
    /// At `y` (`ny` unknowns), not evaluated yet.
    fn new(sweep: &Sweep, ny: usize, y: Vec<f64>) -> Self {
        let setup = sweep.setup;
        let nx = setup.len();
        Iterate {
            y,
            acc: setup.new_eval(),
            res: vec![0.0; ny],
            y_trial: vec![0.0; ny],
            trial: setup.new_eval(),
            res_trial: vec![0.0; ny],
            delta: vec![0.0; ny],
            w_delta: vec![0.0; nx],
            x: vec![0.0; nx],
            rx: vec![0.0; nx],
            rhs: vec![0.0; ny],
            released: setup.transfer.zeros(),
            krylov: Krylov::new(),
        }
    }

    /// A true evaluation at y (one sweep).
    fn evaluate(&mut self, form: &dyn Formulation) {
        evaluate(
            form,
            &self.y,
            &mut self.released,
            &mut self.acc,
            &mut self.res,
            &mut self.x,
        );
    }

    /// (2) Backtracking on `|R|` along `delta` from `|R| = r_norm`, the
    /// trial evaluations without a sweep; the step accepted, if any.
    fn line_search(&mut self, form: &dyn Formulation, r_norm: f64) -> Option<f64> {
        let mut lambda = 1.0;
        for _ in 0..=form.halvings() {
            self.trial_at(form, lambda);
            if norm(&self.res_trial) <= (1.0 - 1e-4 * lambda) * r_norm {
                return Some(lambda);
            }
            lambda *= 0.5;
        }
        None
    }

    /// The trial `y + lambda delta`, evaluated without a sweep.
    fn trial_at(&mut self, form: &dyn Formulation, lambda: f64) {
        for ((t, a), d) in self.y_trial.iter_mut().zip(&self.y).zip(&self.delta) {
            *t = a + lambda * d;
        }
        for ((t, a), w) in self.trial.u_s.iter_mut().zip(&self.acc.u_s).zip(&self.w_delta) {
            *t = a + lambda * w;
        }
        self.trial.broken.copy_from_slice(&self.acc.broken);
        form.residual(&self.y_trial, &mut self.trial, &mut self.res_trial);
    }

    /// The iterate as a checkpoint (`|R| = r_norm`).
    fn checkpoint(&self, r_norm: f64) -> Checkpoint {
        Checkpoint {
            y: self.y.clone(),
            acc: self.acc.clone(),
            res: self.res.clone(),
            r_norm,
        }
    }

    /// Back to a checkpoint.
    fn restore(&mut self, c: Checkpoint) {
        self.y = c.y;
        self.acc = c.acc;
        self.res = c.res;
    }

    /// (3) The plain step `y + R` as the trial, evaluated for real (one
    /// sweep); its pair is kept.
    fn plain_step(&mut self, form: &dyn Formulation) {
        let (nx, ny) = (self.w_delta.len(), self.delta.len());
        for i in 0..ny {
            self.y_trial[i] = self.y[i] + self.res[i];
        }
        self.trial.broken.copy_from_slice(&self.acc.broken);
        evaluate(
            form,
            &self.y_trial,
            &mut self.released,
            &mut self.trial,
            &mut self.res_trial,
            &mut self.x,
        );
        let mut w = self.krylov.buffer(nx);
        for ((wi, a), b) in w.iter_mut().zip(&self.trial.u_s).zip(&self.acc.u_s) {
            *wi = a - b;
        }
        let mut z = self.krylov.buffer(ny);
        z.copy_from_slice(&self.res);
        self.krylov.push(z, w);
    }

    /// Takes the trial as the iterate.
    fn advance(&mut self) {
        std::mem::swap(&mut self.acc, &mut self.trial);
        std::mem::swap(&mut self.y, &mut self.y_trial);
        std::mem::swap(&mut self.res, &mut self.res_trial);
    }

    /// Stopped with `error` at this iterate.
    fn fail(self, error: IterationError) -> Box<Failure> {
        Failure::new(error, self.x, self.acc)
    }

    /// Converged at this iterate.
    fn converged(self, history: Vec<IterationRecord>) -> Converged {
        Converged::new(self.x, self.y, self.acc, history)
    }
}

/// A true evaluation of `form` at `y` (one sweep): `ev`, the residual `res`
/// and `x = G y`.
fn evaluate(
    form: &dyn Formulation,
    y: &[f64],
    released: &mut JointAmplitudes,
    ev: &mut Eval,
    res: &mut [f64],
    x: &mut [f64],
) {
    form.forces(y, x);
    form.sweep().displace(x, released, &mut ev.u_s);
    form.residual(y, ev, res);
}

/// [`newton`] on formulation `form` from `y`.
fn solve(
    sweep: &Sweep,
    form: &mut dyn Formulation,
    y: Vec<f64>,
    settings: &IterationSettings,
    from: Start,
    progress: &mut dyn FnMut(&IterationRecord),
) -> Result<Converged, Box<Failure>> {
    let start = Instant::now();
    let setup = sweep.setup;
    let mut it = Iterate::new(sweep, form.len(), y);
    // The section displacements at the start, if known (no sweep).
    let known = from.u_s.as_ref().filter(|u| u.len() == it.acc.u_s.len());
    let first_solves = match known {
        Some(u) => {
            form.forces(&it.y, &mut it.x);
            it.acc.u_s.copy_from_slice(u);
            form.residual(&it.y, &mut it.acc, &mut it.res);
            0
        }
        None => {
            it.evaluate(form);
            1
        }
    };
    // A predicted start (one more sweep), kept if its residual is smaller.
    let first_solves = match from.predicted.as_deref().filter(|p| p.len() == it.y.len()) {
        Some(p) => {
            it.y_trial.copy_from_slice(p);
            it.trial.broken.copy_from_slice(&it.acc.broken);
            let Iterate {
                y_trial,
                released,
                trial,
                res_trial,
                x,
                ..
            } = &mut it;
            evaluate(form, y_trial, released, trial, res_trial, x);
            if norm(&it.res_trial) < norm(&it.res) {
                it.advance();
            }
            form.forces(&it.y, &mut it.x);
            first_solves + 1
        }
        None => first_solves,
    };
    form.section_residual(&it.res, &mut it.rx);
    let psi_first = setup.section_max(&it.rx);
    let psi0 = from.psi_ref.unwrap_or(psi_first);
    let nothing_released = psi0 <= 1e-14 * setup.load_scale().max(f64::MIN_POSITIVE);
    let first_ratio = if nothing_released { 0.0 } else { psi_first / psi0 };
    let record = sweep.record(1, first_ratio, &it.acc, start, first_solves);
    progress(&record);
    let mut history = vec![record];
    if !psi_first.is_finite() {
        let e = no_equilibrium(setup, &it.rx, "the solution is not finite", record, history);
        return Err(it.fail(e));
    }
    if nothing_released || (from.psi_ref.is_some() && first_ratio < settings.epsilon) {
        return Ok(it.converged(history));
    }

    let mut total = first_solves;
    let mut r_norm = norm(&it.res);
    let (mut r_prev, mut eta) = (r_norm, 0.5f64);
    let mut stall = Stall::new(r_norm, form.stall_window(), 1);
    let mut watchdog = Watchdog::new(form.watchdog());
    let eta_floor = 0.5 * settings.epsilon * psi0;
    let eta_max = form.eta_max();
    let mut fallbacks = 0u32;
    for step in 2..=settings.max_iterations {
        if setup.cancelled() {
            return Err(it.fail(IterationError::Cancelled));
        }
        // (1) The Newton direction at y.
        it.rhs.copy_from_slice(&it.res);
        form.linearize(&it.y, &it.acc);
        if step > 2 {
            let ew = 0.9 * (r_norm / r_prev).powi(2);
            let safe = 0.9 * eta * eta;
            eta = if safe > 0.1 { ew.max(safe) } else { ew };
        }
        eta = eta
            .clamp(NEWTON_ETA_MIN.min(eta_max), eta_max)
            .max(eta_floor / r_norm);
        let budget = settings.max_iterations.saturating_sub(total + 1);
        let mut sweeps = it.krylov.solve(
            form,
            &it.rhs,
            eta,
            budget,
            &mut it.released,
            &mut it.x,
            &mut it.delta,
            &mut it.w_delta,
        );

        // (2) Backtracking, else (3) the plain step; or the whole step
        // under the watchdog.
        let accepted = if watchdog.relax() {
            watchdog.watch(it.checkpoint(r_norm));
            it.trial_at(form, 1.0);
            true
        } else {
            let lambda = it.line_search(form, r_norm);
            watchdog.note(lambda);
            lambda.is_some()
        };
        stall.fell_back(!accepted);
        fallbacks = if accepted { 0 } else { fallbacks + 1 };
        let mut evaluated = !accepted;
        if !accepted {
            it.plain_step(form);
            sweeps += 1;
        }
        it.advance();
        r_prev = r_norm;
        r_norm = norm(&it.res);
        if fallbacks >= SMOOTH_AFTER && !watchdog.watching() && form.smooth() {
            // The same iterate under the smoothed residual (no sweep).
            form.residual(&it.y, &mut it.acc, &mut it.res);
            r_norm = norm(&it.res);
            // (A new window from this step: from step 1, a switch after
            // the window's length of steps stalled at once, a false limit
            // load on the torsion block at k h / E = 1e4.)
            stall = Stall::new(r_norm, form.stall_window(), step);
        }
        if watchdog.watching() {
            form.forces(&it.y, &mut it.x);
            let bad = !r_norm.is_finite() || unresolved(setup, &it.x, psi0, settings.epsilon).is_some();
            if let Verdict::Return(c) = watchdog.verdict(r_norm, bad) {
                // The watched steps do not count towards a stall.
                stall.pause(WATCH_STEPS);
                r_norm = c.r_norm;
                it.restore(*c);
                evaluated = false;
            }
        }
        form.section_residual(&it.res, &mut it.rx);
        let mut ratio = setup.section_max(&it.rx) / psi0;
        if ratio < settings.epsilon && !evaluated {
            // Confirm with a true evaluation.
            it.evaluate(form);
            evaluated = true;
            sweeps += 1;
            r_norm = norm(&it.res);
            form.section_residual(&it.res, &mut it.rx);
            ratio = setup.section_max(&it.rx) / psi0;
        }
        total += sweeps;
        let record = sweep.record(step, ratio, &it.acc, start, sweeps);
        progress(&record);
        history.push(record);
        form.forces(&it.y, &mut it.x);
        if !ratio.is_finite() || !r_norm.is_finite() {
            let e = no_equilibrium(setup, &it.rx, "the solution is not finite", record, history);
            return Err(it.fail(e));
        }
        // (The watched steps wait for the watchdog's verdict.)
        let watching = watchdog.watching();
        if let Some(reason) = unresolved(setup, &it.x, psi0, settings.epsilon).filter(|_| !watching) {
            let e = no_equilibrium(setup, &it.rx, &reason, record, history);
            return Err(it.fail(e));
        }
        if ratio < settings.epsilon && evaluated {
            return Ok(it.converged(history));
        }
        // No equilibrium, unless the residual stalls within
        // [`FLOOR_FACTOR`] of epsilon: there it is at its round-off floor,
        // converged.
        if let Some(reason) = stall.reason(step, r_norm, ratio).filter(|_| !watching) {
            if ratio < FLOOR_FACTOR * settings.epsilon {
                if !evaluated {
                    it.evaluate(form);
                    form.section_residual(&it.res, &mut it.rx);
                    if let Some(last) = history.last_mut() {
                        last.solves += 1;
                        last.ratio = setup.section_max(&it.rx) / psi0;
                    }
                }
                if history
                    .last()
                    .is_some_and(|r| r.ratio < FLOOR_FACTOR * settings.epsilon)
                {
                    return Ok(it.converged(history));
                }
            }
            let e = no_equilibrium(setup, &it.rx, &reason, record, history);
            return Err(it.fail(e));
        }
        if total >= settings.max_iterations {
            break;
        }
    }
    let e = not_converged(setup, &it.rx, settings, history);
    Err(it.fail(e))
}
