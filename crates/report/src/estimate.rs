//! A posteriori error estimate (Zienkiewicz-Zhu) of the stresses: a
//! recovered stress `sigma*` per body by superconvergent patch recovery
//! (SPR), the element errors in the energy norm of the 3D field, and the
//! estimated error of a cut's profile (docs/accuracy.md).
//!
//! | symbol | meaning |
//! |---|---|
//! | sigma_h | the element's own stress amplitude (harmonic m, one family) |
//! | sigma* | the recovered amplitude: continuous within a body |
//! | eta_e | element error, `eta_e^2 = sum_m,family c_m Integral((sigma* - sigma_h)^T D^-1 (sigma* - sigma_h) r dA)` |
//! | p | element order: 1 (T3, Q4) or 2 (T6, Q8, Q9) |
//!
//! The basis functions of the harmonics and families are orthogonal over
//! the turn, so the 3D energy norm is the sum over harmonics and families
//! with the factor `c_m` (docs/theory.md section 3).
//!
//! Recovery is per body: a patch holds only cells of one body, and a node
//! shared by two bodies (or the two copies of a joint node) gets one
//! recovered value per body, so no jump between bodies is smoothed.

use crate::field::{gather, Field, Locator};
use axijoint_mesh::shapes::MAX_CELL_NODES;
use axijoint_mesh::{CellKind, Mesh};
use axijoint_solver::elements::{c_m, point_stress, CellValues, StrainPoint};
use axijoint_solver::material::Elastic;
use rayon::prelude::*;

/// One harmonic and family of the displacement whose stresses are estimated.
struct Mode {
    m: u32,
    antisymmetric: bool,
    u: Vec<f64>,
}

/// The displacement amplitudes of `field` (with those of its initial phase
/// added to harmonic 0): the stresses of a displacement are the ones the
/// mesh approximates; the initial stress `sigma_0` is exact.
fn modes(field: &Field) -> Vec<Mode> {
    let mut out: Vec<Mode> = Vec::new();
    for h in &field.u.harmonics {
        out.push(Mode {
            m: h.m,
            antisymmetric: false,
            u: h.symmetric.clone(),
        });
        if h.m > 0 && h.antisymmetric.iter().any(|&v| v != 0.0) {
            out.push(Mode {
                m: h.m,
                antisymmetric: true,
                u: h.antisymmetric.clone(),
            });
        }
    }
    if let Some(u0) = field.initial.as_ref().and_then(|i| i.u) {
        for h in u0.harmonics.iter().filter(|h| h.m == 0) {
            match out.iter_mut().find(|md| md.m == 0 && !md.antisymmetric) {
                Some(md) => md.u.iter_mut().zip(&h.symmetric).for_each(|(a, b)| *a += b),
                None => out.push(Mode {
                    m: 0,
                    antisymmetric: false,
                    u: h.symmetric.clone(),
                }),
            }
        }
    }
    out.retain(|md| md.u.iter().any(|&v| v != 0.0));
    out
}

/// The element order p of a cell.
pub fn order(kind: CellKind) -> u32 {
    if kind.is_quadratic() {
        2
    } else {
        1
    }
}

/// The compliance `D^-1` of an isotropic material applied to `s`, dotted
/// with `s`: `s^T D^-1 s` (engineering shear strains).
fn compliance_energy(mat: &Elastic, s: &[f64; 6]) -> f64 {
    let (e, nu) = (mat.e, mat.nu);
    let g = mat.shear_modulus();
    let normal = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) / e
        - 2.0 * nu / e * (s[0] * s[1] + s[1] * s[2] + s[2] * s[0]);
    normal + (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]) / g
}

/// The error estimate of a solution.
pub struct Estimate {
    /// The displacement per harmonic and family.
    modes: Vec<Mode>,
    /// First entry of each cell in `recovered[mode]`.
    offsets: Vec<usize>,
    /// Recovered stress amplitudes at the cells' nodes, per mode (a cell's
    /// nodes in its own order: values of its body).
    recovered: Vec<Vec<[f64; 6]>>,
    /// `eta_e^2` per cell.
    pub cell_error2: Vec<f64>,
    /// The volume `2 pi Integral(r dA)` of each cell's ring.
    pub cell_volume: Vec<f64>,
    /// `|sigma_h|^2` in the energy norm: `sum c_m Integral(sigma_h^T D^-1 sigma_h r dA)`.
    pub norm2: f64,
}

