//! Writing a [`Mesh`] as gmsh MSH 4.1 ASCII, joints included: see
//! [`write_msh41`].

use super::element_type;
use crate::{EdgeKind, JointKind, Mesh};
use std::collections::{BTreeMap, HashMap, HashSet};
use std::io::{self, Write};

/// The 4-node quadrangles of a joint element: `[b0, b1, t1, t0]`; a 6-node
/// element gives two, `[b0, b2, t2, t0]` and `[b2, b1, t1, t2]`.
pub fn joint_quads(kind: JointKind, bottom: &[usize], top: &[usize]) -> Vec<[usize; 4]> {
    match kind {
        JointKind::Lin4 => vec![[bottom[0], bottom[1], top[1], top[0]]],
        JointKind::Lin6 => vec![
            [bottom[0], bottom[2], top[2], top[0]],
            [bottom[2], bottom[1], top[1], top[2]],
        ],
    }
}

/// A model entity to write: its physical tags and the nodes of its elements
/// (for the bounding box).
struct Entity {
    tag: i32,
    physical: Vec<i32>,
    nodes: Vec<usize>,
}

/// Element blocks of one dimension, `(entity index, gmsh type, node lists)`:
/// one per run of elements of one entity and type, in element order.
type Blocks = Vec<(usize, i32, Vec<Vec<usize>>)>;

fn push_element(blocks: &mut Blocks, entity: usize, gmsh_type: i32, nodes: Vec<usize>) {
    match blocks.last_mut() {
        Some(b) if b.0 == entity && b.1 == gmsh_type => b.2.push(nodes),
        _ => blocks.push((entity, gmsh_type, vec![nodes])),
    }
}

/// Entities of one dimension keyed by `(source entity, physical tags)`:
/// the source tag is kept when it is free, else a new one is taken.
#[derive(Default)]
struct EntityTable {
    entities: Vec<Entity>,
    index: HashMap<(i32, Vec<i32>), usize>,
    used: HashSet<i32>,
}

impl EntityTable {
    fn get(&mut self, source: i32, physical: Vec<i32>) -> usize {
        let key = (source, physical);
        if let Some(&i) = self.index.get(&key) {
            return i;
        }
        let tag = if source > 0 && !self.used.contains(&source) {
            source
        } else {
            self.fresh()
        };
        self.used.insert(tag);
        self.entities.push(Entity {
            tag,
            physical: key.1.clone(),
            nodes: Vec::new(),
        });
        self.index.insert(key, self.entities.len() - 1);
        self.entities.len() - 1
    }

    /// A new entity with a tag above every source tag.
    fn add(&mut self, physical: Vec<i32>) -> usize {
        let tag = self.fresh();
        self.used.insert(tag);
        self.entities.push(Entity {
            tag,
            physical,
            nodes: Vec::new(),
        });
        self.entities.len() - 1
    }

    fn fresh(&self) -> i32 {
        self.used.iter().copied().max().unwrap_or(0).max(0) + 1
    }
}

