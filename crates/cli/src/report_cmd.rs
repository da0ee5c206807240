//! `axijoint report`: every output of a saved solution, without solving.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub struct ReportArgs {
    /// A solution folder written by `axijoint solve` or `axijoint run`.
    pub dir: PathBuf,
    /// Other solution folders whose convergence goes on the same plot
    /// (each run labelled by its folder name, or as much of its path as
    /// tells it from the others).
    #[arg(long, value_name = "DIR", num_args = 1..)]
    pub compare: Vec<PathBuf>,
}

/// Writes every output of the folder and its `summary.json`.
pub fn run(args: &ReportArgs) -> Result<()> {
    crate::app::report::report(&args.dir, &args.compare)
}
