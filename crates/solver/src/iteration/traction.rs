//! Newton on the released tractions, for joints assembled softer than
//! their law (`k > k_a = E / h`, see `run::model::reference_springs`).
//!
//! The unknowns are the tractions `tau` released at every (section,
//! point); the model carries `t = t0 + k_a d - tau` there (`d` the relative
//! displacement of `u_s = u_F + W G tau`, G the nodal forces of a traction).
//! The law wants `t = P(t_trial)`, `t_trial = t0 + k (d - s)` (s the
//! committed plastic slip), P its return map. Since P projects onto a
//! convex set (the shear disk or box at a given strength, the normal
//! traction below the tensile strength left) and its normal cone is a
//! cone, `t = P(t_trial)` holds exactly when `t = P(z)` with
//!
//! ```text
//! z = t + R (t_trial - t),   R = diag(k_a / k)
//! ```
//!
//! so the residual is `F(tau) = t - P(z)`. The strength of an opening pair
//! fades with `k_open (sigma_t - T') / k_eta`; at `z` the law measures it
//! with `k_open / k_a` times `z_sigma - T' = (k_a / k) (sigma_t - T')`, the
//! same strength where the pair opens (`t_sigma = T'`). Where `k = k_a`
//! this is the nodal form's residual point by point (`z = t_trial`). Where
//! `k >> k_a` it is the primal-dual active-set form of contact mechanics
//! with the parameter `c = k_a` instead of k: a point's state follows
//! `t + k_a (d - t / k)`, so a point predicted open that closes costs a
//! residual of order `k_a d`, not `k d`. With the release tangent
//! `E = d(z - P(z))/dz` and `T = I - E`,
//!
//! ```text
//! dF = Dv k_a dd - Dd dtau,   Dv = I - T (2I - R),   Dd = I - T (I - R)
//! ```
//!
//! (stick: `Dv = R - I`, `Dd = R`; open: `Dv = Dd = I`). With
//! `V = B W G` (relative displacements of released tractions),
//! `J = Dd (Dd^-1 Dv k_a V - I)`: the nodal form's Jacobian with the
//! tangent `Dd^-1 Dv` (stick: `1 - k / k_a`, as the nodal form), row-scaled
//! by Dd. Its preconditioner is the nodal one on that tangent
//! ([`StiffPreconditioner`]): `J^-1 r = -(y + Dd^-1 Dv k_a B S P^-1 A G y)`,
//! `y = Dd^-1 r`, exact when the interface is small.

use super::attempt::Start;
use super::eval::Eval;
use super::formulation::{Formulation, NEWTON_ETA_MAX_STIFF, NEWTON_HALVINGS_STIFF, NEWTON_STALL_STIFF};
use super::precondition::StiffPreconditioner;
use super::release::{law_tangent, Tangent};
use super::sweep::Sweep;
use super::transfer::JointAmplitudes;
use super::types::{InterfaceSolve, IterationSettings};
use nalgebra::Matrix3;
use rayon::prelude::*;

type M3 = [[f64; 3]; 3];

const I3: M3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// The traction formulation and its linearization.
pub(super) struct Traction<'s, 'a> {
    sweep: Sweep<'s, 'a>,
    /// `k_a / k` per joint and component (1 where k = 0).
    rho: Vec<[f64; 3]>,
    /// Per (section, point): `Dv diag(k_a)`, `Dd` and `Dd^-1`.
    dvk: Vec<M3>,
    dd: Vec<M3>,
    dd_inv: Vec<M3>,
    /// `Dd^-1 Dv` per (section, point): the preconditioner's tangent.
    tangents: Vec<Tangent>,
    pre: Option<StiffPreconditioner>,
    /// See [`IterationSettings::interface_solve`](super::types::IterationSettings::interface_solve).
    interface_solve: InterfaceSolve,
    /// See [`IterationSettings::watchdog`](super::types::IterationSettings::watchdog).
    watchdog: bool,
    /// Whether the normal rows are in Fischer-Burmeister form.
    fischer: bool,
    /// See [`IterationSettings::tangent_rho_floor`].
    rho_floor: f64,
    /// Scratch: section forces and displacements.
    x: Vec<f64>,
    u_s: Vec<f64>,
}

impl<'s, 'a> Traction<'s, 'a> {
    pub(super) fn new(sweep: Sweep<'s, 'a>, settings: &IterationSettings) -> Self {
        let (interface_solve, watchdog) = (settings.interface_solve, settings.watchdog);
        let setup = sweep.setup;
        let rho = setup.model.joints.iter().map(|j| j.softening()).collect();
        let n = setup.n_pairs();
        Traction {
            sweep,
            rho,
            dvk: vec![I3; n],
            dd: vec![I3; n],
            dd_inv: vec![I3; n],
            tangents: vec![None; n],
            pre: None,
            interface_solve,
            watchdog,
            fischer: false,
            rho_floor: settings.tangent_rho_floor,
            x: vec![0.0; setup.len()],
            u_s: vec![0.0; setup.len()],
        }
    }

