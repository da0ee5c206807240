//! Views: the revolved `.vtu` (read back with `vtu::read_vtu`; meshio reads
//! it in tests/vtu_meshio_e2e.rs) and the gmsh view (opened by gmsh itself).
//!
//! - Pure bending of a cylinder (docs/theory.md section 15), every meridional cell
//!   kind: point and cell counts per VTK type, the displacement at every
//!   point equal to the closed form, the stress (quadratic cells) equal to
//!   sigma_zz = s x, every cell's volume positive from its VTK node order and
//!   VTK's outward face tables, and the sum equal to the revolved volume.
//! - Scene P (the real pipeline): the joint file with states in {0, 1, 2},
//!   the mirror mapping of the half-circle sections, the stress jump across
//!   the joint kept, only the point arrays asked for, and the gmsh view
//!   opened by gmsh without error.
//! - A non-finite value: no file at all.

use axijoint_mesh::{prepare, CellKind, Mesh};
use axijoint_report::field::Field;
use axijoint_report::gmsh_view::{view_name, write_gmsh_view};
use axijoint_report::vtu::{auto_sections, joints_path, read_vtu, write_vtu};
use axijoint_report::ReportError;
use axijoint_solver::material::Elastic;
use axijoint_solver::results::JointFieldFile;
use axijoint_solver::run::solve_scene;
use axijoint_solver::scene::{Outputs, Scene};
use axijoint_solver::solution::{Displacements, HarmonicDisplacement};
use std::collections::HashMap;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Every point array.
const ALL: [&str; 5] = Outputs::VTU_FIELDS;

fn geo(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../geo").join(name)
}

// ---------------------------------------------------------------------------
// Reading a .vtu back (vtu::read_vtu; tests/vtu_meshio_e2e.rs reads it with meshio).

struct Vtu {
    points: Vec<[f64; 3]>,
    cells: Vec<Vec<usize>>,
    types: Vec<u8>,
    /// name -> (components, values)
    point: HashMap<String, (usize, Vec<f64>)>,
    cell: HashMap<String, (usize, Vec<f64>)>,
}

impl Vtu {
    fn read(path: &Path) -> Vtu {
        let file = read_vtu(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
        let values = |parent: &str, name: &str| -> Vec<f64> {
            file.array(parent, name)
                .unwrap_or_else(|| panic!("no {parent} {name}"))
                .values()
                .unwrap()
        };
        let xyz = values("Points", "Points");
        let points: Vec<[f64; 3]> = xyz.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        assert_eq!(points.len(), file.n_points);
        let connectivity = values("Cells", "connectivity");
        let offsets = values("Cells", "offsets");
        assert_eq!(offsets.len(), file.n_cells);
        let mut cells = Vec::new();
        let mut start = 0usize;
        for &end in &offsets {
            cells.push(
                connectivity[start..end as usize]
                    .iter()
                    .map(|&v| v as usize)
                    .collect(),
            );
            start = end as usize;
        }
        let types = values("Cells", "types").iter().map(|&t| t as u8).collect();
        let arrays = |parent: &str| -> HashMap<String, (usize, Vec<f64>)> {
            file.arrays
                .iter()
                .filter(|a| a.parent == parent)
                .map(|a| (a.name.clone(), (a.components, a.values().unwrap())))
                .collect()
        };
        Vtu {
            points,
            cells,
            types,
            point: arrays("PointData"),
            cell: arrays("CellData"),
        }
    }

    fn point_array(&self, name: &str, k: usize) -> &[f64] {
        let (c, v) = self
            .point
            .get(name)
            .unwrap_or_else(|| panic!("no point array {name}"));
        assert_eq!(*c, k, "{name} components");
        assert_eq!(v.len(), k * self.points.len(), "{name} length");
        v
    }

    fn cell_array(&self, name: &str, k: usize) -> &[f64] {
        let (c, v) = self
            .cell
            .get(name)
            .unwrap_or_else(|| panic!("no cell array {name}"));
        assert_eq!(*c, k, "{name} components");
        assert_eq!(v.len(), k * self.cells.len(), "{name} length");
        v
    }

    fn no_nan(&self) {
        for (name, (_, v)) in self.point.iter().chain(&self.cell) {
            assert!(v.iter().all(|x| x.is_finite()), "{name} has a non-finite value");
        }
        assert!(self.points.iter().flatten().all(|x| x.is_finite()));
    }

    fn count(&self, t: u8) -> usize {
        self.types.iter().filter(|&&x| x == t).count()
    }
}

// ---------------------------------------------------------------------------
// VTK reference cells, from VTK 9's own tables (parametric coordinates and
// the faces of vtkCell::GetFace, outward normals, of vtkHexahedron,
// vtkQuadraticHexahedron, vtkTriQuadraticHexahedron, vtkWedge,
// vtkQuadraticWedge), with shape functions built from a monomial basis.

/// Lagrange shape functions through `nodes` in the span of `exps`.
struct Shape<const D: usize> {
    exps: Vec<[i32; D]>,
    /// `coef[i][j]`: shape function i = sum_j coef[i][j] monomial_j.
    coef: Vec<Vec<f64>>,
}

impl<const D: usize> Shape<D> {
    fn new(nodes: &[[f64; D]], exps: Vec<[i32; D]>) -> Self {
        let n = nodes.len();
        assert_eq!(exps.len(), n);
        // Solve V^T A^T = I, V[k][j] = m_j(x_k): A = (V^T)^-1, by Gauss-Jordan.
        let mono = |x: &[f64; D], e: &[i32; D]| (0..D).map(|d| x[d].powi(e[d])).product::<f64>();
        let mut m: Vec<Vec<f64>> = (0..n)
            .map(|j| {
                let mut row: Vec<f64> = (0..n).map(|k| mono(&nodes[k], &exps[j])).collect();
                row.extend((0..n).map(|i| if i == j { 1.0 } else { 0.0 }));
                row
            })
            .collect();
        for c in 0..n {
            let p = (c..n)
                .max_by(|&a, &b| m[a][c].abs().total_cmp(&m[b][c].abs()))
                .unwrap();
            m.swap(c, p);
            let d = m[c][c];
            assert!(d.abs() > 1e-12, "singular basis");
            for v in m[c].iter_mut() {
                *v /= d;
            }
            let pivot = m[c].clone();
            for (r, row) in m.iter_mut().enumerate() {
                let f = row[c];
                if r != c && f != 0.0 {
                    for (x, p) in row.iter_mut().zip(&pivot) {
                        *x -= f * p;
                    }
                }
            }
        }
        // m = [I | (V^T)^-1], and A = (V^T)^-1.
        let coef = m.iter().map(|row| row[n..].to_vec()).collect();
        Shape { exps, coef }
    }

