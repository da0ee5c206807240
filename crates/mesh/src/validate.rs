//! Mesh validation: what the solver needs before it can trust the mesh.

use crate::geometry::corner_and_gauss_dets;
use crate::{CellKind, Mesh, MeshError};
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
///   (Jacobian of both signs, or clockwise among counter-clockwise ones);
///   a surface entity meshed wholly clockwise is renumbered.
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
        let (min, max) = corner_and_gauss_dets(cell.kind, &coords);
        let h2 = cell_size2(&coords);
        let body = &mesh.bodies[cell.body].name;
        let here = || {
            format!(
                "element {} ({}, body '{body}', surface entity {}) with nodes at {}",
                cell.tag,
                cell.kind.name(),
                cell.entity,
                corners(&coords, cell.kind)
            )
        };
        if !(min.is_finite() && max.is_finite()) || max.abs().max(min.abs()) <= 1e-12 * h2 {
            return Err(invalid(format!("{} is degenerate (zero area)", here())));
        }
        if min * max <= 0.0 {
            return Err(invalid(format!(
                "{} is inverted or distorted: its Jacobian changes sign (min {min:.3e}, max {max:.3e})",
                here()
            )));
        }
        let cw = max < 0.0;
        let e = clockwise.entry(cell.entity).or_default();
        e.0 += usize::from(cw);
        e.1 += 1;
        signs.push(cw);
    }
    for (cell, &cw) in mesh.cells.iter_mut().zip(&signs) {
        let (n_cw, n) = clockwise[&cell.entity];
        if cw && n_cw < n {
            let coords: Vec<[f64; 2]> = cell.nodes.iter().map(|&i| mesh.nodes[i]).collect();
            return Err(invalid(format!(
                "element {} ({}, body '{}', surface entity {}) with nodes at {} is inverted: it is clockwise while {} other elements of its surface are counter-clockwise",
                cell.tag,
                cell.kind.name(),
                mesh.bodies[cell.body].name,
                cell.entity,
                corners(&coords, cell.kind),
                n - n_cw
            )));
        }
        if cw {
            let old = cell.nodes.clone();
            for (slot, &i) in cell.nodes.iter_mut().zip(reversed(cell.kind)) {
                *slot = old[i];
            }
            report.reoriented += 1;
        }
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

fn corners(coords: &[[f64; 2]], kind: CellKind) -> String {
    coords[..kind.n_corners()]
        .iter()
        .map(|p| format!("({}, {})", p[0], p[1]))
        .collect::<Vec<_>>()
        .join(" ")
}
