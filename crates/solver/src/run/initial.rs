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
use crate::linear::Model;
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
    /// The stress of each plastic body point at the end of the phase
    /// (axisymmetric; empty without plastic bodies), in the order of
    /// [`crate::iteration::plastic_points`].
    pub body_stress: Vec<[f64; 6]>,
    /// The plastic strain of each plastic body point at the end of the
    /// phase (same order).
    pub body_plastic: Vec<[f64; 6]>,
}

impl InitialState {
    /// The start state of an iteration on `n_sections` sections.
    pub fn joint_start(&self, n_sections: usize) -> JointStart {
        JointStart {
            traction: self.traction.repeat(n_sections),
            debonded: self.debonded.repeat(n_sections),
            body_stress: self.body_stress.clone(),
            body_plastic: self.body_plastic.clone(),
        }
    }
}

/// The initial stress of every plastic body point of `model` (in the order
/// of [`crate::iteration::plastic_points`]): the material's
/// `initial_stress` (effective with water), zero where it has none.
fn plastic_point_stress(scene: &Scene, model: &Model) -> Result<Vec<[f64; 6]>, SolverError> {
    let points = crate::iteration::plastic_points(model).map_err(|e| SolverError::InitialPhase {
        beyond_capacity: false,
        message: e.to_string(),
    })?;
    if points.is_empty() {
        return Ok(Vec::new());
    }
    let bodies = crate::initial::body_stresses(scene, model);
    Ok(points
        .iter()
        .map(|&(cell, p)| match bodies[model.mesh.cells[cell].body] {
            Some((s0, gamma)) => s0.at(p[1], gamma, scene.water.as_ref()),
            None => [0.0; 6],
        })
        .collect())
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
    let body_stress = plastic_point_stress(scene, model)?;
    let linear = (!scene.has_nonlinear_joints() || model.mesh.joints.is_empty()) && body_stress.is_empty();
    let (displacements, iterations, traction, debonded, body) = if linear {
        // No iteration: the linear joints end at t0 + k d of the phase.
        let u = solve_loads(model, &problem.factors, &phase);
        let points = crate::iteration::joint_point_infos(model);
        let axisymmetric = crate::fourier::Sections::full_circle(vec![0.0]).expect("one section is valid");
        let d = joint_relative_displacements(&points, &u, &axisymmetric);
        let traction = linear_tractions(model, &points, &d, Some(&il.traction));
        (u, 0, traction, vec![false; n_points], None)
    } else {
        let sections = scene_sections(scene, model, loads)?;
        let start = JointStart {
            traction: il.traction.repeat(sections.len()),
            debonded: vec![false; sections.len() * n_points],
            body_stress: body_stress.clone(),
            body_plastic: Vec::new(),
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
            cancel: None,
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
        // The phase is axisymmetric: its first section holds every point.
        let body = outcome.body.map(|b| {
            let n_b = b.points.len();
            (b.sigma[..n_b].to_vec(), b.plastic[..n_b].to_vec())
        });
        (
            outcome.displacements,
            iterations,
            field.p[..n_points].to_vec(),
            field.debonded[..n_points].to_vec(),
            body,
        )
    };
    let (body_stress, body_plastic) = body.unwrap_or((body_stress, Vec::new()));
    Ok(InitialState {
        max_displacement: max_displacement(n, &displacements),
        displacements,
        balance: il.balance,
        iterations,
        traction,
        debonded,
        body_stress,
        body_plastic,
    })
}
