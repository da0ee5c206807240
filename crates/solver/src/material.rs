//! Isotropic linear elasticity.

use nalgebra::SMatrix;

/// Why a material was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MaterialError {
    /// E is zero, negative or not finite.
    #[error("Young's modulus E = {} is not allowed: it must be a finite number > 0", crate::short::short(.e))]
    Modulus {
        /// The value given.
        e: f64,
    },
    /// nu is outside (-1, 0.5).
    #[error("Poisson's ratio nu = {} is not allowed: it must lie strictly between -1 and 0.5 (0.5 is incompressible, which displacement elements cannot represent)", crate::short::short(.nu))]
    Poisson {
        /// The value given.
        nu: f64,
    },
}

/// Isotropic linear elastic material: Young's modulus `e` and Poisson's
/// ratio `nu`.
///
/// Fields are public (plain data); use [`Elastic::new`] or
/// [`Elastic::validate`] before trusting values read from input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Elastic {
    /// Young's modulus E (stress units), E > 0.
    pub e: f64,
    /// Poisson's ratio nu, -1 < nu < 0.5.
    pub nu: f64,
}

/// The softer (smaller E) material of the bodies on a joint's two faces;
/// `None` for a joint without bodies.
pub fn softer_side(joint: &axijoint_mesh::Joint, materials: &[Elastic]) -> Option<Elastic> {
    joint
        .bottom_bodies
        .iter()
        .chain(&joint.top_bodies)
        .map(|&b| materials[b])
        .min_by(|a, b| a.e.total_cmp(&b.e))
}

impl Elastic {
    /// A validated material.
    ///
    /// ```
    /// use axijoint_solver::material::Elastic;
    /// let concrete = Elastic::new(2.0e4, 0.17).unwrap();
    /// assert!((concrete.shear_modulus() - 2.0e4 / 2.34).abs() < 1e-9);
    /// assert!(Elastic::new(2.0e4, 0.5).is_err());
    /// ```
    pub fn new(e: f64, nu: f64) -> Result<Self, MaterialError> {
        let m = Elastic { e, nu };
        m.validate()?;
        Ok(m)
    }

    /// Checks E > 0 (finite) and -1 < nu < 0.5.
    pub fn validate(&self) -> Result<(), MaterialError> {
        if !(self.e.is_finite() && self.e > 0.0) {
            return Err(MaterialError::Modulus { e: self.e });
        }
        if !(self.nu > -1.0 && self.nu < 0.5) {
            return Err(MaterialError::Poisson { nu: self.nu });
        }
        Ok(())
    }

    /// Shear modulus `G = E / (2 (1 + nu))`.
    pub fn shear_modulus(&self) -> f64 {
        self.e / (2.0 * (1.0 + self.nu))
    }

    /// Lame's first parameter `lambda = E nu / ((1 + nu)(1 - 2 nu))`.
    pub fn lame_lambda(&self) -> f64 {
        self.e * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu))
    }

    /// Elasticity matrix `D` with `sigma = D eps` for the strain order
    /// `(e_r, e_z, e_th, g_rz, g_rth, g_zth)` (engineering shear strains):
    ///
    /// ```text
    ///     | l+2G  l     l     0  0  0 |
    ///     | l     l+2G  l     0  0  0 |
    /// D = | l     l     l+2G  0  0  0 |      l = lambda, G = shear modulus
    ///     | 0     0     0     G  0  0 |
    ///     | 0     0     0     0  G  0 |
    ///     | 0     0     0     0  0  G |
    /// ```
    pub fn d_matrix(&self) -> SMatrix<f64, 6, 6> {
        let (l, g) = (self.lame_lambda(), self.shear_modulus());
        let mut d = SMatrix::<f64, 6, 6>::zeros();
        for i in 0..3 {
            for j in 0..3 {
                d[(i, j)] = l;
            }
            d[(i, i)] = l + 2.0 * g;
            d[(i + 3, i + 3)] = g;
        }
        d
    }
}
