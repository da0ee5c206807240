//! The fixed data of an iteration ([`Setup`]): the joint points and nodes,
//! the basis tables, the elastic solution; the synthesis at the sections, the
//! analysis into harmonics, the back-substitution sweeps and one evaluation
//! of `Psi`; and [`FixedPoint`], the same evaluation for tests and
//! diagnostics.

use super::attempt::Converged;
use super::eval::Eval;
use super::interface::Interface;
use super::types::{IterationError, IterationRecord, JointField, JointStart, Outcome, PointInfo};
use crate::elements::JointSprings;
use crate::fourier::{Family, Sections};
use crate::joint_law::{relative_trial, state_counts, JointState, PointHistory};
use crate::linear::{HarmonicFactor, Model};
use crate::loads::HarmonicLoads;
use crate::scene::JointLaw;
use crate::solution::{Displacements, HarmonicDisplacement};
use rayon::prelude::*;
use std::sync::{Arc, OnceLock};
use std::time::Instant;

/// A load step's `observe` sees the displacements of the harmonics up to
/// this one even when their factors keep only their joint blocks (the
/// loaded faces' mean motion is theirs: harmonics 0 and 1).
pub const OBSERVED_UP_TO: u32 = 1;

/// The largest force imbalance ([`Setup::imbalance`]) a converged state may
/// leave, relative to the size of the load: converged runs leave 1e-15 to
/// 2e-7, the mechanisms a converged residual hid (a body left free by open
/// joints, displacements of 1e5 m) 0.1 to 1.4.
pub const IMBALANCE_TOL: f64 = 1e-3;

/// (section, point) pairs below which the loops over the sections run on
/// one thread ([`Setup::min_len`]).
pub(super) const SEQUENTIAL_PAIRS: usize = 1024;

/// Joint-node values per harmonic, `[symmetric, antisymmetric]`, each
/// `3 * joint nodes` (the node order of [`Model::joint_nodes`]).
pub(super) type JointAmplitudes = Vec<[Vec<f64>; 2]>;

/// The fixed data of an iteration: points, joint nodes, basis tables.
pub(super) struct Setup<'a> {
    pub(super) model: &'a Model,
    pub(super) laws: &'a [JointLaw],
    pub(super) sections: &'a Sections,
    loads: &'a [HarmonicLoads],
    pub(super) factor_of: Vec<&'a HarmonicFactor>,
    pub(super) points: Vec<PointInfo>,
    /// Joint nodes (global indices) and each point's nodes in that list.
    pub(super) joint_nodes: Vec<usize>,
    pub(super) local: Vec<Vec<usize>>,
    /// `phi[(s * n_h + h) * 2 + family] = (phi_rz, phi_theta)`.
    phi: Vec<(f64, f64)>,
    pub(super) n_h: usize,
    /// The joint-node amplitudes of the elastic solution `K^-1 F`.
    u0: JointAmplitudes,
    /// Whether harmonic h has an antisymmetric family to solve.
    pub(super) both: Vec<bool>,
    /// The load factor lambda: the loads are `lambda F` (1 but in steps).
    pub(super) lambda: f64,
    /// The committed history of every (section, point) pair (index
    /// `s * n_points + p`): `Some` selects the history law of stepped
    /// loading, `None` the paper's law.
    pub(super) history: Option<Vec<PointHistory>>,
    /// "Release" the whole traction of the assembled springs: only for
    /// [`Setup::reference_release`].
    pub(super) reference_law: bool,
    /// Normal stresses within this of 0 count as 0 in the law (1e-10 of the
    /// largest joint traction of the elastic solution): the analysis and
    /// synthesis of a pure shear leave a normal stress of round-off size,
    /// which must not open or debond a joint whose tensile strength is 0.
    pub(super) tension_tol: f64,
    /// The traction of every pair at zero displacement (the end of an
    /// initial phase; empty: none) and its debonded pairs.
    pub(super) start: JointStart,
    /// The stiff-joint preconditioner's fixed data, formed at first use and
    /// kept for every step of the run.
    pub(super) interface: OnceLock<Arc<Interface>>,
}

