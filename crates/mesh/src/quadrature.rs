//! Quadrature rules on the reference line, quadrilateral and triangle.
//!
//! | rule | points | exact for |
//! |---|---|---|
//! | [`gauss_legendre`]`(n)`, n = 1..=5 | n on [-1, 1] | degree 2n - 1 |
//! | [`gauss_lobatto`]`(n)`, n = 2..=5 | n on [-1, 1], ends included | degree 2n - 3 |
//! | [`quad_gauss`]`(n)`, n = 1..=5 | n x n on [-1, 1]^2 | degree 2n - 1 in xi and in eta |
//! | [`triangle`]`(p)`, p = 1..=6 | 1, 3, 6, 6, 7, 12 | total degree p (Strang-Fix / Dunavant, positive weights, interior points) |
//!
//! Weights sum to the measure of the reference: 2 on the line, 4 on the
//! square, 1/2 on the triangle. All rules are `'static` tables: choosing a
//! rule never allocates.
//!
//! ```
//! use axijoint_mesh::quadrature::triangle;
//! let rule = triangle(4).unwrap();
//! // Integral of x^2 y^2 over the reference triangle = 2! 2! / 6! = 1/180
//! let q: f64 = rule.iter().map(|([x, y], w)| w * x * x * y * y).sum();
//! assert!((q - 1.0 / 180.0).abs() < 1e-15);
//! ```

use crate::CellKind;

/// A rule on [-1, 1]: points s and weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rule1D {
    /// Abscissas, ascending.
    pub points: &'static [f64],
    /// Weights, summing to 2.
    pub weights: &'static [f64],
}

impl Rule1D {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True if the rule has no points (never, for the rules of this module).
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// `(s, weight)` pairs.
    pub fn iter(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.points.iter().copied().zip(self.weights.iter().copied())
    }
}

/// A rule on a 2D reference cell: points (xi, eta) and weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rule2D {
    /// Points in reference coordinates.
    pub points: &'static [[f64; 2]],
    /// Weights, summing to the reference area (4 or 1/2).
    pub weights: &'static [f64],
}

impl Rule2D {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True if the rule has no points (never, for the rules of this module).
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// `(point, weight)` pairs.
    pub fn iter(&self) -> impl Iterator<Item = ([f64; 2], f64)> + '_ {
        self.points.iter().copied().zip(self.weights.iter().copied())
    }
}

// ---------------------------------------------------------------- Gauss-Legendre

const GL4_A: f64 = 0.33998104358485626; // sqrt(3/7 - 2/7 sqrt(6/5))
const GL4_B: f64 = 0.8611363115940526; // sqrt(3/7 + 2/7 sqrt(6/5))
const GL4_WA: f64 = 0.6521451548625461; // (18 + sqrt 30) / 36
const GL4_WB: f64 = 0.34785484513745385; // (18 - sqrt 30) / 36
const GL5_A: f64 = 0.5384693101056831; // sqrt(5 - 2 sqrt(10/7)) / 3
const GL5_B: f64 = 0.906179845938664; // sqrt(5 + 2 sqrt(10/7)) / 3
const GL5_WA: f64 = 0.47862867049936647; // (322 + 13 sqrt 70) / 900
const GL5_WB: f64 = 0.23692688505618908; // (322 - 13 sqrt 70) / 900
const SQRT_1_3: f64 = 0.5773502691896257;
const SQRT_3_5: f64 = 0.7745966692414834;

const GL1_X: [f64; 1] = [0.0];
const GL1_W: [f64; 1] = [2.0];
const GL2_X: [f64; 2] = [-SQRT_1_3, SQRT_1_3];
const GL2_W: [f64; 2] = [1.0, 1.0];
const GL3_X: [f64; 3] = [-SQRT_3_5, 0.0, SQRT_3_5];
const GL3_W: [f64; 3] = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
const GL4_X: [f64; 4] = [-GL4_B, -GL4_A, GL4_A, GL4_B];
const GL4_W: [f64; 4] = [GL4_WB, GL4_WA, GL4_WA, GL4_WB];
const GL5_X: [f64; 5] = [-GL5_B, -GL5_A, 0.0, GL5_A, GL5_B];
const GL5_W: [f64; 5] = [GL5_WB, GL5_WA, 128.0 / 225.0, GL5_WA, GL5_WB];

/// Gauss-Legendre rule with `n` points on [-1, 1] (exact to degree 2n - 1),
/// `None` unless `1 <= n <= 5`.
pub fn gauss_legendre(n: usize) -> Option<Rule1D> {
    let (points, weights): (&'static [f64], &'static [f64]) = match n {
        1 => (&GL1_X, &GL1_W),
        2 => (&GL2_X, &GL2_W),
        3 => (&GL3_X, &GL3_W),
        4 => (&GL4_X, &GL4_W),
        5 => (&GL5_X, &GL5_W),
        _ => return None,
    };
    Some(Rule1D { points, weights })
}

// ---------------------------------------------------------------- Gauss-Lobatto

const SQRT_1_5: f64 = 0.4472135954999579;
const SQRT_3_7: f64 = 0.6546536707079772;

