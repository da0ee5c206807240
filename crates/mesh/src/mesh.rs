//! The meridional mesh as plain data.

use serde::Serialize;

/// Element families of the meridional (r, z) plane, node order as gmsh's.
///
/// Triangles live on the reference triangle (0,0), (1,0), (0,1); quadrilaterals
/// on [-1, 1]^2. Corner nodes come first, counter-clockwise, then mid-side
/// nodes (edge 0-1 first), then the centre node (Q9).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum CellKind {
    /// 3-node triangle (gmsh type 2).
    Tri3,
    /// 6-node triangle (gmsh type 9).
    Tri6,
    /// 4-node quadrilateral (gmsh type 3).
    Quad4,
    /// 8-node serendipity quadrilateral (gmsh type 16).
    Quad8,
    /// 9-node Lagrange quadrilateral (gmsh type 10).
    Quad9,
}

/// Line elements on physical curves, node order as gmsh's: ends, then middle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum EdgeKind {
    /// 2-node line (gmsh type 1).
    Lin2,
    /// 3-node line (gmsh type 8).
    Lin3,
}

impl CellKind {
    /// Number of nodes.
    pub const fn n_nodes(self) -> usize {
        match self {
            CellKind::Tri3 => 3,
            CellKind::Tri6 => 6,
            CellKind::Quad4 => 4,
            CellKind::Quad8 => 8,
            CellKind::Quad9 => 9,
        }
    }

    /// Number of corner nodes (3 or 4).
    pub const fn n_corners(self) -> usize {
        match self {
            CellKind::Tri3 | CellKind::Tri6 => 3,
            _ => 4,
        }
    }

    /// True for the quadratic families (T6, Q8, Q9).
    pub const fn is_quadratic(self) -> bool {
        matches!(self, CellKind::Tri6 | CellKind::Quad8 | CellKind::Quad9)
    }

    /// The kind of the element's edges.
    pub const fn edge_kind(self) -> EdgeKind {
        if self.is_quadratic() {
            EdgeKind::Lin3
        } else {
            EdgeKind::Lin2
        }
    }

    /// Local node indices of edge `e` (0-based, counter-clockwise from edge
    /// 0-1): `[start, end]` for linear cells, `[start, end, middle]` for
    /// quadratic ones.
    pub fn edge_nodes(self, e: usize) -> &'static [usize] {
        const T3: [[usize; 2]; 3] = [[0, 1], [1, 2], [2, 0]];
        const T6: [[usize; 3]; 3] = [[0, 1, 3], [1, 2, 4], [2, 0, 5]];
        const Q4: [[usize; 2]; 4] = [[0, 1], [1, 2], [2, 3], [3, 0]];
        const Q8: [[usize; 3]; 4] = [[0, 1, 4], [1, 2, 5], [2, 3, 6], [3, 0, 7]];
        match self {
            CellKind::Tri3 => &T3[e],
            CellKind::Tri6 => &T6[e],
            CellKind::Quad4 => &Q4[e],
            CellKind::Quad8 | CellKind::Quad9 => &Q8[e],
        }
    }

    /// Short name as used in summaries: `T3`, `T6`, `Q4`, `Q8`, `Q9`.
    pub const fn name(self) -> &'static str {
        match self {
            CellKind::Tri3 => "T3",
            CellKind::Tri6 => "T6",
            CellKind::Quad4 => "Q4",
            CellKind::Quad8 => "Q8",
            CellKind::Quad9 => "Q9",
        }
    }
}

impl EdgeKind {
    /// Number of nodes.
    pub const fn n_nodes(self) -> usize {
        match self {
            EdgeKind::Lin2 => 2,
            EdgeKind::Lin3 => 3,
        }
    }
}

/// A 2D element of a body.
#[derive(Clone, Debug, PartialEq)]
pub struct Cell {
    /// Element family.
    pub kind: CellKind,
    /// Node indices (into [`Mesh::nodes`]), `kind.n_nodes()` of them.
    pub nodes: Vec<usize>,
    /// Index into [`Mesh::bodies`].
    pub body: usize,
    /// The element's tag in the `.msh` file (for messages).
    pub tag: u64,
    /// The gmsh surface entity the element belongs to.
    pub entity: i32,
}

/// A line element on a physical curve.
#[derive(Clone, Debug, PartialEq)]
pub struct Edge {
    /// Line family.
    pub kind: EdgeKind,
    /// Node indices: ends, then the middle node for [`EdgeKind::Lin3`].
    pub nodes: Vec<usize>,
    /// The element's tag in the `.msh` file.
    pub tag: u64,
    /// The gmsh curve entity the element belongs to.
    pub entity: i32,
}

/// A physical surface: one body of one material.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Body {
    /// Physical name.
    pub name: String,
    /// Physical tag.
    pub tag: i32,
}

/// A physical curve with its line elements.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveSet {
    /// Physical name.
    pub name: String,
    /// Physical tag.
    pub tag: i32,
    /// Line elements, in file order.
    pub edges: Vec<Edge>,
}

