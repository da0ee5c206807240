//! Mesh validation: what the solver needs before it can trust the mesh.

use crate::geometry::jacobian_range;
use crate::{CellKind, CurveSet, EdgeKind, Mesh, MeshError};
use std::collections::BTreeMap;
use std::path::Path;

/// What validation changed.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Validation {
    /// Cells renumbered to counter-clockwise, because their whole surface
    /// entity was meshed clockwise (a curve loop given clockwise in the `.geo`).
    pub reoriented: usize,
    /// Nodes with |r| below the tolerance, set to r = 0 exactly.
    pub snapped_to_axis: usize,
}

/// Node order of a cell's mirror image (clockwise <-> counter-clockwise).
fn reversed(kind: CellKind) -> &'static [usize] {
    match kind {
        CellKind::Tri3 => &[0, 2, 1],
        CellKind::Tri6 => &[0, 2, 1, 5, 4, 3],
        CellKind::Quad4 => &[0, 3, 2, 1],
        CellKind::Quad8 => &[0, 3, 2, 1, 7, 6, 5, 4],
        CellKind::Quad9 => &[0, 3, 2, 1, 7, 6, 5, 4, 8],
    }
}

/// Checks (and where unambiguous, repairs) the mesh:
/// - at least one 2D element;
/// - no node at r < 0 (|r| within 1e-9 of the model size is snapped to 0);
/// - no degenerate element (Jacobian ~ 0) and no inverted or folded element
///   (Jacobian zero or of both signs anywhere in the element, not only at
///   its corners and Gauss points: [`jacobian_range`] bounds it over the
///   whole element; or clockwise among counter-clockwise ones); a surface
///   entity meshed wholly clockwise is renumbered.
///
/// The line elements of physical curves are checked where it is known which
/// curves are used ([`CellEdges`]: joints in [`crate::insert_joints`],
/// supports and loads by the solver's scene check).
pub fn validate(mesh: &mut Mesh, path: &Path) -> Result<Validation, MeshError> {
    let invalid = |message: String| MeshError::Invalid {
        path: path.to_path_buf(),
        message,
    };
    if mesh.cells.is_empty() {
        return Err(invalid(
            "no 2D elements in any physical surface (is a Physical Surface defined?)".into(),
        ));
    }
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in &mesh.nodes {
        for d in 0..2 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
    let tol = 1e-9 * size;
    let mut report = Validation::default();
    for (p, tag) in mesh.nodes.iter_mut().zip(&mesh.node_tags) {
        if !p[0].is_finite() || !p[1].is_finite() {
            return Err(invalid(format!("node {tag} has a coordinate that is not finite")));
        }
        if p[0] < -tol {
            return Err(invalid(format!(
                "node {tag} at (r, z) = ({}, {}) has r < 0: the meridional mesh must lie in r >= 0 (gmsh x >= 0)",
                p[0], p[1]
            )));
        }
        if p[0] != 0.0 && p[0].abs() <= tol {
            p[0] = 0.0;
            report.snapped_to_axis += 1;
        }
    }

    // Sign of each cell, then orientation per surface entity.
    let mut clockwise: BTreeMap<i32, (usize, usize)> = BTreeMap::new();
    let mut signs = Vec::with_capacity(mesh.cells.len());
    for cell in &mesh.cells {
        let coords = mesh.cell_coords(cell);
        let (min, max) = jacobian_range(cell.kind, &coords);
        let h2 = cell_size2(&coords);
        let body = &mesh.bodies[cell.body].name;
        let here = || {
            format!(
                "element {} ({}, body '{body}', surface entity {}) with nodes {}",
                cell.tag,
                cell.kind.name(),
                cell.entity,
                node_list(mesh, &cell.nodes)
            )
        };
        if !(min.is_finite() && max.is_finite()) || max.abs().max(min.abs()) <= 1e-12 * h2 {
            return Err(invalid(format!("{} is degenerate (zero area)", here())));
        }
        if min * max <= 0.0 {
            return Err(invalid(format!(
                "{} is inverted or distorted: its Jacobian changes sign over the element (det J is {min:.3e} at one point and {max:.3e} at another){}",
                here(),
                if cell.kind.is_quadratic() {
                    "; is a mid-side node on the wrong edge, or too far from its edge's middle?"
                } else {
                    ""
                }
            )));
        }
        let cw = max < 0.0;
        let e = clockwise.entry(cell.entity).or_default();
        e.0 += usize::from(cw);
        e.1 += 1;
        signs.push(cw);
    }
    for (cell, &cw) in mesh.cells.iter().zip(&signs) {
        let (n_cw, n) = clockwise[&cell.entity];
        if cw && n_cw < n {
            return Err(invalid(format!(
                "element {} ({}, body '{}', surface entity {}) with nodes {} is inverted: it is clockwise while {} other elements of its surface are counter-clockwise",
                cell.tag,
                cell.kind.name(),
                mesh.bodies[cell.body].name,
                cell.entity,
                node_list(mesh, &cell.nodes),
                n - n_cw
            )));
        }
    }
    for (cell, &cw) in mesh.cells.iter_mut().zip(&signs) {
        if cw {
            let old = cell.nodes.clone();
            for (slot, &i) in cell.nodes.iter_mut().zip(reversed(cell.kind)) {
                *slot = old[i];
            }
            report.reoriented += 1;
        }
    }
    // Every physical curve's line elements lie on cell edges, whether or
    // not a scene uses the curve.
    let edges = CellEdges::new(mesh);
    for curve in &mesh.curves {
        edges.check(curve, path)?;
    }
    Ok(report)
}

fn cell_size2(coords: &[[f64; 2]]) -> f64 {
    let mut h: f64 = 0.0;
    for a in coords {
        for b in coords {
            h = h.max((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2));
        }
    }
    h
}

/// `L2` or `L3`.
fn line_name(kind: EdgeKind) -> &'static str {
    match kind {
        EdgeKind::Lin2 => "L2",
        EdgeKind::Lin3 => "L3",
    }
}

