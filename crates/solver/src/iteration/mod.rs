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
//! `Psi(x) = release(u_F + W x)`, `W = S K^-1 A` (A the analysis into
//! harmonics, K^-1 the back-substitution of every harmonic with its factor,
//! S the synthesis of the joint-node displacements at the sections,
//! `u_F = S K^-1 F`). One evaluation of `Psi` (`Setup::evaluate`, shared
//! by every method) costs one back-substitution sweep. The paper iterates
//! `x <- Psi(x)` (and then `rho_s = Psi(x)_s - x_s`), [`Method::Anderson`]
//! mixes the last iterates, [`Method::Newton`] solves `R(x) = Psi(x) - x = 0`
//! by a semi-smooth Newton-Krylov method (see the private `newton` function). Only
//! back-substitutions are ever repeated: no coupled system is factorized.

use crate::driver::{Displacements, HarmonicDisplacement};
use crate::elements::{add_traction_forces, joint_points, relative_displacement, JointPoint, JointSprings};
use crate::fourier::{Family, Sections};
use crate::joint_law::{admissible, JointState};
use crate::linear::{HarmonicFactor, Model};
use crate::loads::HarmonicLoads;
use crate::scene::{JointLaw, ShearCheck};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;
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
    /// Semi-smooth Newton-Krylov on `R(x) = Psi(x) - x = 0`: the
    /// generalized Jacobian `J = D(x) W - I` (D the joint tangent of the
    /// release at the states of x, W the elastic back-substitution chain),
    /// solved by a minimal-residual Krylov method (GCR, equivalent to GMRES)
    /// whose directions are recycled across Newton steps, and a backtracking
    /// line search on `|R|` with a fallback to the plain step. See the `newton` function in this module.
    Newton,
}

/// Convergence settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IterationSettings {
    /// Update rule.
    pub method: Method,
    /// Converged when `Psi_k / Psi_0 < epsilon`.
    pub epsilon: f64,
    /// Iteration limit: iterations of the fixed-point methods (one sweep
    /// each); for [`Method::Newton`] both its steps and its sweeps.
    pub max_iterations: u32,
    /// No equilibrium when the residual ratio makes no new minimum (by 0.1 %)
    /// within this many iterations (fixed-point methods).
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
    /// Iteration (1 = the elastic solve); a Newton step for [`Method::Newton`].
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
    /// Back-substitution sweeps (a solve of every harmonic) this record
    /// cost: 1 per iteration of the fixed-point methods, the Krylov
    /// directions plus any plain-step or verification evaluations of a
    /// Newton step. Their sum over the history is the run's cost in solves.
    #[serde(default)]
    pub solves: u32,
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
    /// The iteration stalled on a joint much stiffer than its elements:
    /// whether an equilibrium exists cannot be told.
    #[error("not converged: {reason}; joint '{joint}' is much stiffer than the elements along it (k h / E = {stiffness:.1}): every method keeps the elastic joint stiffness in K_m, so a released traction comes back through the same stiff spring and the iteration crawls. This does not show that the load exceeds what the joint can carry; soften the joint to k h / E of about 1 or less, or refine the mesh along it (iteration {iteration})")]
    StiffJoint {
        /// The joint with the largest residual.
        joint: String,
        /// `k h / E` of that joint (largest spring, mean element length,
        /// stiffer neighbouring body).
        stiffness: f64,
        /// What was detected.
        reason: String,
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
            IterationError::NoEquilibrium { history, .. }
            | IterationError::NotConverged { history, .. }
            | IterationError::StiffJoint { history, .. } => history,
            IterationError::Setup(_) => &[],
        }
    }
}

/// Joint-node values per harmonic, `[symmetric, antisymmetric]`, each
/// `3 * joint nodes` (the node order of [`Model::joint_nodes`]).
type JointAmplitudes = Vec<[Vec<f64>; 2]>;

/// The fixed data of an iteration: points, joint nodes, basis tables.
struct Setup<'a> {
    model: &'a Model,
    laws: &'a [JointLaw],
    sections: &'a Sections,
    loads: &'a [HarmonicLoads],
    factor_of: Vec<&'a HarmonicFactor>,
    points: Vec<PointInfo>,
    /// Joint nodes (global indices) and each point's nodes in that list.
    joint_nodes: Vec<usize>,
    local: Vec<Vec<usize>>,
    /// `phi[(s * n_h + h) * 2 + family] = (phi_rz, phi_theta)`.
    phi: Vec<(f64, f64)>,
    n_h: usize,
    /// The joint-node amplitudes of the elastic solution `K^-1 F`.
    u0: JointAmplitudes,
    /// Whether harmonic h has an antisymmetric family to solve.
    both: Vec<bool>,
}

/// One evaluation of `Psi`: the joint-node displacements at the sections
/// `u_s`, the released section forces `g = Psi(x)`, and the joint field
/// (index `s * n_points + p`) with the tensile-break memory after it.
#[derive(Clone)]
struct Eval {
    u_s: Vec<f64>,
    g: Vec<f64>,
    d: Vec<[f64; 3]>,
    p: Vec<[f64; 3]>,
    state: Vec<JointState>,
    broken: Vec<bool>,
}

/// The joint tangent at one (section, point): the derivative of the
/// released traction `k d - P(k d)` with respect to the trial traction
/// `k d`; `None` for a sticking point (nothing released, derivative 0).
type Tangent = Option<[[f64; 3]; 3]>;

