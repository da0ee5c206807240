//! `axijoint`: mesh -> solve -> report for axisymmetric bodies with joints.
//!
//! The only place that prints and picks exit codes. A failure prints one
//! message (`error: ...`, naming the file, line, key path or entity) and
//! exits with the status of its class, the same for every subcommand
//! (`mesh`, `solve`, `run`, `report`). docs/outputs.md ("Exit status")
//! has the same table, docs/loading.md ("Exit status") the same statuses
//! (tests/exit_status_e2e.rs checks both).
//!
//! | status | class | when |
//! |---|---|---|
//! | 0 | success | everything was written; for a nonlinear scene the whole load was reached |
//! | 1 | input error | a scene, mesh (`.geo` or `.msh`) or solution folder that does not exist, is malformed, names an entity the mesh lacks or has invalid values; a mesh gmsh made that is unusable (e.g. an inverted element); a model with too few supports (singular stiffness); sections that cannot resolve the harmonics; a bad command-line value (`--set size=abc`); any failure not classed below |
//! | 2 | usage error | the command line does not parse (from clap) |
//! | 3 | beyond capacity | the load exceeds what the joints carry: a stepped run that stopped at its limit load factor below 1 (every output written for that factor; the console prints `LIMIT LOAD FACTOR`), or a one-shot run that found no equilibrium (its last iterate written, marked `"converged": false`) |
//! | 4 | gmsh failure | gmsh is not found or cannot be started, or it exits non-zero or prints an `Error` line (a `.geo`, or a `--set` value, it rejects) |
//! | 5 | I/O error | an existing input that cannot be read for an OS reason (permissions, a folder where a file is expected); an output that cannot be written (permissions, a path under a regular file, a full disk), or an output folder that exists and is not a solution folder |
//! | 6 | numerical failure | the run stopped without a solution for a reason that does not show the load exceeds the joints' capacity: a one-shot run at its iteration limit, stalled on a stiff joint or whose debonding did not settle (its last iterate written, marked `"converged": false`); a stepped run that stopped short of the whole load for such a reason (`limit.beyond_capacity: false`, the console prints `STOPPED (not a limit load)`, every output written for the last converged factor); a result that is not finite; a factorization that failed (out of memory) |
//!
//! [`exit_status`] classifies an error by walking its `anyhow` chain from
//! the outermost error in and taking the first typed error it knows:
//! `LimitReached` (a stepped run that stopped short), `SolverError` and the
//! errors it wraps (`MeshError`, `SceneError`, `SolveError`,
//! `IterationError`, and its own `Output` with its `OutputFault`),
//! `ReportError`, and a bare `std::io::Error` (5). An error with none of
//! these (a message of this binary) is an input error (1). A file that
//! could not be read is an input error when it does not exist (a wrong
//! name), an I/O error otherwise.

mod cases_cmd;
mod mesh_cmd;
mod report_cmd;
mod solve_cmd;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "axijoint",
    version,
    about = "Axisymmetric bodies under non-axisymmetric loads, with joints that open and slip"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Neither read nor write the mesh cache: gmsh meshes every .geo
    /// (cache: $AXIJOINT_CACHE, else $XDG_CACHE_HOME/axijoint, else ~/.cache/axijoint).
    #[arg(long, global = true)]
    no_cache: bool,
}

#[derive(Subcommand)]
enum Command {
    /// Mesh a .geo with gmsh (or read a .msh), insert joints, validate, and print a summary.
    Mesh(mesh_cmd::MeshArgs),
    /// Solve a scene (joints that open and slip by the stress-transfer iteration); write the solution folder.
    Solve(solve_cmd::SolveArgs),
    /// Mesh, solve and write every result of a scene [default: Scene P].
    Run(solve_cmd::RunArgs),
    /// Regenerate every output (CSV, plots, views, summary.json) of a saved solution folder.
    Report(report_cmd::ReportArgs),
}

/// Makes glibc map every allocation of 4 MiB or more on its own (a
/// harmonic's stiffness values, a factor, solver buffers) instead of raising
/// that threshold after the first such free and keeping freed arrays in
/// per-thread heaps: +13 % peak memory measured on Scene P at M = 32
/// without it (docs/performance.md).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn map_large_allocations() {
    // SAFETY: sets one malloc tuning parameter, before any other thread runs.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 4 << 20);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn map_large_allocations() {}

fn main() -> ExitCode {
    map_large_allocations();
    let cli = Cli::parse();
    axijoint_solver::linear::prefer_harmonic_parallelism();
    if !cli.no_cache {
        axijoint_mesh::gmsh::cache::set_dir(axijoint_mesh::gmsh::cache::default_dir());
    }
    let result = match cli.command {
        Command::Mesh(args) => mesh_cmd::run(&args),
        Command::Solve(args) => solve_cmd::run_solve(&args),
        Command::Run(args) => solve_cmd::run_run(&args),
        Command::Report(args) => report_cmd::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(exit_status(&e))
        }
    }
}

/// Exit status of an input error (and of any failure not classed otherwise).
const INPUT_ERROR: u8 = 1;
/// Exit status when the load exceeds what the joints carry.
const BEYOND_CAPACITY: u8 = 3;
/// Exit status of a gmsh failure.
const GMSH_FAILURE: u8 = 4;
/// Exit status of an I/O error.
const IO_ERROR: u8 = 5;
/// Exit status of a run that stopped without a solution for a numerical
/// reason (not a limit load).
const NUMERICAL_FAILURE: u8 = 6;

/// The exit status of a failure (table in the module doc): the class of
/// the outermost error of the chain that has one, else [`INPUT_ERROR`].
///
/// The solver's errors are `#[error(transparent)]` wrappers: a
/// `SolverError::Iteration`'s `source()` is the inner error's source, so
/// the `IterationError` itself never appears in the chain on its own and is
/// classified inside the `SolverError` (as are `MeshError`, `SceneError`
/// and `SolveError`); the inner errors are also recognised on their own,
/// for the paths that return them unwrapped.
fn exit_status(e: &anyhow::Error) -> u8 {
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
    if let Some(l) = c.downcast_ref::<solve_cmd::LimitReached>() {
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
        // Only this binary's own writes (summary.json, a temporary folder)
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
        SceneError::Io { source, .. } => io_status(source),
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