/// Writes `mesh` as gmsh MSH 4.1 ASCII (what gmsh and meshio read).
///
/// - Nodes: node `k` of the mesh (joint copies included) is the `k`-th node
///   of the file, tag `k + 1`, at `(x, y, z) = (r, z, 0)`.
/// - Physical names: the bodies (dimension 2), the curves (1) and the point
///   groups (0) keep their names and tags; the curve of a joint is not
///   written as a curve but as the joint's own physical surface.
/// - Joints: each joint element is a zero-thickness 4-node quadrangle (gmsh
///   type 3) `[b0, b1, t1, t0]` (bottom face first, then the top face
///   backwards, so that node 0 pairs with 3 and 1 with 2); a 6-node joint
///   element gives two such quadrangles (see [`joint_quads`]). The
///   quadrangles of joint `j` form a physical surface named after the joint
///   (`<name>_joint` if another group already has that name), tag = the
///   largest body tag + 1 + `j`.
/// - Elements: the cells first, in mesh order (cell `c` is element `c + 1`,
///   on its surface entity), then the joints' quadrangles (joint by joint,
///   in element order), the line elements (each once) and the points.
///
/// Errors: [`io::ErrorKind::InvalidInput`] for a coordinate that is not
/// finite or nodes without any element, and the writer's errors.
pub fn write_msh41(mesh: &Mesh, w: &mut impl Write) -> io::Result<()> {
    if let Some(k) = mesh.nodes.iter().position(|p| !p.iter().all(|v| v.is_finite())) {
        return Err(invalid(format!(
            "node {} has a coordinate that is not finite ({:?})",
            k, mesh.nodes[k]
        )));
    }
    let joint_curves: HashSet<&str> = mesh.joints.iter().map(|j| j.name.as_str()).collect();
    let (names, joint_tags) = physical_names(mesh, &joint_curves);
    let (points, point_blocks) = point_entities(mesh);
    let (curves, curve_blocks) = curve_entities(mesh, &joint_curves);
    let (surfaces, surface_blocks, mut owner) = surface_entities(mesh, &joint_tags);
    let entities = Entities {
        points,
        curves,
        surfaces,
    };
    complete_owners(&mut owner, &entities)?;

    write_physical_names(w, &names)?;
    write_entities(w, mesh, &entities)?;
    write_nodes(w, mesh, &owner, &entities)?;
    write_elements(
        w,
        [(2, &surface_blocks), (1, &curve_blocks), (0, &point_blocks)],
        &entities,
    )
}

/// An [`io::ErrorKind::InvalidInput`] error.
fn invalid(m: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, m)
}

/// A physical group: `(dim, tag, name)`.
type Name = (i32, i32, String);

/// The entity of each node, `(dim, entity index)`, where known.
type Owners = Vec<Option<(i32, usize)>>;

/// The point, curve and surface entities of the file.
struct Entities {
    points: EntityTable,
    curves: EntityTable,
    surfaces: EntityTable,
}

impl Entities {
    /// The tag of entity `e` of dimension `dim`.
    fn tag_of(&self, (dim, e): (i32, usize)) -> i32 {
        match dim {
            0 => self.points.entities[e].tag,
            1 => self.curves.entities[e].tag,
            _ => self.surfaces.entities[e].tag,
        }
    }
}

/// The physical groups (points, non-joint curves, bodies, joints) and the joints' tags.
fn physical_names(mesh: &Mesh, joint_curves: &HashSet<&str>) -> (Vec<Name>, Vec<i32>) {
    let mut names: Vec<Name> = Vec::new();
    names.extend(mesh.points.iter().map(|p| (0, p.tag, p.name.clone())));
    names.extend(
        mesh.curves
            .iter()
            .filter(|c| !joint_curves.contains(c.name.as_str()))
            .map(|c| (1, c.tag, c.name.clone())),
    );
    names.extend(mesh.bodies.iter().map(|b| (2, b.tag, b.name.clone())));
    let first_joint_tag = mesh.bodies.iter().map(|b| b.tag).max().unwrap_or(0).max(0) + 1;
    let mut joint_tags = Vec::with_capacity(mesh.joints.len());
    for (j, joint) in mesh.joints.iter().enumerate() {
        let mut name = joint.name.clone();
        while names.iter().any(|n| n.2 == name) {
            name.push_str("_joint");
        }
        let tag = first_joint_tag + j as i32;
        names.push((2, tag, name));
        joint_tags.push(tag);
    }
    (names, joint_tags)
}

/// Point entities and their elements: one per node of a point group.
fn point_entities(mesh: &Mesh) -> (EntityTable, Blocks) {
    let mut points = EntityTable::default();
    let mut point_blocks: Blocks = Vec::new();
    let mut point_groups: BTreeMap<usize, Vec<i32>> = BTreeMap::new();
    for set in &mesh.points {
        for &n in &set.nodes {
            let tags = point_groups.entry(n).or_default();
            if !tags.contains(&set.tag) {
                tags.push(set.tag);
            }
        }
    }
    for (n, tags) in point_groups {
        let e = points.add(tags);
        points.entities[e].nodes.push(n);
        push_element(&mut point_blocks, e, element_type::POINT, vec![n]);
    }
    (points, point_blocks)
}

