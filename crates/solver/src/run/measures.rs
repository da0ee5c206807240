//! What a run measures on a solution: support reactions, the motion of
//! loaded faces, the largest displacement, joint relative displacements and
//! the field of linear joints.

use super::model::support_nodes;
use crate::dofs::Component;
use crate::iteration::{JointField, PointInfo};
use crate::linear::Model;
use crate::loads::{load_resultants, HarmonicLoads};
use crate::results::FaceMotion;
use crate::scene::Scene;
use crate::solution::{Displacements, HarmonicDisplacement, SupportReaction};
use axijoint_mesh::Mesh;
use rayon::prelude::*;

/// Reactions `K u - f` at the supported DOFs, per support (a DOF fixed by
/// several supports counts for the first), as Cartesian resultants.
pub fn reactions(
    scene: &Scene,
    model: &Model,
    loads: &[HarmonicLoads],
    u: &Displacements,
) -> Vec<SupportReaction> {
    let mesh = &model.mesh;
    let n = mesh.nodes.len();
    // Residual per harmonic and family, supported DOFs only.
    let residuals: Vec<HarmonicLoads> = loads
        .par_iter()
        .zip(&u.harmonics)
        .map(|(h, d)| {
            let mut out = HarmonicLoads::zeros(h.m, n);
            for (f, ud, o) in [
                (&h.symmetric, &d.symmetric, &mut out.symmetric),
                (&h.antisymmetric, &d.antisymmetric, &mut out.antisymmetric),
            ] {
                if ud.iter().all(|&v| v == 0.0) {
                    continue;
                }
                let ku = model.support_forces(h.m, ud);
                for dof in 0..3 * n {
                    if model.dofs.is_supported(dof) {
                        o[dof] = ku[dof] - f[dof];
                    }
                }
            }
            out
        })
        .collect();
    let mut claimed = vec![false; 3 * n];
    scene
        .all_supports()
        .iter()
        .map(|s| {
            let comps = s.fix.components();
            let mut mine = vec![false; 3 * n];
            for node in support_nodes(mesh, &s.on) {
                for c in Component::ALL {
                    let dof = 3 * node + c.index();
                    if comps[c.index()] && !claimed[dof] {
                        claimed[dof] = true;
                        mine[dof] = true;
                    }
                }
            }
            let per: Vec<HarmonicLoads> = residuals
                .iter()
                .map(|r| {
                    let mut h = HarmonicLoads::zeros(r.m, n);
                    for (dof, _) in mine.iter().enumerate().filter(|(_, &m)| m) {
                        h.symmetric[dof] = r.symmetric[dof];
                        h.antisymmetric[dof] = r.antisymmetric[dof];
                    }
                    h
                })
                .collect();
            let total = load_resultants(&per, mesh, 0.0);
            let per_harmonic = per
                .iter()
                .map(|h| {
                    let r = load_resultants(std::slice::from_ref(h), mesh, 0.0);
                    let (f, m) = (r.force, r.moment);
                    [f64::from(h.m), f[0], f[1], f[2], m[0], m[1], m[2]]
                })
                .collect();
            SupportReaction {
                on: s.on.clone(),
                force: total.force,
                moment: total.moment,
                per_harmonic,
            }
        })
        .collect()
}

/// Face-average Cartesian displacement `(ux, uy, uz)` of a physical curve
/// swept around the axis: `(1/A) Integral(u dA)`, A = 2 pi Integral(r ds).
/// Only harmonics 0 (uz) and 1 (ux from the symmetric, uy from the
/// antisymmetric family) have a non-zero average.
pub fn face_displacement(mesh: &Mesh, curve: &str, u: &Displacements) -> Option<[f64; 3]> {
    let edges = &mesh.curve(curve)?.edges;
    // w_i = 2 pi Integral(N_i r ds): the m = 0 load of a unit t_z.
    let mut w = vec![0.0; mesh.nodes.len()];
    let mut fe = Vec::new();
    let mut coords = Vec::new();
    for e in edges {
        coords.clear();
        coords.extend(e.nodes.iter().map(|&n| mesh.nodes[n]));
        fe.clear();
        fe.resize(3 * e.nodes.len(), 0.0);
        crate::elements::edge_load(e.kind, &coords, 0, &|_, _| [0.0, 1.0, 0.0], &mut fe);
        for (i, &n) in e.nodes.iter().enumerate() {
            w[n] += fe[3 * i + 1];
        }
    }
    let area: f64 = w.iter().sum();
    if area <= 0.0 {
        return None;
    }
    let mut out = [0.0; 3];
    for h in &u.harmonics {
        for (n, &wn) in w.iter().enumerate().filter(|(_, &wn)| wn != 0.0) {
            let (s, a) = (&h.symmetric[3 * n..3 * n + 3], &h.antisymmetric[3 * n..3 * n + 3]);
            match h.m {
                0 => out[2] += wn * s[1],
                1 => {
                    out[0] += wn * (s[0] - s[2]) / 2.0;
                    out[1] += wn * (a[0] - a[2]) / 2.0;
                }
                _ => {}
            }
        }
    }
    Some(out.map(|v| v / area))
}

