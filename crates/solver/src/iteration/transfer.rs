//! The transfer between the sections and the harmonics ([`Transfer`]): the
//! synthesis of joint-node amplitudes at the sections (S) and its
//! transpose with the section weights, the analysis of section forces into
//! harmonic loads (A). The Fourier loop over the sections is written here
//! once, for the iteration and for the released spectrum alike.
//!
//! With plastic bodies the nodes of their cells follow the joint nodes:
//! 3 amplitudes each per harmonic, and at a section
//! [`BODY_VALUES`] values each, the physical displacements and their
//! theta derivatives (the strain needs both); the analysis takes the
//! section forces on both back with the basis and its derivative.

use super::body::BODY_VALUES;
use crate::elements::c_m;
use crate::fourier::{basis_derivative, Family, Sections};
use rayon::prelude::*;

/// Release-node values per harmonic, `[symmetric, antisymmetric]`, each
/// `3 * (joint nodes + body nodes)` (the joint nodes in the order of
/// [`crate::linear::Model::joint_nodes`], then the plastic bodies' nodes).
pub(super) type JointAmplitudes = Vec<[Vec<f64>; 2]>;

/// (section, point) pairs below which the loops over the sections run on
/// one thread ([`Transfer::min_len`]).
pub(super) const SEQUENTIAL_PAIRS: usize = 1024;

/// The families, in the order of [`JointAmplitudes`].
const FAMILIES: [Family; 2] = [Family::Symmetric, Family::Antisymmetric];

/// The basis of a list of harmonics at the sections: the synthesis and
/// analysis of joint-node values between the two.
pub(super) struct Transfer<'a> {
    /// The sections.
    pub(super) sections: &'a Sections,
    /// `phi[(s * n_h + h) * 2 + family] = (phi_rz, phi_theta)`.
    phi: Vec<(f64, f64)>,
    /// Their theta derivatives, in the same order.
    dphi: Vec<(f64, f64)>,
    /// Number of harmonics.
    pub(super) n_h: usize,
    /// Whether harmonic h has an antisymmetric family to solve.
    pub(super) both: Vec<bool>,
    /// Joint-node values per section: `3 * joint nodes`.
    n: usize,
    /// Plastic bodies' nodes.
    nb: usize,
    /// See [`Transfer::min_len`].
    min_len: usize,
}

impl<'a> Transfer<'a> {
    /// The transfer of harmonics `ms` (`both[h]`: whether harmonic h has an
    /// antisymmetric family) at `sections`, for `n_joint_nodes` joint nodes,
    /// `n_points` joint points, and `nodes` and `points` of plastic bodies.
    pub(super) fn new(
        sections: &'a Sections,
        ms: &[u32],
        both: Vec<bool>,
        (n_joint_nodes, n_points): (usize, usize),
        (nodes, points): (usize, usize),
    ) -> Self {
        let min_len = if sections.len() * (n_points + points) < SEQUENTIAL_PAIRS {
            usize::MAX
        } else {
            1
        };
        Self::with_min_len(sections, ms, both, (3 * n_joint_nodes, nodes), min_len)
    }

    fn with_min_len(
        sections: &'a Sections,
        ms: &[u32],
        both: Vec<bool>,
        (n, nb): (usize, usize),
        min_len: usize,
    ) -> Self {
        let mut phi = Vec::with_capacity(sections.len() * ms.len() * 2);
        let mut dphi = Vec::with_capacity(if nb > 0 { phi.capacity() } else { 0 });
        for &t in &sections.theta {
            for &m in ms {
                for family in FAMILIES {
                    phi.push(sections.phi(m, family, t));
                    if nb > 0 {
                        dphi.push(basis_derivative(m, family, t));
                    }
                }
            }
        }
        Transfer {
            sections,
            phi,
            dphi,
            n_h: ms.len(),
            both,
            n,
            nb,
            min_len,
        }
    }

    /// Where the body values begin in a section's values.
    pub(super) fn body_start(&self) -> usize {
        self.n
    }

    /// Length of the amplitudes of one harmonic and family.
    pub(super) fn amplitudes_len(&self) -> usize {
        self.n + 3 * self.nb
    }

    /// The basis `(phi_rz, phi_theta)` of harmonic index `h` at section `s`.
    pub(super) fn phi(&self, s: usize, h: usize, family: Family) -> (f64, f64) {
        self.phi[(s * self.n_h + h) * 2 + family as usize]
    }

    /// Length of a section-force vector: sections x (joint nodes x 3 +
    /// body nodes x [`BODY_VALUES`]).
    pub(super) fn len(&self) -> usize {
        self.sections.len() * (self.n + BODY_VALUES * self.nb)
    }

    /// Values per section (`3 * joint nodes + 6 * body nodes`, at least 1
    /// for chunking).
    pub(super) fn per_section(&self) -> usize {
        (self.n + BODY_VALUES * self.nb).max(1)
    }

    /// The smallest number of sections (or harmonics) a parallel loop over
    /// them hands to one thread: all of them (no hand-off) when the joints
    /// have fewer than [`SEQUENTIAL_PAIRS`] (section, point) pairs, where
    /// waking the threads costs more than the work.
    pub(super) fn min_len(&self) -> usize {
        self.min_len
    }

