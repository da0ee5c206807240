//! The `axijoint` commands as a library: the code the binary runs, for
//! other front ends (the Python package, `crates/python`).
//!
//! The binary (`src/main.rs`) prints and picks exit statuses; these modules
//! do the work: [`solve_cmd::solve_to`] solves a scene into a solution
//! folder, [`report_cmd::write_outputs`] writes the report and
//! `summary.json`.

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

pub mod cases_cmd;
pub mod exit;
pub mod mesh_cmd;
pub mod report_cmd;
pub mod solve_cmd;