/// The derivative of the released traction `e(t) = t - P(t)` of
/// [`admissible`] (t the trial traction `k d`) at the state it gave:
///
/// - stick: `de = 0`;
/// - open: `de = dt` (the whole trial traction is released);
/// - slip, resultant check: `P_t = tau_y n`, `n = t_s / |t_s|` (t_s the shear
///   pair `(t_xi, t_theta)`), `f = tau_y / |t_s|`,
///   `de_s = (1 - f) dt_s + n (f n.dt_s + tan(phi) dsigma)`, `de_sigma = 0`
///   (the `tan(phi)` term only while `tau_y = C - sigma tan(phi) > 0`);
/// - slip, component check: a clamped component `c` has
///   `de_c = dt_c + sign(t_c) tan(phi) dsigma`, an unclamped one `de_c = 0`.
///
/// The law is piecewise smooth; on a switching surface this is the
/// derivative of the piece `admissible` chose (an element of the
/// generalized Jacobian: semi-smooth Newton).
fn release_tangent(law: &JointLaw, trial: [f64; 3], state: JointState) -> Tangent {
    const I: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    match state {
        JointState::Stick => None,
        JointState::Open => Some(I),
        JointState::Slip => {
            let JointLaw::MohrCoulomb(mc) = law else {
                return None;
            };
            let sigma = trial[1];
            let tan_phi = mc.tan_phi();
            let strength = mc.cohesion - sigma * tan_phi;
            let tau_y = strength.max(0.0);
            let tan = if strength > 0.0 { tan_phi } else { 0.0 };
            match mc.shear_check {
                ShearCheck::Resultant => {
                    let tau = trial[0].hypot(trial[2]);
                    if tau <= 0.0 {
                        return None;
                    }
                    let (n0, n2) = (trial[0] / tau, trial[2] / tau);
                    let f = tau_y / tau;
                    Some([
                        [1.0 - f + f * n0 * n0, n0 * tan, f * n0 * n2],
                        [0.0; 3],
                        [f * n0 * n2, n2 * tan, 1.0 - f + f * n2 * n2],
                    ])
                }
                ShearCheck::Components => {
                    let row = |c: usize| {
                        let t = trial[c];
                        if t.abs() > tau_y {
                            let mut r = [0.0; 3];
                            r[c] = 1.0;
                            r[1] = t.signum() * tan;
                            r
                        } else {
                            [0.0; 3]
                        }
                    };
                    Some([row(0), [0.0; 3], row(2)])
                }
            }
        }
    }
}

impl<'a> Setup<'a> {
    /// Checks the harmonics and sections and collects the joint points.
    fn new(
        model: &'a Model,
        factors: &'a [HarmonicFactor],
        loads: &'a [HarmonicLoads],
        laws: &'a [JointLaw],
        sections: &'a Sections,
        elastic: Option<&Displacements>,
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
        let u0 = loads
            .par_iter()
            .zip(&factor_of)
            .zip(&both)
            .map(|((f, factor), &both)| {
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
            })
            .collect();
        Ok(Setup {
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
        })
    }

    /// Length of a section-force vector x: sections x joint nodes x 3.
    fn len(&self) -> usize {
        self.sections.len() * 3 * self.joint_nodes.len()
    }

    /// Values per section (`3 * joint nodes`, at least 1 for chunking).
    fn per_section(&self) -> usize {
        (3 * self.joint_nodes.len()).max(1)
    }

    /// Point-sections.
    fn n_pairs(&self) -> usize {
        self.sections.len() * self.points.len()
    }

    /// Zero joint-node loads per harmonic (the analysis buffer).
    fn zero_loads(&self) -> JointAmplitudes {
        let n = 3 * self.joint_nodes.len();
        self.loads.iter().map(|_| [vec![0.0; n], vec![0.0; n]]).collect()
    }

    /// Evaluation buffers (no point broken yet).
    fn new_eval(&self) -> Eval {
        let (nx, np) = (self.len(), self.n_pairs());
        Eval {
            u_s: vec![0.0; nx],
            g: vec![0.0; nx],
            d: vec![[0.0; 3]; np],
            p: vec![[0.0; 3]; np],
            state: vec![JointState::Stick; np],
            broken: vec![false; np],
        }
    }

    fn phi(&self, s: usize, h: usize, family: Family) -> (f64, f64) {
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

    /// Synthesizes the joint-node displacements at every section.
    fn synthesize_all(&self, u: &JointAmplitudes, u_s: &mut [f64]) {
        u_s.par_chunks_mut(self.per_section())
            .enumerate()
            .for_each(|(s, out)| self.synthesize(u, s, out));
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

    /// The release at every section from `ev.u_s`: `ev.g = release(u_s)`,
    /// the field and the break memory (updated in place).
    fn release_all(&self, ev: &mut Eval) {
        let n_p = self.points.len().max(1);
        let Eval {
            u_s,
            g,
            d,
            p,
            state,
            broken,
        } = ev;
        let u_s = &*u_s;
        let m = self.per_section();
        g.par_chunks_mut(m)
            .zip(broken.par_chunks_mut(n_p))
            .zip(d.par_chunks_mut(n_p))
            .zip(p.par_chunks_mut(n_p))
            .zip(state.par_chunks_mut(n_p))
            .enumerate()
            .for_each(|(s, ((((gs, bs), ds), ps), sts))| {
                self.release(&u_s[s * m..(s + 1) * m], bs, gs, ds, ps, sts)
            });
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
                let mut u = self.model.solve_joint(factor, &[&g[0], &g[1]]);
                if !self.both[h] {
                    u[1].fill(0.0);
                }
                if with_loads {
                    for (uk, u0) in u.iter_mut().zip(&self.u0[h]) {
                        for (a, b) in uk.iter_mut().zip(u0) {
                            *a += b;
                        }
                    }
                }
                u
            })
            .collect()
    }

    /// The displacements of every node for released section forces `x`:
    /// one full solve of `F + A x` per harmonic.
    fn full_displacements(&self, x: &[f64]) -> Displacements {
        let n = self.model.mesh.nodes.len();
        let mut released = self.zero_loads();
        self.analyse(x, &mut released);
        let harmonics = self
            .loads
            .par_iter()
            .zip(&self.factor_of)
            .zip(&released)
            .enumerate()
            .map(|(h, ((f, factor), g))| {
                let mut loads = [f.symmetric.clone(), f.antisymmetric.clone()];
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
            })
            .collect();
        Displacements { harmonics }
    }

