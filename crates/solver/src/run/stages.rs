//! A run in stages (`stages`): each leg ([`Scene::legs`]) raises the load
//! from the totals the one before reached to its own, `F = F_start + lambda
//! (F_end - F_start)`, stepped with the history law from the converged state
//! there (released forces and committed joint history carried over); the
//! run stops in the first leg that cannot reach its load, at its limit
//! load factor.

use super::factors::solve_loads;
use super::measures::{face_motion, joint_areas, member_bodies, padded};
use super::model::{iteration_settings, joint_laws};
use super::start::Start;
use crate::elements::JointSprings;
use crate::error::SolverError;
use crate::fourier::Sections;
use crate::iteration::{IterationRecord, JointField, Outcome, StageEnd, StageStart, StepBodies};
use crate::linear::Model;
use crate::loads::{assemble_loads, load_resultants, HarmonicLoads, Resultants};
use crate::results::{JointFieldFile, LoadPath, StageMark, StepMeasure};
use crate::scene::{Leg, Load, Scene};
use crate::solution::Displacements;

/// `a x + b y`, harmonic by harmonic (same harmonics).
fn combine_loads(a: f64, x: &[HarmonicLoads], b: f64, y: &[HarmonicLoads]) -> Vec<HarmonicLoads> {
    x.iter()
        .zip(y)
        .map(|(p, q)| {
            let mut out = p.scaled(a);
            out.add(b, q);
            out
        })
        .collect()
}

/// The loads at the end of `leg`, harmonics 0..=`m_max`.
fn leg_loads(scene: &Scene, model: &Model, leg: &Leg, m_max: u32) -> Result<Vec<HarmonicLoads>, SolverError> {
    super::motion::loads_on(&scene.stage_scene(leg.loads.clone()), model, m_max).map_err(|e| match e {
        SolverError::Scene(e) => SolverError::Scene(e.in_stage(leg.stage, "loads")),
        e => e,
    })
}

/// The resultant of `loads` (force, moment about the origin).
fn resultant(scene: &Scene, model: &Model, loads: Vec<Load>, m_max: u32) -> Result<Resultants, SolverError> {
    let h = assemble_loads(&scene.stage_scene(loads), &model.mesh, m_max).map_err(SolverError::Scene)?;
    Ok(load_resultants(&h, &model.mesh, 0.0))
}

/// The load of `face` along the direction of `first` (its first load):
/// the force along the first's force, or without one the moment along the
/// first's moment (a torque, or the turn of a tilting `motion`).
fn along(first: &Resultants, r: &Resultants) -> f64 {
    let dot = |a: &[f64; 3], b: &[f64; 3]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let norm = dot(&first.force, &first.force).sqrt();
    if norm > 0.0 {
        dot(&first.force, &r.force) / norm
    } else {
        let norm = dot(&first.moment, &first.moment).sqrt();
        if norm > 0.0 {
            dot(&first.moment, &r.moment) / norm
        } else {
            0.0
        }
    }
}

/// The direction of a moved face: its translation, else its turn.
pub(super) fn motion_direction(mo: &crate::scene::MotionLoad) -> Resultants {
    Resultants {
        force: mo.displacement,
        moment: mo.rotation,
    }
}

/// The reaction `r` along the direction `first` ([`along`]).
pub(super) fn reaction_along(first: &Resultants, r: &crate::solution::SupportReaction) -> f64 {
    along(
        first,
        &Resultants {
            force: r.force,
            moment: r.moment,
        },
    )
}

/// The work of the joints' slip from field `a` to field `b` (same pairs):
/// `sum da (p_b . ds)` over the shear components, `ds = dd - dp / k` the
/// plastic slip, at the traction the law returned to (as its return
/// mapping: a point slips at its strength; the normal component does no
/// plastic work).
fn slip_work(a: &JointField, b: &JointField, springs: &[JointSprings]) -> f64 {
    let n_p = b.points.len();
    let mut work = 0.0;
    for (s, w) in b.sections.weight.iter().enumerate() {
        for (i, pt) in b.points.iter().enumerate() {
            let k = s * n_p + i;
            let sp = springs[pt.joint];
            let (d0, d1, p0, p1) = (a.d[k], b.d[k], a.p[k], b.p[k]);
            let mut dw = 0.0;
            for (c, kc) in [(0, sp.k_xi), (2, sp.k_theta)] {
                if kc > 0.0 {
                    let ds = (d1[c] - d0[c]) - (p1[c] - p0[c]) / kc;
                    dw += p1[c] * ds;
                }
            }
            work += w * pt.point.area() * dw;
        }
    }
    work
}

