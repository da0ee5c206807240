//! Scene files: one JSON document that says everything a run needs.
//!
//! The format (every key, type, unit and default) is documented in
//! `docs/scene-format.md`. Reading is strict: every object refuses unknown
//! keys, and an error names the file and the key path, e.g.
//! `geo/p.json: loads[1].force: 2 numbers given, give three: [Fx, Fy, Fz] (Cartesian, x at theta = 0) (line 14, column 31)`.
//!
//! ```
//! use axijoint_solver::scene::Scene;
//! let text = r#"{
//!   "mesh": {"file": "block.msh"},
//!   "materials": {"block": {"E": 100.0, "nu": 0.25}},
//!   "supports": [{"on": "bottom", "fix": "all"}],
//!   "loads": [{"type": "resultant", "on": "top", "force": [0, 0, -1]}],
//!   "harmonics": 1
//! }"#;
//! let scene = Scene::from_str(text, "cases/block.json").unwrap();
//! assert_eq!(scene.mesh_path(), std::path::Path::new("cases/block.msh"));
//! assert_eq!(scene.harmonics(), 1);
//!
//! let typo = text.replace("\"nu\"", "\"poisson\"");
//! let err = Scene::from_str(&typo, "cases/block.json").unwrap_err();
//! assert_eq!(err.key(), Some("materials.block.poisson"));
//! ```
//!
//! Two levels of checking: [`Scene::from_str`] / [`Scene::from_path`] read
//! types and shapes; [`Scene::check`] checks values and, against a mesh,
//! the physical names.

mod check;
mod error;
mod joint;
mod load;
mod locate;
mod motion;
mod settings;
mod soil;
mod stage;

pub use error::{did_you_mean, nearest, NameKind, SceneError};
pub use joint::{
    JointConfig, JointLaw, JointStiffness, MohrCoulomb, RuleKind, ShearCheck, SpringSource, StiffnessSpec,
    RIGID_STIFFNESS,
};
pub use load::{Family, Linear, Load, MotionLoad, PointLoad, ResultantLoad, RingLoad, TractionLoad};
pub use settings::{
    Adapt, Cut, Fix, Loading, Material, MeshSource, Outputs, Sections, SolverMethod, SolverSettings,
    StageOutputs, Support, Units, VtuSections,
};
pub use soil::{InitialStress, Plasticity, Water};
pub use stage::{stage_label, Cyclic, Leg, Stage, MAX_STAGES};

use axijoint_mesh::JointSpec;
use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use std::marker::PhantomData;
use std::path::{Path, PathBuf};

/// The harmonics of a run: `M` (harmonics 0..=M) or `"auto"` (chosen by
/// the run: the loads' harmonics for a linear scene; for nonlinear joints M
/// grows 4, 8, 16, ... until the cut profiles change by less than
/// `solver.harmonics_tolerance`, at most `solver.max_harmonics`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Harmonics {
    /// Harmonics 0..=M.
    Fixed(u32),
    /// Chosen by the run.
    Auto,
}

impl From<u32> for Harmonics {
    fn from(m: u32) -> Self {
        Harmonics::Fixed(m)
    }
}

impl Serialize for Harmonics {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Harmonics::Fixed(m) => s.serialize_u32(*m),
            Harmonics::Auto => s.serialize_str("auto"),
        }
    }
}

impl<'de> Deserialize<'de> for Harmonics {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = Harmonics;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a highest harmonic M >= 0 or \"auto\"")
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Harmonics, E> {
                u32::try_from(v)
                    .map(Harmonics::Fixed)
                    .map_err(|_| E::custom(format!("{v} harmonics is too many")))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Harmonics, E> {
                u64::try_from(v)
                    .map_err(|_| E::custom(format!("{v}: the highest harmonic is >= 0")))
                    .and_then(|v| self.visit_u64(v))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Harmonics, E> {
                match v {
                    "auto" => Ok(Harmonics::Auto),
                    _ => Err(E::custom(format!("'{v}': expected a number or \"auto\""))),
                }
            }
        }
        d.deserialize_any(V)
    }
}

