//! Zero-thickness joint elements of harmonic m (the paper's Eqs. 1-9).
//!
//! ```text
//!   top:     t0 ---- t2 ---- t1        eta (normal, bottom -> top)
//!            ||      ||      ||         ^
//!   bottom:  b0 ---- b2 ---- b1         |--> xi (tangent, b0 -> b1)
//! ```
//!
//! Element DOFs: `[bottom nodes..., top nodes...]`, each `(u_r, u_z,
//! u_theta)`; 12 for [`JointKind::Lin4`], 18 for [`JointKind::Lin6`]. At a
//! point with face shape values `N_i`, unit tangent `xi = (cos a, sin a)`
//! (a = alpha, the angle from the r axis) and normal `eta = (-sin a, cos a)`:
//!
//! ```text
//! d_global = sum_i N_i (u_top_i - u_bottom_i)            (r, z, theta)
//! d_local  = T d_global,   T = |  cos a   sin a   0 |     (xi, eta, theta)
//!                              | -sin a   cos a   0 |
//!                              |  0       0       1 |
//! p = k d_local,           k = diag(k_xi, k_eta, k_theta)
//! ```
//!
//! so `d_local = T B u_elem` with `B = [-N_1 I, ..., -N_n I, N_1 I, ..., N_n I]`
//! (3 x 6n), and the stiffness (kernel `B^T T^T k T B r`) is
//!
//! ```text
//! K = c_m * sum_q B(q)^T T(q)^T k T(q) B(q) r(q) |dx/ds|(q) w_q
//! ```
//!
//! `T^T K T` of the paper (its Eqs. 8-9) is the same matrix: here `T` is
//! applied per integration point, which also covers curved (Lin6) joints
//! whose tangent turns along the element.

use crate::elements::{c_m, zero_matrix, DOF_PER_NODE};
use axijoint_mesh::geometry::edge_length_and_lateral;
use axijoint_mesh::quadrature::{gauss_legendre, gauss_lobatto, Rule1D};
use axijoint_mesh::shapes::MAX_EDGE_NODES;
use axijoint_mesh::{EdgeKind, JointKind};
use nalgebra::DMatrix;

/// Why joint data was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum JointError {
    /// A spring stiffness is negative or not finite.
    #[error("joint stiffness {name} = {value} is not allowed: it must be a finite number >= 0")]
    Stiffness {
        /// `k_xi`, `k_eta` or `k_theta`.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// The rule has a number of points no table has.
    #[error("joint integration rule {rule:?} is not available: Gauss takes 1 to 5 points, Lobatto 2 to 5")]
    Rule {
        /// The rule asked for.
        rule: JointRule,
    },
}

/// Spring stiffnesses of a joint, force / area / length (e.g. MPa/m):
/// tangential `k_xi`, normal `k_eta`, circumferential `k_theta`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointSprings {
    /// Tangential (along xi) stiffness.
    pub k_xi: f64,
    /// Normal (along eta) stiffness.
    pub k_eta: f64,
    /// Circumferential (along theta) stiffness.
    pub k_theta: f64,
}

impl JointSprings {
    /// Validated springs: each finite and >= 0 (k = 0 is a joint that
    /// transmits nothing in that direction).
    pub fn new(k_xi: f64, k_eta: f64, k_theta: f64) -> Result<Self, JointError> {
        let k = JointSprings { k_xi, k_eta, k_theta };
        k.validate()?;
        Ok(k)
    }

    /// Checks that each stiffness is finite and >= 0.
    pub fn validate(&self) -> Result<(), JointError> {
        for (name, value) in [
            ("k_xi", self.k_xi),
            ("k_eta", self.k_eta),
            ("k_theta", self.k_theta),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(JointError::Stiffness { name, value });
            }
        }
        Ok(())
    }

    /// `k d` for a local relative displacement `d = (d_xi, d_eta, d_theta)`.
    pub fn traction(&self, d: [f64; 3]) -> [f64; 3] {
        [self.k_xi * d[0], self.k_eta * d[1], self.k_theta * d[2]]
    }
}

/// Integration rule along a joint element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointRule {
    /// The paper's Eq. 7: one point at the element centre (s = 0) with the
    /// centre shape values (Lin4: `N = (1/2, 1/2)`; Lin6: the quadratic
    /// shapes at the centre, `N = (0, 0, 1)`), `r = r_bar` (radius of the
    /// centre) and weight = element length L. Rank-deficient by design
    /// (`K = pi r_bar L k / 4` blocks for Lin4, m >= 1).
    Paper,
    /// Gauss-Legendre with n points, n = 1..=5.
    Gauss(usize),
    /// Gauss-Lobatto with n points (the ends included: nodal integration for
    /// n = 2 on Lin4, n = 3 on Lin6), n = 2..=5.
    Lobatto(usize),
}

