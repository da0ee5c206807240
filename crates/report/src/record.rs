//! What the report reads from the run record besides the field: the
//! bodies' materials, the iteration history and the load path.

use crate::error::ReportError;
use axijoint_solver::iteration::IterationRecord;
use axijoint_solver::results::{LoadPath, SavedSolution};

/// The materials of a saved solution's bodies.
pub(crate) fn materials(
    saved: &SavedSolution,
) -> Result<Vec<axijoint_solver::material::Elastic>, ReportError> {
    saved
        .mesh
        .bodies
        .iter()
        .map(|b| {
            saved
                .header
                .scene
                .materials
                .get(&b.name)
                .map(|m| m.elastic())
                .ok_or_else(|| ReportError::Input(format!("no material for body '{}'", b.name)))
        })
        .collect()
}

/// The iteration history saved in a solution's header, if any.
pub fn history(saved: &SavedSolution) -> Option<&[IterationRecord]> {
    saved.header.record.as_ref()?.history.as_deref()
}

/// The load path of a stepped run, if the solution has one.
pub fn load_path(saved: &SavedSolution) -> Option<&LoadPath> {
    saved.header.record.as_ref()?.load_path.as_ref()
}
