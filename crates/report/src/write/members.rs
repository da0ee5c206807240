//! A member's files: its section forces and motion (`member_<body>.csv`),
//! the surroundings' reaction (`reaction_<body>.csv`), their plots, and
//! over a load path the reaction curves (`reaction_curves_<body>.csv`, the
//! p-y family).

use super::context::Ctx;
use crate::error::ReportError;
use crate::{csv_out, plots};
use axijoint_solver::members::MemberForces;
use axijoint_solver::results::LoadPath;

/// Segments drawn in the p-y plot (evenly spread over the member).
const CURVES_DRAWN: usize = 8;

/// Writes the member's files; returns their names.
pub(super) fn write(
    ctx: Ctx,
    member: &MemberForces,
    path: Option<&LoadPath>,
) -> Result<Vec<String>, ReportError> {
    let (dir, outputs) = (ctx.dir, ctx.outputs);
    let (length, force) = (ctx.length, ctx.scene.units.force.as_str());
    let body = &member.body;
    let mut files = Vec::new();
    if outputs.csv {
        let name = format!("member_{body}.csv");
        csv_out::write_member(&dir.join(&name), member, length, force)?;
        files.push(name);
        let name = format!("reaction_{body}.csv");
        csv_out::write_reaction(&dir.join(&name), member, length, force)?;
        files.push(name);
    }
    // The member at every converged step of a load path.
    let steps: Vec<(f64, &MemberForces)> = path
        .into_iter()
        .flat_map(|p| &p.steps)
        .filter_map(|s| Some((s.lambda, s.observed.members.iter().find(|m| m.body == *body)?)))
        .collect();
    if outputs.csv && !steps.is_empty() {
        let name = format!("reaction_curves_{body}.csv");
        csv_out::write_reaction_curves(&dir.join(&name), &steps, length, force)?;
        files.push(name);
    }
    if !outputs.plots {
        return Ok(files);
    }
    if let Some(name) = p_y_plot(ctx, body, &steps)? {
        files.extend(ctx.plot_files(&name));
    }
    let st = &member.stations;
    let along = |label: &str, color: usize, value: &dyn Fn(usize) -> f64| plots::Series {
        label: label.to_string(),
        points: (0..st.len()).map(|k| (value(k), st[k].z)).collect(),
        color,
        dash: 0,
    };
    let seg = &member.segments;
    // Per unit length, drawn as steps over each segment.
    let per_length = |label: &str, color: usize, c: usize| plots::Series {
        label: label.to_string(),
        points: seg
            .iter()
            .flat_map(|s| {
                let q = s.force[c] / (s.z_top - s.z_bottom);
                [(q, s.z_top), (q, s.z_bottom)]
            })
            .collect(),
        color,
        dash: 0,
    };
    let figures: [(&str, String, String, Vec<plots::Series>); 4] = [
        (
            "forces",
            format!("{body}: section forces"),
            format!("force ({force})"),
            vec![
                along("N (tension +)", 0, &|k| st[k].force[2]),
                along("V_x", 1, &|k| st[k].force[0]),
                along("V_y", 2, &|k| st[k].force[1]),
            ],
        ),
        (
            "moments",
            format!("{body}: bending moment and torque"),
            format!("moment ({force} {length})"),
            vec![
                along("M_y", 0, &|k| st[k].moment[1]),
                along("M_x", 1, &|k| st[k].moment[0]),
                along("T", 2, &|k| st[k].moment[2]),
            ],
        ),
        (
            "displacement",
            format!("{body}: mean displacement of the cross-section"),
            format!("displacement ({length})"),
            vec![
                along("u_x", 0, &|k| st[k].displacement[0]),
                along("u_y", 1, &|k| st[k].displacement[1]),
                along("u_z", 2, &|k| st[k].displacement[2]),
            ],
        ),
        (
            "reaction",
            format!("{body}: reaction of the surroundings per unit length"),
            format!("force per length ({force}/{length})"),
            vec![
                per_length("p_x", 0, 0),
                per_length("p_y", 1, 1),
                per_length("t (z)", 2, 2),
            ],
        ),
    ];
    for (tag, title, x_label, series) in figures {
        // A component that is nil (below 1e-9 of the largest) is left out
        // of the legend.
        let largest = |s: &plots::Series| s.points.iter().map(|p| p.0.abs()).fold(0.0, f64::max);
        let top = series.iter().map(largest).fold(0.0, f64::max);
        let series: Vec<plots::Series> = series.into_iter().filter(|s| largest(s) > 1e-9 * top).collect();
        if series.is_empty() {
            continue;
        }
        let name = format!("member_{body}_{tag}");
        let plot = plots::ProfilePlot {
            title: &title,
            x_label: &x_label,
            y_label: &format!("z ({length})"),
            series: &series,
            markers: &[],
            position: plots::Axis::Y,
        };
        plots::plot_profile_with(&dir.join(format!("{name}.svg")), ctx.png(&name).as_deref(), &plot)?;
        files.extend(ctx.plot_files(&name));
    }
    Ok(files)
}

/// The p-y curves of a load path: `p_x` against the segment's mean `u_x`
/// from the unloaded state, [`CURVES_DRAWN`] segments spread over the
/// member; `None` without steps or lateral reaction.
fn p_y_plot(ctx: Ctx, body: &str, steps: &[(f64, &MemberForces)]) -> Result<Option<String>, ReportError> {
    let (length, force) = (ctx.length, ctx.scene.units.force.as_str());
    let Some((_, last)) = steps.last() else {
        return Ok(None);
    };
    let n = last.segments.len();
    if n == 0 || last.segments.iter().all(|s| s.force[0] == 0.0) {
        return Ok(None);
    }
    let picks: Vec<usize> = if n <= CURVES_DRAWN {
        (0..n).collect()
    } else {
        (0..CURVES_DRAWN)
            .map(|i| i * (n - 1) / (CURVES_DRAWN - 1))
            .collect()
    };
    let series: Vec<plots::Series> = picks
        .iter()
        .enumerate()
        .map(|(color, &k)| {
            let seg = &last.segments[k];
            plots::Series {
                label: format!("z = {:.3} to {:.3}", seg.z_top, seg.z_bottom),
                points: std::iter::once((0.0, 0.0))
                    .chain(steps.iter().filter_map(|(_, m)| {
                        let s = m.segments.get(k)?;
                        let u = 0.5 * (m.stations[k].displacement[0] + m.stations[k + 1].displacement[0]);
                        Some((u, s.force[0] / (s.z_top - s.z_bottom)))
                    }))
                    .collect(),
                color,
                dash: 0,
            }
        })
        .collect();
    let name = format!("member_{body}_p_y");
    let title = format!("{body}: p-y curves (reaction p_x per unit length against the mean u_x)");
    plots::plot_profile(
        &ctx.dir.join(format!("{name}.svg")),
        ctx.png(&name).as_deref(),
        &title,
        &format!("u_x ({length})"),
        &format!("p_x ({force}/{length})"),
        &series,
    )?;
    Ok(Some(name))
}