    /// `Psi(x)` (one sweep): solve for `F + A x`, synthesize, release. The
    /// break memory `ev.broken` is carried forward. Returns the joint-node
    /// amplitudes.
    fn evaluate(&self, x: &[f64], released: &mut JointAmplitudes, ev: &mut Eval) -> JointAmplitudes {
        let u = self.solve(x, true, released);
        self.synthesize_all(&u, &mut ev.u_s);
        self.release_all(ev);
        u
    }

    /// `W v = S K^-1 A v` (one sweep): the section displacements of the
    /// joint nodes under the section forces `v` alone.
    fn apply_w(&self, v: &[f64], released: &mut JointAmplitudes, out: &mut [f64]) {
        let u = self.solve(v, false, released);
        self.synthesize_all(&u, out);
    }

    /// The joint tangent of every (section, point) at the states of `ev`.
    fn tangents(&self, ev: &Eval, out: &mut [Tangent]) {
        let n_p = self.points.len().max(1);
        out.par_chunks_mut(n_p).enumerate().for_each(|(s, ts)| {
            for (i, (t, info)) in ts.iter_mut().zip(&self.points).enumerate() {
                let k = s * self.points.len() + i;
                let springs = self.model.joints[info.joint].springs;
                *t = release_tangent(&self.laws[info.joint], springs.traction(ev.d[k]), ev.state[k]);
            }
        });
    }

