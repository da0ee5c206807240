//! Solves on the joint nodes: the joint-block solve, its whole-mesh
//! variant and the stiff joints' `Z_m`, kept with the factor.

use super::{HarmonicFactor, Model};
use crate::factor::{solve_trailing, solve_trailing_whole, InMemory};
use nalgebra::DMatrix;
use std::sync::Arc;

impl Model {
    /// Solves `K_m u = f` for forces `f` on the joint nodes only (`K`
    /// right-hand sides, each `3 * joint_nodes().len()`, node-DOF order of
    /// [`Model::joint_nodes`]) and returns `u` at the joint nodes. The joint
    /// equations are ordered last in the factorization, so this reads only
    /// the trailing block of the factor: a small fraction of a full solve.
    pub fn solve_joint<const K: usize>(&self, factor: &HarmonicFactor, loads: &[&[f64]; K]) -> [Vec<f64>; K] {
        let mut b = self.joint_rhs(factor, loads);
        solve_trailing(&factor.symbolic, &factor.values, factor.offset, &mut b);
        let mut out: [Vec<f64>; K] = std::array::from_fn(|_| vec![0.0; 3 * self.joint_nodes.len()]);
        for (j, &k) in self.joint_nodes.iter().enumerate() {
            for c in 0..3 {
                for (e, coef) in self.dofs.terms(3 * k + c) {
                    for (q, o) in out.iter_mut().enumerate() {
                        o[3 * j + c] += coef * b[self.trail_pos[e]][q];
                    }
                }
            }
        }
        out
    }

    /// `Z_m = [K_m^-1]` on the joint nodes (order `3 * joint_nodes().len()`,
    /// node-DOF order of [`Model::joint_nodes`]) of `factor`, a factor of
    /// this model: formed at the first call from `3 n_j` unit loads through
    /// [`Model::solve_joint`], then kept with the factor (whose values never
    /// change), so every run on the same factors (the M/2 check's beside
    /// the M run's, an initial phase's before it) shares it.
    pub fn joint_inverse(&self, factor: &HarmonicFactor) -> Arc<DMatrix<f64>> {
        factor
            .joint_inverse
            .get_or_init(|| {
                // Unit loads in blocks: each pass reads the factor's joint
                // block once. Measured on the pile in geostatic soil at
                // 1.1e5 unknowns per harmonic (3 n_j = 2526, M = 8,
                // k h / E = 1e4): 128 at a time, the whole run 1.10x faster
                // than with 16, 256 within 3 % of 128; on a small joint a
                // wide block is mostly padding.
                let n = 3 * self.joint_nodes.len();
                Arc::new(if n >= 1024 {
                    self.unit_solves::<128>(factor, n)
                } else {
                    self.unit_solves::<16>(factor, n)
                })
            })
            .clone()
    }

    /// `[K_m^-1]` on the joint nodes, `K` unit loads a pass.
    fn unit_solves<const K: usize>(&self, factor: &HarmonicFactor, n: usize) -> DMatrix<f64> {
        let mut z = DMatrix::<f64>::zeros(n, n);
        let mut e: [Vec<f64>; K] = std::array::from_fn(|_| vec![0.0; n]);
        for first in (0..n).step_by(K) {
            let cols = K.min(n - first);
            for (q, eq) in e.iter_mut().enumerate().take(cols) {
                eq[first + q] = 1.0;
            }
            let loads: [&[f64]; K] = std::array::from_fn(|q| e[q].as_slice());
            let u = self.solve_joint(factor, &loads);
            for (q, eq) in e.iter_mut().enumerate().take(cols) {
                z.column_mut(first + q).copy_from_slice(&u[q]);
                eq[first + q] = 0.0;
            }
        }
        z
    }

    /// The trailing right-hand sides of joint-node forces `loads` (as
    /// [`Model::solve_joint`] takes them), zero at pinned equations.
    fn joint_rhs<const K: usize>(&self, factor: &HarmonicFactor, loads: &[&[f64]; K]) -> Vec<[f64; K]> {
        let mut b = vec![[0.0; K]; self.trailing.len()];
        for (j, &k) in self.joint_nodes.iter().enumerate() {
            for c in 0..3 {
                for (e, coef) in self.dofs.terms(3 * k + c) {
                    for (q, f) in loads.iter().enumerate() {
                        b[self.trail_pos[e]][q] += coef * f[3 * j + c];
                    }
                }
            }
        }
        for (bi, &e) in b.iter_mut().zip(&self.trailing) {
            if factor.pinned[e] {
                *bi = [0.0; K];
            }
        }
        b
    }

    /// Solves `K_m u = f` for forces `f` on the joint nodes only (as
    /// [`Model::solve_joint`] takes them) and returns `u` at every node
    /// (node-DOF order, zero at supports). A factor reduced to its joint
    /// block whose rest is on disk reads that rest last first, through a
    /// window of about a MiB, for the backward solve (the forward solve of
    /// such loads needs only the joint block): no whole factor in memory
    /// and no forward pass over the rest. One not on disk is factorized
    /// again.
    pub fn solve_joint_whole<const K: usize>(
        &self,
        factor: &HarmonicFactor,
        loads: &[&[f64]; K],
    ) -> [Vec<f64>; K] {
        let b = self.joint_rhs(factor, loads);
        let in_memory = |f: &HarmonicFactor| {
            solve_trailing_whole(&f.symbolic, &f.values, 0, &b, &mut InMemory(&f.values))
                .expect("values in memory are read without error")
        };
        let x = if factor.is_full() {
            in_memory(factor)
        } else {
            let streamed = factor.spilled.as_ref().and_then(|s| {
                let mut leading = s.backward().ok()?;
                solve_trailing_whole(&factor.symbolic, &factor.values, factor.offset, &b, &mut leading).ok()
            });
            streamed.unwrap_or_else(|| {
                let whole = self.refactorize(factor);
                let x = in_memory(&whole);
                self.give_back(whole.values);
                x
            })
        };
        std::array::from_fn(|q| {
            let xq: Vec<f64> = x.iter().map(|v| v[q]).collect();
            let mut u = vec![0.0; 3 * self.dofs.n_nodes];
            self.dofs.expand(&xq, &mut u);
            u
        })
    }
}
