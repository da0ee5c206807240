//! The solution types: displacement amplitudes per harmonic, support
//! reactions and timings. A leaf module (it uses no other module of the
//! crate): `run` makes these values, `iteration` and `results` use them.

use serde::{Deserialize, Serialize};

/// Displacement amplitudes of one harmonic (node-major, `(u_r, u_z, u_theta)`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HarmonicDisplacement {
    /// Harmonic m.
    pub m: u32,
    /// Symmetric family (`u cos, v cos, w sin`); for m = 0 also the torsion w.
    pub symmetric: Vec<f64>,
    /// Antisymmetric family (`u sin, v sin, -w cos`); zero for m = 0.
    pub antisymmetric: Vec<f64>,
}

/// The displacement field as Fourier amplitudes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Displacements {
    /// One entry per harmonic 0..=M.
    pub harmonics: Vec<HarmonicDisplacement>,
}

impl Displacements {
    /// `self - other`, harmonic by harmonic (the same harmonics, in order).
    pub fn minus(&self, other: &Displacements) -> Displacements {
        let minus = |u: &[f64], v: &[f64]| u.iter().zip(v).map(|(p, q)| p - q).collect();
        Displacements {
            harmonics: self
                .harmonics
                .iter()
                .zip(&other.harmonics)
                .map(|(p, q)| HarmonicDisplacement {
                    m: p.m,
                    symmetric: minus(&p.symmetric, &q.symmetric),
                    antisymmetric: minus(&p.antisymmetric, &q.antisymmetric),
                })
                .collect(),
        }
    }

    /// `(u_r, u_z, u_theta)` of node `n` at angle `theta` (radians).
    pub fn at(&self, n: usize, theta: f64) -> [f64; 3] {
        let mut u = [0.0; 3];
        for h in &self.harmonics {
            let (sin, cos) = (f64::from(h.m) * theta).sin_cos();
            h.add_at(n, sin, cos, &mut u);
        }
        u
    }

    /// [`Displacements::at`] with `trig[m] = (sin m theta, cos m theta)`
    /// given, for many nodes at one angle (`trig` covers every harmonic).
    pub fn at_trig(&self, n: usize, trig: &[(f64, f64)]) -> [f64; 3] {
        let mut u = [0.0; 3];
        for h in &self.harmonics {
            let (sin, cos) = trig[h.m as usize];
            h.add_at(n, sin, cos, &mut u);
        }
        u
    }
}

impl HarmonicDisplacement {
    /// Adds this harmonic's `(u_r, u_z, u_theta)` of node `n` at the angle
    /// whose `sin m theta`, `cos m theta` are given.
    #[inline]
    fn add_at(&self, n: usize, sin: f64, cos: f64, u: &mut [f64; 3]) {
        let s = &self.symmetric[3 * n..3 * n + 3];
        if self.m == 0 {
            u[0] += s[0];
            u[1] += s[1];
            u[2] += s[2];
            return;
        }
        let a = &self.antisymmetric[3 * n..3 * n + 3];
        u[0] += s[0] * cos + a[0] * sin;
        u[1] += s[1] * cos + a[1] * sin;
        u[2] += s[2] * sin - a[2] * cos;
    }
}

/// Reaction of one support: nodal reactions summed to Cartesian resultants.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SupportReaction {
    /// The support's physical name.
    pub on: String,
    /// `(Fx, Fy, Fz)` summed over harmonics.
    pub force: [f64; 3],
    /// `(Mx, My, Mz)` about the origin.
    pub moment: [f64; 3],
    /// Per harmonic: `[m, Fx, Fy, Fz, Mx, My, Mz]`.
    pub per_harmonic: Vec<[f64; 7]>,
}

/// Wall-clock times of a linear solve, in seconds.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Timings {
    /// Pattern and symbolic factorization (once).
    pub setup: f64,
    /// Assembly and numeric factorization of all harmonics.
    pub factorize: f64,
    /// Back-substitutions.
    pub solve: f64,
    /// Reactions.
    pub reactions: f64,
}