/// The loads applied at factor `lambda` of leg `k` (harmonics
/// 0..=`m_max`): where a staged run stopped.
pub(super) fn applied(
    scene: &Scene,
    model: &Model,
    k: usize,
    lambda: f64,
    m_max: u32,
) -> Result<Vec<HarmonicLoads>, SolverError> {
    let legs = scene.legs();
    let end = leg_loads(scene, model, &legs[k], m_max)?;
    let start = match k {
        0 => end
            .iter()
            .map(|h| HarmonicLoads::zeros(h.m, model.mesh.nodes.len()))
            .collect(),
        _ => leg_loads(scene, model, &legs[k - 1], m_max)?,
    };
    Ok(combine_loads(1.0 - lambda, &start, lambda, &end))
}

/// The staged solution with harmonics 0..=m on `sections`, with what
/// `asked` asks (the whole displacements, a flag that stops it).
pub(super) fn iterate_stages(
    scene: &Scene,
    start: Start<'_>,
    m: u32,
    asked: super::start::Asked<'_>,
    sections: &Sections,
    mut ends: Option<&mut Vec<super::StageSnapshot>>,
    mut progress: impl FnMut(&IterationRecord),
) -> Result<(Outcome, Option<LoadPath>), SolverError> {
    let Start {
        problem,
        loads: all,
        initial,
        ..
    } = start;
    let model = &problem.model;
    let mesh = &model.mesh;
    let n = mesh.nodes.len();
    let m_all = all.iter().map(|h| h.m).max().unwrap_or(0);
    let legs = scene.legs();
    let joint_start = initial.map(|i| i.joint_start(sections.len()));
    let laws = joint_laws(scene, model);
    let settings = iteration_settings(scene);
    let springs: Vec<_> = model.joints.iter().map(|j| j.springs).collect();
    let member_bodies = member_bodies(scene, mesh);
    let faces = scene.staged_faces();
    let zeros: Vec<HarmonicLoads> = all.iter().map(|h| HarmonicLoads::zeros(h.m, n)).collect();
    // The direction of each face: its load's resultant, or a moved face's
    // translation (else its turn about the axis).
    let firsts: Vec<Resultants> = faces
        .iter()
        .map(|l| match l {
            Load::Motion(mo) => Ok(motion_direction(mo)),
            _ => resultant(scene, model, vec![l.clone()], m_all),
        })
        .collect::<Result<_, _>>()?;
    let on_face = |leg: Option<&Leg>, face: &str| -> Vec<Load> {
        leg.map_or_else(Vec::new, |leg| {
            leg.loads.iter().filter(|l| l.on() == face).cloned().collect()
        })
    };
    let mut prev: Option<(Vec<HarmonicLoads>, Displacements, StageEnd)> = None;
    let mut last_field: Option<JointField> = None;
    let mut steps = Vec::new();
    for (k, leg) in legs.iter().enumerate() {
        let mark = StageMark {
            leg: k,
            stage: leg.name.clone(),
            cycle: leg.cycle,
            level: leg.level,
        };
        let total = leg_loads(scene, model, leg, m_all)?;
        let u_total = solve_loads(model, &problem.factors, &total);
        let (base, u_base) = match &prev {
            Some((b, ub, _)) => (b.clone(), ub.clone()),
            None => (zeros.clone(), u_total.minus(&u_total)),
        };
        let step_all = combine_loads(1.0, &total, -1.0, &base);
        let u_step = u_total.minus(&u_base);
        // Each face's load along its direction, at the leg's start and end.
        let face_loads: Vec<(f64, f64)> = faces
            .iter()
            .zip(&firsts)
            .map(|(l, first)| {
                let r0 = resultant(
                    scene,
                    model,
                    on_face(k.checked_sub(1).map(|j| &legs[j]), l.on()),
                    m_all,
                )?;
                let r1 = resultant(scene, model, on_face(Some(leg), l.on()), m_all)?;
                Ok((along(first, &r0), along(first, &r1)))
            })
            .collect::<Result<_, SolverError>>()?;
        let within =
            |v: &[HarmonicLoads]| -> Vec<HarmonicLoads> { v.iter().filter(|h| h.m <= m).cloned().collect() };
        let step = within(&step_all);
        let iteration = crate::iteration::Problem {
            model,
            factors: &problem.factors,
            loads: &step,
            laws: &laws,
            sections,
            elastic: Some(&u_step),
            whole_up_to: asked.whole_up_to,
            cancel: asked.cancel,
            from: prev.as_ref().map(|(b, ub, end)| StageStart {
                loads: b,
                elastic: ub,
                end,
            }),
        };
        let observe = |lambda: f64, u: &Displacements, field: &JointField, bodies: &StepBodies| {
            let d = padded(u, all);
            let file = JointFieldFile::new(mesh, &springs, field);
            let at = combine_loads(1.0, &base, lambda, &step_all);
            // From the unloaded state (the initial traction, no motion)
            // before the first step.
            let start = || JointField {
                d: vec![[0.0; 3]; field.d.len()],
                p: joint_start
                    .as_ref()
                    .filter(|s| s.traction.len() == field.p.len())
                    .map_or_else(|| vec![[0.0; 3]; field.p.len()], |s| s.traction.clone()),
                ..field.clone()
            };
            let dissipated = slip_work(last_field.get_or_insert_with(start), field, &springs);
            // A moved face takes its reaction.
            let held =
                super::measures::moved_reactions(scene, model, &faces, at.clone(), &bodies.released, &d);
            last_field = Some(field.clone());
            StepMeasure {
                faces: faces
                    .iter()
                    .zip(&face_loads)
                    .zip(&firsts)
                    .filter_map(|((l, (a0, a1)), first)| {
                        face_motion(mesh, l, &d).map(|mut f| {
                            f.applied = Some(match held.iter().find(|r| r.on == f.on) {
                                Some(r) if matches!(l, Load::Motion(_)) => reaction_along(first, r),
                                _ => a0 + lambda * (a1 - a0),
                            });
                            f
                        })
                    })
                    .collect(),
                joints: joint_areas(mesh, &file),
                members: member_bodies
                    .iter()
                    .map(|&b| crate::members::member_forces(scene, model, &at, 1.0, &d, Some(field), b))
                    .collect(),
                stage: Some(mark.clone()),
                dissipated: Some(dissipated),
                plastic_volume: bodies.plastic_volume,
            }
        };
        let solved = crate::iteration::solve(
            &iteration,
            &settings,
            joint_start.as_ref(),
            leg.loading.into(),
            observe,
            &mut progress,
        )?;
        let stepped = solved.stepped.ok_or_else(|| {
            SolverError::Solve(crate::linear::SolveError::Input(format!(
                "{}: stages are stepped",
                leg.label()
            )))
        })?;
        steps.extend(stepped.steps);
        let last = k + 1 == legs.len();
        if stepped.limit.is_some() || last {
            let stopped = stepped.limit.is_some().then_some(mark);
            let path = LoadPath {
                steps,
                limit: stepped.limit,
                stopped_in: stopped,
            };
            return Ok((solved.outcome, Some(path)));
        }
        if let Some(ends) = ends.as_deref_mut() {
            ends.push(super::StageSnapshot {
                mark: mark.clone(),
                loads: total.clone(),
                outcome: solved.outcome.clone(),
            });
        }
        let end = solved.end.ok_or_else(|| {
            SolverError::Solve(crate::linear::SolveError::Input(format!(
                "{}: no state to go on from",
                leg.label()
            )))
        })?;
        prev = Some((total, u_total, end));
    }
    Err(SolverError::Solve(crate::linear::SolveError::Input(format!(
        "{}: `stages` gives no load",
        scene.path.display()
    ))))
}
