//! The 3D half model of Scene P built from the gmsh mesh of
//! geo/pile_footing_3d.geo: quadratic tetrahedra in CalculiX node order,
//! the joint made by duplicating the nodes of the pile side, and the node
//! and face sets the deck needs.

use crate::ccx::msh::{check_mid_edges, read_volumes};
use anyhow::{bail, Context, Result};
use std::collections::HashMap;
use std::path::Path;

/// Pile radius a (m).
pub const A: f64 = 0.5;
/// z of the loaded pile end (m).
pub const Z_END: f64 = -1.5;
/// z of the pile head (bonded) (m).
pub const Z_HEAD: f64 = 1.0;
/// Outer radius of the footing (fixed) (m).
pub const R_OUT: f64 = 3.0;
/// Geometric tolerance for classifying nodes (m).
pub const TOL: f64 = 1e-6;

/// Which body an element belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Body {
    /// The pile (physical volume "pile").
    Pile,
    /// The footing (physical volume "footing").
    Footing,
}

/// Local faces of a C3D10 element, CalculiX numbering S1..S4, as indices of
/// the corner nodes (0-based) and of the mid-edge nodes in face order.
pub const TET_FACES: [([usize; 3], [usize; 3]); 4] = [
    ([0, 1, 2], [4, 5, 6]),
    ([0, 3, 1], [7, 8, 4]),
    ([1, 3, 2], [8, 9, 5]),
    ([2, 3, 0], [9, 7, 6]),
];

/// Mid-edge nodes of a C3D10 (indices 4..10) and the corners they join.
pub const TET_EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];

/// The 3D model: nodes, elements and sets, 0-based (CalculiX ids are +1).
#[derive(Clone, Debug)]
pub struct Model3d {
    /// Node coordinates.
    pub coords: Vec<[f64; 3]>,
    /// C3D10 connectivity in CalculiX order.
    pub tets: Vec<[usize; 10]>,
    /// Body of each element.
    pub body: Vec<Body>,
    /// Joint node pairs (pile node, footing copy) on r = a, 0 <= z < 1.
    pub joint_pairs: Vec<(usize, usize)>,
    /// Joint faces seen from the pile: (element, face 0..4).
    pub joint_faces_pile: Vec<(usize, usize)>,
    /// Joint faces seen from the footing: (element, face 0..4).
    pub joint_faces_footing: Vec<(usize, usize)>,
    /// Six-node triangles of the loaded end z = -1.5 (corners, then mids).
    pub end_faces: Vec<[usize; 6]>,
}

impl Model3d {
    /// Reads a gmsh MSH 4.1 file of geo/pile_footing_3d.geo (order 2).
    pub fn from_msh(path: &Path) -> Result<Model3d> {
        let v = read_volumes(
            path,
            [("pile", Body::Pile), ("footing", Body::Footing)],
            std::array::from_fn(|k| k),
            |e| {
                if e.gmsh_type != axijoint_mesh::msh::element_type::TET10 {
                    bail!(
                        "{}: volume element {} has gmsh type {}, expected 11 (10-node tetrahedron; mesh with order 2)",
                        path.display(),
                        e.tag,
                        e.gmsh_type
                    );
                }
                if e.nodes.len() != 10 {
                    bail!(
                        "{}: element {} has {} nodes, expected 10",
                        path.display(),
                        e.tag,
                        e.nodes.len()
                    );
                }
                Ok(())
            },
            "tetrahedra",
        )?;
        let mut tets = v.elements;
        for conn in &mut tets {
            // gmsh tet10 edge nodes: 4 (0,1), 5 (1,2), 6 (2,0), 7 (3,0),
            // 8 (3,2), 9 (3,1); CalculiX: ..., 8 (1,3), 9 (2,3).
            conn.swap(8, 9);
        }
        let (coords, body) = (v.coords, v.body);
        let mut m = Model3d {
            coords,
            tets,
            body,
            joint_pairs: Vec::new(),
            joint_faces_pile: Vec::new(),
            joint_faces_footing: Vec::new(),
            end_faces: Vec::new(),
        };
        m.check_elements()
            .with_context(|| format!("checking the tetrahedra of {}", path.display()))?;
        m.make_joint()
            .with_context(|| format!("making the joint in {}", path.display()))?;
        Ok(m)
    }

    /// Checks that each mid-edge node lies near the middle of its edge and
    /// that the Jacobian determinant of the quadratic map is positive at the
    /// corners and the centroid (so the node order is CalculiX's).
    pub fn check_elements(&self) -> Result<()> {
        for (e, t) in self.tets.iter().enumerate() {
            check_mid_edges(&self.coords, e, t, &TET_EDGES, 4)?;
            let x: Vec<[f64; 3]> = t.iter().map(|&n| self.coords[n]).collect();
            for xi in [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [0.25, 0.25, 0.25],
            ] {
                let d = tet10_det_j(&x, xi);
                if d <= 0.0 {
                    bail!("element {}: Jacobian determinant {d:e} <= 0 at {xi:?}", e + 1);
                }
            }
        }
        Ok(())
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.coords.len()
    }

    /// Bodies each node belongs to: bit 1 pile, bit 2 footing.
    pub fn node_bodies(&self) -> Vec<u8> {
        let mut b = vec![0u8; self.coords.len()];
        for (t, body) in self.tets.iter().zip(&self.body) {
            let bit = match body {
                Body::Pile => 1,
                Body::Footing => 2,
            };
            for &n in t {
                b[n] |= bit;
            }
        }
        b
    }

    /// Nodes on the symmetry plane y = 0.
    pub fn symmetry_nodes(&self) -> Vec<usize> {
        (0..self.coords.len())
            .filter(|&i| self.coords[i][1].abs() < TOL)
            .collect()
    }

