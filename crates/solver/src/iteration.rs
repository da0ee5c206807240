//! The stress-transfer iteration (DESIGN.md section 3, the paper's steps
//! (1)-(5)): the joints stay elastic in every K_m (the harmonics stay
//! decoupled), and the inadmissible part of their traction is released as
//! unbalanced nodal forces, analysed back into harmonics and solved again
//! with the same factors.
//!
//! With `G(u)` the released forces, each iteration solves
//! `K_m u_m = F_m + G_m(u_prev)`; the residual at section s is the change of
//! the released nodal forces there, `rho_s = g_s(u_k) - g_s(u_{k-1})`, and
//! `Psi_k = max_s |rho_s|`, `Psi_0 = max_s |g_s(u_0)|` (the paper's Eq. 12:
//! converged when `Psi_k / Psi_0 < epsilon`).
//!
//! Written as a fixed point on the released section forces x:
//! `Psi(x) = release(synthesize(K^-1 (F + A x)))`; the paper iterates
//! `x <- Psi(x)` (and then `rho_s = Psi(x)_s - x_s`), [`Method::Anderson`]
//! mixes the last iterates. Either way only back-substitutions are repeated.

use crate::driver::{Displacements, HarmonicDisplacement};
use crate::elements::{add_traction_forces, joint_points, relative_displacement, JointPoint};
use crate::fourier::{Family, Sections};
use crate::joint_law::{admissible, JointState};
use crate::linear::{HarmonicFactor, Model};
use crate::loads::HarmonicLoads;
use crate::scene::JointLaw;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// How the next released forces are chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// The paper's plain iteration: `x_{k+1} = Psi(x_k)`.
    Plain,
    /// Anderson mixing over the last `depth` iterates (type II).
    Anderson {
        /// History length.
        depth: usize,
    },
}

/// Convergence settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IterationSettings {
    /// Update rule.
    pub method: Method,
    /// Converged when `Psi_k / Psi_0 < epsilon`.
    pub epsilon: f64,
    /// Iteration limit (solves).
    pub max_iterations: u32,
    /// No equilibrium when the residual ratio makes no new minimum (by 0.1 %)
    /// within this many iterations.
    pub stall_window: u32,
}

impl Default for IterationSettings {
    fn default() -> Self {
        IterationSettings {
            method: Method::Anderson { depth: 8 },
            epsilon: 1e-6,
            max_iterations: 500,
            stall_window: 40,
        }
    }
}

/// One line of the convergence history.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct IterationRecord {
    /// Iteration (1 = the elastic solve).
    pub iteration: u32,
    /// `Psi_k / Psi_0` (0 for the first iteration when nothing is released).
    pub ratio: f64,
    /// Open (point, section) pairs.
    pub open: usize,
    /// Slipping pairs.
    pub slip: usize,
    /// Sticking pairs.
    pub stick: usize,
    /// Seconds since the iteration started.
    pub seconds: f64,
}

/// Where a joint integration point is.
#[derive(Clone, Debug, PartialEq)]
pub struct PointInfo {
    /// Joint index (as `mesh.joints`).
    pub joint: usize,
    /// Element index within the joint.
    pub element: usize,
    /// The integration point.
    pub point: JointPoint,
    /// Element nodes, bottom then top.
    pub nodes: Vec<usize>,
}

/// Joint relative displacements, admissible tractions and states at every
/// point and section: index `s * n_points + p`.
#[derive(Clone, Debug, PartialEq)]
pub struct JointField {
    /// The sections.
    pub sections: Sections,
    /// The points.
    pub points: Vec<PointInfo>,
    /// Relative displacement `(d_xi, d_eta, d_theta)`.
    pub d: Vec<[f64; 3]>,
    /// Admissible traction `(tau_xi, sigma, tau_theta)`.
    pub p: Vec<[f64; 3]>,
    /// State.
    pub state: Vec<JointState>,
}

/// A converged nonlinear solution.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// Displacement amplitudes.
    pub displacements: Displacements,
    /// Size of each harmonic of the released traction at the solution,
    /// `|f_m| / c_m` over the joint nodes, for m up to what the sections
    /// resolve: content above the solved M shows what the truncation drops.
    pub released_spectrum: Vec<f64>,
    /// Convergence history.
    pub history: Vec<IterationRecord>,
    /// Joint field at the solution.
    pub field: JointField,
}

