//! Shape values and gradients of one cell at the points of a rule, computed
//! once per cell ([`CellValues::reinit`]) into reused buffers.
//!
//! | symbol | meaning (at point q) |
//! |---|---|
//! | `N_i` | shape value of node i ([`CellValues::n`]) |
//! | `dN_i` | physical gradient `[dN_i/dr, dN_i/dz]` ([`CellValues::dn`]) |
//! | `r`, `z` | the point's position `sum_i N_i x_i` ([`CellValues::r`], [`CellValues::position`]) |
//! | `det J` | Jacobian determinant of the map, signed ([`CellValues::det`]) |
//! | `w` | `w_q |det J|`: the area element dA of the meridional plane, with neither `r` nor `c_m` ([`CellValues::weight`]) |
//!
//! A ring integral is `c_m Integral(f r dA) = c_m sum_q f(q) r(q) w(q)`.
//! `w_q` is the rule's weight ([`CellValues::w_gauss`]).
//!
//! The reference tables (`N_i` and `dN_i/dxi` at the points) depend on the
//! kind and the rule only and are tabulated once; [`CellValues::reinit`]
//! maps them onto a cell, point by point with the step that
//! [`super::StrainPoint`] (one arbitrary point) takes too.

use axijoint_mesh::geometry::{derivatives_rz, interpolate, jacobian};
use axijoint_mesh::quadrature::{default_rule, Rule2D};
use axijoint_mesh::CellKind;
use std::fmt;

/// Why [`CellValues::reinit`] refused a cell (mesh validation rejects such
/// cells before a solve; this is the element layer's own check).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CellError {
    /// `det J` is zero or not finite at a point: the cell has no area there.
    Degenerate {
        /// The kind of the cell.
        kind: CellKind,
        /// The point.
        point: usize,
        /// Its `(r, z)`.
        position: [f64; 2],
        /// `det J` there.
        det: f64,
    },
    /// `det J` has opposite signs at two points: the cell is inverted
    /// (folded over itself).
    Folded {
        /// The kind of the cell.
        kind: CellKind,
        /// The points (the first one, and the first of the other sign).
        points: [usize; 2],
        /// `det J` at them.
        dets: [f64; 2],
    },
}

impl fmt::Display for CellError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            CellError::Degenerate {
                kind,
                point,
                position: [r, z],
                det,
            } => write!(
                f,
                "degenerate {} cell: det J = {det:e} at quadrature point {point}, (r, z) = ({r}, {z})",
                kind.name()
            ),
            CellError::Folded {
                kind,
                points: [a, b],
                dets: [da, db],
            } => write!(
                f,
                "inverted {} cell: det J is {da:e} at quadrature point {a} and {db:e} at point {b} (the element folds over itself)",
                kind.name()
            ),
        }
    }
}

impl std::error::Error for CellError {}

/// Shape values, physical gradients, positions and weights of one cell at
/// the points of a rule (see the module doc for the notation).
///
/// Build it once per kind and rule, then [`CellValues::reinit`] it for each
/// cell: nothing is allocated per cell unless the kind changes.
#[derive(Clone, Debug)]
pub struct CellValues {
    kind: CellKind,
    nn: usize,
    rule: Rule2D,
    /// `N_i` at point q: `n[q * nn + i]`.
    n: Vec<f64>,
    /// `[dN_i/dxi, dN_i/deta]` at point q: `dn_ref[q * nn + i]`.
    dn_ref: Vec<[f64; 2]>,
    /// `[dN_i/dr, dN_i/dz]` at point q: `dn[q * nn + i]` (after reinit).
    dn: Vec<[f64; 2]>,
    /// `(r, z)` of each point (after reinit).
    x: Vec<[f64; 2]>,
    /// `det J` at each point (after reinit).
    det: Vec<f64>,
    /// Sides of the cell's bounding box (after reinit).
    extent: [f64; 2],
}

impl CellValues {
    /// Tables of `kind` at the points of `rule` (to be mapped by
    /// [`CellValues::reinit`]).
    pub fn new(kind: CellKind, rule: Rule2D) -> Self {
        let mut values = CellValues {
            kind,
            nn: 0,
            rule,
            n: Vec::new(),
            dn_ref: Vec::new(),
            dn: Vec::new(),
            x: Vec::new(),
            det: Vec::new(),
            extent: [0.0; 2],
        };
        values.tabulate(kind, rule);
        values
    }

    /// Tables of `kind` at the points of its [`default_rule`].
    pub fn with_default_rule(kind: CellKind) -> Self {
        CellValues::new(kind, default_rule(kind))
    }

    /// Fills the reference tables of `kind` at the points of `rule`, reusing
    /// the buffers.
    fn tabulate(&mut self, kind: CellKind, rule: Rule2D) {
        let (nn, np) = (kind.n_nodes(), rule.len());
        self.kind = kind;
        self.nn = nn;
        self.rule = rule;
        self.n.resize(np * nn, 0.0);
        self.dn_ref.resize(np * nn, [0.0; 2]);
        self.dn.resize(np * nn, [0.0; 2]);
        self.x.resize(np, [0.0; 2]);
        self.det.resize(np, 0.0);
        for (q, xi) in rule.points.iter().enumerate() {
            kind.eval_n(*xi, &mut self.n[q * nn..(q + 1) * nn]);
            kind.eval_dn(*xi, &mut self.dn_ref[q * nn..(q + 1) * nn]);
        }
    }

