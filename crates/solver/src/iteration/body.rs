//! The plastic bodies of an iteration ([`Bodies`]): their cells, nodes and
//! Gauss points, and what a point does with a section's body values (its
//! strain, the nodal forces of a stress). The body part of a section's
//! values holds, per body node, `(U_r, U_z, U_theta, U'_r, U'_z,
//! U'_theta)`: the physical displacements at the section and their theta
//! derivatives ([`crate::elements::section`]).

use super::types::IterationError;
use crate::elements::section::{add_section_forces, section_strain};
use crate::elements::solid::volumetric_projection;
use crate::elements::CellValues;
use crate::linear::Model;
use crate::material::Elastic;
use crate::plasticity::YieldCriterion;

/// The body tangent at one (section, body point): the derivative of the
/// released stress `D eps - sigma(eps)` with respect to the strain, `D -
/// C` (C the consistent tangent of the return); `None` where the point
/// stays elastic (nothing released, derivative 0).
pub(super) type BodyTangent = Option<[[f64; 6]; 6]>;

/// Values per body node in a section's values.
pub(super) const BODY_VALUES: usize = 6;

/// A plastic cell: its nodes in [`Bodies::nodes`], its shape values at the
/// Gauss points, its first point and material.
pub(super) struct PlasticCell {
    /// Index into the mesh's cells.
    pub(super) cell: usize,
    /// The cell's nodes as indices into [`Bodies::nodes`].
    local: Vec<usize>,
    /// Shape values, gradients, radius and weight at its Gauss points.
    pub(super) values: CellValues,
    /// Index of its first point (points run cell by cell).
    pub(super) first: usize,
    /// Its material.
    pub(super) elastic: Elastic,
    /// The volumetric projection of its Gauss points (B-bar:
    /// [`crate::elements::solid::volumetric_projection`]).
    projection: nalgebra::DMatrix<f64>,
}

/// The plastic bodies of a model: every cell of a body with a yield
/// criterion, its Gauss points (`n_points`, cell by cell) and each point's
/// criterion there (`c_u(z)`).
pub(super) struct Bodies {
    /// Global indices of the nodes of the plastic cells (sorted).
    pub(super) nodes: Vec<usize>,
    /// The plastic cells.
    pub(super) cells: Vec<PlasticCell>,
    /// Each point's criterion.
    pub(super) criteria: Vec<YieldCriterion>,
}

impl Bodies {
    /// The plastic bodies of `model` (none: `None`).
    pub(super) fn new(model: &Model) -> Result<Option<Bodies>, IterationError> {
        let mesh = &model.mesh;
        if model.plasticity.iter().all(Option::is_none) {
            return Ok(None);
        }
        let mut nodes: Vec<usize> = mesh
            .cells
            .iter()
            .filter(|c| model.plasticity.get(c.body).is_some_and(Option::is_some))
            .flat_map(|c| c.nodes.iter().copied())
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        let mut where_ = vec![usize::MAX; mesh.nodes.len()];
        for (j, &k) in nodes.iter().enumerate() {
            where_[k] = j;
        }
        let mut cells = Vec::new();
        let mut criteria = Vec::new();
        for (index, cell) in mesh.cells.iter().enumerate() {
            let Some(Some(plasticity)) = model.plasticity.get(cell.body) else {
                continue;
            };
            let coords: Vec<[f64; 2]> = cell.nodes.iter().map(|&k| mesh.nodes[k]).collect();
            let mut values = CellValues::with_default_rule(cell.kind);
            values.reinit(cell.kind, &coords).map_err(|e| {
                IterationError::Setup(format!(
                    "cell {} of '{}': {e}",
                    cell.tag, mesh.bodies[cell.body].name
                ))
            })?;
            let first = criteria.len();
            for q in 0..values.n_points() {
                criteria.push(plasticity.at(values.position(q)[1]));
            }
            cells.push(PlasticCell {
                projection: volumetric_projection(&values),
                cell: index,
                local: cell.nodes.iter().map(|&k| where_[k]).collect(),
                values,
                first,
                elastic: model.materials[cell.body],
            });
        }
        Ok(Some(Bodies {
            nodes,
            cells,
            criteria,
        }))
    }

