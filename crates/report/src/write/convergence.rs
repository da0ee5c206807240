//! The convergence history: its CSV file and its plot, with the histories
//! of other runs to compare on the same axis.

use super::context::Ctx;
use crate::error::ReportError;
use crate::{csv_out, plots};
use axijoint_solver::iteration::IterationRecord;

/// Writes the history's files (this run's curve labelled `label`, default
/// the scene's title); returns their names.
pub(super) fn write(
    ctx: Ctx,
    history: &[IterationRecord],
    label: Option<&str>,
    compare: &[(String, Vec<IterationRecord>)],
) -> Result<Vec<String>, ReportError> {
    let (dir, outputs) = (ctx.dir, ctx.outputs);
    let mut files = Vec::new();
    if outputs.csv {
        csv_out::write_convergence(&dir.join("convergence.csv"), history)?;
        files.push("convergence.csv".into());
    }
    if outputs.plots {
        let mut runs = vec![(
            label.unwrap_or(&ctx.scene.title).to_owned(),
            history.iter().map(|r| (r.iteration, r.ratio)).collect(),
        )];
        runs.extend(
            compare
                .iter()
                .map(|(label, h)| (label.clone(), h.iter().map(|r| (r.iteration, r.ratio)).collect())),
        );
        plots::plot_convergence(
            &dir.join("convergence.svg"),
            ctx.png("convergence").as_deref(),
            "Residual ratio (Eq. 12) against iteration",
            &runs,
        )?;
        files.extend(ctx.plot_files("convergence"));
    }
    Ok(files)
}
