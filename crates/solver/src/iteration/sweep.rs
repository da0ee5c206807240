//! The sweep ([`Sweep`]): the fixed data of a run at one load state. One
//! sweep back-substitutes every harmonic with its factor: the section
//! displacements of the released section forces (`u_s = u_F + W x`,
//! `W = S K^-1 A`); also the full displacements of a solution, its
//! imbalance, and the record and outcome of an evaluation.

use super::attempt::Converged;
use super::eval::Eval;
use super::setup::Setup;
use super::state::LoadState;
use super::transfer::JointAmplitudes;
use super::types::{IterationRecord, JointField, Outcome};
use crate::joint_law::state_counts;
use crate::loads::HarmonicLoads;
use crate::solution::{Displacements, HarmonicDisplacement};
use rayon::prelude::*;
use std::time::Instant;

/// A load step's `observe` sees the displacements of the harmonics up to
/// this one even when their factors keep only their joint blocks (the
/// loaded faces' mean motion is theirs: harmonics 0 and 1).
pub const OBSERVED_UP_TO: u32 = 1;

/// The largest force imbalance ([`Sweep::imbalance`]) a converged state may
/// leave, relative to the size of the load: converged runs leave 1e-15 to
/// 2e-7, the mechanisms a converged residual hid (a body left free by open
/// joints, displacements of 1e5 m) 0.1 to 1.4.
pub(super) const IMBALANCE_TOL: f64 = 1e-3;

/// The fixed data of a run at one load state: what every evaluation sees.
#[derive(Clone, Copy)]
pub(super) struct Sweep<'s, 'a> {
    /// The fixed data.
    pub(super) setup: &'s Setup<'a>,
    /// The load and the law.
    pub(super) state: LoadState<'s>,
}

impl<'s, 'a> Sweep<'s, 'a> {
    /// `setup` at `state`.
    pub(super) fn new(setup: &'s Setup<'a>, state: LoadState<'s>) -> Self {
        Sweep { setup, state }
    }

    /// One sweep: analyses x (`released` is the buffer), back-substitutes
    /// every harmonic with its factor and lets `finish` complete each
    /// harmonic's joint-node amplitudes. The forces `A x` sit on the joint
    /// nodes only: each solve reads only the joint block of the factor
    /// ([`crate::linear::Model::solve_joint`]).
    fn back_substitute(
        &self,
        x: &[f64],
        released: &mut JointAmplitudes,
        finish: impl Fn(usize, &mut [Vec<f64>; 2]) + Sync,
    ) -> JointAmplitudes {
        let setup = self.setup;
        setup.transfer.analyse(x, released);
        released
            .par_iter()
            .zip(&setup.factor_of)
            .enumerate()
            .map(|(h, (g, factor))| {
                // A harmonic without an antisymmetric family solves one family.
                let mut u = if setup.transfer.both[h] {
                    setup.solve_release(factor, &[&g[0], &g[1]])
                } else {
                    let [s] = setup.solve_release(factor, &[&g[0]]);
                    let zero = vec![0.0; s.len()];
                    [s, zero]
                };
                finish(h, &mut u);
                u
            })
            .collect()
    }

    /// The joint-node displacements `K^-1 (F_start + lambda F + A x)` (one
    /// sweep).
    fn solve_loaded(&self, x: &[f64], released: &mut JointAmplitudes) -> JointAmplitudes {
        let (u0, lambda) = (&self.setup.u0, self.state.lambda);
        let base = self.setup.base.as_ref().map(|(_, b)| b);
        self.back_substitute(x, released, |h, u| {
            for (uk, u0) in u.iter_mut().zip(&u0[h]) {
                for (a, b) in uk.iter_mut().zip(u0) {
                    *a += lambda * b;
                }
            }
            if let Some(base) = base {
                for (uk, b0) in u.iter_mut().zip(&base[h]) {
                    for (a, b) in uk.iter_mut().zip(b0) {
                        *a += b;
                    }
                }
            }
        })
    }

    /// The joint-node displacements `K^-1 A x` (one sweep).
    fn solve_released(&self, x: &[f64], released: &mut JointAmplitudes) -> JointAmplitudes {
        self.back_substitute(x, released, |_, _| {})
    }

