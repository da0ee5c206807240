//! gmsh post-processing views of the meridional field at chosen angles.
//!
//! [`write_gmsh_view`] writes one MSH 2.2 ASCII file that gmsh opens as a
//! mesh with views on it (`gmsh view.msh`):
//!
//! - `$Nodes`: every meridional node (joint copies included) at
//!   `(x, y, z) = (r, z, 0)`, the plane of the `.geo` files; node `i` of the
//!   mesh is node `i + 1` in the file.
//! - `$Elements`: the cells (gmsh types 2, 9, 3, 16, 10, in gmsh node order),
//!   element `c + 1` for cell `c`, physical tag = the body's physical tag,
//!   elementary tag = the cell's surface entity; then the joint elements as
//!   lines (types 1 and 8) on their bottom-face nodes, physical tag = the
//!   joint curve's tag. `$PhysicalNames` names the bodies and joints.
//! - for each theta: a `$NodeData` view `displacement theta=<deg>` with
//!   `(u_r, u_z, u_theta)` (in-plane components first, so that gmsh's
//!   displacement warp of the (r, z) plane works), and six `$ElementNodeData`
//!   views `<component> theta=<deg>` (`sigma_r`, `sigma_z`, `sigma_theta`,
//!   `tau_rz`, `tau_rtheta`, `tau_ztheta`) with each cell's own stress at its
//!   nodes: nothing is averaged between cells, so the jump at a joint (or at
//!   any interface between bodies) shows. The view's time value is theta in
//!   degrees.
//!
//! With the plastic bodies' field ([`write_gmsh_view_with`]), a cell of a
//! plastic body shows at its nodes the stress recovered from `plastic.json`
//! ([`PlasticStress::at`], the section nearest the view's angle), as the
//! cuts and the `.vtu` do.
//!
//! Written under a temporary name and renamed into place; a non-finite value
//! fails with [`ReportError::NotFinite`] and leaves no file.

use crate::error::check_finite;
use crate::field::{Field, STRESS_NAMES};
use crate::recovery::PlasticStress;
use crate::ReportError;
use axijoint_mesh::msh::element_type;
use axijoint_mesh::{atomic, CellKind};
use std::fmt::Write as _;
use std::path::Path;

/// gmsh element type of a meridional cell ([`element_type::of_cell`]).
pub fn gmsh_type(kind: CellKind) -> u32 {
    element_type::of_cell(kind) as u32
}

/// The view name of a field at an angle: `"sigma_z theta=180"`.
pub fn view_name(quantity: &str, theta_deg: f64) -> String {
    format!("{quantity} theta={theta_deg}")
}

/// Writes the meridional mesh with displacement and stress views at each
/// angle of `theta_deg` (degrees) to `path` (MSH 2.2 ASCII; see the module
/// documentation).
pub fn write_gmsh_view(path: &Path, field: &Field, theta_deg: &[f64]) -> Result<(), ReportError> {
    write_gmsh_view_with(path, field, theta_deg, None)
}

