//! The load path of a stepped run: its CSV file and the pushover curves.

use super::context::Ctx;
use crate::error::ReportError;
use crate::{csv_out, plots};
use axijoint_solver::results::LoadPath;

/// Writes the load path's files; returns their names.
pub(super) fn write(ctx: Ctx, path: &LoadPath) -> Result<Vec<String>, ReportError> {
    let (dir, outputs, length) = (ctx.dir, ctx.outputs, ctx.length);
    let mut files = Vec::new();
    if outputs.csv {
        csv_out::write_load_path(&dir.join("load_path.csv"), path, length)?;
        files.push("load_path.csv".into());
    }
    if outputs.plots && !path.steps.is_empty() {
        // Pushover curves: lambda against each loaded face's displacement
        // along its load, from the unloaded state.
        let n_faces = path.steps[0].observed.faces.len();
        let series: Vec<plots::Series> = (0..n_faces)
            .map(|k| plots::Series {
                label: format!("{}, along the load", path.steps[0].observed.faces[k].on),
                points: std::iter::once((0.0, 0.0))
                    .chain(path.steps.iter().map(|s| (s.observed.faces[k].along, s.lambda)))
                    .collect(),
                color: k,
                dash: 0,
            })
            .collect();
        let title = match &path.limit {
            Some(l) => format!(
                "Load path: limit load factor {:.4} (failed at {:.4})",
                l.factor, l.failed_at
            ),
            None => "Load path: load factor against displacement".to_string(),
        };
        plots::plot_profile(
            &dir.join("load_path.svg"),
            ctx.png("load_path").as_deref(),
            &title,
            &format!("displacement along the load ({length})"),
            "load factor lambda (-)",
            &series,
        )?;
        files.extend(ctx.plot_files("load_path"));
    }
    Ok(files)
}
