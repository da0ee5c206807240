//! The fixed-point map of a run and the traction form's residual, for tests
//! and diagnostics ([`FixedPoint`]): the same evaluations the iteration uses.

use super::eval::Eval;
use super::formulation::Formulation;
use super::setup::Setup;
use super::state::LoadState;
use super::sweep::Sweep;
use super::traction::Traction;
use super::types::{IterationError, Problem};
use crate::fourier::Sections;
use crate::joint_law::JointState;
use crate::linear::{HarmonicFactor, Model};
use crate::loads::HarmonicLoads;
use crate::scene::JointLaw;

/// The fixed-point map `Psi` of a model and its Jacobian, for tests and
/// diagnostics: the same evaluation the iteration uses.
pub struct FixedPoint<'a> {
    setup: Setup<'a>,
}

impl<'a> FixedPoint<'a> {
    /// The map for `loads` (every harmonic factorized in `factors`),
    /// `laws[j]` the law of `model.joints[j]`, evaluated at `sections`.
    pub fn new(
        model: &'a Model,
        factors: &'a [HarmonicFactor],
        loads: &'a [HarmonicLoads],
        laws: &'a [JointLaw],
        sections: &'a Sections,
    ) -> Result<Self, IterationError> {
        let problem = Problem {
            model,
            factors,
            loads,
            laws,
            sections,
            elastic: None,
            whole_up_to: None,
            from: None,
            cancel: None,
        };
        Ok(FixedPoint {
            setup: Setup::new(&problem, None)?,
        })
    }

    /// The whole load under the paper's law.
    fn sweep(&self) -> Sweep<'_, 'a> {
        Sweep::new(&self.setup, LoadState::WHOLE)
    }

    /// Length of x: sections x joint nodes x 3 (index `(s * n_j + j) * 3 + c`).
    pub fn len(&self) -> usize {
        self.setup.len()
    }

    /// True when there is no joint node.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// `Psi(x)` and the state of every (section, point) (index
    /// `s * n_points + p`), with no point broken before (one sweep).
    pub fn psi(&self, x: &[f64]) -> (Vec<f64>, Vec<JointState>) {
        let mut released = self.setup.transfer.zeros();
        let mut ev = self.setup.new_eval();
        self.sweep().evaluate(x, &mut released, &mut ev);
        (ev.g, ev.state)
    }

    /// Length of the traction form's unknowns: 3 per (section, point).
    pub fn traction_len(&self) -> usize {
        3 * self.setup.n_pairs()
    }

    /// The traction form's residual `F(tau) = t - P(t + (k_a / k)(t_trial -
    /// t))` (Newton's unknowns where a joint is assembled softer than its
    /// law) and the state of every (section, point) (one sweep).
    pub fn traction_residual(&self, tau: &[f64]) -> (Vec<f64>, Vec<JointState>) {
        let (f, ev) = self.traction_eval(tau);
        (f, ev.state)
    }

    /// `J v` of the traction form at `tau`, at the states of `tau` (two
    /// sweeps), linearized with `R >= rho_floor`
    /// ([`IterationSettings::tangent_rho_floor`](super::IterationSettings::tangent_rho_floor);
    /// 0: the exact Jacobian).
    pub fn traction_jacobian_vector(&self, tau: &[f64], v: &[f64], rho_floor: f64) -> Vec<f64> {
        let s = &self.setup;
        let (_, ev) = self.traction_eval(tau);
        let settings = super::types::IterationSettings {
            tangent_rho_floor: rho_floor,
            ..Default::default()
        };
        let mut form = Traction::new(self.sweep(), &settings);
        form.linearize(tau, &ev);
        let mut released = s.transfer.zeros();
        let mut x = vec![0.0; s.len()];
        form.forces(v, &mut x);
        let mut w = vec![0.0; s.len()];
        self.sweep().apply_w(&x, &mut released, &mut w);
        let mut out = vec![0.0; v.len()];
        form.apply_j(v, &w, &mut out);
        out
    }

    fn traction_eval(&self, tau: &[f64]) -> (Vec<f64>, Eval) {
        let s = &self.setup;
        let form = Traction::new(self.sweep(), &super::types::IterationSettings::default());
        let mut released = s.transfer.zeros();
        let mut ev = s.new_eval();
        let mut x = vec![0.0; s.len()];
        form.forces(tau, &mut x);
        self.sweep().displace(&x, &mut released, &mut ev.u_s);
        let mut f = vec![0.0; tau.len()];
        form.residual(tau, &mut ev, &mut f);
        (f, ev)
    }

    /// `J v = Psi'(x) v - v`, the generalized Jacobian of `R = Psi - x` with
    /// the joint tangent at the states of x (two sweeps: `Psi(x)`, `W v`).
    pub fn jacobian_vector(&self, x: &[f64], v: &[f64]) -> Vec<f64> {
        let (s, sweep) = (&self.setup, self.sweep());
        let mut released = s.transfer.zeros();
        let mut ev = s.new_eval();
        sweep.evaluate(x, &mut released, &mut ev);
        let mut tangents = super::release::Tangents::new(s);
        sweep.tangents(&ev, &mut tangents);
        let mut w = vec![0.0; s.len()];
        sweep.apply_w(v, &mut released, &mut w);
        let mut out = vec![0.0; s.len()];
        sweep.apply_tangent(&tangents, &w, &mut out);
        for (o, vi) in out.iter_mut().zip(v) {
            *o -= vi;
        }
        out
    }
}
