//! Joint insertion: duplicate the nodes of an interface curve and create
//! zero-thickness joint elements between the faces on its two sides.
//!
//! Which nodes split: for each node on a joint curve, the cells around it are
//! grouped into components connected through shared edges that are *not*
//! joint edges. One component (the joint ends inside a body, or meets a
//! bonded line as at Scene P's pile head corner) keeps the node shared, like
//! a crack tip. Each further component (the joint reaches a free boundary,
//! another joint, or the axis from both sides) gets its own copy.

use crate::{CellEdges, Edge, Joint, JointElement, JointKind, Mesh, MeshError};
use std::collections::{BTreeSet, HashMap};
use std::path::Path;
use std::str::FromStr;

/// Which physical curve becomes a joint, and (optionally) which body is on
/// its bottom face and which on its top face.
///
/// Written `curve` or `curve:bottom/top` (e.g. `pile_side:pile/footing`).
/// Without bodies, the bottom is the body of lower physical tag; a joint
/// inside one body takes the right-hand side of the curve's direction as
/// bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct JointSpec {
    /// Physical curve name.
    pub curve: String,
    /// Physical surface on the bottom face.
    pub bottom: Option<String>,
    /// Physical surface on the top face.
    pub top: Option<String>,
}

impl JointSpec {
    /// A joint along `curve` with the default sides.
    pub fn new(curve: &str) -> Self {
        JointSpec {
            curve: curve.to_string(),
            bottom: None,
            top: None,
        }
    }
}

impl FromStr for JointSpec {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let s = s.trim();
        let bad = || format!("joint '{s}': expected CURVE or CURVE:BOTTOM/TOP");
        match s.split_once(':') {
            None if !s.is_empty() => Ok(JointSpec::new(s)),
            None => Err(bad()),
            Some((curve, sides)) => {
                let (b, t) = sides.split_once('/').ok_or_else(bad)?;
                if curve.is_empty() || b.is_empty() || t.is_empty() {
                    return Err(bad());
                }
                Ok(JointSpec {
                    curve: curve.to_string(),
                    bottom: Some(b.to_string()),
                    top: Some(t.to_string()),
                })
            }
        }
    }
}

/// Key of an edge: its two corner nodes, sorted.
fn key(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

/// Tiny union-find over cell indices.
struct Components {
    parent: HashMap<usize, usize>,
}

impl Components {
    fn find(&mut self, c: usize) -> usize {
        let p = *self.parent.entry(c).or_insert(c);
        if p == c {
            return c;
        }
        let root = self.find(p);
        self.parent.insert(c, root);
        root
    }
    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent.insert(ra.max(rb), ra.min(rb));
        }
    }
}

/// One joint edge with its two sides, before renumbering.
struct Pending {
    spec: usize,
    edge_nodes: Vec<usize>,
    tag: u64,
    bottom_cell: usize,
    top_cell: usize,
}

/// Edge adjacency of the 2D cells: edge key -> `(cell, local edge)` list.
type Adjacency = HashMap<(usize, usize), Vec<(usize, usize)>>;

/// The outcome of splitting the joint nodes.
struct Split {
    /// `copy_of[(node, cell)]` = the node index that cell uses after splitting.
    copy_of: HashMap<(usize, usize), usize>,
    /// `(original, copy)` of each new node, in creation order.
    duplicated: Vec<(usize, usize)>,
}

/// A [`MeshError::Invalid`] about the file at `path`.
fn invalid(path: &Path, message: String) -> MeshError {
    MeshError::Invalid {
        path: path.to_path_buf(),
        message,
    }
}

/// A [`MeshError::UnknownName`] listing the names that do exist.
fn unknown_name<'a>(
    path: &Path,
    what: &'static str,
    name: &str,
    known: impl Iterator<Item = &'a str>,
) -> MeshError {
    MeshError::UnknownName {
        path: path.to_path_buf(),
        what,
        name: name.to_string(),
        known: known.collect::<Vec<_>>().join(", "),
    }
}