    /// `u_s = u_F + W x` (one sweep): the section displacements of the
    /// joint nodes under the loads and the released section forces x.
    /// Returns the joint-node amplitudes.
    pub(super) fn displace(
        &self,
        x: &[f64],
        released: &mut JointAmplitudes,
        u_s: &mut [f64],
    ) -> JointAmplitudes {
        let u = self.solve_loaded(x, released);
        self.setup.transfer.synthesize(&u, u_s);
        u
    }

    /// `W v = S K^-1 A v` (one sweep): the section displacements of the
    /// joint nodes under the section forces `v` alone.
    pub(super) fn apply_w(&self, v: &[f64], released: &mut JointAmplitudes, out: &mut [f64]) {
        let u = self.solve_released(v, released);
        self.setup.transfer.synthesize(&u, out);
    }

    /// The displacements of every node for released section forces `x`:
    /// one full solve of `lambda F + A x` per harmonic up to
    /// [`Problem::whole_up_to`](super::Problem::whole_up_to) (a harmonic
    /// whose factor keeps only its joint block is factorized again for it).
    pub(super) fn full_displacements(&self, x: &[f64]) -> Displacements {
        let loads = self.setup.loads;
        let up_to = self.setup.whole_up_to.unwrap_or(u32::MAX);
        self.displacements(x, (0..loads.len()).filter(|&h| loads[h].m <= up_to).collect())
    }

    /// [`Sweep::full_displacements`] of the harmonics a load step's
    /// `observe` sees before the whole load: up to [`OBSERVED_UP_TO`] (the
    /// loaded faces' mean motion), not the back-substitutions of the others.
    pub(super) fn observed_displacements(&self, x: &[f64]) -> Displacements {
        let loads = self.setup.loads;
        self.displacements(
            x,
            (0..loads.len())
                .filter(|&h| loads[h].m <= OBSERVED_UP_TO)
                .collect(),
        )
    }

    /// The displacements of every node of the harmonics (indices) `wanted`.
    fn displacements(&self, x: &[f64], wanted: Vec<usize>) -> Displacements {
        let setup = self.setup;
        let n = setup.model.mesh.nodes.len();
        let mut released = setup.transfer.zeros();
        setup.transfer.analyse(x, &mut released);
        let lambda = self.state.lambda;
        // With the elastic solution known, only the released forces (on
        // the joint nodes) are solved: the forward solve reads the joint
        // block alone, and a reduced factor with its rest on disk streams
        // that rest for the backward solve (no whole factor in memory, so
        // not bounded).
        let superposed = |h: usize| setup.bodies.is_none() && setup.knows_elastic(h);
        let harmonics = setup.model.map_bounded(
            wanted.len(),
            |i| {
                let (h, factor) = (wanted[i], setup.factor_of[wanted[i]]);
                let streamed = factor.on_disk() && superposed(h);
                !factor.is_full() && !streamed
            },
            |i| {
                let h = wanted[i];
                let (factor, g) = (setup.factor_of[h], &released[h]);
                if superposed(h) {
                    if let Some(mut u) = setup.elastic_at(h, lambda) {
                        let add =
                            |to: &mut [f64], du: &[f64]| to.iter_mut().zip(du).for_each(|(a, v)| *a += v);
                        if setup.transfer.both[h] {
                            let [s, a] = setup.model.solve_joint_whole(factor, &[&g[0], &g[1]]);
                            add(&mut u.symmetric, &s);
                            add(&mut u.antisymmetric, &a);
                        } else {
                            let [s] = setup.model.solve_joint_whole(factor, &[&g[0]]);
                            add(&mut u.symmetric, &s);
                        }
                        return u;
                    }
                }
                let f = setup.load_at(h, lambda);
                let mut loads = [f.rhs(0).into_owned(), f.rhs(1).into_owned()];
                for (vec, gk) in loads.iter_mut().zip(g) {
                    setup.add_at_joint_nodes(gk, vec);
                }
                if setup.transfer.both[h] {
                    let mut u = setup.model.solve(factor, &[&loads[0], &loads[1]]);
                    let mut antisymmetric = u.pop().unwrap_or_default();
                    let mut symmetric = u.pop().unwrap_or_default();
                    f.add_prescribed(0, &mut symmetric);
                    f.add_prescribed(1, &mut antisymmetric);
                    HarmonicDisplacement {
                        m: f.m,
                        symmetric,
                        antisymmetric,
                    }
                } else {
                    let mut symmetric = setup.model.solve(factor, &[&loads[0]]).pop().unwrap_or_default();
                    f.add_prescribed(0, &mut symmetric);
                    HarmonicDisplacement {
                        m: f.m,
                        symmetric,
                        antisymmetric: vec![0.0; 3 * n],
                    }
                }
            },
        );
        Displacements { harmonics }
    }

