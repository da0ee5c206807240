//! One harmonic's Cholesky factor `K_m = P^T L L^T P` and its triangular
//! solves.
//!
//! faer computes the symbolic and numeric factorization; the solves run
//! here, column by column on faer's supernodal storage (read through its
//! public accessors), for two reasons:
//!
//! - The joint iteration's right-hand sides live on the joint nodes only,
//!   and only the joint-node displacements are needed. With the joint
//!   equations ordered last (`Model::new`), such a solve reads only the
//!   trailing block of L: 1-2 % of a full solve on Scene P at 6e3-3.6e5
//!   unknowns, with results equal to the full solve's (measured, and a test
//!   in `linear.rs`). faer has no solve restricted to a trailing block.
//! - One or two right-hand sides are interleaved and read L once; for full
//!   solves this loop measured as fast as faer's `solve_in_place` or faster
//!   (faer dispatches a dense kernel per supernode, and the supernodes of 2D
//!   meshes are small). Wide supernodes (at least [`DENSE_COLUMNS`]
//!   columns to solve: the joint block, the top separators) go to faer's
//!   dense triangular solve and product, which vectorize.
//!
//! - A full solve of such a right-hand side needs, beyond the trailing
//!   block, only the backward solve of the other columns, last first: a
//!   factor whose other columns are on disk ([`crate::spill`]) streams them
//!   in that order through a small window ([`solve_trailing_whole`]).
//!
//! A simplicial factor (faer's choice for small or very sparse matrices) is
//! solved by faer itself.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{solve_lower_triangular_in_place, solve_upper_triangular_in_place};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::linalg::cholesky::{
    supernodal::SymbolicSupernodalCholesky, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
};
use faer::{Accum, Conj, MatMut, MatRef, Par};

/// Supernodes with at least this many columns to solve use faer's dense
/// kernels (vectorized); narrower ones the column loop (no call overhead).
const DENSE_COLUMNS: usize = 32;

/// Solves `L L^T x = b` in place for `K` interleaved right-hand sides on
/// faer's supernodal lower factor `values`, for a `b` that is zero before
/// the permuted unknown `first`: `x[i - first][k]` holds unknown `i >= first`
/// (permuted order). The unknowns before `first` stay zero in the forward
/// solve and the backward solve of those from `first` on needs no others,
/// so only the trailing block of L is read. `values` may start at stored
/// value `offset` (a joint block, [`trailing_offset`]).
fn supernodal_solve<const K: usize>(
    sym: &SymbolicSupernodalCholesky<usize>,
    values: &[f64],
    offset: usize,
    x: &mut [[f64; K]],
    first: usize,
) {
    let (begin, end) = (sym.supernode_begin(), sym.supernode_end());
    let row_ptr = sym.col_ptr_for_row_idx();
    let val_ptr = sym.col_ptr_for_val();
    let rows = sym.row_idx();
    let n_s = sym.n_supernodes();
    // Supernode s: columns begin[s]..end[s] (c of them); a column-major
    // (c + p) x c block whose first c rows are the diagonal block and the
    // other p rows are the unknowns `rows[row_ptr[s]..][..p]`.
    let block = |s: usize| {
        let (start, c) = (begin[s], end[s] - begin[s]);
        let l = &values[val_ptr[s] - offset..val_ptr[s + 1] - offset];
        let pattern = &rows[row_ptr[s]..][..l.len() / c - c];
        (start, c, pattern, l)
    };
    // The first supernode that ends after `first`.
    let s0 = end.partition_point(|&e| e <= first);
    assert!(
        s0 == n_s || val_ptr[s0] >= offset,
        "the factor's stored values start after the block to solve"
    );
    // Forward: L y = b, column by column (a wide supernode: faer's dense
    // triangular solve and product on its block).
    let mut tmp: Vec<f64> = Vec::new();
    for s in s0..n_s {
        let (start, c, pattern, l) = block(s);
        let nr = c + pattern.len();
        let start = start as isize - first as isize;
        let at = |i: usize| (start + i as isize) as usize;
        let x0 = (-start).max(0) as usize;
        if c - x0 >= DENSE_COLUMNS {
            let (w, p) = (c - x0, pattern.len());
            let lm = MatRef::from_column_major_slice_with_stride(l, nr, c, nr);
            let mut xc = MatMut::from_row_major_slice_mut(x[at(x0)..at(c)].as_flattened_mut(), w, K);
            solve_lower_triangular_in_place(lm.submatrix(x0, x0, w, w), xc.rb_mut(), Par::Seq);
            if p > 0 {
                tmp.clear();
                tmp.resize(p * K, 0.0);
                let mut t = MatMut::from_row_major_slice_mut(&mut tmp, p, K);
                matmul(
                    t.rb_mut(),
                    Accum::Replace,
                    lm.submatrix(c, x0, p, w),
                    xc.rb(),
                    1.0,
                    Par::Seq,
                );
                for (&r, ti) in pattern.iter().zip(tmp.chunks_exact(K)) {
                    for (xk, tk) in x[r - first].iter_mut().zip(ti) {
                        *xk -= tk;
                    }
                }
            }
            continue;
        }
        for j in x0..c {
            let col = &l[j * nr..(j + 1) * nr];
            let d = col[j];
            let mut xj = x[at(j)];
            for v in &mut xj {
                *v /= d;
            }
            x[at(j)] = xj;
            for (i, &lij) in col[j + 1..c].iter().enumerate() {
                let xi = &mut x[at(j + 1 + i)];
                for k in 0..K {
                    xi[k] -= lij * xj[k];
                }
            }
            for (&r, &lij) in pattern.iter().zip(&col[c..]) {
                let xi = &mut x[r - first];
                for k in 0..K {
                    xi[k] -= lij * xj[k];
                }
            }
        }
    }
    // Backward: L^T x = y, column by column from the last.
    for s in (s0..n_s).rev() {
        let (start, c, pattern, l) = block(s);
        let x0 = first.saturating_sub(start);
        backward_supernode(Supernode { start, c, pattern, l }, x0, x, first, &mut tmp);
    }
}

