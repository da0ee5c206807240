//! The run record: what a run did beside its displacements (the key
//! `extra` of `solution.json`, docs/outputs.md), as types. Built in one
//! place ([`crate::run::record`]) and read by the report, the command
//! line, the Python package and the benchmarks.
//!
//! Every field is optional: a linear run without joints or warnings has
//! no record at all, a
//! nonlinear one the iteration's fields, a stepped one its load path, a
//! run that stopped `converged: false` and its error. Fields appear in
//! the JSON in the order of their names.

use crate::iteration::{IterationRecord, LimitLoad, LoadStep};
use crate::scene::{Loading, SpringSource};
use serde::{Deserialize, Deserializer, Serialize};
use std::collections::BTreeMap;

/// The record of a run (`solution.json`'s `extra`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// The cycles of an adaptive run (`mesh.adapt`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub adapt: Option<AdaptTable>,
    /// The steps of an automatic choice of M (`"harmonics": "auto"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub auto_harmonics: Option<AutoHarmonics>,
    /// `false` when the whole load was not reached (absent: reached).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub complete: Option<bool>,
    /// `false` for the last iterate of a run that stopped (absent: converged).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub converged: Option<bool>,
    /// Why a run stopped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// The M/2 check of a converged nonlinear run (`null` when M < 2).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "present"
    )]
    pub harmonic_check: Option<Option<HarmonicCheck>>,
    /// Every iteration, in order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub history: Option<Vec<IterationRecord>>,
    /// Each joint's springs as solved (after `"rigid"` or a thickness was
    /// resolved on the mesh), by joint name.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub joint_springs: BTreeMap<String, JointSpringsRecord>,
    /// Iterations of the run (of its last step's solve when stepped: the
    /// length of `history`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub iterations: Option<usize>,
    /// The load factor at which a stepped run found no equilibrium.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limit_load_factor: Option<f64>,
    /// The load factor reached by a stepped run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub load_factor: Option<f64>,
    /// The converged steps of a stepped run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub load_path: Option<LoadPath>,
    /// How the load was applied (every nonlinear run).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub loading: Option<Loading>,
    /// What the outputs are, when they are not the whole load's equilibrium.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// The largest released force per harmonic at the end.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub released_spectrum: Option<Vec<f64>>,
    /// The joint sections (degrees).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sections_deg: Option<Vec<f64>>,
    /// Plausibility warnings (a slip of units or scale, more harmonics
    /// than the answer needs).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// A field present in the JSON, `null` included (`Some(None)`).
fn present<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<Option<T>, D::Error> {
    T::deserialize(d).map(Some)
}

impl RunRecord {
    /// Whether the run converged (false only for a last iterate).
    pub fn converged(&self) -> bool {
        self.converged != Some(false)
    }

    /// Whether the whole load was reached.
    pub fn complete(&self) -> bool {
        self.complete != Some(false)
    }

    /// The last iteration, if any.
    pub fn last_iteration(&self) -> Option<&IterationRecord> {
        self.history.as_ref().and_then(|h| h.last())
    }

    /// Where a stepped run stopped short of the whole load.
    pub fn limit(&self) -> Option<&LimitLoad> {
        self.load_path.as_ref().and_then(|p| p.limit.as_ref())
    }
}

/// A joint's springs as solved (stress / length) and where they came from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointSpringsRecord {
    /// Tangential stiffness.
    pub k_xi: f64,
    /// Normal stiffness.
    pub k_eta: f64,
    /// Circumferential stiffness.
    pub k_theta: f64,
    /// `"rigid"`, `"thickness"` or `"given"`.
    pub source: SpringSource,
}

/// The converged steps of a stepped run, and where it stopped short of the
/// whole load.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LoadPath {
    /// Converged steps, in order of lambda.
    pub steps: Vec<LoadStep<StepMeasure>>,
    /// Set when the whole load could not be reached: the limit load factor
    /// (of the stage it stopped in, with stages).
    pub limit: Option<LimitLoad>,
    /// With stages: the stage the run stopped in (`limit` set).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stopped_in: Option<StageMark>,
}

impl LoadPath {
    /// The factor on the run's loads reached (1 when the whole load
    /// converged; with stages the run's loads are those applied where it
    /// stopped: 1).
    pub fn reached(&self) -> f64 {
        match (&self.limit, &self.stopped_in) {
            (Some(l), None) => l.factor,
            _ => 1.0,
        }
    }
}

/// A leg of a staged load path ([`crate::scene::Scene::legs`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StageMark {
    /// 0-based leg in the order run (a cyclic stage has a leg per level
    /// and cycle).
    pub leg: usize,
    /// The stage's name.
    pub stage: String,
    /// 1-based cycle and level of a cyclic stage (0: none).
    pub cycle: u32,
    /// 1-based level in the cycle (0: none).
    pub level: u32,
}

impl StageMark {
    /// `stage 'storm'`, or `stage 'storm', cycle 2, level 1`.
    pub fn label(&self) -> String {
        crate::scene::stage_label(&self.stage, self.cycle, self.level)
    }
}

