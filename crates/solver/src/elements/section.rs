//! A solid cell at one circumferential section theta_s: the physical
//! strain from the nodes' physical displacements there and their theta
//! derivatives, and the nodal forces of a stress (its transpose). The
//! harmonics meet here: the sections synthesize `U = sum_m phi_m u_m` and
//! `U' = sum_m phi_m' u_m` ([`crate::fourier::basis`],
//! [`crate::fourier::basis_derivative`]), and the analysis of the forces
//! back into harmonics, `f_m = sum_s w_s (phi_m F_U + phi_m' F_U')`, is
//! the virtual work `sum_s w_s int delta eps^T sigma r dA` (with `sigma =
//! D eps` and sections that resolve `2 M`, exactly `K_m u_m`).
//!
//! With `h = N / r` (r > 0: Gauss points only), node i's columns of the
//! two strain operators `eps = B_U U + B_D U'` are
//!
//! ```text
//!            B_U                      B_D
//! e_r   | N_r   0     0       |   | 0  0  0 |
//! e_z   | 0     N_z   0       |   | 0  0  0 |
//! e_th  | h     0     0       |   | 0  0  h |
//! g_rz  | N_z   N_r   0       |   | 0  0  0 |
//! g_rth | 0     0     N_r - h |   | h  0  0 |
//! g_zth | 0     0     N_z     |   | 0  h  0 |
//! ```

use super::{CellValues, DOF_PER_NODE};

/// The physical strain `(e_r, e_z, e_th, g_rz, g_rth, g_zth)` (engineering
/// shears) at point `q` of `values` from the nodes' physical displacements
/// `u` and their theta derivatives `du` (node-major `(u_r, u_z, u_theta)`).
pub fn section_strain(values: &CellValues, q: usize, u: &[f64], du: &[f64]) -> [f64; 6] {
    let (n, dn, r) = (values.n(q), values.dn(q), values.r(q));
    // f[c] = [value, d/dr, d/dz] of component c, g[c] = value of its theta derivative
    let mut f = [[0.0; 3]; 3];
    let mut g = [0.0; 3];
    for (i, (ni, di)) in n.iter().zip(dn).enumerate() {
        for c in 0..DOF_PER_NODE {
            let ui = u[DOF_PER_NODE * i + c];
            f[c][0] += ni * ui;
            f[c][1] += di[0] * ui;
            f[c][2] += di[1] * ui;
            g[c] += ni * du[DOF_PER_NODE * i + c];
        }
    }
    let [[ur, ur_r, ur_z], [_, uz_r, uz_z], [ut, ut_r, ut_z]] = f;
    [
        ur_r,
        uz_z,
        (ur + g[2]) / r,
        ur_z + uz_r,
        g[0] / r + ut_r - ut / r,
        g[1] / r + ut_z,
    ]
}