    /// Each Gauss point's position `(r, z)`, cell by cell.
    pub(super) fn positions(&self) -> Vec<[f64; 2]> {
        self.cells
            .iter()
            .flat_map(|c| (0..c.values.n_points()).map(|q| c.values.position(q)))
            .collect()
    }

    /// Each Gauss point's cell (index into the mesh's cells).
    pub(super) fn cells_of_points(&self) -> Vec<usize> {
        self.cells
            .iter()
            .flat_map(|c| std::iter::repeat_n(c.cell, c.values.n_points()))
            .collect()
    }

    /// Number of Gauss points.
    pub(super) fn n_points(&self) -> usize {
        self.criteria.len()
    }

    /// The strain at point `q` of `cell` from a section's body values
    /// `body` (`BODY_VALUES` per body node).
    pub(super) fn strain(&self, cell: &PlasticCell, q: usize, body: &[f64]) -> [f64; 6] {
        let mut u = [0.0; 27];
        let mut du = [0.0; 27];
        for (a, &j) in cell.local.iter().enumerate() {
            let v = &body[BODY_VALUES * j..BODY_VALUES * (j + 1)];
            u[3 * a..3 * a + 3].copy_from_slice(&v[..3]);
            du[3 * a..3 * a + 3].copy_from_slice(&v[3..]);
        }
        let n = 3 * cell.local.len();
        section_strain(&cell.values, q, &u[..n], &du[..n])
    }

    /// The strains of every point of `cell` from a section's body values
    /// `body`, their volumetric part projected (B-bar, as the cell's
    /// stiffness).
    pub(super) fn strains(&self, cell: &PlasticCell, body: &[f64]) -> Vec<[f64; 6]> {
        let nq = cell.values.n_points();
        let mut eps: Vec<[f64; 6]> = (0..nq).map(|q| self.strain(cell, q, body)).collect();
        let vol: Vec<f64> = eps.iter().map(|e| e[0] + e[1] + e[2]).collect();
        for (q, e) in eps.iter_mut().enumerate() {
            let bar: f64 = (0..nq).map(|k| cell.projection[(q, k)] * vol[k]).sum::<f64>() - vol[q];
            for c in e.iter_mut().take(3) {
                *c += bar / 3.0;
            }
        }
        eps
    }

    /// Adds the nodal forces (per radian) of the stresses `sigma` of every
    /// point of `cell` to a section's body values `out`: their mean stress
    /// projected (the transpose of [`Bodies::strains`]).
    pub(super) fn scatter_all(&self, cell: &PlasticCell, sigma: &mut [[f64; 6]], out: &mut [f64]) {
        let nq = sigma.len();
        let p: Vec<f64> = sigma.iter().map(|s| (s[0] + s[1] + s[2]) / 3.0).collect();
        for (q, s) in sigma.iter_mut().enumerate() {
            let bar: f64 = (0..nq).map(|k| cell.projection[(q, k)] * p[k]).sum::<f64>() - p[q];
            for c in s.iter_mut().take(3) {
                *c += bar;
            }
        }
        for (q, s) in sigma.iter().enumerate() {
            self.scatter(cell, q, s, out);
        }
    }

