//! A run whose joints can open or slip: the iteration from the elastic
//! solution (one-shot or along the load path), its M/2 check, and the
//! reactions at the solution.

use super::check::{faces_measure, halved, HalfRun};
use super::elastic::{ElasticLoad, Problem};
use super::initial::InitialState;
use super::measures::{
    face_motion, joint_areas, member_bodies, moved_reactions, padded, reactions, scaled, with_released,
};
use super::model::{iteration_settings, joint_laws};
use super::sections::scene_sections;
use super::stages::{motion_direction, reaction_along};
use super::start::{Asked, Start};
use super::{Run, Stopped};
use crate::error::SolverError;
use crate::fourier::Sections;
use crate::iteration::{IterationRecord, JointField, Outcome, StepBodies};
use crate::linear::HarmonicFactor;
use crate::loads::HarmonicLoads;
use crate::results::{JointFieldFile, LoadPath, StepMeasure};
use crate::scene::{Load, Scene};
use crate::solution::Displacements;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// The nonlinear solution with harmonics 0..=m on `sections`: one-shot or
/// along the load path of `solver.loading` (the iteration chooses), with
/// what `asked` asks.
pub(super) fn iterate(
    scene: &Scene,
    start: Start<'_>,
    m: u32,
    asked: Asked<'_>,
    sections: &Sections,
    ends: Option<&mut Vec<super::StageSnapshot>>,
    progress: impl FnMut(&IterationRecord),
) -> Result<(Outcome, Option<LoadPath>), SolverError> {
    if !scene.stages.is_empty() {
        return super::stages::iterate_stages(scene, start, m, asked, sections, ends, progress);
    }
    let Start {
        problem,
        loads: all,
        elastic,
        initial,
    } = start;
    let joint_start = initial.map(|i| i.joint_start(sections.len()));
    let loads: Vec<HarmonicLoads> = all.iter().filter(|h| h.m <= m).cloned().collect();
    let model = &problem.model;
    let laws = joint_laws(scene, model);
    let settings = iteration_settings(scene);
    let iteration = crate::iteration::Problem {
        model,
        factors: &problem.factors,
        loads: &loads,
        laws: &laws,
        sections,
        elastic: Some(elastic),
        whole_up_to: asked.whole_up_to,
        from: None,
        cancel: asked.cancel,
    };
    let mesh = &model.mesh;
    let springs: Vec<_> = model.joints.iter().map(|j| j.springs).collect();
    let member_bodies = member_bodies(scene, mesh);
    let observe = |lambda: f64, u: &Displacements, field: &JointField, bodies: &StepBodies| {
        let d = padded(u, all);
        let file = JointFieldFile::new(mesh, &springs, field);
        // A moved face takes its reaction along its motion.
        let held = moved_reactions(
            scene,
            model,
            &scene.loads,
            scaled(all, lambda).into_owned(),
            &bodies.released,
            &d,
        );
        StepMeasure {
            faces: scene
                .loads
                .iter()
                .filter_map(|l| {
                    face_motion(mesh, l, &d).map(|mut f| {
                        if let Load::Motion(mo) = l {
                            f.applied = held
                                .iter()
                                .find(|r| r.on == f.on)
                                .map(|r| reaction_along(&motion_direction(mo), r));
                        }
                        f
                    })
                })
                .collect(),
            joints: joint_areas(mesh, &file),
            members: member_bodies
                .iter()
                .map(|&b| crate::members::member_forces(scene, model, all, lambda, &d, Some(field), b))
                .collect(),
            stage: None,
            dissipated: None,
            plastic_volume: bodies.plastic_volume,
        }
    };
    let loading = scene.solver.loading.into();
    let solved = crate::iteration::solve(
        &iteration,
        &settings,
        joint_start.as_ref(),
        loading,
        observe,
        progress,
    )?;
    let path = solved.stepped.map(|s| LoadPath {
        steps: s.steps,
        limit: s.limit,
        stopped_in: None,
    });
    Ok((solved.outcome, path))
}