impl JointRule {
    /// The default full rule: Gauss with 2 points for Lin4 (exact for
    /// `N_i N_j r`, degree 3) and 3 points for Lin6 (degree 5: exact on
    /// straight joints).
    pub fn default_for(kind: JointKind) -> Self {
        match kind {
            JointKind::Lin4 => JointRule::Gauss(2),
            JointKind::Lin6 => JointRule::Gauss(3),
        }
    }

    /// Checks that the rule exists.
    pub fn validate(self) -> Result<(), JointError> {
        match self {
            JointRule::Paper => Ok(()),
            JointRule::Gauss(_) | JointRule::Lobatto(_) => {
                self.table().map(|_| ()).ok_or(JointError::Rule { rule: self })
            }
        }
    }

    fn table(self) -> Option<Rule1D> {
        match self {
            JointRule::Paper => None,
            JointRule::Gauss(n) => gauss_legendre(n),
            JointRule::Lobatto(n) => gauss_lobatto(n),
        }
    }
}

/// One integration point of a joint element, everything the nonlinear
/// iteration needs to evaluate and release tractions there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointPoint {
    /// Reference coordinate s in [-1, 1].
    pub s: f64,
    /// Face shape values `N_i` (the first `n_face` entries are used).
    pub n: [f64; MAX_EDGE_NODES],
    /// Number of nodes per face: 2 (Lin4) or 3 (Lin6).
    pub n_face: usize,
    /// Position (r, z).
    pub position: [f64; 2],
    /// Unit tangent xi = (cos alpha, sin alpha); the normal is
    /// eta = (-sin alpha, cos alpha).
    pub tangent: [f64; 2],
    /// Angle alpha from the r axis to xi, radians.
    pub alpha: f64,
    /// Radius r of the point (the paper's r_bar for [`JointRule::Paper`]).
    pub r: f64,
    /// Length measure `w_q |dx/ds|` (without r and c_m): the weights of an
    /// element sum to its length.
    pub weight: f64,
}

impl JointPoint {
    /// Area measure per unit `c_m`: `r * weight`, so that
    /// `c_m * sum_q area(q)` is the swept area for m = 0 (`2 pi Integral(r ds)`).
    pub fn area(&self) -> f64 {
        self.r * self.weight
    }
}

/// The face line kind of a joint kind.
fn face_kind(kind: JointKind) -> EdgeKind {
    match kind {
        JointKind::Lin4 => EdgeKind::Lin2,
        JointKind::Lin6 => EdgeKind::Lin3,
    }
}

/// The point at s with weight `w * |dx/ds|` (or `weight` when given).
fn point_at(face: EdgeKind, coords: &[[f64; 2]], s: f64, w: f64, weight: Option<f64>) -> JointPoint {
    let nf = face.n_nodes();
    let (mut n, mut dn) = ([0.0; MAX_EDGE_NODES], [0.0; MAX_EDGE_NODES]);
    face.eval_n(s, &mut n);
    face.eval_dn(s, &mut dn);
    let (mut x, mut t) = ([0.0; 2], [0.0; 2]);
    for i in 0..nf {
        for a in 0..2 {
            x[a] += n[i] * coords[i][a];
            t[a] += dn[i] * coords[i][a];
        }
    }
    let jac = t[0].hypot(t[1]);
    let tangent = [t[0] / jac, t[1] / jac];
    JointPoint {
        s,
        n,
        n_face: nf,
        position: x,
        tangent,
        alpha: tangent[1].atan2(tangent[0]),
        r: x[0],
        weight: weight.unwrap_or(w * jac),
    }
}

/// Integration points of a joint element with bottom-face nodes
/// `bottom_coords` (start, end, then middle for Lin6).
///
/// # Panics
/// If `rule` does not exist (check [`JointRule::validate`] when reading
/// input) or the face has zero length.
pub fn joint_points(kind: JointKind, bottom_coords: &[[f64; 2]], rule: JointRule) -> Vec<JointPoint> {
    let face = face_kind(kind);
    match rule {
        JointRule::Paper => {
            let length = edge_length_and_lateral(face, bottom_coords).0;
            vec![point_at(face, bottom_coords, 0.0, 0.0, Some(length))]
        }
        _ => {
            let table = rule
                .table()
                .unwrap_or_else(|| panic!("{}", JointError::Rule { rule }));
            table
                .iter()
                .map(|(s, w)| point_at(face, bottom_coords, s, w, None))
                .collect()
        }
    }
}

