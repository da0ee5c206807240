//! The joint's constitutive law at one integration point and theta section
//! (the paper's Eqs. 10-11; the history law: docs/loading.md).
//!
//! Trial traction `p = k d` in local axes `(tau_xi, sigma, tau_theta)`;
//! `sigma > 0` is tension. The admissible traction:
//! - open: `sigma` above the tensile strength (0 by default), or positive
//!   after the strength was once exceeded: `p = 0`;
//! - stick: `|tau| <= tau_y = max(C - sigma tan(phi), 0)`: `p` unchanged;
//! - slip: the shear is scaled back to `tau_y` (the resultant check keeps
//!   its direction; the component check clamps each component).
//!
//! Two forms:
//! - [`admissible`], the paper's holonomic law (total relative displacement
//!   in, traction out) that a one-shot stress-transfer iteration uses;
//! - [`admissible_history`], the history law of stepped loading: from the
//!   state committed at the last converged step ([`PointHistory`]: debonded
//!   or not, plastic slip `s`), the trial traction is
//!   `t = (k_xi (d_xi - s_xi), k_eta d_eta, k_theta (d_theta - s_theta))`;
//!   the normal traction is capped at the tensile strength left `T'` (T,
//!   or 0 once debonded), and an opening pair's shear strength fades with
//!   its opening, so the law a step solves is continuous in `d`
//!   ([`history_response`]; the caller debonds the points whose trial
//!   `sigma` exceeds T once the step has converged). Debonding takes the
//!   tensile strength only: a debonded point that closes has `C` and
//!   `phi`, as in the paper. [`commit`] stores the plastic slip of a
//!   converged step: `s = d_s - p_s / k_s` (the elastic part of the slip
//!   is `p / k`).

use crate::elements::JointSprings;
use crate::scene::{JointLaw, MohrCoulomb, ShearCheck};
use serde::{Deserialize, Serialize};

/// State of a joint point at one section.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum JointState {
    /// Bonded: the trial traction is admissible.
    Stick,
    /// Sliding at the Mohr-Coulomb strength.
    Slip,
    /// Opening: the trial normal stress above the tensile strength left
    /// (no traction under the paper's law; under the history law the
    /// normal traction capped there and a fading shear strength).
    Open,
}

impl JointState {
    /// Short name.
    pub fn name(self) -> &'static str {
        match self {
            JointState::Stick => "stick",
            JointState::Slip => "slip",
            JointState::Open => "open",
        }
    }
}

/// The (open, slip, stick) counts of `states`.
pub fn state_counts(states: &[JointState]) -> (usize, usize, usize) {
    states.iter().fold((0, 0, 0), |(o, sl, st), s| match s {
        JointState::Open => (o + 1, sl, st),
        JointState::Slip => (o, sl + 1, st),
        JointState::Stick => (o, sl, st + 1),
    })
}

/// The admissible traction for relative displacement `d` (local axes), and
/// the state. `broken` remembers that the tensile strength was exceeded.
pub fn admissible(
    law: &JointLaw,
    k: &JointSprings,
    d: [f64; 3],
    broken: &mut bool,
) -> ([f64; 3], JointState) {
    admissible_trial(law, k.traction(d), broken)
}

/// [`admissible`] at the trial traction `p` (e.g. `t_0 + k d` from an
/// initial traction `t_0`).
pub fn admissible_trial(law: &JointLaw, p: [f64; 3], broken: &mut bool) -> ([f64; 3], JointState) {
    let mc = match law {
        JointLaw::Linear => return (p, JointState::Stick),
        JointLaw::MohrCoulomb(mc) => mc,
    };
    let sigma = p[1];
    if sigma > 0.0 && (*broken || sigma > mc.tensile_strength) {
        *broken = true;
        return ([0.0; 3], JointState::Open);
    }
    shear_return(mc, p)
}