    /// Zero joint-node values per harmonic (the analysis buffer).
    pub(super) fn zeros(&self) -> JointAmplitudes {
        let n = self.amplitudes_len();
        (0..self.n_h).map(|_| [vec![0.0; n], vec![0.0; n]]).collect()
    }

    /// Synthesizes the joint-node values `u` at section `s`.
    fn synthesize_at(&self, u: &JointAmplitudes, s: usize, out: &mut [f64]) {
        out.fill(0.0);
        for (h, hd) in u.iter().enumerate() {
            for (family, amp) in [(Family::Symmetric, &hd[0]), (Family::Antisymmetric, &hd[1])] {
                let (a, b) = self.phi(s, h, family);
                let (da, db) = self.dphi(s, h, family);
                if a == 0.0 && b == 0.0 && da == 0.0 && db == 0.0 {
                    continue;
                }
                let (joint, body) = out.split_at_mut(self.n);
                let (amp_joint, amp_body) = amp.split_at(self.n);
                for (o, v) in joint.chunks_exact_mut(3).zip(amp_joint.chunks_exact(3)) {
                    o[0] += a * v[0];
                    o[1] += a * v[1];
                    o[2] += b * v[2];
                }
                for (o, v) in body.chunks_exact_mut(BODY_VALUES).zip(amp_body.chunks_exact(3)) {
                    o[0] += a * v[0];
                    o[1] += a * v[1];
                    o[2] += b * v[2];
                    o[3] += da * v[0];
                    o[4] += da * v[1];
                    o[5] += db * v[2];
                }
            }
        }
    }

    /// The theta derivative of the basis of harmonic index `h` at section
    /// `s` (zero without plastic bodies: not kept).
    fn dphi(&self, s: usize, h: usize, family: Family) -> (f64, f64) {
        self.dphi
            .get((s * self.n_h + h) * 2 + family as usize)
            .copied()
            .unwrap_or((0.0, 0.0))
    }

    /// `u_s = S u`: synthesizes the joint-node values `u` at every section.
    pub(super) fn synthesize(&self, u: &JointAmplitudes, u_s: &mut [f64]) {
        u_s.par_chunks_mut(self.per_section())
            .with_min_len(self.min_len)
            .enumerate()
            .for_each(|(s, out)| self.synthesize_at(u, s, out));
    }

    /// `A x`: analyses section forces `x` into harmonic loads (the
    /// transpose of [`Transfer::synthesize`] with the section weights).
    pub(super) fn analyse(&self, x: &[f64], released: &mut JointAmplitudes) {
        let (n, per) = (self.n, self.per_section());
        released
            .par_iter_mut()
            .with_min_len(self.min_len)
            .enumerate()
            .for_each(|(h, out)| {
                for s in 0..self.sections.len() {
                    let w = self.sections.weight[s];
                    let xs = &x[s * per..s * per + n + BODY_VALUES * self.nb];
                    let (x_joint, x_body) = xs.split_at(n);
                    for (k, (family, vec)) in FAMILIES.into_iter().zip(out.iter_mut()).enumerate() {
                        if s == 0 {
                            vec.fill(0.0);
                        }
                        let (a, b) = self.phi(s, h, family);
                        let (da, db) = self.dphi(s, h, family);
                        if (a == 0.0 && b == 0.0 && da == 0.0 && db == 0.0) || (k == 1 && !self.both[h]) {
                            continue;
                        }
                        let (v_joint, v_body) = vec.split_at_mut(n);
                        for (v, xj) in v_joint.chunks_exact_mut(3).zip(x_joint.chunks_exact(3)) {
                            v[0] += w * a * xj[0];
                            v[1] += w * a * xj[1];
                            v[2] += w * b * xj[2];
                        }
                        for (v, xj) in v_body.chunks_exact_mut(3).zip(x_body.chunks_exact(BODY_VALUES)) {
                            v[0] += w * (a * xj[0] + da * xj[3]);
                            v[1] += w * (a * xj[1] + da * xj[4]);
                            v[2] += w * (b * xj[2] + db * xj[5]);
                        }
                    }
                }
            });
    }

    /// `|f_m| / c_m` of section forces `x` for m = 0 up to the highest
    /// harmonic the sections resolve (both families together): their
    /// analysis on the basis of those harmonics.
    pub(super) fn spectrum(&self, x: &[f64]) -> Vec<f64> {
        let ms: Vec<u32> = (0..=self.sections.exact_up_to()).collect();
        let basis = Self::with_min_len(
            self.sections,
            &ms,
            vec![true; ms.len()],
            (self.n, self.nb),
            self.min_len,
        );
        let mut f = basis.zeros();
        basis.analyse(x, &mut f);
        f.iter()
            .zip(&ms)
            .map(|(fm, &m)| {
                let mut sum = 0.0;
                for family in fm {
                    sum += family.iter().map(|v| v * v).sum::<f64>();
                }
                sum.sqrt() / c_m(m)
            })
            .collect()
    }
}