/// One supernode of a factor: its first column `start`, its `c` columns,
/// the unknowns of its rows below the diagonal block (`pattern`), and its
/// column-major `(c + pattern.len()) x c` block of L.
#[derive(Clone, Copy)]
struct Supernode<'a> {
    start: usize,
    c: usize,
    pattern: &'a [usize],
    l: &'a [f64],
}

/// The backward solve `L^T x = y` of a supernode's columns `x0..c`, from
/// the last (the unknowns below it solved): unknown `i` at `x[i - base]`.
fn backward_supernode<const K: usize>(
    sn: Supernode<'_>,
    x0: usize,
    x: &mut [[f64; K]],
    base: usize,
    tmp: &mut Vec<f64>,
) {
    let Supernode { start, c, pattern, l } = sn;
    let nr = c + pattern.len();
    let at = |i: usize| start + i - base;
    if c - x0 >= DENSE_COLUMNS {
        let (w, p) = (c - x0, pattern.len());
        let lm = MatRef::from_column_major_slice_with_stride(l, nr, c, nr);
        if p > 0 {
            tmp.clear();
            for &r in pattern {
                tmp.extend_from_slice(&x[r - base]);
            }
        }
        let mut xc = MatMut::from_row_major_slice_mut(x[at(x0)..at(c)].as_flattened_mut(), w, K);
        if p > 0 {
            let t = MatRef::from_row_major_slice(tmp, p, K);
            matmul(
                xc.rb_mut(),
                Accum::Add,
                lm.submatrix(c, x0, p, w).transpose(),
                t,
                -1.0,
                Par::Seq,
            );
        }
        solve_upper_triangular_in_place(lm.submatrix(x0, x0, w, w).transpose(), xc, Par::Seq);
        return;
    }
    backward_columns(sn, x0..c, x, base);
}

