//! Shared helpers of the whole-model verification tests (closed forms,
//! convergence, joints, equilibrium): meshing a `geo/` file with gmsh per
//! element family, supports by physical name, consistent traction loads
//! (also from a Cartesian traction projected on a harmonic), a linear solve,
//! synthesis of the Fourier amplitudes at an angle, resultants, error norms
//! and log-log slopes.
//!
//! Conventions (docs/theory.md section 1): node DOFs `(u_r, u_z, u_theta)`,
//! `3 * node + c`; families
//!
//! | family | u_r | u_z | u_theta |
//! |---|---|---|---|
//! | m = 0 ([`Family::Sym`]) | u | v | w |
//! | [`Family::Sym`], m >= 1 | u cos m.th | v cos m.th | w sin m.th |
//! | [`Family::Anti`], m >= 1 | u sin m.th | v sin m.th | -w cos m.th |
//!
//! and loads the same way; the nodal load of a harmonic is
//! `f_m = c_m * (force per radian amplitude)`.

#![allow(dead_code)] // each test file uses a part of the helpers

use axijoint_mesh::geometry::{derivatives_rz, interpolate, jacobian};
use axijoint_mesh::quadrature::{quad_gauss, triangle};
use axijoint_mesh::shapes::MAX_CELL_NODES;
use axijoint_mesh::{prepare, CellKind, JointSpec, Mesh};
use axijoint_solver::assembly::JointModel;
use axijoint_solver::elements::{c_m, edge_load};
use axijoint_solver::linear::Model;
use axijoint_solver::material::Elastic;
use std::f64::consts::PI;
use std::path::PathBuf;

/// The five meridional element families.
pub const FAMILIES: [CellKind; 5] = [
    CellKind::Tri3,
    CellKind::Tri6,
    CellKind::Quad4,
    CellKind::Quad8,
    CellKind::Quad9,
];

/// The quadratic families.
pub const QUADRATIC: [CellKind; 3] = [CellKind::Tri6, CellKind::Quad8, CellKind::Quad9];

/// Displacement components, index within a node's DOFs.
pub const R: usize = 0;
/// Axial component.
pub const Z: usize = 1;
/// Circumferential component.
pub const TH: usize = 2;

/// Load / displacement family of a harmonic (m = 0 uses [`Family::Sym`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// `(cos, cos, sin)`.
    Sym,
    /// `(sin, sin, -cos)`.
    Anti,
}

/// The angular factors `(g_r, g_z, g_theta)` of harmonic `m` and `family` at
/// `theta`: the physical field is `(g_r u, g_z v, g_theta w)`.
pub fn angular(m: u32, family: Family, theta: f64) -> [f64; 3] {
    let (c, s) = ((m as f64 * theta).cos(), (m as f64 * theta).sin());
    match (m, family) {
        (0, _) => [1.0, 1.0, 1.0],
        (_, Family::Sym) => [c, c, s],
        (_, Family::Anti) => [s, s, -c],
    }
}

/// Path of a file in the workspace's `geo/` folder.
pub fn geo(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../geo")
        .join(name)
}

/// gmsh parameters `(order, quads, serendipity)` that make `kind`.
pub fn kind_params(kind: CellKind) -> [(String, f64); 3] {
    let (order, quads, serendipity) = match kind {
        CellKind::Tri3 => (1.0, 0.0, 0.0),
        CellKind::Tri6 => (2.0, 0.0, 0.0),
        CellKind::Quad4 => (1.0, 1.0, 0.0),
        CellKind::Quad8 => (2.0, 1.0, 1.0),
        CellKind::Quad9 => (2.0, 1.0, 0.0),
    };
    [
        ("order".to_string(), order),
        ("quads".to_string(), quads),
        ("serendipity".to_string(), serendipity),
    ]
}

/// Meshes `geo/<name>` with gmsh, element family `kind` and the extra
/// parameters `params`, inserts `joints`, and checks that every cell is of
/// `kind` (gmsh's recombination may leave triangles: a "Q8" result must come
/// from Q8 cells only).
pub fn mesh(name: &str, kind: CellKind, params: &[(&str, f64)], joints: &[&str]) -> Mesh {
    let mut all: Vec<(String, f64)> = kind_params(kind).to_vec();
    all.extend(params.iter().map(|(k, v)| (k.to_string(), *v)));
    let specs: Vec<JointSpec> = joints.iter().map(|s| s.parse().expect("joint spec")).collect();
    let (mesh, _) = prepare(&geo(name), &all, &specs, None)
        .unwrap_or_else(|e| panic!("meshing {name} with {all:?}: {e}"));
    let other = mesh.cells.iter().filter(|c| c.kind != kind).count();
    assert_eq!(other, 0, "{name}: {other} cells are not {kind:?}");
    mesh
}

