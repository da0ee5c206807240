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
//! | [`csv_out`] | CSV writers |
//! | [`write_report`] | every output of a solution folder |

pub mod csv_out;
pub mod cuts;
pub mod error;
pub mod field;
pub mod plots;
pub mod gmsh_view;
pub mod vtu;

pub use error::ReportError;

use axijoint_solver::iteration::IterationRecord;
use axijoint_solver::results::{read_joint_field, SavedSolution};
use std::path::{Path, PathBuf};

/// Files written by [`write_report`], relative to the solution folder.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Written {
    /// Paths written.
    pub files: Vec<PathBuf>,
}

/// Writes every report output of a saved solution into `dir` (the solution
/// folder itself): cut CSVs, joint CSVs, the convergence CSV.
pub fn write_report(dir: &Path, saved: &SavedSolution) -> Result<Written, ReportError> {
    let scene = &saved.header.scene;
    let materials: Vec<_> = saved
        .mesh
        .bodies
        .iter()
        .map(|b| {
            scene
                .materials
                .get(&b.name)
                .map(|m| m.elastic())
                .ok_or_else(|| ReportError::Input(format!("no material for body '{}'", b.name)))
        })
        .collect::<Result<_, _>>()?;
    let field = field::Field {
        mesh: &saved.mesh,
        materials: &materials,
        u: &saved.displacements,
    };
    let locator = field::Locator::new(&saved.mesh);
    let (length, stress) = (&scene.units.length, &scene.units.stress);
    let mut written = Written::default();
    for cut in &scene.cuts {
        for &t in &cut.theta_deg {
            let rows = cuts::profile(&field, &locator, &[cut.from, cut.to], cut.spacing, &[t]);
            let name = format!("cut_{}_theta{}.csv", cut.name, fmt_angle(t));
            csv_out::write_cut(&dir.join(&name), &rows, length, stress)?;
            written.files.push(name.into());
        }
    }
    let joints = read_joint_field(dir).map_err(|e| ReportError::Input(e.to_string()))?;
    if let Some(jf) = &joints {
        for j in &saved.mesh.joints {
            let name = format!("joint_{}.csv", j.name);
            csv_out::write_joint(&dir.join(&name), jf, &j.name, length, stress)?;
            written.files.push(name.into());
        }
    }
    if let Some(h) = saved.header.extra.get("history") {
        let history: Vec<IterationRecord> =
            serde_json::from_value(h.clone()).map_err(|e| ReportError::Input(format!("history: {e}")))?;
        csv_out::write_convergence(&dir.join("convergence.csv"), &history)?;
        written.files.push("convergence.csv".into());
    }
    Ok(written)
}

/// An angle for file names: `0`, `180`, `22.5`.
pub fn fmt_angle(t: f64) -> String {
    let s = format!("{t}");
    s.replace('-', "m")
}
