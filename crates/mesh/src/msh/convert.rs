//! [`MshFile`] -> [`Mesh`]: bodies, cells, curve and point sets, nodes
//! renumbered from 0 in file order.

use super::types::{role, type_info, Role};
use super::{dim_word, MshFile, MshFormat, RawElement};
use crate::{Body, Cell, CurveSet, Edge, EdgeKind, Mesh, MeshError, PointSet};
use std::collections::{BTreeMap, HashMap, HashSet};
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

/// Node tag -> index into [`MshFile::nodes`]: a table when the tags are
/// dense (gmsh numbers nodes 1..n), a hash map otherwise.
enum TagIndex {
    Dense(Vec<usize>),
    Sparse(HashMap<u64, usize>),
}

impl TagIndex {
    /// The index of `nodes`, or the first tag defined twice.
    fn new(nodes: &[(u64, [f64; 3])]) -> Result<Self, u64> {
        let max = nodes.iter().map(|n| n.0).max().unwrap_or(0);
        let dense_len = usize::try_from(max)
            .ok()
            .filter(|&m| m <= 2 * nodes.len() + 1024)
            .map(|m| m + 1);
        if let Some(len) = dense_len {
            let mut table = vec![usize::MAX; len];
            for (i, &(tag, _)) in nodes.iter().enumerate() {
                match usize::try_from(tag).ok().and_then(|t| table.get_mut(t)) {
                    Some(slot) if *slot == usize::MAX => *slot = i,
                    _ => return Err(tag),
                }
            }
            return Ok(TagIndex::Dense(table));
        }
        let mut map = HashMap::with_capacity(nodes.len());
        for (i, &(tag, _)) in nodes.iter().enumerate() {
            if map.insert(tag, i).is_some() {
                return Err(tag);
            }
        }
        Ok(TagIndex::Sparse(map))
    }

    fn get(&self, tag: u64) -> Option<usize> {
        match self {
            TagIndex::Dense(table) => usize::try_from(tag)
                .ok()
                .and_then(|t| table.get(t))
                .copied()
                .filter(|&i| i != usize::MAX),
            TagIndex::Sparse(map) => map.get(&tag).copied(),
        }
    }
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
        let mut builder = Builder::new(self, path)?;
        for (el_index, el) in self.elements.iter().enumerate() {
            builder.add_element(el_index, el)?;
        }
        builder.finish()
    }
}

/// A [`MeshError::Parse`] at `line` of the file at `path`.
fn parse_error(path: &Path, line: usize, message: String) -> MeshError {
    MeshError::Parse {
        path: path.to_path_buf(),
        line,
        message,
    }
}

/// A [`MeshError::Invalid`] about the file at `path`.
fn invalid(path: &Path, message: String) -> MeshError {
    MeshError::Invalid {
        path: path.to_path_buf(),
        message,
    }
}

/// The mesh of one [`MshFile`] while its elements are read.
struct Builder<'f> {
    msh: &'f MshFile,
    path: &'f Path,
    /// Nodes still index into `msh.nodes` until [`Builder::finish`].
    mesh: Mesh,
    /// Physical tag -> index of the body, curve set, point set.
    body_of: HashMap<i32, usize>,
    curve_of: HashMap<i32, usize>,
    point_of: HashMap<i32, usize>,
    file_index: TagIndex,
    /// `user[i]`: the first kept element using node i (for messages).
    user: Vec<Option<&'f RawElement>>,
    /// The last element added to each curve set.
    curve_last: Vec<Option<usize>>,
    /// (set, node) of point sets.
    point_members: HashSet<(usize, usize)>,
}

