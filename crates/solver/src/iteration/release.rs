//! The release: the joint law at the sections on a sweep's displacements
//! (`impl Sweep`: one evaluation of `Psi`, the released forces and the
//! joint field, [`Sweep::evaluate`]) and the joint tangent of the release
//! ([`release_tangent`]); the reference `Psi_0` ([`reference_release`]).

use super::body::{Bodies, BodyTangent};
use super::eval::{BodySectionEval, Eval, SectionEval};
use super::setup::Setup;
use super::state::{LoadState, Release};
use super::sweep::Sweep;
use super::transfer::JointAmplitudes;
use crate::elements::JointSprings;
use crate::joint_law::{admissible_trial, history_response, JointState, PointHistory};
use crate::plasticity::{return_map, Region};
use crate::scene::{JointLaw, ShearCheck};
use rayon::prelude::*;

/// The joint tangent at one (section, point): the derivative of the
/// released traction `k d - P(k d)` with respect to the trial traction
/// `k d`; `None` for a sticking point (nothing released, derivative 0).
pub(super) type Tangent = crate::joint_law::ReleaseTangent;

/// The tangents of every (section, point) pair of the joints and of the
/// plastic bodies.
pub(super) struct Tangents {
    pub(super) joints: Vec<Tangent>,
    pub(super) bodies: Vec<BodyTangent>,
}

impl Tangents {
    /// Zero tangents for the pairs of `setup`.
    pub(super) fn new(setup: &Setup) -> Self {
        Tangents {
            joints: vec![None; setup.n_pairs()],
            bodies: vec![None; setup.sections().len() * setup.body_points()],
        }
    }
}