    /// Position and tangent vectors `dx/du_d` at `u`.
    fn map(&self, x: &[[f64; 3]], u: [f64; D]) -> ([f64; 3], [[f64; 3]; D]) {
        let (mut p, mut t) = ([0.0; 3], [[0.0; 3]; D]);
        for (i, xi) in x.iter().enumerate() {
            let (mut n, mut dn) = (0.0, [0.0; D]);
            for (e, c) in self.exps.iter().zip(&self.coef[i]) {
                n += c * (0..D).map(|d| u[d].powi(e[d])).product::<f64>();
                for (dd, dnd) in dn.iter_mut().enumerate() {
                    if e[dd] > 0 {
                        *dnd += c
                            * f64::from(e[dd])
                            * (0..D)
                                .map(|d| {
                                    if d == dd {
                                        u[d].powi(e[d] - 1)
                                    } else {
                                        u[d].powi(e[d])
                                    }
                                })
                                .product::<f64>();
                    }
                }
            }
            for a in 0..3 {
                p[a] += n * xi[a];
                for d in 0..D {
                    t[d][a] += dn[d] * xi[a];
                }
            }
        }
        (p, t)
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Gauss-Legendre points and weights on [0, 1].
fn gauss01(n: usize) -> Vec<(f64, f64)> {
    let (x, w): (&[f64], &[f64]) = match n {
        5 => (
            &[
                -0.906_179_845_938_664,
                -0.538_469_310_105_683,
                0.0,
                0.538_469_310_105_683,
                0.906_179_845_938_664,
            ],
            &[
                0.236_926_885_056_189,
                0.478_628_670_499_366,
                0.568_888_888_888_889,
                0.478_628_670_499_366,
                0.236_926_885_056_189,
            ],
        ),
        _ => unreachable!(),
    };
    x.iter().zip(w).map(|(x, w)| (0.5 * (x + 1.0), 0.5 * w)).collect()
}

/// Points and weights on the reference square [0,1]^2 or triangle
/// (collapsed square).
fn rule2(triangle: bool) -> Vec<([f64; 2], f64)> {
    let g = gauss01(5);
    let mut out = vec![];
    for &(a, wa) in &g {
        for &(b, wb) in &g {
            if triangle {
                out.push(([a * (1.0 - b), b], wa * wb * (1.0 - b)));
            } else {
                out.push(([a, b], wa * wb));
            }
        }
    }
    out
}

fn tri_exps(order: i32) -> Vec<[i32; 2]> {
    let mut v = vec![];
    for s in 0..=order {
        for a in 0..=s {
            v.push([a, s - a]);
        }
    }
    v
}

/// A VTK face: reference coordinates of its nodes and the basis.
fn face_shape(n: usize) -> (Shape<2>, bool) {
    const Q: [[f64; 2]; 9] = [
        [0.0, 0.0],
        [1.0, 0.0],
        [1.0, 1.0],
        [0.0, 1.0],
        [0.5, 0.0],
        [1.0, 0.5],
        [0.5, 1.0],
        [0.0, 0.5],
        [0.5, 0.5],
    ];
    const T: [[f64; 2]; 6] = [
        [0.0, 0.0],
        [1.0, 0.0],
        [0.0, 1.0],
        [0.5, 0.0],
        [0.5, 0.5],
        [0.0, 0.5],
    ];
    match n {
        3 => (Shape::new(&T[..3], tri_exps(1)), true),
        6 => (Shape::new(&T, tri_exps(2)), true),
        4 => (Shape::new(&Q[..4], vec![[0, 0], [1, 0], [0, 1], [1, 1]]), false),
        8 => (
            Shape::new(
                &Q[..8],
                vec![[0, 0], [1, 0], [0, 1], [2, 0], [1, 1], [0, 2], [2, 1], [1, 2]],
            ),
            false,
        ),
        9 => (
            Shape::new(&Q, (0..3).flat_map(|a| (0..3).map(move |b| [a, b])).collect()),
            false,
        ),
        _ => unreachable!(),
    }
}

/// VTK's face tables (outward normals).
fn vtk_faces(t: u8) -> Vec<Vec<usize>> {
    let v = |f: &[&[usize]]| f.iter().map(|x| x.to_vec()).collect();
    match t {
        13 => v(&[
            &[0, 2, 1],
            &[3, 4, 5],
            &[0, 1, 4, 3],
            &[1, 2, 5, 4],
            &[2, 0, 3, 5],
        ]),
        26 => v(&[
            &[0, 2, 1, 8, 7, 6],
            &[3, 4, 5, 9, 10, 11],
            &[0, 1, 4, 3, 6, 13, 9, 12],
            &[1, 2, 5, 4, 7, 14, 10, 13],
            &[2, 0, 3, 5, 8, 12, 11, 14],
        ]),
        12 => v(&[
            &[0, 4, 7, 3],
            &[1, 2, 6, 5],
            &[0, 1, 5, 4],
            &[3, 7, 6, 2],
            &[0, 3, 2, 1],
            &[4, 5, 6, 7],
        ]),
        25 | 29 => {
            let mut f: Vec<Vec<usize>> = v(&[
                &[0, 4, 7, 3, 16, 15, 19, 11],
                &[1, 2, 6, 5, 9, 18, 13, 17],
                &[0, 1, 5, 4, 8, 17, 12, 16],
                &[3, 7, 6, 2, 19, 14, 18, 10],
                &[0, 3, 2, 1, 11, 10, 9, 8],
                &[4, 5, 6, 7, 12, 13, 14, 15],
            ]);
            if t == 29 {
                for (i, face) in f.iter_mut().enumerate() {
                    face.push(20 + i);
                }
            }
            f
        }
        _ => unreachable!("type {t}"),
    }
}

/// The cell's volume by the divergence theorem over VTK's outward faces:
/// V = 1/3 sum over faces of Integral(x . n dA).
fn face_volume(t: u8, x: &[[f64; 3]]) -> f64 {
    let mut v = 0.0;
    for face in vtk_faces(t) {
        let (shape, tri) = face_shape(face.len());
        let fx: Vec<[f64; 3]> = face.iter().map(|&i| x[i]).collect();
        for (u, w) in rule2(tri) {
            let (p, [a, b]) = shape.map(&fx, u);
            v += w * dot(p, cross(a, b)) / 3.0;
        }
    }
    v
}

/// The cell's volume as Integral(det J) of VTK's parametric map (VTK's
/// parametric coordinates of vtkHexahedron & co., vtkWedge & co.).
fn parametric_volume(t: u8, x: &[[f64; 3]]) -> f64 {
    const H: [[f64; 3]; 27] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
        [0.5, 0.0, 0.0],
        [1.0, 0.5, 0.0],
        [0.5, 1.0, 0.0],
        [0.0, 0.5, 0.0],
        [0.5, 0.0, 1.0],
        [1.0, 0.5, 1.0],
        [0.5, 1.0, 1.0],
        [0.0, 0.5, 1.0],
        [0.0, 0.0, 0.5],
        [1.0, 0.0, 0.5],
        [1.0, 1.0, 0.5],
        [0.0, 1.0, 0.5],
        [0.0, 0.5, 0.5],
        [1.0, 0.5, 0.5],
        [0.5, 0.0, 0.5],
        [0.5, 1.0, 0.5],
        [0.5, 0.5, 0.0],
        [0.5, 0.5, 1.0],
        [0.5, 0.5, 0.5],
    ];
    const W: [[f64; 3]; 15] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
        [0.5, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.0, 0.5, 0.0],
        [0.5, 0.0, 1.0],
        [0.5, 0.5, 1.0],
        [0.0, 0.5, 1.0],
        [0.0, 0.0, 0.5],
        [1.0, 0.0, 0.5],
        [0.0, 1.0, 0.5],
    ];
    let tensor = |p: i32| -> Vec<[i32; 3]> {
        (0..=p)
            .flat_map(|a| (0..=p).flat_map(move |b| (0..=p).map(move |c| [a, b, c])))
            .collect()
    };
    let (shape, wedge) = match t {
        12 => (Shape::new(&H[..8], tensor(1)), false),
        29 => (Shape::new(&H, tensor(2)), false),
        25 => (Shape::new(&H[..20], serendipity()), false),
        13 => {
            let e: Vec<[i32; 3]> = tri_exps(1)
                .into_iter()
                .flat_map(|[a, b]| [[a, b, 0], [a, b, 1]])
                .collect();
            (Shape::new(&W[..6], e), true)
        }
        26 => {
            let mut e: Vec<[i32; 3]> = tri_exps(2)
                .into_iter()
                .flat_map(|[a, b]| [[a, b, 0], [a, b, 1]])
                .collect();
            e.extend(tri_exps(1).into_iter().map(|[a, b]| [a, b, 2]));
            (Shape::new(&W, e), true)
        }
        _ => unreachable!(),
    };
    let g = gauss01(5);
    let mut v = 0.0;
    for (uv, w2) in rule2(wedge) {
        for &(c, wc) in &g {
            let (_, [a, b, d]) = shape.map(x, [uv[0], uv[1], c]);
            v += w2 * wc * dot(a, cross(b, d));
        }
    }
    v
}

/// The 20 monomials of the serendipity hexahedron: 1, x, y, z, the squares,
/// the products of two, the squares times another coordinate, xyz, and
/// xyz times one more coordinate.
fn serendipity() -> Vec<[i32; 3]> {
    vec![
        [0, 0, 0],
        [1, 0, 0],
        [0, 1, 0],
        [0, 0, 1],
        [2, 0, 0],
        [0, 2, 0],
        [0, 0, 2],
        [1, 1, 0],
        [0, 1, 1],
        [1, 0, 1],
        [2, 1, 0],
        [2, 0, 1],
        [1, 2, 0],
        [0, 2, 1],
        [1, 0, 2],
        [0, 1, 2],
        [1, 1, 1],
        [2, 1, 1],
        [1, 2, 1],
        [1, 1, 2],
    ]
}

// ---------------------------------------------------------------------------
// Pure bending of a solid cylinder.

const E: f64 = 2.0e4;
const NU: f64 = 0.17;
const S: f64 = 1.0;
const A: f64 = 0.5;
const L: f64 = 2.0;

/// Harmonic-1 amplitudes `(u, v, w)` of the exact bending field.
fn bending_amplitudes(r: f64, z: f64) -> [f64; 3] {
    [
        -S / (2.0 * E) * (z * z + NU * r * r),
        S * r * z / E,
        S / (2.0 * E) * (z * z - NU * r * r),
    ]
}

/// Exact Cartesian displacement.
fn bending_xyz(x: f64, y: f64, z: f64) -> [f64; 3] {
    [
        -S / (2.0 * E) * (z * z + NU * (x * x - y * y)),
        -S * NU * x * y / E,
        S * x * z / E,
    ]
}

fn bending_field(mesh: &Mesh) -> Displacements {
    let n = mesh.nodes.len();
    let mut sym = vec![0.0; 3 * n];
    for (i, p) in mesh.nodes.iter().enumerate() {
        sym[3 * i..3 * i + 3].copy_from_slice(&bending_amplitudes(p[0], p[1]));
    }
    Displacements {
        harmonics: vec![
            HarmonicDisplacement {
                m: 0,
                symmetric: vec![0.0; 3 * n],
                antisymmetric: vec![0.0; 3 * n],
            },
            HarmonicDisplacement {
                m: 1,
                symmetric: sym,
                antisymmetric: vec![0.0; 3 * n],
            },
        ],
    }
}

fn cylinder(order: f64, quads: f64, serendipity: f64) -> Mesh {
    let params: Vec<(String, f64)> = [
        ("a", A),
        ("L", L),
        ("size", 0.25),
        ("order", order),
        ("quads", quads),
        ("serendipity", serendipity),
    ]
    .iter()
    .map(|(k, v)| (k.to_string(), *v))
    .collect();
    prepare(&geo("cylinder.geo"), &params, &[], None)
        .expect("gmsh meshes the cylinder")
        .0
}

/// Angular factor of the revolved volume: Integral |w x w'| dt over one slot,
/// w(t) the linear or quadratic interpolation of the unit circle.
fn slot_factor(n: usize, quadratic: bool) -> f64 {
    let d = 2.0 * PI / n as f64;
    if !quadratic {
        return d.sin();
    }
    let p = |a: f64| [a.cos(), a.sin()];
    let (p0, pm, p1) = (p(0.0), p(0.5 * d), p(d));
    gauss01(5)
        .iter()
        .map(|&(t, w)| {
            let l = [
                2.0 * (t - 0.5) * (t - 1.0),
                -4.0 * t * (t - 1.0),
                2.0 * t * (t - 0.5),
            ];
            let dl = [4.0 * t - 3.0, -8.0 * t + 4.0, 4.0 * t - 1.0];
            let x = [0, 1].map(|k| l[0] * p0[k] + l[1] * pm[k] + l[2] * p1[k]);
            let dx = [0, 1].map(|k| dl[0] * p0[k] + dl[1] * pm[k] + dl[2] * p1[k]);
            w * (x[0] * dx[1] - x[1] * dx[0])
        })
        .sum()
}

#[test]
fn bending_cylinder_vtu() {
    let dir = tempfile::tempdir().unwrap();
    let n = 12;
    let cases = [
        (1.0, 0.0, 0.0, CellKind::Tri3, 13u8),
        (1.0, 1.0, 0.0, CellKind::Quad4, 12),
        (2.0, 0.0, 0.0, CellKind::Tri6, 26),
        (2.0, 1.0, 1.0, CellKind::Quad8, 25),
        (2.0, 1.0, 0.0, CellKind::Quad9, 29),
    ];
    for (order, quads, ser, kind, vtk_type) in cases {
        let mesh = cylinder(order, quads, ser);
        assert!(
            mesh.cells.iter().all(|c| c.kind == kind),
            "{kind:?} mesh expected"
        );
        let u = bending_field(&mesh);
        let materials = vec![Elastic { e: E, nu: NU }];
        let field = Field {
            mesh: &mesh,
            materials: &materials,
            u: &u,
            initial: None,
        };
        let path = dir.path().join(format!("bending_{}.vtu", kind.name()));
        write_vtu(&path, &field, n, &ALL, None).unwrap();
        assert!(!joints_path(&path).exists(), "no joint file without joints");
        let vtu = Vtu::read(&path);
        vtu.no_nan();

        // Counts: n rings of every node, plus n mid-angle rings of the
        // corners (T6, Q8) or of every node (Q9).
        let corners: std::collections::BTreeSet<usize> = mesh
            .cells
            .iter()
            .flat_map(|c| c.nodes[..c.kind.n_corners()].iter().copied())
            .collect();
        let mids = match kind {
            CellKind::Tri3 | CellKind::Quad4 => 0,
            CellKind::Tri6 | CellKind::Quad8 => corners.len(),
            CellKind::Quad9 => mesh.nodes.len(),
        };
        assert_eq!(vtu.points.len(), n * (mesh.nodes.len() + mids), "{kind:?} points");
        assert_eq!(vtu.cells.len(), n * mesh.cells.len(), "{kind:?} cells");
        assert_eq!(
            vtu.count(vtk_type),
            vtu.cells.len(),
            "{kind:?}: all cells of VTK type {vtk_type}"
        );
        let nn = [6, 8, 15, 20, 27][[13, 12, 26, 25, 29].iter().position(|&t| t == vtk_type).unwrap()];
        assert!(vtu.cells.iter().all(|c| c.len() == nn));
        assert!(vtu.cell_array("body", 1).iter().all(|&b| b == 0.0));

        // Displacement: the closed form at every point.
        let disp = vtu.point_array("displacement", 3);
        let scale = S * L * L / E;
        let mut worst_u = 0.0f64;
        for (p, u) in vtu.points.iter().zip(disp.chunks(3)) {
            let exact = bending_xyz(p[0], p[1], p[2]);
            for k in 0..3 {
                worst_u = worst_u.max((u[k] - exact[k]).abs() / scale);
            }
        }
        assert!(worst_u < 1e-12, "{kind:?}: displacement error {worst_u:e}");
        // Points on the true circle (including the mid-angle rings).
        for p in &vtu.points {
            let r = p[0].hypot(p[1]);
            assert!(r <= A * (1.0 + 1e-12) && p[2] >= -1e-12 && p[2] <= L + 1e-12);
        }

        // Stress: sigma_zz = s x, all else 0. T6 and Q9 reproduce the
        // quadratic field exactly; the serendipity Q8 only on parallelograms
        // (gmsh's recombined quads are not all), so it gets a loose bound.
        let stress = vtu.point_array("stress", 9);
        let cyl = vtu.point_array("sigma_cyl", 6);
        if kind.is_quadratic() {
            let mut worst = 0.0f64;
            for (i, p) in vtu.points.iter().enumerate() {
                let t = &stress[9 * i..9 * i + 9];
                for (k, &v) in t.iter().enumerate() {
                    let exact = if k == 8 { S * p[0] } else { 0.0 };
                    worst = worst.max((v - exact).abs() / (S * A));
                }
                let theta = p[1].atan2(p[0]);
                let r = p[0].hypot(p[1]);
                worst = worst.max((cyl[6 * i + 1] - S * r * theta.cos()).abs() / (S * A));
            }
            let tol = if kind == CellKind::Quad8 { 0.1 } else { 1e-8 };
            assert!(worst < tol, "{kind:?}: stress error {worst:e}");
            println!("{}: max stress error / (s a) {worst:.1e}", kind.name());
        }
        // Tensor symmetric, and its invariants those of sigma_cyl.
        for i in 0..vtu.points.len() {
            let t = &stress[9 * i..9 * i + 9];
            assert_eq!(t[1], t[3]);
            assert_eq!(t[2], t[6]);
            assert_eq!(t[5], t[7]);
            let c = &cyl[6 * i..6 * i + 6];
            let trace = t[0] + t[4] + t[8] - (c[0] + c[1] + c[2]);
            assert!(trace.abs() <= 1e-9 * (S * A));
        }

        // Volumes from VTK's node order: by VTK's outward faces, and by VTK's
        // parametric map; both positive and equal.
        let (mut total, mut min_v) = (0.0, f64::INFINITY);
        for c in &vtu.cells {
            let x: Vec<[f64; 3]> = c.iter().map(|&i| vtu.points[i]).collect();
            let v = face_volume(vtk_type, &x);
            let pv = parametric_volume(vtk_type, &x);
            assert!(
                (pv - v).abs() <= 1e-9 * v.abs().max(1e-9),
                "{kind:?}: {pv} vs {v}"
            );
            min_v = min_v.min(v).min(pv);
            total += v;
        }
        assert!(min_v > 0.0, "{kind:?}: a cell volume {min_v:e} <= 0");
        // Exactly n * slot factor * Integral(r dA) = n f a^2 L / 2 ...
        let expected = n as f64 * slot_factor(n, kind.is_quadratic()) * A * A * L / 2.0;
        assert!(
            (total - expected).abs() <= 1e-10 * expected,
            "{kind:?}: volume {total} vs {expected}"
        );
        // ... which is pi a^2 L within the chordal error of n sections.
        let exact = PI * A * A * L;
        let chordal = (total - exact).abs() / exact;
        let bound = if kind.is_quadratic() {
            2e-4
        } else {
            (2.0 * PI / n as f64).powi(2) / 6.0
        };
        assert!(
            chordal <= bound,
            "{kind:?}: chordal error {chordal:e} > {bound:e}"
        );
        println!(
            "{}: {} points, {} cells, volume {total:.9} (pi a^2 L = {exact:.9}, chordal error {chordal:.2e}), max displacement error {worst_u:.1e}",
            kind.name(),
            vtu.points.len(),
            vtu.cells.len()
        );
    }
}

#[test]
fn non_finite_values_leave_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = cylinder(2.0, 1.0, 0.0);
    let mut u = bending_field(&mesh);
    u.harmonics[1].symmetric[7] = f64::NAN;
    let materials = vec![Elastic { e: E, nu: NU }];
    let field = Field {
        mesh: &mesh,
        materials: &materials,
        u: &u,
        initial: None,
    };
    let vtu = dir.path().join("bad.vtu");
    let msh = dir.path().join("bad.msh");
    assert!(matches!(
        write_vtu(&vtu, &field, 8, &ALL, None),
        Err(ReportError::NotFinite { .. })
    ));
    assert!(matches!(
        write_gmsh_view(&msh, &field, &[0.0]),
        Err(ReportError::NotFinite { .. })
    ));
    assert!(matches!(
        write_vtu(&vtu, &field, 2, &ALL, None),
        Err(ReportError::Input(_))
    ));
    match write_vtu(&vtu, &field, 8, &["sigma_zz"], None) {
        Err(ReportError::Input(m)) => assert!(m.contains("unknown array 'sigma_zz'"), "{m}"),
        other => panic!("unknown array accepted: {other:?}"),
    }
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(left.is_empty(), "files left behind: {left:?}");
}

