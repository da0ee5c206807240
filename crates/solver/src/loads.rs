//! Scene loads -> consistent nodal forces per harmonic and family.
//!
//! # Amplitudes and nodal forces
//!
//! A load of harmonic m is given by amplitudes `(t_r, t_z, t_theta)`
//! (docs/theory.md section 1):
//!
//! | family | t_r, t_z | t_theta |
//! |---|---|---|
//! | m = 0 | constant | constant (torsion) |
//! | symmetric, m >= 1 | `T cos m.th` | `T sin m.th` |
//! | antisymmetric, m >= 1 | `T sin m.th` | `-T cos m.th` |
//!
//! and its consistent nodal forces are `f = c_m Integral(N^T T r ds)`
//! ([`edge_load`]). Conversely a node i with amplitudes `f_i` carries the
//! physical force per radian `g_i(theta) = f_i / c_m` times the family's
//! cos / sin factors.
//!
//! # Resultants of nodal forces
//!
//! Integrating `g_i` over one turn, with `e_r = (cos, sin, 0)` and
//! `e_theta = (-sin, cos, 0)`, only m = 0 and m = 1 have resultants. Node i
//! at `(r, z)`, `d = z - z_ref`, amplitudes `(f_r, f_z, f_th)`:
//!
//! ```text
//! m = 0:              Fz = f_z                      Mz = r f_th
//! m = 1 symmetric:    Fx = f_r - f_th               My = d (f_r - f_th) - r f_z
//! m = 1 antisym.:     Fy = f_r - f_th               Mx = -d (f_r - f_th) + r f_z
//! ```
//!
//! For example, symmetric m = 1: `g_r = f_r cos / pi`, `g_th = f_th sin / pi`;
//! the x-component of `g_r e_r + g_th e_theta` is `g_r cos - g_th sin =
//! (f_r cos^2 - f_th sin^2) / pi`, whose integral is `f_r - f_th`. The
//! moments are those of `(r e_r + d e_z) x g`. [`load_resultants`] sums
//! these.
//!
//! # Section resultants on a flat end face (beam theory)
//!
//! On a face z = z_f (a disc or an annulus; all nodes of the curve at one
//! z), with the face's discretised area and second moments
//!
//! ```text
//! A = 2 pi Integral(r dr),   I = pi Integral(r^3 dr),   J = 2 pi Integral(r^3 dr) = 2 I
//! ```
//!
//! (computed with the same quadrature as the loads, so the resultants are
//! reproduced to round-off), a force `F = (Fx, Fy, Fz)` acting at
//! `(0, 0, z0)` plus a moment `(Mx', My')` and a torque `T` is, about the
//! face centre, the force F and the moment
//!
//! ```text
//! M = (0, 0, z0 - z_f) x F + (Mx', My', 0) = (-d Fy + Mx', d Fx + My', 0),  d = z0 - z_f.
//! ```
//!
//! Beam theory distributes it as uniform tractions `F/A`, a linear axial
//! traction for the bending moment and a torsional shear `T r / J`:
//!
//! - `t_x = Fx/A`, `t_y = Fy/A`, so `t_r = Fx/A cos + Fy/A sin` and
//!   `t_theta = -Fx/A sin + Fy/A cos`: harmonic 1, symmetric `(T_r, T_th) =
//!   (Fx/A, -Fx/A)`, antisymmetric `(Fy/A, -Fy/A)` (the antisymmetric
//!   t_theta is `-T_th cos`). A force in +y is a force in +x turned by 90
//!   degrees, and its antisymmetric amplitudes are the symmetric ones of +x.
//! - `t_z = a x + b y` on the point `(x, y, z_f)`: its moment about the
//!   centre is `Integral((x, y, 0) x (0, 0, t_z) dA) = Integral((y t_z, -x
//!   t_z, 0) dA) = (b I, -a I, 0)`, so `b = Mx/I`, `a = -My/I` and
//!   `t_z = (-My cos + Mx sin) r / I`: harmonic 1, symmetric `T_z = -My r /
//!   I`, antisymmetric `T_z = Mx r / I`.
//! - `t_z = Fz/A` and `t_theta = T r / J`: harmonic 0.
//!
//! Scene P: `H = 0.5` in +x at `z0 = -3.0` on the face `z_f = -1.5`:
//! `d = -1.5`, `M = (0, -0.75, 0)`, `T_z = 0.75 r / I` (symmetric): the
//! axial traction pushes (+z, into the pile) at theta = 0 and pulls at
//! theta = pi, turning the pile about -y, as H below the face does.
//!
//! # Ring and point loads
//!
//! A ring load of amplitude `f` (force per unit circumferential length) at
//! a node of radius r > 0 gives the nodal force `c_m r f`: per radian the
//! ring carries `r f cos m.th` (symmetric), and `Integral(cos^2 m.th) = c_m`.
//! At r = 0 a ring has no length: use a point load, `(Fx, Fy, Fz)` on the
//! axis, which gives m = 0 `f_z = Fz`, and m = 1 `(f_r, f_th) = (Fx/2,
//! -Fx/2)` symmetric and `(Fy/2, -Fy/2)` antisymmetric (the limit of the
//! uniform shear of a vanishing disc; on the axis `u + w = 0` ties the two
//! and only `f_r - f_th` does work). Copies of a node made by joint
//! insertion share its load equally; a physical point group with several
//! points loads each of them.

