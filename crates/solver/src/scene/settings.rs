//! The plain parts of a scene: units, mesh source, materials, supports,
//! sections, solver settings, cuts and outputs.

use super::soil::{is_zero, InitialStress, Plasticity};
use crate::material::Elastic;
use serde::de::{self, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::collections::BTreeMap;
use std::fmt;

/// Unit labels. Values in a scene are plain numbers in these units; the
/// solver never converts, the labels travel to the reports.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Units {
    /// Length, e.g. `m`.
    #[serde(default = "Units::default_length")]
    pub length: String,
    /// Force, e.g. `MN`.
    #[serde(default = "Units::default_force")]
    pub force: String,
    /// Stress (force / length^2), e.g. `MPa`.
    #[serde(default = "Units::default_stress")]
    pub stress: String,
}

impl Units {
    fn default_length() -> String {
        "m".into()
    }
    fn default_force() -> String {
        "MN".into()
    }
    fn default_stress() -> String {
        "MPa".into()
    }

    /// For labels this module knows (length m, cm, mm; force N, kN, MN;
    /// stress Pa, kPa, MPa, GPa): `Some(true)` if stress = force / length^2,
    /// `Some(false)` if not; `None` when a label is unknown (not checked).
    pub fn consistent(&self) -> Option<bool> {
        let length = match self.length.as_str() {
            "m" => 1.0,
            "cm" => 1e-2,
            "mm" => 1e-3,
            _ => return None,
        };
        let force = match self.force.as_str() {
            "N" => 1.0,
            "kN" => 1e3,
            "MN" => 1e6,
            _ => return None,
        };
        let stress = match self.stress.as_str() {
            "Pa" => 1.0,
            "kPa" => 1e3,
            "MPa" => 1e6,
            "GPa" => 1e9,
            _ => return None,
        };
        let ratio: f64 = force / (length * length) / stress;
        Some((ratio - 1.0).abs() < 1e-9)
    }
}

impl Default for Units {
    fn default() -> Self {
        Units {
            length: Units::default_length(),
            force: Units::default_force(),
            stress: Units::default_stress(),
        }
    }
}

/// Where the mesh comes from: a `.geo` (meshed by gmsh with `parameters`)
/// or a `.msh`, relative to the scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSource {
    /// Path of the `.geo` or `.msh`, relative to the scene file.
    pub file: String,
    /// gmsh `-setnumber NAME VALUE` pairs (only for a `.geo`).
    #[serde(default)]
    pub parameters: BTreeMap<String, f64>,
    /// Re-mesh the `.geo` from the error estimate (docs/accuracy.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub adapt: Option<Adapt>,
}

/// `mesh.adapt`: re-mesh from the error estimate until every cut
/// profile's estimated error is below `target` (docs/accuracy.md).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Adapt {
    /// The estimated error every profile must reach, a fraction of its
    /// max |stress| (0.01 = 1 %).
    pub target: f64,
    /// The most re-meshings (default 6).
    #[serde(default = "Adapt::default_cycles")]
    pub max_cycles: u32,
}

impl Adapt {
    fn default_cycles() -> u32 {
        6
    }
}

/// An isotropic elastic material (stress units).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus E > 0.
    #[serde(rename = "E")]
    pub e: f64,
    /// Poisson's ratio, -1 < nu < 0.5.
    pub nu: f64,
    /// Unit weight gamma (force / length^3, >= 0): the self-weight, a body
    /// force `-gamma` in z. Without an initial phase (no material has an
    /// `initial_stress`) it is a load like the others (scaled by the load
    /// factor of a stepped run); with one it loads the initial phase.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub unit_weight: f64,
    /// The stress the material starts from; any material with one gives the
    /// scene an initial phase (docs/loading.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial_stress: Option<InitialStress>,
    /// The yield criterion of a perfectly plastic material; none: elastic.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plasticity: Option<Plasticity>,
}

impl Material {
    /// As the element layer's material (unchecked: see [`Elastic::validate`]).
    pub fn elastic(&self) -> Elastic {
        Elastic {
            e: self.e,
            nu: self.nu,
        }
    }
}

/// Displacement components a support fixes, in (r, z, theta).
///
/// Written as a list of `"r"`, `"z"`, `"theta"` (or `"all"`), or the
/// string `"all"`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Fix {
    /// u_r = 0.
    pub r: bool,
    /// u_z = 0.
    pub z: bool,
    /// u_theta = 0.
    pub theta: bool,
}

