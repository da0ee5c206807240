//! Faces moved as rigid bodies (`"type": "motion"` loads): held by the
//! model in the components `hold` (every one by default), their prescribed
//! displacements the load.

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

    /// The components a face moved by `motion` loads is held in (its first
    /// motion's `hold`; the scene's checks make them agree).
    pub fn motion_hold(&self, face: &str) -> Fix {
        self.every_load()
            .find_map(|(_, l)| match l {
                Load::Motion(m) if m.on == face => Some(m.hold),
                _ => None,
            })
            .unwrap_or(Fix::ALL)
    }

    /// The supports and the faces moved by `motion` loads (held in the
    /// components of their `hold`): what the model fixes and what reports
    /// reactions.
    pub fn all_supports(&self) -> Vec<Support> {
        let mut out = self.supports.clone();
        out.extend(self.motion_faces().into_iter().map(|on| Support {
            fix: self.motion_hold(&on),
            on,
        }));
        out
    }

    /// A face a `motion` load moves is no support and carries no other load
    /// but in the components its `hold` leaves free; its motions agree on
    /// `hold`; load cases take no motion (each case would need its own
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
            let hold = self.motion_hold(l.on());
            if let Load::Motion(m) = l {
                if m.hold.is_empty() {
                    return Err(self.invalid(
                        format!("{key}.hold"),
                        "a `motion` load holds its face in at least one component (r, z or theta)",
                    ));
                }
                if m.hold != hold {
                    return Err(self.invalid(
                        format!("{key}.hold"),
                        format!(
                            "'{}' is held in {:?} by an earlier `motion` load: every motion of a face holds the same components (the model is built once)",
                            m.on,
                            hold.names()
                        ),
                    ));
                }
                continue;
            }
            if !faces.iter().any(|f| f == l.on()) {
                continue;
            }
            if let Some(held) = held_components(l, hold) {
                return Err(self.invalid(
                    format!("{key}.on"),
                    format!(
                        "'{}' is held in {held} by a `motion` load elsewhere in the scene: a load on a moved face may act only in the components its `hold` leaves free (its reaction is the load it takes)",
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

/// The held components (of `hold`) a load on a moved face would act in, or
/// `None` if it acts only in free ones. A resultant's axial force and
/// moments act in z, its torque in theta, its sideways force in r and
/// theta; a traction in its non-zero components; a ring or point load
/// always counts as held.
fn held_components(load: &Load, hold: Fix) -> Option<&'static str> {
    let needs = match load {
        Load::Resultant(l) => Fix {
            r: l.force[0] != 0.0 || l.force[1] != 0.0,
            z: l.force[2] != 0.0 || l.moment != [0.0, 0.0],
            theta: l.torque != 0.0 || l.force[0] != 0.0 || l.force[1] != 0.0,
        },
        Load::Traction(l) => {
            let on = |c: usize| l.t[c] != Default::default();
            Fix {
                r: on(0),
                z: on(1),
                theta: on(2),
            }
        }
        _ => Fix::ALL,
    };
    [
        (needs.r && hold.r, "r"),
        (needs.z && hold.z, "z"),
        (needs.theta && hold.theta, "theta"),
    ]
    .into_iter()
    .find(|(both, _)| *both)
    .map(|(_, name)| name)
}
