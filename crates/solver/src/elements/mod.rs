//! Element matrices and vectors of one Fourier harmonic m.
//!
//! | module | integrand | what |
//! |---|---|---|
//! | [`cell_values`] | `N`, `dN`, `r`, `w = w_q |det J|` | a cell's shape values and gradients at the points of a rule |
//! | [`section`] | `B_U^T sigma r`, `B_D^T sigma r` | a solid cell at one circumferential section: physical strain, nodal forces of a stress |
//! | [`solid`] | `c_m B^T D B r dr dz` | meridional solids T3, T6, Q4, Q8, Q9: stiffness, strain and stress |
//! | [`joint`] | `c_m B^T T^T k T B r ds` | zero-thickness joints Lin4, Lin6 (the paper's Eqs. 7-9) |
//! | [`traction`] | `c_m N^T t r ds` | consistent nodal loads of a boundary traction |
//!
//! Conventions shared by every element:
//! - 3 DOF per node in the order `(u_r, u_z, u_theta) = (u, v, w)`
//!   (amplitudes of harmonic m); element vectors are node-major,
//!   `[u0, v0, w0, u1, v1, w1, ...]`.
//! - The theta integral is done in closed form: `c_m` = [`c_m`]`(m)`,
//!   `2 pi` for m = 0 and `pi` for m >= 1 (`Integral(cos^2 m.th)` =
//!   `Integral(sin^2 m.th)` over one turn). Symmetric
//!   (`u cos, v cos, w sin`) and antisymmetric (`u sin, v sin, -w cos`)
//!   families give the same matrices.
//! - Every matrix is returned in the caller's `DMatrix`, resized only when
//!   its shape is wrong, so an assembly loop allocates once per element kind.

pub mod cell_values;
pub mod joint;
pub mod section;
pub mod solid;
pub mod traction;

pub use cell_values::{CellError, CellValues};
pub use joint::{
    add_traction_forces, joint_points, joint_stiffness, joint_stiffness_scaled, relative_displacement,
    JointError, JointPoint, JointRule, JointSprings,
};
pub use solid::{
    b_matrix, b_matrix_on_axis, body_force_load, point_strain, point_stress, solid_stiffness,
    solid_stiffness_bbar, solid_stiffness_terms, solid_stiffness_terms_bbar, strain_at, stress_at,
    stress_forces, SolidScratch, StrainPoint, STRESS_NAMES,
};
pub use traction::edge_load;

/// Degrees of freedom per node: `(u_r, u_z, u_theta)`.
pub const DOF_PER_NODE: usize = 3;

/// The circumferential factor `c_m = Integral(cos^2(m theta) d theta)` over
/// `[0, 2 pi]`: `2 pi` for m = 0, `pi` for m >= 1.
///
/// ```
/// use axijoint_solver::elements::c_m;
/// assert_eq!(c_m(0), 2.0 * std::f64::consts::PI);
/// assert_eq!(c_m(3), std::f64::consts::PI);
/// ```
pub fn c_m(m: u32) -> f64 {
    if m == 0 {
        2.0 * std::f64::consts::PI
    } else {
        std::f64::consts::PI
    }
}

/// Makes `out` an `rows x cols` matrix of zeros, allocating only if its shape
/// is wrong.
pub(crate) fn zero_matrix(out: &mut nalgebra::DMatrix<f64>, rows: usize, cols: usize) {
    if out.shape() == (rows, cols) {
        out.fill(0.0);
    } else {
        *out = nalgebra::DMatrix::zeros(rows, cols);
    }
}
