//! The transfer between the sections and the harmonics ([`Transfer`]): the
//! synthesis of joint-node amplitudes at the sections (S) and its
//! transpose with the section weights, the analysis of section forces into
//! harmonic loads (A). The Fourier loop over the sections is written here
//! once, for the iteration and for the released spectrum alike.

use crate::elements::c_m;
use crate::fourier::{Family, Sections};
use rayon::prelude::*;

/// Joint-node values per harmonic, `[symmetric, antisymmetric]`, each
/// `3 * joint nodes` (the node order of [`crate::linear::Model::joint_nodes`]).
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
    /// Number of harmonics.
    pub(super) n_h: usize,
    /// Whether harmonic h has an antisymmetric family to solve.
    pub(super) both: Vec<bool>,
    /// Values per section: `3 * joint nodes`.
    n: usize,
    /// See [`Transfer::min_len`].
    min_len: usize,
}

impl<'a> Transfer<'a> {
    /// The transfer of harmonics `ms` (`both[h]`: whether harmonic h has an
    /// antisymmetric family) at `sections`, for `n_joint_nodes` joint nodes
    /// and `n_points` joint points.
    pub(super) fn new(
        sections: &'a Sections,
        ms: &[u32],
        both: Vec<bool>,
        n_joint_nodes: usize,
        n_points: usize,
    ) -> Self {
        let min_len = if sections.len() * n_points < SEQUENTIAL_PAIRS {
            usize::MAX
        } else {
            1
        };
        Self::with_min_len(sections, ms, both, 3 * n_joint_nodes, min_len)
    }

    fn with_min_len(sections: &'a Sections, ms: &[u32], both: Vec<bool>, n: usize, min_len: usize) -> Self {
        let mut phi = Vec::with_capacity(sections.len() * ms.len() * 2);
        for &t in &sections.theta {
            for &m in ms {
                for family in FAMILIES {
                    phi.push(sections.phi(m, family, t));
                }
            }
        }
        Transfer {
            sections,
            phi,
            n_h: ms.len(),
            both,
            n,
            min_len,
        }
    }

    /// The basis `(phi_rz, phi_theta)` of harmonic index `h` at section `s`.
    pub(super) fn phi(&self, s: usize, h: usize, family: Family) -> (f64, f64) {
        self.phi[(s * self.n_h + h) * 2 + family as usize]
    }

    /// Length of a section-force vector: sections x joint nodes x 3.
    pub(super) fn len(&self) -> usize {
        self.sections.len() * self.n
    }

    /// Values per section (`3 * joint nodes`, at least 1 for chunking).
    pub(super) fn per_section(&self) -> usize {
        self.n.max(1)
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
        (0..self.n_h)
            .map(|_| [vec![0.0; self.n], vec![0.0; self.n]])
            .collect()
    }

    /// Synthesizes the joint-node values `u` at section `s`.
    fn synthesize_at(&self, u: &JointAmplitudes, s: usize, out: &mut [f64]) {
        out.fill(0.0);
        for (h, hd) in u.iter().enumerate() {
            for (family, amp) in [(Family::Symmetric, &hd[0]), (Family::Antisymmetric, &hd[1])] {
                let (a, b) = self.phi(s, h, family);
                if a == 0.0 && b == 0.0 {
                    continue;
                }
                for (o, v) in out.chunks_exact_mut(3).zip(amp.chunks_exact(3)) {
                    o[0] += a * v[0];
                    o[1] += a * v[1];
                    o[2] += b * v[2];
                }
            }
        }
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
        let n = self.n;
        released
            .par_iter_mut()
            .with_min_len(self.min_len)
            .enumerate()
            .for_each(|(h, out)| {
                for s in 0..self.sections.len() {
                    let w = self.sections.weight[s];
                    let xs = &x[s * n..(s + 1) * n];
                    for (k, (family, vec)) in FAMILIES.into_iter().zip(out.iter_mut()).enumerate() {
                        if s == 0 {
                            vec.fill(0.0);
                        }
                        let (a, b) = self.phi(s, h, family);
                        if (a == 0.0 && b == 0.0) || (k == 1 && !self.both[h]) {
                            continue;
                        }
                        for (v, xj) in vec.chunks_exact_mut(3).zip(xs.chunks_exact(3)) {
                            v[0] += w * a * xj[0];
                            v[1] += w * a * xj[1];
                            v[2] += w * b * xj[2];
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
        let basis = Self::with_min_len(self.sections, &ms, vec![true; ms.len()], self.n, self.min_len);
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
