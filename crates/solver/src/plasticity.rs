//! Elastic-perfectly-plastic stress-point algorithms (return mapping) for
//! soil: Tresca, von Mises and Mohr-Coulomb with a tension cut-off.
//!
//! Stresses `(s_r, s_z, s_th, t_rz, t_rth, t_zth)` are plain components,
//! strains engineering shears, tension positive (as in
//! [`crate::material`]). Given the elastic trial stress `D (e - e_p)`,
//! [`return_map`] gives the admissible stress, the plastic strain increment
//! `D^-1 (trial - stress)` and the consistent tangent `d stress / d e`.
//!
//! Tresca and Mohr-Coulomb return in principal space (de Souza Neto, Peric
//! and Owen, Computational Methods for Plasticity, ch. 8). With the sorted
//! trial principal stresses `s1 >= s2 >= s3`, the criterion is a set of
//! planes `f_k = a_k . s - b_k <= 0` and the flow directions `n_k`:
//!
//! ```text
//! main     f = (s1 - s3)/2 + (s1 + s3)/2 sin(phi) - c cos(phi)   n = ((1 + sin psi), 0, -(1 - sin psi))/2
//! s2 = s3  the main plane with s2 for s3 (active with it on the edge s2 = s3)
//! s1 = s2  the main plane with s2 for s1 (active with it on the edge s1 = s2)
//! cut-off  f = s_i - t, i = 1, 2, 3                             n = a (associated)
//! ```
//!
//! The return is closed form: with the active planes `A`, the multipliers
//! solve `(a_k . D n_l) dgamma_l = f_k(trial)` (perfect plasticity) and
//! `s = trial - D n_l dgamma_l`. The active set is the first, fewest planes
//! first, whose multipliers are >= 0, whose stress satisfies every plane and
//! keeps the trial's order (three planes give a point, the tangent there is
//! 0). The stress is rebuilt with the trial's eigenvectors (isotropy).
//!
//! For phi > 0 the cut-off is clamped to the apex `c / tan(phi)`, so there is
//! always one: its associated flow returns to the apex the trial states
//! beyond it that the non-associated flow (`psi < phi`) cannot reach (e.g.
//! `psi = 0` under hydrostatic tension). A cut-off at the apex meets the
//! Mohr-Coulomb planes only there: such returns are [`Region::Apex`].
//!
//! von Mises is the radial return of the deviator to `sqrt(J2) = c_u`.
//!
//! The tangent of a principal-space return is the derivative of an
//! isotropic tensor function: in the trial's eigenbasis,
//! `d s_ii = J_ij d trial_jj` (`J = d s_i / d trial_j` of the return in
//! principal space) and `d s_ij = (s_i - s_j) / (trial_i - trial_j) d trial_ij`
//! for `i != j` (the eigenvector spin); for coincident trial eigenvalues the
//! quotient is its limit, the mean of `J_ii - J_ij` and `J_jj - J_ji`. The
//! tangent is not symmetric when `psi < phi`.

use crate::material::Elastic;
use crate::short::short;
use nalgebra::{Matrix3, SMatrix, SymmetricEigen, Vector3};

/// Why a yield criterion was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlasticityError {
    /// c_u is negative or not finite.
    #[error("undrained strength c_u = {} is not allowed: it must be a finite number >= 0", short(.c_u))]
    UndrainedStrength {
        /// The value given.
        c_u: f64,
    },
    /// The cohesion is negative or not finite.
    #[error("cohesion c = {} is not allowed: it must be a finite number >= 0", short(.cohesion))]
    Cohesion {
        /// The value given.
        cohesion: f64,
    },
    /// phi is outside [0, 90) degrees.
    #[error("friction angle phi = {} deg is not allowed: it must lie in [0, 90) deg", short(.friction_deg))]
    Friction {
        /// The value given (degrees).
        friction_deg: f64,
    },
    /// psi is outside [0, phi].
    #[error("dilation angle psi = {} deg is not allowed: it must lie in [0, phi] = [0, {}] deg", short(.dilation_deg), short(.friction_deg))]
    Dilation {
        /// The value given (degrees).
        dilation_deg: f64,
        /// The friction angle (degrees).
        friction_deg: f64,
    },
    /// c = 0 and phi = 0: no strength at all.
    #[error(
        "cohesion c = 0 with friction angle phi = 0 deg is not allowed: the material would have no strength"
    )]
    NoStrength,
    /// The tension cut-off is negative or NaN.
    #[error("tension cut-off t = {} is not allowed: it must be >= 0 (inf for none)", short(.tension_cutoff))]
    TensionCutoff {
        /// The value given.
        tension_cutoff: f64,
    },
}

/// A yield criterion of a perfectly plastic soil.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum YieldCriterion {
    /// Tresca, `(s1 - s3) / 2 <= c_u`: undrained strength `c_u` (stress);
    /// the caller evaluates `c_u(z)` itself.
    Tresca {
        /// Undrained shear strength c_u (stress), >= 0.
        c_u: f64,
    },
    /// von Mises, `sqrt(J2) <= c_u`: the same `c_u` as [`YieldCriterion::Tresca`]
    /// in pure shear (plane strain at the critical state).
    VonMises {
        /// Undrained shear strength c_u (stress), >= 0.
        c_u: f64,
    },
    /// Mohr-Coulomb `(s1 - s3)/2 + (s1 + s3)/2 sin(phi) <= c cos(phi)` with
    /// the plastic potential of dilation angle `psi` and the tension cut-off
    /// `s1 <= t`.
    MohrCoulomb {
        /// Cohesion c (stress), >= 0.
        cohesion: f64,
        /// Friction angle phi in degrees, 0 <= phi < 90.
        friction_deg: f64,
        /// Dilation angle psi in degrees, 0 <= psi <= phi (psi = phi:
        /// associated flow).
        dilation_deg: f64,
        /// Tension cut-off t (stress), >= 0; `f64::INFINITY` for none. For
        /// phi > 0 a t above the apex `c / tan(phi)` acts as the apex.
        tension_cutoff: f64,
    },
}

impl YieldCriterion {
    /// Checks the parameters (see [`PlasticityError`]).
    ///
    /// ```
    /// use axijoint_solver::plasticity::YieldCriterion;
    /// let sand = YieldCriterion::MohrCoulomb {
    ///     cohesion: 0.0,
    ///     friction_deg: 35.0,
    ///     dilation_deg: 5.0,
    ///     tension_cutoff: 0.0,
    /// };
    /// assert!(sand.validate().is_ok());
    /// assert!(YieldCriterion::Tresca { c_u: -1.0 }.validate().is_err());
    /// ```
    pub fn validate(&self) -> Result<(), PlasticityError> {
        match *self {
            YieldCriterion::Tresca { c_u } | YieldCriterion::VonMises { c_u } => {
                if !(c_u.is_finite() && c_u >= 0.0) {
                    return Err(PlasticityError::UndrainedStrength { c_u });
                }
            }
            YieldCriterion::MohrCoulomb {
                cohesion,
                friction_deg,
                dilation_deg,
                tension_cutoff,
            } => {
                if !(cohesion.is_finite() && cohesion >= 0.0) {
                    return Err(PlasticityError::Cohesion { cohesion });
                }
                if !(0.0..90.0).contains(&friction_deg) {
                    return Err(PlasticityError::Friction { friction_deg });
                }
                if !(0.0..=friction_deg).contains(&dilation_deg) {
                    return Err(PlasticityError::Dilation {
                        dilation_deg,
                        friction_deg,
                    });
                }
                if cohesion == 0.0 && friction_deg == 0.0 {
                    return Err(PlasticityError::NoStrength);
                }
                if tension_cutoff.is_nan() || tension_cutoff < 0.0 {
                    return Err(PlasticityError::TensionCutoff { tension_cutoff });
                }
            }
        }
        Ok(())
    }
}

