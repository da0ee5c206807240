//! `axijoint`: mesh -> solve -> report for axisymmetric bodies with joints.
//!
//! The only place that prints and picks exit codes: 0 success, 1 a failure
//! of the input or the run (the message names file, line or entity), 2 a
//! command-line usage error (from clap), 3 no equilibrium: the load exceeds
//! what the joints carry (a one-shot run that found none, or a stepped run
//! that stopped at its limit load factor below 1, whose outputs are written
//! for the last converged load factor).

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

fn main() -> ExitCode {
    let cli = Cli::parse();
    axijoint_solver::linear::prefer_harmonic_parallelism();
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
            if beyond_capacity(&e) {
                ExitCode::from(NO_EQUILIBRIUM)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}

/// Exit status when the load exceeds what the joints carry.
const NO_EQUILIBRIUM: u8 = 3;

/// Whether an error says the load exceeds the joints' capacity.
///
/// The solver returns an `IterationError` wrapped in `SolverError::Iteration`,
/// which is `#[error(transparent)]`: its `source()` is the inner error's
/// source, so the `IterationError` itself never appears in the chain and
/// must be looked for inside the `SolverError` too.
fn beyond_capacity(e: &anyhow::Error) -> bool {
    use axijoint_solver::error::SolverError;
    use axijoint_solver::iteration::IterationError;
    e.chain().any(|c| {
        c.downcast_ref::<solve_cmd::LimitReached>()
            .is_some_and(|l| l.beyond_capacity)
            || matches!(
                c.downcast_ref::<IterationError>(),
                Some(IterationError::NoEquilibrium { .. })
            )
            || matches!(
                c.downcast_ref::<SolverError>(),
                Some(SolverError::Iteration(IterationError::NoEquilibrium { .. }))
            )
    })
}
