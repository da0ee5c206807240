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

use axijoint_cli::exit::exit_status;
use axijoint_cli::{mesh_cmd, report_cmd, solve_cmd};

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
    /// Neither read nor write the mesh cache: gmsh meshes every .geo once a run
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