/// Gauss data of one cell: points `(r, z)`, weights `w r` (`w = w_q |det J|`
/// of [`CellValues`]) and the element stress per mode at each point.
struct CellGauss {
    points: Vec<[f64; 2]>,
    weights: Vec<f64>,
    stress: Vec<Vec<[f64; 6]>>,
}

impl Estimate {
    /// Recovers the stresses of `field` and estimates the element errors.
    pub fn new(field: &Field) -> Estimate {
        let mesh = field.mesh;
        let modes = modes(field);
        let nm = modes.len();
        let mut offsets = Vec::with_capacity(mesh.cells.len() + 1);
        let mut total = 0;
        for c in &mesh.cells {
            offsets.push(total);
            total += c.nodes.len();
        }
        offsets.push(total);
        // Gauss data of every cell.
        let gauss: Vec<CellGauss> = mesh
            .cells
            .par_iter()
            .map_init(
                || CellValues::with_default_rule(CellKind::Quad9),
                |values, c| {
                    let coords = mesh.cell_coords(c);
                    // Validated meshes have no refused cell; one would
                    // give values that are not finite, refused on writing.
                    let _refused = values.reinit(c.kind, &coords);
                    let nn = c.kind.n_nodes();
                    let mat = &field.materials[c.body];
                    let mut ue = [0.0; 3 * MAX_CELL_NODES];
                    let mut g = CellGauss {
                        points: Vec::new(),
                        weights: Vec::new(),
                        stress: vec![Vec::new(); nm],
                    };
                    for q in 0..values.n_points() {
                        g.points.push(values.position(q));
                        g.weights.push(values.weight(q) * values.r(q));
                        for (k, md) in modes.iter().enumerate() {
                            gather(&md.u, &c.nodes, &mut ue);
                            g.stress[k].push(point_stress(values, q, mat, md.m, &ue[..3 * nn]));
                        }
                    }
                    g
                },
            )
            .collect();
        let recovered = recover(mesh, &gauss, nm, &offsets);
        // Element errors and the norm.
        let ((cell_error2, cell_volume), cell_norm2): ((Vec<f64>, Vec<f64>), Vec<f64>) = mesh
            .cells
            .par_iter()
            .enumerate()
            .map_init(
                || CellValues::with_default_rule(CellKind::Quad9),
                |values, (cell, c)| {
                    // Only the shape values: no reinit.
                    values.set_kind(c.kind);
                    let mat = &field.materials[c.body];
                    let g = &gauss[cell];
                    let (mut error2, mut volume, mut norm2) = (0.0, 0.0, 0.0);
                    for q in 0..values.n_points() {
                        let w = g.weights[q];
                        volume += 2.0 * std::f64::consts::PI * w;
                        for (k, md) in modes.iter().enumerate() {
                            let mut d = [0.0; 6];
                            for (i, ni) in values.n(q).iter().enumerate() {
                                let s = recovered[k][offsets[cell] + i];
                                for a in 0..6 {
                                    d[a] += ni * s[a];
                                }
                            }
                            let sh = g.stress[k][q];
                            for a in 0..6 {
                                d[a] -= sh[a];
                            }
                            let cm = c_m(md.m);
                            error2 += cm * w * compliance_energy(mat, &d);
                            norm2 += cm * w * compliance_energy(mat, &sh);
                        }
                    }
                    ((error2, volume), norm2)
                },
            )
            .unzip();
        let norm2 = cell_norm2.iter().sum();
        Estimate {
            modes,
            offsets,
            recovered,
            cell_error2,
            cell_volume,
            norm2,
        }
    }

    /// The estimated error in the energy norm, `sqrt(sum eta_e^2)`.
    pub fn error(&self) -> f64 {
        self.cell_error2.iter().sum::<f64>().sqrt()
    }

    /// The relative error `eta / sqrt(|sigma_h|^2 + eta^2)` (energy norm).
    pub fn relative(&self) -> f64 {
        let e2: f64 = self.cell_error2.iter().sum();
        if e2 + self.norm2 > 0.0 {
            (e2 / (e2 + self.norm2)).sqrt()
        } else {
            0.0
        }
    }