    /// `out = D du_s`: the released section forces of the displacement
    /// increment `du_s` through the joint tangents (no solve).
    fn apply_tangent(&self, tangents: &[Tangent], du_s: &[f64], out: &mut [f64]) {
        let m = self.per_section();
        let n_p = self.points.len();
        out.par_chunks_mut(m).enumerate().for_each(|(s, os)| {
            os.fill(0.0);
            let du = &du_s[s * m..(s + 1) * m];
            let mut ue = [0.0; 18];
            let mut fe = [0.0; 18];
            for (i, info) in self.points.iter().enumerate() {
                let Some(t) = tangents[s * n_p + i] else {
                    continue;
                };
                let nl = &self.local[i];
                for (a, &j) in nl.iter().enumerate() {
                    ue[3 * a..3 * a + 3].copy_from_slice(&du[3 * j..3 * j + 3]);
                }
                let springs: JointSprings = self.model.joints[info.joint].springs;
                let dt = springs.traction(relative_displacement(&info.point, &ue[..3 * nl.len()]));
                let de = [0, 1, 2].map(|r| t[r][0] * dt[0] + t[r][1] * dt[1] + t[r][2] * dt[2]);
                if de != [0.0; 3] {
                    fe[..3 * nl.len()].fill(0.0);
                    add_traction_forces(&info.point, de, 1.0, &mut fe[..3 * nl.len()]);
                    for (a, &j) in nl.iter().enumerate() {
                        for c in 0..3 {
                            os[3 * j + c] += fe[3 * a + c];
                        }
                    }
                }
            }
        });
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
    fn analyse(&self, x: &[f64], released: &mut JointAmplitudes) {
        let n_j = self.joint_nodes.len();
        released.par_iter_mut().enumerate().for_each(|(h, out)| {
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
    fn section_max(&self, f: &[f64]) -> f64 {
        f.chunks(self.per_section())
            .map(|c| c.iter().map(|v| v * v).sum::<f64>().sqrt())
            .fold(0.0f64, f64::max)
    }

    /// The record of an evaluation.
    fn record(&self, iteration: u32, ratio: f64, ev: &Eval, start: Instant, solves: u32) -> IterationRecord {
        let count = |k: JointState| ev.state.iter().filter(|&&s| s == k).count();
        IterationRecord {
            iteration,
            ratio,
            open: count(JointState::Open),
            slip: count(JointState::Slip),
            stick: count(JointState::Stick),
            seconds: start.elapsed().as_secs_f64(),
            solves,
        }
    }

    /// The converged outcome at released forces `x` and their evaluation
    /// `ev` (one full solve for the displacements of every node).
    fn finish(&self, x: &[f64], ev: Eval, history: Vec<IterationRecord>) -> Outcome {
        Outcome {
            released_spectrum: self.spectrum(&ev.g),
            displacements: self.full_displacements(x),
            history,
            field: JointField {
                sections: self.sections.clone(),
                points: self.points.clone(),
                d: ev.d,
                p: ev.p,
                state: ev.state,
            },
        }
    }

    /// Largest load component (the scale of "nothing released").
    fn load_scale(&self) -> f64 {
        self.loads
            .iter()
            .flat_map(|h| h.symmetric.iter().chain(&h.antisymmetric))
            .fold(0.0f64, |a, v| a.max(v.abs()))
    }
}

/// The fixed-point map `Psi` of a model and its Jacobian, for tests and
/// diagnostics: the same evaluation the iteration uses.
pub struct FixedPoint<'a> {
    setup: Setup<'a>,
}

impl<'a> FixedPoint<'a> {
    /// The map for `loads` (every harmonic factorized in `factors`),
    /// `laws[j]` the law of `model.joints[j]`, evaluated at `sections`.
    pub fn new(
        model: &'a Model,
        factors: &'a [HarmonicFactor],
        loads: &'a [HarmonicLoads],
        laws: &'a [JointLaw],
        sections: &'a Sections,
    ) -> Result<Self, IterationError> {
        Ok(FixedPoint {
            setup: Setup::new(model, factors, loads, laws, sections, None)?,
        })
    }

    /// Length of x: sections x joint nodes x 3 (index `(s * n_j + j) * 3 + c`).
    pub fn len(&self) -> usize {
        self.setup.len()
    }

    /// True when there is no joint node.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// `Psi(x)` and the state of every (section, point) (index
    /// `s * n_points + p`), with no point broken before (one sweep).
    pub fn psi(&self, x: &[f64]) -> (Vec<f64>, Vec<JointState>) {
        let mut released = self.setup.zero_loads();
        let mut ev = self.setup.new_eval();
        self.setup.evaluate(x, &mut released, &mut ev);
        (ev.g, ev.state)
    }

    /// `J v = Psi'(x) v - v`, the generalized Jacobian of `R = Psi - x` with
    /// the joint tangent at the states of x (two sweeps: `Psi(x)`, `W v`).
    pub fn jacobian_vector(&self, x: &[f64], v: &[f64]) -> Vec<f64> {
        let s = &self.setup;
        let mut released = s.zero_loads();
        let mut ev = s.new_eval();
        s.evaluate(x, &mut released, &mut ev);
        let mut tangents = vec![None; s.n_pairs()];
        s.tangents(&ev, &mut tangents);
        let mut w = vec![0.0; s.len()];
        s.apply_w(v, &mut released, &mut w);
        let mut out = vec![0.0; s.len()];
        s.apply_tangent(&tangents, &w, &mut out);
        for (o, vi) in out.iter_mut().zip(v) {
            *o -= vi;
        }
        out
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
    progress: impl FnMut(&IterationRecord),
) -> Result<Outcome, IterationError> {
    stress_transfer_from(model, factors, loads, laws, sections, settings, None, progress)
}

/// [`stress_transfer`] given the elastic solution `K^-1 F` of (some of) the
/// harmonics of `loads`, which then cost no solve.
#[allow(clippy::too_many_arguments)]
pub fn stress_transfer_from(
    model: &Model,
    factors: &[HarmonicFactor],
    loads: &[HarmonicLoads],
    laws: &[JointLaw],
    sections: &Sections,
    settings: &IterationSettings,
    elastic: Option<&Displacements>,
    mut progress: impl FnMut(&IterationRecord),
) -> Result<Outcome, IterationError> {
    let setup = Setup::new(model, factors, loads, laws, sections, elastic)?;
    match settings.method {
        Method::Plain => fixed_point(&setup, 0, settings, &mut progress),
        Method::Anderson { depth } => fixed_point(&setup, depth, settings, &mut progress),
        Method::Newton => newton(&setup, settings, &mut progress),
    }
}

/// The fixed-point iteration `x <- Psi(x)`, Anderson-mixed over `depth`
/// iterates (0: the paper's plain iteration), relaxed on cycles.
fn fixed_point(
    setup: &Setup,
    depth: usize,
    settings: &IterationSettings,
    progress: &mut dyn FnMut(&IterationRecord),
) -> Result<Outcome, IterationError> {
    let start = Instant::now();
    // x: the released section forces applied; ev.g: those released by the
    // current solution.
    let mut ev = setup.new_eval();
    let mut x = vec![0.0; setup.len()];
    let mut released = setup.zero_loads();
    let mut history = Vec::new();
    let mut mixer = Anderson::new(depth);
    let mut last_f = Vec::new();
    let (mut psi0, mut psi_prev, mut best, mut best_at) = (0.0f64, f64::INFINITY, f64::INFINITY, 0u32);
    // Relaxation of the update, halved on each stall; history start of the
    // current relaxation level (for the limit estimate).
    let (mut damping, mut since) = (1.0f64, 0usize);
    let load_scale = setup.load_scale();

    for it in 1..=settings.max_iterations {
        // (3) analyse x, (1) solve every harmonic for F + A x, (2) synthesize
        // at the sections, evaluate the law, release: g = Psi(x).
        let u = setup.evaluate(&x, &mut released, &mut ev);

        // (4) Residual rho = Psi(x) - x per section, and the history.
        let f: Vec<f64> = ev.g.iter().zip(&x).map(|(a, b)| a - b).collect();
        let psi = setup.section_max(&f);
        if it == 1 {
            psi0 = psi;
        }
        let nothing_released = psi0 <= 1e-14 * load_scale.max(f64::MIN_POSITIVE);
        let ratio = if nothing_released { 0.0 } else { psi / psi0 };
        let record = setup.record(it, ratio, &ev, start, 1);
        progress(&record);
        history.push(record);
        if !ratio.is_finite() || u.iter().flatten().flatten().any(|v| !v.is_finite()) {
            return Err(no_equilibrium(
                setup,
                &f,
                "the solution is not finite",
                record,
                history,
            ));
        }
        if !nothing_released {
            if let Some(reason) = unresolved(setup, &x, psi0, settings.epsilon) {
                return Err(no_equilibrium(setup, &f, &reason, record, history));
            }
        }
        if nothing_released || (it > 1 && ratio < settings.epsilon) {
            return Ok(setup.finish(&x, ev, history));
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
                    return Err(no_equilibrium(setup, &f, &reason, record, history));
                }
            }
            if ratio > 1e6 {
                let reason = format!("the residual grows (ratio {ratio:.3e})");
                return Err(no_equilibrium(setup, &f, &reason, record, history));
            }
        }
        // A jump of the residual restarts the mixing from a plain step.
        if psi > 2.0 * psi_prev {
            mixer.reset();
        }
        psi_prev = psi;
        x = mixer.next(&x, &f, damping);
        last_f = f;
    }
    Err(not_converged(setup, &last_f, settings, history))
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// `y += alpha x`.
fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += alpha * xi;
    }
}

/// Pairs `(z, W z)` the Newton iteration has paid a sweep for, kept across
/// its steps (W does not depend on the joint states), and the scratch of
/// the Krylov solve. Memory: `3 (KEEP + INNER)` vectors of x's length.
struct Krylov {
    /// Directions z (oldest first) and their images `W z`.
    z: VecDeque<Vec<f64>>,
    w: VecDeque<Vec<f64>>,
    /// Orthonormal `J p` of this step and their raw coefficients
    /// (`p_j = sum_i t_j[i] z_i`).
    q: Vec<Vec<f64>>,
    t: Vec<Vec<f64>>,
    /// Buffers to reuse.
    spare: Vec<Vec<f64>>,
}

impl Krylov {
    /// Pairs kept from one Newton step to the next.
    const KEEP: usize = 30;
    /// New directions per step at most (GMRES(30)-like memory).
    const INNER: usize = 30;