/// Why the iteration stopped without a solution.
#[derive(Debug, thiserror::Error)]
pub enum IterationError {
    /// The load exceeds what the joints can carry (the residual stalls or grows).
    #[error("no equilibrium: {reason}; joint '{joint}' carries most of the unbalanced force ({open} open and {slip} slipping of {total} point-sections at iteration {iteration})")]
    NoEquilibrium {
        /// The joint with the largest residual.
        joint: String,
        /// What was detected.
        reason: String,
        /// Counts at the last iteration.
        open: usize,
        /// Slipping count.
        slip: usize,
        /// Point-sections.
        total: usize,
        /// Last iteration.
        iteration: u32,
        /// The history so far.
        history: Vec<IterationRecord>,
    },
    /// The iteration limit was reached while still converging.
    #[error("not converged in {iterations} iterations: residual ratio {ratio:.3e} > epsilon {epsilon:.1e}; it was still decreasing: raise solver.max_iterations (if it decreases ever more slowly, the load may be close to what the joints can carry)")]
    NotConverged {
        /// Iterations done.
        iterations: u32,
        /// Last ratio.
        ratio: f64,
        /// The target.
        epsilon: f64,
        /// The history.
        history: Vec<IterationRecord>,
    },
    /// A harmonic or section setting that cannot work.
    #[error("{0}")]
    Setup(String),
}

impl IterationError {
    /// The history up to the stop, if any.
    pub fn history(&self) -> &[IterationRecord] {
        match self {
            IterationError::NoEquilibrium { history, .. } | IterationError::NotConverged { history, .. } => {
                history
            }
            IterationError::Setup(_) => &[],
        }
    }
}

/// The fixed data of an iteration: points, joint nodes, basis tables.
struct Setup<'a> {
    model: &'a Model,
    laws: &'a [JointLaw],
    sections: &'a Sections,
    points: Vec<PointInfo>,
    /// Joint nodes (global indices) and each point's nodes in that list.
    joint_nodes: Vec<usize>,
    local: Vec<Vec<usize>>,
    /// `phi[(s * n_h + h) * 2 + family] = (phi_rz, phi_theta)`.
    phi: Vec<(f64, f64)>,
    n_h: usize,
}

impl Setup<'_> {
    fn phi(&self, s: usize, h: usize, family: Family) -> (f64, f64) {
        self.phi[(s * self.n_h + h) * 2 + family as usize]
    }

    /// Synthesizes the joint-node displacements at section `s`.
    fn synthesize(&self, u: &Displacements, s: usize, out: &mut [f64]) {
        out.fill(0.0);
        for (h, hd) in u.harmonics.iter().enumerate() {
            for (family, amp) in [
                (Family::Symmetric, &hd.symmetric),
                (Family::Antisymmetric, &hd.antisymmetric),
            ] {
                let (a, b) = self.phi(s, h, family);
                if a == 0.0 && b == 0.0 {
                    continue;
                }
                for (j, &n) in self.joint_nodes.iter().enumerate() {
                    out[3 * j] += a * amp[3 * n];
                    out[3 * j + 1] += a * amp[3 * n + 1];
                    out[3 * j + 2] += b * amp[3 * n + 2];
                }
            }
        }
    }

    /// Evaluates the law at every point of section `s`; returns the released
    /// joint-node forces (per radian) into `g`, and the field values.
    #[allow(clippy::too_many_arguments)]
    fn release(
        &self,
        u_s: &[f64],
        broken: &mut [bool],
        g: &mut [f64],
        d_out: &mut [[f64; 3]],
        p_out: &mut [[f64; 3]],
        st_out: &mut [JointState],
    ) {
        g.fill(0.0);
        let mut ue = [0.0; 18];
        let mut fe = [0.0; 18];
        for (i, info) in self.points.iter().enumerate() {
            let nl = &self.local[i];
            for (a, &j) in nl.iter().enumerate() {
                ue[3 * a..3 * a + 3].copy_from_slice(&u_s[3 * j..3 * j + 3]);
            }
            let springs = self.model.joints[info.joint].springs;
            let d = relative_displacement(&info.point, &ue[..3 * nl.len()]);
            let (p, state) = admissible(&self.laws[info.joint], &springs, d, &mut broken[i]);
            let trial = springs.traction(d);
            let excess = [trial[0] - p[0], trial[1] - p[1], trial[2] - p[2]];
            if excess != [0.0; 3] {
                fe[..3 * nl.len()].fill(0.0);
                add_traction_forces(&info.point, excess, 1.0, &mut fe[..3 * nl.len()]);
                for (a, &j) in nl.iter().enumerate() {
                    for c in 0..3 {
                        g[3 * j + c] += fe[3 * a + c];
                    }
                }
            }
            d_out[i] = d;
            p_out[i] = p;
            st_out[i] = state;
        }
    }
}

