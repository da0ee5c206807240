//! The cuts: each cut's CSV files (one per angle, and the initial state's),
//! and its plot with the run without joints dashed.

use super::context::{fmt_angle, Ctx};
use crate::error::ReportError;
use crate::field::{Field, Locator};
use crate::record::materials;
use crate::recovery::PlasticStress;
use crate::{csv_out, cut_plot, cuts, plots};
use axijoint_solver::results::SavedSolution;
use axijoint_solver::scene::Cut;

/// What the cuts are sampled from: the field, the initial state alone
/// (its own cut files), the point locator and the plastic bodies' stress.
pub(super) struct Cuts<'a> {
    pub ctx: Ctx<'a>,
    pub field: &'a Field<'a>,
    pub initial: Option<&'a Field<'a>>,
    pub locator: &'a Locator,
    /// The plastic bodies' stress (`plastic.json`), if any.
    pub plastic: Option<&'a PlasticStress<'a>>,
}

impl Cuts<'_> {
    /// Every cut's files, the cuts in parallel, with `other` (the run
    /// without joints) when there is one.
    pub fn write_all(&self, other: Option<&SavedSolution>) -> Result<Vec<String>, ReportError> {
        use rayon::prelude::*;
        let parts = match other {
            Some(c) => Some((c, materials(c)?, Locator::new(&c.mesh))),
            None => None,
        };
        let other = parts.as_ref().map(|(c, m, loc)| {
            let f = Field {
                mesh: &c.mesh,
                materials: m,
                u: &c.displacements,
                initial: crate::field::Initial::of(c),
            };
            (f, loc)
        });
        let files = self
            .ctx
            .scene
            .cuts
            .par_iter()
            .map(|cut| self.write(cut, other.as_ref().map(|(f, l)| (f, *l))))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(files.concat())
    }

    /// A cut's files; `other`: the run without joints and its locator.
    fn write(&self, cut: &Cut, other: Option<(&Field, &Locator)>) -> Result<Vec<String>, ReportError> {
        let Ctx {
            dir,
            saved,
            outputs,
            length,
            stress,
            ..
        } = self.ctx;
        let mut files = Vec::new();
        let mut series = Vec::new();
        for (k, &t) in cut.theta_deg.iter().enumerate() {
            let rows = cuts::profile_with(
                self.field,
                self.locator,
                &[cut.from, cut.to],
                cut.spacing,
                &[t],
                self.plastic,
            );
            if outputs.csv {
                let name = format!("cut_{}_theta{}.csv", cut.name, fmt_angle(t));
                csv_out::write_cut(&dir.join(&name), &rows, length, stress)?;
                files.push(name);
                if let Some(f) = self.initial {
                    let rows = cuts::profile(f, self.locator, &[cut.from, cut.to], cut.spacing, &[t]);
                    let name = format!("cut_{}_theta{}_initial.csv", cut.name, fmt_angle(t));
                    csv_out::write_cut(&dir.join(&name), &rows, length, stress)?;
                    files.push(name);
                }
            }
            if !outputs.plots {
                continue;
            }
            let c = cut.component_index().unwrap_or(1);
            let with_joints = !saved.mesh.joints.is_empty();
            series.extend(by_body(
                &rows,
                c,
                t,
                k,
                &saved.mesh,
                if with_joints { "with joint" } else { "" },
                false,
            ));
            if let Some((f, loc)) = other {
                let rows = cuts::profile(f, loc, &[cut.from, cut.to], cut.spacing, &[t]);
                series.extend(by_body(&rows, c, t, k, f.mesh, "without joint", true));
            }
        }
        if outputs.plots {
            files.extend(cut_plot::write(
                dir,
                cut,
                &saved.mesh,
                series,
                length,
                stress,
                outputs.png,
            )?);
        }
        Ok(files)
    }
}

/// One plot series per body of a cut's rows (a jump at an interface shows
/// as two lines), as `(s, value)`; colour slot `k * bodies + body`, dash 1
/// when `dashed`.
fn by_body(
    rows: &[cuts::CutRow],
    component: usize,
    theta: f64,
    k: usize,
    mesh: &axijoint_mesh::Mesh,
    variant: &str,
    dashed: bool,
) -> Vec<plots::Series> {
    mesh.bodies
        .iter()
        .enumerate()
        .filter_map(|(b, body)| {
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.body == body.name)
                .map(|r| (r.s, r.stress[component]))
                .collect();
            let sep = if variant.is_empty() { "" } else { ", " };
            (!points.is_empty()).then(|| plots::Series {
                label: format!("theta {theta} deg, {}{sep}{variant}", body.name),
                points,
                color: k * mesh.bodies.len() + b,
                dash: usize::from(dashed),
            })
        })
        .collect()
}