/// A scene: mesh, materials, joints, supports, loads and run settings.
///
/// Plain data with public fields; `path` is the file it was read from
/// (relative paths inside the scene are resolved against its folder).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Free title, echoed in reports.
    #[serde(default)]
    pub title: String,
    /// Free notes, echoed in reports.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// Unit labels.
    #[serde(default)]
    pub units: Units,
    /// The `.geo` or `.msh` and its gmsh parameters.
    pub mesh: MeshSource,
    /// Material of each physical surface, by name.
    #[serde(deserialize_with = "unique_map")]
    pub materials: BTreeMap<String, Material>,
    /// Joints, by physical curve name.
    #[serde(default, deserialize_with = "unique_map")]
    pub joints: BTreeMap<String, JointConfig>,
    /// Supports.
    #[serde(default)]
    pub supports: Vec<Support>,
    /// Loads.
    #[serde(default)]
    pub loads: Vec<Load>,
    /// Named load sets, each solved on the same factors from the initial
    /// state (none: `loads` is the one case).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub load_cases: Vec<LoadCase>,
    /// Loads in stages, each from the converged state of the one before
    /// (none: `loads` is the one stage). When given, `loads` holds the
    /// loads at the end of the last ([`Scene::from_str`] sets them).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stages: Vec<Stage>,
    /// Horizontal pseudo-static (seismic) coefficient k_h: a body force
    /// `k_h gamma` in +x on every material with a unit weight (harmonic 1).
    #[serde(default, skip_serializing_if = "soil::is_zero")]
    pub seismic_coefficient: f64,
    /// Ground water at rest (drained analysis); none: dry.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub water: Option<Water>,
    /// Highest harmonic M (the run solves harmonics 0..=M), or `"auto"`.
    pub harmonics: Harmonics,
    /// Theta sections of the joint law; `None`: the paper's M + 1 sections.
    #[serde(default)]
    pub sections: Option<Sections>,
    /// Solver settings.
    #[serde(default)]
    pub solver: SolverSettings,
    /// Cuts for stress profiles.
    #[serde(default)]
    pub cuts: Vec<Cut>,
    /// Result files.
    #[serde(default)]
    pub outputs: Outputs,
    /// The scene file (not part of the JSON).
    #[serde(skip)]
    pub path: PathBuf,
    /// Go on past the cost limits ([`MAX_HARMONICS`], the memory estimate
    /// of [`crate::run::least_factor_memory`]): the command line's `--force` (not part
    /// of the JSON).
    #[serde(skip)]
    pub force: bool,
    /// The folder the run writes (not part of the JSON): its disk must
    /// hold the estimated outputs ([`crate::run::output_bytes`]); `None`:
    /// not checked.
    #[serde(skip)]
    pub output: Option<PathBuf>,
}

/// The highest harmonic a scene may ask for without `--force`: the
/// answers our users need converge by M = 64 (docs/accuracy.md), a
/// hundred times more only costs time and memory (a units slip or a typo).
pub const MAX_HARMONICS: u32 = 512;

/// A named set of loads ([`Scene::load_cases`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadCase {
    /// Name: the case's sub-folder (letters, digits, `_`, `-`, `.`).
    pub name: String,
    /// Its loads.
    pub loads: Vec<Load>,
}

impl Scene {
    /// The scene of load case `k`: its loads in place of `loads`, no cases,
    /// the case's name after the title.
    pub fn case(&self, k: usize) -> Scene {
        let case = &self.load_cases[k];
        Scene {
            title: format!("{} [load case {}]", self.title, case.name),
            loads: case.loads.clone(),
            load_cases: Vec::new(),
            ..self.clone()
        }
    }

