//! `"harmonics": "auto"`: M grows 4, 8, 16, ... until the measured results
//! settle, the factors of lower harmonics kept.

use super::check::{face_means, motion_reactions};
use super::elastic::{elastic, Elastic};
use super::factors::{factorize_and_solve, plan_factors};
use super::initial::initial_phase;
use super::measures::{reactions, scaled, with_released};
use super::nonlinear::iterate;
use super::sections::scene_sections;
use super::start::Start;
use super::{solve_scene, Run, Stopped};
use crate::iteration::{IterationRecord, Outcome};
use crate::linear::Model;
use crate::results::{AutoStep, LoadPath};
use crate::scene::Scene;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// Chooses M automatically: a linear scene solves the harmonics its loads
/// contain; with nonlinear joints or plastic bodies M grows 4, 8, 16, ... up
/// to `m_max` until `measure` (e.g. the cut profiles), the mean displacement
/// of each face loaded by a force and the reaction on each face a motion
/// moves all change by less than `tolerance` relative to their largest
/// value. Factors of lower harmonics are kept.
pub fn solve_scene_auto(
    scene: &Scene,
    keep_msh: Option<&Path>,
    tolerance: f64,
    m_max: u32,
    measure: impl Fn(&Model, &Outcome) -> Vec<f64>,
    mut progress: impl FnMut(&IterationRecord),
) -> Result<(Scene, Run), Box<Stopped>> {
    let seismic = scene.seismic_coefficient != 0.0 && scene.materials.values().any(|m| m.unit_weight > 0.0);
    let loaded = scene
        .loads
        .iter()
        .map(|l| l.max_harmonic())
        .max()
        .unwrap_or(0)
        .max(u32::from(seismic));
    let mut sc = scene.clone();
    if !scene.is_nonlinear() {
        sc.harmonics = loaded.into();
        let mut run = solve_scene(&sc, keep_msh, progress)?;
        run.auto_steps = vec![AutoStep {
            m: loaded,
            iterations: 0,
            change: None,
        }];
        return Ok((sc, run));
    }
    let mut m = loaded.max(4).min(m_max.max(loaded));
    sc.harmonics = m.into();
    let Elastic { mut problem, load } = elastic(&sc, keep_msh, true)?;
    let (mut loads, mut u, mut timings) = (load.loads, load.u, load.timings);
    let mut steps: Vec<AutoStep> = Vec::new();
    let mut previous: Option<Vec<Vec<f64>>> = None;
    let t = Instant::now();
    let initial = if sc.has_initial_phase() {
        Some(initial_phase(&sc, &problem, &loads, &mut progress)?)
    } else {
        None
    };
    loop {
        let sections = scene_sections(&sc, &problem.model, &loads)?;
        let start = Start {
            problem: &problem,
            loads: &loads,
            elastic: &u,
            initial: initial.as_ref(),
        };
        let (outcome, load_path) =
            iterate(&sc, start, m, Default::default(), &sections, None, &mut progress)?;
        // The measure, the force-loaded faces' mean displacements and the
        // moved faces' reaction forces and moments, each against its own
        // largest value.
        let reactions_now = motion_reactions(&sc, &problem.model, &loads, &outcome);
        let values: Vec<Vec<f64>> = vec![
            measure(&problem.model, &outcome),
            face_means(&sc, &problem.model, &loads, &outcome).concat(),
            reactions_now.iter().flat_map(|r| r[..3].to_vec()).collect(),
            reactions_now.iter().flat_map(|r| r[3..].to_vec()).collect(),
        ];
        let change = previous.as_ref().map(|p| {
            values
                .iter()
                .zip(p)
                .map(|(now, before)| {
                    let scale = now.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                    let diff = now
                        .iter()
                        .zip(before)
                        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
                    if scale > 0.0 {
                        diff / scale
                    } else {
                        0.0
                    }
                })
                .fold(0.0f64, f64::max)
        });
        steps.push(AutoStep {
            m,
            iterations: outcome.history.len(),
            change,
        });
        // Short of the whole load, more harmonics are not tried.
        let short = load_path.as_ref().is_some_and(|p| p.limit.is_some());
        let done = short || change.is_some_and(|c| c < tolerance) || 2 * m > m_max;
        if done {
            timings.solve += t.elapsed().as_secs_f64();
            let lambda = load_path.as_ref().map_or(1.0, LoadPath::reached);
            let reactions = reactions(
                &sc,
                &problem.model,
                &with_released(scaled(&loads, lambda).into_owned(), &outcome.released),
                &outcome.displacements,
            );
            let mut run = Run::new(
                Arc::new(problem),
                super::elastic::ElasticLoad { loads, u, timings },
            );
            run.displacements = outcome.displacements.clone();
            run.reactions = reactions;
            run.outcome = Some(outcome);
            run.auto_steps = steps;
            run.load_path = load_path;
            run.initial = initial;
            return Ok((sc, run));
        }
        previous = Some(values);
        // Grow M: reassemble the loads, factorize only the new harmonics and
        // solve their loads (beyond the factor memory, the factors from
        // `whole_below` on keep only their joint blocks).
        let next = 2 * m;
        sc.harmonics = next.into();
        let new: Vec<u32> = (m + 1..=next).collect();
        loads = super::motion::loads_on(&sc, &problem.model, next)?;
        super::factors::check_cost(&sc, &problem.model, next as usize + 1)?;
        let t1 = Instant::now();
        let whole_below = plan_factors(&problem.model, next as usize + 1)?;
        let model = &problem.model;
        problem.factors = std::mem::take(&mut problem.factors)
            .into_iter()
            .map(|f| {
                if f.m < whole_below {
                    f
                } else {
                    model.joint_block(f)
                }
            })
            .collect();
        for (f, d) in factorize_and_solve(&problem.model, &new, &loads, whole_below)? {
            problem.factors.push(f);
            u.harmonics.retain(|h| h.m != d.m);
            u.harmonics.push(d);
        }
        timings.factorize += t1.elapsed().as_secs_f64();
        m = next;
    }
}
