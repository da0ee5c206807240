//! The harmonic-block preconditioner of Newton's Krylov solve, for joints
//! much stiffer than their elements (used by the traction form,
//! [`super::traction`], with its tangent `D = Dd^-1 Dv k_a`).
//!
//! With `Z_m = [K_m^-1]` on the joint nodes (dense, formed once per run from
//! the elastic factors: `3 n_j / 2` joint-block solves per harmonic) and
//! `W = S Z A` (synthesis, joint-node solve, analysis), the push-through
//! identity gives the exact inverse of Newton's Jacobian `J = D W - I`:
//!
//! ```text
//! J^-1 = -(I + D S (Z^-1 - A D S)^-1 A)
//! ```
//!
//! `A D S` couples the harmonics only through the variation of the joint
//! tangent D around the turn. Its diagonal blocks, one per harmonic m and
//! family f, `Dbar_mf = sum_s w_s Phi_mf(theta_s) D_s Phi_mf(theta_s)`, give
//! the preconditioner
//!
//! ```text
//! M = -(I + D S P^-1 A),   P_mf^-1 = (I - Z_m Dbar_mf)^-1 Z_m
//! ```
//!
//! exact when D does not vary around the turn. When the whole interface is
//! small enough (`(number of harmonics and families) x 3 n_j <=`
//! [`COUPLED_MAX`]), the blocks are not split: `P = Z^-1 - A D S` over all
//! harmonics together, `M = J^-1` exactly, and GCR needs one direction.
//! Where points open on one side of the turn and stick on the other, D
//! varies strongly around the turn and the block-diagonal `P` alone leaves
//! the slow modes. A stiff elastic joint makes
//! `D W` close to I along the joint's modes (the released traction comes
//! back through the same stiff spring): `J` has eigenvalues of order
//! `E / (k h)` there, and the plain Krylov solve crawls; `M` removes them.
//! Cost per Newton step: one dense LU of order `3 n_j` per harmonic and
//! family (`O(M (3 n_j)^3)`), or one of order `2 M 3 n_j` coupled; no
//! sparse factorization; per application no sweep.

use super::release::Tangent;
use super::setup::{JointAmplitudes, Setup};
use crate::elements::{add_traction_forces, relative_displacement};
use crate::fourier::Family;
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::Mat;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use std::sync::Arc;

/// Largest order of the coupled interface tangent factorized densely: an
/// LU of order 6000 takes about 2 s on 2 cores and 3 x 288 MB while it is
/// formed. Measured on the pile in soil with k_eta h / E = 100 (order
/// 5100): converges in 1 load step; block-diagonal, it stopped at
/// lambda = 0 (100 sweeps per Newton step did not reach the forcing term).
pub(super) const COUPLED_MAX: usize = 6000;

/// The preconditioner's fixed data, formed once per run
/// ([`Setup::interface`]).
pub(super) struct Interface {
    /// `Z_m` per harmonic index, order `3 n_j`.
    z: Vec<DMatrix<f64>>,
    /// Per point: `B` (3 x 3 n_e, relative displacement of the element's
    /// joint-node values) and `G` (3 n_e x 3, nodal forces of a traction).
    b: Vec<DMatrix<f64>>,
    g: Vec<DMatrix<f64>>,
    /// Groups of (harmonic index, family) solved together: one group of
    /// every pair (coupled), or one group per pair (block-diagonal).
    groups: Vec<Vec<(usize, usize)>>,
}

/// The preconditioner: its fixed data and its factors at the current
/// tangents.
pub(super) struct BlockPreconditioner {
    fixed: Arc<Interface>,
    /// LU of `I - Z Dbar` per group (`None`: singular, then `P^-1 = Z`).
    lu: Vec<Option<PartialPivLu<f64>>>,
}

impl Interface {
    /// Forms `Z_m` for every harmonic and the point operators.
    pub(super) fn new(setup: &Setup) -> Self {
        let n = 3 * setup.joint_nodes.len();
        let z = setup
            .factor_of
            .par_iter()
            .map(|factor| {
                let mut z = DMatrix::<f64>::zeros(n, n);
                let mut e = [vec![0.0; n], vec![0.0; n]];
                for i in (0..n).step_by(2) {
                    let pair = i + 1 < n;
                    e[0][i] = 1.0;
                    if pair {
                        e[1][i + 1] = 1.0;
                    }
                    let u = setup.model.solve_joint(factor, &[&e[0], &e[1]]);
                    z.column_mut(i).copy_from_slice(&u[0]);
                    e[0][i] = 0.0;
                    if pair {
                        z.column_mut(i + 1).copy_from_slice(&u[1]);
                        e[1][i + 1] = 0.0;
                    }
                }
                z
            })
            .collect();
        let (mut b, mut g) = (Vec::new(), Vec::new());
        for (i, info) in setup.points.iter().enumerate() {
            let ne = 3 * setup.local[i].len();
            let mut bi = DMatrix::<f64>::zeros(3, ne);
            let mut unit = vec![0.0; ne];
            for k in 0..ne {
                unit[k] = 1.0;
                let d = relative_displacement(&info.point, &unit);
                bi.set_column(k, &nalgebra::Vector3::from(d));
                unit[k] = 0.0;
            }
            let mut gi = DMatrix::<f64>::zeros(ne, 3);
            for c in 0..3 {
                let mut t = [0.0; 3];
                t[c] = 1.0;
                let mut f = vec![0.0; ne];
                add_traction_forces(&info.point, t, 1.0, &mut f);
                gi.set_column(c, &DVector::from_vec(f));
            }
            b.push(bi);
            g.push(gi);
        }
        let pairs: Vec<(usize, usize)> = (0..setup.n_h)
            .flat_map(|h| (0..if setup.both[h] { 2 } else { 1 }).map(move |f| (h, f)))
            .collect();
        let groups = if pairs.len() * n <= COUPLED_MAX {
            vec![pairs]
        } else {
            pairs.into_iter().map(|p| vec![p]).collect()
        };
        Interface { z, b, g, groups }
    }
}