/// Curve entities and their elements: each line element once, with every non-joint curve it is in.
fn curve_entities(mesh: &Mesh, joint_curves: &HashSet<&str>) -> (EntityTable, Blocks) {
    let mut edges: Vec<(i32, EdgeKind, Vec<usize>, Vec<i32>)> = Vec::new();
    let mut edge_index: HashMap<(u64, Vec<usize>), usize> = HashMap::new();
    for set in mesh
        .curves
        .iter()
        .filter(|c| !joint_curves.contains(c.name.as_str()))
    {
        for edge in &set.edges {
            let i = *edge_index
                .entry((edge.tag, edge.nodes.clone()))
                .or_insert_with(|| {
                    edges.push((edge.entity, edge.kind, edge.nodes.clone(), Vec::new()));
                    edges.len() - 1
                });
            if !edges[i].3.contains(&set.tag) {
                edges[i].3.push(set.tag);
            }
        }
    }
    let mut curves = EntityTable::default();
    let mut curve_blocks: Blocks = Vec::new();
    for (entity, kind, nodes, mut tags) in edges {
        tags.sort_unstable();
        let e = curves.get(entity, tags);
        curves.entities[e].nodes.extend(&nodes);
        push_element(&mut curve_blocks, e, element_type::of_edge(kind), nodes);
    }
    (curves, curve_blocks)
}

/// Surface entities and elements (the cells', then one per joint); each node's first cell entity.
fn surface_entities(mesh: &Mesh, joint_tags: &[i32]) -> (EntityTable, Blocks, Owners) {
    let mut surfaces = EntityTable::default();
    let mut surface_blocks: Blocks = Vec::new();
    let mut owner: Owners = vec![None; mesh.nodes.len()];
    for cell in &mesh.cells {
        let e = surfaces.get(cell.entity, vec![mesh.bodies[cell.body].tag]);
        surfaces.entities[e].nodes.extend(&cell.nodes);
        for &n in &cell.nodes {
            owner[n].get_or_insert((2, e));
        }
        push_element(
            &mut surface_blocks,
            e,
            element_type::of_cell(cell.kind),
            cell.nodes.clone(),
        );
    }
    for (joint, &tag) in mesh.joints.iter().zip(joint_tags) {
        let e = surfaces.add(vec![tag]);
        for el in &joint.elements {
            for q in joint_quads(el.kind, &el.bottom, &el.top) {
                surfaces.entities[e].nodes.extend(q);
                push_element(&mut surface_blocks, e, element_type::QUAD4, q.to_vec());
            }
        }
    }
    (surfaces, surface_blocks, owner)
}

/// Nodes in no cell belong to the first curve, else point, entity using them; none is an error.
fn complete_owners(owner: &mut Owners, entities: &Entities) -> io::Result<()> {
    for (dim, table) in [(1, &entities.curves), (0, &entities.points)] {
        for (e, entity) in table.entities.iter().enumerate() {
            for &n in &entity.nodes {
                owner[n].get_or_insert((dim, e));
            }
        }
    }
    if let Some(n) = owner.iter().position(Option::is_none) {
        return Err(invalid(format!("node {n} belongs to no element")));
    }
    Ok(())
}

/// Writes `$MeshFormat` and `$PhysicalNames` (quotes and control characters as `_`).
fn write_physical_names(w: &mut impl Write, names: &[Name]) -> io::Result<()> {
    writeln!(w, "$MeshFormat\n4.1 0 8\n$EndMeshFormat")?;
    writeln!(w, "$PhysicalNames\n{}", names.len())?;
    for (dim, tag, name) in names {
        let name: String = name
            .chars()
            .map(|c| if c == '"' || c.is_control() { '_' } else { c })
            .collect();
        writeln!(w, "{dim} {tag} \"{name}\"")?;
    }
    writeln!(w, "$EndPhysicalNames")
}

