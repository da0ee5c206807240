//! What `axijoint mesh` prints: counts, areas and joint sizes.

use crate::geometry::{cell_area, edge_length_and_lateral};
use crate::{EdgeKind, JointKind, Mesh};
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt;

/// Per-body figures.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct BodySummary {
    /// Number of 2D elements.
    pub elements: usize,
    /// Elements per family (`T3`, `T6`, `Q4`, `Q8`, `Q9`).
    pub types: BTreeMap<String, usize>,
    /// Meridional area Integral(dr dz).
    pub area: f64,
}

/// Per-joint figures.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct JointSummary {
    /// Number of joint elements.
    pub elements: usize,
    /// `Lin4` or `Lin6`.
    pub kind: String,
    /// Nodes given a copy on the top face.
    pub duplicated_nodes: usize,
    /// Meridional length of the joint.
    pub length: f64,
    /// Lateral area 2 pi Integral(r ds).
    pub lateral_area: f64,
    /// Bodies on the bottom face, joined by `+`.
    pub bottom: String,
    /// Bodies on the top face, joined by `+`.
    pub top: String,
}

/// Summary of a mesh (see `docs/` for the JSON form).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Summary {
    /// Number of nodes (after joint insertion).
    pub nodes: usize,
    /// Number of 2D elements.
    pub elements: usize,
    /// Bodies by physical name.
    pub bodies: BTreeMap<String, BodySummary>,
    /// Joints by physical curve name.
    pub joints: BTreeMap<String, JointSummary>,
    /// Line elements per physical curve.
    pub curves: BTreeMap<String, usize>,
    /// Nodes per physical point group.
    pub points: BTreeMap<String, usize>,
}

impl Summary {
    /// Computes the summary of `mesh`.
    pub fn of(mesh: &Mesh) -> Summary {
        let names = |bodies: &[usize]| -> String {
            let list: Vec<&str> = bodies.iter().map(|&b| mesh.bodies[b].name.as_str()).collect();
            list.join("+")
        };
        let mut bodies: BTreeMap<String, BodySummary> = mesh
            .bodies
            .iter()
            .map(|b| {
                let s = BodySummary {
                    elements: 0,
                    types: BTreeMap::new(),
                    area: 0.0,
                };
                (b.name.clone(), s)
            })
            .collect();
        for cell in &mesh.cells {
            let b = bodies
                .get_mut(&mesh.bodies[cell.body].name)
                .expect("every cell's body is listed");
            b.elements += 1;
            *b.types.entry(cell.kind.name().to_string()).or_default() += 1;
            b.area += cell_area(cell.kind, &mesh.cell_coords(cell));
        }
        let joints = mesh
            .joints
            .iter()
            .map(|j| {
                let (mut length, mut lateral) = (0.0, 0.0);
                for el in &j.elements {
                    let coords: Vec<[f64; 2]> = el.bottom.iter().map(|&n| mesh.nodes[n]).collect();
                    let kind = match el.kind {
                        JointKind::Lin4 => EdgeKind::Lin2,
                        JointKind::Lin6 => EdgeKind::Lin3,
                    };
                    let (l, r) = edge_length_and_lateral(kind, &coords);
                    length += l;
                    lateral += r;
                }
                let kind = j.elements.first().map_or("none", |e| match e.kind {
                    JointKind::Lin4 => "Lin4",
                    JointKind::Lin6 => "Lin6",
                });
                let s = JointSummary {
                    elements: j.elements.len(),
                    kind: kind.to_string(),
                    duplicated_nodes: j.duplicated.len(),
                    length,
                    lateral_area: 2.0 * std::f64::consts::PI * lateral,
                    bottom: names(&j.bottom_bodies),
                    top: names(&j.top_bodies),
                };
                (j.name.clone(), s)
            })
            .collect();
        Summary {
            nodes: mesh.nodes.len(),
            elements: mesh.cells.len(),
            bodies,
            joints,
            curves: mesh
                .curves
                .iter()
                .map(|c| (c.name.clone(), c.edges.len()))
                .collect(),
            points: mesh
                .points
                .iter()
                .map(|p| (p.name.clone(), p.nodes.len()))
                .collect(),
        }
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "nodes     {}", self.nodes)?;
        writeln!(f, "elements  {}", self.elements)?;
        writeln!(f, "bodies:")?;
        for (name, b) in &self.bodies {
            let types: Vec<String> = b.types.iter().map(|(k, n)| format!("{n} {k}")).collect();
            writeln!(
                f,
                "  {name:<16} {:>7} elements ({})  area {:.6}",
                b.elements,
                types.join(", "),
                b.area
            )?;
        }
        if !self.joints.is_empty() {
            writeln!(f, "joints:")?;
        }
        for (name, j) in &self.joints {
            writeln!(
                f,
                "  {name:<16} {:>7} {} elements, {} duplicated nodes, {} (bottom) / {} (top), length {:.6}, lateral area {:.6}",
                j.elements, j.kind, j.duplicated_nodes, j.bottom, j.top, j.length, j.lateral_area
            )?;
        }
        writeln!(f, "boundary sets:")?;
        for (name, n) in &self.curves {
            writeln!(f, "  {name:<16} {n:>7} line elements")?;
        }
        for (name, n) in &self.points {
            writeln!(f, "  {name:<16} {n:>7} nodes")?;
        }
        Ok(())
    }
}