/// `7 at (1, 0)`: a node by its file tag and coordinates.
fn node(mesh: &Mesh, n: usize) -> String {
    let p = mesh.nodes[n];
    format!("{} at ({}, {})", mesh.node_tags[n], p[0], p[1])
}

/// `3 at (0, 0), 9 at (1, 0), ...`: nodes by file tag and coordinates.
fn node_list(mesh: &Mesh, nodes: &[usize]) -> String {
    nodes
        .iter()
        .map(|&n| node(mesh, n))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The edges of a mesh's 2D elements, to check that the line elements of
/// physical curves lie on them.
///
/// A support, load or joint acts on the nodes of its curve's line elements;
/// a line element that is no element edge (an end node inside a body, a
/// middle node that is not the edge's middle node, an L2 line along
/// quadratic elements) puts it on the wrong nodes. Build once, then
/// [`CellEdges::check`] each curve that is used; [`check_curve_edges`] does
/// both. Works before and after [`crate::insert_joints`] (curves follow the
/// node copies of their elements).
#[derive(Debug)]
pub struct CellEdges<'m> {
    mesh: &'m Mesh,
    /// The cells at each corner node: `cells[start[n]..start[n + 1]]`.
    start: Vec<usize>,
    cells: Vec<usize>,
    /// Nodes used by some element.
    in_cell: Vec<bool>,
}

impl<'m> CellEdges<'m> {
    /// Indexes `mesh`'s cells by their corner nodes (two passes over the
    /// cells, no hashing).
    pub fn new(mesh: &'m Mesh) -> Self {
        let n_nodes = mesh.nodes.len();
        let mut start = vec![0usize; n_nodes + 1];
        let mut in_cell = vec![false; n_nodes];
        for cell in &mesh.cells {
            for &n in &cell.nodes[..cell.kind.n_corners()] {
                start[n + 1] += 1;
            }
            for &n in &cell.nodes {
                in_cell[n] = true;
            }
        }
        for n in 0..n_nodes {
            start[n + 1] += start[n];
        }
        let mut next = start.clone();
        let mut cells = vec![0usize; start[n_nodes]];
        for (c, cell) in mesh.cells.iter().enumerate() {
            for &n in &cell.nodes[..cell.kind.n_corners()] {
                cells[next[n]] = c;
                next[n] += 1;
            }
        }
        CellEdges {
            mesh,
            start,
            cells,
            in_cell,
        }
    }