// ---------------------------------------------------------------------------
// Scene P through the real pipeline.

/// Runs gmsh headless on `args`; asserts exit 0 and no `Error` line, and
/// returns the output; `None` (with a printed reason) when gmsh is absent.
fn run_gmsh(args: &[&std::ffi::OsStr]) -> Option<String> {
    let gmsh = std::env::var("GMSH").unwrap_or_else(|_| "gmsh".into());
    let out = match Command::new(&gmsh).args(args).output() {
        Ok(o) => o,
        Err(e) => {
            println!("SKIP gmsh check: cannot run '{gmsh}': {e}");
            return None;
        }
    };
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "gmsh {args:?} failed:\n{text}");
    assert!(
        !text.lines().any(|l| l.contains("Error")),
        "gmsh {args:?} reported errors:\n{text}"
    );
    Some(text)
}

/// Opens `msh` in gmsh (directly, then merged by a script that prints every
/// view's range): `(min, max)` per view, in file order.
fn gmsh_views(msh: &Path) -> Option<Vec<(f64, f64)>> {
    run_gmsh(&[msh.as_os_str(), "-parse_and_exit".as_ref()])?;
    let script = msh.with_extension("check.geo");
    std::fs::write(
        &script,
        format!(
            "Merge \"{}\";\nPrintf(\"views = %g\", PostProcessing.NbViews);\n\
             For i In {{0:PostProcessing.NbViews-1}}\n  \
             Printf(\"range %.12g %.12g\", View[i].Min, View[i].Max);\nEndFor\n",
            msh.display()
        ),
    )
    .unwrap();
    let text = run_gmsh(&[script.as_os_str(), "-parse_and_exit".as_ref()])?;
    let count: usize = text
        .lines()
        .find_map(|l| l.strip_prefix("views = "))
        .expect("gmsh printed the view count")
        .trim()
        .parse()
        .unwrap();
    let ranges: Vec<(f64, f64)> = text
        .lines()
        .filter_map(|l| l.strip_prefix("range "))
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            (v[0], v[1])
        })
        .collect();
    assert_eq!(ranges.len(), count);
    Some(ranges)
}

