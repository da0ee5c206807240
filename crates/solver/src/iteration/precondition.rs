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
//! small enough, the blocks are not split: `P = Z^-1 - A D S` over all
//! harmonics together, `M = J^-1` exactly, and GCR needs one direction.
//! Where points open on one side of the turn and stick on the other, D
//! varies strongly around the turn and the block-diagonal `P` alone leaves
//! the slow modes. A stiff elastic joint makes
//! `D W` close to I along the joint's modes (the released traction comes
//! back through the same stiff spring): `J` has eigenvalues of order
//! `E / (k h)` there, and the plain Krylov solve crawls; `M` removes them.
//!
//! The joint acts only on the jumps of its node pairs: with C the relative
//! displacement of each pair (top minus bottom, `n_r = 3 pairs`, half the
//! `3 n_j` joint-node unknowns), `A D S = C^T D_r C` and
//!
//! ```text
//! P^-1 = Z + Z C^T (I - D_r Z_r)^-1 D_r C Z,   Z_r = C Z C^T
//! ```
//!
//! The coupled system `(I - D_r Z_r) w = D_r C Z r` is solved by GMRES
//! right-preconditioned by the blocks, each harmonic and family with its
//! own LU of `I - Dbar_mf Z_r`, `D_r` applied through the sections point by
//! point (no dense coupled matrix, no sweep): the blocks alone left the
//! slow modes where D varies around the turn and stopped the pile in soil
//! at lambda = 0. When the whole system is small enough (`(number of
//! harmonics and families) x n_r <=`
//! [`COUPLED_MAX`](super::types::COUPLED_MAX)) its dense LU (one per
//! Newton step, order `n_r` per member; no sparse factorization, per
//! application no sweep) takes over from the first GMRES solve that does
//! not converge, and from the start below [`GMRES_ORDER`] (where it is
//! cheap) and for a joint stiffer than [`GMRES_STIFFNESS`] (where the
//! inexact solves cost Newton more steps than the dense LU costs).

use super::dense_lu::DenseLu;
use super::interface::Interface;
use super::release::Tangent;
use super::setup::Setup;
use super::transfer::JointAmplitudes;
use super::vector::{dot, norm};
use crate::elements::{add_traction_forces, relative_displacement};
use crate::fourier::Family;
use faer::linalg::matmul::matmul;
use faer::{Accum, MatRef, Par};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use std::sync::Arc;

/// The GMRES on the coupled interface tangent above
/// [`IterationSettings::coupled_max`](super::types::IterationSettings::coupled_max):
/// its relative tolerance (measured on the pile in soil at k h / E = 1000:
/// 1e-2 and 1e-3 stalled the outer Newton at lambda = 0, 1e-6 converged in
/// 26 sweeps, as the exact LU), its iteration limit and its restart length.
const INNER_TOLERANCE: f64 = 1e-6;
const INNER_MAX: usize = 1000;
const INNER_RESTART: usize = 50;

/// The stiffness of a joint, as `k / k_assembled` (about `k h / E`), up to
/// which GMRES solves the coupled system first, the dense LU only where
/// it does not converge; above it the dense LU from the start when the
/// system is small enough. Measured on the pile in soil (M = 8, coupled
/// order 4590): at 10, 0.36 s of solve against 1.9 s with the dense LU; at
/// the rigid penalty (1000), 5.7 s against 9.1 s, the same 35 Newton
/// steps; at 1e4 the inexact solves cost Newton its convergence (past
/// 300 s against 55 s).
pub(super) const GMRES_STIFFNESS: f64 = 4.0 * crate::scene::RIGID_STIFFNESS;

/// The order of the coupled system below which its dense LU is used from
/// the start (it costs milliseconds there; GMRES first on the rigid
/// torsion block stopped its stepped run at 0.898 of the load for the
/// exact 0.909, the dense LU brackets it).
pub(super) const GMRES_ORDER: usize = 2000;

/// The families, in the order of the joint amplitudes.
const FAMILIES: [Family; 2] = [Family::Symmetric, Family::Antisymmetric];