/// A physical point group with its nodes.
#[derive(Clone, Debug, PartialEq)]
pub struct PointSet {
    /// Physical name.
    pub name: String,
    /// Physical tag.
    pub tag: i32,
    /// Node indices. After joint insertion a split node is listed with all
    /// its copies.
    pub nodes: Vec<usize>,
}

/// Joint element families: zero thickness, paired faces.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum JointKind {
    /// 4 nodes: 2 on the bottom face, 2 on the top face (along linear edges).
    Lin4,
    /// 6 nodes: 3 on each face (along quadratic edges).
    Lin6,
}

/// A zero-thickness joint element.
///
/// ```text
///   top:     t0 ---- t2 ---- t1        eta (normal, bottom -> top)
///            ||      ||      ||         ^
///   bottom:  b0 ---- b2 ---- b1         |--> xi (tangent, b0 -> b1)
/// ```
///
/// `bottom[i]` and `top[i]` have equal coordinates. The tangent xi runs from
/// `bottom[0]` to `bottom[1]`; the normal eta is xi turned +90 degrees in the
/// (r, z) plane, `eta = (-xi_z, xi_r)`, and points into the top body. The
/// relative displacement is `u(top) - u(bottom)`: positive normal opens.
#[derive(Clone, Debug, PartialEq)]
pub struct JointElement {
    /// Family.
    pub kind: JointKind,
    /// Bottom-face nodes: start, end (and middle for [`JointKind::Lin6`]).
    pub bottom: Vec<usize>,
    /// Top-face nodes, paired with `bottom`.
    pub top: Vec<usize>,
    /// Tag of the line element the joint was made from.
    pub edge_tag: u64,
    /// The bottom-side cell (index into [`Mesh::cells`]).
    pub bottom_cell: usize,
    /// The top-side cell.
    pub top_cell: usize,
}

/// An interface made of joint elements along one physical curve.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Physical name of the curve.
    pub name: String,
    /// Bodies on the bottom face (indices into [`Mesh::bodies`], sorted);
    /// several when the curve runs along several bodies (layered soil).
    pub bottom_bodies: Vec<usize>,
    /// Bodies on the top face (sorted).
    pub top_bodies: Vec<usize>,
    /// Joint elements, in the order of the curve's line elements.
    pub elements: Vec<JointElement>,
    /// Node pairs `(original, copy)` created by the insertion.
    pub duplicated: Vec<(usize, usize)>,
}

impl Joint {
    /// Mean length of its elements (their end nodes' chord) at the node
    /// coordinates `nodes`; 0 without elements.
    pub fn mean_length(&self, nodes: &[[f64; 2]]) -> f64 {
        let total: f64 = self
            .elements
            .iter()
            .map(|e| {
                let (a, b) = (nodes[e.bottom[0]], nodes[e.bottom[1]]);
                (b[0] - a[0]).hypot(b[1] - a[1])
            })
            .sum();
        total / self.elements.len().max(1) as f64
    }

    /// Shortest length of its elements (their end nodes' chord, as
    /// [`Joint::mean_length`]) at the node coordinates `nodes`; 0 without
    /// elements.
    pub fn min_length(&self, nodes: &[[f64; 2]]) -> f64 {
        let shortest = self
            .elements
            .iter()
            .map(|e| {
                let (a, b) = (nodes[e.bottom[0]], nodes[e.bottom[1]]);
                (b[0] - a[0]).hypot(b[1] - a[1])
            })
            .fold(f64::INFINITY, f64::min);
        if shortest.is_finite() {
            shortest
        } else {
            0.0
        }
    }
}

/// A meridional mesh: nodes in (r, z), bodies, boundary sets and joints.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Node coordinates `[r, z]`.
    pub nodes: Vec<[f64; 2]>,
    /// Tag of each node in the `.msh` file; copies made by joint insertion
    /// get fresh tags above the file's largest.
    pub node_tags: Vec<u64>,
    /// 2D elements.
    pub cells: Vec<Cell>,
    /// Physical surfaces.
    pub bodies: Vec<Body>,
    /// Physical curves.
    pub curves: Vec<CurveSet>,
    /// Physical points.
    pub points: Vec<PointSet>,
    /// Interfaces, after [`crate::insert_joints`].
    pub joints: Vec<Joint>,
}

impl Mesh {
    /// The body with this physical name.
    pub fn body(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    /// The physical curve with this name.
    pub fn curve(&self, name: &str) -> Option<&CurveSet> {
        self.curves.iter().find(|c| c.name == name)
    }

    /// The physical point group with this name.
    pub fn point(&self, name: &str) -> Option<&PointSet> {
        self.points.iter().find(|p| p.name == name)
    }

    /// The joint with this name.
    pub fn joint(&self, name: &str) -> Option<&Joint> {
        self.joints.iter().find(|j| j.name == name)
    }

    /// Coordinates of a cell's nodes.
    pub fn cell_coords(&self, cell: &Cell) -> Vec<[f64; 2]> {
        cell.nodes.iter().map(|&n| self.nodes[n]).collect()
    }
}