#[test]
fn scene_p_views() {
    let mut scene = Scene::from_path(geo("pile_footing.json")).unwrap();
    scene.mesh.parameters.insert("size".into(), 0.5);
    let run = solve_scene(&scene, None, |_| {}).expect("Scene P solves");
    let outcome = run.outcome.as_ref().expect("Scene P iterates");
    let model = &run.problem.model;
    let mesh = &model.mesh;
    let springs: Vec<_> = model.joints.iter().map(|j| j.springs).collect();
    let jf = JointFieldFile::new(mesh, &springs, &outcome.field);
    let field = Field {
        mesh,
        materials: &model.materials,
        u: &run.displacements,
        initial: None,
    };
    let dir = tempfile::tempdir().unwrap();

    // --- VTU with the joint file.
    let n = 16;
    let path = dir.path().join("scene_p.vtu");
    write_vtu(&path, &field, n, &ALL, Some(&jf)).unwrap();
    let vtu = Vtu::read(&path);
    vtu.no_nan();
    // Points per body, not shared between bodies.
    let mut expected_points = 0;
    for b in 0..mesh.bodies.len() {
        let mut nodes = std::collections::BTreeSet::new();
        let mut mids = std::collections::BTreeSet::new();
        for c in mesh.cells.iter().filter(|c| c.body == b) {
            nodes.extend(c.nodes.iter().copied());
            match c.kind {
                CellKind::Quad9 => mids.extend(c.nodes.iter().copied()),
                CellKind::Tri6 | CellKind::Quad8 => {
                    mids.extend(c.nodes[..c.kind.n_corners()].iter().copied())
                }
                _ => {}
            }
        }
        expected_points += n * (nodes.len() + mids.len());
    }
    assert_eq!(vtu.points.len(), expected_points);
    assert_eq!(vtu.cells.len(), n * mesh.cells.len());
    let bodies = vtu.cell_array("body", 1);
    for b in 0..mesh.bodies.len() {
        let count = bodies.iter().filter(|&&x| x == b as f64).count();
        assert_eq!(count, n * mesh.cells.iter().filter(|c| c.body == b).count());
    }
    // The displacement at each point is the field's own.
    let disp = vtu.point_array("displacement", 3);
    let umax = disp.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    assert!(umax > 0.0);
    let pile = mesh.body("pile").unwrap();
    let footing = mesh.body("footing").unwrap();
    // The stress jump across the joint survives: points of the pile and of
    // the footing at r = a, z = 0.75, theta = pi (the open side).
    let a = 0.5;
    let body_of_point = {
        let mut v = vec![usize::MAX; vtu.points.len()];
        for (c, cell) in vtu.cells.iter().enumerate() {
            for &p in cell {
                v[p] = bodies[c] as usize;
            }
        }
        v
    };
    let cyl = vtu.point_array("sigma_cyl", 6);
    let near = |p: &[f64; 3], r: f64, z: f64, th: f64| {
        (p[0] - r * th.cos()).abs() < 1e-9 && (p[1] - r * th.sin()).abs() < 1e-9 && (p[2] - z).abs() < 1e-9
    };
    let z_cut = mesh
        .nodes
        .iter()
        .filter(|q| (q[0] - a).abs() < 1e-12 && q[1] > 0.4 && q[1] < 1.0)
        .map(|q| q[1])
        .fold(f64::NAN, f64::max);
    assert!(z_cut.is_finite(), "a node on the pile side");
    let at = |b: usize| {
        (0..vtu.points.len())
            .find(|&i| body_of_point[i] == b && near(&vtu.points[i], a, z_cut, PI))
            .unwrap_or_else(|| panic!("no point of body {b} at r = a, z = {z_cut}, theta = pi"))
    };
    let (ip, if_) = (at(pile), at(footing));
    let (sz_pile, sz_footing) = (cyl[6 * ip + 1], cyl[6 * if_ + 1]);
    println!("Scene P at r = a, z = {z_cut}, theta = pi: sigma_z pile {sz_pile:.4}, footing {sz_footing:.4}");
    assert!(
        (sz_pile - sz_footing).abs() > 1e-3 * sz_pile.abs().max(sz_footing.abs()),
        "the jump at the joint is kept"
    );
    // The footing's displacement there differs from the pile's (open joint).
    let gap: f64 = (0..3)
        .map(|k| (disp[3 * ip + k] - disp[3 * if_ + k]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(gap > 0.0);

    // Only the arrays asked for, in the order of Outputs::VTU_FIELDS, the
    // same values; "auto" gives these 16 sections for M = 4 and Q9 cells.
    assert_eq!(auto_sections(mesh, 4), n);
    let some = dir.path().join("some.vtu");
    write_vtu(&some, &field, n, &["von_mises", "displacement"], None).unwrap();
    let file = read_vtu(&some).unwrap();
    let names: Vec<&str> = file
        .arrays
        .iter()
        .filter(|a| a.parent == "PointData")
        .map(|a| a.name.as_str())
        .collect();
    assert_eq!(names, ["displacement", "von_mises"]);
    let values = |name: &str| file.array("PointData", name).unwrap().values().unwrap();
    assert_eq!(values("displacement"), disp);
    assert_eq!(values("von_mises"), vtu.point_array("von_mises", 1));

    // The joint file.
    let jpath = joints_path(&path);
    let j = Vtu::read(&jpath);
    j.no_nan();
    let n_el: usize = mesh.joints.iter().map(|j| j.elements.len()).sum();
    assert_eq!(j.cells.len(), n * n_el);
    let quadratic = mesh.joints[0].elements[0].kind == axijoint_mesh::JointKind::Lin6;
    assert_eq!(j.count(if quadratic { 28 } else { 9 }), j.cells.len());
    let state = j.cell_array("state", 1);
    assert!(state.iter().all(|s| [0.0, 1.0, 2.0].contains(s)));
    let counts = [0.0, 1.0, 2.0].map(|s| state.iter().filter(|&&x| x == s).count());
    println!(
        "Scene P joint cells: {counts:?} (stick, slip, open) of {}",
        state.len()
    );
    assert!(counts[2] > 0, "the joint opens somewhere (theta = pi side)");
    assert!(counts[0] + counts[1] > 0, "and is closed somewhere");
    let opening = j.cell_array("opening", 1);
    let sigma = j.cell_array("sigma_n", 1);
    for (c, &s) in state.iter().enumerate() {
        if s == 2.0 && j.cell_array("open_fraction", 1)[c] == 1.0 {
            assert!(
                opening[c] > 0.0 && sigma[c] == 0.0,
                "an open cell opens and carries nothing"
            );
        }
    }
    // Sections: the nearest of 0, 45, ..., 180 to the slot's mid angle
    // folded into [0, pi]; mirrored slots carry the same state and normal
    // traction, and the opposite circumferential shear.
    let sec = j.cell_array("section_deg", 1);
    let tau_t = j.cell_array("tau_theta", 1);
    for e in 0..n_el {
        for k in 0..n {
            let c = e * n + k;
            let mid = (k as f64 + 0.5) * 360.0 / n as f64;
            let folded = if mid > 180.0 { 360.0 - mid } else { mid };
            let want = jf
                .sections_deg
                .iter()
                .copied()
                .min_by(|a, b| (a - folded).abs().total_cmp(&(b - folded).abs()))
                .unwrap();
            assert_eq!(sec[c], want, "slot {k}: section");
            let m = e * n + (n - 1 - k);
            assert_eq!(state[c], state[m]);
            assert_eq!(sigma[c], sigma[m]);
            assert_eq!(tau_t[c], -tau_t[m]);
        }
    }
    // Joint cells sit on the pile side r = a, 0 <= z <= 1.
    for p in &j.points {
        assert!((p[0].hypot(p[1]) - a).abs() < 1e-9 && p[2] > -1e-9 && p[2] < 1.0 + 1e-9);
    }

    // --- gmsh view.
    let msh = dir.path().join("scene_p_view.msh");
    let thetas = [0.0, 180.0];
    write_gmsh_view(&msh, &field, &thetas).unwrap();
    let text = std::fs::read_to_string(&msh).unwrap();
    let views = text.matches("$NodeData").count() + text.matches("$ElementNodeData").count();
    assert_eq!(views, thetas.len() * 7);
    assert!(text.contains(&format!("\"{}\"", view_name("sigma_z", 180.0))));
    // Element-node stress: the pile's and the footing's values at a joint
    // node pair differ (nothing averaged across the joint).
    let sz = element_node_values(&text, &view_name("sigma_z", 180.0));
    let pair = &mesh.joints[0].duplicated;
    let mut differs = 0;
    for &(orig, copy) in pair {
        let side = |node: usize| -> Vec<f64> {
            mesh.cells
                .iter()
                .enumerate()
                .flat_map(|(c, cell)| {
                    cell.nodes
                        .iter()
                        .position(|&x| x == node)
                        .map(|i| sz[&(c + 1)][i])
                })
                .collect()
        };
        let (a_side, b_side) = (side(orig), side(copy));
        assert!(!a_side.is_empty() && !b_side.is_empty());
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        if (mean(&a_side) - mean(&b_side)).abs() > 1e-6 {
            differs += 1;
        }
    }
    assert!(differs > 0, "sigma_z jumps across the joint in the gmsh view");
    // gmsh opens it: 7 views per theta, in file order (displacement, then
    // the six stress components), each with the range of the data written.
    if let Some(ranges) = gmsh_views(&msh) {
        assert_eq!(ranges.len(), 7 * thetas.len(), "views gmsh loaded");
        for (step, &deg) in thetas.iter().enumerate() {
            for (q, name) in ["sigma_r", "sigma_z", "sigma_theta", "tau_rz"].iter().enumerate() {
                let values = element_node_values(&text, &view_name(name, deg));
                let all = values.values().flatten();
                let (lo, hi) = all.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                });
                let (glo, ghi) = ranges[7 * step + 1 + q];
                let tol = 1e-9 * (hi - lo).abs().max(1e-12);
                assert!(
                    (glo - lo).abs() <= tol && (ghi - hi).abs() <= tol,
                    "{name} at {deg}: gmsh {glo}..{ghi}, file {lo}..{hi}"
                );
            }
        }
        println!(
            "gmsh loaded {} views; sigma_z at 180 deg spans {:?}",
            ranges.len(),
            ranges[9]
        );
    }
}

