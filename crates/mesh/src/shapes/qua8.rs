//! 8-node serendipity quadrilateral (gmsh type 16).

/// Quadratic serendipity quadrilateral on [-1, 1]^2.
///
/// ```text
///         eta
///          ^
///   3------6----2
///   |      |    |
///   7      +--> 5 xi
///   |           |
///   0------4----1
/// ```
///
/// Corners: `N_i = (1 + xi xi_i)(1 + eta eta_i)(xi xi_i + eta eta_i - 1) / 4`;
/// mid-sides with `xi_i = 0`: `N_i = (1 - xi^2)(1 + eta eta_i) / 2`;
/// mid-sides with `eta_i = 0`: `N_i = (1 + xi xi_i)(1 - eta^2) / 2`.
#[derive(Clone, Copy, Debug)]
pub struct Qua8;

impl Qua8 {
    /// Number of nodes.
    pub const N_NODES: usize = 8;

    /// Reference coordinates (xi, eta) of the nodes.
    pub const REF_COORDS: [[f64; 2]; 8] = [
        [-1.0, -1.0],
        [1.0, -1.0],
        [1.0, 1.0],
        [-1.0, 1.0],
        [0.0, -1.0],
        [1.0, 0.0],
        [0.0, 1.0],
        [-1.0, 0.0],
    ];

    /// Shape functions at `xi` into `n[..8]`.
    pub fn eval_n(xi: [f64; 2], n: &mut [f64]) {
        let [x, y] = xi;
        for (ni, [a, b]) in n.iter_mut().zip(Self::REF_COORDS) {
            *ni = if a == 0.0 {
                0.5 * (1.0 - x * x) * (1.0 + b * y)
            } else if b == 0.0 {
                0.5 * (1.0 + a * x) * (1.0 - y * y)
            } else {
                0.25 * (1.0 + a * x) * (1.0 + b * y) * (a * x + b * y - 1.0)
            };
        }
    }

    /// Derivatives `[dN/dxi, dN/deta]` at `xi` into `dn[..8]`.
    pub fn eval_dn(xi: [f64; 2], dn: &mut [[f64; 2]]) {
        let [x, y] = xi;
        for (d, [a, b]) in dn.iter_mut().zip(Self::REF_COORDS) {
            *d = if a == 0.0 {
                [-x * (1.0 + b * y), 0.5 * b * (1.0 - x * x)]
            } else if b == 0.0 {
                [0.5 * a * (1.0 - y * y), -y * (1.0 + a * x)]
            } else {
                [
                    0.25 * a * (1.0 + b * y) * (2.0 * a * x + b * y),
                    0.25 * b * (1.0 + a * x) * (a * x + 2.0 * b * y),
                ]
            };
        }
    }
}