    /// The released forces `A x` of released section forces `x` as nodal
    /// loads of every harmonic (all nodes; empty without plastic bodies:
    /// the joints' sit on joint nodes no support holds in practice). A
    /// reaction is `K u - f - A x` at a supported DOF.
    pub(super) fn released_loads(&self, x: &[f64]) -> Vec<HarmonicLoads> {
        let setup = self.setup;
        if setup.bodies.is_none() {
            return Vec::new();
        }
        let n = setup.model.mesh.nodes.len();
        let mut released = setup.transfer.zeros();
        setup.transfer.analyse(x, &mut released);
        setup
            .loads
            .iter()
            .zip(&released)
            .map(|(h, g)| {
                let mut out = HarmonicLoads::zeros(h.m, n);
                setup.add_at_joint_nodes(&g[0], &mut out.symmetric);
                setup.add_at_joint_nodes(&g[1], &mut out.antisymmetric);
                out
            })
            .collect()
    }

    /// The volume of the plastic bodies' yielding Gauss points in `ev`:
    /// `sum_s w_s sum_q r |det J| w_q` over the yielding pairs (none without
    /// plastic bodies).
    pub(super) fn plastic_volume(&self, ev: &Eval) -> Option<f64> {
        let bodies = self.setup.bodies.as_ref()?;
        let (n_b, weights) = (bodies.n_points(), &self.setup.sections().weight);
        let mut volume = 0.0;
        for cell in &bodies.cells {
            for q in 0..cell.values.n_points() {
                let ring = cell.values.r(q) * cell.values.weight(q);
                for (s, w) in weights.iter().enumerate() {
                    if ev.yielding[s * n_b + cell.first + q] {
                        volume += w * ring;
                    }
                }
            }
        }
        Some(volume)
    }