impl Setup<'_> {
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
    fn analyse(&self, x: &[f64], released: &mut [HarmonicLoads]) {
        let n_j = self.joint_nodes.len();
        released.par_iter_mut().enumerate().for_each(|(h, out)| {
            out.symmetric.fill(0.0);
            out.antisymmetric.fill(0.0);
            for s in 0..self.sections.len() {
                let w = self.sections.weight[s];
                let xs = &x[s * 3 * n_j..(s + 1) * 3 * n_j];
                for (family, vec) in [
                    (Family::Symmetric, &mut out.symmetric),
                    (Family::Antisymmetric, &mut out.antisymmetric),
                ] {
                    let (a, b) = self.phi(s, h, family);
                    if a == 0.0 && b == 0.0 {
                        continue;
                    }
                    for (j, &k) in self.joint_nodes.iter().enumerate() {
                        vec[3 * k] += w * a * xs[3 * j];
                        vec[3 * k + 1] += w * a * xs[3 * j + 1];
                        vec[3 * k + 2] += w * b * xs[3 * j + 2];
                    }
                }
            }
        });
    }
}

/// Anderson mixing (type II) of a fixed point `x = Psi(x)` from the
/// residuals `f = Psi(x) - x`: `x+ = x + f - (dX + dF) gamma` with `gamma`
/// the least-squares fit of `f` by the residual differences `dF`, and the
/// relaxation beta: `x+ = x + beta f - (dX + beta dF) gamma`. Depth 0 is the
/// (relaxed) plain iteration `x+ = x + beta f`.
struct Anderson {
    depth: usize,
    dx: std::collections::VecDeque<Vec<f64>>,
    df: std::collections::VecDeque<Vec<f64>>,
    last: Option<(Vec<f64>, Vec<f64>)>,
}

impl Anderson {
    fn new(depth: usize) -> Self {
        Anderson {
            depth,
            dx: Default::default(),
            df: Default::default(),
            last: None,
        }
    }

    fn reset(&mut self) {
        self.dx.clear();
        self.df.clear();
        self.last = None;
    }

    fn next(&mut self, x: &[f64], f: &[f64], beta: f64) -> Vec<f64> {
        let plain: Vec<f64> = x.iter().zip(f).map(|(a, b)| a + beta * b).collect();
        if self.depth == 0 {
            return plain;
        }
        if let Some((xp, fp)) = self.last.take() {
            self.dx.push_back(x.iter().zip(&xp).map(|(a, b)| a - b).collect());
            self.df.push_back(f.iter().zip(&fp).map(|(a, b)| a - b).collect());
            if self.dx.len() > self.depth {
                self.dx.pop_front();
                self.df.pop_front();
            }
        }
        self.last = Some((x.to_vec(), f.to_vec()));
        let k = self.df.len();
        if k == 0 {
            return plain;
        }
        // Normal equations of min |f - dF gamma|, lightly regularised.
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let mut a = nalgebra::DMatrix::<f64>::zeros(k, k);
        let mut rhs = nalgebra::DVector::<f64>::zeros(k);
        for i in 0..k {
            for j in 0..=i {
                let v = dot(&self.df[i], &self.df[j]);
                a[(i, j)] = v;
                a[(j, i)] = v;
            }
            rhs[i] = dot(&self.df[i], f);
        }
        let trace: f64 = (0..k).map(|i| a[(i, i)]).sum();
        for i in 0..k {
            a[(i, i)] += 1e-12 * trace.max(f64::MIN_POSITIVE);
        }
        let Some(gamma) = a.cholesky().map(|c| c.solve(&rhs)) else {
            self.reset();
            return plain;
        };
        let mut out = plain;
        for (j, g) in gamma.iter().enumerate() {
            for ((o, dx), df) in out.iter_mut().zip(&self.dx[j]).zip(&self.df[j]) {
                *o -= g * (dx + beta * df);
            }
        }
        out
    }
}

