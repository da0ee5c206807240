//! The fixed data of the stiff-joint preconditioner (formed in
//! `precondition`, kept by `Setup` for the whole run).

use nalgebra::DMatrix;

/// The preconditioner's fixed data, formed once per run
/// (`Setup::interface`).
pub(super) struct Interface {
    /// `Z_m` per harmonic index, order `n = 3 n_j`.
    pub(super) z: Vec<DMatrix<f64>>,
    /// `Z_m C^T` (n x n_r) and `Z_r = C Z_m C^T` (n_r x n_r), C the relative
    /// displacement of each node pair (top minus bottom), `n_r = 3 pairs`.
    pub(super) zc: Vec<DMatrix<f64>>,
    pub(super) zr: Vec<DMatrix<f64>>,
    /// The node pairs (bottom, top) in joint-node numbering.
    pub(super) pairs: Vec<(usize, usize)>,
    /// Per point: its pairs, `B_r` (3 x 3 n_f, the relative displacement of
    /// its pairs' jumps) and `G_r` (3 n_f x 3, the pair forces of a
    /// traction, applied to the top node and opposite to the bottom one).
    pub(super) point_pairs: Vec<Vec<usize>>,
    pub(super) b: Vec<DMatrix<f64>>,
    pub(super) g: Vec<DMatrix<f64>>,
    /// Whether the coupled system is small enough for its dense LU
    /// (`members x n_r <= coupled_max`): the fallback when GMRES fails.
    pub(super) dense_allowed: bool,
    /// Every (harmonic index, family).
    pub(super) members: Vec<(usize, usize)>,
    /// `(a, a, b)` of each member at each section (section-major), for
    /// `D_r` applied through the sections.
    pub(super) phi: Vec<[f64; 3]>,
}
