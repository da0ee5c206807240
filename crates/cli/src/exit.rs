//! Exit statuses: the class of a failure, for the binary (`src/main.rs`,
//! whose module doc has the table) and the Python package.

/// Exit status of an input error (and of any failure not classed otherwise).
pub const INPUT_ERROR: u8 = 1;
/// Exit status when the load exceeds what the joints carry.
pub const BEYOND_CAPACITY: u8 = 3;
/// Exit status of a gmsh failure.
pub const GMSH_FAILURE: u8 = 4;
/// Exit status of an I/O error.
pub const IO_ERROR: u8 = 5;
/// Exit status of a run that stopped without a solution for a numerical
/// reason (not a limit load).
pub const NUMERICAL_FAILURE: u8 = 6;

/// The exit status of a failure (the table in the binary's module doc, `src/main.rs`, and in docs/outputs.md): the class of
/// the outermost error of the chain that has one, else [`INPUT_ERROR`].
///
/// The solver's errors are `#[error(transparent)]` wrappers: a
/// `SolverError::Iteration`'s `source()` is the inner error's source, so
/// the `IterationError` itself never appears in the chain on its own and is
/// classified inside the `SolverError` (as are `MeshError`, `SceneError`
/// and `SolveError`); the inner errors are also recognised on their own,
/// for the paths that return them unwrapped.
pub fn exit_status(e: &anyhow::Error) -> u8 {
    e.chain().find_map(class_of).unwrap_or(INPUT_ERROR)
}

/// The exit status of one error of a chain, if its type says it.
fn class_of(c: &(dyn std::error::Error + 'static)) -> Option<u8> {
    use axijoint_mesh::MeshError;
    use axijoint_report::error::ReportError;
    use axijoint_solver::error::SolverError;
    use axijoint_solver::iteration::IterationError;
    use axijoint_solver::linear::SolveError;
    use axijoint_solver::scene::SceneError;
    if let Some(l) = c.downcast_ref::<crate::app::solve::LimitReached>() {
        return Some(if l.beyond_capacity {
            BEYOND_CAPACITY
        } else {
            NUMERICAL_FAILURE
        });
    }
    if let Some(e) = c.downcast_ref::<SolverError>() {
        return Some(solver_status(e));
    }
    if let Some(e) = c.downcast_ref::<IterationError>() {
        return Some(iteration_status(e));
    }
    if let Some(e) = c.downcast_ref::<MeshError>() {
        return Some(mesh_status(e));
    }
    if let Some(e) = c.downcast_ref::<SceneError>() {
        return Some(scene_status(e));
    }
    if let Some(e) = c.downcast_ref::<SolveError>() {
        return Some(solve_status(e));
    }
    if let Some(e) = c.downcast_ref::<ReportError>() {
        return Some(match e {
            ReportError::Write { .. } => IO_ERROR,
            ReportError::NotFinite { .. } => NUMERICAL_FAILURE,
            ReportError::Input(_) => INPUT_ERROR,
        });
    }
    if c.downcast_ref::<std::io::Error>().is_some() {
        // Only the commands' own writes (summary.json, a temporary folder)
        // reach here bare: every read is inside a typed error above.
        return Some(IO_ERROR);
    }
    None
}

fn solver_status(e: &axijoint_solver::error::SolverError) -> u8 {
    use axijoint_solver::error::{OutputFault, SolverError};
    match e {
        SolverError::Mesh(e) => mesh_status(e),
        SolverError::Scene(e) => scene_status(e),
        SolverError::Solve(e) => solve_status(e),
        SolverError::Iteration(e) => iteration_status(e),
        SolverError::InitialPhase { beyond_capacity, .. } => {
            if *beyond_capacity {
                BEYOND_CAPACITY
            } else {
                NUMERICAL_FAILURE
            }
        }
        SolverError::Output { fault, .. } => match fault {
            OutputFault::Io => IO_ERROR,
            OutputFault::Content => INPUT_ERROR,
            OutputFault::NotFinite => NUMERICAL_FAILURE,
        },
    }
}

fn iteration_status(e: &axijoint_solver::iteration::IterationError) -> u8 {
    use axijoint_solver::iteration::IterationError;
    match e {
        IterationError::NoEquilibrium { .. } => BEYOND_CAPACITY,
        IterationError::NotConverged { .. }
        | IterationError::StiffJoint { .. }
        | IterationError::Rounds { .. } => NUMERICAL_FAILURE,
        IterationError::Setup(_) => INPUT_ERROR,
        // (Only the M/2 check is ever cancelled, and its error is not shown.)
        IterationError::Cancelled => NUMERICAL_FAILURE,
    }
}

fn mesh_status(e: &axijoint_mesh::MeshError) -> u8 {
    use axijoint_mesh::MeshError;
    match e {
        MeshError::GmshMissing { .. } | MeshError::GmshFailed { .. } => GMSH_FAILURE,
        MeshError::Io { source, .. } => io_status(source),
        MeshError::Parse { .. } | MeshError::Invalid { .. } | MeshError::UnknownName { .. } => INPUT_ERROR,
    }
}

fn scene_status(e: &axijoint_solver::scene::SceneError) -> u8 {
    use axijoint_solver::scene::SceneError;
    match e {
        SceneError::Io { error, .. } => io_status(error),
        SceneError::Parse { .. } | SceneError::Invalid { .. } | SceneError::UnknownName { .. } => INPUT_ERROR,
    }
}

fn solve_status(e: &axijoint_solver::linear::SolveError) -> u8 {
    use axijoint_solver::linear::SolveError;
    match e {
        // Singular: a mechanism, i.e. supports missing from the scene.
        SolveError::Singular { .. } | SolveError::Input(_) => INPUT_ERROR,
        SolveError::Factorization(_) => NUMERICAL_FAILURE,
    }
}

/// A file that could not be read: missing is an input error (a wrong
/// name), anything else the OS's (permissions, a folder, ...).
fn io_status(e: &std::io::Error) -> u8 {
    if e.kind() == std::io::ErrorKind::NotFound {
        INPUT_ERROR
    } else {
        IO_ERROR
    }
}