/// Turns each named curve into a joint (see the module doc). Cells must be
/// valid and counter-clockwise ([`crate::validate()`] first); every line
/// element of a joint curve must be a cell edge ([`CellEdges::check`]), and
/// an interior one (a face on each side).
pub fn insert_joints(mesh: &mut Mesh, specs: &[JointSpec], path: &Path) -> Result<(), MeshError> {
    if specs.is_empty() {
        return Ok(());
    }
    let adjacency = edge_adjacency(mesh);
    let pending = pending_edges(mesh, specs, &adjacency, path)?;
    let split = split_nodes(mesh, &pending);
    follow_copies(mesh, specs, &adjacency, &split);
    let joints = joint_elements(mesh, specs, &pending, &split);
    // The joint curves keep their line elements on the bottom face.
    for (spec, joint) in specs.iter().zip(&joints) {
        if let Some(curve) = mesh.curves.iter_mut().find(|c| c.name == spec.curve) {
            for (edge, el) in curve.edges.iter_mut().zip(&joint.elements) {
                edge.nodes.clone_from(&el.bottom);
            }
        }
    }
    mesh.joints.extend(joints);
    Ok(())
}

/// Edge adjacency of the 2D cells, keyed by corner nodes.
fn edge_adjacency(mesh: &Mesh) -> Adjacency {
    let mut adjacency: Adjacency = HashMap::new();
    for (c, cell) in mesh.cells.iter().enumerate() {
        for e in 0..cell.kind.n_corners() {
            let l = cell.kind.edge_nodes(e);
            adjacency
                .entry(key(cell.nodes[l[0]], cell.nodes[l[1]]))
                .or_default()
                .push((c, e));
        }
    }
    adjacency
}

/// Checks each joint curve and its bodies, and lists its line elements with their sides.
fn pending_edges(
    mesh: &Mesh,
    specs: &[JointSpec],
    adjacency: &Adjacency,
    path: &Path,
) -> Result<Vec<Pending>, MeshError> {
    // Every line element of a joint curve must be an element edge.
    let cell_edges = CellEdges::new(mesh);
    let mut pending = Vec::new();
    let mut seen = BTreeSet::new();
    for (s, spec) in specs.iter().enumerate() {
        if !seen.insert(spec.curve.as_str()) {
            return Err(invalid(path, format!("joint '{}' is named twice", spec.curve)));
        }
        let curve = mesh.curve(&spec.curve).ok_or_else(|| {
            unknown_name(
                path,
                "curve",
                &spec.curve,
                mesh.curves.iter().map(|c| c.name.as_str()),
            )
        })?;
        if curve.edges.is_empty() {
            return Err(invalid(
                path,
                format!("joint '{}': the curve has no line elements", spec.curve),
            ));
        }
        cell_edges.check(curve, path)?;
        let body_of = |name: &Option<String>| -> Result<Option<usize>, MeshError> {
            match name {
                None => Ok(None),
                Some(n) => mesh.body(n).map(Some).ok_or_else(|| {
                    unknown_name(path, "surface", n, mesh.bodies.iter().map(|b| b.name.as_str()))
                }),
            }
        };
        let explicit = body_of(&spec.bottom)?.zip(body_of(&spec.top)?);
        for edge in &curve.edges {
            let (bottom_cell, top_cell) = edge_sides(mesh, spec, edge, explicit, adjacency, path)?;
            pending.push(Pending {
                spec: s,
                edge_nodes: edge.nodes.clone(),
                tag: edge.tag,
                bottom_cell,
                top_cell,
            });
        }
    }
    Ok(pending)
}

