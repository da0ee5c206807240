//! Degrees of freedom: supports eliminated, the axis conditions of every
//! harmonic expressed as pinned variables of one shared numbering.
//!
//! On the axis (r = 0) the unknowns (u, v, w) of a node are replaced by
//! (p, v, q) with `u = p + q`, `w = q - p`. The single-valuedness conditions
//! (docs/theory.md section 4) then only pin variables:
//!
//! | m | condition | pinned |
//! |---|---|---|
//! | 0 | u = w = 0 | p, q |
//! | 1 | v = 0, u + w = 0 | v, q |
//! | >= 2 | u = v = w = 0 | p, v, q |
//!
//! so every harmonic shares one sparsity pattern and one symbolic
//! factorization; pinned variables get an identity row. A support on r or
//! theta at an axis node fixes both p and q: there u_r and u_theta describe
//! the same lateral displacement.

use axijoint_mesh::Mesh;

/// Displacement component of a node.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Component {
    /// Radial, u_r.
    R,
    /// Axial, u_z.
    Z,
    /// Circumferential, u_theta.
    Theta,
}

impl Component {
    /// All three, in DOF order.
    pub const ALL: [Component; 3] = [Component::R, Component::Z, Component::Theta];

    /// Index within a node's DOFs.
    pub fn index(self) -> usize {
        self as usize
    }
}

/// A variable that an axis node contributes, pinned per harmonic.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum AxisVar {
    P,
    V,
    Q,
}

impl AxisVar {
    fn pinned(self, m: u32) -> bool {
        match m {
            0 => matches!(self, AxisVar::P | AxisVar::Q),
            1 => matches!(self, AxisVar::V | AxisVar::Q),
            _ => true,
        }
    }
}

/// One equation term of a node DOF: `u_dof = sum coef * x[eq]`.
pub type Term = (usize, f64);

/// Numbering of the unknowns shared by all harmonics.
#[derive(Clone, Debug)]
pub struct DofMap {
    /// Terms of each node DOF (`3 * node + component`): none when supported,
    /// one off the axis, up to two on it.
    terms: Vec<[Option<Term>; 2]>,
    /// Equations that belong to axis variables, with their kind.
    axis: Vec<(usize, AxisVar)>,
    /// Number of equations.
    pub n_eq: usize,
    /// Number of nodes.
    pub n_nodes: usize,
}

impl DofMap {
    /// Numbers the unknowns of `mesh`; `fixed[3 * node + c]` marks supports
    /// (zero displacement in every harmonic). Nodes at r = 0 exactly are
    /// axis nodes ([`axijoint_mesh::validate()`] snaps them).
    pub fn new(mesh: &Mesh, fixed: &[bool]) -> DofMap {
        let n = mesh.nodes.len();
        assert_eq!(fixed.len(), 3 * n, "one support flag per node DOF");
        let mut terms = vec![[None, None]; 3 * n];
        let mut axis = Vec::new();
        let mut n_eq = 0;
        let mut next = |on: bool| {
            on.then(|| {
                n_eq += 1;
                n_eq - 1
            })
        };
        for (node, p) in mesh.nodes.iter().enumerate() {
            let f = &fixed[3 * node..3 * node + 3];
            if p[0] == 0.0 {
                let lateral_free = !f[0] && !f[2];
                let (pe, ve, qe) = (next(lateral_free), next(!f[1]), next(lateral_free));
                for (e, var) in [(pe, AxisVar::P), (ve, AxisVar::V), (qe, AxisVar::Q)] {
                    if let Some(e) = e {
                        axis.push((e, var));
                    }
                }
                if let (Some(pe), Some(qe)) = (pe, qe) {
                    terms[3 * node] = [Some((pe, 1.0)), Some((qe, 1.0))];
                    terms[3 * node + 2] = [Some((pe, -1.0)), Some((qe, 1.0))];
                }
                terms[3 * node + 1] = [ve.map(|e| (e, 1.0)), None];
            } else {
                for c in 0..3 {
                    terms[3 * node + c] = [next(!f[c]).map(|e| (e, 1.0)), None];
                }
            }
        }
        DofMap {
            terms,
            axis,
            n_eq,
            n_nodes: n,
        }
    }

    /// The equation terms of node DOF `dof = 3 * node + component`.
    pub fn terms(&self, dof: usize) -> impl Iterator<Item = Term> + '_ {
        self.terms[dof].iter().flatten().copied()
    }

    /// Whether node DOF `dof` is supported (no unknown).
    pub fn is_supported(&self, dof: usize) -> bool {
        self.terms[dof][0].is_none() && self.terms[dof][1].is_none()
    }

    /// Equations pinned to zero in harmonic `m` (axis conditions).
    pub fn pinned(&self, m: u32) -> Vec<bool> {
        let mut p = vec![false; self.n_eq];
        for &(e, var) in &self.axis {
            p[e] = var.pinned(m);
        }
        p
    }

    /// Equation-space right-hand side `b = T^T f` of a node-DOF load `f`,
    /// zero on the pinned equations.
    pub fn restrict(&self, f: &[f64], pinned: &[bool], b: &mut [f64]) {
        b.fill(0.0);
        for (dof, &fv) in f.iter().enumerate() {
            for (e, c) in self.terms(dof) {
                b[e] += c * fv;
            }
        }
        for (bv, &p) in b.iter_mut().zip(pinned) {
            if p {
                *bv = 0.0;
            }
        }
    }

    /// Node-DOF displacements `u = T x` of an equation-space solution.
    pub fn expand(&self, x: &[f64], u: &mut [f64]) {
        for (dof, uv) in u.iter_mut().enumerate() {
            *uv = self.terms(dof).map(|(e, c)| c * x[e]).sum();
        }
    }
}