impl Fix {
    /// All three components.
    pub const ALL: Fix = Fix {
        r: true,
        z: true,
        theta: true,
    };

    /// `[r, z, theta]`, the node-major DOF order.
    pub fn components(&self) -> [bool; 3] {
        [self.r, self.z, self.theta]
    }

    /// The names of the fixed components, in the order r, z, theta.
    pub fn names(&self) -> Vec<&'static str> {
        [(self.r, "r"), (self.z, "z"), (self.theta, "theta")]
            .iter()
            .filter(|(on, _)| *on)
            .map(|&(_, n)| n)
            .collect()
    }

    /// True if nothing is fixed.
    pub fn is_empty(&self) -> bool {
        !(self.r || self.z || self.theta)
    }

    fn add(&mut self, name: &str) -> Result<(), String> {
        match name {
            "r" => self.r = true,
            "z" => self.z = true,
            "theta" => self.theta = true,
            "all" => *self = Fix::ALL,
            other => {
                return Err(format!(
                    "unknown component `{other}`, expected `r`, `z`, `theta` or `all`"
                ))
            }
        }
        Ok(())
    }
}

impl<'de> Deserialize<'de> for Fix {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct FixVisitor;
        impl<'de> Visitor<'de> for FixVisitor {
            type Value = Fix;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("\"all\" or a list of \"r\", \"z\", \"theta\"")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Fix, E> {
                let mut fix = Fix::default();
                fix.add(v).map_err(E::custom)?;
                Ok(fix)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Fix, A::Error> {
                let mut fix = Fix::default();
                while let Some(name) = seq.next_element::<String>()? {
                    fix.add(&name).map_err(de::Error::custom)?;
                }
                Ok(fix)
            }
        }
        d.deserialize_any(FixVisitor)
    }
}

impl Serialize for Fix {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.names().serialize(s)
    }
}

/// A support: zero displacement of some components, in every harmonic, on
/// all nodes of a physical curve or point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Support {
    /// Physical curve (looked up first) or physical point name.
    pub on: String,
    /// The fixed components.
    pub fix: Fix,
}

/// The theta sections where the joint law is evaluated (nonlinear runs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sections {
    /// Angles in degrees, strictly increasing, in [0, 360).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub theta_deg: Vec<f64>,
    /// Or a number of evenly spaced sections: over [0, 180] degrees (both
    /// ends) for loads symmetric about theta = 0, else over the full turn.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub count: Option<usize>,
}

/// The iteration scheme of the nonlinear joint solution.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverMethod {
    /// The paper's stress-transfer iteration (docs/theory.md section 8): each
    /// iteration applies the forces released by the previous one.
    Paper,
    /// The same fixed point accelerated by Anderson mixing of the released
    /// forces (depth 8, restarted when the residual jumps); no extra
    /// factorization, one solve per iteration like the paper's.
    Anderson,
    /// Semi-smooth Newton-Krylov on the same fixed point: the joint tangent
    /// (open, stick, slip) couples the harmonics inside a Krylov solve that
    /// only back-substitutes with the elastic factors; the directions are
    /// reused across Newton steps, a line search on the residual (trial
    /// evaluations without a solve) and a fallback to the plain step
    /// globalize it. No coupled system is factorized. The default: the
    /// fewest and most mesh-independent sweeps measured on Scene P
    /// (docs/performance.md).
    #[default]
    Newton,
}

/// Solver settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSettings {
    /// Iteration scheme.
    #[serde(default)]
    pub method: SolverMethod,
    /// Convergence when the residual ratio Psi_r / Psi_0 < epsilon, 0 < epsilon < 1.
    #[serde(default = "SolverSettings::default_epsilon")]
    pub epsilon: f64,
    /// Iteration limit, >= 1.
    #[serde(default = "SolverSettings::default_max_iterations")]
    pub max_iterations: u32,
    /// With `"harmonics": "auto"`: stop growing M when the cut profiles
    /// change by less than this, relative to their largest value.
    #[serde(default = "SolverSettings::default_harmonics_tolerance")]
    pub harmonics_tolerance: f64,
    /// With `"harmonics": "auto"`: the largest M tried.
    #[serde(default = "SolverSettings::default_max_harmonics")]
    pub max_harmonics: u32,
    /// How the load is applied (nonlinear joints).
    #[serde(default)]
    pub loading: Loading,
}

