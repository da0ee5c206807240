//! The volume elements of a gmsh MSH 4.1 mesh, for a CalculiX deck: the
//! nodes they use, renumbered from 0, and the body of each element.

use anyhow::{bail, Context, Result};
use axijoint_mesh::msh::RawElement;
use std::collections::HashMap;
use std::path::Path;

/// The volume elements of a mesh.
#[derive(Clone, Debug)]
pub struct Volumes<B, const N: usize> {
    /// Coordinates of the nodes the elements use, in the order first met.
    pub coords: Vec<[f64; 3]>,
    /// Connectivity: node k is gmsh node `order[k]` of [`read_volumes`].
    pub elements: Vec<[usize; N]>,
    /// Body of each element.
    pub body: Vec<B>,
}

/// Reads the volume elements of `path`. `bodies` names the two physical
/// volumes; `check` accepts an element (its type and node count) before
/// its body is looked up; element node k is gmsh node `order[k]`; `noun`
/// names the elements in the error of an empty mesh.
pub fn read_volumes<B: Copy, const N: usize>(
    path: &Path,
    bodies: [(&str, B); 2],
    order: [usize; N],
    check: impl Fn(&RawElement) -> Result<()>,
    noun: &str,
) -> Result<Volumes<B, N>> {
    let bytes = std::fs::read(path).with_context(|| format!("reading mesh {}", path.display()))?;
    let msh =
        axijoint_mesh::parse_msh(&bytes, path).with_context(|| format!("parsing mesh {}", path.display()))?;
    let mut phys: HashMap<i32, B> = HashMap::new();
    for p in msh.physical_names.iter().filter(|p| p.dim == 3) {
        if let Some((_, b)) = bodies.iter().find(|(name, _)| *name == p.name) {
            phys.insert(p.tag, *b);
        }
    }
    if phys.len() != 2 {
        bail!(
            "{}: expected physical volumes \"{}\" and \"{}\"",
            path.display(),
            bodies[0].0,
            bodies[1].0
        );
    }
    let index: HashMap<u64, usize> = msh.nodes.iter().enumerate().map(|(i, (t, _))| (*t, i)).collect();
    let mut used = vec![usize::MAX; msh.nodes.len()];
    let mut out = Volumes {
        coords: Vec::new(),
        elements: Vec::new(),
        body: Vec::new(),
    };
    for e in msh.elements.iter().filter(|e| e.entity_dim == 3) {
        check(e)?;
        let b = e
            .physical_tags
            .iter()
            .find_map(|t| phys.get(t))
            .with_context(|| format!("{}: element {} in no physical volume", path.display(), e.tag))?;
        let mut conn = [0usize; N];
        for (k, g) in order.iter().enumerate() {
            let tag = e.nodes[*g];
            let i = *index
                .get(&tag)
                .with_context(|| format!("{}: element {} uses unknown node {tag}", path.display(), e.tag))?;
            if used[i] == usize::MAX {
                used[i] = out.coords.len();
                out.coords.push(msh.nodes[i].1);
            }
            conn[k] = used[i];
        }
        out.elements.push(conn);
        out.body.push(*b);
    }
    if out.elements.is_empty() {
        bail!("{}: no {noun}", path.display());
    }
    Ok(out)
}

/// Checks that each mid-edge node of element `e` (0-based) with nodes `t`
/// lies near the middle of its edge: node `first_mid + k` of edge
/// `edges[k]`.
pub fn check_mid_edges(
    coords: &[[f64; 3]],
    e: usize,
    t: &[usize],
    edges: &[(usize, usize)],
    first_mid: usize,
) -> Result<()> {
    for (k, &(i, j)) in edges.iter().enumerate() {
        let (p, q, m) = (coords[t[i]], coords[t[j]], coords[t[first_mid + k]]);
        let mid = [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0, (p[2] + q[2]) / 2.0];
        if dist(mid, m) > 0.25 * dist(p, q) {
            bail!(
                "element {}: node {} is not the middle of edge {}-{}",
                e + 1,
                t[first_mid + k] + 1,
                t[i] + 1,
                t[j] + 1
            );
        }
    }
    Ok(())
}

/// Euclidean distance.
pub fn dist(p: [f64; 3], q: [f64; 3]) -> f64 {
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}