use crate::elements::{body_force_load, c_m, edge_load, DOF_PER_NODE};
use crate::scene::{Family, Load, Scene, SceneError};
use axijoint_mesh::shapes::{MAX_CELL_NODES, MAX_EDGE_NODES};
use axijoint_mesh::{CurveSet, Mesh};

/// Nodal forces of one harmonic: `3 * n_nodes` entries per family,
/// node-major `(f_r, f_z, f_theta)` in the mesh's node numbering, before any
/// DOF elimination.
///
/// Harmonic 0 uses `symmetric` only (with the torsional `f_theta`);
/// its `antisymmetric` is all zeros.
#[derive(Clone, Debug, PartialEq)]
pub struct HarmonicLoads {
    /// Harmonic m.
    pub m: u32,
    /// Symmetric family (and harmonic 0).
    pub symmetric: Vec<f64>,
    /// Antisymmetric family.
    pub antisymmetric: Vec<f64>,
    /// Prescribed displacements of faces moved by `motion` loads, if any.
    pub prescribed: Option<Box<Prescribed>>,
}

/// The prescribed displacements of one harmonic (faces moved by `motion`
/// loads, held in the model) and the forces equivalent to them on the
/// free DOFs: a solve of `f + equivalent` plus `displacement` is the
/// solution with the faces moved.
#[derive(Clone, Debug, PartialEq)]
pub struct Prescribed {
    /// Node-DOF displacements per family (symmetric, antisymmetric).
    pub displacement: [Vec<f64>; 2],
    /// `-K_m u_s` per family (zero at held DOFs).
    pub equivalent: [Vec<f64>; 2],
}

impl HarmonicLoads {
    /// The loads times `lambda`.
    pub fn scaled(&self, lambda: f64) -> HarmonicLoads {
        let mut out = HarmonicLoads::zeros(self.m, self.symmetric.len() / DOF_PER_NODE);
        out.add(lambda, self);
        out
    }

    /// `self += a other` (same harmonic and nodes).
    pub fn add(&mut self, a: f64, other: &HarmonicLoads) {
        let axpy = |x: &mut [f64], y: &[f64]| x.iter_mut().zip(y).for_each(|(p, q)| *p += a * q);
        axpy(&mut self.symmetric, &other.symmetric);
        axpy(&mut self.antisymmetric, &other.antisymmetric);
        if let Some(o) = &other.prescribed {
            let n = self.symmetric.len();
            let p = self.prescribed.get_or_insert_with(|| {
                Box::new(Prescribed {
                    displacement: [vec![0.0; n], vec![0.0; n]],
                    equivalent: [vec![0.0; n], vec![0.0; n]],
                })
            });
            for k in 0..2 {
                axpy(&mut p.displacement[k], &o.displacement[k]);
                axpy(&mut p.equivalent[k], &o.equivalent[k]);
            }
        }
    }

