//! The fixed data of the stiff-joint preconditioner (formed in `banded`,
//! kept by `Setup` for the whole run).

use faer::sparse::linalg::lu::SymbolicLu;
use nalgebra::{DMatrix, Matrix3};
use std::sync::Arc;

/// Per pair with jumps a member cannot have, the projector onto them.
pub(super) type NullBlocks = Vec<(usize, Matrix3<f64>)>;

/// The preconditioner's fixed data, formed once per run
/// (`Setup::interface`).
pub(super) struct Interface {
    /// `Z_m` per harmonic index, order `n = 3 n_j` (kept with the factors:
    /// [`crate::linear::Model::joint_inverse`]).
    pub(super) z: Vec<Arc<DMatrix<f64>>>,
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
    /// Every (harmonic index, family).
    pub(super) members: Vec<(usize, usize)>,
    /// `(a, a, b)` of each member at each section (section-major), for
    /// `D_r` applied through the sections.
    pub(super) phi: Vec<[f64; 3]>,
    /// The interface's Schur complement on the pair jumps, per distinct
    /// member kind: `(Z_r' + N)^-1`, `Z_r'` the member's `Z_r` on the
    /// components it uses and N the projector onto the jumps it cannot
    /// have (a component its basis lacks at m = 0, a pair on the axis).
    pub(super) schur: Vec<DMatrix<f64>>,
    /// The index into `schur` of every member.
    pub(super) schur_of: Vec<usize>,
    /// Per member, the pairs with such jumps and N there (3 x 3).
    pub(super) null: Vec<NullBlocks>,
    /// The sparse pattern of the banded system and its symbolic LU.
    pub(super) banded: Banded,
}

/// The pattern of the banded interface system over every member, in the
/// coupled system's unknowns (member-major, `n_r` per member): the
/// entries between the pairs of one joint point, for every two members.
pub(super) struct Banded {
    pub(super) n: usize,
    pub(super) col_ptr: Vec<usize>,
    pub(super) row_idx: Vec<usize>,
    /// The Schur complements' entries in the pattern (the constant part).
    pub(super) base: Vec<f64>,
    /// Per point, where its blocks start in `slot` (`members^2` blocks of
    /// `(3 n_f)^2` entries, column-major within each block).
    pub(super) slot_start: Vec<usize>,
    /// The value index of every entry of every point block.
    pub(super) slot: Vec<u32>,
    pub(super) symbolic: Option<SymbolicLu<usize>>,
}
