//! The preconditioner of Newton's Krylov solve for joints much stiffer
//! than their elements (used by the traction form, [`super::traction`],
//! with its tangent `D = Dd^-1 Dv k_a`).
//!
//! With `Z_m = [K_m^-1]` on the joint nodes (dense, formed once per run
//! from the elastic factors: `3 n_j / 2` joint-block solves per harmonic)
//! and `W = S Z A` (synthesis, joint-node solve, analysis), the
//! push-through identity gives the exact inverse of Newton's Jacobian
//! `J = D W - I`:
//!
//! ```text
//! J^-1 = -(I + D S (Z^-1 - A D S)^-1 A)
//! ```
//!
//! `A D S` couples the harmonics through the variation of the joint
//! tangent D around the turn. The joint acts only on the jumps of its node
//! pairs: with C the relative displacement of each pair (top minus
//! bottom, `n_r = 3 pairs`, half the `3 n_j` joint-node unknowns),
//! `A D S = C^T D_r C` and
//!
//! ```text
//! P^-1 = (Z^-1 - A D S)^-1 = Z + Z C^T (I - D_r Z_r)^-1 D_r C Z,   Z_r = C Z C^T
//! ```
//!
//! The coupled interface system `(I - D_r Z_r) w = D_r C Z r` (order:
//! members x `n_r`, a member being a harmonic and family) is solved by
//! GMRES in its Schur form, preconditioned by the sparse LU of its
//! element-banded part ([`super::banded`]): about ten iterations at every
//! stiffness, no dense coupled matrix, no sweep. Its dense LU
//! ([`InterfaceSolve::Dense`], an LU of the whole order per Newton step) is
//! kept as the reference.
//!
//! A stiff elastic joint makes `D W` close to I along the joint's modes
//! (the released traction comes back through the same stiff spring): `J`
//! has eigenvalues of order `E / (k h)` there, and the plain Krylov solve
//! crawls; `P` removes them.

use super::banded::BandedLu;
use super::dense_lu::DenseLu;
use super::gmres::gmres;
use super::interface::Interface;
use super::release::Tangent;
use super::setup::Setup;
use super::transfer::JointAmplitudes;
use super::types::InterfaceSolve;
use faer::linalg::matmul::matmul;
use faer::{Accum, MatRef, Par};
use nalgebra::{DMatrix, DVector, Matrix3};
use rayon::prelude::*;
use std::sync::Arc;

/// The GMRES on the coupled interface system: its relative tolerance (on
/// the left-preconditioned residual; 9-18 iterations from k h / E = 1 to
/// 1e6), its iteration limit and its restart length. Near a capacity the
/// stiff joint's Newton path depends on it as on round-off: with 1e-12 the
/// torsion block of crates/solver/tests/stiff_limits.rs at k h / E = 1e4
/// stalled at 0.906 of its load from 0.898 (exact 0.909; docs/stability.md,
/// item 10).
const INNER_TOLERANCE: f64 = 1e-10;
const INNER_MAX: usize = 400;
const INNER_RESTART: usize = 60;

/// How the coupled system is solved at the current tangents.
enum Coupled {
    Banded(Box<BandedLu>),
    /// `D_r` over every member and the LU of `I - D_r Z_r`.
    Dense(DMatrix<f64>, DenseLu),
}

/// The preconditioner: its fixed data and the coupled system at the
/// current tangents.
pub(super) struct StiffPreconditioner {
    fixed: Arc<Interface>,
    coupled: Coupled,
    /// The joint tangents of the last update.
    tangents: Vec<Tangent>,
    /// Whether `coupled` is older than `tangents`.
    stale: bool,
}

