//! gmsh element types: node counts (needed to read any element) and what
//! axijoint makes of them (the numbers it uses are named in
//! [`element_type`](super::element_type)).

use super::element_type::{LINE2, LINE3, POINT, QUAD4, QUAD8, QUAD9, TET10, TRI3, TRI6};
use crate::{CellKind, EdgeKind};

/// A gmsh element type the reader knows the size of.
#[derive(Clone, Copy, Debug)]
pub(super) struct TypeInfo {
    /// Number of nodes.
    pub nodes: usize,
    /// Dimension of the element (0 point, 1 line, 2 surface, 3 volume).
    pub dim: i32,
    /// Description for messages.
    pub name: &'static str,
}

/// Node count, dimension and name of gmsh element type `t`
/// (`GmshDefines.h` numbering), or `None` for a type we cannot even size.
pub(super) fn type_info(t: i32) -> Option<TypeInfo> {
    let (nodes, dim, name) = match t {
        LINE2 => (2, 1, "2-node line"),
        TRI3 => (3, 2, "3-node triangle"),
        QUAD4 => (4, 2, "4-node quadrangle"),
        4 => (4, 3, "4-node tetrahedron"),
        5 => (8, 3, "8-node hexahedron"),
        6 => (6, 3, "6-node prism"),
        7 => (5, 3, "5-node pyramid"),
        LINE3 => (3, 1, "3-node line"),
        TRI6 => (6, 2, "6-node triangle"),
        QUAD9 => (9, 2, "9-node quadrangle"),
        TET10 => (10, 3, "10-node tetrahedron"),
        12 => (27, 3, "27-node hexahedron"),
        13 => (18, 3, "18-node prism"),
        14 => (14, 3, "14-node pyramid"),
        POINT => (1, 0, "1-node point"),
        QUAD8 => (8, 2, "8-node quadrangle"),
        17 => (20, 3, "20-node hexahedron"),
        18 => (15, 3, "15-node prism"),
        19 => (13, 3, "13-node pyramid"),
        20 => (9, 2, "9-node incomplete cubic triangle"),
        21 => (10, 2, "10-node cubic triangle"),
        22 => (12, 2, "12-node incomplete quartic triangle"),
        23 => (15, 2, "15-node quartic triangle"),
        24 => (15, 2, "15-node incomplete quintic triangle"),
        25 => (21, 2, "21-node quintic triangle"),
        26 => (4, 1, "4-node cubic line"),
        27 => (5, 1, "5-node quartic line"),
        28 => (6, 1, "6-node quintic line"),
        29 => (20, 3, "20-node cubic tetrahedron"),
        30 => (35, 3, "35-node quartic tetrahedron"),
        31 => (56, 3, "56-node quintic tetrahedron"),
        36 => (16, 2, "16-node cubic quadrangle"),
        37 => (25, 2, "25-node quartic quadrangle"),
        38 => (36, 2, "36-node quintic quadrangle"),
        92 => (64, 3, "64-node cubic hexahedron"),
        93 => (125, 3, "125-node quartic hexahedron"),
        _ => return None,
    };
    Some(TypeInfo { nodes, dim, name })
}

/// What axijoint makes of an element type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Role {
    /// A cell of a body.
    Cell(CellKind),
    /// An edge of physical curves.
    Edge(EdgeKind),
    /// A node of physical points.
    Point,
}

/// The role of gmsh type `t`, `None` if axijoint does not use it.
pub(super) fn role(t: i32) -> Option<Role> {
    Some(match t {
        TRI3 => Role::Cell(CellKind::Tri3),
        TRI6 => Role::Cell(CellKind::Tri6),
        QUAD4 => Role::Cell(CellKind::Quad4),
        QUAD8 => Role::Cell(CellKind::Quad8),
        QUAD9 => Role::Cell(CellKind::Quad9),
        LINE2 => Role::Edge(EdgeKind::Lin2),
        LINE3 => Role::Edge(EdgeKind::Lin3),
        POINT => Role::Point,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roles_agree_with_node_counts() {
        for t in 0..200 {
            let Some(r) = role(t) else { continue };
            let info = type_info(t).expect("every used type is sized");
            let (n, dim) = match r {
                Role::Cell(k) => (k.n_nodes(), 2),
                Role::Edge(k) => (k.n_nodes(), 1),
                Role::Point => (1, 0),
            };
            assert_eq!((info.nodes, info.dim), (n, dim), "type {t}");
        }
    }
}