/// Checks one joint line element (two faces, edge kind, named bodies); gives its (bottom, top) cells.
fn edge_sides(
    mesh: &Mesh,
    spec: &JointSpec,
    edge: &Edge,
    explicit: Option<(usize, usize)>,
    adjacency: &Adjacency,
    path: &Path,
) -> Result<(usize, usize), MeshError> {
    let [a, b] = [edge.nodes[0], edge.nodes[1]];
    let at = |n: usize| mesh.nodes[n];
    let cells = adjacency.get(&key(a, b)).map(Vec::as_slice).unwrap_or(&[]);
    let here = format!(
        "joint '{}': line element {} (curve entity {}) from ({}, {}) to ({}, {})",
        spec.curve,
        edge.tag,
        edge.entity,
        at(a)[0],
        at(a)[1],
        at(b)[0],
        at(b)[1]
    );
    let (c0, c1) = match cells {
        [] => return Err(invalid(path, format!("{here} is not an edge of any 2D element"))),
        [_] => {
            return Err(invalid(
                path,
                format!(
                    "{here} has a face on one side only: a joint must lie between two faces (this edge is on the boundary)"
                ),
            ))
        }
        [x, y] => (x.0, y.0),
        _ => return Err(invalid(path, format!("{here} is shared by more than two elements"))),
    };
    let want_kind = mesh.cells[c0].kind.edge_kind();
    if edge.kind != want_kind || mesh.cells[c1].kind.edge_kind() != want_kind {
        return Err(invalid(
            path,
            format!(
                "{here} is a {:?} edge but its elements have {:?} edges",
                edge.kind, want_kind
            ),
        ));
    }
    let (b0, b1) = (mesh.cells[c0].body, mesh.cells[c1].body);
    // Bottom: the named body, else the body of lower physical tag;
    // inside one body, the cell on the right of the curve a -> b.
    let right_of_curve = |c: usize| {
        let (pa, pb) = (at(a), at(b));
        let cen = centroid(mesh, c);
        (pb[0] - pa[0]) * (cen[1] - pa[1]) - (pb[1] - pa[1]) * (cen[0] - pa[0]) < 0.0
    };
    Ok(match explicit {
        Some((pb, pt)) if (b0, b1) == (pb, pt) && pb != pt => (c0, c1),
        Some((pb, pt)) if (b1, b0) == (pb, pt) && pb != pt => (c1, c0),
        Some((pb, pt)) if !(pb == pt && b0 == pb && b1 == pb) => {
            return Err(invalid(
                path,
                format!(
                    "{here} lies between bodies '{}' and '{}', not between '{}' (bottom) and '{}' (top): a curve between one body and several (a pile through soil layers) takes one physical curve and one joint for each pair of bodies",
                    mesh.bodies[b0].name, mesh.bodies[b1].name, mesh.bodies[pb].name, mesh.bodies[pt].name
                ),
            ))
        }
        _ if b0 == b1 => {
            if right_of_curve(c0) {
                (c0, c1)
            } else {
                (c1, c0)
            }
        }
        _ if b0 < b1 => (c0, c1),
        _ => (c1, c0),
    })
}

/// Gives each further component of the cells around a joint node its own copy of the node.
fn split_nodes(mesh: &mut Mesh, pending: &[Pending]) -> Split {
    let joint_keys: BTreeSet<(usize, usize)> = pending
        .iter()
        .map(|p| key(p.edge_nodes[0], p.edge_nodes[1]))
        .collect();
    let joint_nodes: BTreeSet<usize> = pending
        .iter()
        .flat_map(|p| p.edge_nodes.iter().copied())
        .collect();
    let mut cells_of: HashMap<usize, Vec<usize>> = HashMap::new();
    for (c, cell) in mesh.cells.iter().enumerate() {
        for &n in &cell.nodes {
            if joint_nodes.contains(&n) {
                cells_of.entry(n).or_default().push(c);
            }
        }
    }
    let bottoms: BTreeSet<usize> = pending.iter().map(|p| p.bottom_cell).collect();
    let mut split = Split {
        copy_of: HashMap::new(),
        duplicated: Vec::new(),
    };
    let mut next_tag = mesh.node_tags.iter().copied().max().unwrap_or(0) + 1;
    for &n in &joint_nodes {
        let groups = components_around(mesh, n, &cells_of[&n], &joint_keys);
        if groups.len() < 2 {
            continue;
        }
        // The original stays with a component holding a bottom face.
        let keep = groups
            .iter()
            .position(|g| g.iter().any(|c| bottoms.contains(c)))
            .unwrap_or(0);
        for (g, members) in groups.iter().enumerate() {
            let id = if g == keep {
                n
            } else {
                let id = mesh.nodes.len();
                mesh.nodes.push(mesh.nodes[n]);
                mesh.node_tags.push(next_tag);
                next_tag += 1;
                split.duplicated.push((n, id));
                id
            };
            for &c in members {
                split.copy_of.insert((n, c), id);
            }
        }
    }
    split
}

/// The cells `around` node `n`, grouped through shared edges at `n` that are not joint edges.
fn components_around(
    mesh: &Mesh,
    n: usize,
    around: &[usize],
    joint_keys: &BTreeSet<(usize, usize)>,
) -> Vec<Vec<usize>> {
    let mut comps = Components {
        parent: around.iter().map(|&c| (c, c)).collect(),
    };
    let mut by_edge: HashMap<(usize, usize), usize> = HashMap::new();
    for &c in around {
        let cell = &mesh.cells[c];
        for e in 0..cell.kind.n_corners() {
            let l = cell.kind.edge_nodes(e);
            if !l.iter().any(|&i| cell.nodes[i] == n) {
                continue;
            }
            let k = key(cell.nodes[l[0]], cell.nodes[l[1]]);
            if joint_keys.contains(&k) {
                continue;
            }
            if let Some(&other) = by_edge.get(&k) {
                comps.union(c, other);
            } else {
                by_edge.insert(k, c);
            }
        }
    }
    let mut groups: Vec<(usize, Vec<usize>)> = Vec::new();
    for &c in around {
        let r = comps.find(c);
        match groups.iter_mut().find(|g| g.0 == r) {
            Some(g) => g.1.push(c),
            None => groups.push((r, vec![c])),
        }
    }
    groups.into_iter().map(|g| g.1).collect()
}