/// The shear return at trial traction `t` (normal part kept):
/// `tau_y = max(C - sigma tan(phi), 0)`.
fn shear_return(mc: &MohrCoulomb, t: [f64; 3]) -> ([f64; 3], JointState) {
    let sigma = t[1];
    let tau_y = (mc.cohesion - sigma * mc.tan_phi()).max(0.0);
    match mc.shear_check {
        ShearCheck::Resultant => {
            let tau = t[0].hypot(t[2]);
            if tau <= tau_y {
                (t, JointState::Stick)
            } else {
                let f = tau_y / tau;
                ([t[0] * f, sigma, t[2] * f], JointState::Slip)
            }
        }
        ShearCheck::Components => {
            let clamp = |v: f64| v.clamp(-tau_y, tau_y);
            let q = [clamp(t[0]), sigma, clamp(t[2])];
            let state = if q == t {
                JointState::Stick
            } else {
                JointState::Slip
            };
            (q, state)
        }
    }
}

/// The state a (point, section) pair carries from one converged load step
/// to the next under the history law.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PointHistory {
    /// The normal stress once exceeded the tensile strength: no tensile
    /// strength since (the cohesion stays).
    pub debonded: bool,
    /// Plastic slip `(s_xi, s_theta)` (length).
    pub slip: [f64; 2],
}

/// The trial traction relative to the plastic slip of `h`:
/// `(k_xi (d_xi - s_xi), k_eta d_eta, k_theta (d_theta - s_theta))` (add
/// the initial traction, if any).
pub fn relative_trial(k: &JointSprings, d: [f64; 3], h: &PointHistory) -> [f64; 3] {
    k.traction([d[0] - h.slip[0], d[1], d[2] - h.slip[1]])
}

/// The history law within a load step: the admissible traction for
/// relative displacement `d` from the committed state `h`, and the state.
/// An intact point is never opened here (tension is elastic within the
/// step; see [`exceeds_tensile_strength`]).
pub fn admissible_history(
    law: &JointLaw,
    k: &JointSprings,
    d: [f64; 3],
    h: &PointHistory,
) -> ([f64; 3], JointState) {
    admissible_history_trial(law, relative_trial(k, d, h), h)
}

/// [`admissible_history`] at the trial traction `t` (the
/// [`relative_trial`] plus any initial traction), an opening measured with
/// the normal spring of `t` ([`history_response`] with `rho = 1`).
pub fn admissible_history_trial(law: &JointLaw, t: [f64; 3], h: &PointHistory) -> ([f64; 3], JointState) {
    let r = history_response(law, t, h, 1.0);
    (r.traction, r.state)
}

/// The derivative `d(t - p) / dt` of the traction a law releases at a
/// trial traction `t` (`None`: nothing released nearby, the derivative 0).
pub type ReleaseTangent = Option<[[f64; 3]; 3]>;

/// The history law at one pair: traction, state and release tangent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Response {
    /// The admissible traction `p`.
    pub traction: [f64; 3],
    /// Open (trial tension above the strength left), slip or stick.
    pub state: JointState,
    /// `d(t - p) / dt` at `t`.
    pub tangent: ReleaseTangent,
}