impl<'a> Setup<'a> {
    /// Checks the harmonics and sections and collects the joint points.
    pub(super) fn new(
        model: &'a Model,
        factors: &'a [HarmonicFactor],
        loads: &'a [HarmonicLoads],
        laws: &'a [JointLaw],
        sections: &'a Sections,
        elastic: Option<&Displacements>,
        start: Option<&JointStart>,
    ) -> Result<Self, IterationError> {
        let mesh = &model.mesh;
        let n = mesh.nodes.len();
        let factor_of: Vec<&HarmonicFactor> = loads
            .iter()
            .map(|h| {
                factors
                    .iter()
                    .find(|f| f.m == h.m)
                    .ok_or_else(|| IterationError::Setup(format!("harmonic {} is not factorized", h.m)))
            })
            .collect::<Result<_, _>>()?;
        let torsion = loads
            .iter()
            .any(|h| h.m == 0 && h.symmetric.iter().skip(2).step_by(3).any(|&v| v != 0.0));
        if sections.half && (torsion || loads.iter().any(|h| h.antisymmetric.iter().any(|&v| v != 0.0))) {
            return Err(IterationError::Setup(
                "the loads have antisymmetric or torsional content: the sections must cover the full turn"
                    .into(),
            ));
        }
        // The paper's M + 1 sections resolve harmonics up to M - 1 exactly (the
        // Nyquist harmonic M aliases); fewer, or uneven ones that resolve less,
        // are refused.
        let m_max = loads.iter().map(|h| h.m).max().unwrap_or(0);
        let resolved = sections.resolves_up_to(m_max);
        if m_max > 0 && resolved.is_none_or(|r| r + 1 < m_max) {
            let symmetric = !torsion && loads.iter().all(|h| h.antisymmetric.iter().all(|&v| v == 0.0));
            let advice = if symmetric {
                format!(
                    "give at least {} evenly spaced sections over the half turn (the paper's M + 1), or {} over the full turn",
                    m_max + 1,
                    2 * m_max
                )
            } else {
                format!(
                    "the loads are not symmetric about theta = 0: give at least {} over the full turn (evenly spaced in [0, 360) degrees)",
                    2 * m_max
                )
            };
            return Err(IterationError::Setup(format!(
                "the {} sections resolve harmonics only up to {}, not 0..={m_max}: {advice}",
                sections.len(),
                resolved.map_or("none".into(), |r| r.to_string()),
            )));
        }
        // A stiff joint (assembled softer than its law, solved on its released
        // tractions) needs every harmonic seen whole at the sections: at the
        // paper's M + 1 the circumferential motion of harmonic M, sin(M theta),
        // vanishes at every section, its spring difference cannot be released,
        // and Newton stalls (Scene P from k h / E = 12.5; M + 2 converge).
        let stiff = model.joints.iter().position(|j| j.assembled != j.springs);
        if let Some(stiff) = stiff.and_then(|j| mesh.joints.get(j)) {
            if m_max > 0 && resolved.is_none_or(|r| r < m_max) {
                let at_least = if sections.half {
                    format!("{} evenly spaced sections over the half turn", m_max + 2)
                } else {
                    format!("{} evenly spaced sections over the full turn", 2 * m_max + 1)
                };
                return Err(IterationError::Setup(format!(
                    "joint '{}' is stiff (solved on its released tractions) and the {} sections resolve harmonics only up to {}, not {m_max}: harmonic {m_max} is not seen whole at them (at the paper's M + 1 evenly spaced sections its circumferential motion vanishes at every one), so its joint forces cannot be released; give at least {at_least}, or leave `sections` out (the default)",
                    stiff.name,
                    sections.len(),
                    resolved.map_or("none".into(), |r| r.to_string()),
                )));
            }
        }

        // Points and joint nodes.
        let points = super::types::joint_point_infos(model);
        let joint_nodes = model.joint_nodes().to_vec();
        let mut where_ = vec![usize::MAX; n];
        for (j, &k) in joint_nodes.iter().enumerate() {
            where_[k] = j;
        }
        let local = points
            .iter()
            .map(|p| p.nodes.iter().map(|&k| where_[k]).collect())
            .collect();
        let n_h = loads.len();
        let mut phi = Vec::with_capacity(sections.len() * n_h * 2);
        for &t in &sections.theta {
            for h in loads {
                phi.push(sections.phi(h.m, Family::Symmetric, t));
                phi.push(sections.phi(h.m, Family::Antisymmetric, t));
            }
        }
        // The elastic solution at the joint nodes: given, or one full solve.
        let both: Vec<bool> = loads.iter().map(|h| h.m > 0 && !sections.half).collect();
        let u0 = model.map_bounded(
            loads.len(),
            |h| !factor_of[h].is_full(),
            |h| {
                let (f, factor, both) = (&loads[h], factor_of[h], both[h]);
                let given = elastic.and_then(|e| e.harmonics.iter().find(|d| d.m == f.m));
                let u = if let Some(d) = given {
                    let mut u = vec![d.symmetric.clone()];
                    if both {
                        u.push(d.antisymmetric.clone());
                    }
                    u
                } else if both {
                    model.solve(factor, &[&f.symmetric, &f.antisymmetric])
                } else {
                    model.solve(factor, &[&f.symmetric])
                };
                let pick = |k: usize| -> Vec<f64> {
                    let mut out = vec![0.0; 3 * joint_nodes.len()];
                    if let Some(u) = u.get(k) {
                        for (j, &node) in joint_nodes.iter().enumerate() {
                            out[3 * j..3 * j + 3].copy_from_slice(&u[3 * node..3 * node + 3]);
                        }
                    }
                    out
                };
                [pick(0), pick(1)]
            },
        );
        let mut setup = Setup {
            model,
            laws,
            sections,
            loads,
            factor_of,
            points,
            joint_nodes,
            local,
            phi,
            n_h,
            u0,
            both,
            lambda: 1.0,
            history: None,
            reference_law: false,
            tension_tol: 0.0,
            start: JointStart::default(),
            interface: OnceLock::new(),
        };
        if let Some(start) = start {
            let n = setup.n_pairs();
            if start.traction.len() != n || start.debonded.len() != n {
                return Err(IterationError::Setup(format!(
                    "the joint start state has {} tractions and {} debonded flags for {n} (section, point) pairs",
                    start.traction.len(),
                    start.debonded.len()
                )));
            }
            setup.start = start.clone();
        }
        let t0_max = setup
            .start
            .traction
            .iter()
            .map(|t| t[0].hypot(t[1]).hypot(t[2]))
            .fold(0.0f64, f64::max);
        setup.tension_tol = 1e-10 * setup.elastic_traction_max().max(t0_max);
        Ok(setup)
    }

