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
use faer::linalg::matmul::matmul;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, MatMut, MatRef, Par};

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
pub(super) const KINDS: usize = 4;

/// The kind pairs `(k, l)`, `k <= l`.
const PAIRS: [(usize, usize); 10] = [
    (0, 0),
    (0, 1),
    (0, 2),
    (0, 3),
    (1, 1),
    (1, 2),
    (1, 3),
    (2, 2),
    (2, 3),
    (3, 3),
];

/// The basis of one harmonic m and family at the sections: its four kinds
/// `(a, b, a', b')` are each `alpha_k u + beta_k v` with `(u, v) = (cos m
/// theta, sin m theta)` (`(1, 0)` at m = 0), so a sum over the sections of
/// `w_s k_s l_s T_s` (w the section weights) needs only the three sums of
/// `w u^2 T_s`, `w u v T_s`, `w v^2 T_s`.
pub(super) struct SectionBasis {
    /// `w (u^2, u v, v^2)` per section.
    products: Vec<[f64; 3]>,
    /// `alpha_k` and `beta_k` per kind.
    pub(super) alpha: [f64; KINDS],
    pub(super) beta: [f64; KINDS],
}

impl SectionBasis {
    /// From the kinds' values `f(theta)` at the sections `theta` of
    /// weights `weight`: alpha at theta = 0, beta at `pi / 2m` (none at m =
    /// 0).
    pub(super) fn new(m: u32, theta: &[f64], weight: &[f64], f: impl Fn(f64) -> [f64; KINDS]) -> Self {
        let mf = f64::from(m);
        let uv: Vec<(f64, f64)> = theta
            .iter()
            .map(|&t| {
                if m == 0 {
                    (1.0, 0.0)
                } else {
                    ((mf * t).cos(), (mf * t).sin())
                }
            })
            .collect();
        let products = uv
            .iter()
            .zip(weight)
            .map(|(&(u, v), &w)| [w * u * u, w * u * v, w * v * v])
            .collect();
        let alpha = f(0.0);
        let beta = if m == 0 {
            [0.0; KINDS]
        } else {
            f(std::f64::consts::FRAC_PI_2 / mf)
        };
        SectionBasis {
            products,
            alpha,
            beta,
        }
    }
}

impl Bodies {
    /// Per cell with a yielding point in `tangents`, the stacked strain
    /// operators `[C_a; C_b; C_a'; C_b']` (24 x 3 nodes, column-major) of
    /// each of its points, the volumetric part projected
    /// ([`projected_operators`]); computed once per linearization for
    /// every harmonic's [`Bodies::subtract_tangent`].
    pub(super) fn tangent_operators(&self, tangents: &[BodyTangent]) -> Vec<Option<Vec<f64>>> {
        let n_b = self.n_points();
        let sections = tangents.len() / n_b.max(1);
        self.cells
            .iter()
            .map(|cell| {
                let nq = cell.values.n_points();
                let yielding = (0..sections).any(|s| {
                    tangents[s * n_b + cell.first..s * n_b + cell.first + nq]
                        .iter()
                        .any(Option::is_some)
                });
                yielding.then(|| {
                    let nd = 3 * cell.local.len();
                    let n = 6 * KINDS;
                    let mut c = vec![0.0; nq * n * nd];
                    for (q, ops) in projected_operators(cell).iter().enumerate() {
                        for (kk, op) in ops.iter().enumerate() {
                            for (col, v) in op.iter().enumerate() {
                                for (i, vi) in v.iter().enumerate() {
                                    c[q * n * nd + col * n + 6 * kk + i] = *vi;
                                }
                            }
                        }
                    }
                    c
                })
            })
            .collect()
    }

