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
    /// The initial phase (initial stresses and self-weight) found no
    /// equilibrium.
    #[error("initial phase: {message}")]
    InitialPhase {
        /// What happened.
        message: String,
        /// The joints cannot carry the initial state (not a numerical
        /// failure).
        beyond_capacity: bool,
    },
    /// A result file could not be written or read.
    #[error("{path}: {message}")]
    Output {
        /// The file or folder.
        path: PathBuf,
        /// What went wrong.
        message: String,
        /// Whose fault it is: the file system, the folder read, or the result.
        fault: OutputFault,
    },
}

/// What made a [`SolverError::Output`]: lets a caller (the `axijoint`
/// binary's exit status) tell a disk that refuses from a folder that is not
/// a solution and from a result that cannot be written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFault {
    /// The file system refused (permissions, a full disk, a path under a
    /// regular file, ...), or the output folder cannot be used (it exists
    /// and is not a solution folder).
    Io,
    /// A solution folder read back is not usable: no `solution.json` or
    /// another of its files, malformed, another version, truncated, or a
    /// mesh that does not match.
    Content,
    /// A displacement to write is not finite: the run's result is at
    /// fault, not the disk.
    NotFinite,
}