    /// The right-hand side of family `k` (0 symmetric, 1 antisymmetric):
    /// the forces and those equivalent to the prescribed displacements.
    pub fn rhs(&self, k: usize) -> std::borrow::Cow<'_, [f64]> {
        let f = if k == 0 {
            &self.symmetric
        } else {
            &self.antisymmetric
        };
        match &self.prescribed {
            Some(p) => std::borrow::Cow::Owned(f.iter().zip(&p.equivalent[k]).map(|(a, b)| a + b).collect()),
            None => std::borrow::Cow::Borrowed(f),
        }
    }

    /// Adds the prescribed displacements of family `k` to a solution `u`
    /// of [`HarmonicLoads::rhs`] (zero at held DOFs).
    pub fn add_prescribed(&self, k: usize, u: &mut [f64]) {
        if let Some(p) = &self.prescribed {
            u.iter_mut().zip(&p.displacement[k]).for_each(|(a, b)| *a += b);
        }
    }

    /// Whether any load component of this harmonic is non-zero (forces or
    /// prescribed displacements).
    pub fn is_loaded(&self) -> bool {
        let moved = self
            .prescribed
            .as_ref()
            .is_some_and(|p| p.displacement.iter().flatten().any(|&v| v != 0.0));
        moved
            || self
                .symmetric
                .iter()
                .chain(&self.antisymmetric)
                .any(|&v| v != 0.0)
    }

    /// No load on `n_nodes` nodes.
    pub fn zeros(m: u32, n_nodes: usize) -> Self {
        HarmonicLoads {
            m,
            symmetric: vec![0.0; DOF_PER_NODE * n_nodes],
            antisymmetric: vec![0.0; DOF_PER_NODE * n_nodes],
            prescribed: None,
        }
    }

    /// The vector of a family.
    pub fn family(&self, family: Family) -> &[f64] {
        match family {
            Family::Symmetric => &self.symmetric,
            Family::Antisymmetric => &self.antisymmetric,
        }
    }

    fn family_mut(&mut self, family: Family) -> &mut [f64] {
        match family {
            Family::Symmetric => &mut self.symmetric,
            Family::Antisymmetric => &mut self.antisymmetric,
        }
    }
}

/// Cartesian force and moment of a load system.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resultants {
    /// `(Fx, Fy, Fz)`.
    pub force: [f64; 3],
    /// `(Mx, My, Mz)` about the point `(0, 0, z_ref)`.
    pub moment: [f64; 3],
}

/// Area and second moments of a flat face `z = z`, as discretised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FaceSection {
    /// The face's z.
    pub z: f64,
    /// `A = 2 pi Integral(r dr)`.
    pub area: f64,
    /// `J = 2 pi Integral(r^3 dr)`; `I = J / 2`.
    pub polar: f64,
}

/// Geometric tolerance of a mesh: 1e-9 of its extent.
pub(crate) fn tolerance(mesh: &Mesh) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for x in &mesh.nodes {
        for a in 0..2 {
            lo[a] = lo[a].min(x[a]);
            hi[a] = hi[a].max(x[a]);
        }
    }
    let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    1e-9 * if extent.is_finite() && extent > 0.0 {
        extent
    } else {
        1.0
    }
}

/// Coordinates of an edge's nodes.
fn edge_coords(mesh: &Mesh, nodes: &[usize]) -> [[f64; 2]; MAX_EDGE_NODES] {
    let mut x = [[0.0; 2]; MAX_EDGE_NODES];
    for (xi, &n) in x.iter_mut().zip(nodes) {
        *xi = mesh.nodes[n];
    }
    x
}