/// Nodes of the line elements of a physical curve, sorted, each once.
pub fn curve_nodes(mesh: &Mesh, curve: &str) -> Vec<usize> {
    let set = mesh
        .curve(curve)
        .unwrap_or_else(|| panic!("no physical curve {curve}"));
    let mut nodes: Vec<usize> = set.edges.iter().flat_map(|e| e.nodes.iter().copied()).collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

/// Support flags `fixed[3 * node + c]`, built by physical name.
pub struct Supports<'a> {
    mesh: &'a Mesh,
    /// The flags.
    pub fixed: Vec<bool>,
}

impl<'a> Supports<'a> {
    /// No supports.
    pub fn new(mesh: &'a Mesh) -> Self {
        Supports {
            mesh,
            fixed: vec![false; 3 * mesh.nodes.len()],
        }
    }

    /// Fixes components `comps` of every node of physical curve `curve`.
    pub fn curve(mut self, curve: &str, comps: &[usize]) -> Self {
        for k in curve_nodes(self.mesh, curve) {
            for &c in comps {
                self.fixed[3 * k + c] = true;
            }
        }
        self
    }

    /// Fixes components `comps` of the nodes of physical point `point`.
    pub fn point(mut self, point: &str, comps: &[usize]) -> Self {
        let set = self
            .mesh
            .point(point)
            .unwrap_or_else(|| panic!("no physical point {point}"));
        for &k in &set.nodes {
            for &c in comps {
                self.fixed[3 * k + c] = true;
            }
        }
        self
    }

    /// The flags.
    pub fn done(self) -> Vec<bool> {
        self.fixed
    }
}

/// Consistent nodal loads (node DOFs) of the traction amplitudes
/// `t(r, z) = (t_r, t_z, t_theta)` of harmonic `m` on physical curve `curve`.
pub fn traction(mesh: &Mesh, curve: &str, m: u32, t: &dyn Fn(f64, f64) -> [f64; 3]) -> Vec<f64> {
    let mut f = vec![0.0; 3 * mesh.nodes.len()];
    add_traction(mesh, curve, m, t, &mut f);
    f
}

/// Adds the consistent nodal loads of a traction to `f`.
pub fn add_traction(mesh: &Mesh, curve: &str, m: u32, t: &dyn Fn(f64, f64) -> [f64; 3], f: &mut [f64]) {
    let set = mesh
        .curve(curve)
        .unwrap_or_else(|| panic!("no physical curve {curve}"));
    let mut fe = [0.0; 9];
    for ed in &set.edges {
        let coords: Vec<[f64; 2]> = ed.nodes.iter().map(|&k| mesh.nodes[k]).collect();
        edge_load(ed.kind, &coords, m, t, &mut fe);
        for (i, &k) in ed.nodes.iter().enumerate() {
            for c in 0..3 {
                f[3 * k + c] += fe[3 * i + c];
            }
        }
    }
}

/// Number of angles of the trapezoid rule of [`project`]: exact for
/// trigonometric polynomials of degree < 64.
const N_THETA: usize = 64;

/// Fourier amplitudes of harmonic `m`, family `family`, of a traction given
/// by its Cartesian components `t(x, y, z) -> (t_x, t_y, t_z)` at the point
/// (r, z) of the meridional plane:
///
/// ```text
/// amplitude_c = Integral(t_c(theta) g_c(theta) d theta) / Integral(g_c^2 d theta)
/// ```
///
/// with `t_r = t_x cos + t_y sin`, `t_theta = -t_x sin + t_y cos` and the
/// angular factors `g` of [`angular`]; the integrals by the trapezoid rule
/// over one turn (exact for the polynomial tractions used here). An
/// independent route to the load amplitudes: it checks the sign conventions
/// of the families rather than restating them.
pub fn project(m: u32, family: Family, t: &dyn Fn(f64, f64, f64) -> [f64; 3], r: f64, z: f64) -> [f64; 3] {
    let mut num = [0.0; 3];
    let mut den = [0.0; 3];
    for i in 0..N_THETA {
        let th = 2.0 * PI * i as f64 / N_THETA as f64;
        let (c, s) = (th.cos(), th.sin());
        let tc = t(r * c, r * s, z);
        let cyl = [tc[0] * c + tc[1] * s, tc[2], -tc[0] * s + tc[1] * c];
        let g = angular(m, family, th);
        for k in 0..3 {
            num[k] += cyl[k] * g[k];
            den[k] += g[k] * g[k];
        }
    }
    [num[0] / den[0], num[1] / den[1], num[2] / den[2]]
}

