//! The stress-transfer iteration (docs/theory.md sections 8-11, the paper's
//! steps (1)-(5)): the joints stay elastic in every K_m (the harmonics stay
//! decoupled), and the inadmissible part of their traction is released as
//! unbalanced nodal forces, analysed back into harmonics and solved again
//! with the same factors.
//!
//! With `G(u)` the released forces, each iteration solves
//! `K_m u_m = F_m + G_m(u_prev)`; the residual at section s is the change of
//! the released nodal forces there, `rho_s = g_s(u_k) - g_s(u_{k-1})`, and
//! `Psi_k = max_s |rho_s|`, `Psi_0 = max_s |g_s(u_0)|` (the paper's Eq. 12:
//! converged when `Psi_k / Psi_0 < epsilon`).
//!
//! Written as a fixed point on the released section forces x:
//! `Psi(x) = release(u_F + W x)`, `W = S K^-1 A` (A the analysis into
//! harmonics, K^-1 the back-substitution of every harmonic with its factor,
//! S the synthesis of the joint-node displacements at the sections,
//! `u_F = S K^-1 F`). One evaluation of `Psi` (`Setup::evaluate`, shared
//! by every method) costs one back-substitution sweep. The paper iterates
//! `x <- Psi(x)` (and then `rho_s = Psi(x)_s - x_s`), [`Method::Anderson`]
//! mixes the last iterates, [`Method::Newton`] solves `R(x) = Psi(x) - x = 0`
//! by a semi-smooth Newton-Krylov method (see the private `newton` module).
//! Only back-substitutions are ever repeated: no coupled system is factorized.
//!
//! The private submodules: `types` (the public types), `setup` (the fixed
//! data of a run, synthesis and analysis, one evaluation of `Psi`), `eval`
//! (what one evaluation gives), `release` (the joint law at the sections
//! and its tangent), `attempt` (where a method starts, how it ends), `fixed_point` (the paper's and Anderson's
//! iterations), `formulation` (what Newton iterates on), `newton`
//! (Newton-Krylov, and its nodal form), `traction` (its traction form, for
//! joints stiffer than their elements), `precondition` and `interface`
//! (the interface-tangent preconditioner and its fixed data), `steps` (the
//! load path), `diagnosis` (why a run stopped) and `probe` ([`FixedPoint`],
//! for tests).

mod attempt;
mod diagnosis;
mod eval;
mod fixed_point;
mod formulation;
mod interface;
mod newton;
mod precondition;
mod probe;
mod release;
mod setup;
mod steps;
mod traction;
mod types;

pub use probe::FixedPoint;
pub use setup::OBSERVED_UP_TO;
pub use steps::{
    stress_transfer_stepped, LimitLoad, LoadStep, StepControl, Stepped, BRACKET, EASY_ITERATIONS,
    MAX_CUTBACKS, MAX_ROUNDS, MIN_INCREMENT, PATH_MIN, PATH_TOL,
};

pub use types::{
    joint_point_infos, IterationError, IterationRecord, IterationSettings, JointField, JointStart, Method,
    Outcome, PointInfo,
};

use crate::fourier::Sections;
use crate::linear::{HarmonicFactor, Model};
use crate::loads::HarmonicLoads;
use crate::scene::JointLaw;
use crate::solution::Displacements;
use attempt::Start;
use fixed_point::fixed_point;
use newton::newton;
use setup::Setup;

/// Runs the iteration. `factors` must hold every harmonic of `loads`;
/// `laws[j]` is the law of `model.joints[j]`. `progress` sees each record.
pub fn stress_transfer(
    model: &Model,
    factors: &[HarmonicFactor],
    loads: &[HarmonicLoads],
    laws: &[JointLaw],
    sections: &Sections,
    settings: &IterationSettings,
    progress: impl FnMut(&IterationRecord),
) -> Result<Outcome, IterationError> {
    stress_transfer_from(
        model, factors, loads, laws, sections, settings, None, None, progress,
    )
}

/// [`stress_transfer`] given the elastic solution `K^-1 F` of (some of) the
/// harmonics of `loads`, which then cost no solve, and the joints' `start`
/// state (none: unstressed and intact).
#[allow(clippy::too_many_arguments)]
pub fn stress_transfer_from(
    model: &Model,
    factors: &[HarmonicFactor],
    loads: &[HarmonicLoads],
    laws: &[JointLaw],
    sections: &Sections,
    settings: &IterationSettings,
    elastic: Option<&Displacements>,
    start: Option<&JointStart>,
    mut progress: impl FnMut(&IterationRecord),
) -> Result<Outcome, IterationError> {
    let mut setup = Setup::new(model, factors, loads, laws, sections, elastic, start)?;
    let mut start = Start::zero(&setup);
    if setup.softened() {
        start.psi_ref = Some(setup.reference_release());
    }
    let result = match settings.method {
        Method::Plain => fixed_point(&setup, 0, settings, start, &mut progress),
        Method::Anderson { depth } => fixed_point(&setup, depth, settings, start, &mut progress),
        Method::Newton => newton(&setup, settings, start, &mut progress),
    };
    match result {
        Ok(conv) => {
            let displacements = setup.full_displacements(&conv.x);
            // A converged residual is not yet an equilibrium.
            let imbalance = setup.imbalance(&conv.x, &displacements);
            if imbalance > setup::IMBALANCE_TOL {
                let e = diagnosis::unbalanced(&setup, &conv.ev, imbalance, conv.history.clone());
                return Err(e.with_last(setup.finish_with(conv, displacements)));
            }
            Ok(setup.finish_with(conv, displacements))
        }
        // The last iterate, for the user to see where it stopped (one full
        // solve).
        Err(f) => {
            let history = f.error.history().to_vec();
            let last = setup.finish(&f.x, f.ev, history);
            Err(f.error.with_last(last))
        }
    }
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
