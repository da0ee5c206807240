//! The solution as a field: locate points in the meridional mesh and
//! synthesize displacements and stresses at any theta, body by body.

use axijoint_mesh::shapes::MAX_CELL_NODES;
use axijoint_mesh::{geometry::jacobian, CellKind, Mesh};
use axijoint_solver::elements::StrainPoint;
use axijoint_solver::material::Elastic;
use axijoint_solver::scene::{InitialStress, Water};
use axijoint_solver::solution::Displacements;
use rstar::{RTree, RTreeObject, AABB};

/// The nodal values of `u` (3 per node) at `nodes`, into `out`.
pub(crate) fn gather(u: &[f64], nodes: &[usize], out: &mut [f64]) {
    for (o, &n) in out.chunks_exact_mut(3).zip(nodes) {
        o.copy_from_slice(&u[3 * n..3 * n + 3]);
    }
}

/// A cell's bounding box in the R-tree.
struct CellBox {
    cell: usize,
    envelope: AABB<[f64; 2]>,
}

impl RTreeObject for CellBox {
    type Envelope = AABB<[f64; 2]>;
    fn envelope(&self) -> Self::Envelope {
        self.envelope
    }
}

/// A point found in a cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Location {
    /// Cell index.
    pub cell: usize,
    /// Reference coordinates in the cell.
    pub xi: [f64; 2],
}

/// Spatial index of the cells (R-tree of bounding boxes, then Newton on the
/// element map): no linear scan per point.
pub struct Locator {
    tree: RTree<CellBox>,
    tol: f64,
}

impl Locator {
    /// Indexes the cells of `mesh`.
    pub fn new(mesh: &Mesh) -> Locator {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &mesh.nodes {
            for a in 0..2 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        let tol = 1e-9 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
        let boxes = mesh
            .cells
            .iter()
            .enumerate()
            .map(|(c, cell)| {
                let (mut a, mut b) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
                for &n in &cell.nodes {
                    for k in 0..2 {
                        a[k] = a[k].min(mesh.nodes[n][k] - tol);
                        b[k] = b[k].max(mesh.nodes[n][k] + tol);
                    }
                }
                CellBox {
                    cell: c,
                    envelope: AABB::from_corners(a, b),
                }
            })
            .collect();
        Locator {
            tree: RTree::bulk_load(boxes),
            tol,
        }
    }

    /// Every cell containing `p` (several on element edges), in cell order.
    pub fn locate_all(&self, mesh: &Mesh, p: [f64; 2]) -> Vec<Location> {
        let mut found: Vec<Location> = self
            .tree
            .locate_in_envelope_intersecting(AABB::from_point(p))
            .filter_map(|b| inverse_map(mesh, b.cell, p, self.tol).map(|xi| Location { cell: b.cell, xi }))
            .collect();
        found.sort_by_key(|l| l.cell);
        found
    }
}

/// Reference coordinates of `p` in `cell`, if inside (Newton on x(xi)).
pub fn inverse_map(mesh: &Mesh, cell: usize, p: [f64; 2], tol: f64) -> Option<[f64; 2]> {
    let c = &mesh.cells[cell];
    let coords: Vec<[f64; 2]> = c.nodes.iter().map(|&n| mesh.nodes[n]).collect();
    let nn = c.kind.n_nodes();
    let (mut n, mut dn) = ([0.0; 9], [[0.0; 2]; 9]);
    let mut xi = c.kind.ref_centre();
    for _ in 0..30 {
        c.kind.eval_n(xi, &mut n[..nn]);
        c.kind.eval_dn(xi, &mut dn[..nn]);
        let mut x = [0.0; 2];
        for i in 0..nn {
            x[0] += n[i] * coords[i][0];
            x[1] += n[i] * coords[i][1];
        }
        let (j, det) = jacobian(c.kind, &coords, &dn[..nn]);
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let (rx, ry) = (p[0] - x[0], p[1] - x[1]);
        // j = [[dr/dxi, dr/deta], [dz/dxi, dz/deta]]
        let dxi = (j[1][1] * rx - j[0][1] * ry) / det;
        let deta = (-j[1][0] * rx + j[0][0] * ry) / det;
        xi = [xi[0] + dxi, xi[1] + deta];
        if dxi.abs() + deta.abs() < 1e-13 {
            break;
        }
        if xi[0].abs() > 10.0 || xi[1].abs() > 10.0 {
            return None;
        }
    }
    // Inside, with a tolerance scaled from length to the reference cell.
    let h = coords.iter().fold(0.0f64, |a, q| {
        a.max((q[0] - coords[0][0]).hypot(q[1] - coords[0][1]))
    });
    let t = 1e-7_f64.max(4.0 * tol / h.max(f64::MIN_POSITIVE));
    let inside = if c.kind.n_corners() == 3 {
        xi[0] >= -t && xi[1] >= -t && xi[0] + xi[1] <= 1.0 + t
    } else {
        xi[0].abs() <= 1.0 + t && xi[1].abs() <= 1.0 + t
    };
    inside.then_some(xi)
}

pub use axijoint_solver::elements::STRESS_NAMES;

/// Displacements and stresses of a solution.
pub struct Field<'a> {
    /// The mesh (joints inserted).
    pub mesh: &'a Mesh,
    /// Material per body.
    pub materials: &'a [Elastic],
    /// Amplitudes.
    pub u: &'a Displacements,
    /// The initial state the stresses start from (none: zero).
    pub initial: Option<Initial<'a>>,
}

