//! `plastic.json`: the field of the plastic bodies per Gauss point and
//! section (stress, plastic strain, yielding), as written and read back.

use super::{bad_saved, read_err};
use crate::error::SolverError;
use axijoint_mesh::Mesh;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::Path;

/// The file name of the plastic bodies' field in a solution folder.
pub const PLASTIC_FIELD: &str = "plastic.json";

/// Where a Gauss point of a plastic body is.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyPointOut {
    /// Body name.
    pub body: String,
    /// The point's cell (index into the mesh's cells, element `cell + 1` of
    /// `mesh_solved.msh`).
    pub cell: usize,
    /// Position.
    pub r: f64,
    /// Position.
    pub z: f64,
    /// The pore pressure there with ground water (compression positive).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub pore_pressure: f64,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// The values of a plastic body at one Gauss point and section.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlasticValues {
    /// Total stress `(s_r, s_z, s_th, t_rz, t_rth, t_zth)`, with the initial
    /// stress (the effective stress less the pore pressure with water).
    pub sigma: [f64; 6],
    /// Plastic strain, same order, engineering shears.
    pub plastic: [f64; 6],
    /// Whether the point yields.
    pub yielding: bool,
}

/// `plastic.json`: the field of the plastic bodies of a nonlinear run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlasticFieldFile {
    /// Section angles in degrees.
    pub sections_deg: Vec<f64>,
    /// Section quadrature weights in radians (sum 2 pi).
    pub section_weights: Vec<f64>,
    /// The Gauss points, cell by cell.
    pub points: Vec<BodyPointOut>,
    /// `values[section][point]`.
    pub values: Vec<Vec<PlasticValues>>,
}

/// The equivalent plastic strain `sqrt(2/3 eps:eps)` of a plastic strain
/// `(e_r, e_z, e_th, g_rz, g_rth, g_zth)` with engineering shears (the
/// tensor's shears are half of them): 1 for the isochoric uniaxial
/// `(1, -1/2, -1/2, 0, 0, 0)`, `g / sqrt(3)` for a pure shear `g`.
pub fn equivalent_plastic_strain(e: &[f64; 6]) -> f64 {
    let normal = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
    let shear = 0.5 * (e[3] * e[3] + e[4] * e[4] + e[5] * e[5]);
    (2.0 / 3.0 * (normal + shear)).sqrt()
}

impl PlasticFieldFile {
    /// The plastic bodies' field `field` on `mesh`, its stress made total
    /// with `water`.
    pub fn new(
        mesh: &Mesh,
        field: &crate::iteration::BodyField,
        water: Option<&crate::scene::Water>,
    ) -> Self {
        let points: Vec<BodyPointOut> = field
            .points
            .iter()
            .zip(&field.cells)
            .map(|(&[r, z], &cell)| BodyPointOut {
                body: mesh.bodies[mesh.cells[cell].body].name.clone(),
                cell,
                r,
                z,
                pore_pressure: water.map_or(0.0, |w| w.pressure(z)),
            })
            .collect();
        let n_p = field.points.len();
        let total = |k: usize| {
            let p = points[k % n_p.max(1)].pore_pressure;
            let mut s = field.sigma[k];
            for v in &mut s[..3] {
                *v -= p;
            }
            s
        };
        let values = (0..field.sections.theta.len())
            .map(|s| {
                (s * n_p..(s + 1) * n_p)
                    .map(|k| PlasticValues {
                        sigma: total(k),
                        plastic: field.plastic[k],
                        yielding: field.yielding[k],
                    })
                    .collect()
            })
            .collect();
        PlasticFieldFile {
            sections_deg: field.sections.theta.iter().map(|t| t.to_degrees()).collect(),
            section_weights: field.sections.weight.clone(),
            points,
            values,
        }
    }

    /// Whether the values have the sections and points the file lists.
    fn shape_error(&self) -> Option<String> {
        if self.values.len() != self.sections_deg.len()
            || self.section_weights.len() != self.sections_deg.len()
        {
            return Some(format!(
                "{} sections, {} weights, {} rows of values",
                self.sections_deg.len(),
                self.section_weights.len(),
                self.values.len()
            ));
        }
        let s = self.values.iter().position(|v| v.len() != self.points.len())?;
        Some(format!(
            "section {s} has {} values for {} points",
            self.values[s].len(),
            self.points.len()
        ))
    }

    /// The first value that is not finite, as `(section, point)`
    /// (`section` = `usize::MAX` for an angle, weight or position).
    pub fn first_non_finite(&self) -> Option<(usize, usize)> {
        let fine = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !fine(&self.sections_deg) || !fine(&self.section_weights) {
            return Some((usize::MAX, 0));
        }
        if let Some(p) = self.points.iter().position(|p| !fine(&[p.r, p.z])) {
            return Some((usize::MAX, p));
        }
        self.values.iter().enumerate().find_map(|(s, row)| {
            row.iter()
                .position(|v| !fine(&v.sigma) || !fine(&v.plastic))
                .map(|p| (s, p))
        })
    }
}

/// Writes `field` to `path` (JSON, as [`read_plastic_field`] reads it);
/// `Err` with the I/O error. The caller checks [`PlasticFieldFile::first_non_finite`]
/// first (JSON writes a NaN as `null`) and stages the file.
pub(super) fn write_plastic_field(path: &Path, field: &PlasticFieldFile) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    serde_json::to_writer(&mut w, field)?;
    w.flush()
}

