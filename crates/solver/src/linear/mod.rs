//! The linear model: pattern and symbolic factorization once, one numeric
//! Cholesky per harmonic, many right-hand sides per factor.
//!
//! Several harmonics factorized together take their stiffness from the
//! three arrays of [`StiffnessTerms`], assembled once per model and kept:
//! forming `K_m` from them costs a few percent of an element-by-element
//! assembly (docs/performance.md).

mod joint;
mod reduced;

use crate::assembly::{
    for_each_element, for_each_element_where, pin_axis_rows, scatter, ElementScratch, JointModel, Pattern,
    StiffnessTerms,
};
use crate::dofs::DofMap;
use crate::factor::{solve_interleaved, solve_with_faer, trailing_offset};
use crate::material::Elastic;
use axijoint_mesh::Mesh;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::perm::PermRef;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, SymbolicCholesky, SymmetricOrdering};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Mat, Side};
use nalgebra::DMatrix;
use std::sync::atomic::AtomicUsize;
use std::sync::{Arc, Mutex, OnceLock};

/// [`Model::factorize_all`] assembles the [`StiffnessTerms`] when it
/// factorizes at least this many harmonics: they cost about 1.5
/// assemblies of one harmonic (docs/performance.md).
pub const TERMS_FROM: usize = 2;

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

/// Numeric factor of one harmonic: the whole of L, or only its joint
/// block ([`Model::joint_block`]), all the iteration reads.
pub struct HarmonicFactor {
    /// Harmonic m.
    pub m: u32,
    symbolic: Arc<SymbolicCholesky<usize>>,
    /// Values of the lower factor L in faer's storage for `symbolic`, from
    /// stored value `offset` on.
    values: Vec<f64>,
    /// 0 for the whole factor.
    offset: usize,
    pinned: Vec<bool>,
    /// The values before `offset` on disk, if written there.
    spilled: Option<crate::spill::Spilled>,
    /// Seconds its numeric factorization took.
    seconds: f64,
    /// `[K_m^-1]` on the joint nodes, once asked for
    /// ([`Model::joint_inverse`]).
    joint_inverse: OnceLock<Arc<DMatrix<f64>>>,
}

impl HarmonicFactor {
    /// Whether the whole factor is kept (else only its joint block: a full
    /// solve then factorizes the harmonic again).
    pub fn is_full(&self) -> bool {
        self.offset == 0
    }

    /// Whether a reduced factor keeps the rest of its values on disk
    /// ([`crate::spill`]): a full solve reads them back.
    pub fn on_disk(&self) -> bool {
        self.spilled.is_some()
    }

    /// Bytes of the stored values of L.
    pub fn stored_bytes(&self) -> usize {
        8 * self.values.len()
    }
}

