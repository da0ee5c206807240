//! Consistent nodal loads of boundary tractions.

use crate::elements::{c_m, DOF_PER_NODE};
use axijoint_mesh::quadrature::gauss_legendre;
use axijoint_mesh::shapes::MAX_EDGE_NODES;
use axijoint_mesh::EdgeKind;

/// Consistent nodal loads of a traction of harmonic `m` on a boundary edge
/// (kernel `N^T t r`):
///
/// ```text
/// f = c_m * Integral(N^T t(r, z) r ds)
/// ```
///
/// `traction(r, z)` returns the amplitudes `(t_r, t_z, t_theta)` in global
/// (r, z, theta) axes (symmetric family: `t_r`, `t_z` carry `cos m.th`,
/// `t_theta` carries `sin m.th`). `out` (length `3 * kind.n_nodes()`,
/// node-major `(f_r, f_z, f_theta)`) is overwritten.
///
/// Gauss-Legendre with 3 points (L2) or 5 points (L3): exact for tractions
/// up to quadratic in (r, z) on straight edges, also with an off-centre
/// middle node.
///
/// ```
/// use axijoint_mesh::EdgeKind;
/// use axijoint_solver::elements::edge_load;
/// // Uniform pressure 1 on the end face r = 0..1: total 2 pi * 1/2 = pi.
/// let mut f = [0.0; 6];
/// edge_load(EdgeKind::Lin2, &[[0.0, 0.0], [1.0, 0.0]], 0, &|_, _| [0.0, 1.0, 0.0], &mut f);
/// assert!((f[1] + f[4] - std::f64::consts::PI).abs() < 1e-14);
/// ```
pub fn edge_load(
    kind: EdgeKind,
    coords: &[[f64; 2]],
    m: u32,
    traction: &dyn Fn(f64, f64) -> [f64; 3],
    out: &mut [f64],
) {
    let nn = kind.n_nodes();
    out[..DOF_PER_NODE * nn].fill(0.0);
    let rule = gauss_legendre(if nn == 2 { 3 } else { 5 }).expect("rule exists");
    let cm = c_m(m);
    let (mut n, mut dn) = ([0.0; MAX_EDGE_NODES], [0.0; MAX_EDGE_NODES]);
    for (s, w) in rule.iter() {
        kind.eval_n(s, &mut n);
        kind.eval_dn(s, &mut dn);
        let (mut x, mut t) = ([0.0; 2], [0.0; 2]);
        for i in 0..nn {
            for a in 0..2 {
                x[a] += n[i] * coords[i][a];
                t[a] += dn[i] * coords[i][a];
            }
        }
        let f = cm * x[0] * t[0].hypot(t[1]) * w;
        let tr = traction(x[0], x[1]);
        for i in 0..nn {
            for (c, tc) in tr.iter().enumerate() {
                out[DOF_PER_NODE * i + c] += f * n[i] * tc;
            }
        }
    }
}