/// A, J of a curve that must be flat and perpendicular to the axis; the
/// error says which node is off the plane.
pub(crate) fn face_section(mesh: &Mesh, curve: &CurveSet) -> Result<FaceSection, String> {
    let first = curve
        .edges
        .first()
        .ok_or_else(|| format!("curve '{}' has no line elements", curve.name))?;
    let z = mesh.nodes[first.nodes[0]][1];
    let tol = tolerance(mesh);
    for edge in &curve.edges {
        for &n in &edge.nodes {
            let [rn, zn] = mesh.nodes[n];
            if (zn - z).abs() > tol {
                return Err(format!(
                    "a resultant load needs a flat face perpendicular to the axis, but curve '{}' has \
                     node {} at (r, z) = ({rn}, {zn}) off the plane z = {z} of node {}",
                    curve.name, mesh.node_tags[n], mesh.node_tags[first.nodes[0]]
                ));
            }
        }
    }
    // Same quadrature as the loads: A = sum f_z of t_z = 1, J = of t_z = r^2 (m = 0).
    let (mut area, mut polar) = (0.0, 0.0);
    let mut f = [0.0; DOF_PER_NODE * MAX_EDGE_NODES];
    for edge in &curve.edges {
        let x = edge_coords(mesh, &edge.nodes);
        let nn = edge.kind.n_nodes();
        edge_load(edge.kind, &x[..nn], 0, &|_, _| [0.0, 1.0, 0.0], &mut f);
        area += (0..nn).map(|i| f[DOF_PER_NODE * i + 1]).sum::<f64>();
        edge_load(edge.kind, &x[..nn], 0, &|r, _| [0.0, r * r, 0.0], &mut f);
        polar += (0..nn).map(|i| f[DOF_PER_NODE * i + 1]).sum::<f64>();
    }
    if area <= 0.0 || polar <= 0.0 {
        return Err(format!(
            "curve '{}' encloses no area (A = {area}): a resultant load needs a disc or an annulus",
            curve.name
        ));
    }
    Ok(FaceSection { z, area, polar })
}

/// The distinct locations of a point group: `(r, copies)`, copies being
/// the nodes at that location (joint insertion may have split one).
pub(crate) fn point_locations(mesh: &Mesh, nodes: &[usize]) -> Vec<(f64, Vec<usize>)> {
    let tol = tolerance(mesh);
    let mut out: Vec<([f64; 2], Vec<usize>)> = Vec::new();
    for &n in nodes {
        let x = mesh.nodes[n];
        match out
            .iter_mut()
            .find(|(y, _)| (x[0] - y[0]).abs() <= tol && (x[1] - y[1]).abs() <= tol)
        {
            Some((_, copies)) => copies.push(n),
            None => out.push((x, vec![n])),
        }
    }
    out.into_iter().map(|(x, c)| (x[0], c)).collect()
}

/// Adds `c_m * Integral(N^T t r ds)` over the curve's line elements to `out`.
fn add_curve_load(mesh: &Mesh, curve: &CurveSet, m: u32, t: &dyn Fn(f64, f64) -> [f64; 3], out: &mut [f64]) {
    let mut f = [0.0; DOF_PER_NODE * MAX_EDGE_NODES];
    for edge in &curve.edges {
        let x = edge_coords(mesh, &edge.nodes);
        let nn = edge.kind.n_nodes();
        edge_load(edge.kind, &x[..nn], m, t, &mut f);
        for (i, &n) in edge.nodes.iter().enumerate() {
            for c in 0..DOF_PER_NODE {
                out[DOF_PER_NODE * n + c] += f[DOF_PER_NODE * i + c];
            }
        }
    }
}

/// Adds `f` shared equally by `copies`.
fn add_nodal(copies: &[usize], f: [f64; 3], out: &mut [f64]) {
    let share = 1.0 / copies.len() as f64;
    for &n in copies {
        for (c, fc) in f.iter().enumerate() {
            out[DOF_PER_NODE * n + c] += share * fc;
        }
    }
}