impl BlockPreconditioner {
    /// The preconditioner of `setup` (its fixed data formed at the first call).
    pub(super) fn new(setup: &Setup) -> Self {
        BlockPreconditioner {
            fixed: setup
                .interface
                .get_or_init(|| Arc::new(Interface::new(setup)))
                .clone(),
            lu: Vec::new(),
        }
    }

    /// Factorizes `I - Z Dbar` of every group at the joint tangents `tangents`.
    pub(super) fn update(&mut self, setup: &Setup, tangents: &[Tangent]) {
        let n = 3 * setup.joint_nodes.len();
        let n_p = setup.points.len();
        let sections = setup.sections;
        const FAMILIES: [Family; 2] = [Family::Symmetric, Family::Antisymmetric];
        let fixed = &*self.fixed;
        self.lu = fixed
            .groups
            .par_iter()
            .map(|group| {
                let size = group.len() * n;
                let mut dbar = DMatrix::<f64>::zeros(size, size);
                let mut c = vec![nalgebra::Matrix3::<f64>::zeros(); group.len() * group.len()];
                // Phi = (a, a, b) of each member at each section.
                let phi: Vec<Vec<[f64; 3]>> = (0..sections.len())
                    .map(|s| {
                        group
                            .iter()
                            .map(|&(h, f)| {
                                let (a, b) = setup.phi(s, h, FAMILIES[f]);
                                [a, a, b]
                            })
                            .collect()
                    })
                    .collect();
                for (p, info) in setup.points.iter().enumerate() {
                    let k = setup.model.joints[info.joint].assembled;
                    let kk = [k.k_xi, k.k_eta, k.k_theta];
                    // C_p(i, j) = sum_s w_s Phi_i T_s K Phi_j (local axes; Phi = (a, a, b)).
                    c.iter_mut().for_each(|m| m.fill(0.0));
                    let mut used = false;
                    for s in 0..sections.len() {
                        let Some(t) = tangents[s * n_p + p] else {
                            continue;
                        };
                        used = true;
                        let w = sections.weight[s];
                        for (i, pi) in phi[s].iter().enumerate() {
                            for (j, pj) in phi[s].iter().enumerate() {
                                let cij = &mut c[i * group.len() + j];
                                for r in 0..3 {
                                    for q in 0..3 {
                                        cij[(r, q)] += w * pi[r] * t[r][q] * kk[q] * pj[q];
                                    }
                                }
                            }
                        }
                    }
                    if !used {
                        continue;
                    }
                    let nl = &setup.local[p];
                    for i in 0..group.len() {
                        for j in 0..group.len() {
                            let e = &fixed.g[p] * c[i * group.len() + j] * &fixed.b[p];
                            for (ai, &ja) in nl.iter().enumerate() {
                                for (bi, &jb) in nl.iter().enumerate() {
                                    for ci in 0..3 {
                                        for cj in 0..3 {
                                            dbar[(i * n + 3 * ja + ci, j * n + 3 * jb + cj)] +=
                                                e[(3 * ai + ci, 3 * bi + cj)];
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
                // Q = I - Z Dbar, Z block-diagonal over the group.
                let mut q = DMatrix::<f64>::identity(size, size);
                for (i, &(h, _)) in group.iter().enumerate() {
                    let rows = dbar.rows(i * n, n);
                    let zd = &fixed.z[h] * rows;
                    let mut target = q.rows_mut(i * n, n);
                    target -= zd;
                }
                drop(dbar);
                // faer's blocked LU: nalgebra's unblocked one took most of
                // the time of a stiff-joint run.
                let lu = Mat::<f64>::from_fn(size, size, |r, c| q[(r, c)]).partial_piv_lu();
                let singular = (0..size).any(|i| lu.U()[(i, i)] == 0.0);
                (!singular).then_some(lu)
            })
            .collect();
    }

    /// `u_s = S P^-1 A r`: the section displacements of the section forces
    /// `r` through the coupled interface tangent of the last
    /// [`BlockPreconditioner::update`] (no sweep; `released` is scratch).
    pub(super) fn displacements(
        &self,
        setup: &Setup,
        r: &[f64],
        released: &mut JointAmplitudes,
        u_s: &mut [f64],
    ) {
        let n = 3 * setup.joint_nodes.len();
        setup.analyse(r, released);
        for (h, fams) in released.iter_mut().enumerate() {
            if !setup.both[h] {
                fams[1].fill(0.0);
            }
        }
        for (group, lu) in self.fixed.groups.iter().zip(&self.lu) {
            let mut y = DVector::<f64>::zeros(group.len() * n);
            for (i, &(h, f)) in group.iter().enumerate() {
                let zv = &self.fixed.z[h] * DVector::from_column_slice(&released[h][f]);
                y.rows_mut(i * n, n).copy_from(&zv);
            }
            if let Some(lu) = lu {
                let mut col = y.clone();
                lu.solve_in_place(faer::MatMut::from_column_major_slice_mut(
                    col.as_mut_slice(),
                    y.len(),
                    1,
                ));
                if col.iter().all(|v| v.is_finite()) {
                    y = col;
                }
            }
            for (i, &(h, f)) in group.iter().enumerate() {
                released[h][f].copy_from_slice(y.rows(i * n, n).as_slice());
            }
        }
        setup.synthesize_all(released, u_s);
    }
}