    /// The largest joint traction `|k_a d|` of the elastic solution (the
    /// whole load, the springs as assembled) over every point and section.
    fn elastic_traction_max(&self) -> f64 {
        let mut u_s = vec![0.0; self.len()];
        self.synthesize_all(&self.u0, &mut u_s);
        let m = self.per_section();
        (0..self.sections.len())
            .map(|s| {
                self.points
                    .iter()
                    .enumerate()
                    .map(|(i, info)| {
                        let d = self.relative(i, &u_s[s * m..(s + 1) * m]);
                        // The assembled springs: with a softened joint the
                        // law's springs on this (softer) solution would
                        // overstate the tractions k / k_ref times.
                        let t = self.model.joints[info.joint].assembled.traction(d);
                        t[0].hypot(t[1]).hypot(t[2])
                    })
                    .fold(0.0f64, f64::max)
            })
            .fold(0.0f64, f64::max)
    }

    /// The initial traction of pair `k` (index `s * n_points + p`).
    pub(super) fn t0(&self, k: usize) -> [f64; 3] {
        self.start.traction.get(k).copied().unwrap_or([0.0; 3])
    }

    /// The trial traction the law sees at relative displacement `d` of a
    /// point of `joint`: `t0 + k (d - slip)` (the slip of the history `h`),
    /// its normal part zeroed where within [`Setup::tension_tol`] of 0.
    pub(super) fn trial(
        &self,
        joint: usize,
        d: [f64; 3],
        h: Option<&PointHistory>,
        t0: [f64; 3],
    ) -> [f64; 3] {
        let k = &self.model.joints[joint].springs;
        let kd = match h {
            Some(h) => relative_trial(k, d, h),
            None => k.traction(d),
        };
        let mut t = [t0[0] + kd[0], t0[1] + kd[1], t0[2] + kd[2]];
        if t[1].abs() <= self.tension_tol {
            t[1] = 0.0;
        }
        t
    }