    fn new() -> Self {
        Krylov {
            z: VecDeque::new(),
            w: VecDeque::new(),
            q: Vec::new(),
            t: Vec::new(),
            spare: Vec::new(),
        }
    }

    fn buffer(&mut self, n: usize) -> Vec<f64> {
        let mut v = self.spare.pop().unwrap_or_default();
        v.clear();
        v.resize(n, 0.0);
        v
    }

    /// Adds a pair paid for elsewhere (e.g. a plain step's sweep).
    fn push(&mut self, z: Vec<f64>, w: Vec<f64>) {
        self.z.push_back(z);
        self.w.push_back(w);
    }

    /// Adds raw direction `i` to the orthonormal set of this step:
    /// `q = D w_i - z_i` (no sweep) orthogonalized (modified Gram-Schmidt,
    /// twice) against the previous q; returns whether it was independent.
    fn orthogonalize(
        &mut self,
        setup: &Setup,
        tangents: &[Tangent],
        i: usize,
        r: &mut [f64],
        c: &mut [f64],
    ) -> bool {
        let n = r.len();
        let width = Self::KEEP + Self::INNER + 1;
        let mut q = self.buffer(n);
        setup.apply_tangent(tangents, &self.w[i], &mut q);
        axpy(-1.0, &self.z[i], &mut q);
        let mut t = self.buffer(width);
        t[i] = 1.0;
        let before = norm(&q);
        for _ in 0..2 {
            for (qj, tj) in self.q.iter().zip(&self.t) {
                let h = dot(qj, &q);
                axpy(-h, qj, &mut q);
                axpy(-h, tj, &mut t);
            }
        }
        let nq = norm(&q);
        if nq <= 1e-10 * before || !nq.is_finite() {
            self.spare.push(q);
            self.spare.push(t);
            return false;
        }
        for v in q.iter_mut().chain(t.iter_mut()) {
            *v /= nq;
        }
        let alpha = dot(&q, r);
        axpy(-alpha, &q, r);
        axpy(alpha, &t, c);
        self.q.push(q);
        self.t.push(t);
        true
    }