const GLL2_X: [f64; 2] = [-1.0, 1.0];
const GLL2_W: [f64; 2] = [1.0, 1.0];
const GLL3_X: [f64; 3] = [-1.0, 0.0, 1.0];
const GLL3_W: [f64; 3] = [1.0 / 3.0, 4.0 / 3.0, 1.0 / 3.0];
const GLL4_X: [f64; 4] = [-1.0, -SQRT_1_5, SQRT_1_5, 1.0];
const GLL4_W: [f64; 4] = [1.0 / 6.0, 5.0 / 6.0, 5.0 / 6.0, 1.0 / 6.0];
const GLL5_X: [f64; 5] = [-1.0, -SQRT_3_7, 0.0, SQRT_3_7, 1.0];
const GLL5_W: [f64; 5] = [0.1, 49.0 / 90.0, 32.0 / 45.0, 49.0 / 90.0, 0.1];

/// Gauss-Lobatto rule with `n` points on [-1, 1], both ends included (exact
/// to degree 2n - 3), `None` unless `2 <= n <= 5`.
pub fn gauss_lobatto(n: usize) -> Option<Rule1D> {
    let (points, weights): (&'static [f64], &'static [f64]) = match n {
        2 => (&GLL2_X, &GLL2_W),
        3 => (&GLL3_X, &GLL3_W),
        4 => (&GLL4_X, &GLL4_W),
        5 => (&GLL5_X, &GLL5_W),
        _ => return None,
    };
    Some(Rule1D { points, weights })
}

// ---------------------------------------------------------------- tensor rules

/// Tensor product of a 1D rule with itself; xi runs fastest.
const fn tensor<const N: usize, const NN: usize>(x: [f64; N], w: [f64; N]) -> ([[f64; 2]; NN], [f64; NN]) {
    let mut p = [[0.0; 2]; NN];
    let mut q = [0.0; NN];
    let mut j = 0;
    while j < N {
        let mut i = 0;
        while i < N {
            p[j * N + i] = [x[i], x[j]];
            q[j * N + i] = w[i] * w[j];
            i += 1;
        }
        j += 1;
    }
    (p, q)
}

const Q1: ([[f64; 2]; 1], [f64; 1]) = tensor(GL1_X, GL1_W);
const Q2: ([[f64; 2]; 4], [f64; 4]) = tensor(GL2_X, GL2_W);
const Q3: ([[f64; 2]; 9], [f64; 9]) = tensor(GL3_X, GL3_W);
const Q4: ([[f64; 2]; 16], [f64; 16]) = tensor(GL4_X, GL4_W);
const Q5: ([[f64; 2]; 25], [f64; 25]) = tensor(GL5_X, GL5_W);

/// Tensor Gauss-Legendre rule with `n x n` points on [-1, 1]^2 (xi runs
/// fastest), `None` unless `1 <= n <= 5`.
pub fn quad_gauss(n: usize) -> Option<Rule2D> {
    let (points, weights): (&'static [[f64; 2]], &'static [f64]) = match n {
        1 => (&Q1.0, &Q1.1),
        2 => (&Q2.0, &Q2.1),
        3 => (&Q3.0, &Q3.1),
        4 => (&Q4.0, &Q4.1),
        5 => (&Q5.0, &Q5.1),
        _ => return None,
    };
    Some(Rule2D { points, weights })
}

// ---------------------------------------------------------------- triangles

/// The three points of an orbit `(a, a, 1 - 2a)` in area coordinates, as
/// (xi, eta) = (L1, L2).
const fn s21(a: f64, b: f64) -> [[f64; 2]; 3] {
    [[a, a], [b, a], [a, b]]
}

/// The six points of an orbit `(a, b, c)`, all permutations, as (L1, L2).
const fn s111(a: f64, b: f64, c: f64) -> [[f64; 2]; 6] {
    [[a, b], [b, c], [c, a], [b, a], [a, c], [c, b]]
}

const T1_X: [[f64; 2]; 1] = [[1.0 / 3.0, 1.0 / 3.0]];
const T1_W: [f64; 1] = [0.5];

// Strang-Fix, degree 2: orbit a = 1/6.
const T2_X: [[f64; 2]; 3] = s21(1.0 / 6.0, 2.0 / 3.0);
const T2_W: [f64; 3] = [1.0 / 6.0; 3];

// Dunavant degree 4, 6 points (two S21 orbits).
const D4_A1: f64 = 0.4459484909159649;
const D4_B1: f64 = 0.10810301816807023;
const D4_W1: f64 = 0.11169079483900574;
const D4_A2: f64 = 0.09157621350977074;
const D4_B2: f64 = 0.8168475729804585;
const D4_W2: f64 = 0.054975871827660935;
const T4_X: [[f64; 2]; 6] = {
    let (a, b) = (s21(D4_A1, D4_B1), s21(D4_A2, D4_B2));
    [a[0], a[1], a[2], b[0], b[1], b[2]]
};
const T4_W: [f64; 6] = [D4_W1, D4_W1, D4_W1, D4_W2, D4_W2, D4_W2];