    /// The force and moment that the displacements `u` of released section
    /// forces `x` leave unbalanced, relative to the size of the load
    /// (`sum |lambda F|`, times the mesh's extent for moments): the
    /// resultant of the reactions `K u - A x` at the supports and of the
    /// loads `lambda F` elsewhere, over the harmonics 0 and 1 of `u` (the
    /// others have no resultant). Zero in exact arithmetic, as the internal
    /// forces `K u - A x` have no resultant (the released forces are those
    /// of a self-balanced traction or stress) and equal the loads at the
    /// free DOFs; large where a mechanism (a body that open or sliding
    /// joints or yielding soil leave free) makes the solution huge and its
    /// rounding error as large as the load.
    pub(super) fn imbalance(&self, x: &[f64], u: &Displacements) -> f64 {
        let (setup, lambda) = (self.setup, self.state.lambda);
        let mesh = &setup.model.mesh;
        let n = mesh.nodes.len();
        let mut released = setup.transfer.zeros();
        setup.transfer.analyse(x, &mut released);
        let mut size = 0.0;
        let mut sums = Vec::new();
        // (With the forces equivalent to prescribed displacements.)
        let magnitude =
            |f: &HarmonicLoads| -> f64 { f.rhs(0).iter().chain(f.rhs(1).iter()).map(|v| v.abs()).sum() };
        // A stage that unloads is measured against its largest load.
        let mut stage_size = 0.0;
        for (h, load) in setup.loads.iter().enumerate() {
            let f = setup.load_at(h, lambda);
            size += magnitude(&f);
            if setup.base.is_some() {
                stage_size += magnitude(&setup.load_at(h, 0.0)).max(magnitude(&setup.load_at(h, 1.0)));
            }
            let Some(d) = u
                .harmonics
                .iter()
                .find(|d| d.m == load.m && d.m <= OBSERVED_UP_TO)
            else {
                continue;
            };
            let mut v = HarmonicLoads::zeros(load.m, n);
            // The applied forces (not those equivalent to prescribed
            // displacements: the held faces' K u includes them).
            let families = [
                (&d.symmetric, f.symmetric, &mut v.symmetric),
                (&d.antisymmetric, f.antisymmetric, &mut v.antisymmetric),
            ];
            for (k, (ud, fk, out)) in families.into_iter().enumerate() {
                // The loads, and at the supports the reactions K u - A x.
                let mut ax = vec![0.0; fk.len()];
                setup.add_at_joint_nodes(&released[h][k], &mut ax);
                *out = fk;
                let ku = ud
                    .iter()
                    .any(|&v| v != 0.0)
                    .then(|| setup.model.support_forces(load.m, ud));
                // (The internal forces K u - A x: at a free DOF they are the
                // load, and their resultant over every DOF is zero.)
                for (dof, (o, a)) in out.iter_mut().zip(&ax).enumerate() {
                    if setup.model.dofs.is_supported(dof) {
                        *o = ku.as_ref().map_or(0.0, |ku| ku[dof]) - a;
                    }
                }
            }
            sums.push(v);
        }
        let size = f64::max(size, stage_size);
        if size == 0.0 {
            return 0.0;
        }
        let r = crate::loads::load_resultants(&sums, mesh, 0.0);
        let length = mesh
            .nodes
            .iter()
            .fold(0.0f64, |a, p| a.max(p[0].hypot(p[1])))
            .max(f64::MIN_POSITIVE);
        let norm = |v: [f64; 3]| v.iter().map(|c| c * c).sum::<f64>().sqrt();
        (norm(r.force) / size).max(norm(r.moment) / (size * length))
    }

    /// The record of an evaluation.
    pub(super) fn record(
        &self,
        iteration: u32,
        ratio: f64,
        ev: &Eval,
        start: Instant,
        solves: u32,
    ) -> IterationRecord {
        let (open, slip, stick) = state_counts(&ev.state);
        IterationRecord {
            iteration,
            ratio,
            open,
            slip,
            stick,
            seconds: start.elapsed().as_secs_f64(),
            solves,
            load_factor: self.state.lambda,
        }
    }

    /// The converged outcome at released forces `x` and their evaluation
    /// `ev` (one full solve for the displacements of every node).
    pub(super) fn finish(&self, x: &[f64], ev: Eval, history: Vec<IterationRecord>) -> Outcome {
        let displacements = self.full_displacements(x);
        self.finish_with(Converged::new(x.to_vec(), Vec::new(), ev, history), displacements)
    }

    /// The outcome of a converged solve whose displacements are known.
    pub(super) fn finish_with(&self, conv: Converged, displacements: Displacements) -> Outcome {
        Outcome {
            released_spectrum: self.setup.transfer.spectrum(&conv.ev.g),
            field: self.field(&conv.ev),
            body: self.body_field(&conv.ev),
            released: self.released_loads(&conv.x),
            displacements,
            history: conv.history,
        }
    }

    /// The plastic bodies' field of an evaluation.
    pub(super) fn body_field(&self, ev: &Eval) -> Option<super::types::BodyField> {
        let bodies = self.setup.bodies.as_ref()?;
        let points = bodies.positions();
        let cells = bodies.cells_of_points();
        Some(super::types::BodyField {
            sections: self.setup.sections().clone(),
            points,
            cells,
            sigma: ev.sigma.clone(),
            plastic: ev.plastic.clone(),
            yielding: ev.yielding.clone(),
        })
    }

    /// The joint field of an evaluation.
    pub(super) fn field(&self, ev: &Eval) -> JointField {
        JointField {
            sections: self.setup.sections().clone(),
            points: self.setup.points.clone(),
            d: ev.d.clone(),
            p: ev.p.clone(),
            state: ev.state.clone(),
            debonded: match self.state.history {
                Some(h) => h.joints.iter().map(|h| h.debonded).collect(),
                None => ev.broken.clone(),
            },
        }
    }
}