    /// Adds the nodal forces (per radian) of stress `sigma` at point `q` of
    /// `cell` to a section's body values `out`.
    pub(super) fn scatter(&self, cell: &PlasticCell, q: usize, sigma: &[f64; 6], out: &mut [f64]) {
        if *sigma == [0.0; 6] {
            return;
        }
        let mut fu = [0.0; 27];
        let mut fd = [0.0; 27];
        let n = 3 * cell.local.len();
        let v = &cell.values;
        add_section_forces(v, q, sigma, v.r(q) * v.weight(q), &mut fu[..n], &mut fd[..n]);
        for (a, &j) in cell.local.iter().enumerate() {
            let o = &mut out[BODY_VALUES * j..BODY_VALUES * (j + 1)];
            for c in 0..3 {
                o[c] += fu[3 * a + c];
                o[3 + c] += fd[3 * a + c];
            }
        }
    }
}

/// Kinds of basis factor a section's strain operator takes per DOF: the
/// basis `a` (r, z components) and `b` (theta), and their derivatives.
const KINDS: usize = 4;

/// The basis `(a, b)` of one harmonic and family at a section, and its
/// theta derivative `(a', b')`.
pub(super) type SectionBasis = ((f64, f64), (f64, f64));

impl Bodies {
    /// Subtracts the plastic bodies' part of the harmonic-diagonal tangent
    /// `(A T S)_mm` of one family from the assembled values of `K_m`
    /// (upper triangle, `pinned` equations skipped): `sum_q sum_s w_s B_s^T
    /// T_s B_s r |det J| w_q` with `B_s = B_U Phi_s + B_D Phi'_s`, the
    /// basis `basis[s] = ((a, b), (a', b'))` and `T_s` the symmetric part of
    /// each point's [`BodyTangent`] (index
    /// `s * points + q`; none: elastic there). The sections are summed per
    /// kind pair first (`T_kl = sum_s w_s k_s l_s T_s`), so a point costs the
    /// same at any number of sections.
    pub(super) fn subtract_tangent(
        &self,
        model: &Model,
        basis: &[SectionBasis],
        weights: &[f64],
        tangents: &[BodyTangent],
        pinned: &[bool],
        values: &mut [f64],
    ) {
        let n_b = self.n_points();
        let mut ke = nalgebra::DMatrix::<f64>::zeros(0, 0);
        for cell in &self.cells {
            let nd = 3 * cell.local.len();
            ke.resize_mut(nd, nd, 0.0);
            ke.fill(0.0);
            let nq = cell.values.n_points();
            let sections = weights.len();
            if (0..sections).all(|s| {
                tangents[s * n_b + cell.first..s * n_b + cell.first + nq]
                    .iter()
                    .all(Option::is_none)
            }) {
                continue;
            }
            let mut any = false;
            let ops_all = projected_operators(cell);
            for (q, ops) in ops_all.iter().enumerate() {
                let k = cell.first + q;
                // T_kl over the sections.
                let mut tk = [[[[0.0; 6]; 6]; KINDS]; KINDS];
                let mut yielding = false;
                for (s, (&((a, b), (da, db)), &w)) in basis.iter().zip(weights).enumerate() {
                    let Some(t) = &tangents[s * n_b + k] else { continue };
                    yielding = true;
                    let f = [a, b, da, db];
                    for (kk, row) in tk.iter_mut().enumerate() {
                        for (ll, m) in row.iter_mut().enumerate() {
                            let c = w * f[kk] * f[ll];
                            if c == 0.0 {
                                continue;
                            }
                            for i in 0..6 {
                                for j in 0..6 {
                                    m[i][j] += c * 0.5 * (t[i][j] + t[j][i]);
                                }
                            }
                        }
                    }
                }
                if !yielding {
                    continue;
                }
                any = true;
                let wq = cell.values.r(q) * cell.values.weight(q);
                // ke += wq sum_k C_k^T (sum_l T_kl C_l)
                for (kk, row) in tk.iter().enumerate() {
                    let mut y = vec![[0.0; 6]; nd];
                    for (ll, t) in row.iter().enumerate() {
                        for (col, c) in ops[ll].iter().enumerate() {
                            if *c == [0.0; 6] {
                                continue;
                            }
                            for i in 0..6 {
                                y[col][i] += (0..6).map(|j| t[i][j] * c[j]).sum::<f64>();
                            }
                        }
                    }
                    for (a, ca) in ops[kk].iter().enumerate() {
                        if *ca == [0.0; 6] {
                            continue;
                        }
                        for (b, yb) in y.iter().enumerate() {
                            ke[(a, b)] += wq * (0..6).map(|i| ca[i] * yb[i]).sum::<f64>();
                        }
                    }
                }
            }
            if any {
                ke.neg_mut();
                let nodes: Vec<usize> = cell.local.iter().map(|&j| self.nodes[j]).collect();
                crate::assembly::scatter(model.pattern(), &model.dofs, pinned, &nodes, &ke, values);
            }
        }
    }
}