/// A ratio of stiffnesses (Young's moduli, joint springs times their
/// element length) beyond which a singular factorization is put down to
/// the contrast (a value typed in another unit) rather than to the
/// supports.
pub const STIFFNESS_CONTRAST: f64 = 1e8;

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
    /// The yield criterion of each body (index as `mesh.bodies`); none:
    /// elastic (the default of [`Model::new`]). Released by the iteration
    /// as the joints' tractions are.
    pub plasticity: Vec<Option<crate::scene::Plasticity>>,
    pattern: Pattern,
    symbolic: Arc<SymbolicCholesky<usize>>,
    /// Nodes of the joint elements (sorted).
    joint_nodes: Vec<usize>,
    /// Equations of the joint nodes, ordered last in the factorization.
    trailing: Vec<usize>,
    /// Position of each equation in `trailing` (`usize::MAX` if absent).
    trail_pos: Vec<usize>,
    /// `A`, `B`, `C` of `K_m = c_m (A + m B + m^2 C)`, once assembled.
    terms: Mutex<Option<Arc<StiffnessTerms>>>,
    /// Harmonics reduced to their joint blocks factorized at once.
    lean_at_once: AtomicUsize,
    /// Where reduced factors keep the rest of their values, once opened.
    spill: OnceLock<Option<Arc<crate::spill::SpillFile>>>,
    /// Value buffers of whole factors dropped by a reduction or after a
    /// full solve, for the next: a fresh buffer costs its pages again.
    spare: Arc<Mutex<Vec<Vec<f64>>>>,
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
        let mut joint_node_list: Vec<usize> = joint_nodes.iter().flatten().copied().collect();
        joint_node_list.sort_unstable();
        joint_node_list.dedup();
        let mut trail_pos = vec![usize::MAX; dofs.n_eq];
        let mut trailing = Vec::new();
        for &k in &joint_node_list {
            for dof in 3 * k..3 * k + 3 {
                for (e, _) in dofs.terms(dof) {
                    if trail_pos[e] == usize::MAX {
                        trail_pos[e] = trailing.len();
                        trailing.push(e);
                    }
                }
            }
        }
        let symbolic = symbolic_with_last(&pattern, &trailing, &trail_pos)?;
        Ok(Model {
            plasticity: vec![None; mesh.bodies.len()],
            mesh,
            materials,
            joints,
            dofs,
            fixed,
            pattern,
            symbolic: Arc::new(symbolic),
            joint_nodes: joint_node_list,
            trailing,
            trail_pos,
            terms: Mutex::new(None),
            lean_at_once: AtomicUsize::new(usize::MAX),
            spill: OnceLock::new(),
            spare: Arc::new(Mutex::new(Vec::new())),
        })
    }

    /// Stored values of one harmonic's Cholesky factor L.
    pub fn factor_len(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Nodes of the joint elements, sorted: the node order of
    /// [`Model::solve_joint`].
    pub fn joint_nodes(&self) -> &[usize] {
        &self.joint_nodes
    }

    /// Per body, whether its cells are B-bar cells (the plastic bodies':
    /// their plastic flow keeps the volume, which the full strain locks).
    pub fn mixed(&self) -> Vec<bool> {
        self.plasticity.iter().map(Option::is_some).collect()
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

    /// Assembled values (upper triangle, pattern order) of harmonic `m`,
    /// element by element, and the pinned equations.
    pub fn assemble(&self, m: u32) -> (Vec<f64>, Vec<bool>) {
        let pinned = self.dofs.pinned(m);
        let mut values = vec![0.0; self.pattern.nnz()];
        let mut scratch = ElementScratch::new();
        for_each_element(
            &self.mesh,
            (&self.materials, &self.mixed()),
            &self.joints,
            m,
            &mut scratch,
            |nodes, ke| scatter(&self.pattern, &self.dofs, &pinned, nodes, ke, &mut values),
        );
        pin_axis_rows(&self.pattern, &pinned, &mut values);
        (values, pinned)
    }

    /// [`Model::assemble`] from the [`StiffnessTerms`] (assembled first if
    /// this model has none for its current materials and joints).
    pub fn assemble_from_terms(&self, m: u32) -> (Vec<f64>, Vec<bool>) {
        self.terms_from(&self.stiffness_terms(), m)
    }

    fn terms_from(&self, terms: &StiffnessTerms, m: u32) -> (Vec<f64>, Vec<bool>) {
        let pinned = self.dofs.pinned(m);
        let mut values = terms.harmonic(&self.pattern, m, &pinned);
        pin_axis_rows(&self.pattern, &pinned, &mut values);
        (values, pinned)
    }

    /// The model's [`StiffnessTerms`], assembled on the first call (and
    /// again if `materials` or `joints` changed since).
    pub fn stiffness_terms(&self) -> Arc<StiffnessTerms> {
        let mut slot = self.terms.lock().unwrap_or_else(|e| e.into_inner());
        match &*slot {
            Some(t) if t.matches((&self.materials, &self.mixed()), &self.joints) => t.clone(),
            _ => {
                let t = Arc::new(StiffnessTerms::assemble(
                    &self.mesh,
                    (&self.materials, &self.mixed()),
                    &self.joints,
                    &self.dofs,
                    &self.pattern,
                ));
                *slot = Some(t.clone());
                t
            }
        }
    }

    /// The stiffness terms if they are assembled and current.
    fn current_terms(&self) -> Option<Arc<StiffnessTerms>> {
        let slot = self.terms.lock().unwrap_or_else(|e| e.into_inner());
        slot.as_ref()
            .filter(|t| t.matches((&self.materials, &self.mixed()), &self.joints))
            .cloned()
    }

    /// Assembles and factorizes harmonic `m` (from the [`StiffnessTerms`]
    /// when the model has them, else element by element), and checks the
    /// factor with a probe solve (a mechanism shows as a large probe error).
    pub fn factorize(&self, m: u32) -> Result<HarmonicFactor, SolveError> {
        let (values, pinned) = match self.current_terms() {
            Some(terms) => self.terms_from(&terms, m),
            None => self.assemble(m),
        };
        self.factorize_values(m, &values, pinned)
    }

    /// Factorizes harmonic `m` from its assembled `values` and `pinned`
    /// equations (as [`Model::assemble`] returns them).
    pub fn factorize_values(
        &self,
        m: u32,
        values: &[f64],
        pinned: Vec<bool>,
    ) -> Result<HarmonicFactor, SolveError> {
        let factor = self.numeric(m, values, pinned)?;
        // Probe: x0 pseudo-random, b = K x0, solve, compare.
        let n = self.pattern.n;
        let x0: Vec<f64> = (0..n)
            .map(|i| ((i as f64 + 1.0) * 0.618_033_988_75).fract() - 0.5)
            .collect();
        let mut b = vec![0.0; n];
        self.pattern.sym_matvec(values, &x0, &mut b);
        let mut x: Vec<[f64; 1]> = b.iter().map(|&v| [v]).collect();
        solve_interleaved(&factor.symbolic, &factor.values, &mut x);
        let (mut num, mut den) = (0.0f64, 0.0f64);
        for (xi, x0i) in x.iter().zip(&x0) {
            num = num.max((xi[0] - x0i).abs());
            den = den.max(x0i.abs());
        }
        let err = num / den;
        if !err.is_finite() || err > 1e-6 {
            return Err(SolveError::Singular {
                m,
                detail: format!("probe solve error {err:.1e}"),
                hint: self.unsupported_hint(),
            });
        }
        Ok(factor)
    }

    /// The factor of assembled `values` meant as a preconditioner (a
    /// tangent stiffness near a collapse is nearly singular): the numeric
    /// Cholesky factorization without [`Model::factorize_values`]' probe;
    /// `None` when a pivot is not positive.
    pub fn factorize_preconditioner(
        &self,
        m: u32,
        values: &[f64],
        pinned: Vec<bool>,
    ) -> Option<HarmonicFactor> {
        self.numeric(m, values, pinned).ok()
    }

    /// The numeric factorization of [`Model::factorize_values`], without
    /// its probe.
    fn numeric(&self, m: u32, values: &[f64], pinned: Vec<bool>) -> Result<HarmonicFactor, SolveError> {
        let t = std::time::Instant::now();
        let mat = SparseColMatRef::new(pattern_ref(&self.pattern), values);
        let mut l_values = self.buffer()?;
        l_values.resize(self.symbolic.len_val(), 0.0);
        let par = faer::get_global_parallelism();
        let mut mem = MemBuffer::try_new(
            self.symbolic
                .factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        )
        .map_err(|_| SolveError::Factorization("out of memory for the factorization workspace".into()))?;
        self.symbolic
            .factorize_numeric_llt(
                &mut l_values,
                mat,
                Side::Upper,
                LltRegularization::default(),
                par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|LltError::NonPositivePivot { index }| SolveError::Singular {
                m,
                detail: format!("a non-positive pivot in the Cholesky factorization (step {index})"),
                hint: self.unsupported_hint(),
            })?;
        Ok(HarmonicFactor {
            m,
            symbolic: self.symbolic.clone(),
            values: l_values,
            offset: 0,
            pinned,
            spilled: None,
            seconds: t.elapsed().as_secs_f64(),
            joint_inverse: OnceLock::new(),
        })
    }

    /// Factorizes each harmonic in `ms`, in parallel; from [`TERMS_FROM`]
    /// harmonics on, their stiffnesses come from the [`StiffnessTerms`]
    /// (assembled once, kept for later calls).
    pub fn factorize_all(&self, ms: &[u32]) -> Result<Vec<HarmonicFactor>, SolveError> {
        let all = self.factorize_all_with(ms, |_| true, |_| ())?;
        Ok(all.into_iter().map(|(f, ())| f).collect())
    }

    /// [`Model::factorize_all`], with `each` run on every whole factor
    /// (e.g. its full solves) before it is reduced to its joint block
    /// ([`Model::joint_block`]) unless `keep_full(m)`; the others are
    /// factorized [`Model::set_lean_at_once`] at a time, more while the
    /// joint blocks not yet made leave room for whole factors.
    pub fn factorize_all_with<T: Send>(
        &self,
        ms: &[u32],
        keep_full: impl Fn(u32) -> bool + Sync,
        each: impl Fn(&HarmonicFactor) -> T + Sync,
    ) -> Result<Vec<(HarmonicFactor, T)>, SolveError> {
        if ms.len() >= TERMS_FROM {
            self.stiffness_terms();
        }
        // The joint blocks not yet held leave room for more whole factors
        // at once: the factors never take more than when all are held.
        let lean = ms.iter().filter(|&&m| !keep_full(m)).count();
        if lean > 0 {
            // Open now: the first reductions may write behind.
            self.spill.get_or_init(crate::spill::SpillFile::open);
        }
        let (block, whole) = (self.joint_block_len(), self.factor_len().max(1));
        self.map_bounded_with_room(
            ms.len(),
            |i| !keep_full(ms[i]),
            |done| (lean - done) * block / whole,
            |i| {
                let m = ms[i];
                let f = self.factorize(m)?;
                let t = each(&f);
                Ok((if keep_full(m) { f } else { self.joint_block(f) }, t))
            },
        )
        .into_iter()
        .collect()
    }

    /// Solves `K_m u = f` for node-DOF loads `loads` (each `3 * n_nodes`);
    /// returns node-DOF displacements (zero at supports).
    /// A `factor` reduced to its joint block is factorized again for this
    /// solve (and dropped after it).
    pub fn solve(&self, factor: &HarmonicFactor, loads: &[&[f64]]) -> Vec<Vec<f64>> {
        if !factor.is_full() {
            let whole = self.refactorize(factor);
            let u = self.solve(&whole, loads);
            self.give_back(whole.values);
            return u;
        }
        let n = self.pattern.n;
        let mut b = vec![0.0; n];
        let restrict = |k: usize, b: &mut Vec<f64>| self.dofs.restrict(loads[k], &factor.pinned, b);
        let mut xs: Vec<Vec<f64>> = match loads.len() {
            1 => {
                restrict(0, &mut b);
                let mut x: Vec<[f64; 1]> = b.iter().map(|&v| [v]).collect();
                solve_interleaved(&factor.symbolic, &factor.values, &mut x);
                vec![x.iter().map(|v| v[0]).collect()]
            }
            2 => {
                restrict(0, &mut b);
                let mut x: Vec<[f64; 2]> = b.iter().map(|&v| [v, 0.0]).collect();
                restrict(1, &mut b);
                for (xi, &v) in x.iter_mut().zip(&b) {
                    xi[1] = v;
                }
                solve_interleaved(&factor.symbolic, &factor.values, &mut x);
                vec![x.iter().map(|v| v[0]).collect(), x.iter().map(|v| v[1]).collect()]
            }
            k => {
                let mut rhs = Mat::<f64>::zeros(n, k);
                for j in 0..k {
                    restrict(j, &mut b);
                    for (i, v) in b.iter().enumerate() {
                        rhs[(i, j)] = *v;
                    }
                }
                solve_with_faer(&factor.symbolic, &factor.values, rhs.as_mut());
                (0..k).map(|j| (0..n).map(|i| rhs[(i, j)]).collect()).collect()
            }
        };
        xs.iter_mut()
            .map(|x| {
                let mut u = vec![0.0; 3 * self.dofs.n_nodes];
                self.dofs.expand(x, &mut u);
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
            (&self.materials, &self.mixed()),
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

    /// [`Model::internal_forces`] at the supported DOFs only (zero
    /// elsewhere): only the elements with a supported node are computed.
    pub fn support_forces(&self, m: u32, u: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; u.len()];
        let mut scratch = ElementScratch::new();
        let mut ue = Vec::with_capacity(54);
        let supported = |n: usize| (3 * n..3 * n + 3).any(|d| self.dofs.is_supported(d));
        for_each_element_where(
            &self.mesh,
            (&self.materials, &self.mixed()),
            &self.joints,
            m,
            &mut scratch,
            |nodes| nodes.iter().any(|&n| supported(n)),
            |nodes, ke| {
                ue.clear();
                ue.extend(nodes.iter().flat_map(|&n| u[3 * n..3 * n + 3].iter().copied()));
                for (a, row) in ke.row_iter().enumerate() {
                    let dof = 3 * nodes[a / 3] + a % 3;
                    if self.dofs.is_supported(dof) {
                        out[dof] += row.iter().zip(&ue).map(|(k, x)| k * x).sum::<f64>();
                    }
                }
            },
        );
        out
    }

    /// Bodies of the connected parts that have no support at all, or a
    /// stiffness contrast beyond [`STIFFNESS_CONTRAST`].
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
            let k = props.assembled;
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
            // Moduli, and joint springs times their mean element length.
            let joints = mesh.joints.iter().zip(&self.joints).filter_map(|(j, props)| {
                let k = props.assembled;
                let k = k.k_xi.min(k.k_eta).min(k.k_theta);
                let h = j.mean_length(&mesh.nodes);
                (k > 0.0 && h > 0.0).then_some(k * h)
            });
            let (lo, hi) = self
                .materials
                .iter()
                .map(|m| m.e)
                .chain(joints)
                .fold((f64::INFINITY, 0.0f64), |(lo, hi), e| (lo.min(e), hi.max(e)));
            if lo > 0.0 && hi / lo > STIFFNESS_CONTRAST {
                format!(
                    "the stiffnesses (Young's moduli, and joint springs times their element length) range from {lo:.3e} to {hi:.3e}, a factor {:.1e}: more than the arithmetic resolves; is a modulus or a spring in another unit? (else check the supports: a rigid-body motion of this harmonic is not restrained)",
                    hi / lo
                )
            } else {
                "check the supports (a rigid-body motion of this harmonic is not restrained)".into()
            }
        } else {
            format!("no support reaches bodies {}", free.join(", "))
        }
    }
}

/// Symbolic Cholesky of `pattern` with the equations `last` eliminated
/// last (in that order) and the others in approximate-minimum-degree order
/// of the graph without them. `pos[e]` is the index of `e` in `last`.
fn symbolic_with_last(
    pattern: &Pattern,
    last: &[usize],
    pos: &[usize],
) -> Result<SymbolicCholesky<usize>, SolveError> {
    let failed = |e: faer::sparse::FaerError| SolveError::Factorization(format!("{e:?}"));
    let n = pattern.n;
    if last.is_empty() {
        return factorize_symbolic_cholesky(
            pattern_ref(pattern),
            Side::Upper,
            Default::default(),
            Default::default(),
        )
        .map_err(failed);
    }
    // The interior graph: equations not in `last`, renumbered.
    let interior: Vec<usize> = (0..n).filter(|&e| pos[e] == usize::MAX).collect();
    let mut new_of = vec![usize::MAX; n];
    for (i, &e) in interior.iter().enumerate() {
        new_of[e] = i;
    }
    let mut col_ptr = Vec::with_capacity(interior.len() + 1);
    let mut row_idx = Vec::new();
    col_ptr.push(0);
    for &e in &interior {
        for &r in &pattern.row_idx[pattern.col_ptr[e]..pattern.col_ptr[e + 1]] {
            if new_of[r] != usize::MAX {
                row_idx.push(new_of[r]);
            }
        }
        col_ptr.push(row_idx.len());
    }
    let ni = interior.len();
    let mut fwd = vec![0usize; n];
    let mut inv = vec![0usize; n];
    if ni > 0 {
        let a = SymbolicSparseColMatRef::new_checked(ni, ni, &col_ptr, None, &row_idx);
        let mut mem = MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(ni, row_idx.len()))
            .map_err(|_| failed(faer::sparse::FaerError::OutOfMemory))?;
        amd::order_maybe_unsorted(
            &mut fwd[..ni],
            &mut inv[..ni],
            a,
            amd::Control::default(),
            MemStack::new(&mut mem),
        )
        .map_err(failed)?;
    }
    for i in 0..ni {
        fwd[i] = interior[fwd[i]];
    }
    fwd[ni..].copy_from_slice(last);
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    let perm = PermRef::new_checked(&fwd, &inv, n);
    factorize_symbolic_cholesky(
        pattern_ref(pattern),
        Side::Upper,
        SymmetricOrdering::Custom(perm),
        Default::default(),
    )
    .map_err(failed)
}

fn pattern_ref(p: &Pattern) -> SymbolicSparseColMatRef<'_, usize> {
    SymbolicSparseColMatRef::new_checked(p.n, p.n, &p.col_ptr, None, &p.row_idx)
}