    /// Subtracts the plastic bodies' part of the harmonic-diagonal tangent
    /// `(A T S)_mm` of one family from the assembled values of `K_m`
    /// (upper triangle, `pinned` equations skipped): `sum_q sum_s w_s B_s^T
    /// T_s B_s r |det J| w_q` with `B_s = B_U Phi_s + B_D Phi'_s` (the
    /// kinds of `basis`) and `T_s` the symmetric part of each point's
    /// [`BodyTangent`] (index `s * points + q`; none: elastic there). The
    /// sections are summed first, three sums per point
    /// ([`SectionBasis`]), so a point costs about the same at any number
    /// of sections.
    pub(super) fn subtract_tangent(
        &self,
        model: &Model,
        basis: &SectionBasis,
        tangents: &[BodyTangent],
        operators: &[Option<Vec<f64>>],
        pinned: &[bool],
        values: &mut [f64],
    ) {
        let n_b = self.n_points();
        let mut ke = nalgebra::DMatrix::<f64>::zeros(0, 0);
        // The tangents per kind pair `T_kl` as one 24 x 24 matrix, and its
        // product with a point's stacked operators C.
        let mut tc = nalgebra::DMatrix::<f64>::zeros(0, 0);
        let mut t = nalgebra::DMatrix::<f64>::zeros(6 * KINDS, 6 * KINDS);
        for (cell, ops) in self.cells.iter().zip(operators) {
            let Some(ops) = ops else { continue };
            let nd = 3 * cell.local.len();
            ke.resize_mut(nd, nd, 0.0);
            ke.fill(0.0);
            tc.resize_mut(6 * KINDS, nd, 0.0);
            let mut any = false;
            for (q, c) in ops.chunks_exact(6 * KINDS * nd).enumerate() {
                let k = cell.first + q;
                // S = sum_s w_s (u^2, u v, v^2)_s sym(T_s).
                let mut sums = [[0.0; 36]; 3];
                let mut yielding = false;
                for (s, f) in basis.products.iter().enumerate() {
                    let Some(ts) = &tangents[s * n_b + k] else {
                        continue;
                    };
                    yielding = true;
                    for i in 0..6 {
                        for j in 0..6 {
                            let sym = 0.5 * (ts[i][j] + ts[j][i]);
                            for (sum, fi) in sums.iter_mut().zip(f) {
                                sum[6 * i + j] += fi * sym;
                            }
                        }
                    }
                }
                if !yielding {
                    continue;
                }
                any = true;
                // T_kl = sum_s w_s k_s l_s sym(T_s), k <= l (T_lk = T_kl).
                let (al, be) = (&basis.alpha, &basis.beta);
                for &(kk, ll) in &PAIRS {
                    let f = [
                        al[kk] * al[ll],
                        al[kk] * be[ll] + be[kk] * al[ll],
                        be[kk] * be[ll],
                    ];
                    let mut m = [0.0; 36];
                    for (sum, fi) in sums.iter().zip(f) {
                        if fi != 0.0 {
                            for (mi, si) in m.iter_mut().zip(sum) {
                                *mi += fi * si;
                            }
                        }
                    }
                    for i in 0..6 {
                        for j in 0..6 {
                            t[(6 * kk + i, 6 * ll + j)] = m[6 * i + j];
                            t[(6 * ll + j, 6 * kk + i)] = m[6 * i + j];
                        }
                    }
                }
                // ke += wq C^T T C
                let wq = cell.values.r(q) * cell.values.weight(q);
                let n = 6 * KINDS;
                let cm = MatRef::from_column_major_slice(c, n, nd);
                let mut tcm = MatMut::from_column_major_slice_mut(tc.as_mut_slice(), n, nd);
                matmul(
                    tcm.rb_mut(),
                    Accum::Replace,
                    MatRef::from_column_major_slice(t.as_slice(), n, n),
                    cm,
                    1.0,
                    Par::Seq,
                );
                matmul(
                    MatMut::from_column_major_slice_mut(ke.as_mut_slice(), nd, nd),
                    Accum::Add,
                    cm.transpose(),
                    tcm.rb(),
                    wq,
                    Par::Seq,
                );
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fourier::{basis_derivative, Family, Sections};

    /// The three-sum form of [`SectionBasis`] reproduces every kind of the
    /// basis at every angle, harmonic, family and circle (the half circle
    /// zeroes `b` at m = 0).
    #[test]
    fn section_basis_reproduces_the_kinds() {
        for sections in [Sections::half_equispaced(9), Sections::full_equispaced(12)] {
            for m in 0..5 {
                for family in [Family::Symmetric, Family::Antisymmetric] {
                    let kinds = |t: f64| {
                        let ((a, b), (da, db)) = (sections.phi(m, family, t), basis_derivative(m, family, t));
                        [a, b, da, db]
                    };
                    let basis = SectionBasis::new(m, &sections.theta, &sections.weight, kinds);
                    for &t in &sections.theta {
                        let mt = f64::from(m) * t;
                        let (u, v) = if m == 0 { (1.0, 0.0) } else { (mt.cos(), mt.sin()) };
                        for (k, want) in kinds(t).into_iter().enumerate() {
                            let got = basis.alpha[k] * u + basis.beta[k] * v;
                            assert!(
                                (got - want).abs() < 1e-12,
                                "m {m} {family:?} kind {k} at {t}: {got} vs {want}"
                            );
                        }
                    }
                }
            }
        }
    }
}