    /// Per cell `eta_e^2 / V_e`: the error's `(sigma* - sigma_h)^T D^-1
    /// (sigma* - sigma_h)` averaged over the cell's ring (stress units).
    pub fn cell_density(&self) -> Vec<f64> {
        self.cell_error2
            .iter()
            .zip(&self.cell_volume)
            .map(|(e, v)| if *v > 0.0 { e / v } else { 0.0 })
            .collect()
    }

    /// `(sigma*, sigma_h)` of the displacement at reference point `xi` of
    /// `cell`, angle `theta` (radians): sigma* interpolated from the cell's
    /// recovered nodal values, sigma_h the cell's own stress (the initial
    /// stress `sigma_0` left out of both: it is exact).
    pub fn stresses_at(&self, field: &Field, cell: usize, xi: [f64; 2], theta: f64) -> ([f64; 6], [f64; 6]) {
        let mesh = field.mesh;
        let c = &mesh.cells[cell];
        let coords = mesh.cell_coords(c);
        let nn = c.kind.n_nodes();
        let point = StrainPoint::new(c.kind, &coords, xi);
        let (mut rec, mut raw) = ([0.0; 6], [0.0; 6]);
        for (k, md) in self.modes.iter().enumerate() {
            let (sin, cos) = (f64::from(md.m) * theta).sin_cos();
            let (a, b) = match (md.m, md.antisymmetric) {
                (0, _) => (1.0, 1.0),
                (_, false) => (cos, sin),
                (_, true) => (sin, -cos),
            };
            let mut ue = [0.0; 3 * MAX_CELL_NODES];
            gather(&md.u, &c.nodes, &mut ue);
            let h = point.stress(&field.materials[c.body], md.m, &ue[..3 * nn]);
            for (i, ni) in point.n().iter().enumerate() {
                let s = self.recovered[k][self.offsets[cell] + i];
                for q in 0..6 {
                    rec[q] += if q < 4 { a } else { b } * ni * s[q];
                }
            }
            for q in 0..6 {
                raw[q] += if q < 4 { a } else { b } * h[q];
            }
        }
        (rec, raw)
    }
}