/// An entity's physical tags as written: their count, then each.
fn physical(e: &Entity) -> String {
    let mut s = e.physical.len().to_string();
    for t in &e.physical {
        s.push_str(&format!(" {t}"));
    }
    s
}

/// Writes `$Entities`: points at their node, curves and surfaces with their bounding box.
fn write_entities(w: &mut impl Write, mesh: &Mesh, entities: &Entities) -> io::Result<()> {
    let Entities {
        points,
        curves,
        surfaces,
    } = entities;
    writeln!(w, "$Entities")?;
    writeln!(
        w,
        "{} {} {} 0",
        points.entities.len(),
        curves.entities.len(),
        surfaces.entities.len()
    )?;
    for e in &points.entities {
        let p = mesh.nodes[e.nodes[0]];
        writeln!(w, "{} {:?} {:?} 0 {}", e.tag, p[0], p[1], physical(e))?;
    }
    for e in curves.entities.iter().chain(&surfaces.entities) {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for &n in &e.nodes {
            for a in 0..2 {
                lo[a] = lo[a].min(mesh.nodes[n][a]);
                hi[a] = hi[a].max(mesh.nodes[n][a]);
            }
        }
        writeln!(
            w,
            "{} {:?} {:?} 0 {:?} {:?} 0 {} 0",
            e.tag,
            lo[0],
            lo[1],
            hi[0],
            hi[1],
            physical(e)
        )?;
    }
    writeln!(w, "$EndEntities")
}

/// Writes `$Nodes`: in mesh order, one block per run of nodes of one entity.
fn write_nodes(w: &mut impl Write, mesh: &Mesh, owner: &Owners, entities: &Entities) -> io::Result<()> {
    let mut runs: Vec<((i32, usize), std::ops::Range<usize>)> = Vec::new();
    for (n, o) in owner.iter().enumerate() {
        let o = o.unwrap_or((2, 0));
        match runs.last_mut() {
            Some((last, r)) if *last == o => r.end = n + 1,
            _ => runs.push((o, n..n + 1)),
        }
    }
    let n_nodes = mesh.nodes.len();
    writeln!(w, "$Nodes\n{} {n_nodes} {} {n_nodes}", runs.len(), n_nodes.min(1))?;
    for ((dim, e), range) in &runs {
        writeln!(w, "{dim} {} 0 {}", entities.tag_of((*dim, *e)), range.len())?;
        for n in range.clone() {
            writeln!(w, "{}", n + 1)?;
        }
        for n in range.clone() {
            writeln!(w, "{:?} {:?} 0", mesh.nodes[n][0], mesh.nodes[n][1])?;
        }
    }
    writeln!(w, "$EndNodes")
}

/// Writes `$Elements`: the blocks of each dimension in the order given, numbered from 1.
fn write_elements(w: &mut impl Write, all: [(i32, &Blocks); 3], entities: &Entities) -> io::Result<()> {
    let n_blocks: usize = all.iter().map(|(_, b)| b.len()).sum();
    let n_elements: usize = all.iter().flat_map(|(_, b)| b.iter()).map(|b| b.2.len()).sum();
    writeln!(
        w,
        "$Elements\n{n_blocks} {n_elements} {} {n_elements}",
        n_elements.min(1)
    )?;
    let mut id = 0usize;
    for (dim, blocks) in all {
        for (e, gmsh_type, elements) in blocks {
            writeln!(
                w,
                "{dim} {} {gmsh_type} {}",
                entities.tag_of((dim, *e)),
                elements.len()
            )?;
            for nodes in elements {
                id += 1;
                write!(w, "{id}")?;
                for n in nodes {
                    write!(w, " {}", n + 1)?;
                }
                writeln!(w)?;
            }
        }
    }
    writeln!(w, "$EndElements")
}
