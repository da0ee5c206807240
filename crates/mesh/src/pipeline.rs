//! `.geo`/`.msh` -> validated mesh with joints, in one call.

use crate::{gmsh, insert_joints, validate, JointSpec, Mesh, MeshError, Validation};
use std::path::Path;

/// Loads `path` (meshing a `.geo` with gmsh and `parameters`), validates the
/// cells, and inserts the `joints`. `keep_msh` keeps gmsh's `.msh` there.
pub fn prepare(
    path: &Path,
    parameters: &[(String, f64)],
    joints: &[JointSpec],
    keep_msh: Option<&Path>,
) -> Result<(Mesh, Validation), MeshError> {
    let mut mesh = gmsh::load(path, parameters, keep_msh)?;
    let report = validate(&mut mesh, path)?;
    insert_joints(&mut mesh, joints, path)?;
    Ok((mesh, report))
}
