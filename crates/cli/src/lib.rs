//! The `axijoint` commands as a library: the code the binary runs, for
//! other front ends (the Python package, `crates/python`).
//!
//! The binary (`src/main.rs`) prints and picks exit statuses; these modules
//! do the work: [`solve_cmd::solve_to`] solves a scene into a solution
//! folder, [`report_cmd::write_outputs`] writes the report and
//! `summary.json`.

pub mod cases_cmd;
pub mod exit;
pub mod mesh_cmd;
pub mod report_cmd;
pub mod solve_cmd;