/// Relative displacement `d = u_top - u_bottom` at `point`, in local axes
/// `(d_xi, d_eta, d_theta)`; `d_eta > 0` opens the joint. `u_elem` is the
/// element vector `[bottom nodes..., top nodes...]`.
pub fn relative_displacement(point: &JointPoint, u_elem: &[f64]) -> [f64; 3] {
    let nf = point.n_face;
    let mut d = [0.0; 3];
    for i in 0..nf {
        for (c, dc) in d.iter_mut().enumerate() {
            let jump = u_elem[DOF_PER_NODE * (nf + i) + c] - u_elem[DOF_PER_NODE * i + c];
            *dc += point.n[i] * jump;
        }
    }
    let [c, s] = point.tangent;
    [c * d[0] + s * d[1], -s * d[0] + c * d[1], d[2]]
}

/// Adds the nodal forces of a local traction `p = (p_xi, p_eta, p_theta)` at
/// `point` to `out` (element vector, `[bottom..., top...]`):
///
/// ```text
/// out += scale * B^T T^T p * r * weight
/// ```
///
/// the top face pulled along `+p`, the bottom along `-p`. With
/// `scale = c_m(m)` and `p = k d` the sum over the points of an element is
/// `K u_elem` of [`joint_stiffness`]; with the released part of the
/// traction it is the unbalanced force of the stress-transfer iteration.
pub fn add_traction_forces(point: &JointPoint, p: [f64; 3], scale: f64, out: &mut [f64]) {
    let nf = point.n_face;
    let [c, s] = point.tangent;
    let g = [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]];
    let f = scale * point.area();
    for i in 0..nf {
        for (k, gk) in g.iter().enumerate() {
            let fi = f * point.n[i] * gk;
            out[DOF_PER_NODE * (nf + i) + k] += fi;
            out[DOF_PER_NODE * i + k] -= fi;
        }
    }
}

/// Stiffness of a joint element for harmonic `m` (kernel `B^T T^T k T B r`),
/// see the module doc; DOFs `[bottom nodes..., top nodes...]` x
/// `(u_r, u_z, u_theta)`. `out` is resized to 6n x 6n if needed and
/// overwritten.
///
/// ```
/// use axijoint_mesh::JointKind;
/// use axijoint_solver::elements::{joint_stiffness, JointRule, JointSprings};
/// use nalgebra::DMatrix;
/// // Horizontal joint r = 1..2 at z = 0, the paper's one-point rule, m = 1:
/// // K[0][0] = pi r_bar L k_xi / 4.
/// let k = JointSprings::new(10.0, 20.0, 30.0).unwrap();
/// let mut kmat = DMatrix::zeros(12, 12);
/// joint_stiffness(JointKind::Lin4, &[[1.0, 0.0], [2.0, 0.0]], &k, 1, JointRule::Paper, &mut kmat);
/// let expected = std::f64::consts::PI * 1.5 * 1.0 * 10.0 / 4.0;
/// assert!((kmat[(0, 0)] - expected).abs() < 1e-12);
/// ```
///
/// # Panics
/// As [`joint_points`].
pub fn joint_stiffness(
    kind: JointKind,
    bottom_coords: &[[f64; 2]],
    k: &JointSprings,
    m: u32,
    rule: JointRule,
    out: &mut DMatrix<f64>,
) {
    joint_stiffness_scaled(kind, bottom_coords, k, c_m(m), rule, out);
}

/// [`joint_stiffness`] with `c_m` replaced by `cm`: `cm = 1` gives the
/// matrix that every harmonic multiplies by its `c_m`.
pub fn joint_stiffness_scaled(
    kind: JointKind,
    bottom_coords: &[[f64; 2]],
    k: &JointSprings,
    cm: f64,
    rule: JointRule,
    out: &mut DMatrix<f64>,
) {
    let nf = face_kind(kind).n_nodes();
    let ndof = 2 * DOF_PER_NODE * nf;
    zero_matrix(out, ndof, ndof);
    for point in joint_points(kind, bottom_coords, rule) {
        let [c, s] = point.tangent;
        // T^T k T in global (r, z, theta) components
        let krr = c * c * k.k_xi + s * s * k.k_eta;
        let kzz = s * s * k.k_xi + c * c * k.k_eta;
        let krz = c * s * (k.k_xi - k.k_eta);
        let kg = [[krr, krz, 0.0], [krz, kzz, 0.0], [0.0, 0.0, k.k_theta]];
        let f = cm * point.area();
        for a in 0..2 * nf {
            let na = if a < nf { -point.n[a] } else { point.n[a - nf] };
            for b in 0..2 * nf {
                let nb = if b < nf { -point.n[b] } else { point.n[b - nf] };
                let fab = f * na * nb;
                for (i, row) in kg.iter().enumerate() {
                    for (j, kij) in row.iter().enumerate() {
                        out[(DOF_PER_NODE * a + i, DOF_PER_NODE * b + j)] += fab * kij;
                    }
                }
            }
        }
    }
}
