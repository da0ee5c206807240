//! The 3D half model of the tutorial's pile in clay built from the gmsh mesh
//! of geo/pile_clay_3d.geo: 20-node hexahedra in CalculiX node order and
//! the node sets the deck needs, found from the coordinates.

use crate::ccx::msh::{check_mid_edges, read_volumes};
use anyhow::{bail, Context, Result};
use std::path::Path;

/// Pile radius a (m).
pub const A: f64 = 0.6;
/// Pile length L (m): the head at z = 0, the toe at z = -L.
pub const L: f64 = 6.0;
/// Outer radius of the soil (fixed) (m).
pub const R_OUT: f64 = 12.0;
/// Depth of the soil (its base fixed) (m).
pub const H: f64 = 24.0;
/// Geometric tolerance for classifying nodes (m).
pub const TOL: f64 = 1e-6;

/// gmsh's 20-node hexahedron.
pub const GMSH_HEX20: i32 = 17;

/// CalculiX (Abaqus) C3D20 node k is gmsh hex20 node `GMSH_TO_CCX[k]`:
/// the corners agree; gmsh numbers the edges (0,1), (0,3), (0,4), (1,2),
/// (1,5), (2,3), (2,6), (3,7), (4,5), (4,7), (5,6), (6,7), CalculiX the
/// bottom ring (0,1), (1,2), (2,3), (3,0), the top ring, then the verticals.
pub const GMSH_TO_CCX: [usize; 20] = [
    0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15,
];

/// Edges of a C3D20: the corners each mid-edge node 8..20 joins.
pub const HEX_EDGES: [(usize, usize); 12] = [
    (0, 1),
    (1, 2),
    (2, 3),
    (3, 0),
    (4, 5),
    (5, 6),
    (6, 7),
    (7, 4),
    (0, 4),
    (1, 5),
    (2, 6),
    (3, 7),
];

/// Which body an element belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Body {
    /// The pile (physical volume "pile"), elastic.
    Pile,
    /// The clay (physical volume "soil"), Mises perfectly plastic.
    Soil,
}

/// The 3D model: nodes and elements, 0-based (CalculiX ids are +1).
#[derive(Clone, Debug)]
pub struct HexModel {
    /// Node coordinates.
    pub coords: Vec<[f64; 3]>,
    /// C3D20 connectivity in CalculiX order.
    pub hexes: Vec<[usize; 20]>,
    /// Body of each element.
    pub body: Vec<Body>,
}

impl HexModel {
    /// Reads a gmsh MSH 4.1 file of geo/pile_clay_3d.geo (order 2,
    /// incomplete: 20-node hexahedra).
    pub fn from_msh(path: &Path) -> Result<HexModel> {
        let v = read_volumes(
            path,
            [("pile", Body::Pile), ("soil", Body::Soil)],
            GMSH_TO_CCX,
            |e| {
                if e.gmsh_type != GMSH_HEX20 || e.nodes.len() != 20 {
                    bail!(
                        "{}: volume element {} has gmsh type {} ({} nodes), expected 17 (20-node hexahedron; \
                         mesh with order 2, SecondOrderIncomplete)",
                        path.display(),
                        e.tag,
                        e.gmsh_type,
                        e.nodes.len()
                    );
                }
                Ok(())
            },
            "hexahedra",
        )?;
        let mut m = HexModel {
            coords: v.coords,
            hexes: v.elements,
            body: v.body,
        };
        m.orient()
            .with_context(|| format!("checking the hexahedra of {}", path.display()))?;
        Ok(m)
    }