    /// Length of a section-force vector x: sections x joint nodes x 3.
    pub(super) fn len(&self) -> usize {
        self.sections.len() * 3 * self.joint_nodes.len()
    }

    /// Values per section (`3 * joint nodes`, at least 1 for chunking).
    pub(super) fn per_section(&self) -> usize {
        (3 * self.joint_nodes.len()).max(1)
    }

    /// Point-sections.
    pub(super) fn n_pairs(&self) -> usize {
        self.sections.len() * self.points.len()
    }

    /// Zero joint-node loads per harmonic (the analysis buffer).
    pub(super) fn zero_loads(&self) -> JointAmplitudes {
        let n = 3 * self.joint_nodes.len();
        self.loads.iter().map(|_| [vec![0.0; n], vec![0.0; n]]).collect()
    }

    /// Evaluation buffers (no point broken yet).
    pub(super) fn new_eval(&self) -> Eval {
        let (nx, np) = (self.len(), self.n_pairs());
        Eval {
            u_s: vec![0.0; nx],
            g: vec![0.0; nx],
            d: vec![[0.0; 3]; np],
            p: vec![[0.0; 3]; np],
            state: vec![JointState::Stick; np],
            broken: if self.start.debonded.is_empty() {
                vec![false; np]
            } else {
                self.start.debonded.clone()
            },
        }
    }

    pub(super) fn phi(&self, s: usize, h: usize, family: Family) -> (f64, f64) {
        self.phi[(s * self.n_h + h) * 2 + family as usize]
    }

    /// Synthesizes the joint-node displacements at section `s`.
    fn synthesize(&self, u: &JointAmplitudes, s: usize, out: &mut [f64]) {
        out.fill(0.0);
        for (h, hd) in u.iter().enumerate() {
            for (family, amp) in [(Family::Symmetric, &hd[0]), (Family::Antisymmetric, &hd[1])] {
                let (a, b) = self.phi(s, h, family);
                if a == 0.0 && b == 0.0 {
                    continue;
                }
                for (o, v) in out.chunks_exact_mut(3).zip(amp.chunks_exact(3)) {
                    o[0] += a * v[0];
                    o[1] += a * v[1];
                    o[2] += b * v[2];
                }
            }
        }
    }

    /// The smallest number of sections a parallel loop over them hands to
    /// one thread: all of them (no hand-off) when the joint has fewer than
    /// [`SEQUENTIAL_PAIRS`] (section, point) pairs, where waking the
    /// threads cost more than the work.
    pub(super) fn min_len(&self) -> usize {
        if self.n_pairs() < SEQUENTIAL_PAIRS {
            usize::MAX
        } else {
            1
        }
    }

    /// Synthesizes the joint-node displacements at every section.
    pub(super) fn synthesize_all(&self, u: &JointAmplitudes, u_s: &mut [f64]) {
        u_s.par_chunks_mut(self.per_section())
            .with_min_len(self.min_len())
            .enumerate()
            .for_each(|(s, out)| self.synthesize(u, s, out));
    }

