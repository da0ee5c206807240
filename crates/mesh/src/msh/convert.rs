//! [`MshFile`] -> [`Mesh`]: bodies, cells, curve and point sets, nodes
//! renumbered from 0 in file order.

use super::types::{role, type_info, Role};
use super::{dim_word, MshFile, RawElement};
use crate::{Body, Cell, CurveSet, Edge, Mesh, MeshError, PointSet};
use std::collections::{BTreeMap, HashMap};
use std::path::Path;

/// A node may leave the z = 0 plane by this fraction of the model's extent.
const Z_TOLERANCE: f64 = 1e-10;

/// The physical groups of one dimension: tag -> name, in tag order.
type Groups = BTreeMap<i32, String>;

/// Physical groups of dimension 0, 1 and 2: named ones and those used by
/// entities or elements (named `point_<tag>`, `curve_<tag>`, `surface_<tag>`).
fn physical_groups(msh: &MshFile, path: &Path) -> Result<[Groups; 3], MeshError> {
    let invalid = |message: String| MeshError::Invalid {
        path: path.to_path_buf(),
        message,
    };
    let mut groups: [Groups; 3] = Default::default();
    for p in &msh.physical_names {
        let Some(g) = usize::try_from(p.dim).ok().and_then(|d| groups.get_mut(d)) else {
            continue; // physical volumes: nothing of ours
        };
        if let Some(old) = g.insert(p.tag, p.name.clone()) {
            if old != p.name {
                return Err(invalid(format!(
                    "physical {} {} is named both '{old}' and '{}'",
                    dim_word(p.dim),
                    p.tag,
                    p.name
                )));
            }
        }
    }
    let used_by_entities = msh.entities.iter().map(|e| (e.dim, &e.physical_tags));
    let used_by_elements = msh
        .elements
        .iter()
        .filter_map(|e| type_info(e.gmsh_type).map(|info| (info.dim, &e.physical_tags)));
    for (dim, tags) in used_by_entities.chain(used_by_elements) {
        let Some(g) = usize::try_from(dim).ok().and_then(|d| groups.get_mut(d)) else {
            continue;
        };
        for &t in tags {
            g.entry(t).or_insert_with(|| format!("{}_{t}", dim_word(dim)));
        }
    }
    for (dim, g) in (0i32..).zip(groups.iter()) {
        let mut by_name: HashMap<&str, i32> = HashMap::new();
        for (&tag, name) in g {
            if let Some(other) = by_name.insert(name, tag) {
                return Err(invalid(format!(
                    "physical {}s {other} and {tag} are both named '{name}'",
                    dim_word(dim)
                )));
            }
        }
    }
    Ok(groups)
}

/// "element 17 (surface entity 3, line 120)".
fn describe(el: &RawElement) -> String {
    format!(
        "element {} ({} entity {}, line {})",
        el.tag,
        dim_word(el.entity_dim),
        el.entity_tag,
        el.line
    )
}