/// Where a trial stress returned to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Region {
    /// Inside the surface: the trial stress is admissible.
    Elastic,
    /// One Mohr-Coulomb (Tresca) plane, or the von Mises surface.
    Face,
    /// Two Mohr-Coulomb planes: `s1 = s2` or `s2 = s3`.
    Edge,
    /// The Mohr-Coulomb apex `s1 = s2 = s3 = c / tan(phi)`.
    Apex,
    /// The tension cut-off `s1 = t`.
    Cutoff,
    /// Two cut-off planes: `s1 = s2 = t`.
    CutoffEdge,
    /// Three cut-off planes: `s1 = s2 = s3 = t`.
    CutoffApex,
    /// A Mohr-Coulomb plane and the cut-off `s1 = t` (a line).
    FaceCutoff,
    /// Mohr-Coulomb and cut-off planes meeting at a point: `(t, s, s)` or
    /// `(t, t, s)`.
    Corner,
}

impl Region {
    /// Short name.
    pub fn name(self) -> &'static str {
        match self {
            Region::Elastic => "elastic",
            Region::Face => "face",
            Region::Edge => "edge",
            Region::Apex => "apex",
            Region::Cutoff => "cutoff",
            Region::CutoffEdge => "cutoff_edge",
            Region::CutoffApex => "cutoff_apex",
            Region::FaceCutoff => "face_cutoff",
            Region::Corner => "corner",
        }
    }
}

/// The result of [`return_map`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Returned {
    /// The admissible stress.
    pub stress: [f64; 6],
    /// Where the trial stress returned to.
    pub region: Region,
    /// Plastic strain increment `D^-1 (trial - stress)` (engineering shears).
    pub plastic_strain: [f64; 6],
    /// Consistent tangent `d stress / d strain` (engineering shear strains,
    /// the trial being `D strain`); `D` when [`Region::Elastic`].
    pub tangent: [[f64; 6]; 6],
}

/// Relative tolerance of the yield and order checks (times the stress scale).
const TOL: f64 = 1e-11;

/// Trial eigenvalues closer than this (times the stress scale) count as
/// coincident in the tangent.
const COINCIDENT: f64 = 1e-8;

/// The admissible stress for the elastic `trial` stress, its region, plastic
/// strain and consistent tangent. `criterion` is assumed valid
/// ([`YieldCriterion::validate`]); a trial that is not finite gives NaN
/// stresses.
///
/// ```
/// use axijoint_solver::material::Elastic;
/// use axijoint_solver::plasticity::{return_map, Region, YieldCriterion};
/// let clay = Elastic { e: 1.0e4, nu: 0.3 };
/// // Pure shear t_rz = 80 against c_u = 50 returns to t_rz = 50.
/// let r = return_map(&clay, &YieldCriterion::Tresca { c_u: 50.0 }, [0.0, 0.0, 0.0, 80.0, 0.0, 0.0]);
/// assert_eq!(r.region, Region::Face);
/// assert!((r.stress[3] - 50.0).abs() < 1e-10);
/// ```
pub fn return_map(elastic: &Elastic, criterion: &YieldCriterion, trial: [f64; 6]) -> Returned {
    let d = elastic.d_matrix();
    if surely_elastic(criterion, &trial) {
        return elastic_result(&d, trial);
    }
    match Planes::new(criterion) {
        None => {
            let YieldCriterion::VonMises { c_u } = *criterion else {
                unreachable!("only von Mises has no planes")
            };
            von_mises_return(elastic, &d, c_u, trial)
        }
        Some(planes) => principal_return(elastic, &d, &planes, trial),
    }
}

/// The yield function at `stress`, in stress units: <= 0 admissible.
///
/// Tresca `(s1 - s3)/2 - c_u`; von Mises `sqrt(J2) - c_u`; Mohr-Coulomb the
/// larger of `(s1 - s3)/2 + (s1 + s3)/2 sin(phi) - c cos(phi)` and
/// `s1 - t` (t clamped to the apex).
pub fn yield_value(criterion: &YieldCriterion, stress: [f64; 6]) -> f64 {
    match Planes::new(criterion) {
        None => {
            let YieldCriterion::VonMises { c_u } = *criterion else {
                unreachable!("only von Mises has no planes")
            };
            sqrt_j2(&stress) - c_u
        }
        Some(planes) => {
            let (x, _) = principal(&stress);
            planes.max_value(&x)
        }
    }
}

/// Index pairs of the 6-vector components in the 3 x 3 tensor (r, z, theta).
const PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];

/// The symmetric tensor of a stress 6-vector.
fn tensor(v: &[f64; 6]) -> Matrix3<f64> {
    let mut t = Matrix3::zeros();
    for (k, &(i, j)) in PAIRS.iter().enumerate() {
        t[(i, j)] = v[k];
        t[(j, i)] = v[k];
    }
    t
}

/// The stress 6-vector of a symmetric tensor (mean of the off-diagonal pair).
fn vector(t: &Matrix3<f64>) -> [f64; 6] {
    PAIRS.map(|(i, j)| 0.5 * (t[(i, j)] + t[(j, i)]))
}

