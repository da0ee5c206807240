//! The solver crate's error: one enum over every stage of a run.

use crate::linear::SolveError;
use crate::scene::SceneError;
use axijoint_mesh::MeshError;
use std::path::PathBuf;

/// Anything that stops a run, naming the file, key, entity or harmonic.
#[derive(Debug, thiserror::Error)]
pub enum SolverError {
    /// The mesh could not be made or read.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The scene is malformed or does not fit the mesh.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The linear systems could not be solved.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// The nonlinear iteration found no solution.
    #[error(transparent)]
    Iteration(#[from] crate::iteration::IterationError),
    /// A result file could not be written or read.
    #[error("{path}: {message}")]
    Output {
        /// The file or folder.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}
