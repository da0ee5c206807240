//! The ground of a scene: the yield criterion of a plastic material, the
//! stress a material starts from, and the ground water.

use serde::{Deserialize, Serialize};

/// The yield criterion of a perfectly plastic material
/// ([`crate::plasticity`]), the undrained strength varying with depth:
/// `c_u(z) = c_u + gradient (z_ref - z)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Plasticity {
    /// Tresca, `(s1 - s3) / 2 <= c_u(z)` (undrained, total stress).
    Tresca {
        /// Undrained strength at `z_ref` (stress).
        c_u: f64,
        /// Its growth with depth below `z_ref` (stress / length).
        #[serde(default, skip_serializing_if = "is_zero")]
        gradient: f64,
        /// The reference level (length).
        #[serde(default, skip_serializing_if = "is_zero")]
        z_ref: f64,
    },
    /// von Mises, `sqrt(J2) <= c_u(z)` (Tresca's c_u in pure shear).
    VonMises {
        /// Undrained strength at `z_ref` (stress).
        c_u: f64,
        /// Its growth with depth below `z_ref` (stress / length).
        #[serde(default, skip_serializing_if = "is_zero")]
        gradient: f64,
        /// The reference level (length).
        #[serde(default, skip_serializing_if = "is_zero")]
        z_ref: f64,
    },
    /// Mohr-Coulomb with a dilation angle and a tension cut-off.
    MohrCoulomb {
        /// Cohesion c (stress).
        cohesion: f64,
        /// Friction angle (degrees).
        friction_deg: f64,
        /// Dilation angle psi (degrees, 0 <= psi <= phi; default 0).
        #[serde(default, skip_serializing_if = "is_zero")]
        dilation_deg: f64,
        /// Largest principal stress allowed (stress, >= 0); none: the apex.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        tension_cutoff: Option<f64>,
    },
}

impl Plasticity {
    /// The criterion at height `z`.
    pub fn at(&self, z: f64) -> crate::plasticity::YieldCriterion {
        use crate::plasticity::YieldCriterion as Y;
        match *self {
            Plasticity::Tresca { c_u, gradient, z_ref } => Y::Tresca {
                c_u: c_u + gradient * (z_ref - z),
            },
            Plasticity::VonMises { c_u, gradient, z_ref } => Y::VonMises {
                c_u: c_u + gradient * (z_ref - z),
            },
            Plasticity::MohrCoulomb {
                cohesion,
                friction_deg,
                dilation_deg,
                tension_cutoff,
            } => Y::MohrCoulomb {
                cohesion,
                friction_deg,
                dilation_deg,
                tension_cutoff: tension_cutoff.unwrap_or(f64::INFINITY),
            },
        }
    }

    /// The key of the parameter a criterion error is about.
    pub fn key_of(e: &crate::plasticity::PlasticityError) -> &'static str {
        use crate::plasticity::PlasticityError as E;
        match e {
            E::UndrainedStrength { .. } => "c_u",
            E::Cohesion { .. } | E::NoStrength => "cohesion",
            E::Friction { .. } => "friction_deg",
            E::Dilation { .. } => "dilation_deg",
            E::TensionCutoff { .. } => "tension_cutoff",
        }
    }

    /// The strength parameters that must be finite, with their keys.
    pub fn numbers(&self) -> Vec<(&'static str, f64)> {
        match *self {
            Plasticity::Tresca { c_u, gradient, z_ref } | Plasticity::VonMises { c_u, gradient, z_ref } => {
                vec![("c_u", c_u), ("gradient", gradient), ("z_ref", z_ref)]
            }
            Plasticity::MohrCoulomb {
                cohesion,
                friction_deg,
                dilation_deg,
                tension_cutoff,
            } => vec![
                ("cohesion", cohesion),
                ("friction_deg", friction_deg),
                ("dilation_deg", dilation_deg),
                ("tension_cutoff", tension_cutoff.unwrap_or(0.0)),
            ],
        }
    }
}

