//! The load path of a stepped run: its CSV file and the pushover curves;
//! with stages, the stages' CSV and the hysteresis plot.

use super::context::Ctx;
use crate::error::ReportError;
use crate::{csv_out, plots};
use axijoint_solver::results::LoadPath;
use axijoint_solver::scene::Load;

/// The unit of each loaded face's applied load along its direction (in
/// the order of the steps' faces): a force, or a moment for a pure torque.
fn applied_units(ctx: &Ctx, path: &LoadPath) -> Vec<String> {
    let (force, length) = (&ctx.scene.units.force, ctx.length);
    let Some(first) = path.steps.first() else {
        return Vec::new();
    };
    let loads: Vec<Load> = if ctx.scene.stages.is_empty() {
        ctx.scene.loads.clone()
    } else {
        ctx.scene.staged_faces()
    };
    first
        .observed
        .faces
        .iter()
        .map(|f| match loads.iter().find(|l| l.on() == f.on) {
            Some(Load::Resultant(r)) if r.force == [0.0; 3] => format!("{force} {length}"),
            Some(Load::Motion(m)) if m.displacement == [0.0; 3] => format!("{force} {length}"),
            _ => force.clone(),
        })
        .collect()
}

/// Writes the load path's files; returns their names.
pub(super) fn write(ctx: Ctx, path: &LoadPath) -> Result<Vec<String>, ReportError> {
    let (dir, outputs, length) = (ctx.dir, ctx.outputs, ctx.length);
    let mut files = Vec::new();
    let units = applied_units(&ctx, path);
    let staged = path.steps.first().is_some_and(|s| s.observed.stage.is_some());
    if outputs.csv {
        csv_out::write_load_path(&dir.join("load_path.csv"), path, length, &units)?;
        files.push("load_path.csv".into());
        if staged {
            csv_out::write_stages(&dir.join("stages.csv"), path, length, &units)?;
            files.push("stages.csv".into());
        }
    }
    if outputs.plots && !path.steps.is_empty() {
        // Pushover curves: lambda against each loaded face's displacement
        // along its load, from the unloaded state.
        // Every face moved by a motion (no stages): its reaction instead.
        let n_faces = path.steps[0].observed.faces.len();
        let reaction =
            !staged && n_faces > 0 && path.steps[0].observed.faces.iter().all(|f| f.applied.is_some());
        let series: Vec<plots::Series> = (0..n_faces)
            .map(|k| plots::Series {
                label: format!("{}, along the load", path.steps[0].observed.faces[k].on),
                points: std::iter::once((0.0, 0.0))
                    .chain(path.steps.iter().map(|s| {
                        let f = &s.observed.faces[k];
                        (
                            f.along,
                            if reaction {
                                f.applied.unwrap_or(0.0)
                            } else {
                                s.lambda
                            },
                        )
                    }))
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
            None if reaction => "Load path: reaction against the prescribed displacement".to_string(),
            None => "Load path: load factor against displacement".to_string(),
        };
        let y_label = if reaction {
            format!(
                "reaction along the motion ({})",
                units.first().map_or("-", String::as_str)
            )
        } else {
            "load factor lambda (-)".to_string()
        };
        plots::plot_profile(
            &dir.join("load_path.svg"),
            ctx.png("load_path").as_deref(),
            &title,
            &format!("displacement along the load ({length})"),
            &y_label,
            &series,
        )?;
        files.extend(ctx.plot_files("load_path"));
        if staged && n_faces > 0 {
            plots::plot_profile(
                &dir.join("hysteresis.svg"),
                ctx.png("hysteresis").as_deref(),
                &format!(
                    "Load against displacement of {}, by stage and cycle",
                    path.steps[0].observed.faces[0].on
                ),
                &format!("displacement along the load ({length})"),
                &format!("load ({})", units[0]),
                &hysteresis(path),
            )?;
            files.extend(ctx.plot_files("hysteresis"));
        }
    }
    Ok(files)
}

/// The first face's load against its displacement along it: a series per
/// stage, or per cycle of a cyclic stage, each from the point before it.
fn hysteresis(path: &LoadPath) -> Vec<plots::Series> {
    let mut series: Vec<plots::Series> = Vec::new();
    let mut last = (0.0, 0.0);
    let mut key = None;
    for s in &path.steps {
        let (Some(m), Some(f)) = (&s.observed.stage, s.observed.faces.first()) else {
            continue;
        };
        let point = (f.along, f.applied.unwrap_or(0.0));
        if key.as_ref() != Some(&(m.stage.clone(), m.cycle)) {
            key = Some((m.stage.clone(), m.cycle));
            let label = if m.cycle == 0 {
                m.stage.clone()
            } else {
                format!("{}, cycle {}", m.stage, m.cycle)
            };
            series.push(plots::Series {
                label,
                points: vec![last],
                color: series.len(),
                dash: 0,
            });
        }
        if let Some(cur) = series.last_mut() {
            cur.points.push(point);
        }
        last = point;
    }
    series
}