/// Largest displacement magnitude over the nodes at 16 sections of the turn.
pub fn max_displacement(n_nodes: usize, u: &Displacements) -> f64 {
    let m_max = u.harmonics.iter().map(|h| h.m as usize).max().unwrap_or(0);
    let mut max: f64 = 0.0;
    for k in 0..16 {
        let theta = std::f64::consts::PI * f64::from(k) / 8.0;
        let trig: Vec<(f64, f64)> = (0..=m_max).map(|m| (m as f64 * theta).sin_cos()).collect();
        for n in 0..n_nodes {
            let d = u.at_trig(n, &trig);
            max = max.max((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
        }
    }
    max
}

/// The relative displacement `(d_xi, d_eta, d_theta)` of `u` at every joint
/// point and section: index `s * points.len() + p`.
pub fn joint_relative_displacements(
    points: &[PointInfo],
    u: &Displacements,
    sections: &crate::fourier::Sections,
) -> Vec<[f64; 3]> {
    use crate::fourier::Family;
    let zero = [0.0; 3];
    let mut out = Vec::with_capacity(sections.len() * points.len());
    let mut ue = [0.0; 18];
    for &theta in &sections.theta {
        let phi: Vec<_> = u
            .harmonics
            .iter()
            .map(|h| {
                (
                    sections.phi(h.m, Family::Symmetric, theta),
                    sections.phi(h.m, Family::Antisymmetric, theta),
                )
            })
            .collect();
        for p in points {
            let ue = &mut ue[..3 * p.nodes.len()];
            ue.fill(0.0);
            for (h, &((a, b), (c, e))) in u.harmonics.iter().zip(&phi) {
                for (i, &k) in p.nodes.iter().enumerate() {
                    let s = h.symmetric.get(3 * k..3 * k + 3).unwrap_or(&zero);
                    let t = h.antisymmetric.get(3 * k..3 * k + 3).unwrap_or(&zero);
                    ue[3 * i] += a * s[0] + c * t[0];
                    ue[3 * i + 1] += a * s[1] + c * t[1];
                    ue[3 * i + 2] += b * s[2] + e * t[2];
                }
            }
            out.push(crate::elements::relative_displacement(&p.point, ue));
        }
    }
    out
}

/// The tractions `t0 + k d` of linear joints at the relative displacements
/// `d` (index `s * points.len() + p`); `t0` per point, none: zero.
pub(super) fn linear_tractions(
    model: &Model,
    points: &[PointInfo],
    d: &[[f64; 3]],
    t0: Option<&[[f64; 3]]>,
) -> Vec<[f64; 3]> {
    let n_p = points.len().max(1);
    d.iter()
        .enumerate()
        .map(|(k, d)| {
            let kd = model.joints[points[k % n_p].joint].springs.traction(*d);
            let t = t0.and_then(|t| t.get(k % n_p)).copied().unwrap_or([0.0; 3]);
            [0, 1, 2].map(|c| t[c] + kd[c])
        })
        .collect()
}

/// The joint field of a run whose joints are all linear: at every joint
/// point and section the relative displacement `d` of `u`, the traction
/// `t0 + k d` (`t0` per point: the end of the initial phase, if any) and
/// the state stick.
pub fn linear_joint_field(
    model: &Model,
    u: &Displacements,
    sections: &crate::fourier::Sections,
    t0: Option<&[[f64; 3]]>,
) -> JointField {
    let points = crate::iteration::joint_point_infos(model);
    let d = joint_relative_displacements(&points, u, sections);
    let p = linear_tractions(model, &points, &d, t0);
    let n = d.len();
    JointField {
        sections: sections.clone(),
        points,
        d,
        p,
        state: vec![crate::joint_law::JointState::Stick; n],
        debonded: vec![false; n],
    }
}

/// The bodies of `outputs.members` (indices in `mesh.bodies`).
pub(super) fn member_bodies(scene: &Scene, mesh: &Mesh) -> Vec<usize> {
    scene
        .outputs
        .members
        .iter()
        .filter_map(|b| mesh.body(b))
        .collect()
}

/// Each joint's swept areas by state in `file` (a load step's record).
pub(super) fn joint_areas(
    mesh: &Mesh,
    file: &crate::results::JointFieldFile,
) -> Vec<crate::results::JointAreas> {
    mesh.joints
        .iter()
        .map(|j| {
            let (open, slip, stick) = file.state_areas(&j.name);
            crate::results::JointAreas {
                joint: j.name.clone(),
                open,
                slip,
                stick,
            }
        })
        .collect()
}

/// The motion of a loaded face ([`FaceMotion`]); `None` if the curve has no area.
pub(super) fn face_motion(mesh: &Mesh, load: &crate::scene::Load, u: &Displacements) -> Option<FaceMotion> {
    let on = load.on();
    let mean = face_displacement(mesh, on, u)?;
    // Rigid rotation fit of the torsional (m = 0) u_theta over the face's nodes.
    let mut nodes: Vec<usize> = mesh
        .curve(on)?
        .edges
        .iter()
        .flat_map(|e| e.nodes.iter().copied())
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    let (mut num, mut den, mut r_sum) = (0.0, 0.0, 0.0);
    for h in u.harmonics.iter().filter(|h| h.m == 0) {
        for &n in &nodes {
            let r = mesh.nodes[n][0];
            num += r * h.symmetric[3 * n + 2];
            den += r * r;
            r_sum += r;
        }
    }
    let rotation = if den > 0.0 { num / den } else { 0.0 };
    let (f, torque) = match load {
        crate::scene::Load::Resultant(l) => (l.force, l.torque),
        // Along the motion: its translation, else its turn about the axis.
        crate::scene::Load::Motion(l) => (l.displacement, l.rotation[2]),
        _ => ([0.0; 3], 0.0),
    };
    let f_norm = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
    let r_mean = if nodes.is_empty() {
        0.0
    } else {
        r_sum / nodes.len() as f64
    };
    let along = if f_norm > 0.0 {
        (mean[0] * f[0] + mean[1] * f[1] + mean[2] * f[2]) / f_norm
    } else if torque != 0.0 {
        rotation * r_mean * torque.signum()
    } else {
        // Not a resultant load: its largest component.
        mean.into_iter()
            .fold(0.0f64, |a, v| if v.abs() > a.abs() { v } else { a })
    };
    Some(FaceMotion {
        on: on.to_string(),
        mean,
        rotation,
        along,
        applied: None,
    })
}

/// The loads of a run that reached the load factor `lambda` (borrowed at 1).
pub(super) fn scaled(loads: &[HarmonicLoads], lambda: f64) -> std::borrow::Cow<'_, [HarmonicLoads]> {
    if lambda == 1.0 {
        std::borrow::Cow::Borrowed(loads)
    } else {
        std::borrow::Cow::Owned(loads.iter().map(|h| h.scaled(lambda)).collect())
    }
}

/// Pads amplitudes of harmonics 0..=m with zeros up to the run's harmonics.
pub(super) fn padded(d: &Displacements, all: &[HarmonicLoads]) -> Displacements {
    let n = all.first().map_or(0, |h| h.symmetric.len());
    Displacements {
        harmonics: all
            .iter()
            .map(|h| {
                d.harmonics
                    .iter()
                    .find(|x| x.m == h.m)
                    .cloned()
                    .unwrap_or(HarmonicDisplacement {
                        m: h.m,
                        symmetric: vec![0.0; n],
                        antisymmetric: vec![0.0; n],
                    })
            })
            .collect(),
    }
}

/// The reactions `K u - f - A x` (`loads`, the plastic bodies' `released`
/// forces added) when one of `faces` is moved by a motion (its reaction is
/// its load); empty otherwise.
pub(super) fn moved_reactions(
    scene: &Scene,
    model: &Model,
    faces: &[crate::scene::Load],
    loads: Vec<HarmonicLoads>,
    released: &[HarmonicLoads],
    d: &Displacements,
) -> Vec<SupportReaction> {
    if !faces.iter().any(|l| matches!(l, crate::scene::Load::Motion(_))) {
        return Vec::new();
    }
    reactions(scene, model, &with_released(loads, released), d)
}

/// `loads` plus the released forces of plastic bodies (`released`, per
/// harmonic; empty: none): the forces a reaction `K u - f` balances.
pub(super) fn with_released(mut loads: Vec<HarmonicLoads>, released: &[HarmonicLoads]) -> Vec<HarmonicLoads> {
    for r in released {
        if let Some(h) = loads.iter_mut().find(|h| h.m == r.m) {
            for (a, b) in h.symmetric.iter_mut().zip(&r.symmetric) {
                *a += b;
            }
            for (a, b) in h.antisymmetric.iter_mut().zip(&r.antisymmetric) {
                *a += b;
            }
        }
    }
    loads
}
