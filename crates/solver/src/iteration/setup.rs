//! The fixed data of an iteration ([`Setup`]): the checked problem, the
//! joint points and nodes, the [`Transfer`] between sections and harmonics,
//! the joint-node amplitudes of the elastic solution and the initial
//! tractions; and what a joint point does with them (its relative
//! displacement, the nodal forces of a traction, its trial traction).

use super::body::Bodies;
use super::eval::Eval;
use super::interface::Interface;
use super::transfer::{JointAmplitudes, Transfer};
use super::types::{joint_point_infos, IterationError, JointStart, PointInfo, Problem, StageEnd};
use crate::elements::{add_traction_forces, relative_displacement, JointSprings};
use crate::fourier::Sections;
use crate::joint_law::{relative_trial, JointState, PointHistory};
use crate::linear::{HarmonicFactor, Model};
use crate::loads::HarmonicLoads;
use crate::scene::JointLaw;
use crate::solution::{Displacements, HarmonicDisplacement};
use std::sync::{Arc, OnceLock};

/// The fixed data of an iteration: points, joint nodes, basis, the elastic
/// solution. Nothing in it changes during a run but the preconditioner's
/// data, formed once at first use.
pub(super) struct Setup<'a> {
    pub(super) model: &'a Model,
    pub(super) laws: &'a [JointLaw],
    pub(super) loads: &'a [HarmonicLoads],
    pub(super) factor_of: Vec<&'a HarmonicFactor>,
    pub(super) points: Vec<PointInfo>,
    /// Joint nodes (global indices) and each point's nodes in that list.
    pub(super) joint_nodes: Vec<usize>,
    /// The plastic bodies (none: every body elastic).
    pub(super) bodies: Option<Bodies>,
    pub(super) local: Vec<Vec<usize>>,
    /// The basis of the loaded harmonics at the sections.
    pub(super) transfer: Transfer<'a>,
    /// The joint-node amplitudes of the elastic solution `K^-1 F`.
    pub(super) u0: JointAmplitudes,
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
    /// [`Problem::whole_up_to`].
    pub(super) whole_up_to: Option<u32>,
    /// [`Problem::cancel`].
    cancel: Option<&'a std::sync::atomic::AtomicBool>,
    /// The loads at the stage's start (as `loads`, harmonic by harmonic)
    /// and their elastic joint-node amplitudes ([`Problem::from`]).
    pub(super) base: Option<(Vec<HarmonicLoads>, JointAmplitudes)>,
    /// The whole elastic solutions known: of `loads` and of the stage's
    /// start (none where not given).
    pub(super) elastic: [Option<&'a Displacements>; 2],
    /// The converged state the stage starts from.
    pub(super) resume: Option<&'a StageEnd>,
}

