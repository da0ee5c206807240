//! Factors reduced to their joint blocks ([`Model::joint_block`]): how many
//! whole factors work at once, the rest of a reduced factor on disk or
//! factorized again for a full solve, and the buffers of whole factors
//! kept for the next.

use super::{HarmonicFactor, Model, SolveError};
use rayon::prelude::*;
use std::sync::atomic::Ordering;
use std::sync::Mutex;

impl Model {
    /// At most `n` (at least 1) harmonics whose factors keep only their
    /// joint blocks are factorized at once by [`Model::factorize_all_with`]
    /// and by the iteration's full solves: each holds a whole factor while
    /// it works. Default: no limit (rayon's threads).
    pub fn set_lean_at_once(&self, n: usize) {
        self.lean_at_once.store(n.max(1), Ordering::Relaxed);
    }

    /// `f(i)` for `i` in `0..n`, in parallel, but at most
    /// [`Model::set_lean_at_once`] of the `i` with `lean(i)` at once.
    pub fn map_bounded<T: Send>(
        &self,
        n: usize,
        lean: impl Fn(usize) -> bool + Sync,
        f: impl Fn(usize) -> T + Sync + Send,
    ) -> Vec<T> {
        self.map_bounded_with_room(n, lean, |_| 0, f)
    }

    /// [`Model::map_bounded`], with `room(k)` more of the lean `i` at once
    /// (up to rayon's threads) after `k` of them are done.
    pub(super) fn map_bounded_with_room<T: Send>(
        &self,
        n: usize,
        lean: impl Fn(usize) -> bool + Sync,
        room: impl Fn(usize) -> usize,
        f: impl Fn(usize) -> T + Sync + Send,
    ) -> Vec<T> {
        let (lean_i, whole_i): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| lean(i));
        let mut out: Vec<Option<T>> = (0..n).map(|_| None).collect();
        let mut put = |done: Vec<(usize, T)>| {
            for (i, t) in done {
                out[i] = Some(t);
            }
        };
        put(whole_i.par_iter().map(|&i| (i, f(i))).collect());
        let at_once = self.lean_at_once.load(Ordering::Relaxed).max(1);
        let threads = rayon::current_num_threads().max(1);
        let spill = self.spill.get().and_then(Option::as_ref);
        let mut done = 0;
        while done < lean_i.len() {
            let more = room(done);
            let k = if more > 0 {
                at_once.max(at_once.saturating_add(more).min(threads))
            } else {
                at_once
            };
            let chunk = &lean_i[done..(done + k.min(lean_i.len() - done))];
            // The room beyond the chunk's whole factors holds those of
            // writes still running behind.
            if let Some(file) = spill {
                file.allow_behind(at_once.saturating_add(more).saturating_sub(chunk.len()));
            }
            put(chunk.par_iter().map(|&i| (i, f(i))).collect());
            done += chunk.len();
        }
        if let Some(file) = spill {
            file.allow_behind(0);
        }
        out.into_iter().map(|t| t.expect("every index mapped")).collect()
    }

    /// Stored values of a factor's joint block ([`Model::joint_block`]).
    pub fn joint_block_len(&self) -> usize {
        let first = self.pattern.n - self.trailing.len();
        super::trailing_offset(&self.symbolic, first).map_or(self.factor_len(), |o| self.factor_len() - o)
    }

    /// `factor` reduced to its joint block: the trailing columns of L that
    /// [`Model::solve_joint`] reads (a simplicial factor stays whole). Its
    /// joint solves are those of the whole factor, value for value;
    /// [`Model::solve`] with it reads the rest back from disk
    /// ([`crate::spill::FACTOR_DISK_ENV`]) or, where there is none,
    /// factorizes the harmonic again.
    pub fn joint_block(&self, mut factor: HarmonicFactor) -> HarmonicFactor {
        let first = self.pattern.n - self.trailing.len();
        if let Some(o) = super::trailing_offset(&factor.symbolic, first) {
            if o > factor.offset {
                let cut = o - factor.offset;
                let kept = factor.values[cut..].to_vec();
                let whole = std::mem::replace(&mut factor.values, kept);
                match self.spill.get_or_init(crate::spill::SpillFile::open) {
                    Some(file) if factor.offset == 0 => {
                        let (spare, len, keep) =
                            (self.spare.clone(), self.symbolic.len_val(), self.spare_kept());
                        factor.spilled = file.put(whole, cut, factor.seconds, move |v| {
                            keep_spare(&spare, v, len, keep)
                        });
                    }
                    _ => self.give_back(whole),
                }
                factor.offset = o;
            }
        }
        factor
    }

    /// Frees the rest of the reduced factors on disk, on a thread of its
    /// own (when no more full solves are to come: a later one factorizes
    /// its harmonic again).
    pub fn release_disk(&self) {
        if let Some(Some(file)) = self.spill.get() {
            file.release();
        }
    }

    /// An empty buffer for the values of a whole factor: a spare one, else
    /// a new one.
    pub(super) fn buffer(&self) -> Result<Vec<f64>, SolveError> {
        let len = self.symbolic.len_val();
        if let Some(mut v) = self.spare.lock().ok().and_then(|mut s| s.pop()) {
            v.clear();
            return Ok(v);
        }
        let mut v = Vec::new();
        v.try_reserve_exact(len)
            .map_err(|_| SolveError::Factorization("out of memory for the factor".into()))?;
        Ok(v)
    }

    /// Keeps the values buffer `v` of a dropped whole factor for the next
    /// (as many as [`Model::set_lean_at_once`] allows to work at once: no
    /// more whole factors are held than when they work; the others are
    /// freed).
    pub(super) fn give_back(&self, v: Vec<f64>) {
        keep_spare(&self.spare, v, self.symbolic.len_val(), self.spare_kept());
    }

    /// How many spare buffers [`Model::give_back`] keeps.
    fn spare_kept(&self) -> usize {
        self.lean_at_once
            .load(Ordering::Relaxed)
            .min(rayon::current_num_threads())
            .max(1)
    }

    /// The whole factor of a harmonic whose `factor` keeps only its joint
    /// block: its values read back from disk, else assembled as
    /// [`Model::factorize`] does and factorized again (without the probe:
    /// the harmonic factorized before).
    pub(super) fn refactorize(&self, factor: &HarmonicFactor) -> HarmonicFactor {
        let read = factor.spilled.as_ref().and_then(|s| {
            let buffer = self.buffer().ok()?;
            s.read_then(&factor.values, buffer).ok()
        });
        if let Some(values) = read {
            return HarmonicFactor {
                m: factor.m,
                symbolic: factor.symbolic.clone(),
                values,
                offset: 0,
                pinned: factor.pinned.clone(),
                spilled: None,
                seconds: factor.seconds,
                joint_inverse: factor.joint_inverse.clone(),
            };
        }
        let (values, pinned) = match self.current_terms() {
            Some(terms) => self.terms_from(&terms, factor.m),
            None => self.assemble(factor.m),
        };
        self.numeric(factor.m, &values, pinned)
            .unwrap_or_else(|e| panic!("harmonic {} factorized before, not again: {e}", factor.m))
    }
}

/// Keeps `v` in `spare` if it holds a whole factor (`len` values) and
/// fewer than `keep` are kept.
fn keep_spare(spare: &Mutex<Vec<Vec<f64>>>, v: Vec<f64>, len: usize, keep: usize) {
    if v.capacity() < len {
        return;
    }
    if let Ok(mut spare) = spare.lock() {
        if spare.len() < keep {
            spare.push(v);
        }
    }
}