impl StiffPreconditioner {
    /// The preconditioner of `setup` (its fixed data formed at the first
    /// call).
    pub(super) fn new(setup: &Setup, solve: InterfaceSolve) -> Self {
        StiffPreconditioner {
            fixed: setup
                .interface
                .get_or_init(|| Arc::new(Interface::new(setup)))
                .clone(),
            coupled: match solve {
                InterfaceSolve::Banded => Coupled::Banded(Box::new(BandedLu::new())),
                InterfaceSolve::Dense => Coupled::Dense(DMatrix::zeros(0, 0), DenseLu::new()),
            },
            tangents: Vec::new(),
            stale: false,
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

    /// `v <- P v`: the jumps each member cannot have set to zero.
    fn project(&self, v: &mut [f64]) {
        let nr = 3 * self.fixed.pairs.len();
        for (i, null) in self.fixed.null.iter().enumerate() {
            for (q, n) in null {
                let at = i * nr + 3 * q;
                let x = nalgebra::Vector3::from_column_slice(&v[at..at + 3]);
                let px = x - n * x;
                v[at..at + 3].copy_from_slice(px.as_slice());
            }
        }
    }

    /// Solves `(I - D_r Z_r) w = rhs` over every member: by GMRES on
    /// `H y = P rhs`, `H = S - P D_r P`, left-preconditioned by the banded LU,
    /// and `w = S y` (module `banded`); or by the dense LU.
    fn solve_coupled(&self, setup: &Setup, rhs: &[f64]) -> Vec<f64> {
        let fixed = &*self.fixed;
        match &self.coupled {
            Coupled::Dense(_, lu) => {
                let mut w = rhs.to_vec();
                if lu.ok() {
                    lu.solve_in_place(&mut w, Par::rayon(0));
                }
                w
            }
            Coupled::Banded(lu) => {
                // Left-preconditioned: GMRES minimizes |B^-1 (b - H y)|,
                // which weighs the bodies' soft jumps as much as the
                // joint's stiff ones (right-preconditioned, |b - H y| is
                // the stiff jumps' residual: at k h / E = 1e6 on Scene P
                // the outer Krylov solve then needed 29 directions).
                let n = rhs.len();
                let mut b = rhs.to_vec();
                self.project(&mut b);
                lu.solve_in_place(fixed, &mut b);
                let mut t = vec![0.0; n];
                let mut dt = vec![0.0; n];
                let apply = |v: &[f64], out: &mut [f64]| {
                    fixed.schur_apply(v, out);
                    t.copy_from_slice(v);
                    self.project(&mut t);
                    self.apply_dr(setup, &t, &mut dt);
                    self.project(&mut dt);
                    for (o, d) in out.iter_mut().zip(&dt) {
                        *o -= d;
                    }
                    lu.solve_in_place(fixed, out);
                };
                let identity = |v: &[f64], out: &mut [f64]| out.copy_from_slice(v);
                let (y, _) = gmres(apply, identity, &b, INNER_TOLERANCE, INNER_RESTART, INNER_MAX);
                // w = S y (= rhs + D_r y on the jumps Z C^T sees, without
                // the cancellation of two terms of the joint's stiffness).
                let mut w = vec![0.0; n];
                if y.iter().all(|v| v.is_finite()) {
                    fixed.schur_apply(&y, &mut w);
                }
                w
            }
        }
    }

    /// Takes the joint tangents `tangents`: the coupled system follows at
    /// the first [`StiffPreconditioner::displacements`] (a Newton step
    /// whose kept Krylov directions suffice needs none).
    pub(super) fn update(&mut self, tangents: &[Tangent]) {
        self.tangents.clear();
        self.tangents.extend_from_slice(tangents);
        self.stale = true;
    }

    /// Per point, `C_p(i, j) = sum_s w_s Phi_i T_s K Phi_j` (local axes,
    /// `Phi = (a, a, b)`) for every two members i, j (none where the point
    /// has no tangent at any section).
    fn point_couplings(&self, setup: &Setup) -> Vec<Vec<Matrix3<f64>>> {
        let fixed = &*self.fixed;
        let n_p = setup.points.len();
        let sections = setup.sections();
        let nm = fixed.members.len();
        let tangents = &self.tangents;
        setup
            .points
            .par_iter()
            .enumerate()
            .map(|(p, info)| {
                let k = setup.model.joints[info.joint].assembled;
                let kk = [k.k_xi, k.k_eta, k.k_theta];
                let mut c = Vec::new();
                for s in 0..sections.len() {
                    let Some(t) = tangents[s * n_p + p] else {
                        continue;
                    };
                    if c.is_empty() {
                        c = vec![Matrix3::zeros(); nm * nm];
                    }
                    let w = sections.weight[s];
                    let ph = &fixed.phi[s * nm..(s + 1) * nm];
                    for (i, pi) in ph.iter().enumerate() {
                        for (j, pj) in ph.iter().enumerate() {
                            let cij = &mut c[i * nm + j];
                            for r in 0..3 {
                                for q in 0..3 {
                                    cij[(r, q)] += w * pi[r] * t[r][q] * kk[q] * pj[q];
                                }
                            }
                        }
                    }
                }
                c
            })
            .collect()
    }

    /// Forms the coupled system at the tangents of the last
    /// [`StiffPreconditioner::update`] and factorizes it.
    fn factorize(&mut self, setup: &Setup) {
        self.stale = false;
        let couplings = self.point_couplings(setup);
        let fixed = &*self.fixed;
        match &mut self.coupled {
            Coupled::Banded(lu) => {
                lu.factorize(fixed, &couplings);
            }
            Coupled::Dense(dr, lu) => {
                let nm = fixed.members.len();
                let nr = 3 * fixed.pairs.len();
                let size = nm * nr;
                if dr.nrows() == size {
                    dr.fill(0.0);
                } else {
                    *dr = DMatrix::<f64>::zeros(size, size);
                }
                for (p, c) in couplings.iter().enumerate() {
                    if c.is_empty() {
                        continue;
                    }
                    let pp = &fixed.point_pairs[p];
                    for i in 0..nm {
                        for j in 0..nm {
                            let e = &fixed.g[p] * c[i * nm + j] * &fixed.b[p];
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
                // Q = I - D_r Z_r, Z_r block-diagonal over the members.
                let mut q = lu.matrix(size);
                q.fill(0.0);
                q.as_mut().diagonal_mut().fill(1.0);
                let d = MatRef::from_column_major_slice(dr.as_slice(), size, size);
                for (j, &(h, _)) in fixed.members.iter().enumerate() {
                    let z = &fixed.zr[h];
                    matmul(
                        q.as_mut().subcols_mut(j * nr, nr),
                        Accum::Add,
                        d.subcols(j * nr, nr),
                        MatRef::from_column_major_slice(z.as_slice(), nr, nr),
                        -1.0,
                        Par::rayon(0),
                    );
                }
                lu.factorize(Par::rayon(0));
            }
        }
    }

    /// `u_s = S P^-1 A r`: the section displacements of the section forces
    /// `r` through the coupled interface tangent of the last
    /// [`StiffPreconditioner::update`] (no sweep; `released` is scratch):
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
        let members = &fixed.members;
        // y = Z r per member, and C Z r = (Z C^T)^T r.
        let mut y = Vec::with_capacity(members.len());
        let mut yr = vec![0.0; members.len() * nr];
        for (i, &(h, f)) in members.iter().enumerate() {
            let rv = DVector::from_column_slice(&released[h][f]);
            y.push(&*fixed.z[h] * &rv);
            yr[i * nr..(i + 1) * nr].copy_from_slice(fixed.zc[h].tr_mul(&rv).as_slice());
        }
        let mut rhs = vec![0.0; yr.len()];
        match &self.coupled {
            Coupled::Dense(dr, _) => {
                let v = dr * DVector::from_column_slice(&yr);
                rhs.copy_from_slice(v.as_slice());
            }
            Coupled::Banded(_) => self.apply_dr(setup, &yr, &mut rhs),
        }
        let w = self.solve_coupled(setup, &rhs);
        if w.iter().all(|v| v.is_finite()) {
            for (i, &(h, _)) in members.iter().enumerate() {
                y[i] += &fixed.zc[h] * DVector::from_column_slice(&w[i * nr..(i + 1) * nr]);
            }
        }
        for (i, &(h, f)) in members.iter().enumerate() {
            released[h][f].copy_from_slice(y[i].as_slice());
        }
        setup.transfer.synthesize(released, u_s);
    }
}
