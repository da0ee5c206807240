//! The `axijoint` application as a library: the code the binary runs, for
//! other front ends (the Python package, `crates/python`).
//!
//! ```text
//! main.rs                      arguments -> command -> exit status
//! mesh_cmd, solve_cmd, report_cmd   a command's arguments, read into a scene and options
//! app                          run: solve (or load cases), comparison, report
//! exit                         the exit status of an error
//! ```
//!
//! [`app::run`] solves a scene (or its load cases) into a solution folder,
//! with the comparison without joints and the report as its
//! [`app::Options`] ask; [`app::report::write_outputs`] writes the report
//! and `summary.json` of a saved folder.

/// Prints a line to stdout, best effort: a closed or full stdout (`| head`,
/// `> /dev/full`) must not stop a run before its files are written (the
/// files are the result; `println!` panics there).
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($arg)*);
    }};
}

/// [`say!`] without the newline.
#[macro_export]
macro_rules! say_part {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stdout().lock(), $($arg)*);
    }};
}

pub mod app;
pub mod exit;
pub mod mesh_cmd;
pub mod report_cmd;
pub mod solve_cmd;
