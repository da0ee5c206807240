//! Sparsity pattern (once) and per-harmonic numeric assembly.
//!
//! The pattern is the upper triangle (row <= column) of the equation-space
//! matrix in compressed columns, built once from the element connectivity and
//! shared by every harmonic; each harmonic only fills a value array, either
//! element by element ([`scatter`]) or from the three arrays of
//! [`StiffnessTerms`] (`K_m = c_m (A + m B + m^2 C)`).

use crate::dofs::DofMap;
use crate::elements::{
    c_m, joint_stiffness, joint_stiffness_scaled, solid_stiffness, solid_stiffness_bbar,
    solid_stiffness_terms, solid_stiffness_terms_bbar, JointRule, JointSprings, SolidScratch,
};
use crate::material::Elastic;
use axijoint_mesh::{CellKind, Mesh};
use nalgebra::DMatrix;

/// Upper-triangular compressed-column pattern.
#[derive(Clone, Debug)]
pub struct Pattern {
    /// Order of the matrix (number of equations).
    pub n: usize,
    /// Column pointers, `n + 1` of them.
    pub col_ptr: Vec<usize>,
    /// Row indices, sorted within each column.
    pub row_idx: Vec<usize>,
}

/// Whether the non-empty `lo..hi` ranges follow each other from 0 to `n`.
fn consecutive(ranges: &[(usize, usize)], n: usize) -> bool {
    let mut next = 0;
    for &(lo, hi) in ranges.iter().filter(|r| r.0 < r.1) {
        if lo != next {
            return false;
        }
        next = hi;
    }
    next == n
}

