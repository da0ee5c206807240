//! The load state an evaluation sees ([`LoadState`]): the load factor, the
//! joint law (the paper's, or the history law of a load step) and what the
//! release returns; the committed state of a load step ([`History`]).

use crate::joint_law::PointHistory;

/// What a converged load step commits: the joints' history per (section,
/// point) pair and the plastic bodies' plastic strain per (section, body
/// point) (empty without plastic bodies).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct History {
    /// The joints' history (index `s * n_points + p`).
    pub(crate) joints: Vec<PointHistory>,
    /// The plastic strain (index `s * body points + q`).
    pub(crate) plastic: Vec<[f64; 6]>,
}

/// What the release of a (section, point) returns to the harmonics.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Release {
    /// The inadmissible traction: what K_m's spring and the initial
    /// traction carry minus what the law allows (the iteration).
    Excess,
    /// The whole traction of the assembled springs: only for the
    /// reference `Psi_0` of a run with a softened joint.
    Carried,
}

/// The load and the law an evaluation sees.
#[derive(Clone, Copy)]
pub(super) struct LoadState<'h> {
    /// The load factor lambda: the loads are `lambda F`.
    pub(super) lambda: f64,
    /// The committed history of every (section, point) pair (index
    /// `s * n_points + p`): `Some` selects the history law of stepped
    /// loading, `None` the paper's law.
    pub(super) history: Option<&'h History>,
    /// What the release returns.
    pub(super) release: Release,
}

impl<'h> LoadState<'h> {
    /// The whole load under the paper's law (a one-shot run).
    pub(super) const WHOLE: LoadState<'static> = LoadState {
        lambda: 1.0,
        history: None,
        release: Release::Excess,
    };

    /// The load `lambda F` under the history law from `history`.
    pub(super) fn stepped(lambda: f64, history: &'h History) -> Self {
        LoadState {
            lambda,
            history: Some(history),
            release: Release::Excess,
        }
    }

    /// The committed history of pair `k`, if the history law applies.
    pub(super) fn history_of(&self, k: usize) -> Option<&'h PointHistory> {
        self.history.and_then(|h| h.joints.get(k))
    }

    /// The committed plastic strain of body pair `k` (zero before the
    /// first step and under the paper's law).
    pub(super) fn plastic_of(&self, k: usize) -> [f64; 6] {
        self.history
            .and_then(|h| h.plastic.get(k))
            .copied()
            .unwrap_or([0.0; 6])
    }
}