/// Principal values sorted `x1 >= x2 >= x3` and the matching unit
/// eigenvectors as columns.
fn principal(v: &[f64; 6]) -> ([f64; 3], Matrix3<f64>) {
    let eig = SymmetricEigen::new(tensor(v));
    let mut order = [0, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let x = order.map(|k| eig.eigenvalues[k]);
    let q = Matrix3::from_columns(&order.map(|k| eig.eigenvectors.column(k).into_owned()));
    (x, q)
}

/// `sqrt(J2)` of a stress 6-vector.
fn sqrt_j2(s: &[f64; 6]) -> f64 {
    let p = (s[0] + s[1] + s[2]) / 3.0;
    let dev2 = (s[0] - p).powi(2) + (s[1] - p).powi(2) + (s[2] - p).powi(2);
    (0.5 * dev2 + s[3] * s[3] + s[4] * s[4] + s[5] * s[5]).sqrt()
}

/// `D^-1 s` (engineering shear strains).
fn compliance(elastic: &Elastic, s: &[f64; 6]) -> [f64; 6] {
    let (e, nu, g) = (elastic.e, elastic.nu, elastic.shear_modulus());
    let tr = s[0] + s[1] + s[2];
    let normal = |x: f64| ((1.0 + nu) * x - nu * tr) / e;
    [
        normal(s[0]),
        normal(s[1]),
        normal(s[2]),
        s[3] / g,
        s[4] / g,
        s[5] / g,
    ]
}

fn to_array(m: &SMatrix<f64, 6, 6>) -> [[f64; 6]; 6] {
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}

/// Whether `trial` lies inside the surface by a margin, from its
/// invariants alone (no principal stresses: most points of a body are
/// elastic): with `p` the mean stress and `q = sqrt(J2)`, `(s1 - s3) / 2 <=
/// q`, `(s1 + s3) / 2 <= p + q / sqrt(3)` and `s1 <= p + 2 q / sqrt(3)`.
fn surely_elastic(criterion: &YieldCriterion, trial: &[f64; 6]) -> bool {
    const MARGIN: f64 = 1e-6;
    let p = (trial[0] + trial[1] + trial[2]) / 3.0;
    let dev = [trial[0] - p, trial[1] - p, trial[2] - p];
    let j2 = 0.5 * dev.iter().map(|v| v * v).sum::<f64>() + trial[3..].iter().map(|v| v * v).sum::<f64>();
    let q = j2.sqrt();
    let r3 = 3f64.sqrt();
    match *criterion {
        YieldCriterion::Tresca { c_u } => q < c_u * (1.0 - MARGIN),
        YieldCriterion::VonMises { .. } => false,
        YieldCriterion::MohrCoulomb {
            cohesion,
            friction_deg,
            tension_cutoff,
            ..
        } => {
            let (sin, cos) = friction_deg.to_radians().sin_cos();
            let scale = cohesion.max(q).max(p.abs());
            let face = q + (p + q / r3) * sin - cohesion * cos < -MARGIN * scale;
            let cutoff = tension_cutoff.is_infinite() || p + 2.0 * q / r3 < tension_cutoff - MARGIN * scale;
            face && cutoff
        }
    }
}

fn elastic_result(d: &SMatrix<f64, 6, 6>, trial: [f64; 6]) -> Returned {
    Returned {
        stress: trial,
        region: Region::Elastic,
        plastic_strain: [0.0; 6],
        tangent: to_array(d),
    }
}

/// Radial return of the deviator to `sqrt(J2) = c_u`; the tangent
/// `D - 2G (1 - beta) I_dev - 2G beta N N` with `beta = c_u / sqrt(J2_trial)`
/// and `N` the unit trial deviator.
fn von_mises_return(elastic: &Elastic, d: &SMatrix<f64, 6, 6>, c_u: f64, trial: [f64; 6]) -> Returned {
    let q = sqrt_j2(&trial);
    let scale = trial.iter().fold(c_u, |m, v| m.max(v.abs()));
    if q - c_u <= TOL * scale {
        return elastic_result(d, trial);
    }
    let beta = c_u / q;
    let p = (trial[0] + trial[1] + trial[2]) / 3.0;
    let mut dev = trial;
    for v in &mut dev[..3] {
        *v -= p;
    }
    let mut stress = dev.map(|v| beta * v);
    for v in &mut stress[..3] {
        *v += p;
    }
    // The unit deviator in tensor components (|N| = 1 with both shear halves).
    let norm = std::f64::consts::SQRT_2 * q;
    let n = dev.map(|v| v / norm);
    let g2 = 2.0 * elastic.shear_modulus();
    let mut c = *d;
    for i in 0..6 {
        for j in 0..6 {
            let i_dev = match (i < 3, j < 3) {
                (true, true) => f64::from(u8::from(i == j)) - 1.0 / 3.0,
                (false, false) if i == j => 0.5,
                _ => 0.0,
            };
            c[(i, j)] -= g2 * ((1.0 - beta) * i_dev + beta * n[i] * n[j]);
        }
    }
    let released = std::array::from_fn(|k| trial[k] - stress[k]);
    Returned {
        stress,
        region: Region::Face,
        plastic_strain: compliance(elastic, &released),
        tangent: to_array(&c),
    }
}

/// Index of the main Mohr-Coulomb plane among [`Planes`].
const MAIN: usize = 0;
/// Index of the first cut-off plane (`s1 = t`) among [`Planes`].
const CUTOFF: usize = 3;

/// Tresca or Mohr-Coulomb with its cut-off as planes on sorted principal
/// stresses: 0 main, 1 the `s2 = s3` plane, 2 the `s1 = s2` plane, 3 + i
/// the cut-off `s_(i+1) <= t`.
#[derive(Clone, Copy, Debug)]
struct Planes {
    /// Normals `a_k`.
    a: [[f64; 3]; 6],
    /// Flow directions `n_k`.
    n: [[f64; 3]; 6],
    /// Right-hand sides `b_k`.
    b: [f64; 6],
    /// 3 (no cut-off) or 6.
    count: usize,
    /// `c / tan(phi)` for phi > 0.
    apex: Option<f64>,
    /// The cut-off is at the apex (clamped there, or no cut-off given).
    cutoff_at_apex: bool,
    /// The stress scale of the tolerances: c and t.
    strength: f64,
}

impl Planes {
    /// The planes of Tresca or Mohr-Coulomb; `None` for von Mises.
    fn new(criterion: &YieldCriterion) -> Option<Planes> {
        let (c, phi, psi, t) = match *criterion {
            YieldCriterion::Tresca { c_u } => (c_u, 0.0, 0.0, f64::INFINITY),
            YieldCriterion::VonMises { .. } => return None,
            YieldCriterion::MohrCoulomb {
                cohesion,
                friction_deg,
                dilation_deg,
                tension_cutoff,
            } => (cohesion, friction_deg, dilation_deg, tension_cutoff),
        };
        let (sin_phi, cos_phi) = f64::to_radians(phi).sin_cos();
        let sin_psi = f64::to_radians(psi).sin();
        let apex = (sin_phi > 0.0).then(|| c * cos_phi / sin_phi);
        let t = apex.map_or(t, |p| t.min(p));
        let (hi, lo) = (0.5 * (1.0 + sin_phi), -0.5 * (1.0 - sin_phi));
        let (g_hi, g_lo) = (0.5 * (1.0 + sin_psi), -0.5 * (1.0 - sin_psi));
        let e = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let k = c * cos_phi;
        let finite = t.is_finite();
        Some(Planes {
            a: [[hi, 0.0, lo], [hi, lo, 0.0], [0.0, hi, lo], e[0], e[1], e[2]],
            n: [
                [g_hi, 0.0, g_lo],
                [g_hi, g_lo, 0.0],
                [0.0, g_hi, g_lo],
                e[0],
                e[1],
                e[2],
            ],
            b: [k, k, k, t, t, t],
            count: if finite { 6 } else { 3 },
            apex,
            cutoff_at_apex: apex.is_some_and(|p| t >= p),
            strength: if finite { c.max(t) } else { c },
        })
    }

    fn value(&self, k: usize, x: &[f64; 3]) -> f64 {
        self.a[k][0] * x[0] + self.a[k][1] * x[1] + self.a[k][2] * x[2] - self.b[k]
    }

    /// The yield function at sorted principal stresses (main and `s1 - t`).
    fn max_value(&self, x: &[f64; 3]) -> f64 {
        let f = self.value(MAIN, x);
        if self.count > CUTOFF {
            f.max(self.value(CUTOFF, x))
        } else {
            f
        }
    }
}

/// Active sets of plane indices (fewest first), `len` of them used.
const ACTIVE_SETS: [([usize; 3], usize); 41] = active_sets();

const fn active_sets() -> [([usize; 3], usize); 41] {
    let mut out = [([0; 3], 0); 41];
    let mut k = 0;
    let mut i = 0;
    while i < 6 {
        out[k] = ([i, 0, 0], 1);
        k += 1;
        i += 1;
    }
    let mut i = 0;
    while i < 6 {
        let mut j = i + 1;
        while j < 6 {
            out[k] = ([i, j, 0], 2);
            k += 1;
            j += 1;
        }
        i += 1;
    }
    let mut i = 0;
    while i < 6 {
        let mut j = i + 1;
        while j < 6 {
            let mut l = j + 1;
            while l < 6 {
                out[k] = ([i, j, l], 3);
                k += 1;
                l += 1;
            }
            j += 1;
        }
        i += 1;
    }
    out
}

/// A principal-space return: stresses and `J = d y / d x`.
struct PrincipalReturn {
    y: [f64; 3],
    jacobian: Matrix3<f64>,
    region: Region,
}

/// The return to the active planes `set` from sorted trial `x`, if it is
/// valid (multipliers >= 0, every plane satisfied, order kept, each within
/// `tol`).
fn try_active_set(
    planes: &Planes,
    dp: &Matrix3<f64>,
    set: &[usize],
    x: &[f64; 3],
    tol: f64,
) -> Option<PrincipalReturn> {
    // Padded to 3 x 3: unused rows of A are identity, of a and D n zero.
    let mut a_mat = Matrix3::identity();
    let mut normals = Matrix3::zeros();
    let mut flows = Matrix3::zeros();
    let mut rhs = Vector3::zeros();
    for (r, &k) in set.iter().enumerate() {
        normals.set_row(r, &Vector3::from(planes.a[k]).transpose());
        flows.set_column(r, &(dp * Vector3::from(planes.n[k])));
        rhs[r] = planes.value(k, x);
    }
    for r in 0..set.len() {
        for s in 0..set.len() {
            a_mat[(r, s)] = normals.row(r).dot(&flows.column(s).transpose());
        }
    }
    let row_norms: f64 = a_mat.row_iter().map(|r| r.norm()).product();
    if a_mat.determinant().abs() <= 1e-10 * row_norms {
        return None;
    }
    let inv = a_mat.try_inverse()?;
    let gamma = inv * rhs;
    if (0..set.len()).any(|r| gamma[r] * a_mat[(r, r)] < -tol) {
        return None;
    }
    let (y, jacobian) = if set.len() == 3 {
        // A point: where its three planes meet.
        let b = Vector3::new(planes.b[set[0]], planes.b[set[1]], planes.b[set[2]]);
        let y = normals.try_inverse()? * b;
        ([y[0], y[1], y[2]], Matrix3::zeros())
    } else {
        let y = Vector3::from(*x) - flows * gamma;
        ([y[0], y[1], y[2]], Matrix3::identity() - flows * inv * normals)
    };
    if y[0] < y[1] - tol || y[1] < y[2] - tol {
        return None;
    }
    if (0..planes.count).any(|k| planes.value(k, &y) > tol) {
        return None;
    }
    let mohr = set.iter().filter(|&&k| k < CUTOFF).count();
    match planes.apex {
        // The cut-off at the apex meets the Mohr-Coulomb planes only there.
        Some(p) if mohr == 3 || (planes.cutoff_at_apex && mohr < set.len()) => {
            return Some(PrincipalReturn {
                y: [p; 3],
                jacobian: Matrix3::zeros(),
                region: Region::Apex,
            });
        }
        _ => {}
    }
    let region = match (mohr, set.len() - mohr) {
        (1, 0) => Region::Face,
        (2, 0) => Region::Edge,
        (0, 1) => Region::Cutoff,
        (0, 2) => Region::CutoffEdge,
        (0, 3) => Region::CutoffApex,
        (1, 1) => Region::FaceCutoff,
        _ => Region::Corner,
    };
    Some(PrincipalReturn { y, jacobian, region })
}

/// Tolerances of the active-set search, times the stress scale: the first
/// is [`TOL`]; the looser ones only serve nearly parallel planes (phi near
/// 90 degrees) whose multipliers carry large rounding errors.
const SEARCH_TOLS: [f64; 4] = [TOL, 1e-9, 1e-7, 1e-5];

fn principal_return(elastic: &Elastic, d: &SMatrix<f64, 6, 6>, planes: &Planes, trial: [f64; 6]) -> Returned {
    let (x, q) = principal(&trial);
    let scale = planes.strength.max(x[0].abs()).max(x[2].abs());
    if planes.max_value(&x) <= TOL * scale {
        return elastic_result(d, trial);
    }
    let dp = d.fixed_view::<3, 3>(0, 0).into_owned();
    let sets = ACTIVE_SETS
        .iter()
        .filter(|(set, len)| set[..*len].iter().all(|&k| k < planes.count));
    let found = SEARCH_TOLS.iter().find_map(|tol| {
        sets.clone()
            .find_map(|(set, len)| try_active_set(planes, &dp, &set[..*len], &x, tol * scale))
    });
    let ret = found.unwrap_or_else(|| {
        // A safety net, never reached in 2e5 random trials for each of
        // nu in [-0.9, 0.499], phi up to 89 deg, psi in [0, phi]: the
        // cut-off's apex (Mohr-Coulomb always has one, at the latest at
        // its apex), which the associated cut-off flow reaches from beyond.
        let (y, region) = match (planes.count > CUTOFF, planes.cutoff_at_apex) {
            (true, true) => ([planes.b[CUTOFF]; 3], Region::Apex),
            (true, false) => ([planes.b[CUTOFF]; 3], Region::CutoffApex),
            // Tresca (no cut-off): the deviator scaled onto the surface.
            (false, _) => {
                let mean = (x[0] + x[1] + x[2]) / 3.0;
                let f = planes.strength / (0.5 * (x[0] - x[2])).max(f64::MIN_POSITIVE);
                (x.map(|v| mean + f.min(1.0) * (v - mean)), Region::Face)
            }
        };
        PrincipalReturn {
            y,
            jacobian: Matrix3::zeros(),
            region,
        }
    });
    let stress = vector(&(q * Matrix3::from_diagonal(&Vector3::from(ret.y)) * q.transpose()));
    let released = std::array::from_fn(|k| trial[k] - stress[k]);
    let m = isotropic_derivative(&q, &x, &ret.y, &ret.jacobian, COINCIDENT * scale);
    Returned {
        stress,
        region: ret.region,
        plastic_strain: compliance(elastic, &released),
        tangent: to_array(&(m * d)),
    }
}

/// `d Y / d X` (6 x 6, plain stress components both sides) of the isotropic
/// tensor function `Y = Q diag(y) Q^T` of `X = Q diag(x) Q^T` with principal
/// Jacobian `J = d y / d x`; eigenvalues closer than `gap` count as
/// coincident.
fn isotropic_derivative(
    q: &Matrix3<f64>,
    x: &[f64; 3],
    y: &[f64; 3],
    jac: &Matrix3<f64>,
    gap: f64,
) -> SMatrix<f64, 6, 6> {
    let mut spin = Matrix3::zeros();
    for i in 0..3 {
        for j in 0..3 {
            if i != j {
                spin[(i, j)] = if (x[i] - x[j]).abs() > gap {
                    (y[i] - y[j]) / (x[i] - x[j])
                } else {
                    0.5 * (jac[(i, i)] - jac[(i, j)] + jac[(j, j)] - jac[(j, i)])
                };
            }
        }
    }
    let mut m = SMatrix::<f64, 6, 6>::zeros();
    for (col, &(k, l)) in PAIRS.iter().enumerate() {
        let mut dx = Matrix3::zeros();
        dx[(k, l)] = 1.0;
        dx[(l, k)] = 1.0;
        let dx_eig = q.transpose() * dx * q;
        let dy_diag = jac * dx_eig.diagonal();
        let mut dy_eig = dx_eig.component_mul(&spin);
        dy_eig.set_diagonal(&dy_diag);
        let dy = vector(&(q * dy_eig * q.transpose()));
        for (row, v) in dy.iter().enumerate() {
            m[(row, col)] = *v;
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    /// Deterministic splitmix64 generator.
    struct Rng(u64);

    impl Rng {
        /// Uniform in [lo, hi).
        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            let u = ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64;
            lo + (hi - lo) * u
        }

        /// A random rotation of the (r, z, theta) frame.
        fn rotation(&mut self) -> Matrix3<f64> {
            let axis = Vector3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            Rotation3::from_scaled_axis(axis * 2.0).into_inner()
        }

        /// A random stress: mean in [-3 s, s], components of the deviator up to s.
        fn stress(&mut self, s: f64) -> [f64; 6] {
            let p = self.range(-3.0 * s, s);
            let mut v: [f64; 6] = std::array::from_fn(|_| self.range(-s, s));
            for x in &mut v[..3] {
                *x += p;
            }
            v
        }
    }

    const CLAY: Elastic = Elastic { e: 1.0e4, nu: 0.3 };

    fn mc(c: f64, phi: f64, psi: f64, t: f64) -> YieldCriterion {
        YieldCriterion::MohrCoulomb {
            cohesion: c,
            friction_deg: phi,
            dilation_deg: psi,
            tension_cutoff: t,
        }
    }

    /// Criteria covering every region, with the plastic regions each must reach.
    fn criteria() -> Vec<(YieldCriterion, Vec<Region>)> {
        use Region::*;
        let cut = vec![Face, Edge, Cutoff, CutoffEdge, CutoffApex, FaceCutoff, Corner];
        vec![
            (YieldCriterion::Tresca { c_u: 50.0 }, vec![Face, Edge]),
            (YieldCriterion::VonMises { c_u: 50.0 }, vec![Face]),
            (mc(10.0, 30.0, 30.0, f64::INFINITY), vec![Face, Edge, Apex]),
            (mc(10.0, 30.0, 10.0, f64::INFINITY), vec![Face, Edge, Apex]),
            (mc(10.0, 30.0, 30.0, 5.0), cut.clone()),
            (mc(10.0, 30.0, 10.0, 5.0), cut.clone()),
            (mc(0.0, 35.0, 5.0, f64::INFINITY), vec![Face, Edge, Apex]),
            (mc(20.0, 0.0, 0.0, 10.0), cut.clone()),
            (mc(5.0, 50.0, 0.0, 2.0), cut),
        ]
    }

    fn rotate(r: &Matrix3<f64>, v: &[f64; 6]) -> [f64; 6] {
        vector(&(r * tensor(v) * r.transpose()))
    }

    /// A strain 6-vector (engineering shears) rotated as a tensor.
    fn rotate_strain(r: &Matrix3<f64>, e: &[f64; 6]) -> [f64; 6] {
        let half = [e[0], e[1], e[2], 0.5 * e[3], 0.5 * e[4], 0.5 * e[5]];
        let t = rotate(r, &half);
        [t[0], t[1], t[2], 2.0 * t[3], 2.0 * t[4], 2.0 * t[5]]
    }

    fn max_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
    }

    fn max_abs(a: &[f64]) -> f64 {
        a.iter().fold(0.0, |m, x| m.max(x.abs()))
    }

    fn d_of(v: &[f64; 6]) -> [f64; 6] {
        let d = CLAY.d_matrix();
        std::array::from_fn(|i| (0..6).map(|j| d[(i, j)] * v[j]).sum())
    }

    fn dot(a: &[f64; 6], b: &[f64; 6]) -> f64 {
        a.iter().zip(b).map(|(x, y)| x * y).sum()
    }

    /// Stress scale of a trial for tolerances.
    fn scale(trial: &[f64; 6]) -> f64 {
        max_abs(trial).max(50.0)
    }

    #[test]
    fn elastic_trial_is_unchanged() {
        let trial = [-20.0, -25.0, -22.0, 1.0, 0.5, -0.3];
        let d = to_array(&CLAY.d_matrix());
        for (crit, _) in criteria() {
            assert!(yield_value(&crit, trial) < 0.0, "{crit:?}");
            let r = return_map(&CLAY, &crit, trial);
            assert_eq!(r.region, Region::Elastic, "{crit:?}");
            assert_eq!(r.stress, trial);
            assert_eq!(r.plastic_strain, [0.0; 6]);
            assert_eq!(r.tangent, d);
        }
    }

    #[test]
    fn returned_stress_is_admissible() {
        let mut rng = Rng(7);
        for (crit, regions) in criteria() {
            let mut seen = Vec::new();
            for _ in 0..20_000 {
                let trial = rng.stress(80.0);
                let r = return_map(&CLAY, &crit, trial);
                let s = scale(&trial);
                // Admissible within 1e-10 of the stress scale.
                assert!(
                    yield_value(&crit, r.stress) <= 1e-10 * s,
                    "{crit:?} {trial:?} {r:?}"
                );
                if r.region == Region::Elastic {
                    assert!(yield_value(&crit, trial) <= 1e-10 * s);
                } else {
                    assert!(yield_value(&crit, trial) > 0.0);
                }
                // The plastic strain is D^-1 (trial - stress), to 1e-12.
                let back = d_of(&r.plastic_strain);
                let released: [f64; 6] = std::array::from_fn(|k| trial[k] - r.stress[k]);
                assert!(max_diff(&back, &released) <= 1e-12 * s);
                if !seen.contains(&r.region) {
                    seen.push(r.region);
                }
            }
            for region in regions {
                assert!(
                    seen.contains(&region),
                    "{crit:?}: {region:?} never reached ({seen:?})"
                );
            }
        }
    }

    /// A random admissible stress on or inside the surface: a random stress
    /// pulled towards `inner` (admissible) to the surface if it is outside.
    fn admissible_stress(rng: &mut Rng, crit: &YieldCriterion, inner: f64) -> [f64; 6] {
        let outer = rng.stress(80.0);
        if yield_value(crit, outer) <= 0.0 {
            return outer;
        }
        let at = |l: f64| -> [f64; 6] {
            std::array::from_fn(|k| l * outer[k] + (1.0 - l) * if k < 3 { inner } else { 0.0 })
        };
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if yield_value(crit, at(mid)) <= 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        at(lo)
    }

    #[test]
    fn associated_return_is_closest_point() {
        // Associated criteria and an admissible hydrostatic stress of each.
        let cases = [
            (YieldCriterion::Tresca { c_u: 50.0 }, -10.0),
            (YieldCriterion::VonMises { c_u: 50.0 }, -10.0),
            (mc(10.0, 30.0, 30.0, 5.0), 0.0),
            (mc(10.0, 30.0, 30.0, f64::INFINITY), 0.0),
            (mc(20.0, 0.0, 0.0, 10.0), 0.0),
        ];
        let mut rng = Rng(11);
        for (crit, inner) in cases {
            let others: Vec<[f64; 6]> = (0..2000)
                .map(|_| admissible_stress(&mut rng, &crit, inner))
                .collect();
            let mut checked = 0;
            while checked < 100 {
                let trial = rng.stress(80.0);
                let r = return_map(&CLAY, &crit, trial);
                if r.region == Region::Elastic {
                    continue;
                }
                checked += 1;
                let ep = r.plastic_strain;
                // Energy distance^2 = (trial - s) . D^-1 (trial - s).
                let dist = |s: &[f64; 6]| -> f64 {
                    let ds: [f64; 6] = std::array::from_fn(|k| trial[k] - s[k]);
                    dot(&ds, &compliance(&CLAY, &ds))
                };
                let own = dist(&r.stress);
                for tau in &others {
                    // (trial - s) : D^-1 : (tau - s) <= 0 for every admissible tau ...
                    let dt: [f64; 6] = std::array::from_fn(|k| tau[k] - r.stress[k]);
                    let norm = dot(&ep, &ep).sqrt() * dot(&dt, &dt).sqrt();
                    assert!(dot(&ep, &dt) <= 1e-9 * norm, "{crit:?} {trial:?} {tau:?}");
                    // ... so none is closer in the energy norm.
                    assert!(dist(tau) >= own * (1.0 - 1e-12), "{crit:?} {trial:?} {tau:?}");
                }
            }
        }
    }

    /// The plastic strain in the trial's principal axes (engineering shears
    /// halved to tensor components), sorted like the trial.
    fn principal_plastic_strain(trial: &[f64; 6], ep: &[f64; 6]) -> Matrix3<f64> {
        let (_, q) = principal(trial);
        let half = [ep[0], ep[1], ep[2], 0.5 * ep[3], 0.5 * ep[4], 0.5 * ep[5]];
        q.transpose() * tensor(&half) * q
    }

    /// Checks that the principal plastic strains of the face returns of `crit`
    /// are proportional to `(1 + sin a) : 0 : -(1 - sin a)`.
    fn face_flow_follows(crit: YieldCriterion, angle_deg: f64) {
        let sin_a = angle_deg.to_radians().sin();
        let mut rng = Rng(13);
        let mut checked = 0;
        while checked < 500 {
            let trial = rng.stress(80.0);
            let r = return_map(&CLAY, &crit, trial);
            if r.region != Region::Face {
                continue;
            }
            checked += 1;
            let e = principal_plastic_strain(&trial, &r.plastic_strain);
            let size = e.abs().max();
            assert!(size > 0.0);
            for (i, j) in [(0, 1), (0, 2), (1, 2)] {
                assert!(e[(i, j)].abs() <= 1e-10 * size, "not coaxial: {e}");
            }
            let g = e[(0, 0)] / (1.0 + sin_a);
            assert!((e[(2, 2)] + g * (1.0 - sin_a)).abs() <= 1e-10 * size, "{e}");
            assert!(e[(1, 1)].abs() <= 1e-10 * size, "{e}");
        }
    }

    #[test]
    fn associated_plastic_strain_is_normal() {
        face_flow_follows(mc(10.0, 30.0, 30.0, 5.0), 30.0);
        face_flow_follows(YieldCriterion::Tresca { c_u: 50.0 }, 0.0);
    }

    #[test]
    fn non_associated_flow_follows_potential() {
        face_flow_follows(mc(10.0, 30.0, 10.0, 5.0), 10.0);
        face_flow_follows(mc(5.0, 40.0, 0.0, f64::INFINITY), 0.0);
    }

    #[test]
    fn cutoff_flow_is_the_first_principal_direction() {
        let mut rng = Rng(17);
        let mut checked = 0;
        while checked < 200 {
            let trial = rng.stress(80.0);
            let r = return_map(&CLAY, &mc(10.0, 30.0, 10.0, 5.0), trial);
            if r.region != Region::Cutoff {
                continue;
            }
            checked += 1;
            let e = principal_plastic_strain(&trial, &r.plastic_strain);
            let size = e.abs().max();
            assert!(e[(0, 0)] > 0.0);
            assert!(
                (e - Matrix3::from_diagonal(&Vector3::new(e[(0, 0)], 0.0, 0.0)))
                    .abs()
                    .max()
                    <= 1e-10 * size
            );
            let (s, _) = principal(&r.stress);
            assert!((s[0] - 5.0).abs() <= 1e-12 * scale(&trial));
        }
    }

    #[test]
    fn tresca_is_mohr_coulomb_without_friction() {
        let tresca = YieldCriterion::Tresca { c_u: 50.0 };
        let mohr = mc(50.0, 0.0, 0.0, f64::INFINITY);
        let mut rng = Rng(19);
        for _ in 0..5000 {
            let trial = rng.stress(100.0);
            let (a, b) = (return_map(&CLAY, &tresca, trial), return_map(&CLAY, &mohr, trial));
            assert_eq!(a.region, b.region);
            assert!(max_diff(&a.stress, &b.stress) <= 1e-12 * scale(&trial));
            let (ta, tb) = (a.tangent.concat(), b.tangent.concat());
            assert!(max_diff(&ta, &tb) <= 1e-12 * CLAY.e);
            assert!((yield_value(&tresca, trial) - yield_value(&mohr, trial)).abs() <= 1e-12 * scale(&trial));
        }
        // Closed form: s1 - s3 = 200 -> 100, the mean and s2 kept.
        let r = return_map(&CLAY, &tresca, [0.0, -200.0, -60.0, 0.0, 0.0, 0.0]);
        assert_eq!(r.region, Region::Face);
        assert!(max_diff(&r.stress, &[-50.0, -150.0, -60.0, 0.0, 0.0, 0.0]) < 1e-11);
        // Pure shear 80 -> 50.
        let r = return_map(&CLAY, &tresca, [0.0, 0.0, 0.0, 0.0, 80.0, 0.0]);
        assert!(max_diff(&r.stress, &[0.0, 0.0, 0.0, 0.0, 50.0, 0.0]) < 1e-11);
    }

    #[test]
    fn von_mises_radial_return() {
        let vm = YieldCriterion::VonMises { c_u: 50.0 };
        let r = return_map(&CLAY, &vm, [0.0, 0.0, 0.0, 80.0, 0.0, 0.0]);
        assert_eq!(r.region, Region::Face);
        assert!(max_diff(&r.stress, &[0.0, 0.0, 0.0, 50.0, 0.0, 0.0]) < 1e-12);
        let mut rng = Rng(23);
        for _ in 0..1000 {
            let trial = rng.stress(100.0);
            let r = return_map(&CLAY, &vm, trial);
            let q = sqrt_j2(&trial);
            if q <= 50.0 {
                assert_eq!(r.region, Region::Elastic);
                continue;
            }
            let p = (trial[0] + trial[1] + trial[2]) / 3.0;
            let expect: [f64; 6] = std::array::from_fn(|k| {
                if k < 3 {
                    p + (trial[k] - p) * 50.0 / q
                } else {
                    trial[k] * 50.0 / q
                }
            });
            assert!(max_diff(&r.stress, &expect) <= 1e-12 * scale(&trial));
            assert!((sqrt_j2(&r.stress) - 50.0).abs() <= 1e-12 * scale(&trial));
        }
    }

    #[test]
    fn return_is_isotropic() {
        let mut rng = Rng(29);
        for (crit, _) in criteria() {
            for _ in 0..2000 {
                let trial = rng.stress(80.0);
                let rot = rng.rotation();
                let (a, b) = (
                    return_map(&CLAY, &crit, trial),
                    return_map(&CLAY, &crit, rotate(&rot, &trial)),
                );
                let s = scale(&trial);
                assert_eq!(a.region, b.region, "{crit:?} {trial:?}");
                assert!(
                    max_diff(&rotate(&rot, &a.stress), &b.stress) <= 1e-10 * s,
                    "{crit:?} {trial:?}"
                );
                let ep = rotate_strain(&rot, &a.plastic_strain);
                assert!(max_diff(&ep, &b.plastic_strain) <= 1e-10 * s / CLAY.e);
            }
        }
    }

    /// A region, a stress on its planes, the planes and their multipliers.
    type Case = (Region, [f64; 3], &'static [usize], &'static [f64]);

    /// Trials built backwards: a stress `target` on the planes `set` plus
    /// `D n dgamma`, in a random frame; with the region they must return to.
    fn constructed(crit: &YieldCriterion, rng: &mut Rng) -> Vec<(Region, [f64; 6], [f64; 6])> {
        let planes = Planes::new(crit).unwrap();
        let dp = CLAY.d_matrix().fixed_view::<3, 3>(0, 0).into_owned();
        let YieldCriterion::MohrCoulomb {
            cohesion: c,
            friction_deg,
            dilation_deg,
            ..
        } = *crit
        else {
            unreachable!()
        };
        let (sin_phi, cos_phi) = friction_deg.to_radians().sin_cos();
        // s1 on the main plane for s3, and s3 for s1.
        let s1_of = |s3: f64| (2.0 * c * cos_phi + (1.0 - sin_phi) * s3) / (1.0 + sin_phi);
        let s3_of = |s1: f64| ((1.0 + sin_phi) * s1 - 2.0 * c * cos_phi) / (1.0 - sin_phi);
        let t = planes.b[CUTOFF];
        let (f, s3c) = (s1_of(-40.0), s3_of(t));
        use Region::*;
        let mut cases: Vec<Case> = vec![
            (Face, [f, -20.0, -40.0], &[0], &[4e-3]),
            (Edge, [f, -40.0, -40.0], &[0, 1], &[6e-3, 2e-3]),
            (Edge, [f, f, -40.0], &[0, 2], &[6e-3, 2e-3]),
        ];
        if planes.cutoff_at_apex {
            // With psi = 0 the Mohr-Coulomb flows at the apex span only
            // the deviatoric plane there (a region boundary).
            if dilation_deg > 0.0 {
                cases.push((Apex, [t; 3], &[0, 1, 2], &[6e-3, 4e-3, 2e-3]));
            }
            cases.push((Apex, [t; 3], &[3, 4, 5], &[6e-3, 4e-3, 2e-3]));
        } else {
            cases.extend_from_slice(&[
                (Cutoff, [t, -2.0, -10.0], &[3][..], &[3e-3][..]),
                (CutoffEdge, [t, t, -10.0], &[3, 4], &[4e-3, 2e-3]),
                (CutoffApex, [t; 3], &[3, 4, 5], &[6e-3, 4e-3, 2e-3]),
                (FaceCutoff, [t, 0.5 * (t + s3c), s3c], &[0, 3], &[4e-3, 3e-3]),
                (Corner, [t, s3c, s3c], &[0, 1, 3], &[6e-3, 2e-3, 3e-3]),
                (Corner, [t, t, s3c], &[0, 3, 4], &[5e-3, 6e-3, 1.5e-3]),
            ]);
        }
        cases
            .into_iter()
            .map(|(region, target, set, gamma)| {
                let mut x = Vector3::from(target);
                for (&k, &g) in set.iter().zip(gamma) {
                    x += dp * Vector3::from(planes.n[k]) * g;
                }
                let rot = rng.rotation();
                let diag = |v: [f64; 3]| [v[0], v[1], v[2], 0.0, 0.0, 0.0];
                (
                    region,
                    rotate(&rot, &diag([x[0], x[1], x[2]])),
                    rotate(&rot, &diag(target)),
                )
            })
            .collect()
    }

    fn constructed_criteria() -> [YieldCriterion; 5] {
        [
            mc(10.0, 30.0, 10.0, 5.0),
            mc(10.0, 30.0, 30.0, 5.0),
            mc(10.0, 30.0, 10.0, f64::INFINITY),
            mc(10.0, 30.0, 0.0, f64::INFINITY),
            mc(20.0, 0.0, 0.0, 10.0),
        ]
    }

    #[test]
    fn constructed_trials_return_to_their_region() {
        let mut rng = Rng(31);
        for crit in constructed_criteria() {
            for (region, trial, target) in constructed(&crit, &mut rng) {
                let r = return_map(&CLAY, &crit, trial);
                assert_eq!(r.region, region, "{crit:?} {target:?}");
                assert!(
                    max_diff(&r.stress, &target) <= 1e-11 * scale(&trial),
                    "{crit:?} {r:?} {target:?}"
                );
            }
        }
    }

    /// max |tangent - central differences| / E over the columns, or None
    /// when a perturbed trial changes region.
    fn tangent_error(crit: &YieldCriterion, trial: &[f64; 6]) -> Option<f64> {
        let r = return_map(&CLAY, crit, *trial);
        let strain = compliance(&CLAY, trial);
        let h = 1e-6 * max_abs(&strain);
        let mut err: f64 = 0.0;
        for j in 0..6 {
            let at = |sign: f64| {
                let mut e = strain;
                e[j] += sign * h;
                return_map(&CLAY, crit, d_of(&e))
            };
            let (plus, minus) = (at(1.0), at(-1.0));
            if plus.region != r.region || minus.region != r.region {
                return None;
            }
            for i in 0..6 {
                let fd = (plus.stress[i] - minus.stress[i]) / (2.0 * h);
                err = err.max((r.tangent[i][j] - fd).abs() / CLAY.e);
            }
        }
        Some(err)
    }

    /// Eigenvalues of the trial at least 1 apart (no coincident ones).
    fn distinct(trial: &[f64; 6]) -> bool {
        let (x, _) = principal(trial);
        x[0] - x[1] > 1.0 && x[1] - x[2] > 1.0
    }

    #[test]
    fn tangent_matches_finite_differences() {
        let mut rng = Rng(37);
        let mut seen = Vec::new();
        for crit in constructed_criteria() {
            for (region, trial, _) in constructed(&crit, &mut rng) {
                assert!(distinct(&trial), "{crit:?} {region:?} {trial:?}");
                let err = tangent_error(&crit, &trial).expect("inside its region");
                assert!(err <= 1e-6, "{crit:?} {region:?}: {err:e}");
                seen.push(region);
            }
        }
        // Random trials of every criterion, away from region boundaries.
        for (crit, _) in criteria() {
            let mut checked = 0;
            while checked < 300 {
                let trial = rng.stress(80.0);
                if !distinct(&trial) {
                    continue;
                }
                let Some(err) = tangent_error(&crit, &trial) else {
                    continue;
                };
                checked += 1;
                assert!(err <= 1e-6, "{crit:?} {trial:?}: {err:e}");
                seen.push(return_map(&CLAY, &crit, trial).region);
            }
        }
        use Region::*;
        for region in [
            Elastic, Face, Edge, Apex, Cutoff, CutoffEdge, CutoffApex, FaceCutoff, Corner,
        ] {
            assert!(seen.contains(&region), "{region:?}");
        }
    }

    #[test]
    fn tangent_with_coincident_eigenvalues() {
        // Triaxial trials (two equal principal stresses) inside regions that
        // keep them equal: the limit of the spin term, checked by differences.
        let cases = [
            (
                mc(10.0, 30.0, 10.0, 5.0),
                [20.0, -10.0, -10.0, 0.0, 0.0, 0.0],
                Region::Cutoff,
            ),
            (
                mc(10.0, 30.0, 10.0, 5.0),
                [-30.0, -30.0, -30.0, 0.0, 0.0, 0.0],
                Region::Elastic,
            ),
            (
                mc(10.0, 30.0, 10.0, 5.0),
                [-10.0, -90.0, -10.0, 0.0, 0.0, 0.0],
                Region::Edge,
            ),
            (
                YieldCriterion::Tresca { c_u: 50.0 },
                [-100.0, -300.0, -100.0, 0.0, 0.0, 0.0],
                Region::Edge,
            ),
            (
                YieldCriterion::VonMises { c_u: 50.0 },
                [100.0, -50.0, -50.0, 0.0, 0.0, 0.0],
                Region::Face,
            ),
        ];
        for (crit, trial, region) in cases {
            assert_eq!(return_map(&CLAY, &crit, trial).region, region);
            let err = tangent_error(&crit, &trial).expect("inside its region");
            assert!(err <= 1e-6, "{crit:?} {trial:?}: {err:e}");
        }
    }

    #[test]
    fn yield_values_in_stress_units() {
        let rot = Rng(41).rotation();
        let s = rotate(&rot, &[10.0, -30.0, -90.0, 0.0, 0.0, 0.0]);
        assert!((yield_value(&YieldCriterion::Tresca { c_u: 20.0 }, s) - 30.0).abs() < 1e-12);
        let q = ((40f64.powi(2) + 60f64.powi(2) + 100f64.powi(2)) / 6.0).sqrt();
        assert!((yield_value(&YieldCriterion::VonMises { c_u: 20.0 }, s) - (q - 20.0)).abs() < 1e-12);
        // (s1 - s3)/2 + (s1 + s3)/2 sin 30 - 10 cos 30 = 50 - 20 - 8.66; s1 - t = 10 - 5.
        let f = 50.0 - 20.0 - 10.0 * 30f64.to_radians().cos();
        assert!((yield_value(&mc(10.0, 30.0, 10.0, 5.0), s) - f).abs() < 1e-12);
        let hydro = [20.0, 20.0, 20.0, 0.0, 0.0, 0.0];
        assert!((yield_value(&mc(10.0, 30.0, 10.0, 5.0), hydro) - 15.0).abs() < 1e-12);
        // A cut-off beyond the apex c / tan(phi) = 17.32 acts at the apex.
        let apex = 10.0 / 30f64.to_radians().tan();
        assert!((yield_value(&mc(10.0, 30.0, 10.0, 100.0), hydro) - (20.0 - apex)).abs() < 1e-12);
        let r = return_map(&CLAY, &mc(10.0, 30.0, 10.0, 100.0), hydro);
        assert_eq!(r.region, Region::Apex);
        assert!(max_diff(&r.stress, &[apex, apex, apex, 0.0, 0.0, 0.0]) < 1e-12);
        assert_eq!(r.tangent, [[0.0; 6]; 6]);
    }

    #[test]
    fn validation_names_the_parameter() {
        let message = |c: YieldCriterion| c.validate().unwrap_err().to_string();
        assert!(message(YieldCriterion::Tresca { c_u: -1.0 }).contains("undrained strength c_u = -1"));
        assert!(message(YieldCriterion::VonMises { c_u: f64::NAN }).contains("c_u = NaN"));
        assert!(message(YieldCriterion::Tresca { c_u: f64::INFINITY }).contains("c_u = inf"));
        assert!(message(mc(-2.0, 30.0, 0.0, 0.0)).contains("cohesion c = -2"));
        assert!(message(mc(1.0, 90.0, 0.0, 0.0)).contains("friction angle phi = 90 deg"));
        assert!(message(mc(1.0, -5.0, 0.0, 0.0)).contains("friction angle phi = -5 deg"));
        assert!(message(mc(1.0, 30.0, 35.0, 0.0)).contains("dilation angle psi = 35 deg"));
        assert!(message(mc(1.0, 30.0, -1.0, 0.0)).contains("dilation angle psi = -1 deg"));
        assert!(message(mc(0.0, 0.0, 0.0, 0.0)).contains("cohesion c = 0 with friction angle phi = 0"));
        assert!(message(mc(1.0, 30.0, 0.0, -1.0)).contains("tension cut-off t = -1"));
        assert!(message(mc(1.0, 30.0, 0.0, f64::NAN)).contains("tension cut-off t = NaN"));
        assert_eq!(YieldCriterion::Tresca { c_u: 0.0 }.validate(), Ok(()));
        assert_eq!(mc(0.0, 35.0, 35.0, f64::INFINITY).validate(), Ok(()));
        for (crit, _) in criteria() {
            assert_eq!(crit.validate(), Ok(()), "{crit:?}");
        }
    }
}