/// Consistent nodal forces of every load of `scene` for harmonics
/// `0..=m_max` (see the module doc), one [`HarmonicLoads`] per harmonic.
///
/// Runs on the mesh before or after joint insertion. Checks what it needs
/// (names, flat faces, r of ring and point loads, harmonics within
/// `m_max`); run [`Scene::check`] first for the rest.
pub fn assemble_loads(scene: &Scene, mesh: &Mesh, m_max: u32) -> Result<Vec<HarmonicLoads>, SceneError> {
    let n = mesh.nodes.len();
    let mut out: Vec<HarmonicLoads> = (0..=m_max).map(|m| HarmonicLoads::zeros(m, n)).collect();
    let invalid = |key: String, message: String| SceneError::Invalid {
        path: scene.path.clone(),
        key,
        message,
    };
    for (i, load) in scene.loads.iter().enumerate() {
        let key = |k: &str| format!("loads[{i}].{k}");
        if load.max_harmonic() > m_max {
            let k = match load {
                Load::Traction(_) | Load::Ring(_) => "harmonic",
                Load::Resultant(_) | Load::Point(_) => "force",
                Load::Motion(_) => "displacement",
            };
            return Err(invalid(
                key(k),
                format!(
                    "the load has a part of harmonic {} but the run solves harmonics 0..={m_max} only",
                    load.max_harmonic()
                ),
            ));
        }
        match load {
            Load::Traction(l) => {
                if l.harmonic == 0 && l.family == Family::Antisymmetric {
                    return Err(invalid(key("family"), ANTISYMMETRIC_ZERO.into()));
                }
                let curve = scene.curve(mesh, &l.on, &key("on"))?;
                let t = l.t;
                let field = move |r: f64, z: f64| [t[0].at(r, z), t[1].at(r, z), t[2].at(r, z)];
                let target = out[l.harmonic as usize].family_mut(l.family);
                add_curve_load(mesh, curve, l.harmonic, &field, target);
            }
            Load::Resultant(l) => {
                let curve = scene.curve(mesh, &l.on, &key("on"))?;
                let face = face_section(mesh, curve).map_err(|e| invalid(key("on"), e))?;
                let [fx, fy, fz] = l.force;
                let d = l.at_z.unwrap_or(face.z) - face.z;
                let (mx, my) = (-d * fy + l.moment[0], d * fx + l.moment[1]);
                let (a, j, torque) = (face.area, face.polar, l.torque);
                let inertia = 0.5 * j;
                let axial_torsion = move |r: f64, _: f64| [0.0, fz / a, torque * r / j];
                add_curve_load(mesh, curve, 0, &axial_torsion, &mut out[0].symmetric);
                if m_max >= 1 {
                    let sym = move |r: f64, _: f64| [fx / a, -my * r / inertia, -fx / a];
                    let anti = move |r: f64, _: f64| [fy / a, mx * r / inertia, -fy / a];
                    add_curve_load(mesh, curve, 1, &sym, &mut out[1].symmetric);
                    add_curve_load(mesh, curve, 1, &anti, &mut out[1].antisymmetric);
                }
            }
            Load::Ring(l) => {
                if l.harmonic == 0 && l.family == Family::Antisymmetric {
                    return Err(invalid(key("family"), ANTISYMMETRIC_ZERO.into()));
                }
                let nodes = scene.point_nodes(mesh, &l.on, &key("on"))?;
                let tol = tolerance(mesh);
                let cm = c_m(l.harmonic);
                for (r, copies) in point_locations(mesh, nodes) {
                    if r <= tol {
                        return Err(invalid(key("on"), RING_ON_AXIS.into()));
                    }
                    let f = [cm * r * l.f[0], cm * r * l.f[1], cm * r * l.f[2]];
                    add_nodal(&copies, f, out[l.harmonic as usize].family_mut(l.family));
                }
            }
            Load::Point(l) => {
                let nodes = scene.point_nodes(mesh, &l.on, &key("on"))?;
                let tol = tolerance(mesh);
                let [fx, fy, fz] = l.force;
                for (r, copies) in point_locations(mesh, nodes) {
                    if r > tol {
                        return Err(invalid(key("on"), point_off_axis(r)));
                    }
                    add_nodal(&copies, [0.0, fz, 0.0], &mut out[0].symmetric);
                    if m_max >= 1 {
                        add_nodal(&copies, [0.5 * fx, 0.0, -0.5 * fx], &mut out[1].symmetric);
                        add_nodal(&copies, [0.5 * fy, 0.0, -0.5 * fy], &mut out[1].antisymmetric);
                    }
                }
            }
            // Prescribed displacements: no force here ([`add_motions`]).
            Load::Motion(_) => {}
        }
    }
    add_body_forces(scene, mesh, !scene.has_initial_phase(), &mut out)?;
    Ok(out)
}

