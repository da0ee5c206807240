//! 6-node quadratic triangle (gmsh type 9).

/// Quadratic triangle on the reference triangle (0,0), (1,0), (0,1).
///
/// ```text
///   eta
///    ^
///    2
///    |`\
///    |  `\
///    5    `4
///    |      `\
///    |        `\
///    0-----3----1 --> xi
/// ```
///
/// With the area coordinates `L0 = 1 - xi - eta`, `L1 = xi`, `L2 = eta`:
/// corners `N_i = L_i (2 L_i - 1)`, mid-sides `N3 = 4 L0 L1`,
/// `N4 = 4 L1 L2`, `N5 = 4 L2 L0`.
#[derive(Clone, Copy, Debug)]
pub struct Tri6;

impl Tri6 {
    /// Number of nodes.
    pub const N_NODES: usize = 6;

    /// Reference coordinates (xi, eta) of the nodes.
    pub const REF_COORDS: [[f64; 2]; 6] = [
        [0.0, 0.0],
        [1.0, 0.0],
        [0.0, 1.0],
        [0.5, 0.0],
        [0.5, 0.5],
        [0.0, 0.5],
    ];

    /// Shape functions at `xi` into `n[..6]`.
    pub fn eval_n(xi: [f64; 2], n: &mut [f64]) {
        let [x, y] = xi;
        let l0 = 1.0 - x - y;
        n[0] = l0 * (2.0 * l0 - 1.0);
        n[1] = x * (2.0 * x - 1.0);
        n[2] = y * (2.0 * y - 1.0);
        n[3] = 4.0 * l0 * x;
        n[4] = 4.0 * x * y;
        n[5] = 4.0 * y * l0;
    }

    /// Derivatives `[dN/dxi, dN/deta]` at `xi` into `dn[..6]`.
    pub fn eval_dn(xi: [f64; 2], dn: &mut [[f64; 2]]) {
        let [x, y] = xi;
        let l0 = 1.0 - x - y;
        // dL0/dxi = dL0/deta = -1
        let d0 = 1.0 - 4.0 * l0;
        dn[0] = [d0, d0];
        dn[1] = [4.0 * x - 1.0, 0.0];
        dn[2] = [0.0, 4.0 * y - 1.0];
        dn[3] = [4.0 * (l0 - x), -4.0 * x];
        dn[4] = [4.0 * y, 4.0 * x];
        dn[5] = [-4.0 * y, 4.0 * (l0 - y)];
    }
}