/// The preconditioner: its fixed data and, per group, `D_r` and the LU of
/// `I - D_r Z_r` at the current tangents: one group per member while GMRES
/// solves the coupled system, one group of every member once `dense`.
pub(super) struct BlockPreconditioner {
    fixed: Arc<Interface>,
    dr: Vec<DMatrix<f64>>,
    /// Per group, the LU of `I - D_r Z_r` (kept buffers; see
    /// [`DenseLu::ok`]).
    lu: Vec<DenseLu>,
    /// The joint tangents of the last update (the coupled `D_r`).
    tangents: Vec<Tangent>,
    /// Whether `dr` and `lu` are older than `tangents`.
    stale: bool,
    /// The coupled system by its dense LU (from the first GMRES solve
    /// that did not converge, for the rest of the run; only when
    /// [`Interface::dense_allowed`]).
    dense: bool,
}

impl Interface {
    /// Forms `Z_m` for every harmonic and the point operators.
    pub(super) fn new(setup: &Setup, coupled_max: usize) -> Self {
        let n = 3 * setup.joint_nodes.len();
        // The node pairs of every point (elements are [bottom..., top...]).
        let mut index = std::collections::HashMap::new();
        let mut pairs = Vec::new();
        let point_pairs: Vec<Vec<usize>> = setup
            .points
            .iter()
            .enumerate()
            .map(|(i, info)| {
                let nf = info.point.n_face;
                let nl = &setup.local[i];
                (0..nf)
                    .map(|a| {
                        let key = (nl[a], nl[nf + a]);
                        *index.entry(key).or_insert_with(|| {
                            pairs.push(key);
                            pairs.len() - 1
                        })
                    })
                    .collect()
            })
            .collect();
        let nr = 3 * pairs.len();
        let solved: Vec<[DMatrix<f64>; 3]> = setup
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
                // Z C^T: column (pair, c) = Z e_top - Z e_bottom (Z symmetric).
                let mut zc = DMatrix::<f64>::zeros(n, nr);
                for (q, &(bot, top)) in pairs.iter().enumerate() {
                    for c in 0..3 {
                        let col = z.column(3 * top + c) - z.column(3 * bot + c);
                        zc.set_column(3 * q + c, &col);
                    }
                }
                let mut zr = DMatrix::<f64>::zeros(nr, nr);
                for (q, &(bot, top)) in pairs.iter().enumerate() {
                    for c in 0..3 {
                        let row = zc.row(3 * top + c) - zc.row(3 * bot + c);
                        zr.set_row(3 * q + c, &row);
                    }
                }
                [z, zc, zr]
            })
            .collect();
        let (mut z, mut zc, mut zr) = (Vec::new(), Vec::new(), Vec::new());
        for [a, b, c] in solved {
            z.push(a);
            zc.push(b);
            zr.push(c);
        }
        let (mut b, mut g) = (Vec::new(), Vec::new());
        for info in &setup.points {
            // The top half of the element operators: the jumps of the pairs.
            let nf = info.point.n_face;
            let ne = 6 * nf;
            let mut bi = DMatrix::<f64>::zeros(3, 3 * nf);
            let mut unit = vec![0.0; ne];
            for k in 0..3 * nf {
                unit[3 * nf + k] = 1.0;
                let d = relative_displacement(&info.point, &unit);
                bi.set_column(k, &nalgebra::Vector3::from(d));
                unit[3 * nf + k] = 0.0;
            }
            let mut gi = DMatrix::<f64>::zeros(3 * nf, 3);
            for c in 0..3 {
                let mut t = [0.0; 3];
                t[c] = 1.0;
                let mut f = vec![0.0; ne];
                add_traction_forces(&info.point, t, 1.0, &mut f);
                gi.set_column(c, &DVector::from_column_slice(&f[3 * nf..]));
            }
            b.push(bi);
            g.push(gi);
        }
        let both = &setup.transfer.both;
        let members: Vec<(usize, usize)> = (0..setup.transfer.n_h)
            .flat_map(|h| (0..if both[h] { 2 } else { 1 }).map(move |f| (h, f)))
            .collect();
        let dense_allowed = members.len() * nr <= coupled_max;
        let phi = (0..setup.sections().len())
            .flat_map(|s| {
                members.iter().map(move |&(h, f)| {
                    let (a, b) = setup.transfer.phi(s, h, FAMILIES[f]);
                    [a, a, b]
                })
            })
            .collect();
        Interface {
            z,
            zc,
            zr,
            pairs,
            point_pairs,
            b,
            g,
            dense_allowed,
            members,
            phi,
        }
    }
}