/// The self-weight of every material as harmonic-0 nodal forces (`3 n`,
/// node-major): the load of the initial phase.
pub fn gravity_load(scene: &Scene, mesh: &Mesh) -> Result<Vec<f64>, SceneError> {
    let mut out = vec![HarmonicLoads::zeros(0, mesh.nodes.len())];
    let mut only = scene.clone();
    only.seismic_coefficient = 0.0;
    add_body_forces(&only, mesh, true, &mut out)?;
    Ok(out.swap_remove(0).symmetric)
}

/// The self-weight (`-gamma` in z, harmonic 0; only if `gravity`) and the
/// seismic body force (`k_h gamma` in +x: harmonic 1, symmetric `(b_r,
/// b_theta) = (k_h gamma, -k_h gamma)`) of every cell whose material has a
/// unit weight.
fn add_body_forces(
    scene: &Scene,
    mesh: &Mesh,
    gravity: bool,
    out: &mut [HarmonicLoads],
) -> Result<(), SceneError> {
    let invalid = |key: String, message: String| SceneError::Invalid {
        path: scene.path.clone(),
        key,
        message,
    };
    let k_h = scene.seismic_coefficient;
    if !k_h.is_finite() {
        return Err(invalid(
            "seismic_coefficient".into(),
            "must be a finite number".into(),
        ));
    }
    let mut weights = Vec::with_capacity(mesh.bodies.len());
    for body in &mesh.bodies {
        let gamma = scene.materials.get(&body.name).map_or(0.0, |m| m.unit_weight);
        if !(gamma.is_finite() && gamma >= 0.0) {
            return Err(invalid(
                format!("materials.{}.unit_weight", body.name),
                format!("{gamma}: must be a finite number >= 0"),
            ));
        }
        weights.push(gamma);
    }
    if weights.iter().all(|&g| g == 0.0) {
        return Ok(());
    }
    if k_h != 0.0 && out.len() < 2 {
        return Err(invalid(
            "seismic_coefficient".into(),
            "a horizontal body force is harmonic 1: the run must solve harmonics 0..=1 at least".into(),
        ));
    }
    let mut fe = vec![0.0; 3 * MAX_CELL_NODES];
    let mut coords = Vec::with_capacity(MAX_CELL_NODES);
    let mut values = crate::elements::CellValues::with_default_rule(axijoint_mesh::CellKind::Quad9);
    for cell in &mesh.cells {
        let force = BodyForce {
            gamma: weights[cell.body],
            k_h,
            gravity,
            water: scene.water.as_ref(),
        };
        if force.gamma == 0.0 {
            continue;
        }
        coords.clear();
        coords.extend(cell.nodes.iter().map(|&k| mesh.nodes[k]));
        let fe = &mut fe[..3 * cell.nodes.len()];
        for m in 0..2 {
            if !cell_body_load(&mut values, cell.kind, &coords, m, &force, fe) {
                continue;
            }
            let target = &mut out[m as usize].symmetric;
            for (i, &k) in cell.nodes.iter().enumerate() {
                for c in 0..3 {
                    target[3 * k + c] += fe[3 * i + c];
                }
            }
        }
    }
    Ok(())
}

/// The body force of one material: its unit weight, the seismic
/// coefficient, whether the weight acts (it loads the initial phase when
/// the scene has one) and the ground water (the weight buoyant below it).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BodyForce<'a> {
    pub(crate) gamma: f64,
    pub(crate) k_h: f64,
    pub(crate) gravity: bool,
    pub(crate) water: Option<&'a crate::scene::Water>,
}