/// The columns of the strain operators of point `q` per basis kind (`a`,
/// `b`, `a'`, `b'`; each `3 * nodes` columns of 6 strains, zero where the
/// kind does not act): `B_U` on r, z (a) and theta (b), `B_D` likewise
/// (the module doc of [`crate::elements::section`]).
fn strain_operators(values: &CellValues, q: usize) -> [Vec<[f64; 6]>; KINDS] {
    let (n, dn, r) = (values.n(q), values.dn(q), values.r(q));
    let nd = 3 * n.len();
    let mut ops: [Vec<[f64; 6]>; KINDS] = std::array::from_fn(|_| vec![[0.0; 6]; nd]);
    for (i, (ni, di)) in n.iter().zip(dn).enumerate() {
        let (nr, nz, h) = (di[0], di[1], ni / r);
        // B_U: u_r -> (e_r, e_th, g_rz), u_z -> (e_z, g_rz), u_th -> (g_rth, g_zth)
        ops[0][3 * i] = [nr, 0.0, h, nz, 0.0, 0.0];
        ops[0][3 * i + 1] = [0.0, nz, 0.0, nr, 0.0, 0.0];
        ops[1][3 * i + 2] = [0.0, 0.0, 0.0, 0.0, nr - h, nz];
        // B_D: u_r' -> g_rth, u_z' -> g_zth, u_th' -> e_th
        ops[2][3 * i] = [0.0, 0.0, 0.0, 0.0, h, 0.0];
        ops[2][3 * i + 1] = [0.0, 0.0, 0.0, 0.0, 0.0, h];
        ops[3][3 * i + 2] = [0.0, 0.0, h, 0.0, 0.0, 0.0];
    }
    ops
}

/// [`strain_operators`] of every point of `cell`, their volumetric part
/// projected (B-bar, as [`Bodies::strains`]).
fn projected_operators(cell: &PlasticCell) -> Vec<[Vec<[f64; 6]>; KINDS]> {
    let nq = cell.values.n_points();
    let mut ops: Vec<_> = (0..nq).map(|q| strain_operators(&cell.values, q)).collect();
    let nd = 3 * cell.local.len();
    for k in 0..KINDS {
        for col in 0..nd {
            let vol: Vec<f64> = ops
                .iter()
                .map(|o| o[k][col][0] + o[k][col][1] + o[k][col][2])
                .collect();
            for q in 0..nq {
                let bar: f64 = (0..nq).map(|j| cell.projection[(q, j)] * vol[j]).sum::<f64>() - vol[q];
                for v in ops[q][k][col].iter_mut().take(3) {
                    *v += bar / 3.0;
                }
            }
        }
    }
    ops
}

/// The Gauss points of the plastic bodies of `model`, each with its cell
/// (index into the mesh's cells) and position `(r, z)`, in the order of an
/// iteration's body fields (cells in mesh order); empty without plastic
/// bodies.
pub fn plastic_points(model: &Model) -> Result<Vec<(usize, [f64; 2])>, IterationError> {
    let Some(bodies) = Bodies::new(model)? else {
        return Ok(Vec::new());
    };
    Ok(bodies
        .cells_of_points()
        .into_iter()
        .zip(bodies.positions())
        .collect())
}