impl<'a> Setup<'a> {
    /// Checks the harmonics and sections and collects the joint points;
    /// the joints start from `start` (none: unstressed and intact).
    pub(super) fn new(problem: &Problem<'a>, start: Option<&JointStart>) -> Result<Self, IterationError> {
        let Problem {
            model,
            factors,
            loads,
            laws,
            sections,
            elastic,
            whole_up_to,
            from,
            cancel,
        } = *problem;
        let n = model.mesh.nodes.len();
        let factor_of: Vec<&HarmonicFactor> = loads
            .iter()
            .map(|h| {
                factors
                    .iter()
                    .find(|f| f.m == h.m)
                    .ok_or_else(|| IterationError::Setup(format!("harmonic {} is not factorized", h.m)))
            })
            .collect::<Result<_, _>>()?;
        check_sections(model, loads, sections)?;

        // Points and joint nodes.
        let points = joint_point_infos(model);
        let joint_nodes = model.joint_nodes().to_vec();
        let mut where_ = vec![usize::MAX; n];
        for (j, &k) in joint_nodes.iter().enumerate() {
            where_[k] = j;
        }
        let local = points
            .iter()
            .map(|p| p.nodes.iter().map(|&k| where_[k]).collect())
            .collect();
        let ms: Vec<u32> = loads.iter().map(|h| h.m).collect();
        let both: Vec<bool> = loads.iter().map(|h| h.m > 0 && !sections.half).collect();
        let bodies = Bodies::new(model)?;
        if bodies.is_some() {
            if let Some(f) = factor_of.iter().find(|f| !f.is_full()) {
                return Err(IterationError::Setup(format!(
                    "harmonic {} is factorized only for its joints (the factor memory budget): plastic bodies need whole factors; raise AXIJOINT_FACTOR_MEMORY",
                    f.m
                )));
            }
        }
        let (nb, nbp) = bodies.as_ref().map_or((0, 0), |b| (b.nodes.len(), b.n_points()));
        let transfer = Transfer::new(sections, &ms, both, (joint_nodes.len(), points.len()), (nb, nbp));
        let release_nodes: Vec<usize> = joint_nodes
            .iter()
            .chain(bodies.iter().flat_map(|b| &b.nodes))
            .copied()
            .collect();
        let u0 = elastic_amplitudes(model, loads, &factor_of, &transfer.both, &release_nodes, elastic);
        let base = from.map(|f| {
            let loads: Vec<HarmonicLoads> = loads
                .iter()
                .map(|h| {
                    f.loads
                        .iter()
                        .find(|b| b.m == h.m)
                        .cloned()
                        .unwrap_or_else(|| HarmonicLoads::zeros(h.m, n))
                })
                .collect();
            let u = elastic_amplitudes(
                model,
                &loads,
                &factor_of,
                &transfer.both,
                &release_nodes,
                Some(f.elastic),
            );
            (loads, u)
        });
        let mut setup = Setup {
            model,
            laws,
            loads,
            factor_of,
            points,
            joint_nodes,
            bodies,
            local,
            transfer,
            u0,
            tension_tol: 0.0,
            start: JointStart::default(),
            interface: OnceLock::new(),
            whole_up_to,
            cancel,
            base,
            elastic: [elastic, from.map(|f| f.elastic)],
            resume: from.map(|f| f.end),
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
            let n_b = setup.bodies.as_ref().map_or(0, Bodies::n_points);
            for (what, len) in [
                ("stresses", start.body_stress.len()),
                ("plastic strains", start.body_plastic.len()),
            ] {
                if len != 0 && len != n_b {
                    return Err(IterationError::Setup(format!(
                        "the start state has {len} body {what} for {n_b} plastic body points"
                    )));
                }
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

    /// The loads of harmonic (index) `h` at load factor `lambda`:
    /// `F_start + lambda F` ([`Problem::from`]).
    pub(super) fn load_at(&self, h: usize, lambda: f64) -> HarmonicLoads {
        let mut f = self.loads[h].scaled(lambda);
        if let Some((base, _)) = &self.base {
            f.add(1.0, &base[h]);
        }
        f
    }

    /// The whole elastic displacements `K^-1 F(lambda)` of harmonic `h`
    /// (index) as the sum of the known solutions ([`Setup::elastic`]), if
    /// they hold it: a full solve then needs only the released forces'.
    pub(super) fn elastic_at(&self, h: usize, lambda: f64) -> Option<HarmonicDisplacement> {
        let e = self.known_elastic(h, 0)?;
        let both = self.transfer.both[h];
        let mut u = HarmonicDisplacement {
            m: e.m,
            symmetric: e.symmetric.iter().map(|v| lambda * v).collect(),
            antisymmetric: if both {
                e.antisymmetric.iter().map(|v| lambda * v).collect()
            } else {
                vec![0.0; e.symmetric.len()]
            },
        };
        if self.base.is_some() {
            let b = self.known_elastic(h, 1)?;
            u.symmetric
                .iter_mut()
                .zip(&b.symmetric)
                .for_each(|(a, v)| *a += v);
            if both {
                u.antisymmetric
                    .iter_mut()
                    .zip(&b.antisymmetric)
                    .for_each(|(a, v)| *a += v);
            }
        }
        Some(u)
    }

    /// Whether [`Setup::elastic_at`] knows harmonic `h` (index).
    pub(super) fn knows_elastic(&self, h: usize) -> bool {
        self.known_elastic(h, 0).is_some() && (self.base.is_none() || self.known_elastic(h, 1).is_some())
    }

    /// Harmonic `h` (index) of the known elastic solution `k` (0: of the
    /// loads, 1: of the stage's start).
    fn known_elastic(&self, h: usize, k: usize) -> Option<&'a HarmonicDisplacement> {
        let m = self.loads[h].m;
        self.elastic[k].and_then(|d| d.harmonics.iter().find(|x| x.m == m))
    }

    /// The elastic joint-node amplitudes at load factor `lambda`.
    pub(super) fn u0_at(&self, lambda: f64) -> JointAmplitudes {
        let mut u: JointAmplitudes = self
            .u0
            .iter()
            .map(|fam| fam.clone().map(|v| v.iter().map(|a| lambda * a).collect()))
            .collect();
        if let Some((_, b)) = &self.base {
            for (uh, bh) in u.iter_mut().zip(b) {
                for (uk, bk) in uh.iter_mut().zip(bh) {
                    for (a, v) in uk.iter_mut().zip(bk) {
                        *a += v;
                    }
                }
            }
        }
        u
    }

    /// The largest joint traction `|k_a d|` of the elastic solution (the
    /// whole load, the springs as assembled) over every point and section.
    fn elastic_traction_max(&self) -> f64 {
        let mut u_s = vec![0.0; self.len()];
        self.transfer.synthesize(&self.u0_at(1.0), &mut u_s);
        let m = self.per_section();
        (0..self.sections().len())
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

    /// The sections.
    pub(super) fn sections(&self) -> &'a Sections {
        self.transfer.sections
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
        self.transfer.len()
    }

    /// Values per section (`3 * joint nodes`, at least 1 for chunking).
    pub(super) fn per_section(&self) -> usize {
        self.transfer.per_section()
    }

    /// Point-sections.
    pub(super) fn n_pairs(&self) -> usize {
        self.sections().len() * self.points.len()
    }

    /// The smallest number of sections a parallel loop over them hands to
    /// one thread ([`Transfer::min_len`]).
    pub(super) fn min_len(&self) -> usize {
        self.transfer.min_len()
    }

    /// Plastic body points a section (0 without plastic bodies).
    pub(super) fn body_points(&self) -> usize {
        self.bodies.as_ref().map_or(0, Bodies::n_points)
    }

    /// Evaluation buffers (no point broken yet).
    pub(super) fn new_eval(&self) -> Eval {
        let (nx, np) = (self.len(), self.n_pairs());
        let nb = self.sections().len() * self.body_points();
        Eval {
            sigma: vec![[0.0; 6]; nb],
            plastic: vec![[0.0; 6]; nb],
            yielding: vec![false; nb],
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

    /// The relative displacement at point `i` from the joint-node values
    /// `u` of one section.
    pub(super) fn relative(&self, i: usize, u: &[f64]) -> [f64; 3] {
        let nl = &self.local[i];
        let mut ue = [0.0; 18];
        for (a, &j) in nl.iter().enumerate() {
            ue[3 * a..3 * a + 3].copy_from_slice(&u[3 * j..3 * j + 3]);
        }
        relative_displacement(&self.points[i].point, &ue[..3 * nl.len()])
    }

    /// Adds the nodal forces of traction `t` at point `i` to the joint-node
    /// forces `out` of one section (`fe`: scratch).
    pub(super) fn scatter(&self, i: usize, t: [f64; 3], fe: &mut [f64; 18], out: &mut [f64]) {
        if t == [0.0; 3] {
            return;
        }
        let nl = &self.local[i];
        let fe = &mut fe[..3 * nl.len()];
        fe.fill(0.0);
        add_traction_forces(&self.points[i].point, t, 1.0, fe);
        for (a, &j) in nl.iter().enumerate() {
            for c in 0..3 {
                out[3 * j + c] += fe[3 * a + c];
            }
        }
    }

    /// The opening rate `rho` of the history law for a trial traction of
    /// the springs `k` at a point of `joint`: its opening spring over `k_eta`.
    pub(super) fn opening_rate(&self, joint: usize, k: &JointSprings) -> f64 {
        let opening = self.model.joints[joint].opening;
        if k.k_eta > 0.0 && opening > 0.0 {
            opening / k.k_eta
        } else {
            1.0
        }
    }

    /// Adds release-node values `g` (`3 * (joint nodes + body nodes)`) to
    /// the global vector `out` (`3 * nodes`).
    pub(super) fn add_at_joint_nodes(&self, g: &[f64], out: &mut [f64]) {
        let body_nodes = self.bodies.iter().flat_map(|b| &b.nodes);
        for (&k, gj) in self.joint_nodes.iter().chain(body_nodes).zip(g.chunks_exact(3)) {
            for c in 0..3 {
                out[3 * k + c] += gj[c];
            }
        }
    }

    /// Solves `K_m u = f` for forces `f` on the release nodes (`K` right-hand
    /// sides of `3 * (joint nodes + body nodes)`) and returns `u` there:
    /// only the joint block of the factor without plastic bodies
    /// ([`Model::solve_joint`]), a whole solve with them.
    pub(super) fn solve_release<const K: usize>(
        &self,
        factor: &HarmonicFactor,
        loads: &[&[f64]; K],
    ) -> [Vec<f64>; K] {
        if self.bodies.is_none() {
            return self.model.solve_joint(factor, loads);
        }
        let n = 3 * self.model.mesh.nodes.len();
        let full: Vec<Vec<f64>> = loads
            .iter()
            .map(|g| {
                let mut f = vec![0.0; n];
                self.add_at_joint_nodes(g, &mut f);
                f
            })
            .collect();
        let refs: Vec<&[f64]> = full.iter().map(Vec::as_slice).collect();
        let u = self.model.solve(factor, &refs);
        std::array::from_fn(|k| self.at_release_nodes(&u[k]))
    }

    /// The release-node values (`3 * (joint nodes + body nodes)`) of the
    /// global vector `u` (`3 * nodes`).
    pub(super) fn at_release_nodes(&self, u: &[f64]) -> Vec<f64> {
        let body_nodes = self.bodies.iter().flat_map(|b| &b.nodes);
        self.joint_nodes
            .iter()
            .chain(body_nodes)
            .flat_map(|&k| [u[3 * k], u[3 * k + 1], u[3 * k + 2]])
            .collect()
    }

    /// `Psi = max_s |f_s|` of a residual.
    pub(super) fn section_max(&self, f: &[f64]) -> f64 {
        f.chunks(self.per_section())
            .map(|c| c.iter().map(|v| v * v).sum::<f64>().sqrt())
            .fold(0.0f64, f64::max)
    }

    /// Whether the caller asked the iteration to stop
    /// ([`Problem::cancel`](super::types::Problem::cancel)).
    pub(super) fn cancelled(&self) -> bool {
        self.cancel
            .is_some_and(|c| c.load(std::sync::atomic::Ordering::Relaxed))
    }

    /// Whether a joint is assembled with softer springs than its law's.
    pub(super) fn softened(&self) -> bool {
        self.model.joints.iter().any(|j| j.assembled != j.springs)
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

/// Refuses sections that cannot carry `loads`: a half turn with
/// antisymmetric or torsional loads, fewer sections than the harmonics
/// need, or, with a stiff joint, sections that do not see the highest
/// harmonic whole.
fn check_sections(model: &Model, loads: &[HarmonicLoads], sections: &Sections) -> Result<(), IterationError> {
    let mesh = &model.mesh;
    let torsion = loads
        .iter()
        .any(|h| h.m == 0 && h.symmetric.iter().skip(2).step_by(3).any(|&v| v != 0.0));
    if sections.half && (torsion || loads.iter().any(|h| h.antisymmetric.iter().any(|&v| v != 0.0))) {
        return Err(IterationError::Setup(
            "the loads have antisymmetric or torsional content: the sections must cover the full turn".into(),
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
    Ok(())
}

/// The joint-node amplitudes of the elastic solution `K^-1 F` of every
/// harmonic of `loads`: from `elastic` where it holds the harmonic, else
/// one full solve with its factor.
fn elastic_amplitudes(
    model: &Model,
    loads: &[HarmonicLoads],
    factor_of: &[&HarmonicFactor],
    both: &[bool],
    release_nodes: &[usize],
    elastic: Option<&Displacements>,
) -> JointAmplitudes {
    model.map_bounded(
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
            } else {
                let mut u = if both {
                    model.solve(factor, &[&f.rhs(0), &f.rhs(1)])
                } else {
                    model.solve(factor, &[&f.rhs(0)])
                };
                for (k, uk) in u.iter_mut().enumerate() {
                    f.add_prescribed(k, uk);
                }
                u
            };
            let pick = |k: usize| -> Vec<f64> {
                let mut out = vec![0.0; 3 * release_nodes.len()];
                if let Some(u) = u.get(k) {
                    for (j, &node) in release_nodes.iter().enumerate() {
                        out[3 * j..3 * j + 3].copy_from_slice(&u[3 * node..3 * node + 3]);
                    }
                }
                out
            };
            [pick(0), pick(1)]
        },
    )
}