/// The history law at trial traction `t` from the committed state `h`:
/// tension up to `T'` (`T` intact, 0 debonded; the normal traction is
/// capped there), shear up to `tau_y`, with the shear strength a
/// continuous function of the trial normal stress `sigma_t`:
///
/// ```text
/// sigma_t <= T':  tau_y = max(C - sigma_t tan(phi), 0)                     (Mohr-Coulomb)
/// sigma_t >  T':  tau_y = max(C - T' tan(phi) - rho (sigma_t - T'), 0)     (opening)
/// ```
///
/// An opening pair loses its shear strength with its opening `g`, at the
/// rate `rho k_eta g` of a spring `rho k_eta` (the joint's
/// [`crate::assembly::JointModel::opening`] spring over the normal spring of
/// `t`), and carries nothing once that has taken its strength (the paper's
/// open joint). Debonding takes the tensile strength, not the cohesion:
/// the paper's law, where a joint that closes again has `C` and `phi`.
pub fn history_response(law: &JointLaw, t: [f64; 3], h: &PointHistory, rho: f64) -> Response {
    let mc = match law {
        JointLaw::Linear => {
            return Response {
                traction: t,
                state: JointState::Stick,
                tangent: None,
            }
        }
        JointLaw::MohrCoulomb(mc) => mc,
    };
    let tan_phi = mc.tan_phi();
    let t_left = if h.debonded { 0.0 } else { mc.tensile_strength };
    let sigma_t = t[1];
    let opening = sigma_t > t_left;
    let (strength, slope) = if opening {
        (
            (mc.cohesion - t_left * tan_phi).max(0.0) - rho * (sigma_t - t_left),
            rho,
        )
    } else {
        (mc.cohesion - sigma_t * tan_phi, tan_phi)
    };
    let (tau_y, slope) = if strength > 0.0 {
        (strength, slope)
    } else {
        (0.0, 0.0)
    };
    let sigma = if opening { t_left } else { sigma_t };
    let mut tangent = [[0.0; 3]; 3];
    if opening {
        tangent[1][1] = 1.0;
    }
    let mut slipping = false;
    let traction = match mc.shear_check {
        ShearCheck::Resultant => {
            let tau = t[0].hypot(t[2]);
            if tau <= tau_y {
                [t[0], sigma, t[2]]
            } else {
                slipping = true;
                let f = tau_y / tau;
                let (n0, n2) = (t[0] / tau, t[2] / tau);
                tangent[0] = [1.0 - f + f * n0 * n0, n0 * slope, f * n0 * n2];
                tangent[2] = [f * n0 * n2, n2 * slope, 1.0 - f + f * n2 * n2];
                [t[0] * f, sigma, t[2] * f]
            }
        }
        ShearCheck::Components => {
            let mut q = [t[0], sigma, t[2]];
            for c in [0, 2] {
                if t[c].abs() > tau_y {
                    slipping = true;
                    q[c] = t[c].signum() * tau_y;
                    tangent[c][c] = 1.0;
                    tangent[c][1] = t[c].signum() * slope;
                }
            }
            q
        }
    };
    let state = if opening {
        JointState::Open
    } else if slipping {
        JointState::Slip
    } else {
        JointState::Stick
    };
    Response {
        traction,
        state,
        tangent: (opening || slipping).then_some(tangent),
    }
}

/// Whether an intact pair at the trial normal stress `sigma` (`t_0 + k_eta
/// d_eta`) lies above its tensile strength (it debonds at the end of the
/// step).
pub fn exceeds_tensile_strength(law: &JointLaw, sigma: f64, h: &PointHistory) -> bool {
    match law {
        JointLaw::MohrCoulomb(mc) => !h.debonded && sigma > mc.tensile_strength,
        JointLaw::Linear => false,
    }
}