/// The load path of a nonlinear run: `"one_shot"`, `{"steps": N}` or
/// `{"steps": "auto"}`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Loading {
    /// The whole load in one stress-transfer iteration with the paper's
    /// holonomic law (reproduces the paper).
    OneShot,
    /// Proportional loading `lambda F` in steps of at most `1 / N`, cut back
    /// by bisection where a step does not converge; the history law.
    Steps(u32),
    /// Proportional loading with automatic step control: the whole load
    /// first, bisection on failure, growth after easy steps; the history
    /// law. Ends with the limit load factor when the load cannot be raised.
    #[default]
    Auto,
}

impl Serialize for Loading {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        match self {
            Loading::OneShot => s.serialize_str("one_shot"),
            Loading::Steps(n) => {
                let mut m = s.serialize_map(Some(1))?;
                m.serialize_entry("steps", n)?;
                m.end()
            }
            Loading::Auto => {
                let mut m = s.serialize_map(Some(1))?;
                m.serialize_entry("steps", "auto")?;
                m.end()
            }
        }
    }
}

impl<'de> Deserialize<'de> for Loading {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        const EXPECTED: &str = r#""one_shot", {"steps": N} (N >= 1) or {"steps": "auto"}"#;
        impl<'de> Visitor<'de> for V {
            type Value = Loading;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(EXPECTED)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Loading, E> {
                match v {
                    "one_shot" => Ok(Loading::OneShot),
                    _ => Err(E::invalid_value(de::Unexpected::Str(v), &EXPECTED)),
                }
            }
            fn visit_map<A: de::MapAccess<'de>>(self, mut map: A) -> Result<Loading, A::Error> {
                #[derive(Deserialize)]
                #[serde(untagged)]
                enum Steps {
                    N(u32),
                    Name(String),
                }
                let Some(key) = map.next_key::<String>()? else {
                    return Err(de::Error::missing_field("steps"));
                };
                if key != "steps" {
                    return Err(de::Error::unknown_field(&key, &["steps"]));
                }
                let loading = match map.next_value::<Steps>()? {
                    Steps::N(0) => {
                        return Err(de::Error::invalid_value(de::Unexpected::Unsigned(0), &EXPECTED))
                    }
                    Steps::N(n) => Loading::Steps(n),
                    Steps::Name(s) if s == "auto" => Loading::Auto,
                    Steps::Name(s) => {
                        return Err(de::Error::invalid_value(de::Unexpected::Str(&s), &EXPECTED))
                    }
                };
                if let Some(extra) = map.next_key::<String>()? {
                    return Err(de::Error::unknown_field(&extra, &["steps"]));
                }
                Ok(loading)
            }
        }
        d.deserialize_any(V)
    }
}

impl SolverSettings {
    fn default_epsilon() -> f64 {
        1e-6
    }
    fn default_max_iterations() -> u32 {
        500
    }
    fn default_harmonics_tolerance() -> f64 {
        0.01
    }
    fn default_max_harmonics() -> u32 {
        64
    }
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            method: SolverMethod::default(),
            epsilon: SolverSettings::default_epsilon(),
            max_iterations: SolverSettings::default_max_iterations(),
            harmonics_tolerance: SolverSettings::default_harmonics_tolerance(),
            max_harmonics: SolverSettings::default_max_harmonics(),
            loading: Loading::default(),
        }
    }
}

/// A straight cut in the (r, z) plane, sampled at some theta.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cut {
    /// Name (letters, digits, `-`, `_`, `.`): used in output file names.
    pub name: String,
    /// Start point (r, z), r >= 0.
    pub from: [f64; 2],
    /// End point (r, z), r >= 0.
    pub to: [f64; 2],
    /// Distance between samples along the cut (length units), > 0.
    pub spacing: f64,
    /// Angles in degrees where the cut is sampled.
    #[serde(default = "Cut::default_theta")]
    pub theta_deg: Vec<f64>,
    /// The stress component its plot shows: `sigma_r`, `sigma_z`,
    /// `sigma_theta`, `tau_rz`, `tau_rtheta` or `tau_ztheta` (the CSV has
    /// all six).
    #[serde(default = "Cut::default_component")]
    pub component: String,
}

impl Cut {
    fn default_theta() -> Vec<f64> {
        vec![0.0]
    }
    fn default_component() -> String {
        "sigma_z".into()
    }

