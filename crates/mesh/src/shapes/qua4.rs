//! 4-node bilinear quadrilateral (gmsh type 3).

/// Bilinear quadrilateral on [-1, 1]^2.
///
/// ```text
///         eta
///          ^
///   3-----------2
///   |      |    |
///   |      +--> | xi
///   |           |
///   0-----------1
/// ```
///
/// `N_i = (1 + xi xi_i)(1 + eta eta_i) / 4`.
#[derive(Clone, Copy, Debug)]
pub struct Qua4;

impl Qua4 {
    /// Number of nodes.
    pub const N_NODES: usize = 4;

    /// Reference coordinates (xi, eta) of the nodes.
    pub const REF_COORDS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

    /// Shape functions at `xi` into `n[..4]`.
    pub fn eval_n(xi: [f64; 2], n: &mut [f64]) {
        for (ni, [a, b]) in n.iter_mut().zip(Self::REF_COORDS) {
            *ni = 0.25 * (1.0 + a * xi[0]) * (1.0 + b * xi[1]);
        }
    }

    /// Derivatives `[dN/dxi, dN/deta]` at `xi` into `dn[..4]`.
    pub fn eval_dn(xi: [f64; 2], dn: &mut [[f64; 2]]) {
        for (d, [a, b]) in dn.iter_mut().zip(Self::REF_COORDS) {
            *d = [0.25 * a * (1.0 + b * xi[1]), 0.25 * b * (1.0 + a * xi[0])];
        }
    }
}
