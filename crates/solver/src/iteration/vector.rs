//! Dense vector kernels of the Krylov solvers.
//!
//! The sums run in order. (Eight partial sums, which the compiler
//! vectorizes, took the Krylov orthogonalization of the tutorial's pile in
//! clay from 19 % to 8 % of the run, but changed the order of the sums
//! enough that the torsion block of crates/solver/tests/stiff_limits.rs
//! with `k h / E` = 1e3 or 1e4 stalled 0.3 % below its capacity: stiff
//! interfaces near their capacity are sensitive to round-off.)

/// `a . b`.
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `|a|_2`.
pub(super) fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// `y += alpha x`.
pub(super) fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += alpha * xi;
    }
}