/// What a converged load step measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepMeasure {
    /// Each load's face.
    pub faces: Vec<FaceMotion>,
    /// Each joint's areas by state.
    pub joints: Vec<JointAreas>,
    /// The member forces of the bodies in `outputs.members` at the step
    /// (their reaction curves).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub members: Vec<crate::members::MemberForces>,
    /// With stages: the leg the step belongs to (its `lambda` is the
    /// factor within it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stage: Option<StageMark>,
    /// With stages: the work of the joints' slip in the step (force times
    /// length, >= 0 up to the step's error): `sum da (p . ds)` over the
    /// (section, point) pairs at the step's traction, `ds = dd - dp / k`
    /// the plastic slip.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dissipated: Option<f64>,
    /// With plastic bodies: the volume of their yielding Gauss points at the
    /// step (length^3, each point's share of its ring and section).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plastic_volume: Option<f64>,
}

/// The motion of a loaded face.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FaceMotion {
    /// The physical curve.
    pub on: String,
    /// Face-average Cartesian displacement `(ux, uy, uz)` (length).
    pub mean: [f64; 3],
    /// Mean rotation about the axis (rad): `sum w r u_theta / sum w r^2`.
    pub rotation: f64,
    /// The displacement along the load: `mean . F / |F|` for a resultant
    /// load with a force, the rotation times the face's mean nodal radius
    /// for a pure torque, else the largest component of `mean`.
    pub along: f64,
    /// With stages: the load on the face at the step along the same
    /// direction ([`crate::scene::Scene::staged_faces`]: the force along
    /// that load's force, or the torque of a pure torque): the ordinate of
    /// a hysteresis loop.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub applied: Option<f64>,
}

/// Joint areas by state (length^2), from the section integration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointAreas {
    /// The joint.
    pub joint: String,
    /// Open area.
    pub open: f64,
    /// Slipping area.
    pub slip: f64,
    /// Sticking area.
    pub stick: f64,
}

/// How much the key results change when the harmonics are halved: the
/// user's check that M is enough.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HarmonicCheck {
    /// The solved M.
    pub m: u32,
    /// The compared M/2.
    pub m_half: u32,
    /// Largest change of a force-loaded face's mean displacement,
    /// relative to the largest such displacement, and of the reaction on a
    /// face a motion moves, relative to the largest reaction force (moment)
    /// (none when the M/2 run failed).
    pub face_change: Option<f64>,
    /// Change of the open and of the slipping joint area, relative to the
    /// joints' total area (the larger of the two).
    pub area_change: Option<f64>,
    /// Why the M/2 run gave no comparison.
    pub note: Option<String>,
}

/// The automatic choice of M.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AutoHarmonics {
    /// The M chosen.
    pub chosen: u32,
    /// `solver.harmonics_tolerance`.
    pub tolerance: f64,
    /// Each M tried.
    pub steps: Vec<AutoStep>,
}

/// One step of the automatic choice of M.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AutoStep {
    /// Harmonics 0..=m.
    pub m: u32,
    /// Iterations of this step.
    pub iterations: usize,
    /// Relative change of the measured results against the previous step.
    pub change: Option<f64>,
}

/// Per cut and angle (degrees, as formatted in file names): a value.
pub type PerProfile = BTreeMap<String, BTreeMap<String, f64>>;

/// The cycles of an adaptive run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AdaptTable {
    /// `mesh.adapt.target`.
    pub target: f64,
    /// `mesh.adapt.max_cycles`.
    pub max_cycles: u32,
    /// Whether every profile met the target, confirmed by the cycle before.
    pub reached: bool,
    /// Each cycle, in order.
    pub cycles: Vec<AdaptCycle>,
}

/// One mesh of an adaptive run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AdaptCycle {
    /// 0, 1, ...
    pub cycle: usize,
    /// Nodes (joints inserted).
    pub nodes: usize,
    /// Unknowns per harmonic.
    pub dofs_per_harmonic: usize,
    /// Estimated error of each profile, relative to its max |stress|.
    pub estimated_error: PerProfile,
    /// Largest change of each profile from the cycle before (none on the first).
    pub change: Option<PerProfile>,
    /// Estimated error in the energy norm.
    pub estimated_energy_error: f64,
    /// Wall-clock seconds of the cycle.
    pub seconds: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `harmonic_check` is absent (a last iterate), `null` (a nonlinear run
    /// with M < 2) or an object; each reads back as written, and a record
    /// writes only the keys that apply.
    #[test]
    fn a_record_reads_back_as_written() {
        let check = HarmonicCheck {
            m: 4,
            m_half: 2,
            face_change: Some(1e-3),
            area_change: None,
            note: None,
        };
        for harmonic_check in [None, Some(None), Some(Some(check))] {
            let r = RunRecord {
                harmonic_check,
                iterations: Some(3),
                loading: Some(Loading::Auto),
                ..RunRecord::default()
            };
            let text = serde_json::to_string(&r).unwrap();
            assert_eq!(
                text.contains("harmonic_check"),
                r.harmonic_check.is_some(),
                "{text}"
            );
            assert_eq!(serde_json::from_str::<RunRecord>(&text).unwrap(), r, "{text}");
        }
        let last: RunRecord =
            serde_json::from_str(r#"{"converged": false, "complete": false, "error": "stalled"}"#).unwrap();
        assert!(!last.converged() && !last.complete() && last.limit().is_none());
        assert_eq!(serde_json::to_string(&RunRecord::default()).unwrap(), "{}");
    }
}
