//! Loads of a scene, as the user writes them (see `docs/scene-format.md`);
//! [`crate::loads`] turns them into nodal forces per harmonic.

use super::Fix;
use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// Fourier family of a load of harmonic m >= 1 (docs/theory.md section 1).
///
/// | family | t_r, t_z | t_theta |
/// |---|---|---|
/// | symmetric | `T cos m.th` | `T sin m.th` |
/// | antisymmetric | `T sin m.th` | `-T cos m.th` |
///
/// Harmonic 0 is symmetric only; its t_theta is the plain (torsional)
/// traction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Family {
    /// Symmetric about theta = 0.
    #[default]
    Symmetric,
    /// Antisymmetric about theta = 0.
    Antisymmetric,
}

/// A traction amplitude linear in (r, z): `c + r * r_coef + z * z_coef`.
///
/// Written as a number (a constant) or `{"c": c0, "r": cr, "z": cz}`
/// (each key optional, default 0).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Linear {
    /// Constant part.
    pub c: f64,
    /// Coefficient of r.
    pub r: f64,
    /// Coefficient of z.
    pub z: f64,
}

impl Linear {
    /// The value at (r, z).
    pub fn at(&self, r: f64, z: f64) -> f64 {
        self.c + self.r * r + self.z * z
    }

    /// True if every coefficient is finite.
    pub fn is_finite(&self) -> bool {
        self.c.is_finite() && self.r.is_finite() && self.z.is_finite()
    }
}

/// The object form of [`Linear`].
#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct LinearMap {
    #[serde(default)]
    c: f64,
    #[serde(default)]
    r: f64,
    #[serde(default)]
    z: f64,
}

impl<'de> Deserialize<'de> for Linear {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct LinearVisitor;
        impl<'de> Visitor<'de> for LinearVisitor {
            type Value = Linear;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or an object {\"c\": .., \"r\": .., \"z\": ..}")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Linear, E> {
                Ok(Linear {
                    c: v,
                    ..Linear::default()
                })
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Linear, E> {
                self.visit_f64(v as f64)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Linear, E> {
                self.visit_f64(v as f64)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Linear, A::Error> {
                let m = LinearMap::deserialize(de::value::MapAccessDeserializer::new(map))?;
                Ok(Linear {
                    c: m.c,
                    r: m.r,
                    z: m.z,
                })
            }
        }
        d.deserialize_any(LinearVisitor)
    }
}

impl Serialize for Linear {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        if self.r == 0.0 && self.z == 0.0 {
            self.c.serialize(s)
        } else {
            LinearMap {
                c: self.c,
                r: self.r,
                z: self.z,
            }
            .serialize(s)
        }
    }
}

/// A traction of one harmonic and family on a physical curve, in global
/// (r, z, theta) components (force / length^2).
#[derive(Clone, Debug, PartialEq)]
pub struct TractionLoad {
    /// Physical curve.
    pub on: String,
    /// Harmonic m.
    pub harmonic: u32,
    /// Family (m >= 1; harmonic 0 is symmetric).
    pub family: Family,
    /// Amplitudes `(t_r, t_z, t_theta)`.
    pub t: [Linear; 3],
}

/// Section resultants on a flat end face, distributed as beam theory does.
///
/// The force acts at the point `(0, 0, at_z)` on the axis; the moment
/// about the face centre `(0, 0, z_f)` is `(0, 0, at_z - z_f) x force +
/// (moment[0], moment[1], 0)`, and `torque` is about the z axis. See
/// [`crate::loads`] for the distribution.
#[derive(Clone, Debug, PartialEq)]
pub struct ResultantLoad {
    /// Physical curve: a flat face perpendicular to the axis.
    pub on: String,
    /// `(Fx, Fy, Fz)` (force units).
    pub force: [f64; 3],
    /// z of the point of application on the axis; `None`: the face's z.
    pub at_z: Option<f64>,
    /// Torque about +z (force x length).
    pub torque: f64,
    /// Extra moment `(Mx, My)` about the face centre (force x length).
    pub moment: [f64; 2],
}

/// A face moved as a rigid body (prescribed displacements): every node of
/// the curve gets `displacement + rotation x (x - (0, 0, z_c))`, `z_c` the
/// face's mean z or `at_z`. The face is held in the components `hold`
/// (every one by default), free in the others; its reaction is the load it
/// takes. Harmonics 0 and 1 only.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionLoad {
    /// Physical curve.
    pub on: String,
    /// `(ux, uy, uz)` (length).
    pub displacement: [f64; 3],
    /// `(rx, ry, rz)` (radians, small).
    pub rotation: [f64; 3],
    /// z of the centre of rotation on the axis; `None`: the face's mean z.
    pub at_z: Option<f64>,
    /// The components (r, z, theta) the face is held in, in every harmonic:
    /// the motion must not move it in the others, where other loads may
    /// act on it (e.g. a head twisted with its axial force given).
    pub hold: Fix,
}