/// [`backward_supernode`] of the columns `cols` of a supernode, column by
/// column (the columns after them and the unknowns below solved).
fn backward_columns<const K: usize>(
    sn: Supernode<'_>,
    cols: std::ops::Range<usize>,
    x: &mut [[f64; K]],
    base: usize,
) {
    let Supernode { start, c, pattern, l } = sn;
    let nr = c + pattern.len();
    let at = |i: usize| start + i - base;
    for j in cols.rev() {
        let col = &l[j * nr..(j + 1) * nr];
        let mut acc = x[at(j)];
        for (i, &lij) in col[j + 1..c].iter().enumerate() {
            let xi = x[at(j + 1 + i)];
            for k in 0..K {
                acc[k] -= lij * xi[k];
            }
        }
        for (&r, &lij) in pattern.iter().zip(&col[c..]) {
            let xi = x[r - base];
            for k in 0..K {
                acc[k] -= lij * xi[k];
            }
        }
        for v in &mut acc {
            *v /= col[j];
        }
        x[at(j)] = acc;
    }
}

/// Where the values of a factor's leading supernodes come from, last
/// first: [`Leading::values`] is asked for ranges of stored values in
/// decreasing order (each below the one before).
pub(crate) trait Leading {
    /// The stored values `from..to`.
    fn values(&mut self, from: usize, to: usize) -> std::io::Result<&[f64]>;
}

/// Completes [`solve_trailing`] of a right-hand side on the last unknowns
/// into a whole solve: with `x` the trailing solution at `x[first..]`
/// (permuted order) and zeros before, the backward solve of the unknowns
/// before `first` (the forward solve left them zero). The kept values
/// `values` (from stored value `offset` on, a joint block) hold the
/// supernode that straddles `first`; those before it come from `leading`,
/// last first.
fn backward_leading<const K: usize>(
    sym: &SymbolicSupernodalCholesky<usize>,
    values: &[f64],
    offset: usize,
    x: &mut [[f64; K]],
    first: usize,
    leading: &mut dyn Leading,
) -> std::io::Result<()> {
    let (begin, end) = (sym.supernode_begin(), sym.supernode_end());
    let row_ptr = sym.col_ptr_for_row_idx();
    let val_ptr = sym.col_ptr_for_val();
    let rows = sym.row_idx();
    let node = |s: usize, l: &'_ [f64]| -> (usize, usize, usize) {
        let c = end[s] - begin[s];
        (begin[s], c, l.len() / c - c)
    };
    let s0 = end.partition_point(|&e| e <= first);
    if s0 < sym.n_supernodes() && begin[s0] < first {
        let l = &values[val_ptr[s0] - offset..val_ptr[s0 + 1] - offset];
        let (start, c, p) = node(s0, l);
        let pattern = &rows[row_ptr[s0]..][..p];
        backward_columns(Supernode { start, c, pattern, l }, 0..first - start, x, 0);
    }
    let mut tmp = Vec::new();
    for s in (0..s0).rev() {
        let l = leading.values(val_ptr[s], val_ptr[s + 1])?;
        let (start, c, p) = node(s, l);
        let pattern = &rows[row_ptr[s]..][..p];
        backward_supernode(Supernode { start, c, pattern, l }, 0, x, 0, &mut tmp);
    }
    Ok(())
}

/// Solves `A x = b` for `K` interleaved right-hand sides with the factor
/// (`symbolic`, `values`) of `A`; `b` (natural order) is overwritten by `x`.
pub(crate) fn solve_interleaved<const K: usize>(
    symbolic: &SymbolicCholesky<usize>,
    values: &[f64],
    b: &mut [[f64; K]],
) {
    let n = symbolic.nrows();
    assert_eq!(b.len(), n, "right-hand side of the wrong length");
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(sym) => {
            let mut x = vec![[0.0; K]; n];
            match symbolic.perm() {
                Some(perm) => {
                    let (fwd, inv) = perm.arrays();
                    for (xi, &f) in x.iter_mut().zip(fwd) {
                        *xi = b[f];
                    }
                    supernodal_solve(sym, values, 0, &mut x, 0);
                    for (bi, &v) in b.iter_mut().zip(inv) {
                        *bi = x[v];
                    }
                }
                None => supernodal_solve(sym, values, 0, b, 0),
            }
        }
        SymbolicCholeskyRaw::Simplicial(_) => {
            let mut rhs = faer::Mat::<f64>::from_fn(n, K, |i, k| b[i][k]);
            solve_with_faer(symbolic, values, rhs.as_mut());
            for (i, bi) in b.iter_mut().enumerate() {
                for (k, v) in bi.iter_mut().enumerate() {
                    *v = rhs[(i, k)];
                }
            }
        }
    }
}