/// SPR per body: for every corner node a least-squares polynomial of the
/// patch's order through the Gauss-point stresses of the body's cells at
/// that node, evaluated at every node of the patch; a node's value is the
/// mean of the polynomials of the patches that hold it, those centred on
/// interior corner nodes only when it has one (extrapolation from inside
/// the body is better than a fit at its edge).
fn recover(mesh: &Mesh, gauss: &[CellGauss], nm: usize, offsets: &[usize]) -> Vec<Vec<[f64; 6]>> {
    let total = *offsets.last().unwrap_or(&0);
    let mut out = vec![vec![[0.0; 6]; total]; nm];
    let width = nm * 6;
    for body in 0..mesh.bodies.len() {
        let cells: Vec<usize> = (0..mesh.cells.len())
            .filter(|&c| mesh.cells[c].body == body)
            .collect();
        // Corner node -> its cells in the body; edges used once -> boundary.
        let mut patches: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
        let mut edges: std::collections::HashMap<(usize, usize), usize> = Default::default();
        for &c in &cells {
            let cell = &mesh.cells[c];
            for i in 0..cell.kind.n_corners() {
                patches.entry(cell.nodes[i]).or_default().push(c);
                let l = cell.kind.edge_nodes(i);
                let (a, b) = (cell.nodes[l[0]], cell.nodes[l[1]]);
                *edges.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        let mut on_boundary: std::collections::HashSet<usize> = Default::default();
        for (&(a, b), &k) in &edges {
            if k == 1 {
                on_boundary.insert(a);
                on_boundary.insert(b);
            }
        }
        // Sums per node: [interior patches, all patches].
        let mut local: std::collections::HashMap<usize, usize> = Default::default();
        for &c in &cells {
            for &n in &mesh.cells[c].nodes {
                let k = local.len();
                local.entry(n).or_insert(k);
            }
        }
        let mut sums = [vec![0.0; local.len() * width], vec![0.0; local.len() * width]];
        let mut counts = [vec![0usize; local.len()], vec![0usize; local.len()]];
        for (&centre, patch) in &patches {
            let x0 = mesh.nodes[centre];
            let p = patch
                .iter()
                .map(|&c| order(mesh.cells[c].kind))
                .max()
                .unwrap_or(1);
            let pts: Vec<(usize, usize)> = patch
                .iter()
                .flat_map(|&c| (0..gauss[c].points.len()).map(move |q| (c, q)))
                .collect();
            let h = pts
                .iter()
                .map(|&(c, q)| {
                    let x = gauss[c].points[q];
                    (x[0] - x0[0]).hypot(x[1] - x0[1])
                })
                .fold(0.0f64, f64::max)
                .max(f64::MIN_POSITIVE);
            let scaled = |x: [f64; 2]| [(x[0] - x0[0]) / h, (x[1] - x0[1]) / h];
            let Some((deg, coef)) = (0..=p).rev().find_map(|deg| {
                let nt = n_terms(deg);
                if pts.len() < nt + usize::from(deg > 0) {
                    return None;
                }
                let mut ata = vec![0.0; nt * nt];
                let mut atb = vec![0.0; nt * width];
                let mut phi = [0.0; 6];
                for &(c, q) in &pts {
                    basis(deg, scaled(gauss[c].points[q]), &mut phi);
                    for i in 0..nt {
                        for j in 0..nt {
                            ata[i * nt + j] += phi[i] * phi[j];
                        }
                        for (k, s) in gauss[c].stress.iter().enumerate() {
                            for a in 0..6 {
                                atb[i * width + 6 * k + a] += phi[i] * s[q][a];
                            }
                        }
                    }
                }
                solve_in_place(nt, &mut ata, &mut atb, width).then_some((deg, atb))
            }) else {
                continue;
            };
            let tier = usize::from(on_boundary.contains(&centre));
            let mut nodes: Vec<usize> = patch
                .iter()
                .flat_map(|&c| mesh.cells[c].nodes.iter().copied())
                .collect();
            nodes.sort_unstable();
            nodes.dedup();
            let nt = n_terms(deg);
            let mut phi = [0.0; 6];
            for n in nodes {
                basis(deg, scaled(mesh.nodes[n]), &mut phi);
                let l = local[&n];
                for t in [0, 1] {
                    if t == 0 && tier == 1 {
                        continue;
                    }
                    counts[t][l] += 1;
                    for i in 0..nt {
                        for v in 0..width {
                            sums[t][l * width + v] += phi[i] * coef[i * width + v];
                        }
                    }
                }
            }
        }
        for &c in &cells {
            for (i, n) in mesh.cells[c].nodes.iter().enumerate() {
                let l = local[n];
                let t = if counts[0][l] > 0 { 0 } else { 1 };
                let k = counts[t][l].max(1) as f64;
                for (md, o) in out.iter_mut().enumerate() {
                    for a in 0..6 {
                        o[offsets[c] + i][a] = sums[t][l * width + 6 * md + a] / k;
                    }
                }
            }
        }
    }
    out
}

/// Terms of a complete polynomial of degree `deg` in two variables.
fn n_terms(deg: u32) -> usize {
    match deg {
        0 => 1,
        1 => 3,
        _ => 6,
    }
}

/// The monomials `1, x, y, x^2, xy, y^2` up to degree `deg`.
fn basis(deg: u32, x: [f64; 2], out: &mut [f64; 6]) {
    *out = [1.0, x[0], x[1], x[0] * x[0], x[0] * x[1], x[1] * x[1]];
    if deg == 0 {
        out[1..].fill(0.0);
    } else if deg == 1 {
        out[3..].fill(0.0);
    }
}

/// Solves `a x = b` (n x n, `width` right-hand sides, row-major) by
/// Gaussian elimination with partial pivoting, x into `b`; false when a
/// pivot falls below `1e-10` of the largest diagonal (a patch that does not
/// determine the polynomial).
fn solve_in_place(n: usize, a: &mut [f64], b: &mut [f64], width: usize) -> bool {
    let scale = (0..n).map(|i| a[i * n + i].abs()).fold(0.0, f64::max);
    if scale == 0.0 {
        return false;
    }
    for col in 0..n {
        let piv = (col..n)
            .max_by(|&i, &j| a[i * n + col].abs().total_cmp(&a[j * n + col].abs()))
            .unwrap_or(col);
        if a[piv * n + col].abs() < 1e-10 * scale {
            return false;
        }
        if piv != col {
            for j in 0..n {
                a.swap(col * n + j, piv * n + j);
            }
            for j in 0..width {
                b.swap(col * width + j, piv * width + j);
            }
        }
        for row in col + 1..n {
            let f = a[row * n + col] / a[col * n + col];
            if f == 0.0 {
                continue;
            }
            for j in col..n {
                a[row * n + j] -= f * a[col * n + j];
            }
            for j in 0..width {
                b[row * width + j] -= f * b[col * width + j];
            }
        }
    }
    for col in (0..n).rev() {
        for j in 0..width {
            let mut v = b[col * width + j];
            for k in col + 1..n {
                v -= a[col * n + k] * b[k * width + j];
            }
            b[col * width + j] = v / a[col * n + col];
        }
    }
    true
}

/// The estimated error of a cut's profile at one angle: the largest
/// `|sigma*_c - sigma_h,c|` over the cut's samples (every body that holds a
/// sample, as [`crate::cuts::profile`] reports them), divided by the
/// largest `|sigma_c|` of the profile (total stress, initial stress
/// included); `c` the cut's component, `theta_deg` in degrees. 0 for a
/// profile that is zero everywhere.
pub fn cut_error(
    field: &Field,
    estimate: &Estimate,
    locator: &Locator,
    points: &[[f64; 2]],
    spacing: f64,
    theta_deg: f64,
    component: usize,
) -> f64 {
    let (err, max) = cut_error_and_scale(field, estimate, locator, points, spacing, theta_deg, component);
    if max > 0.0 {
        err / max
    } else {
        0.0
    }
}

/// [`cut_error`]'s parts: the largest `|sigma*_c - sigma_h,c|` and the
/// largest `|sigma_c|` along the cut.
pub fn cut_error_and_scale(
    field: &Field,
    estimate: &Estimate,
    locator: &Locator,
    points: &[[f64; 2]],
    spacing: f64,
    theta_deg: f64,
    component: usize,
) -> (f64, f64) {
    let mesh = field.mesh;
    let theta = theta_deg.to_radians();
    let (mut err, mut max): (f64, f64) = (0.0, 0.0);
    for (_, p) in crate::cuts::sample_positions(mesh, points, spacing) {
        let mut seen: Vec<usize> = Vec::new();
        for l in locator.locate_all(mesh, p) {
            let body = mesh.cells[l.cell].body;
            if seen.contains(&body) {
                continue;
            }
            seen.push(body);
            let (rec, raw) = estimate.stresses_at(field, l.cell, l.xi, theta);
            err = err.max((rec[component] - raw[component]).abs());
            max = max.max(field.stress(l.cell, l.xi, theta)[component].abs());
        }
    }
    (err, max)
}

/// The estimated errors of every cut of a scene: `(cut name, theta in
/// degrees, fraction)`, in the scene's order.
pub fn cut_errors(
    field: &Field,
    estimate: &Estimate,
    locator: &Locator,
    cuts: &[axijoint_solver::scene::Cut],
) -> Vec<(String, f64, f64)> {
    profile_estimates(field, estimate, locator, cuts)
        .into_iter()
        .map(|(c, t, e, _)| (c, t, e))
        .collect()
}

/// [`cut_errors`] with each profile's max |stress| last.
pub fn profile_estimates(
    field: &Field,
    estimate: &Estimate,
    locator: &Locator,
    cuts: &[axijoint_solver::scene::Cut],
) -> Vec<(String, f64, f64, f64)> {
    let mut out = Vec::new();
    for cut in cuts {
        let c = cut.component_index().unwrap_or(1);
        for &t in &cut.theta_deg {
            let (e, max) =
                cut_error_and_scale(field, estimate, locator, &[cut.from, cut.to], cut.spacing, t, c);
            out.push((cut.name.clone(), t, if max > 0.0 { e / max } else { 0.0 }, max));
        }
    }
    out
}