/// The initial state of a solution: the stresses are `sigma_0` of the
/// bodies plus those of the initial phase's displacements plus those of
/// [`Field::u`], less the pore pressure `p I` with ground water (the
/// model's stress is effective, outputs are total).
#[derive(Clone)]
pub struct Initial<'a> {
    /// Initial stress and unit weight of each body (`None`: no initial
    /// stress).
    pub stress: Vec<Option<(InitialStress, f64)>>,
    /// The displacements of the initial phase (harmonic 0), if any.
    pub u: Option<&'a Displacements>,
    /// The ground water, if any.
    pub water: Option<Water>,
}

impl<'a> Initial<'a> {
    /// The initial state of a saved solution (`None` without an initial
    /// phase and without water).
    pub fn of(saved: &'a axijoint_solver::results::SavedSolution) -> Option<Initial<'a>> {
        let scene = &saved.header.scene;
        if saved.header.initial.is_none() && scene.water.is_none() {
            return None;
        }
        Some(Initial {
            stress: saved
                .mesh
                .bodies
                .iter()
                .map(|b| {
                    let m = scene.materials.get(&b.name)?;
                    m.initial_stress
                        .filter(|_| saved.header.initial.is_some())
                        .map(|s| (s, m.unit_weight))
                })
                .collect(),
            u: saved.initial_displacements.as_ref(),
            water: scene.water,
        })
    }
}

impl Field<'_> {
    /// `(u_r, u_z, u_theta)` at node `n`, angle `theta`.
    pub fn displacement(&self, n: usize, theta: f64) -> [f64; 3] {
        self.u.at(n, theta)
    }

    /// Cartesian `(ux, uy, uz)` at node `n`, angle `theta`.
    pub fn displacement_xyz(&self, n: usize, theta: f64) -> [f64; 3] {
        let [ur, uz, ut] = self.u.at(n, theta);
        let (s, c) = theta.sin_cos();
        [ur * c - ut * s, ur * s + ut * c, uz]
    }

    /// Stress `(sigma_r, sigma_z, sigma_theta, tau_rz, tau_rtheta,
    /// tau_ztheta)` at reference point `xi` of `cell`, angle `theta`, from
    /// the cell's own field (never averaged with a neighbour).
    pub fn stress(&self, cell: usize, xi: [f64; 2], theta: f64) -> [f64; 6] {
        let point = self.point(cell, xi);
        let mut out = self.stress_of(self.u, cell, &point, theta);
        if let Some(init) = &self.initial {
            for (o, v) in out.iter_mut().zip(self.sigma0(init, cell, &point)) {
                *o += v;
            }
            if let Some(u0) = init.u {
                for (o, v) in out.iter_mut().zip(self.stress_of(u0, cell, &point, theta)) {
                    *o += v;
                }
            }
        }
        out
    }

    /// The point `xi` of `cell`: shape values and gradients, evaluated once
    /// for every displacement and the initial stress there.
    fn point(&self, cell: usize, xi: [f64; 2]) -> StrainPoint {
        let c = &self.mesh.cells[cell];
        let mut coords = [[0.0; 2]; MAX_CELL_NODES];
        for (x, &n) in coords.iter_mut().zip(&c.nodes) {
            *x = self.mesh.nodes[n];
        }
        StrainPoint::new(c.kind, &coords[..c.nodes.len()], xi)
    }

    /// The stress of the displacements `u` alone.
    fn stress_of(&self, u: &Displacements, cell: usize, point: &StrainPoint, theta: f64) -> [f64; 6] {
        let mut out = [0.0; 6];
        self.each_stress(u, cell, point, |m, anti, s| {
            let (sin, cos) = (f64::from(m) * theta).sin_cos();
            let (a, b) = match (m, anti) {
                (0, _) => (1.0, 1.0),
                (_, false) => (cos, sin),
                (_, true) => (sin, -cos),
            };
            for k in 0..4 {
                out[k] += a * s[k];
            }
            out[4] += b * s[4];
            out[5] += b * s[5];
        });
        out
    }