/// [`write_gmsh_view`], the stress of a cell of a plastic body from
/// `plastic` when given.
pub fn write_gmsh_view_with(
    path: &Path,
    field: &Field,
    theta_deg: &[f64],
    plastic: Option<&PlasticStress>,
) -> Result<(), ReportError> {
    let mesh = field.mesh;
    check_finite(path, theta_deg, || "an angle".into())?;
    let mut s = String::new();
    let w = &mut s;
    // Formatting into a String cannot fail.
    let _ = writeln!(w, "$MeshFormat\n2.2 0 8\n$EndMeshFormat");

    // Physical names: bodies (dimension 2), joints (dimension 1).
    let joint_tags: Vec<i32> = mesh
        .joints
        .iter()
        .enumerate()
        .map(|(j, joint)| mesh.curve(&joint.name).map_or(100_000 + j as i32, |c| c.tag))
        .collect();
    let _ = writeln!(w, "$PhysicalNames\n{}", mesh.bodies.len() + mesh.joints.len());
    for (joint, tag) in mesh.joints.iter().zip(&joint_tags) {
        let _ = writeln!(w, "1 {tag} \"{}\"", quote(&joint.name));
    }
    for b in &mesh.bodies {
        let _ = writeln!(w, "2 {} \"{}\"", b.tag, quote(&b.name));
    }
    let _ = writeln!(w, "$EndPhysicalNames");

    check_finite(path, mesh.nodes.as_flattened(), || "a node coordinate".into())?;
    let _ = writeln!(w, "$Nodes\n{}", mesh.nodes.len());
    for (i, p) in mesh.nodes.iter().enumerate() {
        let _ = writeln!(w, "{} {:e} {:e} 0", i + 1, p[0], p[1]);
    }
    let _ = writeln!(w, "$EndNodes");

    let n_lines: usize = mesh.joints.iter().map(|j| j.elements.len()).sum();
    let _ = writeln!(w, "$Elements\n{}", mesh.cells.len() + n_lines);
    for (c, cell) in mesh.cells.iter().enumerate() {
        let physical = mesh.bodies[cell.body].tag;
        let entity = if cell.entity > 0 {
            cell.entity
        } else {
            physical.max(1)
        };
        let _ = write!(w, "{} {} 2 {physical} {entity}", c + 1, gmsh_type(cell.kind));
        for &n in &cell.nodes {
            let _ = write!(w, " {}", n + 1);
        }
        let _ = writeln!(w);
    }
    let mut id = mesh.cells.len();
    for (j, joint) in mesh.joints.iter().enumerate() {
        for el in &joint.elements {
            id += 1;
            let t = element_type::of_joint_face(el.kind);
            let _ = write!(w, "{id} {t} 2 {0} {0}", joint_tags[j]);
            for &n in &el.bottom {
                let _ = write!(w, " {}", n + 1);
            }
            let _ = writeln!(w);
        }
    }
    let _ = writeln!(w, "$EndElements");

    for (step, &deg) in theta_deg.iter().enumerate() {
        let theta = deg.to_radians();
        // Displacement at the nodes.
        let _ = writeln!(
            w,
            "$NodeData\n1\n\"{}\"\n1\n{deg:e}\n3\n{step}\n3\n{}",
            view_name("displacement", deg),
            mesh.nodes.len()
        );
        for n in 0..mesh.nodes.len() {
            let u = field.displacement(n, theta);
            check_finite(path, &u, || {
                format!("the displacement of node {n} at theta = {deg} deg")
            })?;
            let _ = writeln!(w, "{} {:e} {:e} {:e}", n + 1, u[0], u[1], u[2]);
        }
        let _ = writeln!(w, "$EndNodeData");
        // Stress at each cell's nodes, the cell's own field.
        let stress: Vec<Vec<[f64; 6]>> = (0..mesh.cells.len())
            .map(|c| match plastic.filter(|ps| ps.has(c)) {
                Some(ps) => mesh.cells[c]
                    .nodes
                    .iter()
                    .map(|&n| ps.at(c, mesh.nodes[n], theta).unwrap_or([f64::NAN; 6]))
                    .collect(),
                None => field.cell_node_stress(c, theta),
            })
            .collect();
        for (c, values) in stress.iter().enumerate() {
            check_finite(path, values.as_flattened(), || {
                format!("the stress of cell {c} at theta = {deg} deg")
            })?;
        }
        for (q, name) in STRESS_NAMES.iter().enumerate() {
            let _ = writeln!(
                w,
                "$ElementNodeData\n1\n\"{}\"\n1\n{deg:e}\n3\n{step}\n1\n{}",
                view_name(name, deg),
                mesh.cells.len()
            );
            for (c, values) in stress.iter().enumerate() {
                let _ = write!(w, "{} {}", c + 1, values.len());
                for v in values {
                    let _ = write!(w, " {:e}", v[q]);
                }
                let _ = writeln!(w);
            }
            let _ = writeln!(w, "$EndElementNodeData");
        }
    }
    atomic::write_bytes(path, s.as_bytes()).map_err(|e| ReportError::write(path, e))
}

/// A name inside gmsh's double quotes (no quote or newline inside).
fn quote(name: &str) -> String {
    name.chars()
        .map(|c| if c == '"' || c.is_control() { '_' } else { c })
        .collect()
}
