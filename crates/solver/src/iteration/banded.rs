//! The stiff-joint preconditioner's fixed data ([`Interface`]) and its
//! banded interface system ([`BandedLu`]).
//!
//! The coupled interface system of [`super::precondition`],
//! `(I - D_r Z_r) w = r`, is solved in its Schur form: with `y = Z_r w`,
//!
//! ```text
//! H y = P r,   H = S - P D_r P,   w = S y
//! ```
//!
//! S the interface's Schur complement on the pair jumps of each member
//! (`Z_r^-1` on the jumps the member can have, the identity on the others)
//! and P the projector onto the jumps it can have. S is dense, the same for
//! every Newton step, and does not couple the harmonics; `D_r` (the joint
//! tangent, `k_a - k_t`) couples them, but only the pairs of one joint
//! point. The banded system keeps all of `D_r` and S's entries between the
//! pairs of one point:
//!
//! ```text
//! B = band(S) - P D_r P
//! ```
//!
//! a sparse matrix of `members x n_r` unknowns with about `(3 n_f
//! members)^2` entries per point, factorized by faer's sparse LU at each
//! Newton step's tangent (its symbolic analysis once per run). B is exact
//! where the joint is stiff (the joint's stiffness is all in `D_r`), so
//! GMRES on H preconditioned by B needs about ten iterations at every
//! stiffness from `k h / E` = 1 to 1e6 (measured on the pile in soil,
//! docs/stability.md); what it leaves out (the bodies' coupling of pairs
//! of different points) is bounded by the bodies' own stiffness.

use super::interface::{Banded, Interface, NullBlocks};
use super::setup::Setup;
use crate::elements::{add_traction_forces, relative_displacement};
use crate::fourier::Family;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::solvers::DenseSolveCore;
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, LuSymbolicParams, NumericLu};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{MatMut, Par, Side};
use nalgebra::{DMatrix, DVector, Matrix3, SymmetricEigen};
use rayon::prelude::*;
use std::collections::HashMap;

/// The families, in the order of the joint amplitudes.
const FAMILIES: [Family; 2] = [Family::Symmetric, Family::Antisymmetric];

/// A pair's jump direction counts as one it cannot have when the
/// compliance along it is below this fraction of the member's largest
/// (measured: 1e-16 on the axis, 1e-3 and above elsewhere).
const NULL_COMPLIANCE: f64 = 1e-10;

