//! What Newton iterates on ([`Formulation`]): the nodal form (`newton`) and
//! the traction form (`traction`) implement it; the Newton loop, its
//! Krylov solver and line search are written once against it.

use super::eval::Eval;
use super::sweep::Sweep;
use super::transfer::JointAmplitudes;

/// Halvings of the Newton step before the plain step is taken instead
/// (lambda >= 1/32: a smaller one means a joint point switches state just
/// ahead, where the linearization says nothing, and accepting tiny steps
/// only creeps along the switching surface).
pub(super) const NEWTON_HALVINGS: u32 = 5;

/// Halvings with a joint stiffer than its elements (the traction form):
/// the law's kinks lie closer together there. Measured on Scene P with
/// k_eta h / E = 12.5 and 100: 30 halvings fail the one-shot runs, 10
/// converge them and the stepped runs.
pub(super) const NEWTON_HALVINGS_STIFF: u32 = 10;

/// Newton steps without a 1 % decrease of `|R|` before no equilibrium is
/// reported, with a joint stiffer than its elements (the traction form).
/// Measured beyond capacity (crates/solver/tests/stiff_limits.rs): with 8,
/// the sliding block at k h / E = 1e4 (of its shortest element) stopped
/// at 0.570 of the load for 0.952 (a change of the springs by 6e-7 gave
/// 0.945), and the rigid torsion block at 0.898 for 0.909; with 16 both
/// bracket the exact factor, the sliding one in 715 solves instead of 2333.
pub(super) const NEWTON_STALL_STIFF: u32 = 16;

/// The largest Eisenstat-Walker forcing term of the Krylov solve of a
/// Newton step (measured on Scene P: an upper bound of 0.5 or 0.1 instead
/// of 0.3 costs 0 to 3 more sweeps).
const NEWTON_ETA_MAX: f64 = 0.3;

/// The largest Eisenstat-Walker forcing term with a joint stiffer than its
/// elements (the traction form). With the nodal form's 0.3, a slow step
/// (`|R|` down by a few percent) sets the next term to 0.3, the Krylov
/// directions kept from earlier steps then meet it without a sweep, and
/// that poor direction makes the next step slow again: on the pile in soil
/// at k h / E = 1e5 with harmonics 0..=4 and 17 sections (its M/2 check),
/// a stall at ratio 1.006e-6 reported as a limit load at 0.061 of the load
/// after 270 s; with 0.03 it converges in 5 s (with the springs changed by
/// 3e-14, 8 and 14 s, and once not in 90 s: so close to the switching
/// surface the path is chaotic, docs/stability.md). Measured on the pile in
/// soil (M = 8) with 0.3 / 0.03 / 0.01: rigid 3.4 / 2.9 / 4.3 s (a tighter
/// term pays more dense LUs of the preconditioner), k h / E = 1e5 270 (the
/// M/2 check stalled) / 28 / 19 s.
pub(super) const NEWTON_ETA_MAX_STIFF: f64 = 0.03;

/// Plain steps in a row (no descent along the Newton direction) after
/// which a Newton solve switches to the smoothed residual
/// ([`Formulation::smooth`]; docs/stability.md, item 9).
pub(super) const SMOOTH_AFTER: u32 = 3;

/// Line-search steps in a row at `lambda <= CRAWL_LAMBDA` after which the
/// watchdog takes the whole Newton step ([`Formulation::watchdog`]).
pub(super) const CRAWL_STEPS: u32 = 3;

/// A step at most this long counts as a crawl: any step the line search
/// had to shorten. At 1/16 the tutorial's pile with rigid joints crawled
/// at lambda = 1/8 for 80 Newton steps of a load step (docs/stability.md,
/// item 13).
pub(super) const CRAWL_LAMBDA: f64 = 1.0 / 2.0;

/// Steps after the watchdog's whole step (that one included) within which
/// `|R|` must fall below the checkpoint's, else the run returns there.
pub(super) const WATCH_STEPS: u32 = 5;

/// What Newton iterates on: unknowns y, the section displacements
/// `u_s = u_F + W G y` (G: the section forces of y, one sweep), the residual
/// `R(y)` at given displacements (no sweep) and its generalized Jacobian
/// `J = dR/dy` at the states of the last [`Formulation::linearize`].
pub(super) trait Formulation {
    /// The run's data at its load state.
    fn sweep(&self) -> &Sweep<'_, '_>;
    /// Number of unknowns.
    fn len(&self) -> usize;
    /// `x = G y`, the released section forces of y.
    fn forces(&self, y: &[f64], x: &mut [f64]);
    /// `R(y)` at the displacements `ev.u_s` (no sweep), the law choosing
    /// each point's state; fills `ev`.
    fn residual(&self, y: &[f64], ev: &mut Eval, res: &mut [f64]);
    /// The section-force residual (`G R`) of a residual, for the ratio and
    /// the diagnosis.
    fn section_residual(&self, res: &[f64], out: &mut [f64]);
    /// The joint tangent at `ev` (the evaluation at y), and the
    /// preconditioner's factors.
    fn linearize(&mut self, y: &[f64], ev: &Eval);
    /// `out = J z` given `wz = W G z` (no sweep).
    fn apply_j(&self, z: &[f64], wz: &[f64], out: &mut [f64]);
    /// `out = M r`, M an approximate inverse of J (no sweep); `false` when
    /// there is none (`out` untouched).
    fn precondition(&mut self, r: &[f64], released: &mut JointAmplitudes, out: &mut [f64]) -> bool;
    /// Halvings of the line search.
    fn halvings(&self) -> u32;
    /// Steps without a new minimum of `|R|` (by 1 %) before no equilibrium.
    fn stall_window(&self) -> u32;
    /// Switches the residual to a smoothed form with the same solutions;
    /// whether it switched.
    fn smooth(&mut self) -> bool {
        false
    }
    /// The largest forcing term of the Krylov solve.
    fn eta_max(&self) -> f64 {
        NEWTON_ETA_MAX
    }
    /// Whether a crawl of short line-search steps is broken by a whole
    /// Newton step under a watchdog (see [`newton`](super::newton::newton)).
    fn watchdog(&self) -> bool {
        false
    }
}