    /// Nodes on the fixed outer surface r = 3.
    pub fn outer_nodes(&self) -> Vec<usize> {
        (0..self.coords.len())
            .filter(|&i| (radius(self.coords[i]) - R_OUT).abs() < TOL)
            .collect()
    }

    /// Finds the pile-side faces shared by a pile and a footing element,
    /// gives the footing its own copies of their nodes (except on the bonded
    /// head edge z = 1, where the joint ends like a crack tip, as in
    /// axijoint), and collects the loaded end faces.
    fn make_joint(&mut self) -> Result<()> {
        let mut faces: HashMap<[usize; 3], Vec<(usize, usize)>> = HashMap::new();
        for (e, t) in self.tets.iter().enumerate() {
            for (f, (c, _)) in TET_FACES.iter().enumerate() {
                let mut key = [t[c[0]], t[c[1]], t[c[2]]];
                key.sort_unstable();
                faces.entry(key).or_default().push((e, f));
            }
        }
        let mut keys: Vec<&[usize; 3]> = faces.keys().collect();
        keys.sort_unstable();
        let on_side = |n: usize| {
            let p = self.coords[n];
            (radius(p) - A).abs() < TOL && p[2] > -TOL && p[2] < Z_HEAD + TOL
        };
        let mut joint_nodes: Vec<usize> = Vec::new();
        let (mut end_faces, mut jfp, mut jff) = (Vec::new(), Vec::new(), Vec::new());
        for key in keys {
            let owners = &faces[key];
            match owners.as_slice() {
                [(e, f)] => {
                    if key.iter().all(|&n| (self.coords[n][2] - Z_END).abs() < TOL) {
                        end_faces.push(self.face_nodes(*e, *f));
                    }
                }
                [(e1, f1), (e2, f2)] => {
                    if self.body[*e1] == self.body[*e2] || !key.iter().all(|&n| on_side(n)) {
                        continue;
                    }
                    if key.iter().all(|&n| (self.coords[n][2] - Z_HEAD).abs() < TOL) {
                        continue;
                    }
                    let ((ep, fp), (ef, ff)) = if self.body[*e1] == Body::Pile {
                        ((*e1, *f1), (*e2, *f2))
                    } else {
                        ((*e2, *f2), (*e1, *f1))
                    };
                    jfp.push((ep, fp));
                    jff.push((ef, ff));
                    joint_nodes.extend(self.face_nodes(ep, fp));
                }
                _ => bail!("face {key:?} belongs to {} elements", owners.len()),
            }
        }
        self.end_faces = end_faces;
        self.joint_faces_pile = jfp;
        self.joint_faces_footing = jff;
        if self.joint_faces_pile.is_empty() {
            bail!("no pile-side faces between pile and footing elements");
        }
        if self.end_faces.is_empty() {
            bail!("no faces on the loaded end z = {Z_END}");
        }
        joint_nodes.sort_unstable();
        joint_nodes.dedup();
        let mut copy: HashMap<usize, usize> = HashMap::new();
        for n in joint_nodes {
            if (self.coords[n][2] - Z_HEAD).abs() < TOL {
                continue;
            }
            let c = self.coords.len();
            self.coords.push(self.coords[n]);
            copy.insert(n, c);
            self.joint_pairs.push((n, c));
        }
        for (t, b) in self.tets.iter_mut().zip(&self.body) {
            if *b == Body::Footing {
                for n in t.iter_mut() {
                    if let Some(&c) = copy.get(n) {
                        *n = c;
                    }
                }
            }
        }
        // A pile node still used by a footing element (other than on the
        // head edge) would mean the joint does not separate the bodies.
        let bodies = self.node_bodies();
        for &(p, _) in &self.joint_pairs {
            if bodies[p] != 1 {
                bail!("joint node {} still shared by both bodies", p + 1);
            }
        }
        Ok(())
    }

    /// The six nodes of face `f` of element `e` (corners, then mid-edges).
    pub fn face_nodes(&self, e: usize, f: usize) -> [usize; 6] {
        let t = &self.tets[e];
        let (c, m) = TET_FACES[f];
        [t[c[0]], t[c[1]], t[c[2]], t[m[0]], t[m[1]], t[m[2]]]
    }
}

/// sqrt(x^2 + y^2).
pub fn radius(p: [f64; 3]) -> f64 {
    p[0].hypot(p[1])
}

/// Jacobian determinant of a C3D10 (CalculiX order) at natural coordinates
/// `xi` (node 1 at the origin, 2, 3, 4 on the xi, eta, zeta axes).
pub fn tet10_det_j(x: &[[f64; 3]], xi: [f64; 3]) -> f64 {
    let l = [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]];
    let dl = [
        [-1.0, -1.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let mut dn = [[0.0; 3]; 10];
    for i in 0..4 {
        for d in 0..3 {
            dn[i][d] = (4.0 * l[i] - 1.0) * dl[i][d];
        }
    }
    for (k, &(i, j)) in TET_EDGES.iter().enumerate() {
        for d in 0..3 {
            dn[4 + k][d] = 4.0 * (l[i] * dl[j][d] + l[j] * dl[i][d]);
        }
    }
    let mut jac = [[0.0; 3]; 3];
    for a in 0..10 {
        for r in 0..3 {
            for c in 0..3 {
                jac[r][c] += x[a][r] * dn[a][c];
            }
        }
    }
    jac[0][0] * (jac[1][1] * jac[2][2] - jac[1][2] * jac[2][1])
        - jac[0][1] * (jac[1][0] * jac[2][2] - jac[1][2] * jac[2][0])
        + jac[0][2] * (jac[1][0] * jac[2][1] - jac[1][1] * jac[2][0])
}