/// Puts the cells and the other curves on the node copies; point sets gain the copies.
fn follow_copies(mesh: &mut Mesh, specs: &[JointSpec], adjacency: &Adjacency, split: &Split) {
    // Boundary curves and points follow the copy of an adjacent cell.
    for curve in &mut mesh.curves {
        if specs.iter().any(|s| s.curve == curve.name) {
            continue;
        }
        for edge in &mut curve.edges {
            let k = key(edge.nodes[0], edge.nodes[1]);
            if let Some(&(c, _)) = adjacency.get(&k).and_then(|v| v.first()) {
                for n in &mut edge.nodes {
                    if let Some(&id) = split.copy_of.get(&(*n, c)) {
                        *n = id;
                    }
                }
            }
        }
    }
    for set in &mut mesh.points {
        let extra: Vec<usize> = split
            .duplicated
            .iter()
            .filter(|(o, _)| set.nodes.contains(o))
            .map(|&(_, c)| c)
            .collect();
        set.nodes.extend(extra);
    }
    for (&(n, c), &id) in &split.copy_of {
        if id != n {
            for slot in &mut mesh.cells[c].nodes {
                if *slot == n {
                    *slot = id;
                }
            }
        }
    }
}

/// The joints: elements (eta = (-xi_z, xi_r) into the top), bodies on each side, copied nodes.
fn joint_elements(mesh: &Mesh, specs: &[JointSpec], pending: &[Pending], split: &Split) -> Vec<Joint> {
    let mut joints: Vec<Joint> = specs
        .iter()
        .map(|spec| Joint {
            name: spec.curve.clone(),
            bottom_bodies: Vec::new(),
            top_bodies: Vec::new(),
            elements: Vec::new(),
            duplicated: Vec::new(),
        })
        .collect();
    for p in pending {
        let side = |cell: usize| -> Vec<usize> {
            p.edge_nodes
                .iter()
                .map(|&n| split.copy_of.get(&(n, cell)).copied().unwrap_or(n))
                .collect()
        };
        let (mut bottom, mut top) = (side(p.bottom_cell), side(p.top_cell));
        let (pa, pb) = (mesh.nodes[bottom[0]], mesh.nodes[bottom[1]]);
        let cen = centroid(mesh, p.top_cell);
        let eta = [-(pb[1] - pa[1]), pb[0] - pa[0]];
        if eta[0] * (cen[0] - pa[0]) + eta[1] * (cen[1] - pa[1]) < 0.0 {
            bottom.swap(0, 1);
            top.swap(0, 1);
        }
        let kind = match p.edge_nodes.len() {
            2 => JointKind::Lin4,
            _ => JointKind::Lin6,
        };
        joints[p.spec].elements.push(JointElement {
            kind,
            bottom,
            top,
            edge_tag: p.tag,
            bottom_cell: p.bottom_cell,
            top_cell: p.top_cell,
        });
    }
    for joint in &mut joints {
        let bodies = |cells: Vec<usize>| -> Vec<usize> {
            let set: BTreeSet<usize> = cells.into_iter().map(|c| mesh.cells[c].body).collect();
            set.into_iter().collect()
        };
        joint.bottom_bodies = bodies(joint.elements.iter().map(|e| e.bottom_cell).collect());
        joint.top_bodies = bodies(joint.elements.iter().map(|e| e.top_cell).collect());
        let on_joint: BTreeSet<usize> = joint
            .elements
            .iter()
            .flat_map(|e| e.bottom.iter().copied())
            .collect();
        joint.duplicated = split
            .duplicated
            .iter()
            .copied()
            .filter(|(o, _)| on_joint.contains(o))
            .collect();
    }
    joints
}

/// Centroid of a cell's corner nodes.
fn centroid(mesh: &Mesh, c: usize) -> [f64; 2] {
    let cell = &mesh.cells[c];
    let k = cell.kind.n_corners();
    let mut s = [0.0, 0.0];
    for &n in &cell.nodes[..k] {
        s[0] += mesh.nodes[n][0];
        s[1] += mesh.nodes[n][1];
    }
    [s[0] / k as f64, s[1] / k as f64]
}