/// A linear model of one material on every body, solved for harmonic `m`
/// and each load vector in `loads` (one factorization).
pub fn solve(
    mesh: Mesh,
    material: Elastic,
    joints: Vec<JointModel>,
    fixed: Vec<bool>,
    m: u32,
    loads: &[&[f64]],
) -> (Model, Vec<Vec<f64>>) {
    let materials = vec![material; mesh.bodies.len()];
    let model = Model::new(mesh, materials, joints, fixed).expect("model");
    let factor = model
        .factorize(m)
        .unwrap_or_else(|e| panic!("factorizing harmonic {m}: {e}"));
    let u = model.solve(&factor, loads);
    (model, u)
}

/// The physical displacement `(u_r, u_z, u_theta)` of node `k` at `theta`
/// from the amplitudes `u` of harmonic `m`, family `family`.
pub fn synthesize(u: &[f64], k: usize, m: u32, family: Family, theta: f64) -> [f64; 3] {
    let g = angular(m, family, theta);
    [g[0] * u[3 * k], g[1] * u[3 * k + 1], g[2] * u[3 * k + 2]]
}

/// Largest nodal error `max_k,c |u[3k+c] - exact(r, z)[c]|` and the largest
/// exact value, over the components `comps`.
pub fn max_nodal_error(
    mesh: &Mesh,
    u: &[f64],
    comps: &[usize],
    exact: &dyn Fn(f64, f64) -> [f64; 3],
) -> (f64, f64) {
    let (mut err, mut scale) = (0.0f64, 0.0f64);
    for (k, p) in mesh.nodes.iter().enumerate() {
        let ex = exact(p[0], p[1]);
        for &c in comps {
            err = err.max((u[3 * k + c] - ex[c]).abs());
            scale = scale.max(ex[c].abs());
        }
    }
    (err, scale)
}

/// Quadrature rule for error norms: more points than the stiffness, so that
/// the error of the rule is far below the discretization error.
fn norm_rule(kind: CellKind) -> axijoint_mesh::quadrature::Rule2D {
    if kind.is_triangle() {
        triangle(6)
    } else {
        quad_gauss(5)
    }
    .expect("rule exists")
}

/// L2 norms of the displacement error and of the exact field over the
/// meridional section, weighted by r (the volume norm over one radian):
///
/// ```text
/// |e|^2 = Integral(sum_c (u_h,c - u_c)^2 r dr dz)
/// ```
///
/// `u_h` interpolated with the cell shape functions, over components `comps`.
pub fn l2_error(mesh: &Mesh, u: &[f64], comps: &[usize], exact: &dyn Fn(f64, f64) -> [f64; 3]) -> (f64, f64) {
    let (mut e2, mut x2) = (0.0, 0.0);
    let mut n = [0.0; MAX_CELL_NODES];
    let mut dn = [[0.0; 2]; MAX_CELL_NODES];
    for cell in &mesh.cells {
        let coords = mesh.cell_coords(cell);
        for (xi, w) in norm_rule(cell.kind).iter() {
            cell.kind.eval_n(xi, &mut n);
            cell.kind.eval_dn(xi, &mut dn);
            let det = jacobian(cell.kind, &coords, &dn).1;
            let [r, z] = interpolate(&coords, &n[..cell.kind.n_nodes()]);
            let ex = exact(r, z);
            for &c in comps {
                let uh: f64 = cell.nodes.iter().zip(&n).map(|(&k, ni)| ni * u[3 * k + c]).sum();
                e2 += (uh - ex[c]).powi(2) * r * det * w;
                x2 += ex[c].powi(2) * r * det * w;
            }
        }
    }
    (e2.sqrt(), x2.sqrt())
}

/// Energy-type (H1 seminorm) error of the radial displacement of an
/// axisymmetric field `u_r(r)`: `Integral((du_h/dr - u')^2 + (u_h - u)^2 / r^2) r dr dz`
/// (the strains e_r and e_theta), square-rooted; `exact(r)` returns
/// `(u, du/dr)`.
pub fn radial_energy_error(mesh: &Mesh, u: &[f64], exact: &dyn Fn(f64) -> (f64, f64)) -> f64 {
    let mut e2 = 0.0;
    let mut n = [0.0; MAX_CELL_NODES];
    let mut dn = [[0.0; 2]; MAX_CELL_NODES];
    let mut drz = [[0.0; 2]; MAX_CELL_NODES];
    for cell in &mesh.cells {
        let coords = mesh.cell_coords(cell);
        let nn = cell.kind.n_nodes();
        for (xi, w) in norm_rule(cell.kind).iter() {
            cell.kind.eval_n(xi, &mut n);
            cell.kind.eval_dn(xi, &mut dn);
            let (jac, det) = jacobian(cell.kind, &coords, &dn);
            derivatives_rz(&jac, det, &dn[..nn], &mut drz[..nn]);
            let r = interpolate(&coords, &n[..nn])[0];
            let (ue, due) = exact(r);
            let uh: f64 = cell.nodes.iter().zip(&n).map(|(&k, ni)| ni * u[3 * k]).sum();
            let duh: f64 = cell.nodes.iter().zip(&drz).map(|(&k, d)| d[0] * u[3 * k]).sum();
            e2 += ((duh - due).powi(2) + ((uh - ue) / r).powi(2)) * r * det * w;
        }
    }
    e2.sqrt()
}