    /// Solves `J delta = -R` (`J = D W - I`, D from `tangents`) to
    /// `|R + J delta| <= eta |R|` by GCR (minimal residual; in exact
    /// arithmetic GMRES) over the kept directions (free: their `W z` is
    /// known) and at most [`Krylov::INNER`] new ones `z = r / |r|` (one
    /// sweep each, at most `budget`). Writes `delta` and `W delta`; returns
    /// the sweeps paid.
    #[allow(clippy::too_many_arguments)]
    fn solve(
        &mut self,
        setup: &Setup,
        tangents: &[Tangent],
        residual: &[f64],
        eta: f64,
        budget: u32,
        released: &mut JointAmplitudes,
        delta: &mut [f64],
        w_delta: &mut [f64],
    ) -> u32 {
        let n = residual.len();
        while self.z.len() > Self::KEEP {
            if let (Some(z), Some(w)) = (self.z.pop_front(), self.w.pop_front()) {
                self.spare.push(z);
                self.spare.push(w);
            }
        }
        let (q, t) = (std::mem::take(&mut self.q), std::mem::take(&mut self.t));
        self.spare.extend(q.into_iter().chain(t));
        let mut r = self.buffer(n);
        for (ri, v) in r.iter_mut().zip(residual) {
            *ri = -v;
        }
        let target = eta * norm(residual);
        let mut c = vec![0.0; Self::KEEP + Self::INNER + 1];
        for i in 0..self.z.len() {
            self.orthogonalize(setup, tangents, i, &mut r, &mut c);
        }
        let mut sweeps = 0;
        while norm(&r) > target && sweeps < Self::INNER.min(budget as usize) as u32 {
            let nr = norm(&r);
            let mut z = self.buffer(n);
            for (zi, ri) in z.iter_mut().zip(&r) {
                *zi = ri / nr;
            }
            let mut w = self.buffer(n);
            setup.apply_w(&z, released, &mut w);
            sweeps += 1;
            self.push(z, w);
            if !self.orthogonalize(setup, tangents, self.z.len() - 1, &mut r, &mut c) {
                break;
            }
        }
        delta.fill(0.0);
        w_delta.fill(0.0);
        for (i, (z, w)) in self.z.iter().zip(&self.w).enumerate() {
            if c[i] != 0.0 {
                axpy(c[i], z, delta);
                axpy(c[i], w, w_delta);
            }
        }
        self.spare.push(r);
        sweeps
    }
}

/// Semi-smooth Newton-Krylov on `R(x) = Psi(x) - x = 0`.
///
/// With `u_s(x) = u_F + W x` the section displacements (W = S K^-1 A, linear
/// and the same for every joint state) and the release acting point by point,
/// `Psi(x) = g(u_F + W x)` and the generalized Jacobian is
/// `J = D(x) W - I`, D the joint tangent per (section, point) at the states
/// of x ([`release_tangent`]: open releases the whole trial-traction
/// increment, stick nothing, slip the tangent of the radial return). It is
/// the coupled tangent stiffness `K - A D S` right-preconditioned by the
/// elastic block-diagonal K: `(K - A D S) K^-1 = I - A (D S K^-1)` and
/// `-J = I - (D S K^-1) A` have the same eigenvalues apart from 1s:
/// the joint tangent couples the harmonics, only the elastic factors are
/// ever used.
///
/// Each step: (1) solve `J delta = -R` by GCR to the Eisenstat-Walker
/// tolerance eta (choice 2, `eta_k = 0.9 (|R_k| / |R_{k-1}|)^2`, safeguarded,
/// in `[1e-3, 0.3]`, no tighter than the target needs); every `W z` the
/// solve pays a sweep for is kept, and the kept pairs span the next step's
/// first directions at no cost (`J z = D (W z) - z`); (2) backtrack
/// `x + lambda delta` (lambda = 1, 1/2, ..., 1/32) until `|R|_2` decreases
/// by the Armijo factor `1 - 1e-4 lambda`: since
/// `u_s(x + lambda delta) = u_s(x) + lambda W delta` with `W delta` known,
/// these trial evaluations of `Psi` cost no sweep; (3) if none decreases
/// `|R|` (a joint point switches state just ahead: the law is only
/// piecewise smooth, and discontinuous where a cohesive joint opens), take
/// the plain step `x + R` with a true evaluation (one sweep; its pair
/// `(R, W R)` is kept too). A ratio below epsilon is confirmed by a true
/// evaluation (one sweep), which also gives the displacement amplitudes.
///
/// No equilibrium: when the load exceeds what the joints carry, the points
/// along the unbalanced force all slip or open, the tangent releases the
/// whole increment along it (J is singular there), the Newton step the
/// linearization asks for does not reduce `|R|`, and the plain fallback
/// steps leave the unbalanced part of R unchanged. Reported when `|R|` has
/// made no new minimum by 1 % within [`NEWTON_STALL`] steps, when the
/// released forces outgrow what the residual can resolve ([`unresolved`]),
/// or when the residual grows past 1e6 Psi_0.
fn newton(
    setup: &Setup,
    settings: &IterationSettings,
    progress: &mut dyn FnMut(&IterationRecord),
) -> Result<Outcome, IterationError> {
    let start = Instant::now();
    let nx = setup.len();
    let mut released = setup.zero_loads();
    let mut acc = setup.new_eval();
    let mut trial = setup.new_eval();
    let mut x = vec![0.0; nx];
    let mut x_trial = vec![0.0; nx];
    let mut delta = vec![0.0; nx];
    let mut w_delta = vec![0.0; nx];
    let mut tangents: Vec<Tangent> = vec![None; setup.n_pairs()];
    let mut krylov = Krylov::new();

    // The elastic solve.
    setup.evaluate(&x, &mut released, &mut acc);
    // Whether `acc` is a true evaluation at x (not a linearized trial).
    let mut evaluated;
    let mut res: Vec<f64> = acc.g.iter().zip(&x).map(|(a, b)| a - b).collect();
    let mut res_trial = vec![0.0; nx];
    let psi0 = setup.section_max(&res);
    let nothing_released = psi0 <= 1e-14 * setup.load_scale().max(f64::MIN_POSITIVE);
    let record = setup.record(1, if nothing_released { 0.0 } else { 1.0 }, &acc, start, 1);
    progress(&record);
    let mut history = vec![record];
    if !psi0.is_finite() {
        return Err(no_equilibrium(
            setup,
            &res,
            "the solution is not finite",
            record,
            history,
        ));
    }
    if nothing_released {
        return Ok(setup.finish(&x, acc, history));
    }

    let mut total = 1u32;
    let mut r_norm = norm(&res);
    let (mut r_prev, mut eta) = (r_norm, 0.5f64);
    let (mut best, mut best_at) = (r_norm, 1u32);
    let eta_floor = 0.5 * settings.epsilon * psi0;
    // Whether each of the last steps fell back to the plain step.
    let mut fallbacks = VecDeque::new();
    for step in 2..=settings.max_iterations {
        // (1) The Newton direction.
        setup.tangents(&acc, &mut tangents);
        if step > 2 {
            let ew = 0.9 * (r_norm / r_prev).powi(2);
            let safe = 0.9 * eta * eta;
            eta = if safe > 0.1 { ew.max(safe) } else { ew };
        }
        eta = eta.clamp(NEWTON_ETA_MIN, NEWTON_ETA_MAX).max(eta_floor / r_norm);
        let budget = settings.max_iterations.saturating_sub(total + 1);
        let mut sweeps = krylov.solve(
            setup,
            &tangents,
            &res,
            eta,
            budget,
            &mut released,
            &mut delta,
            &mut w_delta,
        );

        // (2) Backtracking on |R|, the trial evaluations without a sweep.
        let mut lambda = 1.0;
        let mut accepted = false;
        for _ in 0..=NEWTON_HALVINGS {
            for i in 0..nx {
                x_trial[i] = x[i] + lambda * delta[i];
                trial.u_s[i] = acc.u_s[i] + lambda * w_delta[i];
            }
            trial.broken.copy_from_slice(&acc.broken);
            setup.release_all(&mut trial);
            for i in 0..nx {
                res_trial[i] = trial.g[i] - x_trial[i];
            }
            if norm(&res_trial) <= (1.0 - 1e-4 * lambda) * r_norm {
                accepted = true;
                break;
            }
            lambda *= 0.5;
        }
        fallbacks.push_back(!accepted);
        if fallbacks.len() > NEWTON_STALL as usize {
            fallbacks.pop_front();
        }
        if accepted {
            evaluated = false;
        } else {
            // (3) The plain step, evaluated for real; its pair is kept.
            for i in 0..nx {
                x_trial[i] = x[i] + res[i];
            }
            trial.broken.copy_from_slice(&acc.broken);
            setup.evaluate(&x_trial, &mut released, &mut trial);
            evaluated = true;
            sweeps += 1;
            let mut w = krylov.buffer(nx);
            for ((wi, a), b) in w.iter_mut().zip(&trial.u_s).zip(&acc.u_s) {
                *wi = a - b;
            }
            let mut z = krylov.buffer(nx);
            z.copy_from_slice(&res);
            krylov.push(z, w);
            for i in 0..nx {
                res_trial[i] = trial.g[i] - x_trial[i];
            }
        }
        std::mem::swap(&mut acc, &mut trial);
        std::mem::swap(&mut x, &mut x_trial);
        std::mem::swap(&mut res, &mut res_trial);
        r_prev = r_norm;
        r_norm = norm(&res);
        let mut ratio = setup.section_max(&res) / psi0;
        if ratio < settings.epsilon && !evaluated {
            // Confirm with a true evaluation.
            setup.evaluate(&x, &mut released, &mut acc);
            evaluated = true;
            sweeps += 1;
            for i in 0..nx {
                res[i] = acc.g[i] - x[i];
            }
            r_norm = norm(&res);
            ratio = setup.section_max(&res) / psi0;
        }
        total += sweeps;
        let record = setup.record(step, ratio, &acc, start, sweeps);
        progress(&record);
        history.push(record);
        if !ratio.is_finite() || !r_norm.is_finite() {
            return Err(no_equilibrium(
                setup,
                &res,
                "the solution is not finite",
                record,
                history,
            ));
        }
        if let Some(reason) = unresolved(setup, &x, psi0, settings.epsilon) {
            return Err(no_equilibrium(setup, &res, &reason, record, history));
        }
        if ratio < settings.epsilon && evaluated {
            return Ok(setup.finish(&x, acc, history));
        }

        // No equilibrium.
        let reason = if r_norm < 0.99 * best {
            best = r_norm;
            best_at = step;
            None
        } else if step - best_at >= NEWTON_STALL {
            Some(format!(
                "the Newton residual stalls at ratio {ratio:.3e} (|R| made no new minimum by 1 % in {NEWTON_STALL} steps, {} of which fell back to the plain step: the joint tangent has (almost) no stiffness left along the unbalanced force, and the step the linearization asks for does not reduce the residual)",
                fallbacks.iter().filter(|&&f| f).count()
            ))
        } else {
            None
        };
        let reason =
            reason.or_else(|| (ratio > 1e6).then(|| format!("the residual grows (ratio {ratio:.3e})")));
        if let Some(reason) = reason {
            return Err(no_equilibrium(setup, &res, &reason, record, history));
        }
        if total >= settings.max_iterations {
            break;
        }
    }
    Err(not_converged(setup, &res, settings, history))
}

/// The end at the iteration limit: `NotConverged`, or `StiffJoint` when the
/// joint with the largest residual `f` is much stiffer than its elements.
fn not_converged(
    setup: &Setup,
    f: &[f64],
    settings: &IterationSettings,
    history: Vec<IterationRecord>,
) -> IterationError {
    let last = history.last().copied();
    let ratio = last.map_or(f64::NAN, |r| r.ratio);
    let worst = worst_joint(setup, f);
    let stiffness = joint_stiffness_ratio(setup, worst);
    if stiffness > STIFF_JOINT {
        return IterationError::StiffJoint {
            joint: setup
                .model
                .mesh
                .joints
                .get(worst)
                .map_or_else(|| "?".into(), |j| j.name.clone()),
            stiffness,
            reason: format!(
                "the iteration limit ({}) was reached at residual ratio {ratio:.3e} > epsilon {:.1e}",
                settings.max_iterations, settings.epsilon
            ),
            iteration: last.map_or(0, |r| r.iteration),
            history,
        };
    }
    IterationError::NotConverged {
        iterations: history.len() as u32,
        ratio,
        epsilon: settings.epsilon,
        history,
    }
}

/// The joint that carries most of a section-force residual `f`.
fn worst_joint(setup: &Setup, f: &[f64]) -> usize {
    let n_j = setup.joint_nodes.len();
    let mut per_joint = vec![0.0f64; setup.model.mesh.joints.len()];
    for (i, info) in setup.points.iter().enumerate() {
        for &j in &setup.local[i] {
            for s in 0..setup.sections.len() {
                for c in 0..3 {
                    per_joint[info.joint] += f.get(s * 3 * n_j + 3 * j + c).map_or(0.0, |v| v * v);
                }
            }
        }
    }
    per_joint
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |(j, _)| j)
}