    /// The first iterate: the tractions a warm start carries (same run,
    /// same formulation), else zero.
    pub(super) fn start(&self, from: &Start) -> Vec<f64> {
        let n = 3 * self.sweep.setup.n_pairs();
        match &from.y0 {
            Some(y) if y.len() == n => y.clone(),
            _ => vec![0.0; n],
        }
    }

    /// The cap of the normal traction at pair `k` (point i) under the
    /// history law (0 debonded, else the tensile strength), where the
    /// residual's normal row is in Fischer-Burmeister form ([`fischer`]).
    fn cap_of(sweep: &Sweep, on: bool, k: usize, i: usize) -> Option<f64> {
        if !on {
            return None;
        }
        let s = sweep.setup;
        let h = sweep.state.history_of(k)?;
        match &s.laws[s.points[i].joint] {
            crate::scene::JointLaw::MohrCoulomb(mc) => {
                Some(if h.debonded { 0.0 } else { mc.tensile_strength })
            }
            crate::scene::JointLaw::Linear => None,
        }
    }

    fn cap(&self, k: usize, i: usize) -> Option<f64> {
        Self::cap_of(&self.sweep, self.fischer, k, i)
    }

    /// At pair `k` (point i of section s) with relative displacement `d`
    /// and released traction `tau`: the traction the model carries `t`,
    /// and the point `z` the law is evaluated at.
    fn carried(
        sweep: &Sweep,
        rho: &[[f64; 3]],
        k: usize,
        i: usize,
        d: [f64; 3],
        tau: &[f64],
    ) -> ([f64; 3], [f64; 3]) {
        let s = sweep.setup;
        let joint = s.points[i].joint;
        let t0 = s.t0(k);
        let ka = s.model.joints[joint].assembled.traction(d);
        let h = sweep.state.history_of(k);
        let trial = s.trial(joint, d, h, t0);
        let rho = rho[joint];
        let t = [0, 1, 2].map(|c| t0[c] + ka[c] - tau[c]);
        let mut z = [0, 1, 2].map(|c| t[c] + rho[c] * (trial[c] - t[c]));
        if z[1].abs() <= s.tension_tol {
            z[1] = 0.0;
        }
        (t, z)
    }
}

/// The normal row of the residual in Fischer-Burmeister form and its
/// derivatives `(dphi/da, dphi/db)`: `a = t_left - t_n`, `b = z_n - t_n`,
/// `F_n = -(a + b - |(a, b)|)` (the projection's row is `-min(a, b)`: the
/// same zeros, but `|R|^2` smooth across the switching surface, so the
/// Newton direction descends at a point that sits on it; used after
/// three plain steps in a row, [`Formulation::smooth`]).
fn fischer(t_left: f64, t_n: f64, z_n: f64) -> (f64, f64, f64) {
    let (a, b) = (t_left - t_n, z_n - t_n);
    let r = a.hypot(b);
    let (pa, pb) = if r > 0.0 {
        (1.0 - a / r, 1.0 - b / r)
    } else {
        (0.0, 1.0)
    };
    (-(a + b - r), pa, pb)
}

fn mul3(a: &M3, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|r| a[r][0] * v[0] + a[r][1] * v[1] + a[r][2] * v[2])
}

impl Formulation for Traction<'_, '_> {
    fn sweep(&self) -> &Sweep<'_, '_> {
        &self.sweep
    }

    fn len(&self) -> usize {
        3 * self.sweep.setup.n_pairs()
    }

    fn forces(&self, y: &[f64], x: &mut [f64]) {
        let s = self.sweep.setup;
        let n_p = s.points.len();
        x.par_chunks_mut(s.per_section())
            .with_min_len(s.min_len())
            .enumerate()
            .for_each(|(sec, xs)| {
                xs.fill(0.0);
                let mut fe = [0.0; 18];
                for i in 0..n_p {
                    let k = sec * n_p + i;
                    s.scatter(i, [y[3 * k], y[3 * k + 1], y[3 * k + 2]], &mut fe, xs);
                }
            });
    }

