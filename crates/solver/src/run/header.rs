//! The header of a solution folder (`solution.json`) and its run record,
//! built in one place from a [`Run`].

use super::initial::InitialState;
use super::measures::{face_displacement, max_displacement};
use super::Run;
use crate::iteration::IterationError;
use crate::results::*;
use crate::scene::Scene;

/// The header of a run of `scene` (the scene as run: its harmonics chosen),
/// its record included (see [`crate::results`]). Like every other output,
/// `applied` is that of the last converged load step (the reactions
/// balance `lambda F`, not `F`).
pub fn solution_header(scene: &Scene, run: &Run) -> SolutionHeader {
    let mut header = bare_header(scene, run);
    header.record = record(scene, run);
    header.members = members(scene, run);
    if let Some(limit) = run.load_path.as_ref().and_then(|p| p.limit.as_ref()) {
        let a = &mut header.applied;
        for v in a.force.iter_mut().chain(a.moment.iter_mut()) {
            *v *= limit.factor;
        }
    }
    header
}

/// The header of the last iterate of a one-shot run that stopped with
/// `error` (`run`: that iterate), marked `"converged": false`.
pub fn last_iterate_header(scene: &Scene, run: &Run, error: &IterationError) -> SolutionHeader {
    let mut header = bare_header(scene, run);
    header.record = run.outcome.as_ref().map(|last| RunRecord {
        joint_springs: joint_springs(scene, run),
        converged: Some(false),
        complete: Some(false),
        error: Some(error.to_string()),
        iterations: Some(last.history.len()),
        sections_deg: Some(sections_deg(last)),
        history: Some(last.history.clone()),
        loading: Some(scene.solver.loading),
        note: Some(
            "not converged: the displacements and joint states are those of the last iterate, not an equilibrium"
                .into(),
        ),
        ..RunRecord::default()
    });
    header
}

/// The record of a finished run; `None` for a linear run of a given M
/// without joints or warnings.
pub fn record(scene: &Scene, run: &Run) -> Option<RunRecord> {
    let mut r = RunRecord {
        joint_springs: joint_springs(scene, run),
        ..RunRecord::default()
    };
    if let Some(outcome) = &run.outcome {
        r.iterations = Some(outcome.history.len());
        r.sections_deg = Some(sections_deg(outcome));
        r.history = Some(outcome.history.clone());
        r.released_spectrum = Some(outcome.released_spectrum.clone());
        r.harmonic_check = Some(run.harmonic_check.clone());
        // Every nonlinear run says how its load was applied (a one-shot
        // run has no load path but is one).
        r.loading = Some(scene.solver.loading);
    }
    if let Some(path) = &run.load_path {
        r.load_path = Some(path.clone());
        r.load_factor = Some(path.reached());
        if let Some(limit) = &path.limit {
            if limit.beyond_capacity {
                r.limit_load_factor = Some(limit.factor);
            }
            r.complete = Some(false);
            let of = path.stopped_in.as_ref().map_or(String::new(), |m| {
                format!(" of {} (the loads are those applied there)", m.label())
            });
            r.note = Some(format!(
                "the whole load was not reached: every result is that of the last converged load factor {:.6}{of}",
                limit.factor
            ));
        }
    }
    if !run.auto_steps.is_empty() {
        r.auto_harmonics = Some(AutoHarmonics {
            chosen: scene.harmonics(),
            tolerance: scene.solver.harmonics_tolerance,
            steps: run.auto_steps.clone(),
        });
    }
    r.warnings = super::plausible::warnings(scene, run);
    (r != RunRecord::default()).then_some(r)
}

/// The member forces of the bodies in `outputs.members` at the last
/// converged load factor.
fn members(scene: &Scene, run: &Run) -> Vec<crate::members::MemberForces> {
    let model = &run.problem.model;
    let lambda = run.load_path.as_ref().map_or(1.0, LoadPath::reached);
    let field = run.joint_field(scene).ok().flatten();
    scene
        .outputs
        .members
        .iter()
        .filter_map(|name| model.mesh.body(name))
        .map(|body| {
            crate::members::member_forces(
                scene,
                model,
                &run.loads,
                lambda,
                &run.displacements,
                field.as_deref(),
                body,
            )
        })
        .collect()
}

/// Each joint's springs as solved and their source, by name.
fn joint_springs(scene: &Scene, run: &Run) -> std::collections::BTreeMap<String, JointSpringsRecord> {
    let model = &run.problem.model;
    model
        .mesh
        .joints
        .iter()
        .zip(&model.joints)
        .filter_map(|(j, m)| {
            let config = scene.joints.get(&j.name)?;
            let source = config.stiffness().ok()?.source();
            let k = m.springs;
            Some((
                j.name.clone(),
                JointSpringsRecord {
                    k_xi: k.k_xi,
                    k_eta: k.k_eta,
                    k_theta: k.k_theta,
                    source,
                },
            ))
        })
        .collect()
}

/// The joint sections of an outcome, in degrees.
fn sections_deg(outcome: &crate::iteration::Outcome) -> Vec<f64> {
    outcome
        .field
        .sections
        .theta
        .iter()
        .map(|t| t.to_degrees())
        .collect()
}

/// The header without a record.
fn bare_header(scene: &Scene, run: &Run) -> SolutionHeader {
    let mesh = &run.problem.model.mesh;
    // With stages, every face loaded in some stage (the last may unload).
    let staged = scene.staged_faces();
    let loads = if scene.stages.is_empty() {
        &scene.loads
    } else {
        &staged
    };
    let loaded_faces = loads
        .iter()
        .filter_map(|l| face_displacement(mesh, l.on(), &run.displacements).map(|d| (l.on().to_string(), d)))
        .collect();
    let h = run.displacements.harmonics.len();
    SolutionHeader {
        format: FORMAT.into(),
        version: VERSION,
        scene_file: scene.path.display().to_string(),
        scene: scene.clone(),
        mesh: MeshRef {
            file: "mesh.msh".into(),
            nodes: mesh.nodes.len(),
            elements: mesh.cells.len(),
            joints: mesh.joints.iter().map(|j| j.name.clone()).collect(),
            checksum: mesh_checksum(mesh),
        },
        dofs_per_harmonic: run.problem.model.n_eq(),
        harmonics: run.displacements.harmonics.iter().map(|d| d.m).collect(),
        displacement: ArrayRef {
            file: "displacement.f64".into(),
            dtype: "f64le".into(),
            shape: vec![h, 2, mesh.nodes.len(), 3],
            layout: "[harmonic 0..=M][family: symmetric, antisymmetric][node][u_r, u_z, u_theta]".into(),
        },
        applied: run.applied.into(),
        reactions: run.reactions.clone(),
        loaded_faces,
        max_displacement: max_displacement(mesh.nodes.len(), &run.displacements),
        timings: run.timings.clone(),
        record: None,
        members: Vec::new(),
        initial: run.initial.as_ref().map(initial_info),
    }
}

/// The header's [`InitialInfo`] of an initial phase.
fn initial_info(initial: &InitialState) -> InitialInfo {
    let n = initial
        .displacements
        .harmonics
        .first()
        .map_or(0, |h| h.symmetric.len() / 3);
    InitialInfo {
        displacement: ArrayRef {
            file: "initial_displacement.f64".into(),
            dtype: "f64le".into(),
            shape: vec![1, 2, n, 3],
            layout: "[harmonic 0][family: symmetric, antisymmetric][node][u_r, u_z, u_theta]".into(),
        },
        balance: initial.balance,
        max_displacement: initial.max_displacement,
        iterations: initial.iterations,
    }
}