/// Runs the iteration. `factors` must hold every harmonic of `loads`;
/// `laws[j]` is the law of `model.joints[j]`. `progress` sees each record.
pub fn stress_transfer(
    model: &Model,
    factors: &[HarmonicFactor],
    loads: &[HarmonicLoads],
    laws: &[JointLaw],
    sections: &Sections,
    settings: &IterationSettings,
    mut progress: impl FnMut(&IterationRecord),
) -> Result<Outcome, IterationError> {
    let start = Instant::now();
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
            "the loads have antisymmetric or torsional content: the sections must cover the full turn".into(),
        ));
    }
    // The paper's M + 1 sections resolve harmonics up to M - 1 exactly (the
    // Nyquist harmonic M aliases); fewer, or uneven ones that resolve less,
    // are refused.
    let m_max = loads.iter().map(|h| h.m).max().unwrap_or(0);
    let resolved = sections.resolves_up_to(m_max);
    if m_max > 0 && resolved.is_none_or(|r| r + 1 < m_max) {
        return Err(IterationError::Setup(format!(
            "the {} sections resolve harmonics only up to {}, not 0..={m_max}: give at least {} evenly spaced sections over the half turn (the paper's M + 1), or {} over the full turn",
            sections.len(),
            resolved.map_or("none".into(), |r| r.to_string()),
            m_max + 1,
            2 * m_max
        )));
    }

    // Points and joint nodes.
    let mut points = Vec::new();
    for (j, joint) in mesh.joints.iter().enumerate() {
        let rule = model.joints[j].rule;
        for (e, el) in joint.elements.iter().enumerate() {
            let coords: Vec<[f64; 2]> = el.bottom.iter().map(|&k| mesh.nodes[k]).collect();
            let nodes: Vec<usize> = el.bottom.iter().chain(&el.top).copied().collect();
            for point in joint_points(el.kind, &coords, rule) {
                points.push(PointInfo {
                    joint: j,
                    element: e,
                    point,
                    nodes: nodes.clone(),
                });
            }
        }
    }
    let mut joint_nodes: Vec<usize> = points.iter().flat_map(|p| p.nodes.iter().copied()).collect();
    joint_nodes.sort_unstable();
    joint_nodes.dedup();
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
    let setup = Setup {
        model,
        laws,
        sections,
        points,
        joint_nodes,
        local,
        phi,
        n_h,
    };
    let (n_s, n_p, n_j) = (sections.len(), setup.points.len(), setup.joint_nodes.len());

    // State per (section, point); x: the released section forces applied,
    // g: those released by the current solution.
    let mut broken = vec![false; n_s * n_p];
    let mut d = vec![[0.0; 3]; n_s * n_p];
    let mut p = vec![[0.0; 3]; n_s * n_p];
    let mut state = vec![JointState::Stick; n_s * n_p];
    let mut x = vec![0.0; n_s * 3 * n_j];
    let mut g = vec![0.0; n_s * 3 * n_j];
    let mut u_s = vec![0.0; n_s * 3 * n_j];
    let mut released: Vec<HarmonicLoads> = loads.iter().map(|h| HarmonicLoads::zeros(h.m, n)).collect();
    let mut history = Vec::new();
    let mut mixer = Anderson::new(match settings.method {
        Method::Plain => 0,
        Method::Anderson { depth } => depth,
    });
    let (mut psi0, mut psi_prev, mut best, mut best_at) = (0.0f64, f64::INFINITY, f64::INFINITY, 0u32);
    // Relaxation of the update, halved on each stall; history start of the
    // current relaxation level (for the limit estimate).
    let (mut damping, mut since) = (1.0f64, 0usize);
    let load_scale = loads
        .iter()
        .flat_map(|h| h.symmetric.iter().chain(&h.antisymmetric))
        .fold(0.0f64, |a, v| a.max(v.abs()));

    for it in 1..=settings.max_iterations {
        // (3) Analyse the applied released forces into harmonics.
        if it > 1 {
            setup.analyse(&x, &mut released);
        }
        // (1) Solve every harmonic for F + A x.
        let harmonics: Vec<HarmonicDisplacement> = loads
            .par_iter()
            .zip(&released)
            .zip(&factor_of)
            .map(|((f, gm), factor)| {
                let add =
                    |a: &[f64], b: &[f64]| -> Vec<f64> { a.iter().zip(b).map(|(x, y)| x + y).collect() };
                let sym = add(&f.symmetric, &gm.symmetric);
                let anti_needed = f.m > 0 && !sections.half;
                if anti_needed {
                    let anti = add(&f.antisymmetric, &gm.antisymmetric);
                    let mut u = model.solve(factor, &[&sym, &anti]);
                    let antisymmetric = u.pop().unwrap_or_default();
                    let symmetric = u.pop().unwrap_or_default();
                    HarmonicDisplacement {
                        m: f.m,
                        symmetric,
                        antisymmetric,
                    }
                } else {
                    let symmetric = model.solve(factor, &[&sym]).pop().unwrap_or_default();
                    HarmonicDisplacement {
                        m: f.m,
                        symmetric,
                        antisymmetric: vec![0.0; 3 * n],
                    }
                }
            })
            .collect();
        let u = Displacements { harmonics };

        // (2) Synthesize at the sections, evaluate the law, release: g = Psi(x).
        u_s.par_chunks_mut(3 * n_j)
            .enumerate()
            .for_each(|(s, out)| setup.synthesize(&u, s, out));
        g.par_chunks_mut(3 * n_j)
            .zip(broken.par_chunks_mut(n_p.max(1)))
            .zip(d.par_chunks_mut(n_p.max(1)))
            .zip(p.par_chunks_mut(n_p.max(1)))
            .zip(state.par_chunks_mut(n_p.max(1)))
            .enumerate()
            .for_each(|(s, ((((gs, bs), ds), ps), sts))| {
                setup.release(&u_s[s * 3 * n_j..(s + 1) * 3 * n_j], bs, gs, ds, ps, sts)
            });

        // (4) Residual rho = Psi(x) - x per section, and the history.
        let f: Vec<f64> = g.iter().zip(&x).map(|(a, b)| a - b).collect();
        let psi = f
            .chunks(3 * n_j.max(1))
            .map(|c| c.iter().map(|v| v * v).sum::<f64>().sqrt())
            .fold(0.0f64, f64::max);
        if it == 1 {
            psi0 = psi;
        }
        let nothing_released = psi0 <= 1e-14 * load_scale.max(f64::MIN_POSITIVE);
        let ratio = if nothing_released { 0.0 } else { psi / psi0 };
        let count = |k: JointState| state.iter().filter(|&&s| s == k).count();
        let record = IterationRecord {
            iteration: it,
            ratio,
            open: count(JointState::Open),
            slip: count(JointState::Slip),
            stick: count(JointState::Stick),
            seconds: start.elapsed().as_secs_f64(),
        };
        progress(&record);
        history.push(record);
        if !ratio.is_finite()
            || u.harmonics
                .iter()
                .any(|h| h.symmetric.iter().any(|v| !v.is_finite()))
        {
            return Err(no_equilibrium(
                &setup,
                &f,
                "the solution is not finite",
                record,
                history,
            ));
        }
        if nothing_released || (it > 1 && ratio < settings.epsilon) {
            return Ok(Outcome {
                released_spectrum: setup.spectrum(&g),
                displacements: u,
                history,
                field: JointField {
                    sections: sections.clone(),
                    points: setup.points,
                    d,
                    p,
                    state,
                },
            });
        }
        if it > 1 {
            let stalled = if ratio < best * 0.999 {
                best = ratio;
                best_at = it;
                None
            } else if it - best_at >= settings.stall_window {
                Some(format!(
                    "the residual ratio stalls at {ratio:.3e} (no decrease in {} iterations)",
                    settings.stall_window
                ))
            } else {
                residual_limit(&history[since..], settings.stall_window / 2)
                    .filter(|&limit| limit > settings.epsilon && limit > 0.75 * ratio)
                    .map(|limit| format!("the residual ratio tends to {limit:.3e} > epsilon, not to zero (it is {ratio:.3e})"))
            };
            if let Some(reason) = stalled {
                // A stall whose ratio oscillates is a cycle between joint
                // states (the law with friction is not a projection, and the
                // shear strength drops from C to 0 on opening): relax the
                // update first. A smooth approach to a positive limit is the
                // signature of a load the joints cannot carry.
                let window = &history[history.len().saturating_sub(settings.stall_window as usize)..];
                let (lo, hi) = window.iter().fold((f64::INFINITY, 0.0f64), |(l, h), r| {
                    (l.min(r.ratio), h.max(r.ratio))
                });
                let cycling = hi > 2.0 * lo;
                if cycling && damping > 0.125 {
                    damping *= 0.5;
                    mixer.reset();
                    since = history.len();
                    best = ratio;
                    best_at = it;
                } else {
                    let reason = if cycling {
                        format!("{reason}, also with the update relaxed to 1/8; the ratio oscillates: the iteration cycles between joint states (try more harmonics or sections)")
                    } else {
                        reason
                    };
                    return Err(no_equilibrium(&setup, &f, &reason, record, history));
                }
            }
            if ratio > 1e6 {
                let reason = format!("the residual grows (ratio {ratio:.3e})");
                return Err(no_equilibrium(&setup, &f, &reason, record, history));
            }
        }
        // A jump of the residual restarts the mixing from a plain step.
        if psi > 2.0 * psi_prev {
            mixer.reset();
        }
        psi_prev = psi;
        x = mixer.next(&x, &f, damping);
    }
    let last = history.last().map_or(f64::NAN, |r| r.ratio);
    Err(IterationError::NotConverged {
        iterations: settings.max_iterations,
        ratio: last,
        epsilon: settings.epsilon,
        history,
    })
}

