//! The M/2 check: the key results of a nonlinear run against the same run
//! with harmonics 0..=M/2, the user's check that M is enough.

use super::measures::{face_displacement, max_displacement, moved_reactions, padded};
use crate::error::SolverError;
use crate::iteration::Outcome;
use crate::linear::Model;
use crate::loads::HarmonicLoads;
use crate::results::{HarmonicCheck, JointFieldFile, LoadPath};
use crate::scene::{Load, Scene};

/// Compares the key results of two solutions of the same model (`loads`:
/// the run's, every harmonic).
pub(super) fn harmonic_check(
    scene: &Scene,
    model: &Model,
    loads: &[HarmonicLoads],
    full: (&Outcome, u32),
    half: (&Outcome, u32),
) -> HarmonicCheck {
    let mesh = &model.mesh;
    let (a, b) = (
        face_means(scene, model, loads, full.0),
        face_means(scene, model, loads, half.0),
    );
    let scale = a.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a
        .iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    let springs: Vec<_> = model.joints.iter().map(|j| j.springs).collect();
    let areas = |o: &Outcome| -> Vec<(f64, f64, f64)> {
        let file = JointFieldFile::new(mesh, &springs, &o.field);
        mesh.joints.iter().map(|j| file.state_areas(&j.name)).collect()
    };
    let (fa, ha) = (areas(full.0), areas(half.0));
    let total: f64 = fa.iter().map(|a| a.0 + a.1 + a.2).sum();
    let (open, slip) = fa.iter().zip(&ha).fold((0.0, 0.0), |acc, (x, y)| {
        (acc.0 + (x.0 - y.0).abs(), acc.1 + (x.1 - y.1).abs())
    });
    // Loads of harmonics >= 2 move a face without moving its mean: then
    // the change of the whole field (every node, 16 angles) instead.
    let (uf, uh) = (
        padded(&full.0.displacements, loads),
        padded(&half.0.displacements, loads),
    );
    let n = mesh.nodes.len();
    let u_max = max_displacement(n, &uf);
    let motion_change = reaction_change(
        &motion_reactions(scene, model, loads, full.0),
        &motion_reactions(scene, model, loads, half.0),
    );
    let (face_change, note) = if let Some(change) = motion_change {
        // A motion's face moves as prescribed: its reaction measures.
        let faces = if measured_by_faces(scale, u_max) {
            diff / scale
        } else {
            0.0
        };
        (change.max(faces), None)
    } else if measured_by_faces(scale, u_max) {
        (diff / scale, None)
    } else {
        let delta = uf.minus(&uh);
        let change = if u_max > 0.0 {
            max_displacement(n, &delta) / u_max
        } else {
            0.0
        };
        (
            change,
            Some("the loaded faces' mean displacement is about zero (loads of harmonics >= 2): face_change is the largest change of the displacement field over its largest value".to_string()),
        )
    };
    HarmonicCheck {
        m: full.1,
        m_half: half.1,
        face_change: Some(face_change),
        area_change: Some(if total > 0.0 { open.max(slip) / total } else { 0.0 }),
        note,
    }
}

/// The mean displacement of each face loaded by a force (harmonics 0 and
/// 1 of `o`; a motion's face moves as prescribed).
pub(super) fn face_means(
    scene: &Scene,
    model: &Model,
    loads: &[HarmonicLoads],
    o: &Outcome,
) -> Vec<[f64; 3]> {
    let d = padded(&o.displacements, loads);
    scene
        .loads
        .iter()
        .filter(|l| !matches!(l, Load::Motion(_)))
        .filter_map(|l| face_displacement(&model.mesh, l.on(), &d))
        .collect()
}

/// The reaction `(F, M)` on each face a motion moves, from harmonics 0
/// and 1 of `o` (the others have no resultant).
pub(super) fn motion_reactions(
    scene: &Scene,
    model: &Model,
    loads: &[HarmonicLoads],
    o: &Outcome,
) -> Vec<[f64; 6]> {
    let moved: Vec<&str> = scene
        .loads
        .iter()
        .filter(|l| matches!(l, Load::Motion(_)))
        .map(Load::on)
        .collect();
    let low: Vec<HarmonicLoads> = loads.iter().filter(|h| h.m <= 1).cloned().collect();
    let d = padded(&o.displacements, &low);
    moved_reactions(scene, model, &scene.loads, low, &o.released, &d)
        .into_iter()
        .filter(|r| moved.contains(&r.on.as_str()))
        .map(|r| [r.force, r.moment].concat().try_into().expect("six values"))
        .collect()
}

/// The largest change from `a` to `b` of the reaction forces over the
/// largest force, and of the moments over the largest moment; `None`
/// without motions.
fn reaction_change(a: &[[f64; 6]], b: &[[f64; 6]]) -> Option<f64> {
    if a.is_empty() {
        return None;
    }
    let part = |range: std::ops::Range<usize>| {
        let scale = a
            .iter()
            .flat_map(|r| &r[range.clone()])
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = a
            .iter()
            .zip(b)
            .flat_map(|(x, y)| range.clone().map(move |k| (x[k] - y[k]).abs()))
            .fold(0.0f64, f64::max);
        if scale > 0.0 {
            diff / scale
        } else {
            0.0
        }
    };
    Some(part(0..3).max(part(3..6)))
}

/// Whether faces moving `scale` in a field whose largest displacement is
/// `u_max` measure the check (else loads of harmonics >= 2 move the faces
/// without moving their mean, and the whole field is compared).
fn measured_by_faces(scale: f64, u_max: f64) -> bool {
    scale > 1e-3 * u_max
}

/// Whether the loaded faces' mean motion measures the M/2 check of the run
/// with outcome `full`: then the run with harmonics 0..=M/2 needs whole
/// displacements of harmonics 0 and 1 only.
pub(super) fn faces_measure(scene: &Scene, model: &Model, loads: &[HarmonicLoads], full: &Outcome) -> bool {
    let scale = face_means(scene, model, loads, full)
        .iter()
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let u = padded(&full.displacements, loads);
    measured_by_faces(scale, max_displacement(model.mesh.nodes.len(), &u))
}

/// The run with harmonics 0..=M/2 of a check.
pub(super) enum HalfRun {
    /// Not run: the whole load was not reached.
    NotRun,
    /// Its outcome and load path, or why it stopped.
    Solved(Box<Result<(Outcome, Option<LoadPath>), SolverError>>),
}

/// The M/2 check of a run with harmonics 0..=M (`full`; none when M < 2).
pub(super) fn halved(
    scene: &Scene,
    model: &Model,
    loads: &[HarmonicLoads],
    full: (&Outcome, u32),
    half: HalfRun,
) -> Option<HarmonicCheck> {
    let m = full.1;
    if m < 2 {
        return None;
    }
    let no_comparison = |note: String| HarmonicCheck {
        m,
        m_half: m / 2,
        face_change: None,
        area_change: None,
        note: Some(note),
    };
    let half = match half {
        HalfRun::NotRun => {
            return Some(no_comparison(
                "the whole load was not reached: no comparison".into(),
            ))
        }
        HalfRun::Solved(half) => *half,
    };
    Some(match half {
        Ok((_, Some(path))) if path.limit.is_some() => no_comparison(format!(
            "the run with harmonics 0..={} reached only the load factor {:.4}",
            m / 2,
            path.reached()
        )),
        Ok((half, _)) => harmonic_check(scene, model, loads, full, (&half, m / 2)),
        Err(e) => no_comparison(format!("the run with harmonics 0..={} failed: {e}", m / 2)),
    })
}
