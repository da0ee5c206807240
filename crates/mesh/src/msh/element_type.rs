//! The gmsh element type numbers axijoint reads and writes
//! (`GmshDefines.h`), and the type of each cell, line and joint kind.

use crate::{CellKind, EdgeKind, JointKind};

/// 2-node line.
pub const LINE2: i32 = 1;
/// 3-node triangle.
pub const TRI3: i32 = 2;
/// 4-node quadrangle.
pub const QUAD4: i32 = 3;
/// 3-node line.
pub const LINE3: i32 = 8;
/// 6-node triangle.
pub const TRI6: i32 = 9;
/// 9-node quadrangle.
pub const QUAD9: i32 = 10;
/// 10-node tetrahedron.
pub const TET10: i32 = 11;
/// 1-node point.
pub const POINT: i32 = 15;
/// 8-node quadrangle.
pub const QUAD8: i32 = 16;

/// The gmsh type of a meridional cell.
pub fn of_cell(kind: CellKind) -> i32 {
    match kind {
        CellKind::Tri3 => TRI3,
        CellKind::Tri6 => TRI6,
        CellKind::Quad4 => QUAD4,
        CellKind::Quad8 => QUAD8,
        CellKind::Quad9 => QUAD9,
    }
}

/// The gmsh type of a line element.
pub fn of_edge(kind: EdgeKind) -> i32 {
    match kind {
        EdgeKind::Lin2 => LINE2,
        EdgeKind::Lin3 => LINE3,
    }
}

/// The gmsh type of a joint element's face (a line of 2 or 3 nodes).
pub fn of_joint_face(kind: JointKind) -> i32 {
    match kind {
        JointKind::Lin4 => LINE2,
        JointKind::Lin6 => LINE3,
    }
}