/// Adds `w B_U^T sigma` to `fu` and `w B_D^T sigma` to `fd` (node-major):
/// the nodal forces of stress `sigma` at point `q`, `w` its weight (e.g.
/// `r |det J| w_q`).
pub fn add_section_forces(
    values: &CellValues,
    q: usize,
    sigma: &[f64; 6],
    w: f64,
    fu: &mut [f64],
    fd: &mut [f64],
) {
    let (n, dn, r) = (values.n(q), values.dn(q), values.r(q));
    let [s_r, s_z, s_t, t_rz, t_rt, t_zt] = sigma.map(|s| w * s);
    for (i, (ni, di)) in n.iter().zip(dn).enumerate() {
        let (nr, nz, h) = (di[0], di[1], ni / r);
        let k = DOF_PER_NODE * i;
        fu[k] += nr * s_r + h * s_t + nz * t_rz;
        fu[k + 1] += nz * s_z + nr * t_rz;
        fu[k + 2] += (nr - h) * t_rt + nz * t_zt;
        fd[k] += h * t_rt;
        fd[k + 1] += h * t_zt;
        fd[k + 2] += h * s_t;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::solid::{solid_stiffness, SolidScratch};
    use crate::fourier::{basis, basis_derivative, Family, Sections};
    use crate::material::Elastic;
    use axijoint_mesh::CellKind;
    use nalgebra::DMatrix;

    /// A curved cell of each kind (nodes in gmsh order), away from the axis.
    fn cell(kind: CellKind) -> Vec<[f64; 2]> {
        let corners = [[1.0, 0.0], [2.1, 0.2], [1.9, 1.3], [0.9, 1.0]];
        let mid =
            |a: [f64; 2], b: [f64; 2], bulge: f64| [0.5 * (a[0] + b[0]) + bulge, 0.5 * (a[1] + b[1]) - bulge];
        match kind {
            CellKind::Tri3 => vec![corners[0], corners[1], corners[2]],
            CellKind::Tri6 => vec![
                corners[0],
                corners[1],
                corners[2],
                mid(corners[0], corners[1], 0.05),
                mid(corners[1], corners[2], 0.03),
                mid(corners[2], corners[0], 0.0),
            ],
            CellKind::Quad4 => corners.to_vec(),
            CellKind::Quad8 | CellKind::Quad9 => {
                let mut c = corners.to_vec();
                for (a, b, e) in [(0, 1, 0.05), (1, 2, -0.04), (2, 3, 0.02), (3, 0, 0.0)] {
                    c.push(mid(corners[a], corners[b], e));
                }
                if kind == CellKind::Quad9 {
                    c.push([1.5, 0.62]);
                }
                c
            }
        }
    }

    /// With `sigma = D eps` at every section, the analysis of the section
    /// forces is `K_m u_m`: every kind, harmonics 0 to 3, both families
    /// (the sections resolve 2 m).
    #[test]
    fn the_section_quadrature_of_the_virtual_work_is_the_stiffness() {
        quadrature_is_the_stiffness(false);
    }

    /// The same with the volumetric strain and the mean stress projected
    /// at each section (B-bar): `K-bar_m u_m`.
    #[test]
    fn the_projected_section_quadrature_is_the_b_bar_stiffness() {
        quadrature_is_the_stiffness(true);
    }

    /// Replaces `v[q][0..3]` by their projection `P` of the mean (`mean`:
    /// the mean stress, else the volumetric strain).
    fn project(p: &DMatrix<f64>, v: &mut [[f64; 6]], mean: bool) {
        let scale = if mean { 1.0 / 3.0 } else { 1.0 };
        let tr: Vec<f64> = v.iter().map(|e| scale * (e[0] + e[1] + e[2])).collect();
        for (q, e) in v.iter_mut().enumerate() {
            let bar: f64 = (0..tr.len()).map(|k| p[(q, k)] * tr[k]).sum::<f64>() - tr[q];
            for c in e.iter_mut().take(3) {
                *c += if mean { bar } else { bar / 3.0 };
            }
        }
    }

    fn quadrature_is_the_stiffness(bbar: bool) {
        let mat = Elastic::new(210.0, 0.3).unwrap();
        let d = mat.d_matrix();
        let sections = Sections::full_equispaced(9);
        for kind in [
            CellKind::Tri3,
            CellKind::Tri6,
            CellKind::Quad4,
            CellKind::Quad8,
            CellKind::Quad9,
        ] {
            let coords = cell(kind);
            let nn = kind.n_nodes();
            let mut values = CellValues::with_default_rule(kind);
            values.reinit(kind, &coords).unwrap();
            let amp: Vec<f64> = (0..3 * nn)
                .map(|k| ((k * 7 + 3) % 11) as f64 / 11.0 - 0.4)
                .collect();
            let projection = crate::elements::solid::volumetric_projection(&values);
            for m in 0..=3u32 {
                let mut k = DMatrix::zeros(0, 0);
                if bbar {
                    crate::elements::solid::solid_stiffness_bbar(
                        kind,
                        &coords,
                        &mat,
                        m,
                        &mut SolidScratch::new(kind),
                        &mut k,
                    );
                } else {
                    solid_stiffness(kind, &coords, &mat, m, &mut SolidScratch::new(kind), &mut k);
                }
                let ku = &k * nalgebra::DVector::from_column_slice(&amp);
                for family in [Family::Symmetric, Family::Antisymmetric] {
                    if m == 0 && family == Family::Antisymmetric {
                        continue;
                    }
                    let mut f = vec![0.0; 3 * nn];
                    for (s, &t) in sections.theta.iter().enumerate() {
                        let ((a, b), (da, db)) = (basis(m, family, t), basis_derivative(m, family, t));
                        let phys = |x: f64, y: f64| -> Vec<f64> {
                            amp.chunks(3)
                                .flat_map(|c| [x * c[0], x * c[1], y * c[2]])
                                .collect()
                        };
                        let (u, du) = (phys(a, b), phys(da, db));
                        let (mut fu, mut fd) = (vec![0.0; 3 * nn], vec![0.0; 3 * nn]);
                        let nq = values.n_points();
                        let mut eps: Vec<[f64; 6]> =
                            (0..nq).map(|q| section_strain(&values, q, &u, &du)).collect();
                        if bbar {
                            project(&projection, &mut eps, false);
                        }
                        let mut sigma: Vec<[f64; 6]> = eps
                            .iter()
                            .map(|e| (d * nalgebra::Vector6::from_column_slice(e)).into())
                            .collect();
                        if bbar {
                            project(&projection, &mut sigma, true);
                        }
                        for (q, s) in sigma.iter().enumerate() {
                            add_section_forces(
                                &values,
                                q,
                                s,
                                values.r(q) * values.weight(q),
                                &mut fu,
                                &mut fd,
                            );
                        }
                        let w = sections.weight[s];
                        for i in 0..nn {
                            for c in 0..3 {
                                let (p, dp) = if c < 2 { (a, da) } else { (b, db) };
                                f[3 * i + c] += w * (p * fu[3 * i + c] + dp * fd[3 * i + c]);
                            }
                        }
                    }
                    let scale = ku.amax();
                    for (i, (a, b)) in f.iter().zip(ku.iter()).enumerate() {
                        assert!(
                            (a - b).abs() < 1e-12 * scale,
                            "{kind:?} m = {m} {family:?} dof {i}: {a} vs {b}"
                        );
                    }
                }
            }
        }
    }
}
