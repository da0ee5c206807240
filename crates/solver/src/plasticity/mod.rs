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
mod tests;
