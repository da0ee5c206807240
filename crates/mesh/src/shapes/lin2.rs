//! 2-node linear line (gmsh type 1).

/// Linear line on [-1, 1].
///
/// ```text
///   0-----------1 --> s
///  s=-1        s=+1
/// ```
///
/// `N0 = (1 - s) / 2`, `N1 = (1 + s) / 2`.
#[derive(Clone, Copy, Debug)]
pub struct Lin2;

impl Lin2 {
    /// Number of nodes.
    pub const N_NODES: usize = 2;

    /// Reference coordinates s of the nodes.
    pub const REF_COORDS: [f64; 2] = [-1.0, 1.0];

    /// Shape functions at `s` into `n[..2]`.
    pub fn eval_n(s: f64, n: &mut [f64]) {
        n[0] = 0.5 * (1.0 - s);
        n[1] = 0.5 * (1.0 + s);
    }

    /// Derivatives dN/ds into `dn[..2]` (constant).
    pub fn eval_dn(_s: f64, dn: &mut [f64]) {
        dn[0] = -0.5;
        dn[1] = 0.5;
    }
}