/// The nodal forces `fe` of one cell's body force in harmonic `m` (its
/// symmetric family): the self-weight `-gamma` in z (m = 0, if `gravity`;
/// buoyant below the water table) and the seismic `k_h gamma` in +x
/// (m = 1, the whole mass). `false`, `fe` untouched, when the cell has
/// none in that harmonic.
pub(crate) fn cell_body_load(
    values: &mut crate::elements::CellValues,
    kind: axijoint_mesh::CellKind,
    coords: &[[f64; 2]],
    m: u32,
    force: &BodyForce,
    fe: &mut [f64],
) -> bool {
    let BodyForce {
        gamma,
        k_h,
        gravity,
        water,
    } = *force;
    if gamma == 0.0 || !(m == 0 && gravity || m == 1 && k_h != 0.0) {
        return false;
    }
    fe.fill(0.0);
    if m == 0 {
        let bz = |x: [f64; 2]| [0.0, crate::scene::Water::body_force_z(water, gamma, x[1]), 0.0];
        body_force_load(values, kind, coords, m, bz, fe);
    } else {
        let b = [k_h * gamma, 0.0, -k_h * gamma];
        body_force_load(values, kind, coords, m, |_| b, fe);
    }
    true
}

pub(crate) const ANTISYMMETRIC_ZERO: &str =
    "harmonic 0 has no antisymmetric family: use \"symmetric\" (its t_theta / f_theta is the torsional part)";

pub(crate) const RING_ON_AXIS: &str =
    "a ring load needs r > 0 (force per unit circumferential length); on the axis use a point load, {\"type\": \"point\", \"force\": [Fx, Fy, Fz]}";

pub(crate) fn point_off_axis(r: f64) -> String {
    format!("a point load must be on the axis r = 0 (this point is at r = {r}); off the axis use a ring load")
}

/// Cartesian resultants of nodal forces, about `(0, 0, z_ref)` (the
/// formulas of the module doc; harmonics other than 0 and 1 have none).
///
/// ```
/// use axijoint_mesh::Mesh;
/// use axijoint_solver::loads::{load_resultants, HarmonicLoads};
/// // One node at r = 1, z = 2, harmonic 1 symmetric: f_r = 3, f_theta = -1.
/// let mesh = Mesh { nodes: vec![[1.0, 2.0]], ..Mesh::default() };
/// let mut h1 = HarmonicLoads::zeros(1, 1);
/// h1.symmetric.copy_from_slice(&[3.0, 0.0, -1.0]);
/// let res = load_resultants(&[h1], &mesh, 0.0);
/// assert_eq!(res.force, [4.0, 0.0, 0.0]);
/// assert_eq!(res.moment, [0.0, 8.0, 0.0]); // z * Fx
/// ```
pub fn load_resultants(loads: &[HarmonicLoads], mesh: &Mesh, z_ref: f64) -> Resultants {
    let mut out = Resultants {
        force: [0.0; 3],
        moment: [0.0; 3],
    };
    for h in loads {
        for (i, &x) in mesh.nodes.iter().enumerate() {
            let dofs = DOF_PER_NODE * i..DOF_PER_NODE * (i + 1);
            let s = &h.symmetric[dofs.clone()];
            let a = &h.antisymmetric[dofs];
            add_node_resultant(h.m, x, [s[0], s[1], s[2]], [a[0], a[1], a[2]], z_ref, &mut out);
        }
    }
    out
}

/// Adds to `out` the Cartesian resultant about `(0, 0, z_ref)` of the
/// harmonic-`m` nodal forces `s` (symmetric family) and `a`
/// (antisymmetric) of a node at `[r, z]`, `(f_r, f_z, f_theta)` each; only
/// harmonics 0 and 1 have one.
pub fn add_node_resultant(
    m: u32,
    [r, z]: [f64; 2],
    s: [f64; 3],
    a: [f64; 3],
    z_ref: f64,
    out: &mut Resultants,
) {
    let d = z - z_ref;
    let Resultants { force, moment } = out;
    match m {
        0 => {
            force[2] += s[1];
            moment[2] += r * s[2];
        }
        1 => {
            force[0] += s[0] - s[2];
            moment[1] += d * (s[0] - s[2]) - r * s[1];
            force[1] += a[0] - a[2];
            moment[0] += -d * (a[0] - a[2]) + r * a[1];
        }
        _ => {}
    }
}
