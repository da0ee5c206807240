//! The plastic bodies' field as cell data of the solid grid: per revolved
//! cell, its meridional cell's Gauss points at the section nearest the
//! cell's mid angle.

use super::encoding::Array;
use super::revolution::{mid_angle, SectionMap};
use crate::error::{check_finite, ReportError};
use axijoint_mesh::Mesh;
use axijoint_solver::results::{equivalent_plastic_strain, PlasticFieldFile};
use std::path::Path;

/// The cell arrays `yield_fraction`, `plastic_strain_eq` and
/// `plastic_section_deg` of the revolved cells `cells` (their meridional
/// cells; each meridional cell's `n` revolved cells in slot order
/// `[theta_k, theta_{k+1}]`, k = 0 .. n-1, as the solid grid makes them).
/// A cell without Gauss points in `pf` (an elastic body) has 0 for both.
pub(super) fn plastic_arrays(
    path: &Path,
    mesh: &Mesh,
    pf: &PlasticFieldFile,
    cells: &[i64],
    n: usize,
) -> Result<Vec<Array>, ReportError> {
    let bad = |m: String| ReportError::Input(format!("{}: plastic field: {m}", path.display()));
    let points_of = crate::recovery::cell_points(mesh, pf).map_err(bad)?;
    let map = SectionMap::new(&pf.sections_deg, &pf.section_weights);
    // The section of each slot (the mirror image of a half-circle set is
    // the same: both values are even in theta).
    let section_of: Vec<usize> = (0..n).map(|k| map.nearest(mid_angle(k, n)).0).collect();
    let mut fraction = Vec::with_capacity(cells.len());
    let mut strain = Vec::with_capacity(cells.len());
    let mut section_deg = Vec::with_capacity(cells.len());
    for (i, &c) in cells.iter().enumerate() {
        let s = section_of[i % n];
        let values = &pf.values[s];
        let points = &points_of[c as usize];
        let count = points.len().max(1) as f64;
        let yielding = points.iter().filter(|&&q| values[q].yielding).count() as f64;
        let eq: f64 = points
            .iter()
            .map(|&q| equivalent_plastic_strain(&values[q].plastic))
            .sum();
        let (f, e) = (yielding / count, eq / count);
        check_finite(path, &[f, e], || {
            format!(
                "the plastic strain of cell {c}, section {} deg",
                pf.sections_deg[s]
            )
        })?;
        fraction.push(f);
        strain.push(e);
        section_deg.push(pf.sections_deg[s]);
    }
    Ok(vec![
        Array::f64("yield_fraction", 1, fraction),
        Array::f64("plastic_strain_eq", 1, strain),
        Array::f64("plastic_section_deg", 1, section_deg),
    ])
}
