//! 9-node Lagrange quadrilateral (gmsh type 10).

use super::lin3::Lin3;

/// Biquadratic Lagrange quadrilateral on [-1, 1]^2.
///
/// ```text
///         eta
///          ^
///   3------6----2
///   |      |    |
///   7      8--> 5 xi
///   |           |
///   0------4----1
/// ```
///
/// `N_i(xi, eta) = l_a(xi) l_b(eta)` with the 1D quadratic Lagrange
/// polynomials `l_{-1}(t) = t (t - 1) / 2`, `l_{+1}(t) = t (t + 1) / 2`,
/// `l_0(t) = 1 - t^2` ([`Lin3`]) and `(a, b)` the node's reference coordinates.
#[derive(Clone, Copy, Debug)]
pub struct Qua9;

/// For each node, the [`Lin3`] indices of its xi and eta factors.
const FACTORS: [[usize; 2]; 9] = [
    [0, 0],
    [1, 0],
    [1, 1],
    [0, 1],
    [2, 0],
    [1, 2],
    [2, 1],
    [0, 2],
    [2, 2],
];

impl Qua9 {
    /// Number of nodes.
    pub const N_NODES: usize = 9;

    /// Reference coordinates (xi, eta) of the nodes.
    pub const REF_COORDS: [[f64; 2]; 9] = [
        [-1.0, -1.0],
        [1.0, -1.0],
        [1.0, 1.0],
        [-1.0, 1.0],
        [0.0, -1.0],
        [1.0, 0.0],
        [0.0, 1.0],
        [-1.0, 0.0],
        [0.0, 0.0],
    ];

    /// Shape functions at `xi` into `n[..9]`.
    pub fn eval_n(xi: [f64; 2], n: &mut [f64]) {
        let (mut lx, mut ly) = ([0.0; 3], [0.0; 3]);
        Lin3::eval_n(xi[0], &mut lx);
        Lin3::eval_n(xi[1], &mut ly);
        for (ni, [i, j]) in n.iter_mut().zip(FACTORS) {
            *ni = lx[i] * ly[j];
        }
    }

    /// Derivatives `[dN/dxi, dN/deta]` at `xi` into `dn[..9]`.
    pub fn eval_dn(xi: [f64; 2], dn: &mut [[f64; 2]]) {
        let (mut lx, mut ly, mut dx, mut dy) = ([0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
        Lin3::eval_n(xi[0], &mut lx);
        Lin3::eval_n(xi[1], &mut ly);
        Lin3::eval_dn(xi[0], &mut dx);
        Lin3::eval_dn(xi[1], &mut dy);
        for (d, [i, j]) in dn.iter_mut().zip(FACTORS) {
            *d = [dx[i] * ly[j], lx[i] * dy[j]];
        }
    }
}
