//! Stress profiles along the cuts a-a and b-b, the common currency of the
//! accuracy study: axijoint's cut CSVs and the CalculiX peer both become
//! [`Profile`]s, and errors are measured between profiles.

/// One stress sample on a cut.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// Radius r of the sample (m).
    pub r: f64,
    /// Body the value belongs to ("pile" or "footing"); at the interface
    /// r = a both bodies report a sample.
    pub body: String,
    /// Stress component value (MPa).
    pub value: f64,
}

/// A stress profile: one cut at one angle, one component.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    /// Cut name: "a-a" (z = 0.75, sigma_z) or "b-b" (z = 0.25, sigma_r).
    pub cut: String,
    /// Angle of the meridional half-plane (deg): 0 or 180.
    pub theta_deg: f64,
    /// Component name as in axijoint's CSV header: "sigma_z", "sigma_r".
    pub component: String,
    /// Samples in order of increasing r (pile before footing at r = a).
    pub samples: Vec<Sample>,
}

impl Profile {
    /// A profile from `(body, [(r, value), ...])` groups, in that order.
    pub fn from_bodies<P: AsRef<[(f64, f64)]>>(
        cut: &str,
        theta_deg: f64,
        component: &str,
        bodies: &[(&str, P)],
    ) -> Profile {
        Profile {
            cut: cut.into(),
            theta_deg,
            component: component.into(),
            samples: bodies
                .iter()
                .flat_map(|(body, pts)| {
                    pts.as_ref().iter().map(|&(r, value)| Sample {
                        r,
                        body: (*body).to_owned(),
                        value,
                    })
                })
                .collect(),
        }
    }
}