/// The no-equilibrium reason when the released forces x have grown so far
/// that rounding hides a residual ratio of epsilon: `Psi(x) - x` is a
/// difference of numbers of size |x|, so below `64 eps_mach max_s |x_s|` a
/// "converged" ratio (even an exact 0) is noise. An extrapolating method
/// (Anderson, Newton) chasing an equilibrium that does not exist reaches
/// this; a solution that exists has released forces of the order of the
/// joint forces.
fn unresolved(setup: &Setup, x: &[f64], psi0: f64, epsilon: f64) -> Option<String> {
    let x_max = setup.section_max(x);
    (64.0 * f64::EPSILON * x_max > epsilon * psi0).then(|| {
        format!(
            "the released forces grew to {:.1e} times the first release, where rounding hides a residual ratio of epsilon = {epsilon:.0e}: they grow without bound (the joints cannot carry the load), or epsilon is below what the arithmetic resolves",
            x_max / psi0
        )
    })
}

/// Newton steps without a 1 % decrease of `|R|` before no equilibrium is
/// reported (measured on the block torsion beyond capacity: 10 to 22 steps,
/// 15 to 25 sweeps from 1.01 to 2 T_max).
const NEWTON_STALL: u32 = 8;

/// The range of the Eisenstat-Walker forcing term (measured on Scene P:
/// an upper bound of 0.5 or 0.1 instead of 0.3 costs 0 to 3 more sweeps).
const NEWTON_ETA_MIN: f64 = 1e-3;
const NEWTON_ETA_MAX: f64 = 0.3;