impl Interface {
    /// Forms `Z_m` for every harmonic, the point operators, the Schur
    /// complements and the banded pattern.
    pub(super) fn new(setup: &Setup) -> Self {
        let n = 3 * setup.joint_nodes.len();
        // The node pairs of every point (elements are [bottom..., top...]).
        let mut index = HashMap::new();
        let mut pairs = Vec::new();
        let point_pairs: Vec<Vec<usize>> = setup
            .points
            .iter()
            .enumerate()
            .map(|(i, info)| {
                let nf = info.point.n_face;
                let nl = &setup.local[i];
                (0..nf)
                    .map(|a| {
                        let key = (nl[a], nl[nf + a]);
                        *index.entry(key).or_insert_with(|| {
                            pairs.push(key);
                            pairs.len() - 1
                        })
                    })
                    .collect()
            })
            .collect();
        let nr = 3 * pairs.len();
        let (z, zc_zr): (Vec<_>, Vec<_>) = setup
            .factor_of
            .par_iter()
            .map(|factor| {
                let z = setup.model.joint_inverse(factor);
                // Z C^T: column (pair, c) = Z e_top - Z e_bottom (Z symmetric).
                let mut zc = DMatrix::<f64>::zeros(n, nr);
                for (q, &(bot, top)) in pairs.iter().enumerate() {
                    for c in 0..3 {
                        let col = z.column(3 * top + c) - z.column(3 * bot + c);
                        zc.set_column(3 * q + c, &col);
                    }
                }
                let mut zr = DMatrix::<f64>::zeros(nr, nr);
                for (q, &(bot, top)) in pairs.iter().enumerate() {
                    for c in 0..3 {
                        let row = zc.row(3 * top + c) - zc.row(3 * bot + c);
                        zr.set_row(3 * q + c, &row);
                    }
                }
                (z, (zc, zr))
            })
            .unzip();
        let (zc, zr): (Vec<_>, Vec<_>) = zc_zr.into_iter().unzip();
        let (mut b, mut g) = (Vec::new(), Vec::new());
        for info in &setup.points {
            // The top half of the element operators: the jumps of the pairs.
            let nf = info.point.n_face;
            let ne = 6 * nf;
            let mut bi = DMatrix::<f64>::zeros(3, 3 * nf);
            let mut unit = vec![0.0; ne];
            for k in 0..3 * nf {
                unit[3 * nf + k] = 1.0;
                let d = relative_displacement(&info.point, &unit);
                bi.set_column(k, &nalgebra::Vector3::from(d));
                unit[3 * nf + k] = 0.0;
            }
            let mut gi = DMatrix::<f64>::zeros(3 * nf, 3);
            for c in 0..3 {
                let mut t = [0.0; 3];
                t[c] = 1.0;
                let mut f = vec![0.0; ne];
                add_traction_forces(&info.point, t, 1.0, &mut f);
                gi.set_column(c, &DVector::from_column_slice(&f[3 * nf..]));
            }
            b.push(bi);
            g.push(gi);
        }
        let both = &setup.transfer.both;
        let members: Vec<(usize, usize)> = (0..setup.transfer.n_h)
            .flat_map(|h| (0..if both[h] { 2 } else { 1 }).map(move |f| (h, f)))
            .collect();
        let sections = setup.sections();
        let phi: Vec<[f64; 3]> = (0..sections.len())
            .flat_map(|s| {
                members.iter().map(move |&(h, f)| {
                    let (a, b) = setup.transfer.phi(s, h, FAMILIES[f]);
                    [a, a, b]
                })
            })
            .collect();
        // The components each member uses: its basis is not zero at every
        // section (m = 0: the symmetric family has no theta component, the
        // antisymmetric one only that).
        let nm = members.len();
        let used: Vec<[bool; 3]> = (0..nm)
            .map(|i| {
                [0, 1, 2].map(|c| {
                    (0..sections.len()).any(|s| phi[s * nm + i][c] != 0.0 && sections.weight[s] != 0.0)
                })
            })
            .collect();
        let mut kinds: Vec<(usize, [bool; 3])> = Vec::new();
        let schur_of: Vec<usize> = members
            .iter()
            .zip(&used)
            .map(|(&(h, _), &u)| {
                kinds.iter().position(|&k| k == (h, u)).unwrap_or_else(|| {
                    kinds.push((h, u));
                    kinds.len() - 1
                })
            })
            .collect();
        let formed: Vec<(DMatrix<f64>, NullBlocks)> = kinds
            .par_iter()
            .map(|&(h, u)| schur_complement(&zr[h], u))
            .collect();
        let (mut schur, mut kind_null) = (Vec::new(), Vec::new());
        for (s, nl) in formed {
            schur.push(s);
            kind_null.push(nl);
        }
        let null: Vec<_> = schur_of.iter().map(|&k| kind_null[k].clone()).collect();
        let banded = Banded::new(nm, nr, &point_pairs, &schur, &schur_of);
        Interface {
            z,
            zc,
            zr,
            pairs,
            point_pairs,
            b,
            g,
            members,
            phi,
            schur,
            schur_of,
            null,
            banded,
        }
    }
}

impl Interface {
    /// `out = S v` over every member (member-major, `n_r` each).
    pub(super) fn schur_apply(&self, v: &[f64], out: &mut [f64]) {
        let nr = 3 * self.pairs.len();
        out.par_chunks_mut(nr).enumerate().for_each(|(i, o)| {
            let s = &self.schur[self.schur_of[i]];
            let x = nalgebra::DVectorView::from_slice(&v[i * nr..(i + 1) * nr], nr);
            let mut y = nalgebra::DVectorViewMut::from_slice(o, nr);
            y.gemv(1.0, s, &x, 0.0);
        });
    }
}