/// Commits a converged step from the initial traction `t0`: the plastic
/// slip `s = d_s - (p_s - t0_s) / k_s` of a slipping or opening pair (an
/// open one carries no shear: `s = d_s + t0_s / k_s`); a sticking pair
/// keeps its slip. A zero spring keeps its slip (its traction never
/// changes).
pub fn commit(
    k: &JointSprings,
    d: [f64; 3],
    t0: [f64; 3],
    p: [f64; 3],
    state: JointState,
    h: &mut PointHistory,
) {
    let slip = |d: f64, t0: f64, p: f64, k: f64, old: f64| if k > 0.0 { d - (p - t0) / k } else { old };
    if state != JointState::Stick {
        h.slip = [
            slip(d[0], t0[0], p[0], k.k_xi, h.slip[0]),
            slip(d[2], t0[2], p[2], k.k_theta, h.slip[1]),
        ];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law(c: f64, phi: f64, t0: f64, check: ShearCheck) -> JointLaw {
        JointLaw::MohrCoulomb(MohrCoulomb {
            cohesion: c,
            friction_deg: phi,
            tensile_strength: t0,
            shear_check: check,
        })
    }
    const K: JointSprings = JointSprings {
        k_xi: 10.0,
        k_eta: 20.0,
        k_theta: 5.0,
    };

    #[test]
    fn open_in_tension_transmits_nothing() {
        let mut b = false;
        let (p, s) = admissible(
            &law(0.5, 30.0, 0.0, ShearCheck::Resultant),
            &K,
            [0.01, 1e-9, 0.02],
            &mut b,
        );
        assert_eq!((p, s), ([0.0; 3], JointState::Open));
        assert!(b);
    }

    #[test]
    fn tensile_strength_then_no_tension() {
        let l = law(0.5, 30.0, 0.1, ShearCheck::Resultant);
        let mut b = false;
        // sigma = 20 * 0.004 = 0.08 < 0.1: intact, tau_y = 0.5 - 0.08 tan 30.
        let (p, s) = admissible(&l, &K, [0.0, 0.004, 0.0], &mut b);
        assert_eq!((p[1], s, b), (0.08, JointState::Stick, false));
        // sigma = 0.2 > 0.1 breaks it; afterwards any tension opens.
        assert_eq!(admissible(&l, &K, [0.0, 0.01, 0.0], &mut b).1, JointState::Open);
        assert_eq!(admissible(&l, &K, [0.0, 0.001, 0.0], &mut b).1, JointState::Open);
        // Compression closes it again.
        assert_eq!(
            admissible(&l, &K, [0.0, -0.001, 0.0], &mut b).1,
            JointState::Stick
        );
    }

    #[test]
    fn mohr_coulomb_resultant_slip_keeps_direction() {
        // sigma = -20 * 0.05 = -1, tau_y = 0.5 + tan(30 deg) = 1.0773503.
        let tau_y = 0.5 + 30f64.to_radians().tan();
        let mut b = false;
        let (p, s) = admissible(
            &law(0.5, 30.0, 0.0, ShearCheck::Resultant),
            &K,
            [0.3, -0.05, 0.4],
            &mut b,
        );
        assert_eq!(s, JointState::Slip);
        assert!((p[0].hypot(p[2]) - tau_y).abs() < 1e-14);
        assert!(
            (p[0] / p[2] - 3.0 / 2.0).abs() < 1e-14,
            "direction of (10 * 0.3, 5 * 0.4)"
        );
        assert_eq!(p[1], -1.0);
        // Below the strength: stick, unchanged.
        let (q, s) = admissible(
            &law(0.5, 30.0, 0.0, ShearCheck::Resultant),
            &K,
            [0.05, -0.05, 0.05],
            &mut b,
        );
        assert_eq!((q, s), ([0.5, -1.0, 0.25], JointState::Stick));
    }

    #[test]
    fn component_check_clamps_each() {
        let mut b = false;
        // tau_y = 0.5 (phi = 0); trial (3, -1, 0.25): xi clamps, theta sticks.
        let (p, s) = admissible(
            &law(0.5, 0.0, 0.0, ShearCheck::Components),
            &K,
            [0.3, -0.05, 0.05],
            &mut b,
        );
        assert_eq!((p, s), ([0.5, -1.0, 0.25], JointState::Slip));
        // The resultant check is stricter: |(0.5, 0.25)| > 0.5 would slip.
        let (_, s) = admissible(
            &law(0.5, 0.0, 0.0, ShearCheck::Resultant),
            &K,
            [0.05, -0.05, 0.05],
            &mut b,
        );
        assert_eq!(s, JointState::Slip);
    }

    #[test]
    fn linear_law_never_changes() {
        let mut b = false;
        let (p, s) = admissible(&JointLaw::Linear, &K, [1.0, 2.0, 3.0], &mut b);
        assert_eq!((p, s), ([10.0, 40.0, 15.0], JointState::Stick));
    }

    #[test]
    fn history_law_caps_tension_at_the_strength_until_committed() {
        // Intact, sigma_t = 0.2 > T = 0.1: opening, the normal traction
        // capped at T, the shear strength C - T tan 30 - (0.2 - 0.1) = 0.34226
        // carries tau = 0.1.
        let l = law(0.5, 30.0, 0.1, ShearCheck::Resultant);
        let h = PointHistory::default();
        let (p, s) = admissible_history(&l, &K, [0.01, 0.01, 0.0], &h);
        assert_eq!(s, JointState::Open);
        assert!(
            (p[0] - 0.1).abs() < 1e-15 && (p[1] - 0.1).abs() < 1e-15 && p[2] == 0.0,
            "{p:?}"
        );
        // tau = 0.5 > 0.34226: the shear slips at the opening strength.
        let (p, _) = admissible_history(&l, &K, [0.05, 0.01, 0.0], &h);
        let strength = 0.5 - 0.1 * 30f64.to_radians().tan() - 0.1;
        assert!((p[0] - strength).abs() < 1e-14, "{p:?}");
        assert!(exceeds_tensile_strength(&l, K.k_eta * 0.01, &h));
        assert!(!exceeds_tensile_strength(&l, K.k_eta * 0.004, &h));
    }

    #[test]
    fn debonded_point_keeps_its_cohesion_and_opens_in_tension() {
        let l = law(0.5, 30.0, 0.1, ShearCheck::Resultant);
        let h = PointHistory {
            debonded: true,
            slip: [0.0; 2],
        };
        // A small opening (sigma_t = 2e-5) keeps the shear strength
        // 0.5 - 2e-5 and no normal traction: tau = 0.1 is carried.
        let (p, s) = admissible_history(&l, &K, [0.01, 1e-6, 0.0], &h);
        assert_eq!((p, s), ([0.1, 0.0, 0.0], JointState::Open));
        // An opening of sigma_t >= C carries nothing (the paper's open joint).
        assert_eq!(
            admissible_history(&l, &K, [0.01, 0.03, 0.0], &h),
            ([0.0; 3], JointState::Open)
        );
        // Closed at sigma = -1: tau_y = C + tan 30, the paper's law.
        let tau_y = 0.5 + 30f64.to_radians().tan();
        let (p, s) = admissible_history(&l, &K, [0.05, -0.05, 0.0], &h);
        assert_eq!((p[0], s), (0.5, JointState::Stick));
        let (p, s) = admissible_history(&l, &K, [0.3, -0.05, 0.0], &h);
        assert_eq!(s, JointState::Slip);
        assert!((p[0] - tau_y).abs() < 1e-14);
        assert!(!exceeds_tensile_strength(&l, K.k_eta, &h));
    }

    /// The history law is continuous in the trial traction where the paper's
    /// is not (closing and opening, the end of the opening branch, the
    /// tensile strength), and its tangent is the derivative of the release
    /// away from the switching surfaces, on every branch and check.
    #[test]
    fn history_law_is_continuous_and_its_tangent_is_its_derivative() {
        for check in [ShearCheck::Resultant, ShearCheck::Components] {
            for (t_strength, debonded) in [(0.0, false), (0.1, false), (0.1, true)] {
                let l = law(0.5, 30.0, t_strength, check);
                let h = PointHistory {
                    debonded,
                    slip: [0.0; 2],
                };
                let t_left = if debonded { 0.0 } else { t_strength };
                let rho = 0.7;
                let at = |t: [f64; 3]| history_response(&l, t, &h, rho);
                // Continuity across sigma_t = T' and the end of the opening branch.
                let end = t_left + (0.5 - t_left * 30f64.to_radians().tan()) / rho;
                for sigma in [t_left, end] {
                    for shear in [[0.05, 0.02], [0.4, -0.3], [2.0, 1.0]] {
                        let below = at([shear[0], sigma - 1e-9, shear[1]]).traction;
                        let above = at([shear[0], sigma + 1e-9, shear[1]]).traction;
                        for c in 0..3 {
                            assert!(
                                (below[c] - above[c]).abs() < 1e-8,
                                "{check:?} {sigma} {shear:?}: {below:?} {above:?}"
                            );
                        }
                    }
                }
                // The tangent against central differences.
                let samples = [
                    [0.05, -0.3, 0.02],
                    [0.9, -0.3, -0.6],
                    [0.05, t_left + 0.1, 0.02],
                    [0.4, t_left + 0.1, -0.3],
                    [0.4, end + 0.1, -0.3],
                ];
                for t in samples {
                    let r = at(t);
                    let tangent = r.tangent.unwrap_or([[0.0; 3]; 3]);
                    let e = 1e-7;
                    for j in 0..3 {
                        let (mut a, mut b) = (t, t);
                        a[j] += e;
                        b[j] -= e;
                        let (ra, rb) = (at(a), at(b));
                        assert_eq!((ra.state, rb.state), (r.state, r.state), "{t:?}");
                        for i in 0..3 {
                            let release = |r: &Response, t: [f64; 3]| t[i] - r.traction[i];
                            let fd = (release(&ra, a) - release(&rb, b)) / (2.0 * e);
                            assert!(
                                (fd - tangent[i][j]).abs() < 1e-6,
                                "{check:?} T' {t_left} {t:?}: d e_{i} / d t_{j} = {} vs {fd}",
                                tangent[i][j]
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn plastic_slip_is_kept_and_unloads_elastically() {
        // phi = 0, C = 0.5: slip at d_xi = 0.3 leaves s = 0.3 - 0.5 / 10 = 0.25.
        let l = law(0.5, 0.0, 0.0, ShearCheck::Resultant);
        let mut h = PointHistory::default();
        let d = [0.3, -0.01, 0.0];
        let (p, s) = admissible_history(&l, &K, d, &h);
        assert_eq!((p[0], s), (0.5, JointState::Slip));
        commit(&K, d, [0.0; 3], p, s, &mut h);
        assert!((h.slip[0] - 0.25).abs() < 1e-15);
        // Unloading to d_xi = 0.2 sticks at tau = 10 (0.2 - 0.25) = -0.5 ...
        let (p, s) = admissible_history(&l, &K, [0.2, -0.01, 0.0], &h);
        assert_eq!(s, JointState::Stick);
        assert!((p[0] + 0.5).abs() < 1e-14);
        // ... and reversing further slips the other way.
        let (p, s) = admissible_history(&l, &K, [0.1, -0.01, 0.0], &h);
        assert_eq!((p[0], s), (-0.5, JointState::Slip));
        // An open pair carries no shear: its slip follows d.
        commit(&K, [0.7, 0.1, 0.2], [0.0; 3], [0.0; 3], JointState::Open, &mut h);
        assert_eq!(h.slip, [0.7, 0.2]);
    }

    #[test]
    fn initial_compression_gives_friction_and_slip_is_measured_from_it() {
        // t0 = (0, -1, 0), C = 0, phi = 30: tau_y = tan 30 = 0.577 from the
        // start; k_xi = 10 sticks up to d_xi = 0.0577.
        let l = law(0.0, 30.0, 0.0, ShearCheck::Resultant);
        let t0 = [0.0, -1.0, 0.0];
        let mut h = PointHistory::default();
        let tau_y = 30f64.to_radians().tan();
        let trial = |d: [f64; 3], h: &PointHistory| {
            let t = relative_trial(&K, d, h);
            [t[0] + t0[0], t[1] + t0[1], t[2] + t0[2]]
        };
        let (p, s) = admissible_history_trial(&l, trial([0.05, 0.0, 0.0], &h), &h);
        assert_eq!((p, s), ([0.5, -1.0, 0.0], JointState::Stick));
        let d = [0.1, 0.0, 0.0];
        let (p, s) = admissible_history_trial(&l, trial(d, &h), &h);
        assert_eq!(s, JointState::Slip);
        assert!((p[0] - tau_y).abs() < 1e-14);
        commit(&K, d, t0, p, s, &mut h);
        // The traction after commit at the same d is the admissible one.
        let t = trial(d, &h);
        assert!((t[0] - tau_y).abs() < 1e-14 && t[1] == -1.0, "{t:?}");
        // Opening (sigma = -1 + 20 d_eta > 0) releases everything; its slip
        // leaves no shear when it closes at the same d.
        let d = [0.2, 0.06, 0.0];
        // Intact (T = 0): an opening of sigma_t = 0.2 >= C = 0 carries nothing.
        let (p, s) = admissible_history_trial(&l, trial(d, &h), &h);
        assert_eq!((p, s), ([0.0; 3], JointState::Open));
        assert!(exceeds_tensile_strength(&l, trial(d, &h)[1], &h));
        h.debonded = true;
        let (p2, s2) = admissible_history_trial(&l, trial(d, &h), &h);
        assert_eq!((p2, s2), ([0.0; 3], JointState::Open));
        commit(&K, d, t0, p2, s2, &mut h);
        assert_eq!(trial(d, &h)[0], 0.0);
    }

    #[test]
    fn history_law_from_a_virgin_state_is_the_paper_law_in_compression() {
        // Without history and in compression both laws give the same traction.
        let h = PointHistory::default();
        for check in [ShearCheck::Resultant, ShearCheck::Components] {
            let l = law(0.5, 30.0, 0.0, check);
            for d in [[0.3, -0.05, 0.4], [0.01, -0.02, -0.03], [-0.2, -0.001, 0.05]] {
                let mut b = false;
                assert_eq!(admissible_history(&l, &K, d, &h), admissible(&l, &K, d, &mut b));
            }
        }
    }
}
