//! What the user reads: stress profiles along cuts, joint fields,
//! convergence histories, plots, and 3D views of a saved solution.
//!
//! | symbol | meaning |
//! |---|---|
//! | r, z, theta | cylindrical coordinates; theta = 0 on +x |
//! | s | distance along a cut or a joint |
//! | sigma_r ... tau_ztheta | stress components (tension positive) |
//! | sigma, tau_xi, tau_theta | joint normal and shear tractions |
//! | d_xi, d_eta, d_theta | joint relative displacement (top - bottom) |
//!
//! | main items | role |
//! |---|---|
//! | [`field::Locator`] | R-tree point location in the meridional mesh |
//! | [`field::Field`] | displacement and stress synthesized at any theta, per body |
//! | [`cuts::profile`] | a cut's rows, two per interface crossing |
//! | [`cuts::joint_crossings`], [`cut_plot`] | where a cut meets joints; a cut's plot |
//! | [`csv_out`] | CSV writers |
//! | [`plots`] | SVG and PNG plots (embedded font) |
//! | [`vtu`], [`gmsh_view`] | the field revolved for ParaView; a gmsh view |
//! | [`write_report`] | every output of a solution folder |
//!
//! The report's stages ([`write_report`]): read the run record (materials,
//! [`history`], [`load_path`]); make the [`field::Field`] of the solution
//! (and of its initial state) and its [`field::Locator`]; then write each
//! output in parallel, every file whole or not at all
//! ([`axijoint_mesh::atomic`]): the cuts (CSV and plot), each joint (CSV
//! and state map), the convergence and the load path (CSV and plot), the
//! revolved `.vtu` and the gmsh view; the error estimate
//! ([`estimate::Estimate`]) runs alongside.

pub mod adapt;
pub mod csv_out;
pub mod cut_plot;
pub mod cuts;
pub mod error;
pub mod estimate;
pub mod field;
pub mod gmsh_view;
pub mod plots;
mod record;
pub mod recovery;
pub mod vtu;
mod write;

pub use error::ReportError;
pub use record::{history, load_path};
pub use write::{fmt_angle, write_report, Written};