impl BlockPreconditioner {
    /// The preconditioner of `setup` (its fixed data formed at the first
    /// call); `gmres_first`: see
    /// [`IterationSettings::gmres_first`](super::types::IterationSettings::gmres_first).
    pub(super) fn new(setup: &Setup, coupled_max: usize, gmres_first: bool) -> Self {
        BlockPreconditioner {
            fixed: setup
                .interface
                .get_or_init(|| Arc::new(Interface::new(setup, coupled_max)))
                .clone(),
            dr: Vec::new(),
            lu: Vec::new(),
            tangents: Vec::new(),
            stale: false,
            dense: false,
        }
        .starting_dense(setup, gmres_first)
    }

    /// Dense from the start when the coupled system is small enough and
    /// either smaller than [`GMRES_ORDER`] or a joint is stiffer than
    /// [`GMRES_STIFFNESS`].
    fn starting_dense(mut self, setup: &Setup, gmres_first: bool) -> Self {
        let stiffest = setup
            .model
            .joints
            .iter()
            .flat_map(|j| j.softening())
            .map(|rho| 1.0 / rho)
            .fold(1.0, f64::max);
        let order = self.fixed.members.len() * 3 * self.fixed.pairs.len();
        self.dense =
            self.fixed.dense_allowed && (!gmres_first || stiffest > GMRES_STIFFNESS || order < GMRES_ORDER);
        self
    }

    /// The groups of members factorized together, as ranges of
    /// [`Interface::members`]: every member in one (dense), or one each
    /// (GMRES).
    fn groups(&self) -> Vec<std::ops::Range<usize>> {
        let nm = self.fixed.members.len();
        if self.dense {
            std::iter::once(0..nm).collect()
        } else {
            (0..nm).map(|i| i..i + 1).collect()
        }
    }

    /// `out = D_r v` over every (harmonic, family) member, coupled (through
    /// the sections, no dense matrix): `v`, `out` are member-major, `n_r`
    /// per member.
    fn apply_dr(&self, setup: &Setup, v: &[f64], out: &mut [f64]) {
        let fixed = &*self.fixed;
        let nr = 3 * fixed.pairs.len();
        let n_p = setup.points.len();
        let sections = setup.sections();
        let nm = fixed.members.len();
        let phi = &fixed.phi;
        out.fill(0.0);
        let mut jb = vec![[0.0; 3]; nm];
        let mut acc = vec![[0.0; 3]; nm];
        for (p, info) in setup.points.iter().enumerate() {
            let pp = &fixed.point_pairs[p];
            let k = setup.model.joints[info.joint].assembled;
            let kk = [k.k_xi, k.k_eta, k.k_theta];
            // The jump at the point of every member: B_p v_i.
            for (i, j) in jb.iter_mut().enumerate() {
                let mut d = [0.0; 3];
                for (a, &q) in pp.iter().enumerate() {
                    for c in 0..3 {
                        let x = v[i * nr + 3 * q + c];
                        for (r, dr) in d.iter_mut().enumerate() {
                            *dr += fixed.b[p][(r, 3 * a + c)] * x;
                        }
                    }
                }
                *j = d;
            }
            acc.iter_mut().for_each(|a| *a = [0.0; 3]);
            let mut used = false;
            for s in 0..sections.len() {
                let Some(t) = self.tangents[s * n_p + p] else {
                    continue;
                };
                used = true;
                let ph = &phi[s * nm..(s + 1) * nm];
                let mut d = [0.0; 3];
                for (j, pj) in jb.iter().zip(ph) {
                    for c in 0..3 {
                        d[c] += pj[c] * j[c];
                    }
                }
                let kd = [0, 1, 2].map(|c| kk[c] * d[c]);
                let w = sections.weight[s];
                let tr = [0, 1, 2].map(|r| w * (t[r][0] * kd[0] + t[r][1] * kd[1] + t[r][2] * kd[2]));
                for (a, pi) in acc.iter_mut().zip(ph) {
                    for c in 0..3 {
                        a[c] += pi[c] * tr[c];
                    }
                }
            }
            if !used {
                continue;
            }
            for (i, a) in acc.iter().enumerate() {
                for (ai, &q) in pp.iter().enumerate() {
                    for c in 0..3 {
                        let g = &fixed.g[p];
                        out[i * nr + 3 * q + c] +=
                            g[(3 * ai + c, 0)] * a[0] + g[(3 * ai + c, 1)] * a[1] + g[(3 * ai + c, 2)] * a[2];
                    }
                }
            }
        }
    }

