//! A joint's CSV file and its map of states over (s, theta).

use super::context::Ctx;
use crate::error::ReportError;
use crate::{csv_out, plots};
use axijoint_mesh::Joint;
use axijoint_solver::results::JointFieldFile;

/// Writes joint `j`'s files from the joint field `jf`; returns their names.
pub(super) fn write(ctx: Ctx, jf: &JointFieldFile, j: &Joint) -> Result<Vec<String>, ReportError> {
    let Ctx {
        dir,
        outputs,
        length,
        stress,
        ..
    } = ctx;
    let mut files = Vec::new();
    if outputs.csv {
        let name = format!("joint_{}.csv", j.name);
        csv_out::write_joint(&dir.join(&name), jf, &j.name, length, stress)?;
        files.push(name);
    }
    if outputs.plots {
        let mut order: Vec<usize> = (0..jf.points.len())
            .filter(|&i| jf.points[i].joint == j.name)
            .collect();
        order.sort_by(|&a, &b| jf.points[a].s.total_cmp(&jf.points[b].s));
        order.dedup_by(|a, b| jf.points[*a].s == jf.points[*b].s);
        let s: Vec<f64> = order.iter().map(|&i| jf.points[i].s).collect();
        let states: Vec<Vec<_>> = jf
            .values
            .iter()
            .map(|v| order.iter().map(|&i| v[i].state).collect())
            .collect();
        let name = format!("joint_{}_states", j.name);
        plots::plot_joint_map(
            &dir.join(format!("{name}.svg")),
            ctx.png(&name).as_deref(),
            &format!("Joint {}: state over s ({length}) and theta", j.name),
            &s,
            &jf.sections_deg,
            &states,
        )?;
        files.extend(ctx.plot_files(&name));
    }
    Ok(files)
}
