//! Shape functions of the meridional elements, gmsh node order.
//!
//! One file per shape ([`Tri3`], [`Tri6`], [`Qua4`], [`Qua8`], [`Qua9`],
//! [`Lin2`], [`Lin3`]), each with its node diagram, reference coordinates and
//! functions that fill caller-owned buffers (no allocation). [`CellKind`] and
//! [`EdgeKind`] dispatch to them:
//!
//! ```
//! use axijoint_mesh::CellKind;
//! let kind = CellKind::Quad8;
//! let mut n = [0.0; 9];
//! kind.eval_n([0.3, -0.2], &mut n);
//! let sum: f64 = n[..kind.n_nodes()].iter().sum();
//! assert!((sum - 1.0).abs() < 1e-14);
//! ```
//!
//! References: triangles on (0,0), (1,0), (0,1); quadrilaterals on
//! [-1, 1]^2; lines on [-1, 1] (ends, then middle).

mod lin2;
mod lin3;
mod qua4;
mod qua8;
mod qua9;
mod tri3;
mod tri6;

pub use lin2::Lin2;
pub use lin3::Lin3;
pub use qua4::Qua4;
pub use qua8::Qua8;
pub use qua9::Qua9;
pub use tri3::Tri3;
pub use tri6::Tri6;

use crate::{CellKind, EdgeKind};

/// The largest number of nodes of a cell (Q9): size of stack buffers.
pub const MAX_CELL_NODES: usize = 9;

/// The largest number of nodes of an edge (L3).
pub const MAX_EDGE_NODES: usize = 3;

impl CellKind {
    /// Reference coordinates (xi, eta) of the nodes, gmsh order.
    pub fn ref_coords(self) -> &'static [[f64; 2]] {
        match self {
            CellKind::Tri3 => &Tri3::REF_COORDS,
            CellKind::Tri6 => &Tri6::REF_COORDS,
            CellKind::Quad4 => &Qua4::REF_COORDS,
            CellKind::Quad8 => &Qua8::REF_COORDS,
            CellKind::Quad9 => &Qua9::REF_COORDS,
        }
    }

    /// True for the triangle families (reference triangle (0,0), (1,0), (0,1)).
    pub const fn is_triangle(self) -> bool {
        matches!(self, CellKind::Tri3 | CellKind::Tri6)
    }

    /// Reference coordinates of the centre: (1/3, 1/3) or (0, 0).
    pub const fn ref_centre(self) -> [f64; 2] {
        if self.is_triangle() {
            [1.0 / 3.0, 1.0 / 3.0]
        } else {
            [0.0, 0.0]
        }
    }

    /// Shape functions `N_i(xi)` into `n[..self.n_nodes()]`.
    ///
    /// # Panics
    /// If `n` is shorter than [`CellKind::n_nodes`].
    pub fn eval_n(self, xi: [f64; 2], n: &mut [f64]) {
        match self {
            CellKind::Tri3 => Tri3::eval_n(xi, n),
            CellKind::Tri6 => Tri6::eval_n(xi, n),
            CellKind::Quad4 => Qua4::eval_n(xi, n),
            CellKind::Quad8 => Qua8::eval_n(xi, n),
            CellKind::Quad9 => Qua9::eval_n(xi, n),
        }
    }

    /// Reference derivatives `[dN_i/dxi, dN_i/deta]` into `dn[..self.n_nodes()]`.
    ///
    /// # Panics
    /// If `dn` is shorter than [`CellKind::n_nodes`].
    pub fn eval_dn(self, xi: [f64; 2], dn: &mut [[f64; 2]]) {
        match self {
            CellKind::Tri3 => Tri3::eval_dn(xi, dn),
            CellKind::Tri6 => Tri6::eval_dn(xi, dn),
            CellKind::Quad4 => Qua4::eval_dn(xi, dn),
            CellKind::Quad8 => Qua8::eval_dn(xi, dn),
            CellKind::Quad9 => Qua9::eval_dn(xi, dn),
        }
    }
}

impl EdgeKind {
    /// Reference coordinates s of the nodes: ends, then middle.
    pub fn ref_coords(self) -> &'static [f64] {
        match self {
            EdgeKind::Lin2 => &Lin2::REF_COORDS,
            EdgeKind::Lin3 => &Lin3::REF_COORDS,
        }
    }

    /// Shape functions `N_i(s)` into `n[..self.n_nodes()]`.
    ///
    /// # Panics
    /// If `n` is shorter than [`EdgeKind::n_nodes`].
    pub fn eval_n(self, s: f64, n: &mut [f64]) {
        match self {
            EdgeKind::Lin2 => Lin2::eval_n(s, n),
            EdgeKind::Lin3 => Lin3::eval_n(s, n),
        }
    }

    /// Derivatives `dN_i/ds` into `dn[..self.n_nodes()]`.
    ///
    /// # Panics
    /// If `dn` is shorter than [`EdgeKind::n_nodes`].
    pub fn eval_dn(self, s: f64, dn: &mut [f64]) {
        match self {
            EdgeKind::Lin2 => Lin2::eval_dn(s, dn),
            EdgeKind::Lin3 => Lin3::eval_dn(s, dn),
        }
    }
}