/// The rest of a run from its elastic solution and initial state: the
/// iteration if a joint can open or slip, the M/2 check, the reactions.
/// `t`: when the run's solve began. A one-shot iteration that stops comes
/// back with its last iterate.
pub(super) fn finish(
    scene: &Scene,
    problem: Arc<Problem>,
    load: ElasticLoad,
    initial: Option<InitialState>,
    t: Instant,
    mut progress: impl FnMut(&IterationRecord),
) -> Result<Run, Box<Stopped>> {
    // The run's displacements are the elastic ones until the solution.
    let mut run = Run::new(problem, load);
    run.initial = initial;
    if !scene.is_nonlinear() || (run.problem.model.mesh.joints.is_empty() && !scene.has_plastic_bodies()) {
        run.reactions = reactions(scene, &run.problem.model, &run.loads, &run.displacements);
        run.timings.solve += t.elapsed().as_secs_f64();
        return Ok(run);
    }
    let sections = scene_sections(scene, &run.problem.model, &run.loads)?;
    let m = scene.harmonics();
    let start = Start {
        problem: &run.problem,
        loads: &run.loads,
        elastic: &run.displacements,
        initial: run.initial.as_ref(),
    };
    let mut ends = Vec::new();
    let keep = scene.outputs.stages == crate::scene::StageOutputs::Each;
    let half_run = |whole_up_to: Option<u32>, cancel: Option<&AtomicBool>| {
        let asked = Asked { whole_up_to, cancel };
        iterate(scene, start, m / 2, asked, &sections, None, |_| {})
    };
    // The M/2 check's run beside the run it checks, on a thread of its own
    // (the iteration's serial parts keep about one core busy), asking for
    // the whole displacements of harmonics 0 and 1 as it will in most runs;
    // stopped when the run it checks ends short of the whole load. Not
    // where factors are reduced: each run would read or make their rest.
    // Not with plastic bodies: each run refactorizes every harmonic's
    // tangent at every Newton step on all cores, and two at once took
    // 1.28x the wall time and 1.48x the peak memory of one after the other
    // (docs/tutorial/pile_clay.json at M = 8, docs/performance.md).
    let beside =
        m >= 2 && run.problem.factors.iter().all(HarmonicFactor::is_full) && !scene.has_plastic_bodies();
    let cancel = AtomicBool::new(false);
    let (solved, early) = std::thread::scope(|s| {
        let early = if beside {
            std::thread::Builder::new()
                .name("axijoint-half".into())
                .spawn_scoped(s, || half_run(Some(1), Some(&cancel)))
                .ok()
        } else {
            None
        };
        let solved = iterate(
            scene,
            start,
            m,
            Asked::default(),
            &sections,
            keep.then_some(&mut ends),
            &mut progress,
        );
        if !matches!(&solved, Ok((_, path)) if path.as_ref().is_none_or(|p| p.limit.is_none())) {
            cancel.store(true, Ordering::Relaxed);
        }
        let early = early.map(|h| h.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)));
        (solved, early)
    });
    let (outcome, load_path) = match solved {
        Ok(v) => v,
        Err(SolverError::Iteration(e)) => {
            let last = e.last().cloned().map(|last| {
                run.displacements = padded(&last.displacements, &run.loads);
                run.outcome = Some(last);
                Box::new(run)
            });
            return Err(Box::new(Stopped {
                error: SolverError::Iteration(e),
                last,
            }));
        }
        Err(e) => return Err(e.into()),
    };
    let complete = load_path.as_ref().is_none_or(|p| p.limit.is_none());
    let half = if m >= 2 && complete {
        // Where the loaded faces' mean motion measures the check, the half
        // run needs no whole displacements beyond harmonic 1; else it runs
        // again for all of them.
        let whole_up_to = faces_measure(scene, &run.problem.model, &run.loads, &outcome).then_some(1);
        HalfRun::Solved(Box::new(match early {
            Some(half) if whole_up_to.is_some() => half,
            _ => half_run(whole_up_to, None),
        }))
    } else {
        HalfRun::NotRun
    };
    run.harmonic_check = halved(scene, &run.problem.model, &run.loads, (&outcome, m), half);
    if let Some((mark, limit)) = load_path
        .as_ref()
        .and_then(|p| p.stopped_in.as_ref().zip(p.limit.as_ref()))
    {
        // Stopped within a stage: the loads applied there.
        let m_all = run.loads.iter().map(|h| h.m).max().unwrap_or(0);
        match super::stages::applied(scene, &run.problem.model, mark.leg, limit.factor, m_all) {
            Ok(loads) => {
                run.applied = crate::loads::load_resultants(&loads, &run.problem.model.mesh, 0.0);
                run.loads = loads;
            }
            Err(error) => return Err(Box::new(Stopped { error, last: None })),
        }
    }
    run.displacements = outcome.displacements.clone();
    run.timings.solve += t.elapsed().as_secs_f64();
    let lambda = load_path.as_ref().map_or(1.0, LoadPath::reached);
    run.reactions = reactions(
        scene,
        &run.problem.model,
        &with_released(scaled(&run.loads, lambda).into_owned(), &outcome.released),
        &run.displacements,
    );
    run.outcome = Some(outcome);
    run.load_path = load_path;
    run.stage_ends = ends;
    Ok(run)
}
