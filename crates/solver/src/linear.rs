//! The linear model: pattern and symbolic factorization once, one numeric
//! Cholesky per harmonic, many right-hand sides per factor.

use crate::assembly::{for_each_element, scatter, ElementScratch, JointModel, Pattern};
use crate::dofs::DofMap;
use crate::material::Elastic;
use axijoint_mesh::Mesh;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Mat, Side};
use rayon::prelude::*;

/// Errors of the linear solve.
#[derive(Debug, thiserror::Error)]
pub enum SolveError {
    /// The stiffness of a harmonic is singular: a mechanism.
    #[error("harmonic {m}: the stiffness matrix is singular or nearly so ({detail}); the model can move without straining: {hint}")]
    Singular {
        /// Harmonic.
        m: u32,
        /// What was detected.
        detail: String,
        /// Which parts look unsupported.
        hint: String,
    },
    /// A model input does not fit the mesh.
    #[error("{0}")]
    Input(String),
    /// faer failed for a reason other than the matrix (memory).
    #[error("sparse factorization failed: {0}")]
    Factorization(String),
}

/// Sets faer's parallelism for this process to sequential inside each
/// factorization and solve: the harmonics already run in parallel (rayon),
/// and measured on Scene P (docs/performance.md) one harmonic factorizes 3x
/// faster sequentially at 1e4 DOF, 1.4x at 1e5 and 1.2x at 5e5 (medians of
/// interleaved runs), with less CPU; with all harmonics in parallel the two
/// modes are within 5 %.
/// Called once by the `axijoint` binary; a library user may choose otherwise.
pub fn prefer_harmonic_parallelism() {
    faer::set_global_parallelism(faer::Par::Seq);
}

/// Numeric factor of one harmonic.
pub struct HarmonicFactor {
    /// Harmonic m.
    pub m: u32,
    llt: Llt<usize, f64>,
    pinned: Vec<bool>,
}

/// A mesh with materials, joints and supports, ready to factorize.
pub struct Model {
    /// The mesh (joints inserted).
    pub mesh: Mesh,
    /// Material of each body (index as `mesh.bodies`).
    pub materials: Vec<Elastic>,
    /// Linear properties of each joint (index as `mesh.joints`).
    pub joints: Vec<JointModel>,
    /// Unknown numbering.
    pub dofs: DofMap,
    /// Support flags per node DOF.
    pub fixed: Vec<bool>,
    pattern: Pattern,
    symbolic: SymbolicLlt<usize>,
}

impl Model {
    /// Numbers the unknowns, builds the pattern and the symbolic Cholesky.
    pub fn new(
        mesh: Mesh,
        materials: Vec<Elastic>,
        joints: Vec<JointModel>,
        fixed: Vec<bool>,
    ) -> Result<Model, SolveError> {
        if materials.len() != mesh.bodies.len() {
            return Err(SolveError::Input(format!(
                "{} materials for {} bodies",
                materials.len(),
                mesh.bodies.len()
            )));
        }
        if joints.len() != mesh.joints.len() {
            return Err(SolveError::Input(format!(
                "{} joint properties for {} joints",
                joints.len(),
                mesh.joints.len()
            )));
        }
        let dofs = DofMap::new(&mesh, &fixed);
        if dofs.n_eq == 0 {
            return Err(SolveError::Input(
                "every degree of freedom is supported: nothing to solve".into(),
            ));
        }
        let joint_nodes: Vec<Vec<usize>> = mesh
            .joints
            .iter()
            .flat_map(|j| j.elements.iter())
            .map(|e| e.bottom.iter().chain(&e.top).copied().collect())
            .collect();
        let pattern = Pattern::new(
            &dofs,
            mesh.cells
                .iter()
                .map(|c| c.nodes.as_slice())
                .chain(joint_nodes.iter().map(Vec::as_slice)),
        );
        let symbolic = SymbolicLlt::try_new(pattern_ref(&pattern), Side::Upper)
            .map_err(|e| SolveError::Factorization(format!("{e:?}")))?;
        Ok(Model {
            mesh,
            materials,
            joints,
            dofs,
            fixed,
            pattern,
            symbolic,
        })
    }

    /// Number of unknowns per harmonic.
    pub fn n_eq(&self) -> usize {
        self.dofs.n_eq
    }

    /// The sparsity pattern (upper triangle) shared by every harmonic.
    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    /// Stored entries of the upper triangle.
    pub fn nnz(&self) -> usize {
        self.pattern.nnz()
    }

    /// Assembled values (upper triangle, pattern order) of harmonic `m`.
    pub fn assemble(&self, m: u32) -> (Vec<f64>, Vec<bool>) {
        let pinned = self.dofs.pinned(m);
        let mut values = vec![0.0; self.pattern.nnz()];
        let mut scratch = ElementScratch::new();
        for_each_element(
            &self.mesh,
            &self.materials,
            &self.joints,
            m,
            &mut scratch,
            |nodes, ke| scatter(&self.pattern, &self.dofs, &pinned, nodes, ke, &mut values),
        );
        // Identity rows (scaled) for the pinned axis variables.
        let free_diag: Vec<f64> = (0..self.pattern.n)
            .filter(|&e| !pinned[e])
            .map(|e| values[self.pattern.slot(e, e)].abs())
            .collect();
        let scale = if free_diag.is_empty() {
            1.0
        } else {
            free_diag.iter().sum::<f64>() / free_diag.len() as f64
        };
        for (e, &p) in pinned.iter().enumerate() {
            if p {
                values[self.pattern.slot(e, e)] = scale;
            }
        }
        (values, pinned)
    }

