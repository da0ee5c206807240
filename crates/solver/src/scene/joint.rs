//! Joints of a scene: springs (given, rigid or from a layer's thickness),
//! constitutive law and integration rule.

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
    /// How the springs follow from the bodies and the mesh: `"rigid"` or
    /// `{"thickness": t}` (not beside the `k_*`). With neither this nor
    /// the `k_*` the joint is rigid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<StiffnessSpec>,
    /// Tangential stiffness (stress / length), >= 0 (give all three `k_*`
    /// or none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_xi: Option<f64>,
    /// Normal stiffness (stress / length), >= 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_eta: Option<f64>,
    /// Circumferential stiffness (stress / length), >= 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_theta: Option<f64>,
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
    /// The form of its stiffness: the given `k_*` (unchecked: see
    /// [`JointSprings::validate`]), `"rigid"` (also when nothing is given)
    /// or a layer's thickness (unchecked). `Err((key, message))` when both
    /// `stiffness` and a `k_*` are given, or only some of the `k_*`; `key`
    /// is relative to the joint.
    pub fn stiffness(&self) -> Result<JointStiffness, (&'static str, String)> {
        let given = [
            ("k_xi", self.k_xi),
            ("k_eta", self.k_eta),
            ("k_theta", self.k_theta),
        ];
        let named = |pick: fn(&Option<f64>) -> bool| {
            let v: Vec<&str> = given.iter().filter(|(_, k)| pick(k)).map(|(n, _)| *n).collect();
            v.join(", ")
        };
        let some = given.iter().filter(|(_, k)| k.is_some()).count();
        match (self.stiffness, some) {
            (Some(_), 1..) => Err((
                "stiffness",
                format!(
                    "give either `stiffness` or the springs k_xi, k_eta and k_theta, not both (also given: {})",
                    named(Option::is_some)
                ),
            )),
            (Some(StiffnessSpec::Rigid), 0) | (None, 0) => Ok(JointStiffness::Rigid),
            (Some(StiffnessSpec::Thickness(t)), 0) => Ok(JointStiffness::Thickness(t)),
            (None, 3) => Ok(JointStiffness::Given(JointSprings {
                k_xi: self.k_xi.unwrap_or_default(),
                k_eta: self.k_eta.unwrap_or_default(),
                k_theta: self.k_theta.unwrap_or_default(),
            })),
            (None, _) => {
                let missing = given
                    .iter()
                    .find(|(_, k)| k.is_none())
                    .map_or("k_xi", |(n, _)| *n);
                Err((
                    missing,
                    format!(
                        "{} given but not {}: give all three springs k_xi, k_eta and k_theta, or none of them and `\"stiffness\": \"rigid\"` (the default) or `{{\"thickness\": t}}`",
                        named(Option::is_some),
                        named(Option::is_none)
                    ),
                ))
            }
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

/// `k h_min / E` of a `"rigid"` joint: its three springs are
/// `RIGID_STIFFNESS E / h_min`, E the smallest Young's modulus of the bodies
/// on its faces and `h_min` its shortest element. The displacement error of
/// a finite penalty is about `E / (k L)` = `h_min / (1000 L)` for a loaded
/// body of size L: about 1e-4 measured on the piles of `geo/`, against the
/// same scenes bonded (docs/stability.md, "Which stiffness to choose").
pub const RIGID_STIFFNESS: f64 = 1000.0;

/// The `stiffness` of a joint as written: `"rigid"` or `{"thickness": t}`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StiffnessSpec {
    /// `"rigid"`: a penalty `RIGID_STIFFNESS E / h_min` ([`RIGID_STIFFNESS`]).
    Rigid,
    /// `{"thickness": t}`: an interface layer of thickness t (length) of the
    /// softer adjacent body.
    Thickness(f64),
}

/// `{"thickness": t}`, read with unknown keys refused.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ThicknessSpec {
    thickness: f64,
}

impl Serialize for StiffnessSpec {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match *self {
            StiffnessSpec::Rigid => s.serialize_str("rigid"),
            StiffnessSpec::Thickness(thickness) => ThicknessSpec { thickness }.serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for StiffnessSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::{self, MapAccess, Visitor};
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = StiffnessSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(r#""rigid" or {"thickness": t} (t a length > 0)"#)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<StiffnessSpec, E> {
                match v {
                    "rigid" => Ok(StiffnessSpec::Rigid),
                    _ => Err(E::custom(format!(
                        r#"'{v}' is not a stiffness: give "rigid", {{"thickness": t}} (t a length > 0), or leave out `stiffness` and give k_xi, k_eta and k_theta"#
                    ))),
                }
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<StiffnessSpec, A::Error> {
                ThicknessSpec::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(|t| StiffnessSpec::Thickness(t.thickness))
            }
        }
        d.deserialize_any(V)
    }
}

/// The form of a joint's stiffness, its `k_*` and `stiffness` read
/// together ([`JointConfig::stiffness`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointStiffness {
    /// The springs as given.
    Given(JointSprings),
    /// A penalty `RIGID_STIFFNESS E / h_min` ([`RIGID_STIFFNESS`]).
    Rigid,
    /// An interface layer of this thickness (length) of the softer body.
    Thickness(f64),
}

/// Where a joint's springs came from (`joint_springs` in the run record).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SpringSource {
    /// `"stiffness": "rigid"` (or nothing given).
    Rigid,
    /// `"stiffness": {"thickness": t}`.
    Thickness,
    /// `k_xi`, `k_eta`, `k_theta` as given.
    Given,
}

impl JointStiffness {
    /// Where the springs come from.
    pub fn source(&self) -> SpringSource {
        match self {
            JointStiffness::Given(_) => SpringSource::Given,
            JointStiffness::Rigid => SpringSource::Rigid,
            JointStiffness::Thickness(_) => SpringSource::Thickness,
        }
    }

    /// The springs of a joint whose softer adjacent body (smallest E) is
    /// `softer` and whose shortest element is `h_min` long:
    /// - rigid: `k_xi = k_eta = k_theta = RIGID_STIFFNESS E / h_min`;
    /// - thickness t: `k_eta = E_oed / t`, `E_oed = E (1 - nu) / ((1 + nu)
    ///   (1 - 2 nu))`, and `k_xi = k_theta = G / t`, `G = E / (2 (1 + nu))`;
    /// - given: as given.
    pub fn resolve(&self, softer: crate::material::Elastic, h_min: f64) -> JointSprings {
        let (e, nu) = (softer.e, softer.nu);
        match *self {
            JointStiffness::Given(k) => k,
            JointStiffness::Rigid => {
                let k = RIGID_STIFFNESS * e / h_min;
                JointSprings {
                    k_xi: k,
                    k_eta: k,
                    k_theta: k,
                }
            }
            JointStiffness::Thickness(t) => {
                let e_oed = e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
                let g = e / (2.0 * (1.0 + nu));
                JointSprings {
                    k_xi: g / t,
                    k_eta: e_oed / t,
                    k_theta: g / t,
                }
            }
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