/// The first stored value of L that a solve for the last `n - first`
/// unknowns reads (the start of the supernode holding unknown `first`):
/// keeping `values[offset..]` keeps all such a solve needs. `None` for a
/// simplicial factor (solved in full).
pub(crate) fn trailing_offset(symbolic: &SymbolicCholesky<usize>, first: usize) -> Option<usize> {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(sym) => {
            let s0 = sym.supernode_end().partition_point(|&e| e <= first);
            Some(sym.col_ptr_for_val()[s0])
        }
        SymbolicCholeskyRaw::Simplicial(_) => None,
    }
}

/// Solves `A x = b` for a `b` that vanishes outside the last `b.len()`
/// unknowns of the factor's permuted order, and returns those unknowns of
/// `x` in `b` (both in permuted order): the joint block of the iteration.
/// `values` are the factor's stored values from `offset` on (0: all).
pub(crate) fn solve_trailing<const K: usize>(
    symbolic: &SymbolicCholesky<usize>,
    values: &[f64],
    offset: usize,
    b: &mut [[f64; K]],
) {
    let n = symbolic.nrows();
    let first = n - b.len();
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(sym) => supernodal_solve(sym, values, offset, b, first),
        SymbolicCholeskyRaw::Simplicial(_) => {
            assert_eq!(offset, 0, "a simplicial factor is kept whole");
            // Small problems: a full solve in natural order.
            let fwd: Vec<usize> = match symbolic.perm() {
                Some(p) => p.arrays().0.to_vec(),
                None => (0..n).collect(),
            };
            let mut full = vec![[0.0; K]; n];
            for (i, bi) in b.iter().enumerate() {
                full[fwd[first + i]] = *bi;
            }
            solve_interleaved(symbolic, values, &mut full);
            for (i, bi) in b.iter_mut().enumerate() {
                *bi = full[fwd[first + i]];
            }
        }
    }
}

/// The stored values of a whole factor as a [`Leading`] source.
pub(crate) struct InMemory<'a>(pub(crate) &'a [f64]);

impl Leading for InMemory<'_> {
    fn values(&mut self, from: usize, to: usize) -> std::io::Result<&[f64]> {
        Ok(&self.0[from..to])
    }
}

/// Solves `A x = b` for a `b` that vanishes outside the last `b.len()`
/// unknowns of the factor's permuted order (as [`solve_trailing`]) and
/// returns all of `x` in natural order: the trailing block from `values`
/// (stored values from `offset` on), the columns before it read from
/// `leading`, last first (a factor on disk streams through a small
/// window: no whole factor in memory).
pub(crate) fn solve_trailing_whole<const K: usize>(
    symbolic: &SymbolicCholesky<usize>,
    values: &[f64],
    offset: usize,
    b: &[[f64; K]],
    leading: &mut dyn Leading,
) -> std::io::Result<Vec<[f64; K]>> {
    let n = symbolic.nrows();
    let first = n - b.len();
    let mut x = vec![[0.0; K]; n];
    x[first..].copy_from_slice(b);
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(sym) => {
            supernodal_solve(sym, values, offset, &mut x[first..], first);
            backward_leading(sym, values, offset, &mut x, first, leading)?;
        }
        SymbolicCholeskyRaw::Simplicial(_) => {
            assert_eq!(offset, 0, "a simplicial factor is kept whole");
            // Small problems: the full solve in natural order.
            let mut full = vec![[0.0; K]; n];
            let fwd: Vec<usize> = match symbolic.perm() {
                Some(p) => p.arrays().0.to_vec(),
                None => (0..n).collect(),
            };
            for (i, bi) in b.iter().enumerate() {
                full[fwd[first + i]] = *bi;
            }
            solve_interleaved(symbolic, values, &mut full);
            return Ok(full);
        }
    }
    Ok(match symbolic.perm() {
        Some(perm) => perm.arrays().1.iter().map(|&v| x[v]).collect(),
        None => x,
    })
}

