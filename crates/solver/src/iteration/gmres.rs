//! Restarted GMRES, right-preconditioned: the Krylov solve of the
//! stiff-joint preconditioner's coupled interface system
//! ([`super::precondition`]). No sweep is ever paid here: its operator and
//! preconditioner act on the interface's pair unknowns only.

use super::vector::{axpy, dot, norm};

/// Solves `A x = b` from `x = 0` to `|b - A x| <= tol |b|` by GMRES with
/// restarts every `restart` iterations, at most `max_its` in all, right-
/// preconditioned by `m` (`x = M y`); `a(v, out)` writes `A v`, `m(v, out)`
/// writes `M v`. Returns x and the iterations taken (applications of the
/// operator in the Krylov basis).
pub(super) fn gmres(
    mut a: impl FnMut(&[f64], &mut [f64]),
    mut m: impl FnMut(&[f64], &mut [f64]),
    b: &[f64],
    tol: f64,
    restart: usize,
    max_its: usize,
) -> (Vec<f64>, usize) {
    let n = b.len();
    let tol = tol * norm(b);
    let mut x = vec![0.0; n];
    let mut r = b.to_vec();
    let mut its = 0;
    let (mut t1, mut t2) = (vec![0.0; n], vec![0.0; n]);
    while its < max_its {
        let beta = norm(&r);
        if beta <= tol || beta == 0.0 {
            break;
        }
        let mut v: Vec<Vec<f64>> = vec![r.iter().map(|x| x / beta).collect()];
        let mut h = vec![vec![0.0; restart]; restart + 1];
        let (mut cs, mut sn) = (vec![0.0; restart], vec![0.0; restart]);
        let mut g = vec![0.0; restart + 1];
        g[0] = beta;
        let mut k = 0;
        while k < restart && its < max_its {
            m(&v[k], &mut t1);
            a(&t1, &mut t2);
            // Modified Gram-Schmidt, twice (the basis stays orthogonal
            // where the preconditioned operator is far from normal).
            for _ in 0..2 {
                for j in 0..=k {
                    let hj = dot(&v[j], &t2);
                    h[j][k] += hj;
                    axpy(-hj, &v[j], &mut t2);
                }
            }
            let hn = norm(&t2);
            h[k + 1][k] = hn;
            for j in 0..k {
                let t = cs[j] * h[j][k] + sn[j] * h[j + 1][k];
                h[j + 1][k] = -sn[j] * h[j][k] + cs[j] * h[j + 1][k];
                h[j][k] = t;
            }
            let d = h[k][k].hypot(h[k + 1][k]);
            if d == 0.0 {
                break;
            }
            cs[k] = h[k][k] / d;
            sn[k] = h[k + 1][k] / d;
            h[k][k] = d;
            h[k + 1][k] = 0.0;
            g[k + 1] = -sn[k] * g[k];
            g[k] *= cs[k];
            its += 1;
            k += 1;
            if g[k].abs() <= tol || hn == 0.0 {
                break;
            }
            v.push(t2.iter().map(|x| x / hn).collect());
        }
        if k == 0 {
            break;
        }
        let mut y = vec![0.0; k];
        for i in (0..k).rev() {
            let s = g[i] - (i + 1..k).map(|j| h[i][j] * y[j]).sum::<f64>();
            y[i] = s / h[i][i];
        }
        t1.fill(0.0);
        for (j, yj) in y.iter().enumerate() {
            axpy(*yj, &v[j], &mut t1);
        }
        m(&t1, &mut t2);
        axpy(1.0, &t2, &mut x);
        a(&x, &mut t1);
        for ((ri, bi), ai) in r.iter_mut().zip(b).zip(&t1) {
            *ri = bi - ai;
        }
        if g[k].abs() <= tol {
            break;
        }
    }
    (x, its)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A non-symmetric tridiagonal system solved to its tolerance, with and
    /// without a (Jacobi) preconditioner and with restarts; the
    /// preconditioned solve needs fewer iterations.
    #[test]
    fn solves_a_nonsymmetric_system_to_its_tolerance() {
        let n = 60;
        let diag = |i: usize| 2.0 + i as f64;
        let a = |v: &[f64], out: &mut [f64]| {
            for i in 0..n {
                let left = if i > 0 { -v[i - 1] } else { 0.0 };
                let right = if i + 1 < n { -0.5 * v[i + 1] } else { 0.0 };
                out[i] = diag(i) * v[i] + left + right;
            }
        };
        let b: Vec<f64> = (0..n).map(|i| ((i * 7) % 5) as f64 - 2.0).collect();
        let plain = gmres(a, |v, o| o.copy_from_slice(v), &b, 1e-10, 10, 500);
        let jacobi = gmres(
            a,
            |v, o| {
                for i in 0..n {
                    o[i] = v[i] / diag(i);
                }
            },
            &b,
            1e-10,
            10,
            500,
        );
        for (x, _) in [&plain, &jacobi] {
            let mut ax = vec![0.0; n];
            a(x, &mut ax);
            let res: f64 = ax
                .iter()
                .zip(&b)
                .map(|(p, q)| (p - q).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!(res <= 1e-9 * norm(&b), "{res:e}");
        }
        assert!(jacobi.1 < plain.1, "{} {}", jacobi.1, plain.1);
    }
}