    /// Assembles and factorizes harmonic `m`, and checks the factor with a
    /// probe solve (a mechanism shows as a large probe error).
    pub fn factorize(&self, m: u32) -> Result<HarmonicFactor, SolveError> {
        let (values, pinned) = self.assemble(m);
        let singular = |detail: String| SolveError::Singular {
            m,
            detail,
            hint: self.unsupported_hint(),
        };
        let mat = SparseColMatRef::new(pattern_ref(&self.pattern), &values);
        let llt =
            Llt::try_new_with_symbolic(self.symbolic.clone(), mat, Side::Upper).map_err(|e| match e {
                faer::sparse::linalg::LltError::Numeric(_) => {
                    singular("a non-positive pivot in the Cholesky factorization".into())
                }
                faer::sparse::linalg::LltError::Generic(g) => SolveError::Factorization(format!("{g:?}")),
            })?;
        // Probe: x0 pseudo-random, b = K x0, solve, compare.
        let n = self.pattern.n;
        let x0: Vec<f64> = (0..n)
            .map(|i| ((i as f64 + 1.0) * 0.618_033_988_75).fract() - 0.5)
            .collect();
        let mut b = vec![0.0; n];
        self.pattern.sym_matvec(&values, &x0, &mut b);
        let mut rhs = Mat::from_fn(n, 1, |i, _| b[i]);
        llt.solve_in_place(rhs.as_mut());
        let (mut num, mut den) = (0.0f64, 0.0f64);
        for (i, x) in x0.iter().enumerate() {
            num = num.max((rhs[(i, 0)] - x).abs());
            den = den.max(x.abs());
        }
        let err = num / den;
        if !err.is_finite() || err > 1e-6 {
            return Err(singular(format!("probe solve error {err:.1e}")));
        }
        Ok(HarmonicFactor { m, llt, pinned })
    }

    /// Factorizes each harmonic in `ms`, in parallel.
    pub fn factorize_all(&self, ms: &[u32]) -> Result<Vec<HarmonicFactor>, SolveError> {
        ms.par_iter().map(|&m| self.factorize(m)).collect()
    }

    /// Solves `K_m u = f` for node-DOF loads `loads` (each `3 * n_nodes`);
    /// returns node-DOF displacements (zero at supports).
    pub fn solve(&self, factor: &HarmonicFactor, loads: &[&[f64]]) -> Vec<Vec<f64>> {
        let n = self.pattern.n;
        let mut b = vec![0.0; n];
        let mut rhs = Mat::<f64>::zeros(n, loads.len());
        for (k, f) in loads.iter().enumerate() {
            self.dofs.restrict(f, &factor.pinned, &mut b);
            for (i, v) in b.iter().enumerate() {
                rhs[(i, k)] = *v;
            }
        }
        factor.llt.solve_in_place(rhs.as_mut());
        (0..loads.len())
            .map(|k| {
                let x: Vec<f64> = (0..n).map(|i| rhs[(i, k)]).collect();
                let mut u = vec![0.0; 3 * self.dofs.n_nodes];
                self.dofs.expand(&x, &mut u);
                u
            })
            .collect()
    }

    /// Internal nodal forces `K_m u` of node-DOF displacements, element by
    /// element (supports included: reactions are `K u - f` there).
    pub fn internal_forces(&self, m: u32, u: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; u.len()];
        let mut scratch = ElementScratch::new();
        let mut ue = Vec::with_capacity(54);
        for_each_element(
            &self.mesh,
            &self.materials,
            &self.joints,
            m,
            &mut scratch,
            |nodes, ke| {
                ue.clear();
                ue.extend(nodes.iter().flat_map(|&n| u[3 * n..3 * n + 3].iter().copied()));
                for (a, row) in ke.row_iter().enumerate() {
                    let fa: f64 = row.iter().zip(&ue).map(|(k, x)| k * x).sum();
                    out[3 * nodes[a / 3] + a % 3] += fa;
                }
            },
        );
        out
    }

    /// Bodies of the connected parts that have no support at all.
    fn unsupported_hint(&self) -> String {
        let mesh = &self.mesh;
        let n = mesh.nodes.len();
        let mut parent: Vec<usize> = (0..n).collect();
        fn find(p: &mut [usize], mut a: usize) -> usize {
            while p[a] != a {
                p[a] = p[p[a]];
                a = p[a];
            }
            a
        }
        let link = |p: &mut Vec<usize>, a: usize, b: usize| {
            let (ra, rb) = (find(p, a), find(p, b));
            p[ra] = rb;
        };
        for c in &mesh.cells {
            for w in c.nodes.windows(2) {
                link(&mut parent, w[0], w[1]);
            }
        }
        for (j, props) in mesh.joints.iter().zip(&self.joints) {
            let k = props.springs;
            if k.k_xi > 0.0 || k.k_eta > 0.0 || k.k_theta > 0.0 {
                for e in &j.elements {
                    link(&mut parent, e.bottom[0], e.top[0]);
                }
            }
        }
        let mut supported = vec![false; n];
        for node in 0..n {
            if self.fixed[3 * node..3 * node + 3].iter().any(|&f| f) {
                let r = find(&mut parent, node);
                supported[r] = true;
            }
        }
        let mut free: Vec<String> = Vec::new();
        for c in &mesh.cells {
            let r = find(&mut parent, c.nodes[0]);
            let name = &mesh.bodies[c.body].name;
            if !supported[r] && !free.contains(name) {
                free.push(name.clone());
            }
        }
        if free.is_empty() {
            "check the supports (a rigid-body motion of this harmonic is not restrained)".into()
        } else {
            format!("no support reaches bodies {}", free.join(", "))
        }
    }
}

fn pattern_ref(p: &Pattern) -> SymbolicSparseColMatRef<'_, usize> {
    SymbolicSparseColMatRef::new_checked(p.n, p.n, &p.col_ptr, None, &p.row_idx)
}