impl Pattern {
    /// The pattern of all element couplings; `elements` yields each element's
    /// node list (joints: bottom nodes then top nodes). Built from the node
    /// graph: [`DofMap`] numbers the equations node by node, so a node's
    /// equations are one range and its sorted neighbours give a column's
    /// rows in order.
    pub fn new<'a>(dofs: &DofMap, elements: impl Iterator<Item = &'a [usize]>) -> Pattern {
        // The equations of each node: `lo..hi` (empty when all supported).
        let mut range = vec![(usize::MAX, 0usize); dofs.n_nodes];
        for (node, r) in range.iter_mut().enumerate() {
            for (e, _) in (3 * node..3 * node + 3).flat_map(|d| dofs.terms(d)) {
                *r = (r.0.min(e), r.1.max(e + 1));
            }
        }
        debug_assert!(consecutive(&range, dofs.n_eq));
        // Each node's neighbours (itself included: the diagonal, which pinned
        // rows need), sorted.
        let mut adj: Vec<Vec<usize>> = (0..dofs.n_nodes).map(|n| vec![n]).collect();
        for nodes in elements {
            for &a in nodes {
                let list = &mut adj[a];
                list.extend_from_slice(nodes);
                // Keep memory in check on large meshes.
                if list.len() > 256 {
                    list.sort_unstable();
                    list.dedup();
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(dofs.n_eq + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for (b, list) in adj.iter_mut().enumerate() {
            list.sort_unstable();
            list.dedup();
            let (lo, hi) = range[b];
            for e in lo..hi {
                for &a in list.iter() {
                    let (alo, ahi) = range[a];
                    row_idx.extend(alo..ahi.min(e + 1));
                }
                col_ptr.push(row_idx.len());
            }
        }
        debug_assert_eq!(col_ptr.len(), dofs.n_eq + 1);
        Pattern {
            n: dofs.n_eq,
            col_ptr,
            row_idx,
        }
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Position of entry (row, col), row <= col, in the value array.
    #[inline]
    pub fn slot(&self, row: usize, col: usize) -> usize {
        let (lo, hi) = (self.col_ptr[col], self.col_ptr[col + 1]);
        match self.row_idx[lo..hi].binary_search(&row) {
            Ok(i) => lo + i,
            Err(_) => panic!("entry ({row}, {col}) is not in the pattern"),
        }
    }

    /// `y = K x` for a symmetric matrix stored as this upper triangle.
    pub fn sym_matvec(&self, values: &[f64], x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for col in 0..self.n {
            let range = self.col_ptr[col]..self.col_ptr[col + 1];
            for (&row, &v) in self.row_idx[range.clone()].iter().zip(&values[range]) {
                y[row] += v * x[col];
                if row != col {
                    y[col] += v * x[row];
                }
            }
        }
    }
}

/// Linear joint properties of one interface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointModel {
    /// Elastic stiffnesses (the joint law's).
    pub springs: JointSprings,
    /// The stiffnesses assembled into K_m: `springs`, or for a stiff
    /// nonlinear joint solved by Newton a softer reference (the difference
    /// is released with the law's traction, see `iteration`).
    pub assembled: JointSprings,
    /// The normal spring an opening is measured with where the history
    /// law's shear strength fades ([`crate::joint_law::history_response`]):
    /// `min(k_eta, E / h)` for a nonlinear joint of a scene, whatever the
    /// method; `k_eta` by default.
    pub opening: f64,
    /// Integration rule.
    pub rule: JointRule,
}

impl JointModel {
    /// A joint whose springs are assembled as they are.
    pub fn new(springs: JointSprings, rule: JointRule) -> Self {
        JointModel {
            springs,
            assembled: springs,
            opening: springs.k_eta,
            rule,
        }
    }

    /// `k_assembled / k` per component `(xi, eta, theta)`: 1 for a joint
    /// assembled as it is (or a spring of 0), below 1 for a softened one.
    pub fn softening(&self) -> [f64; 3] {
        let (k, a) = (self.springs, self.assembled);
        [(a.k_xi, k.k_xi), (a.k_eta, k.k_eta), (a.k_theta, k.k_theta)].map(|(a, k)| {
            if k > 0.0 && a > 0.0 {
                a / k
            } else {
                1.0
            }
        })
    }
}

/// Per-thread buffers of the element loop.
pub(crate) struct ElementScratch {
    solid: SolidScratch,
    ke: DMatrix<f64>,
    coords: Vec<[f64; 2]>,
    nodes: Vec<usize>,
}

impl ElementScratch {
    pub(crate) fn new() -> Self {
        ElementScratch {
            solid: SolidScratch::new(CellKind::Quad9),
            ke: DMatrix::zeros(0, 0),
            coords: Vec::with_capacity(9),
            nodes: Vec::with_capacity(9),
        }
    }
}

/// Calls `f(nodes, K_e)` for every element (cells, then joint elements) with
/// its stiffness of harmonic `m`; joint element nodes are bottom then top.
pub(crate) fn for_each_element(
    mesh: &Mesh,
    (materials, mixed): (&[Elastic], &[bool]),
    joints: &[JointModel],
    m: u32,
    s: &mut ElementScratch,
    f: impl FnMut(&[usize], &DMatrix<f64>),
) {
    for_each_element_where(mesh, (materials, mixed), joints, m, s, |_| true, f);
}

/// [`for_each_element`] over the elements whose node list passes `keep`
/// (the others' matrices are not computed).
pub(crate) fn for_each_element_where(
    mesh: &Mesh,
    (materials, mixed): (&[Elastic], &[bool]),
    joints: &[JointModel],
    m: u32,
    s: &mut ElementScratch,
    keep: impl Fn(&[usize]) -> bool,
    mut f: impl FnMut(&[usize], &DMatrix<f64>),
) {
    for cell in &mesh.cells {
        if !keep(&cell.nodes) {
            continue;
        }
        s.coords.clear();
        s.coords.extend(cell.nodes.iter().map(|&n| mesh.nodes[n]));
        let stiffness = if mixed.get(cell.body).copied().unwrap_or(false) {
            solid_stiffness_bbar
        } else {
            solid_stiffness
        };
        stiffness(
            cell.kind,
            &s.coords,
            &materials[cell.body],
            m,
            &mut s.solid,
            &mut s.ke,
        );
        f(&cell.nodes, &s.ke);
    }
    for (joint, props) in mesh.joints.iter().zip(joints) {
        for el in &joint.elements {
            s.nodes.clear();
            s.nodes.extend_from_slice(&el.bottom);
            s.nodes.extend_from_slice(&el.top);
            if !keep(&s.nodes) {
                continue;
            }
            s.coords.clear();
            s.coords.extend(el.bottom.iter().map(|&n| mesh.nodes[n]));
            joint_stiffness(el.kind, &s.coords, &props.assembled, m, props.rule, &mut s.ke);
            f(&s.nodes, &s.ke);
        }
    }
}

/// Adds an element matrix into the value array (upper triangle), through the
/// DOF terms; contributions to `pinned` equations are skipped.
pub fn scatter(
    pattern: &Pattern,
    dofs: &DofMap,
    pinned: &[bool],
    nodes: &[usize],
    ke: &DMatrix<f64>,
    values: &mut [f64],
) {
    let nd = 3 * nodes.len();
    for a in 0..nd {
        let da = 3 * nodes[a / 3] + a % 3;
        for (ea, ca) in dofs.terms(da) {
            if pinned[ea] {
                continue;
            }
            for b in 0..nd {
                let k = ke[(a, b)];
                if k == 0.0 {
                    continue;
                }
                let db = 3 * nodes[b / 3] + b % 3;
                for (eb, cb) in dofs.terms(db) {
                    if ea <= eb && !pinned[eb] {
                        values[pattern.slot(ea, eb)] += ca * cb * k;
                    }
                }
            }
        }
    }
}

/// The stiffness of every harmonic from three arrays on the shared pattern:
/// `K_m = c_m (A + m B + m^2 C)` entry by entry, before the axis rows of
/// harmonic m are pinned. A solid's `B` matrix is linear in m
/// ([`solid_stiffness_terms`]) and a joint's stiffness is `c_m` times a
/// constant, so this is exact up to rounding. Costs `24 nnz` bytes.
#[derive(Clone, Debug)]
pub struct StiffnessTerms {
    /// `[A, B, C]` of each pattern entry (upper triangle, pattern order).
    values: Vec<[f64; 3]>,
    /// The materials, B-bar bodies and joints they were assembled with.
    materials: Vec<Elastic>,
    mixed: Vec<bool>,
    joints: Vec<JointModel>,
}

impl StiffnessTerms {
    /// Assembles `A`, `B` and `C` (no equation pinned) in one element loop.
    pub fn assemble(
        mesh: &Mesh,
        (materials, mixed): (&[Elastic], &[bool]),
        joints: &[JointModel],
        dofs: &DofMap,
        pattern: &Pattern,
    ) -> StiffnessTerms {
        let mut values = vec![[0.0; 3]; pattern.nnz()];
        let mut solid = SolidScratch::new(CellKind::Quad9);
        let mut ke = [DMatrix::zeros(0, 0), DMatrix::zeros(0, 0), DMatrix::zeros(0, 0)];
        let mut coords = Vec::with_capacity(9);
        for cell in &mesh.cells {
            coords.clear();
            coords.extend(cell.nodes.iter().map(|&n| mesh.nodes[n]));
            let terms = if mixed.get(cell.body).copied().unwrap_or(false) {
                solid_stiffness_terms_bbar
            } else {
                solid_stiffness_terms
            };
            terms(cell.kind, &coords, &materials[cell.body], &mut solid, &mut ke);
            scatter_terms(pattern, dofs, &cell.nodes, &ke, 3, &mut values);
        }
        let mut nodes = Vec::with_capacity(6);
        for (joint, props) in mesh.joints.iter().zip(joints) {
            for el in &joint.elements {
                nodes.clear();
                nodes.extend_from_slice(&el.bottom);
                nodes.extend_from_slice(&el.top);
                coords.clear();
                coords.extend(el.bottom.iter().map(|&n| mesh.nodes[n]));
                joint_stiffness_scaled(el.kind, &coords, &props.assembled, 1.0, props.rule, &mut ke[0]);
                scatter_terms(pattern, dofs, &nodes, &ke, 1, &mut values);
            }
        }
        StiffnessTerms {
            values,
            materials: materials.to_vec(),
            mixed: mixed.to_vec(),
            joints: joints.to_vec(),
        }
    }

    /// Whether these terms were assembled with `materials` (B-bar cells in
    /// the bodies `mixed`) and `joints`.
    pub fn matches(&self, (materials, mixed): (&[Elastic], &[bool]), joints: &[JointModel]) -> bool {
        self.materials == materials && self.mixed == mixed && self.joints == joints
    }

    /// The values of `K_m` on `pattern` with the rows and columns of the
    /// `pinned` equations zeroed (their diagonal is left for
    /// [`pin_axis_rows`]).
    pub fn harmonic(&self, pattern: &Pattern, m: u32, pinned: &[bool]) -> Vec<f64> {
        let (c, x) = (c_m(m), f64::from(m));
        let x2 = x * x;
        let mut out = vec![0.0; self.values.len()];
        for col in 0..pattern.n {
            if pinned[col] {
                continue;
            }
            let range = pattern.col_ptr[col]..pattern.col_ptr[col + 1];
            for ((o, t), &row) in out[range.clone()]
                .iter_mut()
                .zip(&self.values[range.clone()])
                .zip(&pattern.row_idx[range])
            {
                if !pinned[row] {
                    *o = c * (t[0] + x * t[1] + x2 * t[2]);
                }
            }
        }
        out
    }
}

/// Adds the first `n_terms` of the element matrices `ke` into the
/// corresponding terms of `values`, through the DOF terms (nothing pinned).
fn scatter_terms(
    pattern: &Pattern,
    dofs: &DofMap,
    nodes: &[usize],
    ke: &[DMatrix<f64>; 3],
    n_terms: usize,
    values: &mut [[f64; 3]],
) {
    let nd = 3 * nodes.len();
    for a in 0..nd {
        let da = 3 * nodes[a / 3] + a % 3;
        for (ea, ca) in dofs.terms(da) {
            for b in 0..nd {
                let k: [f64; 3] = std::array::from_fn(|t| if t < n_terms { ke[t][(a, b)] } else { 0.0 });
                if k == [0.0; 3] {
                    continue;
                }
                let db = 3 * nodes[b / 3] + b % 3;
                for (eb, cb) in dofs.terms(db) {
                    if ea <= eb {
                        let v = &mut values[pattern.slot(ea, eb)];
                        let f = ca * cb;
                        for t in 0..n_terms {
                            v[t] += f * k[t];
                        }
                    }
                }
            }
        }
    }
}

/// Sets the diagonal of each `pinned` equation (whose row and column are
/// already zero) to the mean |diagonal| of the free ones: an identity row
/// scaled like the matrix.
pub fn pin_axis_rows(pattern: &Pattern, pinned: &[bool], values: &mut [f64]) {
    let (mut sum, mut count) = (0.0, 0usize);
    for e in (0..pattern.n).filter(|&e| !pinned[e]) {
        sum += values[pattern.slot(e, e)].abs();
        count += 1;
    }
    let scale = if count == 0 { 1.0 } else { sum / count as f64 };
    for (e, &p) in pinned.iter().enumerate() {
        if p {
            values[pattern.slot(e, e)] = scale;
        }
    }
}