/// `(Z' + N)^-1` and N per pair: `Z'` is `zr` on the components `used`
/// (zero elsewhere) and N the projector onto the directions of each pair
/// along which `Z'` has no compliance (a pair on the axis at m >= 1, the
/// components the member lacks), found from the pair's 3 x 3 block (`Z'`
/// is positive semi-definite, so a direction without compliance there is
/// one of its null space).
fn schur_complement(zr: &DMatrix<f64>, used: [bool; 3]) -> (DMatrix<f64>, NullBlocks) {
    let nr = zr.nrows();
    let mut a = zr.clone();
    for i in 0..nr {
        if !used[i % 3] {
            a.row_mut(i).fill(0.0);
            a.column_mut(i).fill(0.0);
        }
    }
    let scale = (0..nr).map(|i| a[(i, i)]).fold(0.0, f64::max);
    let mut null = Vec::new();
    for q in 0..nr / 3 {
        let block: Matrix3<f64> = a.fixed_view::<3, 3>(3 * q, 3 * q).into_owned();
        let eig = SymmetricEigen::new(0.5 * (block + block.transpose()));
        let mut n = Matrix3::zeros();
        for k in 0..3 {
            if eig.eigenvalues[k] <= NULL_COMPLIANCE * scale {
                let v = eig.eigenvectors.column(k);
                n += v * v.transpose();
            }
        }
        if n != Matrix3::zeros() {
            let mut view = a.fixed_view_mut::<3, 3>(3 * q, 3 * q);
            view += n;
            null.push((q, n));
        }
    }
    let mat = faer::MatRef::from_column_major_slice(a.as_slice(), nr, nr);
    let inverse = match mat.llt(Side::Lower) {
        Ok(llt) => llt.inverse(),
        // A null space that is not pair by pair (never seen): the LU's
        // inverse of the same matrix, regularized.
        Err(_) => {
            let mut reg = a.clone();
            for i in 0..nr {
                reg[(i, i)] += NULL_COMPLIANCE * scale;
            }
            faer::MatRef::from_column_major_slice(reg.as_slice(), nr, nr)
                .partial_piv_lu()
                .inverse()
        }
    };
    let s = DMatrix::from_fn(nr, nr, |i, j| 0.5 * (inverse[(i, j)] + inverse[(j, i)]));
    (s, null)
}