/// Ground water at rest, for a drained analysis: the pore pressure is
/// hydrostatic, `p = gamma_w (surface_z - z)` below `surface_z` and 0
/// above, and does not change with the loads. The bodies' model stress is
/// the effective stress `sigma' = sigma + p I` (tension positive), in
/// balance with the buoyant weight `gamma - gamma_w` below the surface;
/// yield criteria and the joints' law act on it; outputs give the total
/// stress `sigma' - p I` with `p` beside it (docs/theory.md, "Water").
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Water {
    /// The water table (phreatic surface) z_w (length).
    pub surface_z: f64,
    /// Unit weight of water gamma_w > 0 (force / length^3).
    pub unit_weight: f64,
}

impl Water {
    /// The pore pressure at height z (compression positive, >= 0).
    pub fn pressure(&self, z: f64) -> f64 {
        self.unit_weight * (self.surface_z - z).max(0.0)
    }

    /// The body force in z of a material of unit weight `gamma` at height
    /// z: `-gamma` above the water table, the buoyant `gamma_w - gamma`
    /// below (a weightless material, `gamma = 0`, has no buoyancy either).
    pub fn body_force_z(water: Option<&Water>, gamma: f64, z: f64) -> f64 {
        match water {
            Some(w) if gamma != 0.0 && z < w.surface_z => w.unit_weight - gamma,
            _ => -gamma,
        }
    }
}

/// The stress a material starts from, axisymmetric (harmonic 0), tension
/// positive, in the components `(sigma_r, sigma_z, sigma_theta, tau_rz)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum InitialStress {
    /// At-rest soil: below the surface `sigma_z = -q - gamma (z_s - z)`
    /// (gamma the material's `unit_weight`, q the `surcharge`: the vertical
    /// stress at `z = z_s`, e.g. the weight of layers above), above it
    /// `sigma_z = -q`; `sigma_r = sigma_theta = K0 sigma_z`, `tau_rz = 0`.
    /// With [`Water`] the stress is effective: below the water table the
    /// weight is the buoyant `gamma - gamma_w`.
    Geostatic {
        /// Ground surface z_s (length).
        surface_z: f64,
        /// Earth pressure coefficient at rest K0 >= 0.
        #[serde(rename = "K0")]
        k0: f64,
        /// Vertical pressure q >= 0 at the surface (stress), default 0.
        #[serde(default, skip_serializing_if = "is_zero")]
        surcharge: f64,
    },
    /// The same stress everywhere in the material.
    Constant {
        /// sigma_r.
        sigma_r: f64,
        /// sigma_z.
        sigma_z: f64,
        /// sigma_theta.
        sigma_theta: f64,
        /// tau_rz, default 0.
        #[serde(default, skip_serializing_if = "is_zero")]
        tau_rz: f64,
    },
    /// No initial stress: the initial phase carries the material's weight
    /// (gravity loading).
    Gravity,
}

impl InitialStress {
    /// `(sigma_r, sigma_z, sigma_theta, tau_rz, tau_rtheta, tau_ztheta)` at
    /// height z, for a material of unit weight `gamma` (effective with
    /// `water`).
    pub fn at(&self, z: f64, gamma: f64, water: Option<&Water>) -> [f64; 6] {
        match *self {
            InitialStress::Geostatic {
                surface_z,
                k0,
                surcharge,
            } => {
                // Below the water table up to the ground surface, the water's
                // weight is carried by the pore pressure.
                let lift = match water {
                    Some(w) if gamma != 0.0 => w.unit_weight * (w.surface_z.min(surface_z) - z).max(0.0),
                    _ => 0.0,
                };
                let sz = -surcharge - gamma * (surface_z - z).max(0.0) + lift;
                [k0 * sz, sz, k0 * sz, 0.0, 0.0, 0.0]
            }
            InitialStress::Constant {
                sigma_r,
                sigma_z,
                sigma_theta,
                tau_rz,
            } => [sigma_r, sigma_z, sigma_theta, tau_rz, 0.0, 0.0],
            InitialStress::Gravity => [0.0; 6],
        }
    }

    /// Whether the joints next to this material take their initial
    /// traction from it (every type but `gravity`).
    pub fn gives_traction(&self) -> bool {
        !matches!(self, InitialStress::Gravity)
    }
}

/// Whether a number is 0 (serde: keys left out at their default).
pub(crate) fn is_zero(v: &f64) -> bool {
    *v == 0.0
}
