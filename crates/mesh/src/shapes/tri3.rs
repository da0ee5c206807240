//! 3-node linear triangle (gmsh type 2).

/// Linear triangle on the reference triangle (0,0), (1,0), (0,1).
///
/// ```text
///   eta
///    ^
///    2
///    |`\
///    |  `\
///    |    `\
///    |      `\
///    0--------1 --> xi
/// ```
///
/// With the area coordinates `L0 = 1 - xi - eta`, `L1 = xi`, `L2 = eta`:
/// `N_i = L_i`.
#[derive(Clone, Copy, Debug)]
pub struct Tri3;

impl Tri3 {
    /// Number of nodes.
    pub const N_NODES: usize = 3;

    /// Reference coordinates (xi, eta) of the nodes.
    pub const REF_COORDS: [[f64; 2]; 3] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];

    /// Shape functions at `xi` into `n[..3]`.
    pub fn eval_n(xi: [f64; 2], n: &mut [f64]) {
        let [x, y] = xi;
        n[0] = 1.0 - x - y;
        n[1] = x;
        n[2] = y;
    }

    /// Derivatives `[dN/dxi, dN/deta]` at `xi` into `dn[..3]` (constant).
    pub fn eval_dn(_xi: [f64; 2], dn: &mut [[f64; 2]]) {
        dn[0] = [-1.0, -1.0];
        dn[1] = [1.0, 0.0];
        dn[2] = [0.0, 1.0];
    }
}