    /// One sweep: the joint-node displacements `K^-1 (F + A x)`
    /// (`with_loads`) or `K^-1 A x`, every harmonic with its factor. The
    /// forces `A x` sit on the joint nodes only: each solve reads only the
    /// joint block of the factor ([`Model::solve_joint`]).
    fn solve(&self, x: &[f64], with_loads: bool, released: &mut JointAmplitudes) -> JointAmplitudes {
        self.analyse(x, released);
        released
            .par_iter()
            .zip(&self.factor_of)
            .enumerate()
            .map(|(h, (g, factor))| {
                // A harmonic without an antisymmetric family solves one family.
                let mut u = if self.both[h] {
                    self.model.solve_joint(factor, &[&g[0], &g[1]])
                } else {
                    let [s] = self.model.solve_joint(factor, &[&g[0]]);
                    let zero = vec![0.0; s.len()];
                    [s, zero]
                };
                if with_loads {
                    for (uk, u0) in u.iter_mut().zip(&self.u0[h]) {
                        for (a, b) in uk.iter_mut().zip(u0) {
                            *a += self.lambda * b;
                        }
                    }
                }
                u
            })
            .collect()
    }

    /// The displacements of every node for released section forces `x`:
    /// one full solve of `lambda F + A x` per harmonic (a harmonic whose
    /// factor keeps only its joint block is factorized again for it).
    pub(super) fn full_displacements(&self, x: &[f64]) -> Displacements {
        self.displacements(x, false)
    }

    /// [`Setup::full_displacements`] of the harmonics a load step's
    /// `observe` sees before the whole load: up to [`OBSERVED_UP_TO`] (the
    /// loaded faces' mean motion), not the back-substitutions of the others.
    pub(super) fn observed_displacements(&self, x: &[f64]) -> Displacements {
        self.displacements(x, true)
    }