    /// Calls `f(m, antisymmetric, stress amplitude)` for every harmonic and
    /// family of `u` with a displacement on `cell`, at `point`.
    fn each_stress(
        &self,
        u: &Displacements,
        cell: usize,
        point: &StrainPoint,
        mut f: impl FnMut(u32, bool, [f64; 6]),
    ) {
        let c = &self.mesh.cells[cell];
        let nn = c.nodes.len();
        let mat = &self.materials[c.body];
        let mut ue = [0.0; 3 * MAX_CELL_NODES];
        for h in &u.harmonics {
            for (amp, anti) in [(&h.symmetric, false), (&h.antisymmetric, true)] {
                if h.m == 0 && anti {
                    continue;
                }
                gather(amp, &c.nodes, &mut ue);
                if ue[..3 * nn].iter().all(|&v| v == 0.0) {
                    continue;
                }
                f(h.m, anti, point.stress(mat, h.m, &ue[..3 * nn]));
            }
        }
    }

    /// The initial stress `sigma_0` of `init` at `point` of `cell` (zero
    /// where the body has none).
    fn sigma0(&self, init: &Initial, cell: usize, point: &StrainPoint) -> [f64; 6] {
        let c = &self.mesh.cells[cell];
        let z: f64 = c
            .nodes
            .iter()
            .zip(point.n())
            .map(|(&k, ni)| ni * self.mesh.nodes[k][1])
            .sum();
        let mut s = match init.stress.get(c.body).copied().flatten() {
            Some((s0, gamma)) => s0.at(z, gamma, init.water.as_ref()),
            None => [0.0; 6],
        };
        if let Some(w) = &init.water {
            for v in &mut s[..3] {
                *v -= w.pressure(z);
            }
        }
        s
    }

    /// The ground water of the solution, if any.
    pub fn water(&self) -> Option<&Water> {
        self.initial.as_ref().and_then(|i| i.water.as_ref())
    }

    /// [`Field::stress`] at `xi` of `cell` as a trigonometric polynomial
    /// in theta: the coefficients of `1, cos t, sin t, ..., cos Mt, sin Mt`
    /// (at least `2 m_max + 1`; more when a harmonic above `m_max` is
    /// there), read off each harmonic's amplitude without sampling theta.
    pub fn stress_coefficients(&self, cell: usize, xi: [f64; 2], m_max: usize) -> Vec<[f64; 6]> {
        let point = self.point(cell, xi);
        let mut out = vec![[0.0; 6]; 2 * m_max + 1];
        self.add_coefficients(self.u, cell, &point, &mut out);
        if let Some(init) = &self.initial {
            for (o, v) in out[0].iter_mut().zip(self.sigma0(init, cell, &point)) {
                *o += v;
            }
            if let Some(u0) = init.u {
                self.add_coefficients(u0, cell, &point, &mut out);
            }
        }
        out
    }

    /// Adds the coefficients of the stress of `u` alone (as in
    /// [`Field::stress_of`]: in-plane components go with cos, the shears
    /// with theta with sin, for the symmetric family; the other way round,
    /// the shears negated, for the antisymmetric one).
    fn add_coefficients(&self, u: &Displacements, cell: usize, point: &StrainPoint, out: &mut Vec<[f64; 6]>) {
        self.each_stress(u, cell, point, |m, anti, s| {
            let m = m as usize;
            if out.len() < 2 * m + 1 {
                out.resize(2 * m + 1, [0.0; 6]);
            }
            if m == 0 {
                for (o, v) in out[0].iter_mut().zip(s) {
                    *o += v;
                }
                return;
            }
            let (cos, sin) = (2 * m - 1, 2 * m);
            let (in_plane, shear) = if anti { (sin, cos) } else { (cos, sin) };
            let sign = if anti { -1.0 } else { 1.0 };
            for k in 0..4 {
                out[in_plane][k] += s[k];
            }
            for k in 4..6 {
                out[shear][k] += sign * s[k];
            }
        });
    }

    /// Stress at the nodes of each cell, `(cell, local node) -> stress`:
    /// the element's own values at its nodes.
    pub fn cell_node_stress(&self, cell: usize, theta: f64) -> Vec<[f64; 6]> {
        let kind: CellKind = self.mesh.cells[cell].kind;
        kind.ref_coords()
            .iter()
            .map(|&xi| self.stress(cell, xi, theta))
            .collect()
    }
}