impl Banded {
    /// The pattern over `nm` members of `nr` pair unknowns each: every two
    /// unknowns of pairs of one point, of any two members.
    fn new(
        nm: usize,
        nr: usize,
        point_pairs: &[Vec<usize>],
        schur: &[DMatrix<f64>],
        schur_of: &[usize],
    ) -> Self {
        let n = nm * nr;
        let mut rows: Vec<Vec<usize>> = vec![Vec::new(); n];
        let local = |pp: &[usize], a: usize| 3 * pp[a / 3] + a % 3;
        for pp in point_pairs {
            let m = 3 * pp.len();
            for j in 0..nm {
                for b in 0..m {
                    let col = &mut rows[j * nr + local(pp, b)];
                    for i in 0..nm {
                        col.extend((0..m).map(|a| i * nr + local(pp, a)));
                    }
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        let mut row_idx = Vec::new();
        for col in &mut rows {
            col.sort_unstable();
            col.dedup();
            row_idx.extend_from_slice(col);
            col_ptr.push(row_idx.len());
        }
        let mut slot_start = Vec::with_capacity(point_pairs.len() + 1);
        let mut slot = Vec::new();
        for pp in point_pairs {
            slot_start.push(slot.len());
            let m = 3 * pp.len();
            for i in 0..nm {
                for j in 0..nm {
                    for b in 0..m {
                        let col = j * nr + local(pp, b);
                        let range = col_ptr[col]..col_ptr[col + 1];
                        for a in 0..m {
                            let row = i * nr + local(pp, a);
                            let at = row_idx[range.clone()]
                                .binary_search(&row)
                                .expect("in the pattern");
                            slot.push((range.start + at) as u32);
                        }
                    }
                }
            }
        }
        slot_start.push(slot.len());
        let mut base = vec![0.0; row_idx.len()];
        for col in 0..n {
            let j = col / nr;
            for k in col_ptr[col]..col_ptr[col + 1] {
                let row = row_idx[k];
                if row / nr == j {
                    base[k] = schur[schur_of[j]][(row % nr, col % nr)];
                }
            }
        }
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        // Supernodal: the pattern is dense blocks of `3 members` unknowns
        // per pair (measured on the pile in soil, order 2295: 3.6 ms per
        // LU against 14 ms simplicial, faer's choice).
        let params = LuSymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let symbolic = factorize_symbolic_lu(pattern, params).ok();
        Banded {
            n,
            col_ptr,
            row_idx,
            base,
            slot_start,
            slot,
            symbolic,
        }
    }
}

/// The banded system's values and LU at one tangent.
pub(super) struct BandedLu {
    values: Vec<f64>,
    numeric: NumericLu<usize, f64>,
    ok: bool,
}

impl BandedLu {
    pub(super) fn new() -> Self {
        BandedLu {
            values: Vec::new(),
            numeric: NumericLu::new(),
            ok: false,
        }
    }

    /// Factorizes `band(S) - P D_r P` at the joint tangents `coupled`: per
    /// point, `C_p(i, j)` (3 x 3 in the point's local axes) for every two
    /// members, `G_p C_p B_p` its pair block; whether the LU succeeded.
    pub(super) fn factorize(&mut self, fixed: &Interface, coupled: &[Vec<Matrix3<f64>>]) -> bool {
        let band = &fixed.banded;
        let nm = fixed.members.len();
        self.values.clone_from(&band.base);
        let mut gc = vec![0.0; 0];
        let mut e = vec![0.0; 0];
        for (p, c) in coupled.iter().enumerate() {
            if c.is_empty() {
                continue;
            }
            let pp = &fixed.point_pairs[p];
            let m = 3 * pp.len();
            let (g, b) = (&fixed.g[p], &fixed.b[p]);
            gc.resize(3 * m, 0.0);
            e.resize(m * m, 0.0);
            // Per member, the local pair positions with jumps it cannot have.
            let null_at = |i: usize| {
                fixed.null[i]
                    .iter()
                    .filter_map(|(q, n)| pp.iter().position(|x| x == q).map(|a| (a, n)))
                    .collect::<Vec<_>>()
            };
            let nulls: Vec<_> = (0..nm).map(null_at).collect();
            let slots = &band.slot[band.slot_start[p]..band.slot_start[p + 1]];
            for i in 0..nm {
                for j in 0..nm {
                    let cij = &c[i * nm + j];
                    // e = G C B (m x m), column-major.
                    for a in 0..m {
                        for q in 0..3 {
                            gc[a + m * q] = (0..3).map(|r| g[(a, r)] * cij[(r, q)]).sum();
                        }
                    }
                    for bb in 0..m {
                        for a in 0..m {
                            e[a + m * bb] = (0..3).map(|q| gc[a + m * q] * b[(q, bb)]).sum();
                        }
                    }
                    // P on both sides: the jumps a member cannot have.
                    for &(a, n) in &nulls[i] {
                        for col in 0..m {
                            let x = [0, 1, 2].map(|k| e[3 * a + k + m * col]);
                            for r in 0..3 {
                                e[3 * a + r + m * col] = x[r] - (0..3).map(|k| n[(r, k)] * x[k]).sum::<f64>();
                            }
                        }
                    }
                    for &(bb, n) in &nulls[j] {
                        for row in 0..m {
                            let x = [0, 1, 2].map(|k| e[row + m * (3 * bb + k)]);
                            for r in 0..3 {
                                e[row + m * (3 * bb + r)] =
                                    x[r] - (0..3).map(|k| x[k] * n[(k, r)]).sum::<f64>();
                            }
                        }
                    }
                    let block = &slots[(i * nm + j) * m * m..(i * nm + j + 1) * m * m];
                    for (&at, v) in block.iter().zip(&e) {
                        self.values[at as usize] -= v;
                    }
                }
            }
        }
        let Some(symbolic) = band.symbolic.as_ref() else {
            self.ok = false;
            return false;
        };
        let pattern =
            SymbolicSparseColMatRef::new_checked(band.n, band.n, &band.col_ptr, None, &band.row_idx);
        let mat = SparseColMatRef::new(pattern, &self.values);
        let mut mem =
            MemBuffer::new(symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()));
        self.ok = symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                mat,
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .is_ok();
        self.ok
    }

    /// `v <- B^-1 v` (the identity when the LU failed).
    pub(super) fn solve_in_place(&self, fixed: &Interface, v: &mut [f64]) {
        let Some(symbolic) = fixed.banded.symbolic.as_ref().filter(|_| self.ok) else {
            return;
        };
        let lu = LuRef::new_unchecked(symbolic, &self.numeric);
        let mut mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        let n = v.len();
        lu.solve_in_place_with_conj(
            faer::Conj::No,
            MatMut::from_column_major_slice_mut(v, n, 1),
            Par::Seq,
            MemStack::new(&mut mem),
        );
    }
}