/// The derivative of the released traction `e(t) = t - P(t)` of
/// [`admissible`](crate::joint_law::admissible) (t the trial traction `k d`) at the state it gave:
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
pub(super) fn release_tangent(law: &JointLaw, trial: [f64; 3], state: JointState) -> Tangent {
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

/// The release tangent of `law` at trial traction `trial`: the history
/// law's (opening rate `rho`) where the pair has a history `h`, else the
/// paper's law's at the state `state` it chose.
pub(super) fn law_tangent(
    law: &JointLaw,
    h: Option<&PointHistory>,
    trial: [f64; 3],
    state: JointState,
    rho: f64,
) -> Tangent {
    match h {
        Some(h) => history_response(law, trial, h, rho).tangent,
        None => release_tangent(law, trial, state),
    }
}

/// The tangent of the release `k_a d - P(k d)` with respect to
/// `t_a = k_a d` (`k_a` the springs assembled in K_m, k the law's):
/// `I - (I - T) diag(k / k_a)`, T the law's [`release_tangent`]; T itself
/// when `k_a = k`.
fn reference_tangent(law: Tangent, k: &JointSprings, k_a: &JointSprings) -> Tangent {
    let rho = [k.k_xi / k_a.k_xi, k.k_eta / k_a.k_eta, k.k_theta / k_a.k_theta];
    if rho == [1.0; 3] || rho.iter().any(|r| !r.is_finite()) {
        return law;
    }
    let t = law.unwrap_or([[0.0; 3]; 3]);
    let mut out = [[0.0; 3]; 3];
    for (r, row) in out.iter_mut().enumerate() {
        for (q, v) in row.iter_mut().enumerate() {
            let delta = if r == q { 1.0 } else { 0.0 };
            *v = delta - (delta - t[r][q]) * rho[q];
        }
    }
    Some(out)
}

/// The reference `Psi_0` of a stepped run: the paper's Eq. 12, the
/// largest released section force of the elastic solution of the whole
/// load under the paper's law. Where a stiff joint is assembled softer,
/// its release carries the stiff spring (`k / k_ref` times the forces,
/// or nothing at all for a law that never yields), so the reference is
/// instead the largest section force the joints carry in the elastic
/// solution of the model as assembled (one sweep).
pub(super) fn reference_release(setup: &Setup) -> f64 {
    let state = LoadState {
        release: if setup.softened() {
            Release::Carried
        } else {
            Release::Excess
        },
        ..LoadState::WHOLE
    };
    let mut released = setup.transfer.zeros();
    let mut ev = setup.new_eval();
    Sweep::new(setup, state).evaluate(&vec![0.0; setup.len()], &mut released, &mut ev);
    let end = setup.section_max(&ev.g);
    if setup.base.is_none() {
        return end;
    }
    // A stage: the larger of its start and its end (one that unloads ends
    // with no load).
    let start = LoadState { lambda: 0.0, ..state };
    let mut ev = setup.new_eval();
    Sweep::new(setup, start).evaluate(&vec![0.0; setup.len()], &mut released, &mut ev);
    end.max(setup.section_max(&ev.g))
}

impl Sweep<'_, '_> {
    /// `Psi(x)` (one sweep): solve for `lambda F + A x`, synthesize,
    /// release. The break memory `ev.broken` is carried forward. Returns
    /// the joint-node amplitudes.
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

    /// The admissible traction and state of pair `k` (point `i`) at trial
    /// traction `t` of the springs `springs`: the history law where the
    /// pair has a committed history, else the paper's law with the break
    /// memory `broken`.
    pub(super) fn admissible(
        &self,
        (k, i): (usize, usize),
        t: [f64; 3],
        springs: &JointSprings,
        broken: &mut bool,
    ) -> ([f64; 3], JointState) {
        let joint = self.setup.points[i].joint;
        let law = &self.setup.laws[joint];
        match self.state.history_of(k) {
            Some(h) => {
                let r = history_response(law, t, h, self.setup.opening_rate(joint, springs));
                (r.traction, r.state)
            }
            None => admissible_trial(law, t, broken),
        }
    }

    /// Evaluates the law at every point of section `s` from its joint-node
    /// displacements `u_s`: the released joint-node forces (per radian)
    /// into `out.g`, and the field values.
    fn release(&self, s: usize, u_s: &[f64], out: SectionEval) {
        let setup = self.setup;
        let n_p = setup.points.len();
        out.g.fill(0.0);
        let mut fe = [0.0; 18];
        for (i, info) in setup.points.iter().enumerate() {
            let k = s * n_p + i;
            let joint = &setup.model.joints[info.joint];
            let d = setup.relative(i, u_s);
            let t0 = setup.t0(k);
            let h = self.state.history_of(k);
            let t = setup.trial(info.joint, d, h, t0);
            let (p, state) = self.admissible((k, i), t, &joint.springs, &mut out.broken[i]);
            // Released: what K_m's spring and the initial traction carry
            // minus what the law allows.
            let trial = joint.assembled.traction(d);
            let excess = match self.state.release {
                Release::Excess => [0, 1, 2].map(|c| trial[c] + t0[c] - p[c]),
                Release::Carried => trial,
            };
            setup.scatter(i, excess, &mut fe, out.g);
            out.d[i] = d;
            out.p[i] = p;
            out.state[i] = state;
        }
    }

    /// The release at every section from `ev.u_s`: `ev.g = release(u_s)`,
    /// the field and the break memory (updated in place).
    pub(super) fn release_all(&self, ev: &mut Eval) {
        let setup = self.setup;
        let m = setup.per_section();
        let (u_s, sections) = ev.sections_mut(m, setup.points.len().max(1), setup.min_len());
        sections.for_each(|(s, out)| self.release(s, &u_s[s * m..(s + 1) * m], out));
        if let Some(bodies) = &setup.bodies {
            let start = setup.transfer.body_start();
            let (u_s, sections) = ev.body_sections_mut(m, bodies.n_points().max(1));
            sections.with_min_len(setup.min_len()).for_each(|(s, out)| {
                self.release_bodies(bodies, s, &u_s[s * m + start..(s + 1) * m], out);
            });
        }
    }

    /// The return of every plastic body point of section `s` from the
    /// section's body values `u_b`: the released stress `D eps - sigma`
    /// as nodal forces into the body part of `out.g`, and the field.
    fn release_bodies(&self, bodies: &Bodies, s: usize, u_b: &[f64], out: BodySectionEval) {
        let start = self.setup.transfer.body_start();
        let g = &mut out.g[start..];
        g.fill(0.0);
        let n_b = bodies.n_points();
        let start = &self.setup.start;
        for cell in &bodies.cells {
            let d = cell.elastic.d_matrix();
            let eps = bodies.strains(cell, u_b);
            let mut released = vec![[0.0; 6]; eps.len()];
            let mut any = false;
            for (q, eps) in eps.iter().enumerate() {
                let k = cell.first + q;
                let committed = self.state.plastic_of(s * n_b + k);
                let r = return_map(
                    &cell.elastic,
                    &bodies.criteria[k],
                    self.trial(&d, k, eps, &committed),
                );
                if r.region != Region::Elastic {
                    // sigma_0 + D eps - sigma = D eps_p (committed and of
                    // the step).
                    let carried = self.carried(&d, k, eps);
                    released[q] = std::array::from_fn(|c| carried[c] - r.stress[c]);
                    any = true;
                } else if committed != [0.0; 6] {
                    released[q] = (d * nalgebra::Vector6::from(committed)).into();
                    any = true;
                }
                out.sigma[k] = r.stress;
                let before = start.body_plastic.get(k).copied().unwrap_or_default();
                out.plastic[k] = std::array::from_fn(|c| before[c] + committed[c] + r.plastic_strain[c]);
                out.yielding[k] = r.region != Region::Elastic;
            }
            if any {
                bodies.scatter_all(cell, &mut released, g);
            }
        }
    }

    /// The stress the elastic model carries at body point `k` with strain
    /// `eps`: `sigma_0 + D eps` (`sigma_0` the start's).
    fn carried(&self, d: &nalgebra::Matrix6<f64>, k: usize, eps: &[f64; 6]) -> [f64; 6] {
        let s0 = self.setup.start.body_stress.get(k).copied().unwrap_or_default();
        let de: [f64; 6] = (d * nalgebra::Vector6::from(*eps)).into();
        std::array::from_fn(|c| s0[c] + de[c])
    }

    /// The trial stress of body point `k`: `sigma_0 + D (eps - eps_p)`.
    fn trial(&self, d: &nalgebra::Matrix6<f64>, k: usize, eps: &[f64; 6], committed: &[f64; 6]) -> [f64; 6] {
        let elastic: [f64; 6] = std::array::from_fn(|c| eps[c] - committed[c]);
        self.carried(d, k, &elastic)
    }

    /// The tangent of every (section, point) of the joints and the plastic
    /// bodies at the states of `ev`.
    pub(super) fn tangents(&self, ev: &Eval, out: &mut Tangents) {
        self.joint_tangents(ev, &mut out.joints);
        let Some(bodies) = &self.setup.bodies else { return };
        let (m, start, n_b) = (
            self.setup.per_section(),
            self.setup.transfer.body_start(),
            bodies.n_points(),
        );
        out.bodies
            .par_chunks_mut(n_b.max(1))
            .with_min_len(self.setup.min_len())
            .enumerate()
            .for_each(|(s, ts)| {
                let u_b = &ev.u_s[s * m + start..(s + 1) * m];
                for cell in &bodies.cells {
                    let d = cell.elastic.d_matrix();
                    let strains = bodies.strains(cell, u_b);
                    for (q, eps) in strains.iter().enumerate() {
                        let k = cell.first + q;
                        if !ev.yielding[s * n_b + k] {
                            ts[k] = None;
                            continue;
                        }
                        let committed = self.state.plastic_of(s * n_b + k);
                        let trial = self.trial(&d, k, eps, &committed);
                        let r = return_map(&cell.elastic, &bodies.criteria[k], trial);
                        ts[k] = Some(std::array::from_fn(|i| {
                            std::array::from_fn(|j| d[(i, j)] - r.tangent[i][j])
                        }));
                    }
                }
            });
    }

    /// The joint tangent of every (section, point) at the states of `ev`.
    fn joint_tangents(&self, ev: &Eval, out: &mut [Tangent]) {
        let setup = self.setup;
        let n_p = setup.points.len().max(1);
        out.par_chunks_mut(n_p)
            .with_min_len(setup.min_len())
            .enumerate()
            .for_each(|(s, ts)| {
                for (i, (t, info)) in ts.iter_mut().zip(&setup.points).enumerate() {
                    let k = s * setup.points.len() + i;
                    let joint = &setup.model.joints[info.joint];
                    let springs = joint.springs;
                    let law = &setup.laws[info.joint];
                    let h = self.state.history_of(k);
                    let trial = setup.trial(info.joint, ev.d[k], h, setup.t0(k));
                    let law_tangent = law_tangent(
                        law,
                        h,
                        trial,
                        ev.state[k],
                        setup.opening_rate(info.joint, &springs),
                    );
                    *t = reference_tangent(law_tangent, &springs, &joint.assembled);
                }
            });
    }

    /// `out = D du_s`: the released section forces of the displacement
    /// increment `du_s` through the tangents of the joints and the plastic
    /// bodies (no solve).
    pub(super) fn apply_tangent(&self, tangents: &Tangents, du_s: &[f64], out: &mut [f64]) {
        self.apply_joint_tangent(&tangents.joints, du_s, out);
        let Some(bodies) = &self.setup.bodies else { return };
        let (m, start, n_b) = (
            self.setup.per_section(),
            self.setup.transfer.body_start(),
            bodies.n_points(),
        );
        out.par_chunks_mut(m)
            .zip(tangents.bodies.par_chunks(n_b.max(1)))
            .with_min_len(self.setup.min_len())
            .enumerate()
            .for_each(|(s, (os, ts))| {
                let g = &mut os[start..];
                g.fill(0.0);
                let du = &du_s[s * m + start..(s + 1) * m];
                for cell in &bodies.cells {
                    let nq = cell.values.n_points();
                    if ts[cell.first..cell.first + nq].iter().all(Option::is_none) {
                        continue;
                    }
                    let de = bodies.strains(cell, du);
                    let mut ds: Vec<[f64; 6]> = de
                        .iter()
                        .enumerate()
                        .map(|(q, de)| match &ts[cell.first + q] {
                            Some(t) => std::array::from_fn(|i| (0..6).map(|j| t[i][j] * de[j]).sum()),
                            None => [0.0; 6],
                        })
                        .collect();
                    bodies.scatter_all(cell, &mut ds, g);
                }
            });
    }

    /// The joint part of [`Sweep::apply_tangent`] (zeroes every section's
    /// values first).
    fn apply_joint_tangent(&self, tangents: &[Tangent], du_s: &[f64], out: &mut [f64]) {
        let setup = self.setup;
        let m = setup.per_section();
        let n_p = setup.points.len();
        out.par_chunks_mut(m)
            .with_min_len(setup.min_len())
            .enumerate()
            .for_each(|(s, os)| {
                os.fill(0.0);
                let du = &du_s[s * m..(s + 1) * m];
                let mut fe = [0.0; 18];
                for (i, info) in setup.points.iter().enumerate() {
                    let Some(t) = tangents[s * n_p + i] else {
                        continue;
                    };
                    let springs: JointSprings = setup.model.joints[info.joint].assembled;
                    let dt = springs.traction(setup.relative(i, du));
                    let de = [0, 1, 2].map(|r| t[r][0] * dt[0] + t[r][1] * dt[1] + t[r][2] * dt[2]);
                    setup.scatter(i, de, &mut fe, os);
                }
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::joint_law::admissible;
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
