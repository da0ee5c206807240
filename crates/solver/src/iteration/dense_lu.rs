//! A dense LU with partial pivoting, factorized in place in a buffer that
//! is kept from one factorization to the next (faer's `lu_in_place`).
//!
//! The stiff-joint preconditioner factorizes a new matrix of the same
//! order at every Newton step; `PartialPivLu::new` copies the matrix and
//! splits off U, so each step paid for three fresh matrices' pages (at
//! order 4590, 170 MB each: a fifth of a k h / E = 1e4 run went to page
//! faults).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::perm::PermRef;
use faer::{Mat, MatMut, MatRef, Par};

/// `P A = L U` in one matrix (L unit lower, U upper) and its row
/// permutation.
pub(super) struct DenseLu {
    lu: Mat<f64>,
    forward: Vec<usize>,
    inverse: Vec<usize>,
    /// Whether the last factorization had no zero pivot.
    ok: bool,
}

impl DenseLu {
    pub(super) fn new() -> Self {
        DenseLu {
            lu: Mat::zeros(0, 0),
            forward: Vec::new(),
            inverse: Vec::new(),
            ok: false,
        }
    }

    /// The `n x n` matrix to fill before [`DenseLu::factorize`] (its
    /// values are those of the last use).
    pub(super) fn matrix(&mut self, n: usize) -> MatMut<'_, f64> {
        if self.lu.nrows() != n {
            self.lu = Mat::zeros(n, n);
            self.forward = vec![0; n];
            self.inverse = vec![0; n];
        }
        self.ok = false;
        self.lu.as_mut()
    }

    /// Factorizes the matrix in place; whether no pivot is zero.
    pub(super) fn factorize(&mut self, par: Par) -> bool {
        let n = self.lu.nrows();
        let mut mem = MemBuffer::new(factor::lu_in_place_scratch::<usize, f64>(
            n,
            n,
            par,
            Default::default(),
        ));
        factor::lu_in_place(
            self.lu.as_mut(),
            &mut self.forward,
            &mut self.inverse,
            par,
            MemStack::new(&mut mem),
            Default::default(),
        );
        self.ok = (0..n).all(|i| self.lu[(i, i)] != 0.0);
        self.ok
    }

    /// Whether the last factorization can solve.
    pub(super) fn ok(&self) -> bool {
        self.ok
    }

    /// `rhs <- A^-1 rhs` (one column).
    pub(super) fn solve_in_place(&self, rhs: &mut [f64], par: Par) {
        let n = self.lu.nrows();
        let mut mem = MemBuffer::new(solve::solve_in_place_scratch::<usize, f64>(n, 1, par));
        let lu: MatRef<'_, f64> = self.lu.as_ref();
        solve::solve_in_place_with_conj(
            lu,
            lu,
            PermRef::new_checked(&self.forward, &self.inverse, n),
            faer::Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            par,
            MemStack::new(&mut mem),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A_k = I + k B (B fixed, not symmetric), solved against the
    /// multiplication back; the buffer reused between two matrices and a
    /// change of order.
    #[test]
    fn solves_in_a_reused_buffer() {
        let mut lu = DenseLu::new();
        for (n, k) in [(7, 0.3), (7, 2.5), (4, 1.0)] {
            let a = |i: usize, j: usize| {
                let b = ((i * 31 + j * 17) % 11) as f64 / 11.0 - 0.45;
                f64::from(u8::from(i == j)) + k * b
            };
            let mut m = lu.matrix(n);
            for j in 0..n {
                for i in 0..n {
                    m[(i, j)] = a(i, j);
                }
            }
            assert!(lu.factorize(Par::Seq));
            let x: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
            let mut rhs: Vec<f64> = (0..n).map(|i| (0..n).map(|j| a(i, j) * x[j]).sum()).collect();
            lu.solve_in_place(&mut rhs, Par::Seq);
            for (got, want) in rhs.iter().zip(&x) {
                assert!(
                    (got - want).abs() < 1e-12 * want,
                    "n {n} k {k}: {got} against {want}"
                );
            }
        }
    }

    #[test]
    fn a_zero_pivot_is_reported() {
        let mut lu = DenseLu::new();
        let mut m = lu.matrix(3);
        m.fill(1.0);
        assert!(!lu.factorize(Par::Seq));
        assert!(!lu.ok());
    }
}