    /// Solves `(I - D_r Z_r) w = rhs` over every member by right-
    /// preconditioned restarted GMRES, the preconditioner the block LUs;
    /// whether it reached its tolerance.
    fn solve_coupled(&self, setup: &Setup, rhs: &[f64]) -> (Vec<f64>, bool) {
        let fixed = &*self.fixed;
        let nr = 3 * fixed.pairs.len();
        let n = rhs.len();
        let apply_m = |x: &[f64], out: &mut [f64]| {
            out.copy_from_slice(x);
            for (i, lu) in self.lu.iter().enumerate() {
                if lu.ok() {
                    lu.solve_in_place(&mut out[i * nr..(i + 1) * nr], Par::Seq);
                }
            }
        };
        let mut zr_v = vec![0.0; n];
        let mut dz = vec![0.0; n];
        let mut apply_a = |x: &[f64], out: &mut [f64]| {
            for (i, &(h, _)) in fixed.members.iter().enumerate() {
                let xv = nalgebra::DVectorView::from_slice(&x[i * nr..(i + 1) * nr], nr);
                let mut y = nalgebra::DVectorViewMut::from_slice(&mut zr_v[i * nr..(i + 1) * nr], nr);
                y.gemv(1.0, &fixed.zr[h], &xv, 0.0);
            }
            self.apply_dr(setup, &zr_v, &mut dz);
            for ((o, a), b) in out.iter_mut().zip(x).zip(&dz) {
                *o = a - b;
            }
        };
        let restart = INNER_RESTART;
        let max_its = INNER_MAX;
        let tol = INNER_TOLERANCE * norm(rhs);
        let mut w = vec![0.0; n];
        let mut r = rhs.to_vec();
        let mut its = 0;
        let mut t1 = vec![0.0; n];
        let mut t2 = vec![0.0; n];
        while its < max_its {
            let beta = norm(&r);
            if beta <= tol || beta == 0.0 {
                break;
            }
            let mut v: Vec<Vec<f64>> = vec![r.iter().map(|x| x / beta).collect()];
            let mut h = vec![vec![0.0; restart]; restart + 1];
            let (mut cs, mut sn) = (vec![0.0; restart], vec![0.0; restart]);
            let mut g = vec![0.0; restart + 1];
            g[0] = beta;
            let mut k = 0;
            while k < restart && its < max_its {
                apply_m(&v[k], &mut t1);
                apply_a(&t1, &mut t2);
                for j in 0..=k {
                    let hj = dot(&v[j], &t2);
                    h[j][k] = hj;
                    for (a, b) in t2.iter_mut().zip(&v[j]) {
                        *a -= hj * b;
                    }
                }
                let hn = norm(&t2);
                h[k + 1][k] = hn;
                for j in 0..k {
                    let t = cs[j] * h[j][k] + sn[j] * h[j + 1][k];
                    h[j + 1][k] = -sn[j] * h[j][k] + cs[j] * h[j + 1][k];
                    h[j][k] = t;
                }
                let d = (h[k][k] * h[k][k] + h[k + 1][k] * h[k + 1][k]).sqrt();
                cs[k] = h[k][k] / d;
                sn[k] = h[k + 1][k] / d;
                h[k][k] = d;
                h[k + 1][k] = 0.0;
                g[k + 1] = -sn[k] * g[k];
                g[k] *= cs[k];
                its += 1;
                k += 1;
                if g[k].abs() <= tol || hn == 0.0 {
                    break;
                }
                v.push(t2.iter().map(|x| x / hn).collect());
            }
            // Back-substitution and update.
            let mut yk = vec![0.0; k];
            for i in (0..k).rev() {
                let mut s = g[i];
                for j in i + 1..k {
                    s -= h[i][j] * yk[j];
                }
                yk[i] = s / h[i][i];
            }
            t1.fill(0.0);
            for (j, y) in yk.iter().enumerate() {
                for (a, b) in t1.iter_mut().zip(&v[j]) {
                    *a += y * b;
                }
            }
            apply_m(&t1, &mut t2);
            for (a, b) in w.iter_mut().zip(&t2) {
                *a += b;
            }
            apply_a(&w, &mut t1);
            for ((ri, a), b) in r.iter_mut().zip(rhs).zip(&t1) {
                *ri = a - b;
            }
            if g[k].abs() <= tol {
                break;
            }
        }
        let converged = norm(&r) <= 10.0 * tol && w.iter().all(|v| v.is_finite());
        (w, converged)
    }