    fn displacements(&self, x: &[f64], observed: bool) -> Displacements {
        let n = self.model.mesh.nodes.len();
        let mut released = self.zero_loads();
        self.analyse(x, &mut released);
        let wanted: Vec<usize> = (0..self.loads.len())
            .filter(|&h| !observed || self.loads[h].m <= OBSERVED_UP_TO)
            .collect();
        let harmonics = self.model.map_bounded(
            wanted.len(),
            |i| !self.factor_of[wanted[i]].is_full(),
            |i| {
                let h = wanted[i];
                let (factor, g) = (self.factor_of[h], &released[h]);
                let f = self.loads[h].scaled(self.lambda);
                let mut loads = [f.symmetric, f.antisymmetric];
                for (vec, gk) in loads.iter_mut().zip(g) {
                    for (&k, gj) in self.joint_nodes.iter().zip(gk.chunks_exact(3)) {
                        for c in 0..3 {
                            vec[3 * k + c] += gj[c];
                        }
                    }
                }
                if self.both[h] {
                    let mut u = self.model.solve(factor, &[&loads[0], &loads[1]]);
                    let antisymmetric = u.pop().unwrap_or_default();
                    let symmetric = u.pop().unwrap_or_default();
                    HarmonicDisplacement {
                        m: f.m,
                        symmetric,
                        antisymmetric,
                    }
                } else {
                    let symmetric = self.model.solve(factor, &[&loads[0]]).pop().unwrap_or_default();
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

    /// The force and moment that the displacements `u` of released section
    /// forces `x` leave unbalanced, relative to the size of the load
    /// (`sum |lambda F|`, times the mesh's extent for moments): the
    /// resultant of the reactions `K u` at the supports and of the loads
    /// `lambda F + A x` elsewhere, over the harmonics 0 and 1 of `u` (the
    /// others have no resultant). Zero in exact arithmetic, as `K` has no
    /// resultant and the released forces come in opposite pairs; large
    /// where a mechanism (a body that open or sliding joints leave free)
    /// makes the solution huge and its rounding error as large as the load.
    pub(super) fn imbalance(&self, x: &[f64], u: &Displacements) -> f64 {
        let mesh = &self.model.mesh;
        let n = mesh.nodes.len();
        let mut released = self.zero_loads();
        self.analyse(x, &mut released);
        let mut size = 0.0;
        let mut sums = Vec::new();
        for (h, load) in self.loads.iter().enumerate() {
            let magnitude: f64 = load
                .symmetric
                .iter()
                .chain(&load.antisymmetric)
                .map(|v| v.abs())
                .sum();
            size += self.lambda.abs() * magnitude;
            let Some(d) = u
                .harmonics
                .iter()
                .find(|d| d.m == load.m && d.m <= OBSERVED_UP_TO)
            else {
                continue;
            };
            let f = load.scaled(self.lambda);
            let mut v = HarmonicLoads::zeros(load.m, n);
            let families = [
                (&d.symmetric, f.symmetric, &mut v.symmetric),
                (&d.antisymmetric, f.antisymmetric, &mut v.antisymmetric),
            ];
            for (k, (ud, fk, out)) in families.into_iter().enumerate() {
                *out = fk;
                for (&node, g) in self.joint_nodes.iter().zip(released[h][k].chunks_exact(3)) {
                    for c in 0..3 {
                        out[3 * node + c] += g[c];
                    }
                }
                let ku = ud
                    .iter()
                    .any(|&v| v != 0.0)
                    .then(|| self.model.support_forces(load.m, ud));
                for (dof, o) in out.iter_mut().enumerate() {
                    if self.model.dofs.is_supported(dof) {
                        *o = ku.as_ref().map_or(0.0, |ku| ku[dof]);
                    }
                }
            }
            sums.push(v);
        }
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

    /// `Psi(x)` (one sweep): solve for `F + A x`, synthesize, release. The
    /// break memory `ev.broken` is carried forward. Returns the joint-node
    /// amplitudes.
    pub(super) fn evaluate(
        &self,
        x: &[f64],
        released: &mut JointAmplitudes,
        ev: &mut Eval,
    ) -> JointAmplitudes {
        let u = self.displace(x, released, &mut ev.u_s);
        self.release_all(ev);
        u
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
        let u = self.solve(x, true, released);
        self.synthesize_all(&u, u_s);
        u
    }

    /// `W v = S K^-1 A v` (one sweep): the section displacements of the
    /// joint nodes under the section forces `v` alone.
    pub(super) fn apply_w(&self, v: &[f64], released: &mut JointAmplitudes, out: &mut [f64]) {
        let u = self.solve(v, false, released);
        self.synthesize_all(&u, out);
    }

    /// `|f_m| / c_m` of section forces `x` for m = 0 up to the highest
    /// harmonic the sections resolve (both families together).
    fn spectrum(&self, x: &[f64]) -> Vec<f64> {
        let n_j = self.joint_nodes.len();
        let top = self.sections.exact_up_to();
        (0..=top)
            .map(|m| {
                let mut sum = 0.0;
                for family in [Family::Symmetric, Family::Antisymmetric] {
                    let mut f = vec![0.0; 3 * n_j];
                    for (s, (&t, &w)) in self.sections.theta.iter().zip(&self.sections.weight).enumerate() {
                        let (a, b) = self.sections.phi(m, family, t);
                        let xs = &x[s * 3 * n_j..(s + 1) * 3 * n_j];
                        for j in 0..n_j {
                            f[3 * j] += w * a * xs[3 * j];
                            f[3 * j + 1] += w * a * xs[3 * j + 1];
                            f[3 * j + 2] += w * b * xs[3 * j + 2];
                        }
                    }
                    sum += f.iter().map(|v| v * v).sum::<f64>();
                }
                sum.sqrt() / crate::elements::c_m(m)
            })
            .collect()
    }

    /// Analyses section forces `x` into harmonic loads (the transpose of
    /// [`Setup::synthesize`] with the section weights).
    pub(super) fn analyse(&self, x: &[f64], released: &mut JointAmplitudes) {
        let n_j = self.joint_nodes.len();
        released
            .par_iter_mut()
            .with_min_len(self.min_len())
            .enumerate()
            .for_each(|(h, out)| {
                for s in 0..self.sections.len() {
                    let w = self.sections.weight[s];
                    let xs = &x[s * 3 * n_j..(s + 1) * 3 * n_j];
                    for (k, (family, vec)) in [Family::Symmetric, Family::Antisymmetric]
                        .into_iter()
                        .zip(out.iter_mut())
                        .enumerate()
                    {
                        if s == 0 {
                            vec.fill(0.0);
                        }
                        let (a, b) = self.phi(s, h, family);
                        if (a == 0.0 && b == 0.0) || (k == 1 && !self.both[h]) {
                            continue;
                        }
                        for (v, xj) in vec.chunks_exact_mut(3).zip(xs.chunks_exact(3)) {
                            v[0] += w * a * xj[0];
                            v[1] += w * a * xj[1];
                            v[2] += w * b * xj[2];
                        }
                    }
                }
            });
    }

    /// `Psi = max_s |f_s|` of a residual.
    pub(super) fn section_max(&self, f: &[f64]) -> f64 {
        f.chunks(self.per_section())
            .map(|c| c.iter().map(|v| v * v).sum::<f64>().sqrt())
            .fold(0.0f64, f64::max)
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
            load_factor: self.lambda,
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
            released_spectrum: self.spectrum(&conv.ev.g),
            field: self.field(&conv.ev),
            displacements,
            history: conv.history,
        }
    }

    /// The joint field of an evaluation.
    pub(super) fn field(&self, ev: &Eval) -> JointField {
        JointField {
            sections: self.sections.clone(),
            points: self.points.clone(),
            d: ev.d.clone(),
            p: ev.p.clone(),
            state: ev.state.clone(),
            debonded: match &self.history {
                Some(h) => h.iter().map(|h| h.debonded).collect(),
                None => ev.broken.clone(),
            },
        }
    }

    /// Whether a joint is assembled with softer springs than its law's.
    pub(super) fn softened(&self) -> bool {
        self.model.joints.iter().any(|j| j.assembled != j.springs)
    }

    /// The reference `Psi_0` of a stepped run: the paper's Eq. 12, the
    /// largest released section force of the elastic solution of the whole
    /// load under the paper's law. Where a stiff joint is assembled softer,
    /// its release carries the stiff spring (`k / k_ref` times the forces,
    /// or nothing at all for a law that never yields), so the reference is
    /// instead the largest section force the joints carry in the elastic
    /// solution of the model as assembled (one sweep).
    pub(super) fn reference_release(&mut self) -> f64 {
        let (lambda, history) = (self.lambda, self.history.take());
        self.lambda = 1.0;
        self.reference_law = self.softened();
        let mut released = self.zero_loads();
        let mut ev = self.new_eval();
        self.evaluate(&vec![0.0; self.len()], &mut released, &mut ev);
        self.reference_law = false;
        (self.lambda, self.history) = (lambda, history);
        self.section_max(&ev.g)
    }

    /// The springs of the joint of pair `i` (index `s * n_points + p`).
    pub(super) fn springs(&self, i: usize) -> JointSprings {
        let info = &self.points[i % self.points.len().max(1)];
        self.model.joints[info.joint].springs
    }

    /// Largest load component (the scale of "nothing released").
    pub(super) fn load_scale(&self) -> f64 {
        self.loads
            .iter()
            .flat_map(|h| h.symmetric.iter().chain(&h.antisymmetric))
            .fold(0.0f64, |a, v| a.max(v.abs()))
    }
}