// Radon / Dunavant degree 5, 7 points: centroid and two S21 orbits with
// a = (6 -+ sqrt 15) / 21, weights (155 -+ sqrt 15) / 2400, centroid 9/80.
const D5_A1: f64 = 0.10128650732345634;
const D5_B1: f64 = 0.7974269853530873;
const D5_W1: f64 = 0.06296959027241357;
const D5_A2: f64 = 0.4701420641051151;
const D5_B2: f64 = 0.05971587178976982;
const D5_W2: f64 = 0.0661970763942531;
const T5_X: [[f64; 2]; 7] = {
    let (a, b) = (s21(D5_A1, D5_B1), s21(D5_A2, D5_B2));
    [[1.0 / 3.0, 1.0 / 3.0], a[0], a[1], a[2], b[0], b[1], b[2]]
};
const T5_W: [f64; 7] = [0.1125, D5_W1, D5_W1, D5_W1, D5_W2, D5_W2, D5_W2];

// Dunavant degree 6, 12 points: two S21 orbits and one S111 orbit.
const D6_A1: f64 = 0.24928674517091043;
const D6_B1: f64 = 0.5014265096581791;
const D6_W1: f64 = 0.058393137863189684;
const D6_A2: f64 = 0.06308901449150223;
const D6_B2: f64 = 0.8738219710169955;
const D6_W2: f64 = 0.02542245318510341;
const D6_A3: f64 = 0.053145049844816945;
const D6_B3: f64 = 0.3103524510337844;
const D6_C3: f64 = 0.6365024991213987;
const D6_W3: f64 = 0.041425537809186785;
const T6_X: [[f64; 2]; 12] = {
    let (a, b, c) = (s21(D6_A1, D6_B1), s21(D6_A2, D6_B2), s111(D6_A3, D6_B3, D6_C3));
    [
        a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], c[3], c[4], c[5],
    ]
};
const T6_W: [f64; 12] = [
    D6_W1, D6_W1, D6_W1, D6_W2, D6_W2, D6_W2, D6_W3, D6_W3, D6_W3, D6_W3, D6_W3, D6_W3,
];

/// The cheapest rule of this module exact for polynomials of total degree
/// `degree` on the reference triangle (0,0), (1,0), (0,1); weights sum to 1/2.
/// `None` unless `1 <= degree <= 6`.
///
/// | degree | points | rule |
/// |---|---|---|
/// | 1 | 1 | centroid |
/// | 2 | 3 | Strang-Fix, interior points (1/6, 1/6, 2/3) |
/// | 3, 4 | 6 | Dunavant degree 4 (a positive 6-point rule beats the 4-point degree-3 rule with its negative weight) |
/// | 5 | 7 | Radon / Dunavant degree 5 |
/// | 6 | 12 | Dunavant degree 6 |
pub fn triangle(degree: usize) -> Option<Rule2D> {
    let (points, weights): (&'static [[f64; 2]], &'static [f64]) = match degree {
        1 => (&T1_X, &T1_W),
        2 => (&T2_X, &T2_W),
        3 | 4 => (&T4_X, &T4_W),
        5 => (&T5_X, &T5_W),
        6 => (&T6_X, &T6_W),
        _ => return None,
    };
    Some(Rule2D { points, weights })
}

/// The rule used for the stiffness `Integral(B^T D B r dr dz)` of each family.
///
/// `B = B0 + B1 / r` where `B0` holds the derivatives dN and `B1` the values N
/// (the hoop and circumferential terms), so for a straight-sided element
/// (constant Jacobian for triangles, affine for parallelograms)
/// `B^T D B r = B0^T D B0 r + (B0^T D B1 + B1^T D B0) + B1^T D B1 / r`: the
/// first two parts are polynomials, the last is rational and no rule
/// integrates it exactly. The choice integrates the polynomial parts exactly
/// and gives a full-rank matrix (no spurious zero-energy modes) for every
/// harmonic:
///
/// | family | rule | polynomial degree of `B0^T D B0 r`, `B0^T D B1` |
/// |---|---|---|
/// | T3 | [`triangle`]`(2)`, 3 points | 1, 1 (one centroid point would leave a spurious mode for m = 0: 4 strains at one point for 5 deformation modes) |
/// | T6 | [`triangle`]`(4)`, 6 points | 3, 3 (degree 4 for the `N N / r` part) |
/// | Q4 | [`quad_gauss`]`(2)`, 2 x 2 | per direction 3 |
/// | Q8, Q9 | [`quad_gauss`]`(3)`, 3 x 3 | per direction 5 |
///
/// Every point is interior, so no Gauss point sits on the axis r = 0.
pub fn default_rule(kind: CellKind) -> Rule2D {
    let rule = match kind {
        CellKind::Tri3 => triangle(2),
        CellKind::Tri6 => triangle(4),
        CellKind::Quad4 => quad_gauss(2),
        CellKind::Quad8 | CellKind::Quad9 => quad_gauss(3),
    };
    rule.expect("the default rules exist")
}