    /// The element edges with corners `a` and `b` (either order): `(cell,
    /// local edge)`.
    fn edges_between(&self, a: usize, b: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        let cells = &self.cells[self.start[a]..self.start[a + 1]];
        cells.iter().flat_map(move |&c| {
            let cell = &self.mesh.cells[c];
            (0..cell.kind.n_corners()).filter_map(move |e| {
                let l = cell.kind.edge_nodes(e);
                let (p, q) = (cell.nodes[l[0]], cell.nodes[l[1]]);
                ((p, q) == (a, b) || (p, q) == (b, a)).then_some((c, e))
            })
        })
    }

    /// Checks that every line element of `curve` is an edge of a 2D
    /// element: its end nodes are the two corners of an element edge, its
    /// middle node (L3) is that edge's middle node, and it has as many nodes
    /// as the element's edges. The error names the file, the curve, the line
    /// element (tag and nodes, by file tag and coordinates) and what is off.
    pub fn check(&self, curve: &CurveSet, path: &Path) -> Result<(), MeshError> {
        let mesh = self.mesh;
        for edge in &curve.edges {
            let (a, b) = (edge.nodes[0], edge.nodes[1]);
            // The line is element edge e of cell c, middle node and all.
            let fits = |(c, e): (usize, usize)| {
                let cell = &mesh.cells[c];
                let l = cell.kind.edge_nodes(e);
                edge.kind == cell.kind.edge_kind()
                    && (edge.kind == EdgeKind::Lin2 || cell.nodes[l[2]] == edge.nodes[2])
            };
            let mut found = self.edges_between(a, b).peekable();
            let Some(&first) = found.peek() else {
                let loose: Vec<String> = [a, b]
                    .iter()
                    .filter(|&&n| !self.in_cell[n])
                    .map(|&n| format!("node {}", node(mesh, n)))
                    .collect();
                return Err(self.off_edges(
                    curve,
                    edge,
                    path,
                    if loose.is_empty() {
                        format!(
                            "no element has an edge from node {} to node {}",
                            mesh.node_tags[a], mesh.node_tags[b]
                        )
                    } else {
                        format!("{} belongs to no 2D element", loose.join(" and "))
                    },
                ));
            };
            if found.any(fits) {
                continue;
            }
            let (c, e) = first;
            let cell = &mesh.cells[c];
            let want = cell.kind.edge_kind();
            let why = if edge.kind != want {
                format!(
                    "its end nodes are the corners of an edge of element {} ({}), whose edges are {} lines",
                    cell.tag,
                    cell.kind.name(),
                    line_name(want)
                )
            } else {
                format!(
                    "its end nodes are the corners of an edge of element {} ({}), whose middle node is {}, not {}",
                    cell.tag,
                    cell.kind.name(),
                    node(mesh, cell.nodes[cell.kind.edge_nodes(e)[2]]),
                    mesh.node_tags[edge.nodes[2]]
                )
            };
            return Err(self.off_edges(curve, edge, path, why));
        }
        Ok(())
    }

    fn off_edges(&self, curve: &CurveSet, edge: &crate::Edge, path: &Path, why: String) -> MeshError {
        let kind = line_name(edge.kind);
        MeshError::Invalid {
            path: path.to_path_buf(),
            message: format!(
                "physical curve '{}': line element {} ({kind}, curve entity {}) with nodes {} is not an edge of any 2D element: {why} (a support, load or joint on these nodes would act on the wrong nodes)",
                curve.name,
                edge.tag,
                edge.entity,
                node_list(self.mesh, &edge.nodes)
            ),
        }
    }
}

/// Checks the line elements of the physical curves `curves` with
/// [`CellEdges::check`]; a name that is no physical curve is an error.
pub fn check_curve_edges(mesh: &Mesh, curves: &[&str], path: &Path) -> Result<(), MeshError> {
    let edges = CellEdges::new(mesh);
    for &name in curves {
        let curve = mesh.curve(name).ok_or_else(|| MeshError::UnknownName {
            path: path.to_path_buf(),
            what: "curve",
            name: name.to_string(),
            known: mesh
                .curves
                .iter()
                .map(|c| c.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        })?;
        edges.check(curve, path)?;
    }
    Ok(())
}