/// The limit of the residual-ratio sequence predicted from its decrease over
/// the last two windows of `w` iterations (geometric fit): 0 for geometric
/// convergence, about half the current ratio for the slow hyperbolic
/// convergence the paper reports, and the positive limit the ratio settles
/// to when no equilibrium exists. `None` until there are 3w + 1 values or
/// while the ratio does not decrease steadily.
fn residual_limit(history: &[IterationRecord], w: u32) -> Option<f64> {
    let w = w.max(2) as usize;
    let n = history.len();
    if n < 3 * w + 1 {
        return None;
    }
    // Window minima damp the oscillations of the accelerated iteration.
    let min = |a: usize, b: usize| {
        history[a..b]
            .iter()
            .map(|r| r.ratio)
            .fold(f64::INFINITY, f64::min)
    };
    let (r0, r1, r2) = (min(n - 3 * w, n - 2 * w), min(n - 2 * w, n - w), min(n - w, n));
    let (d1, d2) = (r0 - r1, r1 - r2);
    if !(d1 > 0.0 && d2 > 0.0 && d2 < d1) {
        return None;
    }
    let q = d2 / d1;
    Some(r2 - d2 * q / (1.0 - q))
}

/// The no-equilibrium error, naming the joint with the largest residual `f`.
fn no_equilibrium(
    setup: &Setup,
    f: &[f64],
    reason: &str,
    last: IterationRecord,
    history: Vec<IterationRecord>,
) -> IterationError {
    let mesh = &setup.model.mesh;
    let n_j = setup.joint_nodes.len();
    let mut per_joint = vec![0.0f64; mesh.joints.len()];
    for (i, info) in setup.points.iter().enumerate() {
        for &j in &setup.local[i] {
            for s in 0..setup.sections.len() {
                for c in 0..3 {
                    per_joint[info.joint] += f[s * 3 * n_j + 3 * j + c].powi(2);
                }
            }
        }
    }
    let worst = per_joint
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |(j, _)| j);
    IterationError::NoEquilibrium {
        joint: mesh
            .joints
            .get(worst)
            .map_or_else(|| "?".into(), |j| j.name.clone()),
        reason: reason.to_string(),
        open: last.open,
        slip: last.slip,
        total: last.open + last.slip + last.stick,
        iteration: last.iteration,
        history,
    }
}
