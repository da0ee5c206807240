//! Consistent nodal forces of Scene P's end load on the six-node triangles
//! of the pile end z = -1.5 (half model: half of H and of its moment).
//!
//! Tractions: a uniform shear t_x and a beam-theory axial traction
//! t_z = c (x - x_c), both scaled on the discrete (isoparametric) end face so
//! that the nodal forces sum to exactly (H/2, 0, 0) and their moment about
//! the face centre (0, 0, -1.5) has M_y = -(H/2) * 1.5, the moment of H/2
//! acting at (0, 0, -3). (M_z of the half face is -t_x * integral of y, as
//! for the continuous traction; it cancels only in the full model.)

use super::model::{Model3d, Z_END};

/// Horizontal load H on the full pile (MN).
pub const H: f64 = 0.5;
/// z of the point of action of H (m).
pub const Z_LOAD: f64 = -3.0;

/// Nodal forces of the end load: (node, (Fx, Fy, Fz)), sorted by node.
#[derive(Clone, Debug)]
pub struct EndLoad {
    /// Forces per node.
    pub forces: Vec<(usize, [f64; 3])>,
    /// Uniform shear traction t_x (MPa).
    pub t_x: f64,
    /// Slope c of t_z = c (x - x_c) (MPa/m).
    pub c: f64,
    /// Centroid x_c of the discrete end face (m).
    pub x_c: f64,
    /// Area of the discrete end face (m^2).
    pub area: f64,
}

/// Points (on (0, 1)) and weights of 5-point Gauss-Legendre.
fn gauss5() -> [(f64, f64); 5] {
    // Nodes and weights on [-1, 1].
    let (x1, x2) = (0.906_179_845_938_664, 0.538_469_310_105_683);
    let (w0, w1, w2) = (128.0 / 225.0, 0.236_926_885_056_189_1, 0.478_628_670_499_366_5);
    let m = |x: f64, w: f64| ((1.0 + x) / 2.0, w / 2.0);
    [m(-x1, w1), m(-x2, w2), m(0.0, w0), m(x2, w2), m(x1, w1)]
}

/// Quadrature on the unit triangle (collapsed 5 x 5 Gauss, exact to degree
/// 9): (xi, eta, weight).
fn triangle_rule() -> Vec<(f64, f64, f64)> {
    let g = gauss5();
    let mut q = Vec::with_capacity(25);
    for &(u, wu) in &g {
        for &(v, wv) in &g {
            q.push((u, v * (1.0 - u), wu * wv * (1.0 - u)));
        }
    }
    q
}

/// Tri6 shape functions (corners 1-3, mids 1-2, 2-3, 3-1) and derivatives.
fn tri6(xi: f64, eta: f64) -> ([f64; 6], [[f64; 2]; 6]) {
    let l = [1.0 - xi - eta, xi, eta];
    let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
    let mut n = [0.0; 6];
    let mut dn = [[0.0; 2]; 6];
    for i in 0..3 {
        n[i] = l[i] * (2.0 * l[i] - 1.0);
        for d in 0..2 {
            dn[i][d] = (4.0 * l[i] - 1.0) * dl[i][d];
        }
    }
    for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
        n[3 + k] = 4.0 * l[i] * l[j];
        for d in 0..2 {
            dn[3 + k][d] = 4.0 * (l[i] * dl[j][d] + l[j] * dl[i][d]);
        }
    }
    (n, dn)
}

/// Integrates over every end face: calls `f(node weights N_a dA, x, y)`
/// at each quadrature point.
fn integrate(model: &Model3d, mut f: impl FnMut(&[usize; 6], &[f64; 6], f64, f64)) {
    let rule = triangle_rule();
    for face in &model.end_faces {
        let p: Vec<[f64; 3]> = face.iter().map(|&n| model.coords[n]).collect();
        for &(xi, eta, w) in &rule {
            let (n, dn) = tri6(xi, eta);
            let mut g = [[0.0; 3]; 2];
            let (mut x, mut y) = (0.0, 0.0);
            for a in 0..6 {
                x += n[a] * p[a][0];
                y += n[a] * p[a][1];
                for d in 0..2 {
                    for c in 0..3 {
                        g[d][c] += dn[a][d] * p[a][c];
                    }
                }
            }
            let cross = [
                g[0][1] * g[1][2] - g[0][2] * g[1][1],
                g[0][2] * g[1][0] - g[0][0] * g[1][2],
                g[0][0] * g[1][1] - g[0][1] * g[1][0],
            ];
            let da = w * (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
            let nw = n.map(|v| v * da);
            f(face, &nw, x, y);
        }
    }
}

/// Consistent nodal forces of the end load on the half model.
pub fn end_load(model: &Model3d) -> EndLoad {
    let (mut area, mut sx, mut sxx) = (0.0, 0.0, 0.0);
    integrate(model, |_, nw, x, _| {
        let da: f64 = nw.iter().sum();
        area += da;
        sx += x * da;
        sxx += x * x * da;
    });
    let x_c = sx / area;
    // integral of x (x - x_c) dA
    let ixx = sxx - x_c * sx;
    let t_x = 0.5 * H / area;
    // M_y = -c * ixx must equal -(H/2) * (Z_END - Z_LOAD).
    let c = 0.5 * H * (Z_END - Z_LOAD) / ixx;
    let mut acc = vec![[0.0; 3]; model.n_nodes()];
    integrate(model, |face, nw, x, _| {
        let tz = c * (x - x_c);
        for a in 0..6 {
            acc[face[a]][0] += nw[a] * t_x;
            acc[face[a]][2] += nw[a] * tz;
        }
    });
    let forces = acc
        .into_iter()
        .enumerate()
        .filter(|(_, f)| f[0] != 0.0 || f[2] != 0.0)
        .collect();
    EndLoad {
        forces,
        t_x,
        c,
        x_c,
        area,
    }
}

/// Resultant force and moment about (0, 0, z_ref) of nodal forces.
pub fn resultant(model: &Model3d, forces: &[(usize, [f64; 3])], z_ref: f64) -> ([f64; 3], [f64; 3]) {
    let mut f = [0.0; 3];
    let mut m = [0.0; 3];
    for (n, v) in forces {
        let p = model.coords[*n];
        let r = [p[0], p[1], p[2] - z_ref];
        for d in 0..3 {
            f[d] += v[d];
        }
        m[0] += r[1] * v[2] - r[2] * v[1];
        m[1] += r[2] * v[0] - r[0] * v[2];
        m[2] += r[0] * v[1] - r[1] * v[0];
    }
    (f, m)
}
