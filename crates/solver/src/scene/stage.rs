//! Loads in stages (`stages`): an ordered list, each stage's loads the
//! totals reached at its end, each starting from the converged state of
//! the one before; a stage may repeat a load sequence (`cyclic`).

use super::{Load, Loading, Scene, SceneError};
use serde::{Deserialize, Serialize};

/// The most stages a scene expands to (cycles times levels, summed).
pub const MAX_STAGES: usize = 10_000;

/// One stage of [`Scene::stages`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stage {
    /// Name (letters, digits, `_`, `-`, `.`), in outputs and messages.
    pub name: String,
    /// The loads at the end of the stage (totals, not increments): a load
    /// of the stage before that is not here is removed over the stage.
    #[serde(default)]
    pub loads: Vec<Load>,
    /// How the stage is stepped (`{"steps": N}` or `{"steps": "auto"}`);
    /// none: the scene's `solver.loading`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub loading: Option<Loading>,
    /// A load sequence repeated: the stage ends at each level in turn.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cyclic: Option<Cyclic>,
}

/// The loads of a stage that repeat at levels ([`Stage::cyclic`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cyclic {
    /// The loads that cycle, beside the stage's `loads` (which stay).
    pub loads: Vec<Load>,
    /// The factors on `loads` reached in turn (e.g. `[1, -1]`).
    pub levels: Vec<f64>,
    /// How many times the levels are run through.
    #[serde(default = "one")]
    pub cycles: u32,
}

fn one() -> u32 {
    1
}

/// One leg of the load path: a stage, or one level of one cycle of a
/// cyclic stage.
#[derive(Clone, Debug, PartialEq)]
pub struct Leg {
    /// Index of the stage in [`Scene::stages`].
    pub stage: usize,
    /// The stage's name.
    pub name: String,
    /// 1-based cycle and level of a cyclic stage (0, 0: none).
    pub cycle: u32,
    /// 1-based level within the cycle.
    pub level: u32,
    /// The loads at the leg's end.
    pub loads: Vec<Load>,
    /// How the leg is stepped.
    pub loading: Loading,
}

/// A leg's label for messages: `stage 'storm'` or `stage 'storm', cycle
/// 2, level 1` (`cycle` 0: not cyclic).
pub fn stage_label(name: &str, cycle: u32, level: u32) -> String {
    if cycle == 0 {
        format!("stage '{name}'")
    } else {
        format!("stage '{name}', cycle {cycle}, level {level}")
    }
}

impl Leg {
    /// A label for messages ([`stage_label`]).
    pub fn label(&self) -> String {
        stage_label(&self.name, self.cycle, self.level)
    }
}

impl Scene {
    /// The legs of the load path of a scene with stages, in order (empty
    /// without stages).
    pub fn legs(&self) -> Vec<Leg> {
        let mut out = Vec::new();
        for (k, s) in self.stages.iter().enumerate() {
            let loading = s.loading.unwrap_or(self.solver.loading);
            let Some(c) = &s.cyclic else {
                out.push(Leg {
                    stage: k,
                    name: s.name.clone(),
                    cycle: 0,
                    level: 0,
                    loads: s.loads.clone(),
                    loading,
                });
                continue;
            };
            for cycle in 1..=c.cycles {
                for (j, &f) in c.levels.iter().enumerate() {
                    let mut loads = s.loads.clone();
                    loads.extend(c.loads.iter().map(|l| l.scaled(f)));
                    out.push(Leg {
                        stage: k,
                        name: s.name.clone(),
                        cycle,
                        level: j as u32 + 1,
                        loads,
                        loading,
                    });
                }
            }
        }
        out
    }

    /// Each face loaded in some leg, with the load its motion and applied
    /// load are measured along: its first cycling load, else its first.
    pub fn staged_faces(&self) -> Vec<Load> {
        let mut faces: Vec<Load> = Vec::new();
        let cycling = self
            .stages
            .iter()
            .flat_map(|s| s.cyclic.iter().flat_map(|c| c.loads.iter()));
        let all = self.stages.iter().flat_map(|s| s.loads.iter());
        for l in cycling.chain(all) {
            if !faces.iter().any(|f| f.on() == l.on()) {
                faces.push(l.clone());
            }
        }
        faces
    }

    /// The scene with its loads at the end of stage `k`: the stage's loads
    /// in place of `loads`, no stages (for messages, keys as `loads[i]`).
    pub(crate) fn stage_scene(&self, loads: Vec<Load>) -> Scene {
        Scene {
            loads,
            stages: Vec::new(),
            ..self.clone()
        }
    }

    /// The checks of `stages` that need no mesh.
    pub(super) fn check_stages(&self) -> Result<(), SceneError> {
        if self.stages.is_empty() {
            return Ok(());
        }
        if !self.load_cases.is_empty() {
            return Err(self.invalid("stages", "give either `stages` or `load_cases`, not both"));
        }
        if self.solver.loading == Loading::OneShot {
            return Err(self.invalid(
                "solver.loading",
                "stages are stepped (the history law carries each stage's state to the next): not \"one_shot\"",
            ));
        }
        let mut legs = 0usize;
        for (k, s) in self.stages.iter().enumerate() {
            let key = |sub: &str| format!("stages[{k}].{sub}");
            let name = &s.name;
            let valid = !name.is_empty()
                && name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || "_-.".contains(c));
            if !valid {
                return Err(self.invalid(
                    key("name"),
                    format!("'{name}' is not allowed (letters, digits, _, - and .)"),
                ));
            }
            if self.stages[..k].iter().any(|t| &t.name == name) {
                return Err(self.invalid(key("name"), format!("'{name}' is used twice")));
            }
            if s.loading == Some(Loading::OneShot) {
                return Err(self.invalid(
                    key("loading"),
                    "a stage is stepped: {\"steps\": N} or {\"steps\": \"auto\"}",
                ));
            }
            let scene = self.stage_scene(s.loads.clone());
            for (i, load) in s.loads.iter().enumerate() {
                scene.check_load(i, load).map_err(|e| e.in_stage(k, "loads"))?;
            }
            legs += 1;
            if let Some(c) = &s.cyclic {
                if c.levels.is_empty() || c.levels.iter().any(|f| !f.is_finite()) {
                    return Err(self.invalid(key("cyclic.levels"), "give finite load factors, e.g. [1, -1]"));
                }
                if c.cycles == 0 {
                    return Err(self.invalid(key("cyclic.cycles"), "must be at least 1"));
                }
                if c.loads.is_empty() {
                    return Err(self.invalid(
                        key("cyclic.loads"),
                        "no load cycles: give the loads the levels scale",
                    ));
                }
                let scene = self.stage_scene(c.loads.clone());
                for (i, load) in c.loads.iter().enumerate() {
                    scene
                        .check_load(i, load)
                        .map_err(|e| e.in_stage(k, "cyclic.loads"))?;
                }
                legs = legs - 1 + (c.cycles as usize).saturating_mul(c.levels.len());
            }
        }
        if legs > MAX_STAGES {
            return Err(self.invalid(
                "stages",
                format!("{legs} stages and levels in all, more than {MAX_STAGES}: fewer cycles or levels"),
            ));
        }
        Ok(())
    }
}
