//! 3-node quadratic line (gmsh type 8).

/// Quadratic line on [-1, 1]: ends first, then the middle node.
///
/// ```text
///   0-----2-----1 --> s
///  s=-1  s=0   s=+1
/// ```
///
/// `N0 = s (s - 1) / 2`, `N1 = s (s + 1) / 2`, `N2 = 1 - s^2`.
#[derive(Clone, Copy, Debug)]
pub struct Lin3;

impl Lin3 {
    /// Number of nodes.
    pub const N_NODES: usize = 3;

    /// Reference coordinates s of the nodes.
    pub const REF_COORDS: [f64; 3] = [-1.0, 1.0, 0.0];

    /// Shape functions at `s` into `n[..3]`.
    pub fn eval_n(s: f64, n: &mut [f64]) {
        n[0] = 0.5 * s * (s - 1.0);
        n[1] = 0.5 * s * (s + 1.0);
        n[2] = 1.0 - s * s;
    }

    /// Derivatives dN/ds at `s` into `dn[..3]`.
    pub fn eval_dn(s: f64, dn: &mut [f64]) {
        dn[0] = s - 0.5;
        dn[1] = s + 0.5;
        dn[2] = -2.0 * s;
    }
}