/// Least-squares slope of `log(err)` against `log(h)`.
pub fn slope(h: &[f64], err: &[f64]) -> f64 {
    let x: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let y: Vec<f64> = err.iter().map(|v| v.ln()).collect();
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

/// Slopes between consecutive refinements (for the messages).
pub fn local_slopes(h: &[f64], err: &[f64]) -> Vec<f64> {
    (1..h.len())
        .map(|i| (err[i] / err[i - 1]).ln() / (h[i] / h[i - 1]).ln())
        .collect()
}

/// Cartesian resultants `[Fx, Fy, Fz, Mx, My, Mz]` about the origin of the
/// nodal forces `f` (node DOFs, `f_m = c_m * force-per-radian amplitude`)
/// of harmonic `m`, family `family`, summed over the nodes where `select`
/// is true. A node ring at (r, z) carries per radian
/// `F(theta) = f g(theta) / c_m` in (r, z, theta) components; integrating
/// over one turn (see [`resultants_by_quadrature`] for the check):
///
/// | m, family | nonzero resultants |
/// |---|---|
/// | 0 | Fz = sum f_z, Mz = sum r f_theta |
/// | 1, Sym | Fx = sum (f_r - f_theta), My = sum (z (f_r - f_theta) - r f_z) |
/// | 1, Anti | Fy = sum (f_r - f_theta), Mx = sum (r f_z - z (f_r - f_theta)) |
/// | >= 2 | none (every resultant integrates to zero) |
pub fn resultants(
    mesh: &Mesh,
    f: &[f64],
    m: u32,
    family: Family,
    select: &dyn Fn(usize) -> bool,
) -> [f64; 6] {
    let mut out = [0.0; 6];
    for (k, p) in mesh.nodes.iter().enumerate() {
        if !select(k) {
            continue;
        }
        let (r, z) = (p[0], p[1]);
        let (fr, fz, ft) = (f[3 * k], f[3 * k + 1], f[3 * k + 2]);
        match (m, family) {
            (0, _) => {
                out[2] += fz;
                out[5] += r * ft;
            }
            (1, Family::Sym) => {
                out[0] += fr - ft;
                out[4] += z * (fr - ft) - r * fz;
            }
            (1, Family::Anti) => {
                out[1] += fr - ft;
                out[3] += r * fz - z * (fr - ft);
            }
            _ => {}
        }
    }
    out
}

/// The same resultants by brute force: each node ring's force per radian
/// `F(theta) = f g(theta) / c_m` turned into Cartesian components at the
/// ring point (r cos, r sin, z), force and moment `x cross F` summed by the
/// trapezoid rule over one turn. Independent of the table of [`resultants`].
pub fn resultants_by_quadrature(mesh: &Mesh, f: &[f64], m: u32, family: Family) -> [f64; 6] {
    let mut out = [0.0; 6];
    let cm = c_m(m);
    let dth = 2.0 * PI / N_THETA as f64;
    for (k, p) in mesh.nodes.iter().enumerate() {
        let (r, z) = (p[0], p[1]);
        for i in 0..N_THETA {
            let th = dth * i as f64;
            let (c, s) = (th.cos(), th.sin());
            let g = angular(m, family, th);
            let (fr, fz, ft) = (
                f[3 * k] * g[0] / cm,
                f[3 * k + 1] * g[1] / cm,
                f[3 * k + 2] * g[2] / cm,
            );
            let fc = [fr * c - ft * s, fr * s + ft * c, fz];
            let x = [r * c, r * s, z];
            let mom = [
                x[1] * fc[2] - x[2] * fc[1],
                x[2] * fc[0] - x[0] * fc[2],
                x[0] * fc[1] - x[1] * fc[0],
            ];
            for d in 0..3 {
                out[d] += fc[d] * dth;
                out[3 + d] += mom[d] * dth;
            }
        }
    }
    out
}

/// Largest absolute value of a slice.
pub fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, b| a.max(b.abs()))
}

/// `[1.234e-5, ...]` for messages.
pub fn sci(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|x| format!("{x:.3e}")).collect();
    format!("[{}]", items.join(", "))
}
