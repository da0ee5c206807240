//! From a scene to a model: the mesh (gmsh, checks, joints inserted), the
//! supports, the joints' assembled springs, the laws and the iteration's
//! settings.

use crate::assembly::JointModel;
use crate::elements::JointSprings;
use crate::error::SolverError;
use crate::linear::Model;
use crate::scene::{JointLaw, JointStiffness, Scene, SceneError};
use axijoint_mesh::{gmsh, insert_joints, validate, Mesh, Validation};
use std::path::Path;

/// A scene's mesh (joints inserted) after validation against the scene.
pub fn mesh_scene(scene: &Scene, keep_msh: Option<&Path>) -> Result<(Mesh, Validation), SolverError> {
    let path = scene.mesh_path();
    let mut mesh = gmsh::load(&path, &scene.gmsh_parameters(), keep_msh)?;
    scene.check(&mesh)?;
    let report = validate(&mut mesh, &path)?;
    insert_joints(&mut mesh, &scene.joint_specs(), &path)?;
    Ok((mesh, report))
}

/// Support flags per node DOF (`3 * node + component`).
pub fn support_flags(scene: &Scene, mesh: &Mesh) -> Vec<bool> {
    let mut fixed = vec![false; 3 * mesh.nodes.len()];
    for s in &scene.all_supports() {
        let comps = s.fix.components();
        for n in support_nodes(mesh, &s.on) {
            for c in 0..3 {
                fixed[3 * n + c] |= comps[c];
            }
        }
    }
    fixed
}

/// Nodes of a physical curve (looked up first) or point group.
pub fn support_nodes(mesh: &Mesh, name: &str) -> Vec<usize> {
    let mut nodes: Vec<usize> = match mesh.curve(name) {
        Some(c) => c.edges.iter().flat_map(|e| e.nodes.iter().copied()).collect(),
        None => mesh.point(name).map(|p| p.nodes.clone()).unwrap_or_default(),
    };
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

/// `k h / E` above which a nonlinear joint solved by Newton is assembled
/// with the softer reference `k_ref = REFERENCE_STIFFNESS E / h` (per
/// component, never stiffer than the joint): every method converged up to
/// `k h / E = 1` on Scene P (docs/stability.md).
pub const REFERENCE_STIFFNESS: f64 = 1.0;

/// The springs assembled for a nonlinear joint: `min(k, k_ref)` per
/// component, `k_ref = REFERENCE_STIFFNESS E / h` with h its mean element
/// length and E the smallest Young's modulus of its bodies.
fn reference_springs(
    mesh: &Mesh,
    joint: &axijoint_mesh::Joint,
    materials: &[crate::material::Elastic],
    k: crate::elements::JointSprings,
) -> crate::elements::JointSprings {
    let h = joint.mean_length(&mesh.nodes);
    let e = crate::material::softer_side(joint, materials).map_or(f64::INFINITY, |m| m.e);
    if !(e.is_finite() && h > 0.0) {
        return k;
    }
    let cap = REFERENCE_STIFFNESS * e / h;
    crate::elements::JointSprings {
        k_xi: k.k_xi.min(cap),
        k_eta: k.k_eta.min(cap),
        k_theta: k.k_theta.min(cap),
    }
}

/// The springs of joint `joint` of `scene` on `mesh` (joints inserted;
/// `materials` per body): as given, or resolved from the softer body on its
/// faces (smallest E, with its nu) and its shortest element
/// ([`JointStiffness::resolve`]).
pub fn joint_springs(
    scene: &Scene,
    mesh: &Mesh,
    joint: &axijoint_mesh::Joint,
    materials: &[crate::material::Elastic],
) -> Result<JointSprings, SolverError> {
    let config = &scene.joints[&joint.name];
    let stiffness = scene.joint_stiffness(&joint.name, config)?;
    if let JointStiffness::Given(k) = stiffness {
        return Ok(k);
    }
    let softer = crate::material::softer_side(joint, materials);
    let h_min = joint.min_length(&mesh.nodes);
    match softer {
        Some(softer) if h_min > 0.0 => Ok(stiffness.resolve(softer, h_min)),
        _ => Err(SceneError::Invalid {
            path: scene.path.clone(),
            key: format!("joints.{}.stiffness", joint.name),
            message: "the joint has no elements between bodies to measure: give k_xi, k_eta and k_theta"
                .into(),
        }
        .into()),
    }
}

/// Builds the linear model of a scene on its mesh; each joint's springs
/// are resolved here, once ([`joint_springs`]).
pub fn build_model(scene: &Scene, mesh: Mesh) -> Result<Model, SolverError> {
    let materials: Vec<_> = mesh
        .bodies
        .iter()
        .map(|b| scene.materials[&b.name].elastic())
        .collect();
    let joints = mesh
        .joints
        .iter()
        .map(|j| {
            let config = &scene.joints[&j.name];
            let kind = j
                .elements
                .first()
                .map_or(axijoint_mesh::JointKind::Lin6, |e| e.kind);
            let springs = joint_springs(scene, &mesh, j, &materials)?;
            let mut joint = JointModel::new(springs, config.rule(kind));
            if config.law != JointLaw::Linear {
                let reference = reference_springs(&mesh, j, &materials, joint.springs);
                joint.opening = reference.k_eta;
                if scene.solver.method == crate::scene::SolverMethod::Newton {
                    joint.assembled = reference;
                }
            }
            Ok(joint)
        })
        .collect::<Result<Vec<_>, SolverError>>()?;
    let fixed = support_flags(scene, &mesh);
    let plasticity = mesh
        .bodies
        .iter()
        .map(|b| scene.materials[&b.name].plasticity)
        .collect();
    let mut model = Model::new(mesh, materials, joints, fixed)?;
    model.plasticity = plasticity;
    Ok(model)
}

/// The laws of the model's joints, in model order.
pub(super) fn joint_laws(scene: &Scene, model: &Model) -> Vec<JointLaw> {
    model
        .mesh
        .joints
        .iter()
        .map(|j| scene.joints[&j.name].law)
        .collect()
}

/// The iteration settings of a scene's `solver` block.
pub fn iteration_settings(scene: &Scene) -> crate::iteration::IterationSettings {
    use crate::iteration::{IterationSettings, Method};
    IterationSettings {
        method: match scene.solver.method {
            crate::scene::SolverMethod::Paper => Method::Plain,
            crate::scene::SolverMethod::Anderson => Method::Anderson { depth: 8 },
            crate::scene::SolverMethod::Newton => Method::Newton,
        },
        epsilon: scene.solver.epsilon,
        max_iterations: scene.solver.max_iterations,
        ..IterationSettings::default()
    }
}