    /// Makes these the tables of `kind` with its [`default_rule`], unless
    /// they already are for `kind` (then the rule is kept). The reference
    /// values ([`CellValues::n`]) are valid afterwards, the mapped ones after
    /// [`CellValues::reinit`].
    pub fn set_kind(&mut self, kind: CellKind) {
        if kind != self.kind {
            self.tabulate(kind, default_rule(kind));
        }
    }

    /// Maps the tables onto the cell of `kind` with nodes `coords` (gmsh
    /// order; at least `kind.n_nodes()` of them), first switching kind as
    /// [`CellValues::set_kind`] does. Either orientation is accepted.
    ///
    /// # Errors
    /// [`CellError::Degenerate`] if `det J` is zero or not finite at a
    /// point, [`CellError::Folded`] if it changes sign between points. The
    /// values are filled in either case.
    pub fn reinit(&mut self, kind: CellKind, coords: &[[f64; 2]]) -> Result<(), CellError> {
        self.set_kind(kind);
        let nn = self.nn;
        let coords = &coords[..nn];
        for q in 0..self.rule.len() {
            let (x, det) = map_point(
                kind,
                coords,
                &self.n[q * nn..(q + 1) * nn],
                &self.dn_ref[q * nn..(q + 1) * nn],
                &mut self.dn[q * nn..(q + 1) * nn],
            );
            self.x[q] = x;
            self.det[q] = det;
        }
        self.extent = cell_extent(coords);
        self.check()
    }

    /// The first degenerate point or sign change of `det J`.
    fn check(&self) -> Result<(), CellError> {
        let kind = self.kind;
        if let Some(q) = self.det.iter().position(|d| *d == 0.0 || !d.is_finite()) {
            return Err(CellError::Degenerate {
                kind,
                point: q,
                position: self.x[q],
                det: self.det[q],
            });
        }
        let first = self.det.first().copied().unwrap_or(1.0);
        match self.det.iter().position(|d| (*d > 0.0) != (first > 0.0)) {
            Some(q) => Err(CellError::Folded {
                kind,
                points: [0, q],
                dets: [first, self.det[q]],
            }),
            None => Ok(()),
        }
    }

    /// The cell kind of the tables.
    #[inline]
    pub fn kind(&self) -> CellKind {
        self.kind
    }

    /// The integration rule.
    #[inline]
    pub fn rule(&self) -> Rule2D {
        self.rule
    }

    /// The number of points.
    #[inline]
    pub fn n_points(&self) -> usize {
        self.rule.len()
    }

    /// `N_i` at point `q`, `kind.n_nodes()` values.
    #[inline]
    pub fn n(&self, q: usize) -> &[f64] {
        &self.n[q * self.nn..(q + 1) * self.nn]
    }

    /// `[dN_i/dr, dN_i/dz]` at point `q`.
    #[inline]
    pub fn dn(&self, q: usize) -> &[[f64; 2]] {
        &self.dn[q * self.nn..(q + 1) * self.nn]
    }

    /// The radius `r = sum_i N_i r_i` of point `q`.
    #[inline]
    pub fn r(&self, q: usize) -> f64 {
        self.x[q][0]
    }

    /// The position `(r, z)` of point `q`.
    #[inline]
    pub fn position(&self, q: usize) -> [f64; 2] {
        self.x[q]
    }

    /// `det J` at point `q` (negative for a clockwise cell).
    #[inline]
    pub fn det(&self, q: usize) -> f64 {
        self.det[q]
    }

    /// The rule's weight `w_q` of point `q`.
    #[inline]
    pub fn w_gauss(&self, q: usize) -> f64 {
        self.rule.weights[q]
    }

    /// `w = w_q |det J|` at point `q`: the area element, neither `r` nor
    /// `c_m` in it.
    #[inline]
    pub fn weight(&self, q: usize) -> f64 {
        self.rule.weights[q] * self.det[q].abs()
    }

    /// The diagonal of the cell's bounding box (the length scale of the
    /// on-axis test of the strains).
    #[inline]
    pub fn size(&self) -> f64 {
        self.extent[0].hypot(self.extent[1])
    }
}

/// Physical gradients into `dn_rz`, position and `det J` at one point of the
/// cell `coords` (exactly `kind.n_nodes()` nodes), from the shape values
/// `n` and reference derivatives `dn_ref` there.
pub(crate) fn map_point(
    kind: CellKind,
    coords: &[[f64; 2]],
    n: &[f64],
    dn_ref: &[[f64; 2]],
    dn_rz: &mut [[f64; 2]],
) -> ([f64; 2], f64) {
    let (jac, det) = jacobian(kind, coords, dn_ref);
    derivatives_rz(&jac, det, dn_ref, dn_rz);
    (interpolate(coords, n), det)
}

/// The sides `(dr, dz)` of the bounding box of `coords`; its diagonal is
/// `dr.hypot(dz)`.
pub(crate) fn cell_extent(coords: &[[f64; 2]]) -> [f64; 2] {
    let (lo, hi) = coords
        .iter()
        .fold(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]), |(lo, hi), x| {
            (
                [lo[0].min(x[0]), lo[1].min(x[1])],
                [hi[0].max(x[0]), hi[1].max(x[1])],
            )
        });
    [hi[0] - lo[0], hi[1] - lo[1]]
}