    /// Reads and parses a scene file (types and shapes only; see
    /// [`Scene::check`]).
    pub fn from_path(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|error| SceneError::Io {
            path: path.to_path_buf(),
            error,
        })?;
        Scene::from_str(&text, path)
    }

    /// Parses scene text; `path` is the file it stands for (for messages and
    /// to resolve `mesh.file`).
    pub fn from_str(text: &str, path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let parse_error = |key: String, e: serde_json::Error| SceneError::Parse {
            path: path.to_path_buf(),
            key,
            message: strip_location(&e),
            line: e.line(),
            column: e.column(),
            overridden: false,
        };
        let mut de = serde_json::Deserializer::from_str(text);
        let mut scene: Scene = serde_path_to_error::deserialize(&mut de).map_err(|e| {
            let key = e.path().to_string();
            parse_error(key, e.into_inner())
        })?;
        de.end().map_err(|e| parse_error(".".into(), e))?;
        scene.path = path.to_path_buf();
        if !scene.stages.is_empty() {
            if !scene.loads.is_empty() {
                return Err(scene.invalid("stages", "give either `loads` (one stage) or `stages`, not both"));
            }
            // What every load-based output reads: the loads at the end.
            scene.loads = scene.legs().pop().map(|l| l.loads).unwrap_or_default();
        }
        Ok(scene)
    }

    /// The mesh file, resolved against the scene file's folder.
    pub fn mesh_path(&self) -> PathBuf {
        let file = Path::new(&self.mesh.file);
        match self.path.parent() {
            Some(dir) if file.is_relative() => dir.join(file),
            _ => file.to_path_buf(),
        }
    }

    /// gmsh `-setnumber` pairs, sorted by name.
    pub fn gmsh_parameters(&self) -> Vec<(String, f64)> {
        self.mesh
            .parameters
            .iter()
            .map(|(k, v)| (k.clone(), *v))
            .collect()
    }

    /// Highest harmonic M (the run solves 0..=M).
    pub fn harmonics(&self) -> u32 {
        match self.harmonics {
            Harmonics::Fixed(m) => m,
            Harmonics::Auto => self
                .loads
                .iter()
                .chain(
                    self.stages
                        .iter()
                        .flat_map(|s| s.loads.iter().chain(s.cyclic.iter().flat_map(|c| c.loads.iter()))),
                )
                .map(|l| l.max_harmonic())
                .max()
                .unwrap_or(0)
                .max(4),
        }
    }

    /// Whether the scene starts with an initial phase: some material has an
    /// `initial_stress`.
    pub fn has_initial_phase(&self) -> bool {
        self.materials.values().any(|m| m.initial_stress.is_some())
    }

    /// Whether a joint can open or slip (its law is not `linear`).
    pub fn has_nonlinear_joints(&self) -> bool {
        self.joints.values().any(|j| j.law != JointLaw::Linear)
    }

    /// Whether a material yields (it has a `plasticity`).
    pub fn has_plastic_bodies(&self) -> bool {
        self.materials.values().any(|m| m.plasticity.is_some())
    }

    /// Whether the run iterates: a joint can open or slip, or a material
    /// yields.
    pub fn is_nonlinear(&self) -> bool {
        self.has_nonlinear_joints() || self.has_plastic_bodies()
    }

    /// The joints as the mesh crate inserts them.
    pub fn joint_specs(&self) -> Vec<JointSpec> {
        self.joints.iter().map(|(name, j)| j.spec(name)).collect()
    }

    /// The theta sections of the joint law. `symmetric_only`: the loads are
    /// symmetric about theta = 0 (no antisymmetric family, no torsion), so a
    /// set over [0, pi] stands for the whole turn.
    ///
    /// Given angles are used as they are (a half set when `symmetric_only`
    /// and all lie in [0, 180] degrees); `count` spaces that many evenly;
    /// by default the set is dealiased: 2M + 1 over the half turn (4M over
    /// the full turn), so that the law's released traction, which has
    /// content above M, does not fold back onto the harmonics 0..=M.
    pub fn theta_sections(&self, symmetric_only: bool) -> Result<crate::fourier::Sections, SceneError> {
        use crate::fourier::Sections as Set;
        let m = self.harmonics() as usize;
        let invalid = |message: String| SceneError::Invalid {
            path: self.path.clone(),
            key: "sections".into(),
            message,
        };
        match &self.sections {
            Some(s) if s.count.is_some() => {
                let n = s.count.unwrap_or(1);
                Ok(if symmetric_only {
                    Set::half_equispaced(n)
                } else {
                    Set::full_equispaced(n)
                })
            }
            Some(s) => {
                let theta: Vec<f64> = s.theta_deg.iter().map(|d| d.to_radians()).collect();
                if symmetric_only && theta.iter().all(|&t| t <= std::f64::consts::PI + 1e-12) {
                    Set::half_circle(theta).map_err(invalid)
                } else {
                    Set::full_circle(theta).map_err(invalid)
                }
            }
            None if symmetric_only => Ok(Set::half_equispaced(2 * m + 1)),
            None => Ok(Set::full_equispaced((4 * m).max(1))),
        }
    }
}

/// serde_json's message without its trailing " at line L column C".
fn strip_location(e: &serde_json::Error) -> String {
    let text = e.to_string();
    let suffix = format!(" at line {} column {}", e.line(), e.column());
    text.strip_suffix(&suffix).unwrap_or(&text).to_string()
}

/// Reads a JSON object into a map, refusing a key given twice (serde's
/// own map would keep the last one silently).
fn unique_map<'de, D, T>(d: D) -> Result<BTreeMap<String, T>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    struct UniqueMap<T>(PhantomData<T>);
    impl<'de, T: Deserialize<'de>> Visitor<'de> for UniqueMap<T> {
        type Value = BTreeMap<String, T>;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str("an object keyed by physical name")
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
            let mut out = BTreeMap::new();
            while let Some(key) = map.next_key::<String>()? {
                if out.contains_key(&key) {
                    return Err(de::Error::custom(format!("`{key}` is given twice")));
                }
                let value = map.next_value()?;
                out.insert(key, value);
            }
            Ok(out)
        }
    }
    d.deserialize_map(UniqueMap(PhantomData))
}