/// A ring line load at a physical point (force per unit circumferential
/// length), one harmonic and family.
#[derive(Clone, Debug, PartialEq)]
pub struct RingLoad {
    /// Physical point (r > 0).
    pub on: String,
    /// Harmonic m.
    pub harmonic: u32,
    /// Family.
    pub family: Family,
    /// Amplitudes `(f_r, f_z, f_theta)`.
    pub f: [f64; 3],
}

/// A point force at a physical point on the axis r = 0.
#[derive(Clone, Debug, PartialEq)]
pub struct PointLoad {
    /// Physical point (r = 0).
    pub on: String,
    /// `(Fx, Fy, Fz)` (force units).
    pub force: [f64; 3],
}

/// One load of a scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "LoadSpec", into = "LoadSpec")]
pub enum Load {
    /// `"type": "traction"`.
    Traction(TractionLoad),
    /// `"type": "resultant"`.
    Resultant(ResultantLoad),
    /// `"type": "ring"`.
    Ring(RingLoad),
    /// `"type": "point"`.
    Point(PointLoad),
    /// `"type": "motion"`: prescribed displacements of a face.
    Motion(MotionLoad),
}

impl Load {
    /// The physical name the load acts on.
    pub fn on(&self) -> &str {
        match self {
            Load::Traction(l) => &l.on,
            Load::Resultant(l) => &l.on,
            Load::Ring(l) => &l.on,
            Load::Point(l) => &l.on,
            Load::Motion(l) => &l.on,
        }
    }

    /// The load times `f` (forces, moments, torques and tractions; not
    /// where they act).
    pub fn scaled(&self, f: f64) -> Load {
        let mut out = self.clone();
        let lin = |l: &mut Linear| {
            l.c *= f;
            l.r *= f;
            l.z *= f;
        };
        match &mut out {
            Load::Traction(l) => l.t.iter_mut().for_each(lin),
            Load::Resultant(l) => {
                l.force.iter_mut().for_each(|v| *v *= f);
                l.moment.iter_mut().for_each(|v| *v *= f);
                l.torque *= f;
            }
            Load::Ring(l) => l.f.iter_mut().for_each(|v| *v *= f),
            Load::Point(l) => l.force.iter_mut().for_each(|v| *v *= f),
            Load::Motion(l) => {
                l.displacement.iter_mut().for_each(|v| *v *= f);
                l.rotation.iter_mut().for_each(|v| *v *= f);
            }
        }
        out
    }

    /// The highest harmonic with a non-zero part.
    pub fn max_harmonic(&self) -> u32 {
        match self {
            Load::Traction(l) => l.harmonic,
            Load::Ring(l) => l.harmonic,
            Load::Resultant(l) => {
                let lateral = l.force[0] != 0.0 || l.force[1] != 0.0;
                let bending = l.moment != [0.0, 0.0];
                u32::from(lateral || bending)
            }
            Load::Point(l) => u32::from(l.force[0] != 0.0 || l.force[1] != 0.0),
            Load::Motion(l) => {
                let [ux, uy, _] = l.displacement;
                let [rx, ry, _] = l.rotation;
                u32::from(ux != 0.0 || uy != 0.0 || rx != 0.0 || ry != 0.0)
            }
        }
    }
}

/// The `type` key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
enum LoadType {
    Traction,
    Resultant,
    Ring,
    Point,
    Motion,
}

/// A load as written: one flat object for every type (so that serde's key
/// paths reach each value, e.g. `loads[1].force`), checked for keys of the
/// wrong type when turned into [`Load`].
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LoadSpec {
    #[serde(rename = "type")]
    kind: Option<LoadType>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    on: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    harmonic: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    family: Option<Family>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    t_r: Option<Linear>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    t_z: Option<Linear>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    t_theta: Option<Linear>,
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "force_list"
    )]
    force: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    at_z: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    torque: Option<f64>,
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "moment_list"
    )]
    moment: Option<[f64; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    f_r: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    f_z: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    f_theta: Option<f64>,
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "displacement_list"
    )]
    displacement: Option<[f64; 3]>,
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "rotation_list"
    )]
    rotation: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    hold: Option<Fix>,
}

/// A list of exactly `N` numbers, its length said in words otherwise.
fn list<'de, D: serde::Deserializer<'de>, const N: usize>(
    d: D,
    what: &str,
) -> Result<Option<[f64; N]>, D::Error> {
    let v: Vec<f64> = Deserialize::deserialize(d)?;
    <[f64; N]>::try_from(v.as_slice())
        .map(Some)
        .map_err(|_| serde::de::Error::custom(format!("{} numbers given, give {what}", v.len())))
}

fn force_list<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<[f64; 3]>, D::Error> {
    list(d, "three: [Fx, Fy, Fz] (Cartesian, x at theta = 0)")
}

fn displacement_list<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<[f64; 3]>, D::Error> {
    list(d, "three: [ux, uy, uz] (Cartesian, x at theta = 0)")
}

fn rotation_list<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<[f64; 3]>, D::Error> {
    list(d, "three: [rx, ry, rz] (radians about x, y and the axis)")
}

fn moment_list<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
    list(d, "two: [Mx, My] (the moment about z is `torque`)")
}

