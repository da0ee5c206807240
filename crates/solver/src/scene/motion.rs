//! Faces moved as rigid bodies (`"type": "motion"` loads): held in every
//! component by the model, their prescribed displacements the load.

use super::{Fix, Load, Scene, SceneError, Support};

impl Scene {
    /// Every load of the scene with its key path: `loads`, or (with
    /// stages, whose last leg's loads `loads` repeats) every stage's and
    /// cyclic stage's.
    fn every_load(&self) -> impl Iterator<Item = (String, &Load)> {
        let plain = self
            .loads
            .iter()
            .enumerate()
            .filter(|_| self.stages.is_empty())
            .map(|(i, l)| (format!("loads[{i}]"), l));
        let staged = self.stages.iter().enumerate().flat_map(|(k, s)| {
            let own = s
                .loads
                .iter()
                .enumerate()
                .map(move |(i, l)| (format!("stages[{k}].loads[{i}]"), l));
            let cyc = s.cyclic.iter().flat_map(move |c| {
                c.loads
                    .iter()
                    .enumerate()
                    .map(move |(i, l)| (format!("stages[{k}].cyclic.loads[{i}]"), l))
            });
            own.chain(cyc)
        });
        plain.chain(staged)
    }

    /// The faces a `motion` load moves, in order of first mention.
    pub fn motion_faces(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for (_, l) in self.every_load() {
            if let Load::Motion(m) = l {
                if !out.contains(&m.on) {
                    out.push(m.on.clone());
                }
            }
        }
        out
    }

    /// The supports and the faces moved by `motion` loads (held in every
    /// component): what the model fixes and what reports reactions.
    pub fn all_supports(&self) -> Vec<Support> {
        let mut out = self.supports.clone();
        out.extend(
            self.motion_faces()
                .into_iter()
                .map(|on| Support { on, fix: Fix::ALL }),
        );
        out
    }

    /// A face a `motion` load moves carries no other load and is no
    /// support; load cases take no motion (each case would need its own
    /// model).
    pub(super) fn check_motions(&self) -> Result<(), SceneError> {
        let faces = self.motion_faces();
        if faces.is_empty() {
            return Ok(());
        }
        if self
            .load_cases
            .iter()
            .any(|c| c.loads.iter().any(|l| matches!(l, Load::Motion(_))))
        {
            return Err(self.invalid(
                "load_cases",
                "a `motion` load holds its face in the model: give it in `loads` or `stages`, not in load cases",
            ));
        }
        for (key, l) in self.every_load() {
            if !matches!(l, Load::Motion(_)) && faces.iter().any(|f| f == l.on()) {
                return Err(self.invalid(
                    format!("{key}.on"),
                    format!(
                        "'{}' is moved by a `motion` load elsewhere in the scene: a moved face takes no other load (its reaction is the load it takes)",
                        l.on()
                    ),
                ));
            }
        }
        for (i, s) in self.supports.iter().enumerate() {
            if faces.contains(&s.on) {
                return Err(self.invalid(
                    format!("supports[{i}].on"),
                    format!(
                        "'{}' is moved by a `motion` load: a support holds it at zero; give one or the other",
                        s.on
                    ),
                ));
            }
        }
        Ok(())
    }
}