    /// Index of [`Cut::component`] in the stress vector, if it is a known name.
    pub fn component_index(&self) -> Option<usize> {
        crate::elements::STRESS_NAMES
            .iter()
            .position(|n| *n == self.component)
    }
}

/// Which result files to write besides the solution itself.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Outputs {
    /// CSV of every cut, joint and of the convergence.
    #[serde(default = "yes")]
    pub csv: bool,
    /// SVG plots of the cuts, joint states and convergence.
    #[serde(default = "yes")]
    pub plots: bool,
    /// A PNG beside every SVG plot (off by default: the PNGs take more
    /// than half of the report's CPU time, docs/performance.md).
    #[serde(default)]
    pub png: bool,
    /// `axijoint run` of a scene with joints also solves it bonded, for
    /// the dashed curves of the cut plots.
    #[serde(default = "yes")]
    pub compare_without_joints: bool,
    /// ParaView `.vtu` of the field revolved in 3D.
    #[serde(default = "yes")]
    pub vtu: bool,
    /// Sections of the turn in the `.vtu`: a number, or `"auto"` (the
    /// default) for as many as the highest harmonic needs.
    #[serde(default)]
    pub vtu_sections: VtuSections,
    /// Point arrays of `field.vtu`, from [`Outputs::VTU_FIELDS`].
    #[serde(default = "Outputs::default_vtu_fields")]
    pub vtu_fields: Vec<String>,
    /// zlib-compressed `.vtu` arrays (a fifth smaller, about twice the
    /// time of writing them raw; docs/outputs.md).
    #[serde(default)]
    pub vtu_compress: bool,
    /// gmsh post-processing view of the meridional fields at the cuts' angles.
    #[serde(default = "yes")]
    pub gmsh_views: bool,
    /// Bodies read as members along the axis (a pile, an anchor): their
    /// section forces, the surroundings' reaction and the capacity split
    /// ([`crate::members`]; `member_<body>.csv`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub members: Vec<String>,
    /// With `stages`: `"each"` writes a solution folder (and its report)
    /// at the end of every leg but the last, in `stages/`; `"end"` (the
    /// default): the run's folder only.
    #[serde(default, skip_serializing_if = "StageOutputs::is_end")]
    pub stages: StageOutputs,
}

/// Which states of a staged run get outputs ([`Outputs::stages`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StageOutputs {
    /// The end of the run only.
    #[default]
    End,
    /// The end of every leg.
    Each,
}

impl StageOutputs {
    fn is_end(&self) -> bool {
        *self == StageOutputs::End
    }
}

fn yes() -> bool {
    true
}

impl Outputs {
    /// Point arrays `field.vtu` can hold.
    pub const VTU_FIELDS: [&'static str; 5] = [
        "displacement",
        "displacement_cyl",
        "stress",
        "sigma_cyl",
        "von_mises",
    ];

    fn default_vtu_fields() -> Vec<String> {
        ["displacement", "sigma_cyl", "von_mises"]
            .map(String::from)
            .to_vec()
    }
}

/// Sections of the turn in the `.vtu`: `"auto"` or a number.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum VtuSections {
    /// Enough for the highest harmonic solved (the report chooses).
    #[default]
    Auto,
    /// This many.
    Count(usize),
}

impl Serialize for VtuSections {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            VtuSections::Auto => s.serialize_str("auto"),
            VtuSections::Count(n) => s.serialize_u64(*n as u64),
        }
    }
}

impl<'de> Deserialize<'de> for VtuSections {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = VtuSections;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number of sections or \"auto\"")
            }
            fn visit_u64<E: de::Error>(self, n: u64) -> Result<VtuSections, E> {
                usize::try_from(n)
                    .map(VtuSections::Count)
                    .map_err(|_| E::custom("too many sections"))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<VtuSections, E> {
                match v {
                    "auto" => Ok(VtuSections::Auto),
                    _ => Err(E::invalid_value(de::Unexpected::Str(v), &self)),
                }
            }
        }
        d.deserialize_any(V)
    }
}

impl Default for Outputs {
    fn default() -> Self {
        Outputs {
            csv: true,
            plots: true,
            png: false,
            compare_without_joints: true,
            vtu: true,
            vtu_sections: VtuSections::Auto,
            vtu_fields: Outputs::default_vtu_fields(),
            vtu_compress: false,
            gmsh_views: true,
            members: Vec::new(),
            stages: StageOutputs::End,
        }
    }
}
