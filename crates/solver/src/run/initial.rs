//! The initial phase (docs/loading.md, "Initial phase"): self-weight and
//! initial stresses brought to balance before the scene's loads, the joint
//! law acting on the initial tractions.

use super::elastic::Problem;
use super::factors::solve_loads;
use super::measures::{joint_relative_displacements, linear_tractions, max_displacement};
use super::model::{iteration_settings, joint_laws};
use super::sections::scene_sections;
use crate::error::SolverError;
use crate::iteration::{IterationError, IterationRecord, JointStart};
use crate::loads::HarmonicLoads;
use crate::scene::Scene;
use crate::solution::Displacements;

/// The end of a scene's initial phase (docs/loading.md).
#[derive(Clone, Debug)]
pub struct InitialState {
    /// Displacements of the phase (harmonic 0 only).
    pub displacements: Displacements,
    /// The out-of-balance of the initial stresses.
    pub balance: crate::initial::Balance,
    /// Largest displacement magnitude of the phase.
    pub max_displacement: f64,
    /// Iterations of the phase (0 without nonlinear joints).
    pub iterations: usize,
    /// Joint traction `(tau_xi, sigma, tau_theta)` at the end of the phase,
    /// per joint point (axisymmetric: the same at every theta): the initial
    /// traction plus what the joint law adds along the phase (`k d` for a
    /// linear joint).
    pub traction: Vec<[f64; 3]>,
    /// Debonded joint points.
    pub debonded: Vec<bool>,
}

impl InitialState {
    /// The joint start state of an iteration on `n_sections` sections.
    pub fn joint_start(&self, n_sections: usize) -> JointStart {
        JointStart {
            traction: self.traction.repeat(n_sections),
            debonded: self.debonded.repeat(n_sections),
        }
    }
}

/// Solves the initial phase of `scene` on the factors of `problem`
/// (harmonic 0 must be among them; `loads`: the scene's, for its sections):
/// its out-of-balance with the joint law acting on the initial tractions,
/// along the scene's loading path.
pub fn initial_phase(
    scene: &Scene,
    problem: &Problem,
    loads: &[HarmonicLoads],
    progress: impl FnMut(&IterationRecord),
) -> Result<InitialState, SolverError> {
    let model = &problem.model;
    let il = crate::initial::initial_load(scene, model)?;
    let n = model.mesh.nodes.len();
    let phase = vec![HarmonicLoads {
        m: 0,
        symmetric: il.load,
        antisymmetric: vec![0.0; 3 * n],
        prescribed: None,
    }];
    let n_points = il.traction.len();
    let (displacements, iterations, traction, debonded) = if !scene.has_nonlinear_joints()
        || model.mesh.joints.is_empty()
    {
        // No iteration: the linear joints end at t0 + k d of the phase.
        let u = solve_loads(model, &problem.factors, &phase);
        let points = crate::iteration::joint_point_infos(model);
        let axisymmetric = crate::fourier::Sections::full_circle(vec![0.0]).expect("one section is valid");
        let d = joint_relative_displacements(&points, &u, &axisymmetric);
        let traction = linear_tractions(model, &points, &d, Some(&il.traction));
        (u, 0, traction, vec![false; n_points])
    } else {
        let sections = scene_sections(scene, model, loads)?;
        let start = JointStart {
            traction: il.traction.repeat(sections.len()),
            debonded: vec![false; sections.len() * n_points],
        };
        let laws = joint_laws(scene, model);
        let settings = iteration_settings(scene);
        let failed = |e: IterationError| SolverError::InitialPhase {
            beyond_capacity: matches!(e, IterationError::NoEquilibrium { .. }),
            message: e.to_string(),
        };
        let problem = crate::iteration::Problem {
            model,
            factors: &problem.factors,
            loads: &phase,
            laws: &laws,
            sections: &sections,
            elastic: None,
            whole_up_to: None,
            from: None,
        };
        let loading = scene.solver.loading.into();
        let solved = crate::iteration::solve(
            &problem,
            &settings,
            Some(&start),
            loading,
            |_, _, _, _| (),
            progress,
        )
        .map_err(failed)?;
        if let Some(limit) = solved.stepped.and_then(|s| s.limit) {
            return Err(SolverError::InitialPhase {
                message: format!(
                    "the joints cannot carry the initial state: the phase reached only {:.4} of its load ({})",
                    limit.factor, limit.reason
                ),
                beyond_capacity: limit.beyond_capacity,
            });
        }
        let outcome = solved.outcome;
        let iterations = outcome.history.len();
        let field = outcome.field;
        (
            outcome.displacements,
            iterations,
            field.p[..n_points].to_vec(),
            field.debonded[..n_points].to_vec(),
        )
    };
    Ok(InitialState {
        max_displacement: max_displacement(n, &displacements),
        displacements,
        balance: il.balance,
        iterations,
        traction,
        debonded,
    })
}