    fn residual(&self, y: &[f64], ev: &mut Eval, res: &mut [f64]) {
        let s = self.sweep.setup;
        let n_p = s.points.len().max(1);
        let m = s.per_section();
        let (u_s, sections) = ev.sections_mut(m, n_p, s.min_len());
        sections
            .zip(res.par_chunks_mut(3 * n_p))
            .for_each(|((sec, out), rs)| {
                out.g.fill(0.0);
                let mut fe = [0.0; 18];
                for i in 0..s.points.len() {
                    let k = sec * n_p + i;
                    let tau = &y[3 * k..3 * k + 3];
                    let dk = s.relative(i, &u_s[sec * m..(sec + 1) * m]);
                    let (t, z) = Self::carried(&self.sweep, &self.rho, k, i, dk, tau);
                    let springs = &s.model.joints[s.points[i].joint].assembled;
                    let (pk, st) = self.sweep.admissible((k, i), z, springs, &mut out.broken[i]);
                    let mut f = [0, 1, 2].map(|c| t[c] - pk[c]);
                    if let Some(t_left) = self.cap(k, i) {
                        f[1] = fischer(t_left, t[1], z[1]).0;
                    }
                    rs[3 * i..3 * i + 3].copy_from_slice(&f);
                    // The release in nodal form: what the model's spring and
                    // the initial traction carry minus what the law allows.
                    s.scatter(i, [0, 1, 2].map(|c| tau[c] + f[c]), &mut fe, out.g);
                    out.d[i] = dk;
                    out.p[i] = pk;
                    out.state[i] = st;
                }
            });
    }

    fn section_residual(&self, res: &[f64], out: &mut [f64]) {
        self.forces(res, out);
    }

    fn linearize(&mut self, y: &[f64], ev: &Eval) {
        let Traction {
            sweep,
            rho,
            dvk,
            dd,
            dd_inv,
            tangents,
            pre,
            interface_solve,
            fischer: smoothed,
            rho_floor,
            ..
        } = self;
        let (fischer_on, rho_floor) = (*smoothed, *rho_floor);
        let (sweep, s) = (&*sweep, sweep.setup);
        let n_p = s.points.len().max(1);
        dvk.par_iter_mut()
            .zip(dd.par_iter_mut())
            .zip(dd_inv.par_iter_mut())
            .zip(tangents.par_iter_mut())
            .enumerate()
            .for_each(|(k, (((dvk, dd), dd_inv), tangent))| {
                let i = k % n_p;
                let joint = s.points[i].joint;
                let (t, z) = Self::carried(sweep, rho, k, i, ev.d[k], &y[3 * k..3 * k + 3]);
                let law = &s.laws[joint];
                let rate = s.opening_rate(joint, &s.model.joints[joint].assembled);
                let e = law_tangent(law, sweep.state.history_of(k), z, ev.state[k], rate)
                    .unwrap_or([[0.0; 3]; 3]);
                let rho = rho[joint].map(|r| r.max(rho_floor));
                let ka = s.model.joints[joint].assembled;
                let ka = [ka.k_xi, ka.k_eta, ka.k_theta];
                let mut dv = [[0.0; 3]; 3];
                for r in 0..3 {
                    for c in 0..3 {
                        let t = I3[r][c] - e[r][c];
                        dd[r][c] = I3[r][c] - t * (1.0 - rho[c]);
                        dv[r][c] = I3[r][c] - t * (2.0 - rho[c]);
                        dvk[r][c] = dv[r][c] * ka[c];
                    }
                }
                if let Some(t_left) = Self::cap_of(sweep, fischer_on, k, i) {
                    let (_, pa, pb) = fischer(t_left, t[1], z[1]);
                    dd[1] = [0.0, pa + rho[1] * pb, 0.0];
                    dv[1] = [0.0, pa - (1.0 - rho[1]) * pb, 0.0];
                    dvk[1] = [0.0, dv[1][1] * ka[1], 0.0];
                }
                let inv = Matrix3::from_fn(|r, c| dd[r][c]).try_inverse();
                *dd_inv = inv.map_or(I3, |m| [0, 1, 2].map(|r| [0, 1, 2].map(|c| m[(r, c)])));
                let inv = *dd_inv;
                *tangent = Some(
                    [0, 1, 2].map(|r| [0, 1, 2].map(|c| (0..3).map(|q| inv[r][q] * dv[q][c]).sum::<f64>())),
                );
            });
        // At every step's tangents (factorized when first used): reusing
        // it while the states stay the same (the slip tangents move) cost
        // 2 -> 15 load steps at k_eta h / E = 1e5 on Scene P and stopped
        // 1e6 at lambda = 0.
        let pre = pre.get_or_insert_with(|| StiffPreconditioner::new(s, *interface_solve));
        pre.update(tangents);
    }