/// Reads `plastic.json` of a solution folder, if the run had plastic bodies
/// (`None` without the file: every body elastic, or a folder written before
/// it existed).
pub fn read_plastic_field(dir: &Path) -> Result<Option<PlasticFieldFile>, SolverError> {
    let path = dir.join(PLASTIC_FIELD);
    if !path.is_file() {
        return Ok(None);
    }
    let file = std::fs::File::open(&path).map_err(|e| read_err(&path, e))?;
    let field: PlasticFieldFile =
        serde_json::from_reader(std::io::BufReader::new(file)).map_err(|e| bad_saved(&path, e))?;
    if let Some(m) = field.shape_error() {
        return Err(bad_saved(&path, m));
    }
    if field.first_non_finite().is_some() {
        return Err(bad_saved(&path, "contains values that are not finite"));
    }
    Ok(Some(field))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equivalent_plastic_strain_of_hand_cases() {
        // Isochoric uniaxial: eps:eps = 1 + 1/4 + 1/4 = 3/2, sqrt(2/3 * 3/2) = 1.
        assert!((equivalent_plastic_strain(&[1.0, -0.5, -0.5, 0.0, 0.0, 0.0]) - 1.0).abs() < 1e-15);
        // Pure shear g = 0.3 (tensor shear 0.15 twice): sqrt(2/3 * 2 * 0.15^2) = 0.3 / sqrt(3).
        for k in 3..6 {
            let mut e = [0.0; 6];
            e[k] = 0.3;
            let want = 0.3 / 3f64.sqrt();
            assert!((equivalent_plastic_strain(&e) - want).abs() < 1e-15, "{k}");
        }
        // A mixed case by hand: (2, -1, -1, 2, 0, 0): eps:eps = 4 + 1 + 1 + 2 * 1 = 8,
        // sqrt(16 / 3).
        let e = [2.0, -1.0, -1.0, 2.0, 0.0, 0.0];
        assert!((equivalent_plastic_strain(&e) - (16.0f64 / 3.0).sqrt()).abs() < 1e-15);
        assert_eq!(equivalent_plastic_strain(&[0.0; 6]), 0.0);
    }

    fn sample() -> PlasticFieldFile {
        // Values that do not print short (1/3, pi, ...), of mixed sizes and signs.
        let x = |i: usize| ((i as f64) * 0.7310585786).sin() * 10f64.powi((i % 7) as i32 - 3);
        let points: Vec<BodyPointOut> = (0..5)
            .map(|i| BodyPointOut {
                body: if i < 3 { "soil".into() } else { "clay".into() },
                cell: i / 2,
                r: 0.5 + x(i).abs(),
                z: -x(i + 11),
                pore_pressure: if i == 4 { x(3).abs() } else { 0.0 },
            })
            .collect();
        let values = (0..3)
            .map(|s| {
                (0..points.len())
                    .map(|p| {
                        let k = 100 * s + 13 * p;
                        PlasticValues {
                            sigma: std::array::from_fn(|c| x(k + c) * 1e3 / 3.0),
                            plastic: std::array::from_fn(|c| x(k + 6 + c) * 1e-4 / 7.0),
                            yielding: (s + p) % 2 == 0,
                        }
                    })
                    .collect()
            })
            .collect();
        PlasticFieldFile {
            sections_deg: vec![0.0, 180.0 / 7.0, 100.0 / 3.0],
            section_weights: vec![
                std::f64::consts::PI / 3.0,
                4.0 * std::f64::consts::PI / 3.0,
                1.0 / 3.0,
            ],
            points,
            values,
        }
    }

    /// Written and read back, every value equal to 1e-15 (relative); no
    /// file reads as no field; a file of the wrong shape or with a NaN
    /// (`null`) is refused.
    #[test]
    fn the_file_reads_back_as_written() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(read_plastic_field(dir.path()).unwrap(), None);
        let field = sample();
        assert_eq!(field.first_non_finite(), None);
        write_plastic_field(&dir.path().join(PLASTIC_FIELD), &field).unwrap();
        let back = read_plastic_field(dir.path())
            .unwrap()
            .expect("the file is there");
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-15 * b.abs().max(1e-300);
        let all_close =
            |a: &[f64], b: &[f64]| a.len() == b.len() && a.iter().zip(b).all(|(&x, &y)| close(x, y));
        assert!(all_close(&back.sections_deg, &field.sections_deg));
        assert!(all_close(&back.section_weights, &field.section_weights));
        assert_eq!(back.points.len(), field.points.len());
        for (a, b) in back.points.iter().zip(&field.points) {
            assert_eq!((&a.body, a.cell), (&b.body, b.cell));
            assert!(all_close(&[a.r, a.z], &[b.r, b.z]));
        }
        assert_eq!(back.values.len(), field.values.len());
        for (ra, rb) in back.values.iter().zip(&field.values) {
            assert_eq!(ra.len(), rb.len());
            for (a, b) in ra.iter().zip(rb) {
                assert!(all_close(&a.sigma, &b.sigma), "{a:?} {b:?}");
                assert!(all_close(&a.plastic, &b.plastic), "{a:?} {b:?}");
                assert_eq!(a.yielding, b.yielding);
            }
        }

        let mut short = field.clone();
        short.values[1].pop();
        write_plastic_field(&dir.path().join(PLASTIC_FIELD), &short).unwrap();
        let e = read_plastic_field(dir.path()).unwrap_err().to_string();
        assert!(e.contains("section 1 has 4 values for 5 points"), "{e}");

        let mut nan = field;
        nan.values[2][3].plastic[4] = f64::NAN;
        assert_eq!(nan.first_non_finite(), Some((2, 3)));
        write_plastic_field(&dir.path().join(PLASTIC_FIELD), &nan).unwrap();
        assert!(read_plastic_field(dir.path()).is_err());
    }
}