/// Halvings of the Newton step before the plain step is taken instead
/// (lambda >= 1/32: a smaller one means a joint point switches state just
/// ahead, where the linearization says nothing, and accepting tiny steps
/// only creeps along the switching surface).
const NEWTON_HALVINGS: u32 = 5;

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

/// Largest `k h / E` of joint `j`: its largest spring stiffness times its
/// mean element length over the smallest Young's modulus of its bodies.
fn joint_stiffness_ratio(setup: &Setup, j: usize) -> f64 {
    let model = setup.model;
    let (Some(joint), Some(props)) = (model.mesh.joints.get(j), model.joints.get(j)) else {
        return 0.0;
    };
    let k = props
        .springs
        .k_xi
        .max(props.springs.k_eta)
        .max(props.springs.k_theta);
    let n = joint.elements.len().max(1) as f64;
    let h: f64 = joint
        .elements
        .iter()
        .map(|e| {
            let (a, b) = (model.mesh.nodes[e.bottom[0]], model.mesh.nodes[e.bottom[1]]);
            (b[0] - a[0]).hypot(b[1] - a[1])
        })
        .sum::<f64>()
        / n;
    let e = joint
        .bottom_bodies
        .iter()
        .chain(&joint.top_bodies)
        .map(|&b| model.materials[b].e)
        .fold(f64::INFINITY, f64::min);
    if e.is_finite() && e > 0.0 {
        k * h / e
    } else {
        0.0
    }
}

/// The no-equilibrium error, naming the joint with the largest residual `f`.
/// `k h / E` above which a stall is blamed on the joint's stiffness: every
/// method converged on Scene P up to 1 and stalled at 12.5 (case 3 of
/// crates/solver/tests/stability.rs).
const STIFF_JOINT: f64 = 5.0;

fn no_equilibrium(
    setup: &Setup,
    f: &[f64],
    reason: &str,
    last: IterationRecord,
    history: Vec<IterationRecord>,
) -> IterationError {
    let mesh = &setup.model.mesh;
    let worst = worst_joint(setup, f);
    let joint = mesh
        .joints
        .get(worst)
        .map_or_else(|| "?".into(), |j| j.name.clone());
    // A joint much stiffer than its bodies (k h / E >> 1) makes every
    // method crawl (docs/stability.md, case 3), which looks like no
    // equilibrium: not reported as one.
    let stiffness = joint_stiffness_ratio(setup, worst);
    if stiffness > STIFF_JOINT {
        return IterationError::StiffJoint {
            joint,
            stiffness,
            reason: reason.to_string(),
            iteration: last.iteration,
            history,
        };
    }
    IterationError::NoEquilibrium {
        joint,
        reason: reason.to_string(),
        open: last.open,
        slip: last.slip,
        total: last.open + last.slip + last.stick,
        iteration: last.iteration,
        history,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::MohrCoulomb;

    fn law(c: f64, phi: f64, check: ShearCheck) -> JointLaw {
        JointLaw::MohrCoulomb(MohrCoulomb {
            cohesion: c,
            friction_deg: phi,
            tensile_strength: 0.0,
            shear_check: check,
        })
    }

    /// The released traction `t - P(t)` with unit springs (d = t).
    fn excess(law: &JointLaw, t: [f64; 3]) -> ([f64; 3], JointState) {
        let k = JointSprings {
            k_xi: 1.0,
            k_eta: 1.0,
            k_theta: 1.0,
        };
        let (p, state) = admissible(law, &k, t, &mut false);
        ([t[0] - p[0], t[1] - p[1], t[2] - p[2]], state)
    }

    /// [`release_tangent`] against central differences of [`admissible`],
    /// away from the switching surfaces, for every state and check.
    #[test]
    fn release_tangent_is_the_derivative_of_the_law() {
        let cases = [
            (
                law(0.5, 30.0, ShearCheck::Resultant),
                [0.3, -1.0, 0.2],
                JointState::Stick,
            ),
            (
                law(0.5, 30.0, ShearCheck::Resultant),
                [0.8, 0.2, -0.3],
                JointState::Open,
            ),
            (
                law(0.5, 30.0, ShearCheck::Resultant),
                [1.2, -0.4, -0.7],
                JointState::Slip,
            ),
            (
                law(0.0, 0.0, ShearCheck::Resultant),
                [1.2, -0.4, -0.7],
                JointState::Slip,
            ),
            // C - sigma tan(phi) < 0 is impossible for sigma <= 0 with C >= 0;
            // a zero strength at sigma < 0 comes from C = 0, phi = 0 above.
            (
                law(0.5, 30.0, ShearCheck::Components),
                [1.2, -0.4, 0.1],
                JointState::Slip,
            ),
            (
                law(0.5, 30.0, ShearCheck::Components),
                [-1.2, -0.4, 0.9],
                JointState::Slip,
            ),
        ];
        for (law, t, expect) in cases {
            let (_, state) = excess(&law, t);
            assert_eq!(state, expect, "{t:?}");
            let tangent = release_tangent(&law, t, state).unwrap_or([[0.0; 3]; 3]);
            let h = 1e-6;
            for j in 0..3 {
                let (mut a, mut b) = (t, t);
                a[j] += h;
                b[j] -= h;
                let ((ea, sa), (eb, sb)) = (excess(&law, a), excess(&law, b));
                assert_eq!((sa, sb), (state, state));
                for i in 0..3 {
                    let fd = (ea[i] - eb[i]) / (2.0 * h);
                    assert!(
                        (fd - tangent[i][j]).abs() < 1e-8,
                        "{state:?} {t:?}: d e_{i} / d t_{j} = {} vs {fd}",
                        tangent[i][j]
                    );
                }
            }
        }
    }
}