    /// Takes the joint tangents `tangents`: `D_r` (the joint tangent
    /// `A D S` on the pairs' relative displacements, coupled over each
    /// group) and the LUs of `I - D_r Z_r` follow at the first
    /// [`BlockPreconditioner::displacements`] (a Newton step whose kept
    /// Krylov directions suffice needs none: in a stiff joint's crawl
    /// most steps).
    pub(super) fn update(&mut self, tangents: &[Tangent]) {
        self.tangents.clear();
        self.tangents.extend_from_slice(tangents);
        self.stale = true;
    }

    /// Forms `D_r` and the LUs of every group at the tangents of the last
    /// [`BlockPreconditioner::update`].
    fn factorize(&mut self, setup: &Setup) {
        self.stale = false;
        let n_p = setup.points.len();
        let sections = setup.sections();
        let fixed = &*self.fixed;
        let nr = 3 * fixed.pairs.len();
        let tangents = &self.tangents;
        let groups = self.groups();
        // The buffers of the last factorization, where the groups are the same.
        if self.dr.len() != groups.len() {
            self.dr = groups.iter().map(|_| DMatrix::zeros(0, 0)).collect();
            self.lu = groups.iter().map(|_| DenseLu::new()).collect();
        }
        // One group (the coupled system): faer's LU on every core.
        let par = if groups.len() == 1 {
            Par::rayon(0)
        } else {
            Par::Seq
        };
        groups
            .par_iter()
            .zip(self.dr.par_iter_mut())
            .zip(self.lu.par_iter_mut())
            .for_each(|((range, dr), lu)| {
                let group = &fixed.members[range.clone()];
                let size = group.len() * nr;
                if dr.nrows() == size {
                    dr.fill(0.0);
                } else {
                    *dr = DMatrix::<f64>::zeros(size, size);
                }
                let mut c = vec![nalgebra::Matrix3::<f64>::zeros(); group.len() * group.len()];
                // Phi = (a, a, b) of the group's members at section s.
                let nm = fixed.members.len();
                let phi = |s: usize| &fixed.phi[s * nm + range.start..s * nm + range.end];
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
                        for (i, pi) in phi(s).iter().enumerate() {
                            for (j, pj) in phi(s).iter().enumerate() {
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
                    let pp = &fixed.point_pairs[p];
                    for i in 0..group.len() {
                        for j in 0..group.len() {
                            let e = &fixed.g[p] * c[i * group.len() + j] * &fixed.b[p];
                            for (ai, &qa) in pp.iter().enumerate() {
                                for (bi, &qb) in pp.iter().enumerate() {
                                    for ci in 0..3 {
                                        for cj in 0..3 {
                                            dr[(i * nr + 3 * qa + ci, j * nr + 3 * qb + cj)] +=
                                                e[(3 * ai + ci, 3 * bi + cj)];
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
                // Q = I - D_r Z_r, Z_r block-diagonal over the group.
                let mut q = lu.matrix(size);
                q.fill(0.0);
                q.as_mut().diagonal_mut().fill(1.0);
                let d = MatRef::from_column_major_slice(dr.as_slice(), size, size);
                for (j, &(h, _)) in group.iter().enumerate() {
                    let z = &fixed.zr[h];
                    matmul(
                        q.as_mut().subcols_mut(j * nr, nr),
                        Accum::Add,
                        d.subcols(j * nr, nr),
                        MatRef::from_column_major_slice(z.as_slice(), nr, nr),
                        -1.0,
                        par,
                    );
                }
                // faer's blocked LU: nalgebra's unblocked one took most of
                // the time of a stiff-joint run.
                lu.factorize(par);
            });
    }

    /// `u_s = S P^-1 A r`: the section displacements of the section forces
    /// `r` through the coupled interface tangent of the last
    /// [`BlockPreconditioner::update`] (no sweep; `released` is scratch):
    /// `P^-1 = (Z^-1 - C^T D_r C)^-1 = Z + Z C^T (I - D_r Z_r)^-1 D_r C Z`.
    pub(super) fn displacements(
        &mut self,
        setup: &Setup,
        r: &[f64],
        released: &mut JointAmplitudes,
        u_s: &mut [f64],
    ) {
        if self.stale {
            self.factorize(setup);
        }
        let fixed = self.fixed.clone();
        let fixed = &*fixed;
        let nr = 3 * fixed.pairs.len();
        setup.transfer.analyse(r, released);
        for (h, fams) in released.iter_mut().enumerate() {
            if !setup.transfer.both[h] {
                fams[1].fill(0.0);
            }
        }
        if !self.dense {
            let members = &fixed.members;
            let mut y = Vec::with_capacity(members.len());
            let mut yr = vec![0.0; members.len() * nr];
            for (i, &(h, f)) in members.iter().enumerate() {
                let rv = DVector::from_column_slice(&released[h][f]);
                y.push(&fixed.z[h] * &rv);
                yr[i * nr..(i + 1) * nr].copy_from_slice(fixed.zc[h].tr_mul(&rv).as_slice());
            }
            let mut rhs = vec![0.0; yr.len()];
            self.apply_dr(setup, &yr, &mut rhs);
            let (w, converged) = self.solve_coupled(setup, &rhs);
            if !converged && fixed.dense_allowed {
                // Where GMRES crawls (joints far stiffer than rigid), the
                // dense LU of the coupled system from here on.
                self.dense = true;
                self.factorize(setup);
                return self.displacements(setup, r, released, u_s);
            }
            if w.iter().all(|v| v.is_finite()) {
                for (i, &(h, _)) in members.iter().enumerate() {
                    y[i] += &fixed.zc[h] * DVector::from_column_slice(&w[i * nr..(i + 1) * nr]);
                }
            }
            for (i, &(h, f)) in members.iter().enumerate() {
                released[h][f].copy_from_slice(y[i].as_slice());
            }
            setup.transfer.synthesize(released, u_s);
            return;
        }
        for ((range, lu), dr) in self.groups().into_iter().zip(&self.lu).zip(&self.dr) {
            let group = &fixed.members[range];
            // y = Z r per member, and C Z r = (Z C^T)^T r.
            let mut y = Vec::with_capacity(group.len());
            let mut yr = DVector::<f64>::zeros(group.len() * nr);
            for (i, &(h, f)) in group.iter().enumerate() {
                let rv = DVector::from_column_slice(&released[h][f]);
                y.push(&fixed.z[h] * &rv);
                yr.rows_mut(i * nr, nr).copy_from(&fixed.zc[h].tr_mul(&rv));
            }
            if lu.ok() {
                let mut w = dr * yr;
                lu.solve_in_place(w.as_mut_slice(), Par::rayon(0));
                if w.iter().all(|v| v.is_finite()) {
                    for (i, &(h, _)) in group.iter().enumerate() {
                        y[i] += &fixed.zc[h] * w.rows(i * nr, nr);
                    }
                }
            }
            for (i, &(h, f)) in group.iter().enumerate() {
                released[h][f].copy_from_slice(y[i].as_slice());
            }
        }
        setup.transfer.synthesize(released, u_s);
    }
}