impl<'f> Builder<'f> {
    /// The physical groups as empty bodies and sets, and the node tag index.
    fn new(msh: &'f MshFile, path: &'f Path) -> Result<Self, MeshError> {
        let [point_groups, curve_groups, surface_groups] = physical_groups(msh, path)?;
        let index_of =
            |g: &Groups| -> HashMap<i32, usize> { g.keys().enumerate().map(|(i, &t)| (t, i)).collect() };
        let mesh = Mesh {
            bodies: surface_groups
                .iter()
                .map(|(&tag, name)| Body {
                    name: name.clone(),
                    tag,
                })
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
        let file_index = TagIndex::new(&msh.nodes)
            .map_err(|tag| invalid(path, format!("node tag {tag} is defined twice")))?;
        Ok(Builder {
            msh,
            path,
            body_of: index_of(&surface_groups),
            curve_of: index_of(&curve_groups),
            point_of: index_of(&point_groups),
            file_index,
            user: vec![None; msh.nodes.len()],
            curve_last: vec![None; mesh.curves.len()],
            point_members: HashSet::new(),
            mesh,
        })
    }

    /// Adds element `el_index` as a cell, a curve edge or point set nodes.
    fn add_element(&mut self, el_index: usize, el: &'f RawElement) -> Result<(), MeshError> {
        let Some(role) = role(el.gmsh_type) else {
            let what = type_info(el.gmsh_type).map_or("unknown", |i| i.name);
            return Err(parse_error(
                self.path,
                el.line,
                format!(
                    "{} has unsupported gmsh element type {} ({what}); axijoint reads \
                     triangles (2, 9), quadrangles (3, 16, 10), lines (1, 8) and points (15)",
                    describe(el),
                    el.gmsh_type
                ),
            ));
        };
        let nodes = self.element_nodes(el, role)?;
        let keep = match role {
            Role::Cell(kind) => {
                let body = self.cell_body(el)?;
                self.mesh.cells.push(Cell {
                    kind,
                    nodes: nodes.clone(),
                    body,
                    tag: el.tag,
                    entity: el.entity_tag,
                });
                true
            }
            Role::Edge(kind) => self.add_edge(el_index, el, kind, &nodes),
            Role::Point => self.add_point(el, &nodes),
        };
        if keep {
            for &i in &nodes {
                if let Some(u) = self.user.get_mut(i) {
                    u.get_or_insert(el);
                }
            }
        }
        Ok(())
    }

    /// The element's nodes as indices into `msh.nodes`, checking their count.
    fn element_nodes(&self, el: &RawElement, role: Role) -> Result<Vec<usize>, MeshError> {
        let expected = match role {
            Role::Cell(k) => k.n_nodes(),
            Role::Edge(k) => k.n_nodes(),
            Role::Point => 1,
        };
        if el.nodes.len() != expected {
            return Err(parse_error(
                self.path,
                el.line,
                format!(
                    "{} has {} nodes, its type needs {expected}",
                    describe(el),
                    el.nodes.len()
                ),
            ));
        }
        let mut nodes = Vec::with_capacity(expected);
        for &n in &el.nodes {
            let Some(i) = self.file_index.get(n) else {
                return Err(parse_error(
                    self.path,
                    el.line,
                    format!(
                        "{} references node {n}, which $Nodes does not define",
                        describe(el)
                    ),
                ));
            };
            nodes.push(i);
        }
        Ok(nodes)
    }

    /// The one body of a cell, from its physical tags.
    fn cell_body(&self, el: &RawElement) -> Result<usize, MeshError> {
        // Up to two distinct bodies: one is right, two is enough to refuse.
        let mut bodies: Vec<usize> = Vec::with_capacity(2);
        for t in &el.physical_tags {
            if let Some(&b) = self.body_of.get(t) {
                if !bodies.contains(&b) {
                    bodies.push(b);
                    if bodies.len() == 2 {
                        break;
                    }
                }
            }
        }
        match bodies.as_slice() {
            [b] => Ok(*b),
            [] => {
                let hint = if self.msh.entities.is_empty() && self.msh.format != MshFormat::V22Ascii {
                    "the file has no $Entities section, so no physical groups"
                } else {
                    "every cell must belong to one body: add its surface to a Physical Surface"
                };
                Err(invalid(
                    self.path,
                    format!("{} is in no physical surface ({hint})", describe(el)),
                ))
            }
            several => {
                let names: Vec<String> = several
                    .iter()
                    .filter_map(|&b| self.mesh.bodies.get(b))
                    .map(|b| format!("'{}' ({})", b.name, b.tag))
                    .collect();
                Err(invalid(
                    self.path,
                    format!(
                        "{} is in more than one physical surface, {}: a cell belongs to \
                         exactly one body",
                        describe(el),
                        names.join(" and ")
                    ),
                ))
            }
        }
    }

    /// Adds a line element to each curve set of its physical tags; true if any.
    fn add_edge(&mut self, el_index: usize, el: &RawElement, kind: EdgeKind, nodes: &[usize]) -> bool {
        let mut keep = false;
        for t in &el.physical_tags {
            let Some(&c) = self.curve_of.get(t) else { continue };
            // A tag listed twice adds the edge once.
            if self.curve_last.get(c) == Some(&Some(el_index)) {
                continue;
            }
            if let (Some(set), Some(last)) = (self.mesh.curves.get_mut(c), self.curve_last.get_mut(c)) {
                *last = Some(el_index);
                set.edges.push(Edge {
                    kind,
                    nodes: nodes.to_vec(),
                    tag: el.tag,
                    entity: el.entity_tag,
                });
                keep = true;
            }
        }
        keep
    }

    /// Adds a point element's node to each point set of its physical tags; true if any.
    fn add_point(&mut self, el: &RawElement, nodes: &[usize]) -> bool {
        let mut keep = false;
        for t in &el.physical_tags {
            let Some(&p) = self.point_of.get(t) else { continue };
            if let Some(set) = self.mesh.points.get_mut(p) {
                for &n in nodes {
                    if self.point_members.insert((p, n)) {
                        set.nodes.push(n);
                    }
                }
                keep = true;
            }
        }
        keep
    }

    /// Renumbers the used nodes from 0, in file order, after checking z = 0.
    fn finish(self) -> Result<Mesh, MeshError> {
        let Builder {
            msh,
            path,
            mut mesh,
            user,
            ..
        } = self;
        let mut new_index = vec![usize::MAX; msh.nodes.len()];
        let mut extent: f64 = 0.0;
        for (i, &(tag, [x, y, _])) in msh.nodes.iter().enumerate() {
            if user.get(i).is_some_and(Option::is_some) {
                if let Some(slot) = new_index.get_mut(i) {
                    *slot = mesh.nodes.len();
                }
                mesh.nodes.push([x, y]);
                mesh.node_tags.push(tag);
                extent = extent.max(x.abs()).max(y.abs());
            }
        }
        for (&(tag, [x, y, z]), el) in msh.nodes.iter().zip(&user) {
            if let (Some(el), true) = (el, z.abs() > Z_TOLERANCE * extent) {
                return Err(invalid(
                    path,
                    format!(
                        "node {tag} at ({x:?}, {y:?}, {z:?}), used by {}, is off the z = 0 plane: the \
                         mesh must lie in the meridional plane (gmsh x = r, y = z, z = 0)",
                        describe(el)
                    ),
                ));
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