    fn apply_j(&self, z: &[f64], wz: &[f64], out: &mut [f64]) {
        let s = self.sweep.setup;
        let n_p = s.points.len().max(1);
        let m = s.per_section();
        out.par_chunks_mut(3 * n_p)
            .with_min_len(s.min_len())
            .enumerate()
            .for_each(|(sec, os)| {
                let w = &wz[sec * m..(sec + 1) * m];
                for i in 0..s.points.len() {
                    let k = sec * n_p + i;
                    let a = mul3(&self.dvk[k], s.relative(i, w));
                    let b = mul3(&self.dd[k], [z[3 * k], z[3 * k + 1], z[3 * k + 2]]);
                    for c in 0..3 {
                        os[3 * i + c] = a[c] - b[c];
                    }
                }
            });
    }

    fn precondition(&mut self, r: &[f64], released: &mut JointAmplitudes, out: &mut [f64]) -> bool {
        if self.pre.is_none() {
            return false;
        }
        let s = self.sweep.setup;
        let n_p = s.points.len().max(1);
        for (k, o) in out.chunks_mut(3).enumerate() {
            o.copy_from_slice(&mul3(&self.dd_inv[k], [r[3 * k], r[3 * k + 1], r[3 * k + 2]]));
        }
        let mut x = std::mem::take(&mut self.x);
        self.forces(out, &mut x);
        if let Some(pre) = self.pre.as_mut() {
            pre.displacements(s, &x, released, &mut self.u_s);
        }
        self.x = x;
        let m = s.per_section();
        let u_s = &self.u_s;
        let tangents = &self.tangents;
        out.par_chunks_mut(3 * n_p)
            .with_min_len(s.min_len())
            .enumerate()
            .for_each(|(sec, os)| {
                let u = &u_s[sec * m..(sec + 1) * m];
                for (i, info) in s.points.iter().enumerate() {
                    let k = sec * n_p + i;
                    let ka = s.model.joints[info.joint].assembled.traction(s.relative(i, u));
                    let e = tangents[k].map_or([0.0; 3], |t| mul3(&t, ka));
                    for c in 0..3 {
                        os[3 * i + c] = -(os[3 * i + c] + e[c]);
                    }
                }
            });
        true
    }

    fn halvings(&self) -> u32 {
        NEWTON_HALVINGS_STIFF
    }

    fn stall_window(&self) -> u32 {
        NEWTON_STALL_STIFF
    }

    fn watchdog(&self) -> bool {
        self.watchdog
    }

    fn eta_max(&self) -> f64 {
        NEWTON_ETA_MAX_STIFF
    }

    fn smooth(&mut self) -> bool {
        !std::mem::replace(&mut self.fischer, true)
    }
}

#[cfg(test)]
mod tests {
    use super::fischer;

    /// The Fischer-Burmeister row vanishes where the projection's row
    /// `t_n - min(z_n, T')` does (closed: `z_n = t_n <= T'`; open:
    /// `t_n = T' <= z_n`), keeps its sign elsewhere, and its derivatives
    /// match central differences (1e-6) and are the closed / open rows
    /// far from the corner.
    #[test]
    fn the_fischer_row_has_the_projections_zeros_and_derivatives() {
        let cap = 0.1;
        for (t, z) in [(-0.3, -0.3), (0.1, 0.5), (0.1, 0.1)] {
            assert!(fischer(cap, t, z).0.abs() < 1e-15, "{t} {z}");
        }
        for (t, z) in [(-0.3, -0.2), (-0.3, 0.4), (0.05, 0.07), (0.2, 0.3), (-1.0, -1.5)] {
            let (f, pa, pb) = fischer(cap, t, z);
            let proj = t - f64::min(z, cap);
            assert!(f * proj > 0.0, "{t} {z}: {f} vs {proj}");
            // d/da at fixed b: move t_left; d/db at fixed a: move z_n.
            let h = 1e-7;
            let da = (fischer(cap + h, t, z).0 - fischer(cap - h, t, z).0) / (2.0 * h);
            let db = (fischer(cap, t, z + h).0 - fischer(cap, t, z - h).0) / (2.0 * h);
            assert!((da + pa).abs() < 1e-6 && (db + pb).abs() < 1e-6, "{t} {z}");
        }
        let (_, pa, pb) = fischer(cap, -1.0, -1.0 + 1e-9);
        assert!(pa.abs() < 1e-6 && (pb - 1.0).abs() < 1e-6, "closed: {pa} {pb}");
        let (_, pa, pb) = fischer(cap, cap - 1e-9, 2.0);
        assert!((pa - 1.0).abs() < 1e-6 && pb.abs() < 1e-6, "open: {pa} {pb}");
    }
}
