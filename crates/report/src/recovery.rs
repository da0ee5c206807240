//! The stress of the plastic bodies from `plastic.json`: the returned
//! stress at the Gauss points, recovered at any point of a cell by a
//! least-squares fit of the cell's Gauss-point values by `1, r, z` (the
//! mean for a cell with fewer than 3 points or collinear ones), at the
//! section nearest the angle asked.

use crate::vtu::revolution::SectionMap;
use axijoint_mesh::Mesh;
use axijoint_solver::results::PlasticFieldFile;

/// The plastic bodies' stress of a `plastic.json` on its mesh.
pub struct PlasticStress<'a> {
    pf: &'a PlasticFieldFile,
    map: SectionMap,
    /// The Gauss points of each meridional cell (none in an elastic body).
    points_of: Vec<Vec<usize>>,
}

impl<'a> PlasticStress<'a> {
    /// The recovery of `pf` on `mesh`; an error when they do not match.
    pub fn new(mesh: &Mesh, pf: &'a PlasticFieldFile) -> Result<PlasticStress<'a>, String> {
        let points_of = cell_points(mesh, pf)?;
        Ok(PlasticStress {
            pf,
            map: SectionMap::new(&pf.sections_deg, &pf.section_weights),
            points_of,
        })
    }

    /// Whether meridional cell `cell` has Gauss points in the file (is in a
    /// plastic body).
    pub fn has(&self, cell: usize) -> bool {
        self.points_of.get(cell).is_some_and(|p| !p.is_empty())
    }

    /// The stress `(s_r, s_z, s_th, t_rz, t_rth, t_zth)` at `p = (r, z)`
    /// of cell `cell` at angle `theta` (radians), at the section nearest
    /// `theta` (mirrored for a half-circle set: the two shears with theta
    /// change sign); `None` for a cell without Gauss points.
    pub fn at(&self, cell: usize, p: [f64; 2], theta: f64) -> Option<[f64; 6]> {
        let points = self.points_of.get(cell).filter(|p| !p.is_empty())?;
        let (section, mirrored) = self.map.nearest(theta);
        let values = &self.pf.values[section];
        let n = points.len() as f64;
        // Centred and scaled coordinates (conditioning).
        let (rc, zc) = points.iter().fold((0.0, 0.0), |(r, z), &q| {
            (r + self.pf.points[q].r / n, z + self.pf.points[q].z / n)
        });
        let h = points
            .iter()
            .map(|&q| (self.pf.points[q].r - rc).hypot(self.pf.points[q].z - zc))
            .fold(0.0, f64::max);
        let basis = |r: f64, z: f64| {
            if h > 0.0 {
                [1.0, (r - rc) / h, (z - zc) / h]
            } else {
                [1.0, 0.0, 0.0]
            }
        };
        let mut mean = [0.0; 6];
        for &q in points {
            for (m, v) in mean.iter_mut().zip(&values[q].sigma) {
                *m += v / n;
            }
        }
        let mut s = mean;
        if points.len() >= 3 && h > 0.0 {
            // Normal equations A c = b, one right-hand side per component.
            let mut a = [[0.0; 3]; 3];
            let mut b = [[0.0; 6]; 3];
            for &q in points {
                let phi = basis(self.pf.points[q].r, self.pf.points[q].z);
                for i in 0..3 {
                    for j in 0..3 {
                        a[i][j] += phi[i] * phi[j];
                    }
                    for (k, v) in values[q].sigma.iter().enumerate() {
                        b[i][k] += phi[i] * v;
                    }
                }
            }
            if let Some(inv) = inverse(&a) {
                let phi = basis(p[0], p[1]);
                for (k, sk) in s.iter_mut().enumerate() {
                    *sk = (0..3)
                        .map(|i| phi[i] * (0..3).map(|j| inv[i][j] * b[j][k]).sum::<f64>())
                        .sum();
                }
            }
        }
        if mirrored {
            s[4] = -s[4];
            s[5] = -s[5];
        }
        Some(s)
    }
}

/// The inverse of a symmetric 3x3 matrix, `None` when nearly singular
/// (collinear points).
fn inverse(a: &[[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let c = |i: usize, j: usize| {
        let (i1, i2, j1, j2) = ((i + 1) % 3, (i + 2) % 3, (j + 1) % 3, (j + 2) % 3);
        a[i1][j1] * a[i2][j2] - a[i1][j2] * a[i2][j1]
    };
    let det = a[0][0] * c(0, 0) + a[0][1] * c(0, 1) + a[0][2] * c(0, 2);
    let scale = a[0][0] * a[1][1] * a[2][2];
    if det.is_nan() || det.abs() <= 1e-10 * scale.abs() {
        return None;
    }
    let mut inv = [[0.0; 3]; 3];
    for (i, row) in inv.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = c(j, i) / det;
        }
    }
    Some(inv)
}

/// The Gauss points of each meridional cell of `mesh` in `pf` (none in an
/// elastic body), after checking that `pf`'s sections, values and cells
/// fit together and the mesh; the error says what does not.
pub(crate) fn cell_points(mesh: &Mesh, pf: &PlasticFieldFile) -> Result<Vec<Vec<usize>>, String> {
    if pf.sections_deg.is_empty()
        || pf.values.len() != pf.sections_deg.len()
        || pf.section_weights.len() != pf.sections_deg.len()
    {
        return Err(format!(
            "{} sections, {} weights, {} rows of values",
            pf.sections_deg.len(),
            pf.section_weights.len(),
            pf.values.len()
        ));
    }
    if let Some(s) = pf.values.iter().position(|v| v.len() != pf.points.len()) {
        return Err(format!(
            "section {s} has {} values for {} points",
            pf.values[s].len(),
            pf.points.len()
        ));
    }
    let mut points_of: Vec<Vec<usize>> = vec![Vec::new(); mesh.cells.len()];
    for (i, p) in pf.points.iter().enumerate() {
        points_of
            .get_mut(p.cell)
            .ok_or_else(|| {
                format!(
                    "point {i} is in cell {}, the mesh has {}",
                    p.cell,
                    mesh.cells.len()
                )
            })?
            .push(i);
    }
    Ok(points_of)
}

#[cfg(test)]
mod tests {
    use super::inverse;

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn inverse_of_a_symmetric_matrix() {
        let a = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]];
        let inv = inverse(&a).unwrap();
        for (i, row) in a.iter().enumerate() {
            for j in 0..3 {
                let p: f64 = (0..3).map(|k| row[k] * inv[k][j]).sum();
                assert!((p - f64::from(u8::from(i == j))).abs() < 1e-14, "{i} {j} {p}");
            }
        }
        assert!(inverse(&[[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 1.0]]).is_none());
    }
}