impl LoadSpec {
    /// Names of the keys present, in declaration order (`type` and `on` left out).
    fn present(&self) -> Vec<&'static str> {
        [
            ("harmonic", self.harmonic.is_some()),
            ("family", self.family.is_some()),
            ("t_r", self.t_r.is_some()),
            ("t_z", self.t_z.is_some()),
            ("t_theta", self.t_theta.is_some()),
            ("force", self.force.is_some()),
            ("at_z", self.at_z.is_some()),
            ("torque", self.torque.is_some()),
            ("moment", self.moment.is_some()),
            ("f_r", self.f_r.is_some()),
            ("f_z", self.f_z.is_some()),
            ("f_theta", self.f_theta.is_some()),
            ("displacement", self.displacement.is_some()),
            ("rotation", self.rotation.is_some()),
            ("hold", self.hold.is_some()),
        ]
        .into_iter()
        .filter(|(_, p)| *p)
        .map(|(k, _)| k)
        .collect()
    }
}

impl TryFrom<LoadSpec> for Load {
    type Error = String;
    fn try_from(s: LoadSpec) -> Result<Self, String> {
        let kind = s
            .kind
            .ok_or("missing field `type` (traction, resultant, ring, point or motion)")?;
        let (name, allowed): (&str, &[&str]) = match kind {
            LoadType::Traction => ("traction", &["harmonic", "family", "t_r", "t_z", "t_theta"]),
            LoadType::Resultant => ("resultant", &["force", "at_z", "torque", "moment"]),
            LoadType::Ring => ("ring", &["harmonic", "family", "f_r", "f_z", "f_theta"]),
            LoadType::Point => ("point", &["force"]),
            LoadType::Motion => ("motion", &["displacement", "rotation", "at_z", "hold"]),
        };
        if let Some(key) = s.present().into_iter().find(|k| !allowed.contains(k)) {
            return Err(format!(
                "key `{key}` does not belong to a {name} load (it takes: type, on, {})",
                allowed.join(", ")
            ));
        }
        let on =
            s.on.clone()
                .ok_or_else(|| format!("missing field `on` (the physical name a {name} load acts on)"))?;
        let harmonic = || {
            s.harmonic
                .ok_or_else(|| format!("missing field `harmonic` (a {name} load is given per harmonic)"))
        };
        Ok(match kind {
            LoadType::Traction => Load::Traction(TractionLoad {
                on,
                harmonic: harmonic()?,
                family: s.family.unwrap_or_default(),
                t: [
                    s.t_r.unwrap_or_default(),
                    s.t_z.unwrap_or_default(),
                    s.t_theta.unwrap_or_default(),
                ],
            }),
            LoadType::Resultant => Load::Resultant(ResultantLoad {
                on,
                force: s.force.unwrap_or_default(),
                at_z: s.at_z,
                torque: s.torque.unwrap_or_default(),
                moment: s.moment.unwrap_or_default(),
            }),
            LoadType::Ring => Load::Ring(RingLoad {
                on,
                harmonic: harmonic()?,
                family: s.family.unwrap_or_default(),
                f: [
                    s.f_r.unwrap_or_default(),
                    s.f_z.unwrap_or_default(),
                    s.f_theta.unwrap_or_default(),
                ],
            }),
            LoadType::Point => Load::Point(PointLoad {
                on,
                force: s.force.unwrap_or_default(),
            }),
            LoadType::Motion => Load::Motion(MotionLoad {
                on,
                displacement: s.displacement.unwrap_or_default(),
                rotation: s.rotation.unwrap_or_default(),
                at_z: s.at_z,
                hold: s.hold.unwrap_or(Fix::ALL),
            }),
        })
    }
}

impl From<Load> for LoadSpec {
    fn from(load: Load) -> Self {
        match load {
            Load::Traction(l) => LoadSpec {
                kind: Some(LoadType::Traction),
                on: Some(l.on),
                harmonic: Some(l.harmonic),
                family: Some(l.family),
                t_r: Some(l.t[0]),
                t_z: Some(l.t[1]),
                t_theta: Some(l.t[2]),
                ..LoadSpec::default()
            },
            Load::Resultant(l) => LoadSpec {
                kind: Some(LoadType::Resultant),
                on: Some(l.on),
                force: Some(l.force),
                at_z: l.at_z,
                torque: Some(l.torque),
                moment: Some(l.moment),
                ..LoadSpec::default()
            },
            Load::Ring(l) => LoadSpec {
                kind: Some(LoadType::Ring),
                on: Some(l.on),
                harmonic: Some(l.harmonic),
                family: Some(l.family),
                f_r: Some(l.f[0]),
                f_z: Some(l.f[1]),
                f_theta: Some(l.f[2]),
                ..LoadSpec::default()
            },
            Load::Point(l) => LoadSpec {
                kind: Some(LoadType::Point),
                on: Some(l.on),
                force: Some(l.force),
                ..LoadSpec::default()
            },
            Load::Motion(l) => LoadSpec {
                kind: Some(LoadType::Motion),
                on: Some(l.on),
                displacement: Some(l.displacement),
                rotation: Some(l.rotation),
                at_z: l.at_z,
                hold: (l.hold != Fix::ALL).then_some(l.hold),
                ..LoadSpec::default()
            },
        }
    }
}