/// `$ElementNodeData` values of one view: element id -> values.
fn element_node_values(text: &str, name: &str) -> HashMap<usize, Vec<f64>> {
    let head = format!("$ElementNodeData\n1\n\"{name}\"\n");
    let start = text.find(&head).expect("view present") + head.len();
    let mut lines = text[start..].lines();
    // real tags (1, time), integer tags (3: step, components, count)
    let _ = (
        lines.next(),
        lines.next(),
        lines.next(),
        lines.next(),
        lines.next(),
    );
    let count: usize = lines.next().unwrap().trim().parse().unwrap();
    (0..count)
        .map(|_| {
            let v: Vec<f64> = lines
                .next()
                .unwrap()
                .split_whitespace()
                .map(|x| x.parse().unwrap())
                .collect();
            let id = v[0] as usize;
            assert_eq!(v[1] as usize, v.len() - 2);
            (id, v[2..].to_vec())
        })
        .collect()
}

/// Scene P with linear elements (order 1, triangles): 4-node joints become
/// VTK quads, T3 cells wedges; joint states still in {0, 1, 2}.
#[test]
fn scene_p_linear_joint_quads() {
    let mut scene = Scene::from_path(geo("pile_footing.json")).unwrap();
    for (k, v) in [("size", 0.5), ("order", 1.0), ("quads", 0.0)] {
        scene.mesh.parameters.insert(k.into(), v);
    }
    let run = solve_scene(&scene, None, |_| {}).expect("Scene P solves");
    let outcome = run.outcome.as_ref().expect("Scene P iterates");
    let model = &run.problem.model;
    let mesh = &model.mesh;
    assert!(mesh.cells.iter().all(|c| c.kind == CellKind::Tri3));
    let springs: Vec<_> = model.joints.iter().map(|j| j.springs).collect();
    let jf = JointFieldFile::new(mesh, &springs, &outcome.field);
    let field = Field {
        mesh,
        materials: &model.materials,
        u: &run.displacements,
        initial: None,
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p1.vtu");
    let n = 8;
    write_vtu(&path, &field, n, &ALL, Some(&jf)).unwrap();
    let vtu = Vtu::read(&path);
    vtu.no_nan();
    assert_eq!(vtu.count(13), n * mesh.cells.len());
    for c in &vtu.cells {
        let x: Vec<[f64; 3]> = c.iter().map(|&i| vtu.points[i]).collect();
        assert!(face_volume(13, &x) > 0.0);
    }
    let j = Vtu::read(&joints_path(&path));
    j.no_nan();
    let n_el: usize = mesh.joints.iter().map(|j| j.elements.len()).sum();
    assert_eq!(j.count(9), n * n_el);
    assert!(j.cells.iter().all(|c| c.len() == 4));
    let state = j.cell_array("state", 1);
    assert!(state.iter().all(|s| [0.0, 1.0, 2.0].contains(s)));
    // Joint surface area: 2 pi a (pile side, 0 <= z <= 1) times the chord
    // factor sin(pi / n) / (pi / n) of flat quads.
    let area: f64 = j
        .cells
        .iter()
        .map(|c| {
            let p: Vec<[f64; 3]> = c.iter().map(|&i| j.points[i]).collect();
            let (d1, d2) = (sub(p[2], p[0]), sub(p[3], p[1]));
            0.5 * norm(cross(d1, d2))
        })
        .sum();
    let h = PI / n as f64;
    let expected = 2.0 * PI * 0.5 * 1.0 * h.sin() / h;
    assert!(
        (area - expected).abs() < 1e-9 * expected,
        "joint area {area} vs {expected}"
    );
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