/// faer's own solve (any storage), sequential.
pub(crate) fn solve_with_faer(symbolic: &SymbolicCholesky<usize>, values: &[f64], rhs: MatMut<'_, f64>) {
    let par = Par::Seq;
    let mut mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(rhs.ncols(), par));
    LltRef::new(symbolic, values).solve_in_place_with_conj(Conj::No, rhs, par, MemStack::new(&mut mem));
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::linalg::cholesky::llt::factor::LltRegularization;
    use faer::sparse::linalg::cholesky::factorize_symbolic_cholesky;
    use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
    use faer::Side;

    /// SPD 2D Laplacian-like matrix on a g x g grid with 3 unknowns per
    /// point (large enough for faer to choose supernodal storage).
    fn grid(g: usize) -> (usize, Vec<usize>, Vec<usize>, Vec<f64>) {
        let n = 3 * g * g;
        let id = |i: usize, j: usize, c: usize| 3 * (i * g + j) + c;
        let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        for i in 0..g {
            for j in 0..g {
                for c in 0..3 {
                    let a = id(i, j, c);
                    // Upper triangle: entries (row <= col).
                    cols[a].push((a, 8.0 + c as f64));
                    for c2 in 0..c {
                        cols[a].push((id(i, j, c2), 0.5));
                    }
                    if i > 0 {
                        cols[a].push((id(i - 1, j, c), -1.0));
                    }
                    if j > 0 {
                        cols[a].push((id(i, j - 1, c), -1.0 - 0.1 * c as f64));
                    }
                }
            }
        }
        let mut col_ptr = vec![0];
        let (mut row_idx, mut val) = (Vec::new(), Vec::new());
        for col in &mut cols {
            col.sort_by_key(|e| e.0);
            for &(r, v) in col.iter() {
                row_idx.push(r);
                val.push(v);
            }
            col_ptr.push(row_idx.len());
        }
        (n, col_ptr, row_idx, val)
    }

    /// The grid's symbolic and numeric factors.
    fn factor(g: usize) -> (SymbolicCholesky<usize>, Vec<f64>) {
        let (n, col_ptr, row_idx, val) = grid(g);
        let pat = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let symbolic =
            factorize_symbolic_cholesky(pat, Side::Upper, Default::default(), Default::default()).unwrap();
        let mut values = vec![0.0; symbolic.len_val()];
        let par = Par::Seq;
        let mut mem = MemBuffer::new(symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()));
        symbolic
            .factorize_numeric_llt(
                &mut values,
                SparseColMatRef::new(pat, &val),
                Side::Upper,
                LltRegularization::default(),
                par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .unwrap();
        (symbolic, values)
    }

    /// Serves stored values as [`InMemory`] does and records the ranges
    /// asked.
    struct Recorded<'a>(&'a [f64], Vec<(usize, usize)>);

    impl Leading for Recorded<'_> {
        fn values(&mut self, from: usize, to: usize) -> std::io::Result<&[f64]> {
            self.1.push((from, to));
            Ok(&self.0[from..to])
        }
    }

    /// A right-hand side on the last unknowns, solved with the joint
    /// block's values and the rest fetched last first, equals the full
    /// solve of the same right-hand side (a trailing block that starts
    /// inside a supernode and one that starts at the first unknown).
    #[test]
    fn a_trailing_solve_completed_from_the_rest_equals_the_full_solve() {
        let (symbolic, values) = factor(60);
        let n = symbolic.nrows();
        let SymbolicCholeskyRaw::Supernodal(sym) = symbolic.raw() else {
            panic!("supernodal storage expected");
        };
        let fwd = symbolic.perm().unwrap().arrays().0.to_vec();
        for trailing in [517, 1, n] {
            let first = n - trailing;
            let s0 = sym.supernode_end().partition_point(|&e| e <= first);
            if trailing == 517 {
                assert!(
                    sym.supernode_begin()[s0] < first,
                    "the block starts inside a supernode"
                );
            }
            let offset = trailing_offset(&symbolic, first).unwrap();
            let b: Vec<[f64; 2]> = (0..trailing)
                .map(|i| [((i * 5 % 11) as f64).cos(), (i as f64 * 0.7).sin()])
                .collect();
            let mut rest = Recorded(&values[..offset], Vec::new());
            let ours = solve_trailing_whole(&symbolic, &values[offset..], offset, &b, &mut rest).unwrap();
            let mut full = vec![[0.0; 2]; n];
            for (i, bi) in b.iter().enumerate() {
                full[fwd[first + i]] = *bi;
            }
            solve_interleaved(&symbolic, &values, &mut full);
            let scale = full.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
            let worst = ours
                .iter()
                .flatten()
                .zip(full.iter().flatten())
                .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
            assert!(
                worst <= 1e-14 * scale,
                "trailing {trailing}: max difference {worst:e} of {scale:e}"
            );
            // Every value before the block asked once, last first.
            let asked = &rest.1;
            assert_eq!(asked.first().map(|r| r.1), (offset > 0).then_some(offset));
            assert!(asked.windows(2).all(|w| w[1].1 == w[0].0));
            assert_eq!(asked.last().map_or(0, |r| r.0), 0);
        }
    }

    fn check(g: usize, want_supernodal: bool) {
        let (n, col_ptr, row_idx, val) = grid(g);
        let (symbolic, values) = factor(g);
        assert_eq!(
            matches!(symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_)),
            want_supernodal
        );
        let b: Vec<[f64; 2]> = (0..n)
            .map(|i| [((i * 7 % 13) as f64).sin(), (i as f64 * 0.3).cos()])
            .collect();
        let mut ours = b.clone();
        solve_interleaved(&symbolic, &values, &mut ours);
        let mut theirs = faer::Mat::<f64>::from_fn(n, 2, |i, k| b[i][k]);
        solve_with_faer(&symbolic, &values, theirs.as_mut());
        let mut worst = 0.0f64;
        for i in 0..n {
            for k in 0..2 {
                worst = worst.max((ours[i][k] - theirs[(i, k)]).abs());
            }
        }
        assert!(worst < 1e-13, "max difference {worst:e}");
        // And A x = b itself (upper triangle stored, symmetric product).
        let mut ax = vec![[0.0; 2]; n];
        for c in 0..n {
            for p in col_ptr[c]..col_ptr[c + 1] {
                let (r, v) = (row_idx[p], val[p]);
                for k in 0..2 {
                    ax[r][k] += v * ours[c][k];
                    if r != c {
                        ax[c][k] += v * ours[r][k];
                    }
                }
            }
        }
        let res = (0..n)
            .flat_map(|i| (0..2).map(move |k| (i, k)))
            .map(|(i, k)| (ax[i][k] - b[i][k]).abs());
        let res = res.fold(0.0f64, f64::max);
        assert!(res < 1e-12, "residual {res:e}");
    }

    #[test]
    fn supernodal_solve_matches_faer_and_the_matrix() {
        check(60, true);
    }

    /// The grid of [`check`] has supernodes wide enough for the dense path,
    /// with rows below them (the product and scatter are exercised).
    #[test]
    fn the_grid_exercises_the_dense_path() {
        let (n, col_ptr, row_idx, _) = grid(60);
        let pat = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let symbolic =
            factorize_symbolic_cholesky(pat, Side::Upper, Default::default(), Default::default()).unwrap();
        let SymbolicCholeskyRaw::Supernodal(sym) = symbolic.raw() else {
            panic!("supernodal storage expected");
        };
        let (begin, end) = (sym.supernode_begin(), sym.supernode_end());
        let row_ptr = sym.col_ptr_for_row_idx();
        let wide_with_rows = (0..sym.n_supernodes())
            .filter(|&s| end[s] - begin[s] >= DENSE_COLUMNS && row_ptr[s + 1] > row_ptr[s])
            .count();
        assert!(wide_with_rows > 0);
    }

    #[test]
    fn simplicial_factors_fall_back_to_faer() {
        check(2, false);
    }
}