impl MshFile {
    /// The axijoint mesh of this file; `path` only names the file in errors.
    ///
    /// - Nodes: those used by a kept element, numbered from 0 in file order,
    ///   `[r, z] = [x, y]`; every one must have z = 0 (to 1e-10 of the
    ///   model's extent).
    /// - Bodies: one per physical surface, in tag order; cells (types 2, 9,
    ///   3, 16, 10) must each be in exactly one.
    /// - Curves: one [`CurveSet`] per physical curve, with the line elements
    ///   (types 1, 8) of its entities; an element may be in several.
    /// - Points: one [`PointSet`] per physical point (type 15 elements).
    /// - Unnamed groups are called `surface_<tag>`, `curve_<tag>`,
    ///   `point_<tag>`. Lines and points in no physical group are dropped.
    ///
    /// Errors: an element type other than the above, a node that `$Nodes`
    /// does not define, a cell in zero or two bodies, a node off the z = 0
    /// plane, two groups of one dimension with one name.
    pub fn to_mesh(&self, path: &Path) -> Result<Mesh, MeshError> {
        let parse_error = |line: usize, message: String| MeshError::Parse {
            path: path.to_path_buf(),
            line,
            message,
        };
        let invalid = |message: String| MeshError::Invalid {
            path: path.to_path_buf(),
            message,
        };
        let [point_groups, curve_groups, surface_groups] = physical_groups(self, path)?;
        let index_of = |g: &Groups| -> HashMap<i32, usize> { g.keys().enumerate().map(|(i, &t)| (t, i)).collect() };
        let (body_of, curve_of, point_of) = (
            index_of(&surface_groups),
            index_of(&curve_groups),
            index_of(&point_groups),
        );
        let mut mesh = Mesh {
            bodies: surface_groups
                .iter()
                .map(|(&tag, name)| Body { name: name.clone(), tag })
                .collect(),
            curves: curve_groups
                .iter()
                .map(|(&tag, name)| CurveSet {
                    name: name.clone(),
                    tag,
                    edges: Vec::new(),
                })
                .collect(),
            points: point_groups
                .iter()
                .map(|(&tag, name)| PointSet {
                    name: name.clone(),
                    tag,
                    nodes: Vec::new(),
                })
                .collect(),
            ..Mesh::default()
        };

        let mut file_index: HashMap<u64, usize> = HashMap::with_capacity(self.nodes.len());
        for (i, &(tag, _)) in self.nodes.iter().enumerate() {
            if file_index.insert(tag, i).is_some() {
                return Err(invalid(format!("node tag {tag} is defined twice")));
            }
        }
        // Node indices below are into `self.nodes` until the renumbering.
        let mut used = vec![false; self.nodes.len()];
        for el in &self.elements {
            let Some(role) = role(el.gmsh_type) else {
                let what = type_info(el.gmsh_type).map_or("unknown", |i| i.name);
                return Err(parse_error(
                    el.line,
                    format!(
                        "{} has unsupported gmsh element type {} ({what}); axijoint reads \
                         triangles (2, 9), quadrangles (3, 16, 10), lines (1, 8) and points (15)",
                        describe(el),
                        el.gmsh_type
                    ),
                ));
            };
            let expected = match role {
                Role::Cell(k) => k.n_nodes(),
                Role::Edge(k) => k.n_nodes(),
                Role::Point => 1,
            };
            if el.nodes.len() != expected {
                return Err(parse_error(
                    el.line,
                    format!("{} has {} nodes, its type needs {expected}", describe(el), el.nodes.len()),
                ));
            }
            let mut nodes = Vec::with_capacity(expected);
            for &n in &el.nodes {
                let Some(&i) = file_index.get(&n) else {
                    return Err(parse_error(
                        el.line,
                        format!("{} references node {n}, which $Nodes does not define", describe(el)),
                    ));
                };
                nodes.push(i);
            }
            let mut keep = false;
            match role {
                Role::Cell(kind) => {
                    let mut bodies: Vec<usize> = Vec::new();
                    for t in &el.physical_tags {
                        if let Some(&b) = body_of.get(t) {
                            if !bodies.contains(&b) {
                                bodies.push(b);
                            }
                        }
                    }
                    let body = match bodies.as_slice() {
                        [b] => *b,
                        [] => {
                            return Err(invalid(format!(
                                "{} is in no physical surface (every cell must belong to one body: \
                                 add its surface to a Physical Surface)",
                                describe(el)
                            )))
                        }
                        several => {
                            let names: Vec<String> = several
                                .iter()
                                .filter_map(|&b| mesh.bodies.get(b))
                                .map(|b| format!("'{}' ({})", b.name, b.tag))
                                .collect();
                            return Err(invalid(format!(
                                "{} is in {} physical surfaces, {}: a cell belongs to exactly one body",
                                describe(el),
                                several.len(),
                                names.join(" and ")
                            )));
                        }
                    };
                    mesh.cells.push(Cell {
                        kind,
                        nodes,
                        body,
                        tag: el.tag,
                        entity: el.entity_tag,
                    });
                    keep = true;
                }
                Role::Edge(kind) => {
                    for t in &el.physical_tags {
                        if let Some(set) = curve_of.get(t).and_then(|&c| mesh.curves.get_mut(c)) {
                            set.edges.push(Edge {
                                kind,
                                nodes: nodes.clone(),
                                tag: el.tag,
                                entity: el.entity_tag,
                            });
                            keep = true;
                        }
                    }
                }
                Role::Point => {
                    for t in &el.physical_tags {
                        if let Some(set) = point_of.get(t).and_then(|&p| mesh.points.get_mut(p)) {
                            for &n in &nodes {
                                if !set.nodes.contains(&n) {
                                    set.nodes.push(n);
                                }
                            }
                            keep = true;
                        }
                    }
                }
            }
            if keep {
                for &n in &el.nodes {
                    if let Some(u) = file_index.get(&n).and_then(|&i| used.get_mut(i)) {
                        *u = true;
                    }
                }
            }
        }

        // Renumber the used nodes from 0, in file order.
        let mut new_index = vec![usize::MAX; self.nodes.len()];
        let mut extent: f64 = 0.0;
        for (i, &(tag, [x, y, _])) in self.nodes.iter().enumerate() {
            if used.get(i) == Some(&true) {
                if let Some(slot) = new_index.get_mut(i) {
                    *slot = mesh.nodes.len();
                }
                mesh.nodes.push([x, y]);
                mesh.node_tags.push(tag);
                extent = extent.max(x.abs()).max(y.abs());
            }
        }
        for (i, &(tag, [x, y, z])) in self.nodes.iter().enumerate() {
            if used.get(i) == Some(&true) && z.abs() > Z_TOLERANCE * extent {
                return Err(invalid(format!(
                    "node {tag} at ({x}, {y}, {z}) is off the z = 0 plane: the mesh must lie in \
                     the meridional plane (gmsh x = r, y = z, z = 0)"
                )));
            }
        }
        let renumber = |nodes: &mut Vec<usize>| {
            for n in nodes.iter_mut() {
                *n = new_index.get(*n).copied().unwrap_or(usize::MAX);
            }
        };
        for cell in &mut mesh.cells {
            renumber(&mut cell.nodes);
        }
        for set in &mut mesh.curves {
            for edge in &mut set.edges {
                renumber(&mut edge.nodes);
            }
        }
        for set in &mut mesh.points {
            renumber(&mut set.nodes);
        }
        Ok(mesh)
    }
}
