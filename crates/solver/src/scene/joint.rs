//! Joints of a scene: springs, constitutive law and integration rule.

use crate::elements::{JointRule, JointSprings};
use axijoint_mesh::{JointKind, JointSpec};
use serde::{Deserialize, Serialize};

/// A joint along a physical curve (the key of `joints` in the scene).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointConfig {
    /// Physical surface on the bottom face (give both sides or neither).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bottom: Option<String>,
    /// Physical surface on the top face.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub top: Option<String>,
    /// Tangential stiffness (stress / length), >= 0.
    pub k_xi: f64,
    /// Normal stiffness (stress / length), >= 0.
    pub k_eta: f64,
    /// Circumferential stiffness (stress / length), >= 0.
    pub k_theta: f64,
    /// Constitutive law.
    pub law: JointLaw,
    /// Integration rule family.
    #[serde(default)]
    pub rule: RuleKind,
    /// Number of points of a Gauss (1..=5) or Lobatto (2..=5) rule; by
    /// default 2 on linear and 3 on quadratic joints.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub points: Option<usize>,
    /// Initial traction `(tau_xi, sigma, tau_theta)` (stress, tension
    /// positive) along the whole joint; by default that of the initial
    /// stress of the bodies it separates.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial_traction: Option<[f64; 3]>,
}

impl JointConfig {
    /// The spring stiffnesses (unchecked: see [`JointSprings::validate`]).
    pub fn springs(&self) -> JointSprings {
        JointSprings {
            k_xi: self.k_xi,
            k_eta: self.k_eta,
            k_theta: self.k_theta,
        }
    }

    /// The integration rule for joint elements of `kind`.
    pub fn rule(&self, kind: JointKind) -> JointRule {
        let default_points = match kind {
            JointKind::Lin4 => 2,
            JointKind::Lin6 => 3,
        };
        let n = self.points.unwrap_or(default_points);
        match self.rule {
            RuleKind::Gauss => JointRule::Gauss(n),
            RuleKind::Lobatto => JointRule::Lobatto(n),
            RuleKind::Paper => JointRule::Paper,
        }
    }

    /// The mesh crate's description of this joint along `curve`.
    pub fn spec(&self, curve: &str) -> JointSpec {
        JointSpec {
            curve: curve.to_string(),
            bottom: self.bottom.clone(),
            top: self.top.clone(),
        }
    }
}

/// Integration rule family along joint elements.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RuleKind {
    /// Gauss-Legendre.
    #[default]
    Gauss,
    /// Gauss-Lobatto (nodal integration with 2 points on Lin4, 3 on Lin6).
    Lobatto,
    /// The paper's one point at the element centre (its Eq. 7).
    Paper,
}

/// How the shear is checked against the Mohr-Coulomb strength tau_y.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShearCheck {
    /// `|(tau_xi, tau_theta)| <= tau_y` (isotropic).
    #[default]
    Resultant,
    /// `|tau_xi| <= tau_y` and `|tau_theta| <= tau_y` each (the paper's reading).
    Components,
}

/// Mohr-Coulomb strength with a tension cut-off (docs/theory.md section 7, the joint law):
/// `tau_y = C - sigma tan(phi)` for `sigma <= 0`; the joint opens when the
/// normal stress exceeds the tensile strength.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MohrCoulomb {
    /// Cohesion C (stress), >= 0.
    pub cohesion: f64,
    /// Friction angle phi in degrees, 0 <= phi < 90.
    pub friction_deg: f64,
    /// Tensile strength (stress), >= 0; 0 is the paper's no-tension joint.
    pub tensile_strength: f64,
    /// Shear check.
    pub shear_check: ShearCheck,
}

impl MohrCoulomb {
    /// `tan(phi)`.
    pub fn tan_phi(&self) -> f64 {
        self.friction_deg.to_radians().tan()
    }
}

/// Constitutive law of a joint.
///
/// Written `{"type": "linear"}` or `{"type": "mohr_coulomb", "cohesion": C,
/// "friction_deg": phi, "tensile_strength": 0, "shear_check": "resultant"}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "LawSpec", into = "LawSpec")]
pub enum JointLaw {
    /// Linear springs: the joint never opens or slips.
    Linear,
    /// No tension and Mohr-Coulomb slip.
    MohrCoulomb(MohrCoulomb),
}

/// The law's kind, the `type` key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
enum LawType {
    Linear,
    MohrCoulomb,
}

/// The law as written: a flat object (so that key paths reach every value),
/// turned into [`JointLaw`] once its `type` is known.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LawSpec {
    #[serde(rename = "type")]
    kind: LawType,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    cohesion: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    friction_deg: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    tensile_strength: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    shear_check: Option<ShearCheck>,
}

impl TryFrom<LawSpec> for JointLaw {
    type Error = String;
    fn try_from(s: LawSpec) -> Result<Self, String> {
        match s.kind {
            LawType::Linear => {
                let given = [
                    ("cohesion", s.cohesion.is_some()),
                    ("friction_deg", s.friction_deg.is_some()),
                    ("tensile_strength", s.tensile_strength.is_some()),
                    ("shear_check", s.shear_check.is_some()),
                ];
                match given.iter().find(|(_, g)| *g) {
                    Some((key, _)) => Err(format!(
                        "key `{key}` does not belong to a linear law (it takes only `type`)"
                    )),
                    None => Ok(JointLaw::Linear),
                }
            }
            LawType::MohrCoulomb => Ok(JointLaw::MohrCoulomb(MohrCoulomb {
                cohesion: s
                    .cohesion
                    .ok_or("a mohr_coulomb law needs `cohesion` (stress units)")?,
                friction_deg: s
                    .friction_deg
                    .ok_or("a mohr_coulomb law needs `friction_deg` (degrees)")?,
                tensile_strength: s.tensile_strength.unwrap_or(0.0),
                shear_check: s.shear_check.unwrap_or_default(),
            })),
        }
    }
}

impl From<JointLaw> for LawSpec {
    fn from(law: JointLaw) -> Self {
        match law {
            JointLaw::Linear => LawSpec {
                kind: LawType::Linear,
                cohesion: None,
                friction_deg: None,
                tensile_strength: None,
                shear_check: None,
            },
            JointLaw::MohrCoulomb(mc) => LawSpec {
                kind: LawType::MohrCoulomb,
                cohesion: Some(mc.cohesion),
                friction_deg: Some(mc.friction_deg),
                tensile_strength: Some(mc.tensile_strength),
                shear_check: Some(mc.shear_check),
            },
        }
    }
}
