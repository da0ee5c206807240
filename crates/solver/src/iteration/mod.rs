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
//! `u_F = S K^-1 F`). One evaluation of `Psi` (`Sweep::evaluate`, shared
//! by every method) costs one back-substitution sweep. The paper iterates
//! `x <- Psi(x)` (and then `rho_s = Psi(x)_s - x_s`), [`Method::Anderson`]
//! mixes the last iterates, [`Method::Newton`] solves `R(x) = Psi(x) - x = 0`
//! by a semi-smooth Newton-Krylov method (see the private `newton` module).
//! Only back-substitutions are ever repeated: no coupled system is factorized.
//!
//! The stages, entry -> setup -> transfer -> sweep -> release -> method
//! (fixed point / Newton) -> steps, each a private module:
//!
//! - `entry`: [`solve`], the one entry; it chooses one-shot or stepped;
//! - `setup`: the fixed data of a run (the checked problem, the joint
//!   points and nodes, the plastic bodies (`body`: their cells, Gauss
//!   points and nodes, released like the joints: docs/theory.md section 8),
//!   the elastic solution);
//! - `transfer`: synthesis S and analysis A between sections and harmonics;
//! - `sweep`: the fixed data at one load `state` (the load factor and the
//!   law); one sweep back-substitutes every harmonic;
//! - `release`: the joint law on a sweep's displacements (one evaluation
//!   of `Psi`, an `eval`) and its tangent;
//! - `method`: a run from a start to a converged state or a failure
//!   (`attempt`): `fixed_point` (the paper's and Anderson's iterations) or
//!   `newton` (Newton-Krylov on a `formulation`: its nodal form, or the
//!   `traction` form for joints stiffer than their elements, with the
//!   `precondition`er, its fixed `interface` data and `banded` interface
//!   system, solved by `gmres`);
//! - `steps`: the load path, step by step.
//!
//! Beneath them `types` (the public types) and `diagnosis` (why a run
//! stopped); beside them `probe` ([`FixedPoint`], for tests). A module
//! imports only modules below it: types, body, eval, transfer, interface, state
//! <- setup <- attempt, diagnosis, banded <- sweep <- release <- formulation,
//! gmres, precondition <- traction <- newton, fixed_point <- method <- steps <-
//! entry (probe above traction). This file holds nothing they import.

mod attempt;
mod banded;
mod body;
mod dense_lu;
mod diagnosis;
mod entry;
mod eval;
mod fixed_point;
mod formulation;
mod gmres;
mod interface;
mod method;
mod newton;
mod precondition;
mod probe;
mod release;
mod setup;
mod stall;
mod state;
mod steps;
mod sweep;
mod traction;
mod transfer;
mod types;
mod vector;
mod watchdog;

pub use body::plastic_points;
pub use entry::{solve, stress_transfer, Solved, Stepping};
pub use probe::FixedPoint;
pub use steps::{
    LimitLoad, LoadStep, StepControl, Stepped, BRACKET, EASY_ITERATIONS, MAX_CUTBACKS, MAX_ROUNDS,
    MIN_INCREMENT, PATH_MIN, PATH_TOL,
};
pub use sweep::OBSERVED_UP_TO;
pub use types::{
    joint_point_infos, BodyField, InterfaceSolve, IterationError, IterationRecord, IterationSettings,
    JointField, JointStart, Method, Outcome, PointInfo, Problem, StageEnd, StageStart, StepBodies,
    TANGENT_RHO_FLOOR,
};
