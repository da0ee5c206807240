//! The method stage: the scene's method ([`Method`]) run on one sweep,
//! from a start, to a converged state or a failure.

use super::attempt::{Converged, Failure, Start};
use super::fixed_point::fixed_point;
use super::newton::newton;
use super::sweep::Sweep;
use super::types::{IterationRecord, IterationSettings, Method};

/// Runs `settings.method` on `sweep` from `start`; `progress` sees each
/// record.
pub(super) fn run(
    sweep: &Sweep,
    settings: &IterationSettings,
    start: Start,
    progress: &mut dyn FnMut(&IterationRecord),
) -> Result<Converged, Box<Failure>> {
    match settings.method {
        Method::Plain => fixed_point(sweep, 0, settings, start, progress),
        Method::Anderson { depth } => fixed_point(sweep, depth, settings, start, progress),
        Method::Newton => newton(sweep, settings, start, progress),
    }
}