    /// Checks that each mid-edge node lies near the middle of its edge and
    /// turns every element whose corners are numbered clockwise (a negative
    /// Jacobian at the centre: the extrusion downward) the right way round,
    /// by swapping its bottom and top faces.
    pub fn orient(&mut self) -> Result<()> {
        for e in 0..self.hexes.len() {
            let t = self.hexes[e];
            check_mid_edges(&self.coords, e, &t, &HEX_EDGES, 8)?;
            let corners: Vec<[f64; 3]> = t[..8].iter().map(|&n| self.coords[n]).collect();
            let d = hex8_det_j_centre(&corners);
            if d == 0.0 || !d.is_finite() {
                bail!("element {}: degenerate (Jacobian {d:e} at the centre)", e + 1);
            }
            if d < 0.0 {
                let mut f = [0usize; 20];
                let order = [
                    4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15, 8, 9, 10, 11, 16, 17, 18, 19,
                ];
                for (k, &o) in order.iter().enumerate() {
                    f[k] = t[o];
                }
                self.hexes[e] = f;
            }
        }
        Ok(())
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.coords.len()
    }

    /// Nodes of the elements of `body`.
    fn body_nodes(&self, body: Body) -> Vec<bool> {
        let mut on = vec![false; self.coords.len()];
        for (t, b) in self.hexes.iter().zip(&self.body) {
            if *b == body {
                for &n in t {
                    on[n] = true;
                }
            }
        }
        on
    }

    /// Nodes where `keep` holds, in order.
    fn nodes_where(&self, keep: impl Fn(usize, [f64; 3]) -> bool) -> Vec<usize> {
        (0..self.coords.len())
            .filter(|&i| keep(i, self.coords[i]))
            .collect()
    }

    /// The pile head: nodes of pile elements at z = 0 (r <= a, the rim
    /// included, as axijoint's pile_head curve includes its end r = a).
    pub fn head_nodes(&self) -> Vec<usize> {
        let pile = self.body_nodes(Body::Pile);
        self.nodes_where(|i, p| pile[i] && p[2].abs() < TOL)
    }

    /// Nodes on the symmetry plane y = 0.
    pub fn symmetry_nodes(&self) -> Vec<usize> {
        self.nodes_where(|_, p| p[1].abs() < TOL)
    }

    /// Nodes on the fixed outer side r = R.
    pub fn side_nodes(&self) -> Vec<usize> {
        self.nodes_where(|_, p| (p[0].hypot(p[1]) - R_OUT).abs() < 1e-4 * R_OUT)
    }

    /// Nodes on the fixed base z = -H.
    pub fn base_nodes(&self) -> Vec<usize> {
        self.nodes_where(|_, p| (p[2] + H).abs() < TOL)
    }

    /// Volume of the elements of `body` (corner hexahedra, 2x2x2 Gauss;
    /// for checks: the half model's soil is pi R^2 H / 2 less the pile).
    pub fn volume(&self, body: Body) -> f64 {
        let g = 1.0 / 3f64.sqrt();
        let mut v = 0.0;
        for (t, b) in self.hexes.iter().zip(&self.body) {
            if *b != body {
                continue;
            }
            let x: Vec<[f64; 3]> = t[..8].iter().map(|&n| self.coords[n]).collect();
            for xi in [-g, g] {
                for eta in [-g, g] {
                    for zeta in [-g, g] {
                        v += hex8_det_j(&x, [xi, eta, zeta]);
                    }
                }
            }
        }
        v
    }
}

/// Natural coordinates of the corners of a hexahedron (Abaqus order).
const CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// Jacobian determinant of the trilinear map of the corners `x` at `xi`.
pub fn hex8_det_j(x: &[[f64; 3]], xi: [f64; 3]) -> f64 {
    let mut j = [[0.0; 3]; 3];
    for (a, c) in CORNERS.iter().enumerate() {
        let f = [
            (1.0 + c[0] * xi[0]) / 2.0,
            (1.0 + c[1] * xi[1]) / 2.0,
            (1.0 + c[2] * xi[2]) / 2.0,
        ];
        let dn = [
            c[0] / 2.0 * f[1] * f[2],
            f[0] * c[1] / 2.0 * f[2],
            f[0] * f[1] * c[2] / 2.0,
        ];
        for r in 0..3 {
            for s in 0..3 {
                j[r][s] += x[a][r] * dn[s];
            }
        }
    }
    j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1]) - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0])
}

/// [`hex8_det_j`] at the centre.
pub fn hex8_det_j_centre(x: &[[f64; 3]]) -> f64 {
    hex8_det_j(x, [0.0, 0.0, 0.0])
}
