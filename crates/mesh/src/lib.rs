//! Meridional meshes for axisymmetric bodies with zero-thickness joints.
//!
//! | symbol | meaning |
//! |---|---|
//! | r, z | radial and axial coordinates of the meridional half plane (gmsh x, y) |
//! | theta | circumferential angle, 0 on the +x axis |
//! | xi, eta | joint tangent (bottom\[0\] -> bottom\[1\]) and normal (bottom -> top) |
//! | T3, T6, Q4, Q8, Q9 | triangle / quadrilateral families (gmsh node order) |
//! | L2, L3 | line elements on physical curves |
//!
//! | main types | role |
//! |---|---|
//! | [`Mesh`] | nodes, cells, bodies, boundary sets, joints (plain data) |
//! | [`MshFile`] | a `.msh` file as read (MSH 4.1 ASCII/binary, MSH 2.2 ASCII) |
//! | [`Joint`], [`JointElement`] | zero-thickness interfaces made by [`insert_joints`] |
//! | [`CellEdges`] | the cell edges, to check the line elements of used curves |
//! | [`MeshError`] | every failure, naming file, line or entity |
//! | [`msh::element_type`] | the gmsh element type numbers, one place |
//! | [`atomic`] | files written whole or not at all (partial file, then rename) |
//!
//! Pipeline: [`gmsh::mesh_geo`] (`.geo` -> `.msh`), [`read_msh`] (`.msh` ->
//! [`Mesh`]), [`validate()`], [`insert_joints`], [`Summary`]; [`write_msh41`]
//! writes a mesh back, joints included.
//!
//! Validation: [`validate()`] refuses nodes at r < 0 and cells whose
//! Jacobian vanishes or changes sign anywhere in the cell (bounded over the
//! whole cell by [`geometry::jacobian_range`], not sampled at corners and
//! Gauss points), renumbers surfaces meshed clockwise, and refuses a line
//! element of any physical curve that is not an edge of a cell
//! ([`CellEdges`]; a caller that names a curve, as the solver's scene check
//! does, checks it first to name its own key).

pub mod atomic;
pub mod error;
pub mod geometry;
pub mod gmsh;
pub mod joints;
pub mod mesh;
pub mod msh;
pub mod pipeline;
pub mod quadrature;
pub mod shapes;
pub mod summary;
pub mod validate;

pub use error::MeshError;
pub use joints::{insert_joints, JointSpec};
pub use mesh::*;
pub use msh::{parse_msh, read_msh, write_msh41, MshFile};
pub use pipeline::prepare;
pub use summary::Summary;
pub use validate::{check_curve_edges, validate, CellEdges, Validation};

/// A byte count: a number of bytes, or a number with the suffix `K`, `M` or
/// `G` (KiB, MiB, GiB; `1.5G`); `None` for anything else.
pub fn parse_bytes(v: &str) -> Option<u64> {
    let (num, unit) = match v.char_indices().last()? {
        (i, c) if c.is_ascii_alphabetic() => (&v[..i], c.to_ascii_uppercase()),
        _ => (v, 'B'),
    };
    let shift = match unit {
        'B' => 0,
        'K' => 10,
        'M' => 20,
        'G' => 30,
        _ => return None,
    };
    let x: f64 = num.trim().parse().ok()?;
    (x >= 0.0 && x.is_finite()).then(|| (x * (1u64 << shift) as f64) as u64)
}
