//! One evaluation of `Psi` ([`Eval`]): the section displacements, the
//! released section forces and the joint field they give.

use crate::joint_law::JointState;
use rayon::prelude::*;

/// One evaluation of `Psi`: the joint-node displacements at the sections
/// `u_s`, the released section forces `g = Psi(x)`, and the joint field
/// (index `s * n_points + p`) with the tensile-break memory after it; with
/// plastic bodies their field (index `s * body points + q`): the stress,
/// the plastic strain (committed and of the step) and whether it yields.
#[derive(Clone)]
pub(super) struct Eval {
    pub(super) u_s: Vec<f64>,
    pub(super) g: Vec<f64>,
    pub(super) d: Vec<[f64; 3]>,
    pub(super) p: Vec<[f64; 3]>,
    pub(super) state: Vec<JointState>,
    pub(super) broken: Vec<bool>,
    pub(super) sigma: Vec<[f64; 6]>,
    pub(super) plastic: Vec<[f64; 6]>,
    pub(super) yielding: Vec<bool>,
}

/// The writable fields of one section of an [`Eval`] (its points in
/// order).
pub(super) struct SectionEval<'e> {
    pub(super) g: &'e mut [f64],
    pub(super) d: &'e mut [[f64; 3]],
    pub(super) p: &'e mut [[f64; 3]],
    pub(super) state: &'e mut [JointState],
    pub(super) broken: &'e mut [bool],
}

/// The writable body fields of one section of an [`Eval`].
pub(super) struct BodySectionEval<'e> {
    /// The section's values, of which the body part is written.
    pub(super) g: &'e mut [f64],
    pub(super) sigma: &'e mut [[f64; 6]],
    pub(super) plastic: &'e mut [[f64; 6]],
    pub(super) yielding: &'e mut [bool],
}

impl Eval {
    /// `u_s`, and the writable fields section by section in parallel
    /// (`m` values and `n_p` points a section, at least `min_len` sections
    /// a thread).
    pub(super) fn sections_mut(
        &mut self,
        m: usize,
        n_p: usize,
        min_len: usize,
    ) -> (
        &[f64],
        impl IndexedParallelIterator<Item = (usize, SectionEval<'_>)>,
    ) {
        let Eval {
            u_s,
            g,
            d,
            p,
            state,
            broken,
            ..
        } = self;
        let sections = g
            .par_chunks_mut(m)
            .with_min_len(min_len)
            .zip(d.par_chunks_mut(n_p))
            .zip(p.par_chunks_mut(n_p))
            .zip(state.par_chunks_mut(n_p))
            .zip(broken.par_chunks_mut(n_p))
            .map(|((((g, d), p), state), broken)| SectionEval {
                g,
                d,
                p,
                state,
                broken,
            })
            .enumerate();
        (u_s, sections)
    }
}

impl Eval {
    /// `u_s`, and the writable body fields section by section in parallel
    /// (`m` values and `n_b` > 0 body points a section).
    pub(super) fn body_sections_mut(
        &mut self,
        m: usize,
        n_b: usize,
    ) -> (
        &[f64],
        impl IndexedParallelIterator<Item = (usize, BodySectionEval<'_>)>,
    ) {
        let Eval {
            u_s,
            g,
            sigma,
            plastic,
            yielding,
            ..
        } = self;
        let sections = g
            .par_chunks_mut(m)
            .zip(sigma.par_chunks_mut(n_b))
            .zip(plastic.par_chunks_mut(n_b))
            .zip(yielding.par_chunks_mut(n_b))
            .map(|(((g, sigma), plastic), yielding)| BodySectionEval {
                g,
                sigma,
                plastic,
                yielding,
            })
            .enumerate();
        (u_s, sections)
    }
}
