//! The joint's constitutive law at one integration point and theta section
//! (the paper's Eqs. 10-11, DESIGN.md section 2).
//!
//! Trial traction `p = k d` in local axes `(tau_xi, sigma, tau_theta)`;
//! `sigma > 0` is tension. The admissible traction:
//! - open: `sigma` above the tensile strength (0 by default), or positive
//!   after the strength was once exceeded: `p = 0`;
//! - stick: `|tau| <= tau_y = max(C - sigma tan(phi), 0)`: `p` unchanged;
//! - slip: the shear is scaled back to `tau_y` (the resultant check keeps
//!   its direction; the component check clamps each component).
//!
//! The law is holonomic (total relative displacement in, traction out), as
//! the stress-transfer iteration of a single load step uses it.

use crate::elements::JointSprings;
use crate::scene::{JointLaw, ShearCheck};
use serde::{Deserialize, Serialize};

/// State of a joint point at one section.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum JointState {
    /// Bonded: the trial traction is admissible.
    Stick,
    /// Sliding at the Mohr-Coulomb strength.
    Slip,
    /// Debonded: no traction.
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

/// The admissible traction for relative displacement `d` (local axes), and
/// the state. `broken` remembers that the tensile strength was exceeded.
pub fn admissible(
    law: &JointLaw,
    k: &JointSprings,
    d: [f64; 3],
    broken: &mut bool,
) -> ([f64; 3], JointState) {
    let p = k.traction(d);
    let mc = match law {
        JointLaw::Linear => return (p, JointState::Stick),
        JointLaw::MohrCoulomb(mc) => mc,
    };
    let sigma = p[1];
    if sigma > 0.0 && (*broken || sigma > mc.tensile_strength) {
        *broken = true;
        return ([0.0; 3], JointState::Open);
    }
    let tau_y = (mc.cohesion - sigma * mc.tan_phi()).max(0.0);
    match mc.shear_check {
        ShearCheck::Resultant => {
            let tau = p[0].hypot(p[2]);
            if tau <= tau_y {
                (p, JointState::Stick)
            } else {
                let f = tau_y / tau;
                ([p[0] * f, sigma, p[2] * f], JointState::Slip)
            }
        }
        ShearCheck::Components => {
            let clamp = |t: f64| t.clamp(-tau_y, tau_y);
            let q = [clamp(p[0]), sigma, clamp(p[2])];
            let state = if q == p {
                JointState::Stick
            } else {
                JointState::Slip
            };
            (q, state)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::MohrCoulomb;

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
}
