//! From a scene to a solved linear model: mesh, check, model, loads, solve.

use crate::assembly::JointModel;
use crate::dofs::Component;
use crate::error::SolverError;
use crate::linear::{HarmonicFactor, Model};
use crate::loads::{assemble_loads, load_resultants, HarmonicLoads, Resultants};
use crate::scene::Scene;
use axijoint_mesh::{gmsh, insert_joints, validate, Mesh, Validation};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;

pub use crate::solution::{Displacements, HarmonicDisplacement, SupportReaction, Timings};

/// A scene's mesh (joints inserted) after validation against the scene.
pub fn mesh_scene(scene: &Scene, keep_msh: Option<&Path>) -> Result<(Mesh, Validation), SolverError> {
    let path = scene.mesh_path();
    let mut mesh = gmsh::load(&path, &scene.gmsh_parameters(), keep_msh)?;
    scene.check(&mesh)?;
    let report = validate(&mut mesh, &path)?;
    insert_joints(&mut mesh, &scene.joint_specs(), &path)?;
    Ok((mesh, report))
}

/// Support flags per node DOF (`3 * node + component`).
pub fn support_flags(scene: &Scene, mesh: &Mesh) -> Vec<bool> {
    let mut fixed = vec![false; 3 * mesh.nodes.len()];
    for s in &scene.supports {
        let comps = s.fix.components();
        for n in support_nodes(mesh, &s.on) {
            for c in 0..3 {
                fixed[3 * n + c] |= comps[c];
            }
        }
    }
    fixed
}

/// Nodes of a physical curve (looked up first) or point group.
pub fn support_nodes(mesh: &Mesh, name: &str) -> Vec<usize> {
    let mut nodes: Vec<usize> = match mesh.curve(name) {
        Some(c) => c.edges.iter().flat_map(|e| e.nodes.iter().copied()).collect(),
        None => mesh.point(name).map(|p| p.nodes.clone()).unwrap_or_default(),
    };
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

/// `k h / E` above which a nonlinear joint solved by Newton is assembled
/// with the softer reference `k_ref = REFERENCE_STIFFNESS E / h` (per
/// component, never stiffer than the joint): every method converged up to
/// `k h / E = 1` on Scene P (docs/stability.md).
pub const REFERENCE_STIFFNESS: f64 = 1.0;

/// The springs assembled for a nonlinear joint: `min(k, k_ref)` per
/// component, `k_ref = REFERENCE_STIFFNESS E / h` with h its mean element
/// length and E the smallest Young's modulus of its bodies.
fn reference_springs(
    mesh: &Mesh,
    joint: &axijoint_mesh::Joint,
    materials: &[crate::material::Elastic],
    k: crate::elements::JointSprings,
) -> crate::elements::JointSprings {
    let h = joint.mean_length(&mesh.nodes);
    let e = joint
        .bottom_bodies
        .iter()
        .chain(&joint.top_bodies)
        .map(|&b| materials[b].e)
        .fold(f64::INFINITY, f64::min);
    if !(e.is_finite() && h > 0.0) {
        return k;
    }
    let cap = REFERENCE_STIFFNESS * e / h;
    crate::elements::JointSprings {
        k_xi: k.k_xi.min(cap),
        k_eta: k.k_eta.min(cap),
        k_theta: k.k_theta.min(cap),
    }
}

/// Builds the linear model of a scene on its mesh.
pub fn build_model(scene: &Scene, mesh: Mesh) -> Result<Model, SolverError> {
    let materials: Vec<_> = mesh
        .bodies
        .iter()
        .map(|b| scene.materials[&b.name].elastic())
        .collect();
    let joints = mesh
        .joints
        .iter()
        .map(|j| {
            let config = &scene.joints[&j.name];
            let kind = j
                .elements
                .first()
                .map_or(axijoint_mesh::JointKind::Lin6, |e| e.kind);
            let mut joint = JointModel::new(config.springs(), config.rule(kind));
            if config.law != crate::scene::JointLaw::Linear {
                let reference = reference_springs(&mesh, j, &materials, joint.springs);
                joint.opening = reference.k_eta;
                if scene.solver.method == crate::scene::SolverMethod::Newton {
                    joint.assembled = reference;
                }
            }
            joint
        })
        .collect();
    let fixed = support_flags(scene, &mesh);
    Ok(Model::new(mesh, materials, joints, fixed)?)
}

/// Environment variable: the memory the whole Cholesky factors of a run's
/// harmonics may take at once, in bytes (suffix `K`, `M` or `G`: KiB, MiB,
/// GiB). When the factors of every harmonic do not fit, the lowest
/// harmonics keep whole factors, the others only their joint blocks (all
/// the stress-transfer iteration reads), and a full solve of one of those
/// factorizes it again, as many at once as fit beside the kept ones (at
/// least one). Unset: half the memory available when the run starts. `0`:
/// joint blocks only, one whole factor at a time.
pub const FACTOR_MEMORY_ENV: &str = "AXIJOINT_FACTOR_MEMORY";

/// The byte budget of [`FACTOR_MEMORY_ENV`].
pub fn factor_memory_budget() -> Result<u64, SolverError> {
    match std::env::var(FACTOR_MEMORY_ENV) {
        Ok(v) if !v.trim().is_empty() => parse_bytes(v.trim()).ok_or_else(|| {
            SolverError::Solve(crate::linear::SolveError::Input(format!(
                "{FACTOR_MEMORY_ENV}={v}: give bytes, or a number with K, M or G (e.g. 4G)"
            )))
        }),
        _ => Ok(mem_available().map_or(u64::MAX, |b| b / 2)),
    }
}

fn parse_bytes(v: &str) -> Option<u64> {
    let (num, unit) = match v.char_indices().last()? {
        (i, c) if c.is_ascii_alphabetic() => (&v[..i], c.to_ascii_uppercase()),
        _ => (v, 'B'),
    };
    let shift = match unit {
        'B' => 0,
        'K' => 10,
        'M' => 20,
        'G' => 30,
        _ => return None,
    };
    let x: f64 = num.trim().parse().ok()?;
    (x >= 0.0 && x.is_finite()).then(|| (x * (1u64 << shift) as f64) as u64)
}

/// `MemAvailable` of `/proc/meminfo`, in bytes.
fn mem_available() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// For the factors of `n` harmonics (0..n unless all fit) within the
/// budget of [`FACTOR_MEMORY_ENV`]: the harmonics below the returned one
/// keep whole factors (`u32::MAX`: all), and the model's
/// [`Model::set_lean_at_once`] is set to what fits beside them.
fn plan_factors(model: &Model, n: usize) -> Result<u32, SolverError> {
    let one = (8 * model.factor_len() as u64).max(1);
    let fit = (factor_memory_budget()? / one).min(u32::MAX as u64) as usize;
    if n <= 1 || fit >= n {
        return Ok(u32::MAX);
    }
    let at_once = fit.clamp(1, rayon::current_num_threads().max(1));
    model.set_lean_at_once(at_once);
    Ok((fit - fit.min(at_once)) as u32)
}

/// Solves harmonic `h` of the loads with `factor` (zero when unloaded).
fn solve_harmonic(model: &Model, factor: Option<&HarmonicFactor>, h: &HarmonicLoads) -> HarmonicDisplacement {
    match factor {
        Some(f) if h.is_loaded() => {
            let mut u = model.solve(f, &[&h.symmetric, &h.antisymmetric]);
            let antisymmetric = u.pop().unwrap_or_default();
            let symmetric = u.pop().unwrap_or_default();
            HarmonicDisplacement {
                m: h.m,
                symmetric,
                antisymmetric,
            }
        }
        _ => {
            let n = h.symmetric.len();
            HarmonicDisplacement {
                m: h.m,
                symmetric: vec![0.0; n],
                antisymmetric: vec![0.0; n],
            }
        }
    }
}

/// Factorizes harmonics `ms` and solves their `loads` (each harmonic of
/// `ms` must be in `loads`); harmonics from `whole_below` on keep only
/// their joint blocks (each solved while whole).
fn factorize_and_solve(
    model: &Model,
    ms: &[u32],
    loads: &[HarmonicLoads],
    whole_below: u32,
) -> Result<Vec<(HarmonicFactor, HarmonicDisplacement)>, SolverError> {
    let load_of = |m: u32| {
        loads
            .iter()
            .find(|h| h.m == m)
            .expect("the loads of every harmonic")
    };
    Ok(model.factorize_all_with(
        ms,
        |m| m < whole_below,
        |f| solve_harmonic(model, Some(f), load_of(f.m)),
    )?)
}

/// A solved linear model.
pub struct LinearRun {
    /// The model (mesh, DOFs, pattern, symbolic factor).
    pub model: Model,
    /// Loads per harmonic.
    pub loads: Vec<HarmonicLoads>,
    /// Numeric factors of the harmonics that were factorized.
    pub factors: Vec<HarmonicFactor>,
    /// Displacement amplitudes.
    pub displacements: Displacements,
    /// Applied load resultants about the origin.
    pub applied: Resultants,
    /// Reactions per support.
    pub reactions: Vec<SupportReaction>,
    /// Times.
    pub timings: Timings,
}

/// Meshes, builds and solves a scene with its joints as linear springs.
/// Harmonics without load are not factorized unless `all_factors`.
pub fn solve_linear(
    scene: &Scene,
    keep_msh: Option<&Path>,
    all_factors: bool,
) -> Result<LinearRun, SolverError> {
    linear_run(scene, keep_msh, all_factors, true)
}

/// [`solve_linear`]; the reactions are left empty unless `with_reactions`
/// (a nonlinear run computes them once, at its solution).
fn linear_run(
    scene: &Scene,
    keep_msh: Option<&Path>,
    all_factors: bool,
    with_reactions: bool,
) -> Result<LinearRun, SolverError> {
    let (mesh, _) = mesh_scene(scene, keep_msh)?;
    let m_max = scene.harmonics();
    let loads = assemble_loads(scene, &mesh, m_max)?;
    let t0 = Instant::now();
    let model = build_model(scene, mesh)?;
    let setup = t0.elapsed().as_secs_f64();
    let wanted: Vec<u32> = loads
        .iter()
        .filter(|h| all_factors || h.is_loaded() || (h.m == 0 && scene.has_initial_phase()))
        .map(|h| h.m)
        .collect();
    let t1 = Instant::now();
    let whole_below = plan_factors(&model, wanted.len())?;
    let (factors, displacements, factorize, solve) = if wanted.iter().all(|&m| m < whole_below) {
        let factors = model.factorize_all(&wanted)?;
        let factorize = t1.elapsed().as_secs_f64();
        let t2 = Instant::now();
        let displacements = solve_loads(&model, &factors, &loads);
        (factors, displacements, factorize, t2.elapsed().as_secs_f64())
    } else {
        // Each harmonic solved while its factor is whole (the solves are
        // counted in the factorization time).
        let solved = factorize_and_solve(&model, &wanted, &loads, whole_below)?;
        let (factors, solved): (Vec<_>, Vec<_>) = solved.into_iter().unzip();
        let harmonics = loads
            .iter()
            .map(|h| match solved.iter().find(|d| d.m == h.m) {
                Some(d) => d.clone(),
                None => solve_harmonic(&model, None, h),
            })
            .collect();
        (
            factors,
            Displacements { harmonics },
            t1.elapsed().as_secs_f64(),
            0.0,
        )
    };
    let t3 = Instant::now();
    let reactions = if with_reactions {
        reactions(scene, &model, &loads, &displacements)
    } else {
        Vec::new()
    };
    let applied = load_resultants(&loads, &model.mesh, 0.0);
    Ok(LinearRun {
        model,
        loads,
        factors,
        displacements,
        applied,
        reactions,
        timings: Timings {
            setup,
            factorize,
            solve,
            reactions: t3.elapsed().as_secs_f64(),
        },
    })
}

/// Displacements of `loads`: each loaded harmonic solved with its factor in
/// `factors` (both families in one solve), the others zero.
/// A factor that keeps only its joint block is factorized again for its solve.
pub fn solve_loads(model: &Model, factors: &[HarmonicFactor], loads: &[HarmonicLoads]) -> Displacements {
    let factor_of = |i: usize| factors.iter().find(|f| f.m == loads[i].m);
    let harmonics = model.map_bounded(
        loads.len(),
        |i| factor_of(i).is_some_and(|f| !f.is_full()),
        |i| solve_harmonic(model, factor_of(i), &loads[i]),
    );
    Displacements { harmonics }
}

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
        .supports
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

/// The header of a solved run (see [`crate::results`]).
pub fn solution_header(scene: &Scene, run: &LinearRun) -> crate::results::SolutionHeader {
    use crate::results::*;
    let mesh = &run.model.mesh;
    let loaded_faces = scene
        .loads
        .iter()
        .filter_map(|l| face_displacement(mesh, l.on(), &run.displacements).map(|d| (l.on().to_string(), d)))
        .collect();
    let h = run.displacements.harmonics.len();
    SolutionHeader {
        format: FORMAT.into(),
        version: VERSION,
        scene_file: scene.path.display().to_string(),
        scene: scene.clone(),
        mesh: MeshRef {
            file: "mesh.msh".into(),
            nodes: mesh.nodes.len(),
            elements: mesh.cells.len(),
            joints: mesh.joints.iter().map(|j| j.name.clone()).collect(),
            checksum: mesh_checksum(mesh),
        },
        dofs_per_harmonic: run.model.n_eq(),
        harmonics: run.displacements.harmonics.iter().map(|d| d.m).collect(),
        displacement: ArrayRef {
            file: "displacement.f64".into(),
            dtype: "f64le".into(),
            shape: vec![h, 2, mesh.nodes.len(), 3],
            layout: "[harmonic 0..=M][family: symmetric, antisymmetric][node][u_r, u_z, u_theta]".into(),
        },
        applied: run.applied.into(),
        reactions: run.reactions.clone(),
        loaded_faces,
        max_displacement: max_displacement(mesh.nodes.len(), &run.displacements),
        timings: run.timings.clone(),
        extra: serde_json::Value::Null,
        initial: None,
    }
}

/// The header's [`crate::results::InitialInfo`] of an initial phase.
pub fn initial_info(initial: &InitialState) -> crate::results::InitialInfo {
    let n = initial
        .displacements
        .harmonics
        .first()
        .map_or(0, |h| h.symmetric.len() / 3);
    crate::results::InitialInfo {
        displacement: crate::results::ArrayRef {
            file: "initial_displacement.f64".into(),
            dtype: "f64le".into(),
            shape: vec![1, 2, n, 3],
            layout: "[harmonic 0][family: symmetric, antisymmetric][node][u_r, u_z, u_theta]".into(),
        },
        balance: initial.balance,
        max_displacement: initial.max_displacement,
        iterations: initial.iterations,
    }
}

/// The theta sections of a scene's joint law for its loads (see
/// [`Scene::theta_sections`]).
pub fn scene_sections(
    scene: &Scene,
    loads: &[HarmonicLoads],
) -> Result<crate::fourier::Sections, SolverError> {
    let symmetric_only = loads.iter().all(|h| {
        h.antisymmetric.iter().all(|&v| v == 0.0)
            && (h.m > 0 || h.symmetric.iter().skip(2).step_by(3).all(|&v| v == 0.0))
    });
    Ok(scene.theta_sections(symmetric_only)?)
}

/// A solved scene: the linear model and, when a joint is nonlinear, the
/// converged iteration.
pub struct Run {
    /// The linear run (its displacements are the final ones).
    pub linear: LinearRun,
    /// The iteration, if any joint is nonlinear.
    pub outcome: Option<crate::iteration::Outcome>,
    /// Key results with harmonics 0..=M/2 against 0..=M (nonlinear, M >= 2).
    pub harmonic_check: Option<HarmonicCheck>,
    /// The steps of an automatic choice of M.
    pub auto_steps: Vec<AutoStep>,
    /// The load path of a stepped run (`solver.loading` not `"one_shot"`).
    pub load_path: Option<LoadPath>,
    /// The initial phase, if the scene has one; the displacements of the
    /// run are relative to its end.
    pub initial: Option<InitialState>,
}

impl Run {
    /// The joint field of the run: the iteration's, or when every joint is
    /// linear [`linear_joint_field`] of the displacements on the sections
    /// of `scene` (the solved scene); `None` without joints.
    pub fn joint_field(
        &self,
        scene: &Scene,
    ) -> Result<Option<std::borrow::Cow<'_, crate::iteration::JointField>>, SolverError> {
        use std::borrow::Cow;
        if let Some(outcome) = &self.outcome {
            return Ok(Some(Cow::Borrowed(&outcome.field)));
        }
        let model = &self.linear.model;
        if model.mesh.joints.is_empty() {
            return Ok(None);
        }
        let sections = scene_sections(scene, &self.linear.loads)?;
        let t0 = self.initial.as_ref().map(|i| i.traction.as_slice());
        Ok(Some(Cow::Owned(linear_joint_field(
            model,
            &self.linear.displacements,
            &sections,
            t0,
        ))))
    }
}

/// The relative displacement `(d_xi, d_eta, d_theta)` of `u` at every joint
/// point and section: index `s * points.len() + p`.
pub fn joint_relative_displacements(
    points: &[crate::iteration::PointInfo],
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
fn linear_tractions(
    model: &Model,
    points: &[crate::iteration::PointInfo],
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
) -> crate::iteration::JointField {
    let points = crate::iteration::joint_point_infos(model);
    let d = joint_relative_displacements(&points, u, sections);
    let p = linear_tractions(model, &points, &d, t0);
    let n = d.len();
    crate::iteration::JointField {
        sections: sections.clone(),
        points,
        d,
        p,
        state: vec![crate::joint_law::JointState::Stick; n],
        debonded: vec![false; n],
    }
}

/// The end of a scene's initial phase (docs/loading.md).
#[derive(Clone, Debug)]
pub struct InitialState {
    /// Displacements of the phase (harmonic 0 only).
    pub displacements: Displacements,
    /// The out-of-balance of the initial stresses.
    pub balance: crate::initial::Balance,
    /// Largest displacement magnitude of the phase.
    pub max_displacement: f64,
    /// Iterations of the phase (0 without nonlinear joints).
    pub iterations: usize,
    /// Joint traction `(tau_xi, sigma, tau_theta)` at the end of the phase,
    /// per joint point (axisymmetric: the same at every theta): the initial
    /// traction plus what the joint law adds along the phase (`k d` for a
    /// linear joint).
    pub traction: Vec<[f64; 3]>,
    /// Debonded joint points.
    pub debonded: Vec<bool>,
}

impl InitialState {
    /// The joint start state of an iteration on `n_sections` sections.
    pub fn joint_start(&self, n_sections: usize) -> crate::iteration::JointStart {
        crate::iteration::JointStart {
            traction: self.traction.repeat(n_sections),
            debonded: self.debonded.repeat(n_sections),
        }
    }
}

/// Solves the initial phase of `scene` on the factors of `linear` (harmonic
/// 0 must be among them): its out-of-balance with the joint law acting on
/// the initial tractions, along the scene's loading path.
pub fn initial_phase(
    scene: &Scene,
    linear: &LinearRun,
    progress: impl FnMut(&crate::iteration::IterationRecord),
) -> Result<InitialState, SolverError> {
    use crate::scene::JointLaw;
    let model = &linear.model;
    let il = crate::initial::initial_load(scene, model)?;
    let n = model.mesh.nodes.len();
    let loads = vec![HarmonicLoads {
        m: 0,
        symmetric: il.load,
        antisymmetric: vec![0.0; 3 * n],
    }];
    let nonlinear = scene.joints.values().any(|j| j.law != JointLaw::Linear);
    let n_points = il.traction.len();
    let (displacements, iterations, traction, debonded) = if !nonlinear || model.mesh.joints.is_empty() {
        // No iteration: the linear joints end at t0 + k d of the phase.
        let u = solve_loads(model, &linear.factors, &loads);
        let points = crate::iteration::joint_point_infos(model);
        let axisymmetric = crate::fourier::Sections::full_circle(vec![0.0]).expect("one section is valid");
        let d = joint_relative_displacements(&points, &u, &axisymmetric);
        let traction = linear_tractions(model, &points, &d, Some(&il.traction));
        (u, 0, traction, vec![false; n_points])
    } else {
        let sections = scene_sections(scene, &linear.loads)?;
        let start = crate::iteration::JointStart {
            traction: il.traction.repeat(sections.len()),
            debonded: vec![false; sections.len() * n_points],
        };
        let laws = joint_laws(scene, model);
        let settings = iteration_settings(scene);
        let failed = |e: crate::iteration::IterationError| SolverError::InitialPhase {
            beyond_capacity: matches!(e, crate::iteration::IterationError::NoEquilibrium { .. }),
            message: e.to_string(),
        };
        let problem = crate::iteration::Problem {
            model,
            factors: &linear.factors,
            loads: &loads,
            laws: &laws,
            sections: &sections,
            elastic: None,
        };
        let loading = scene.solver.loading.into();
        let solved =
            crate::iteration::solve(&problem, &settings, Some(&start), loading, |_, _, _| (), progress)
                .map_err(failed)?;
        if let Some(limit) = solved.stepped.and_then(|s| s.limit) {
            return Err(SolverError::InitialPhase {
                message: format!(
                    "the joints cannot carry the initial state: the phase reached only {:.4} of its load ({})",
                    limit.factor, limit.reason
                ),
                beyond_capacity: limit.beyond_capacity,
            });
        }
        let outcome = solved.outcome;
        let iterations = outcome.history.len();
        let field = outcome.field;
        (
            outcome.displacements,
            iterations,
            field.p[..n_points].to_vec(),
            field.debonded[..n_points].to_vec(),
        )
    };
    Ok(InitialState {
        max_displacement: max_displacement(n, &displacements),
        displacements,
        balance: il.balance,
        iterations,
        traction,
        debonded,
    })
}

/// The converged steps of a stepped run, and where it stopped short of the
/// whole load.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LoadPath {
    /// Converged steps, in order of lambda.
    pub steps: Vec<crate::iteration::LoadStep<StepMeasure>>,
    /// Set when the whole load could not be reached: the limit load factor.
    pub limit: Option<crate::iteration::LimitLoad>,
}

impl LoadPath {
    /// The load factor reached (1 when the whole load converged).
    pub fn reached(&self) -> f64 {
        self.limit.as_ref().map_or(1.0, |l| l.factor)
    }
}

/// What a converged load step measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepMeasure {
    /// Each load's face.
    pub faces: Vec<FaceMotion>,
    /// Each joint's areas by state.
    pub joints: Vec<JointAreas>,
}

/// The motion of a loaded face.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FaceMotion {
    /// The physical curve.
    pub on: String,
    /// Face-average Cartesian displacement `(ux, uy, uz)` (length).
    pub mean: [f64; 3],
    /// Mean rotation about the axis (rad): `sum w r u_theta / sum w r^2`.
    pub rotation: f64,
    /// The displacement along the load: `mean . F / |F|` for a resultant
    /// load with a force, the rotation times the face's mean nodal radius
    /// for a pure torque, else the largest component of `mean`.
    pub along: f64,
}

/// Joint areas by state (length^2), from the section integration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointAreas {
    /// The joint.
    pub joint: String,
    /// Open area.
    pub open: f64,
    /// Slipping area.
    pub slip: f64,
    /// Sticking area.
    pub stick: f64,
}

/// How much the key results change when the harmonics are halved: the
/// user's check that M is enough.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HarmonicCheck {
    /// The solved M.
    pub m: u32,
    /// The compared M/2.
    pub m_half: u32,
    /// Largest change of a loaded face's mean displacement, relative to
    /// the largest such displacement (none when the M/2 run failed).
    pub face_change: Option<f64>,
    /// Change of the open and of the slipping joint area, relative to the
    /// joints' total area (the larger of the two).
    pub area_change: Option<f64>,
    /// Why the M/2 run gave no comparison.
    pub note: Option<String>,
}

/// One step of the automatic choice of M.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AutoStep {
    /// Harmonics 0..=m.
    pub m: u32,
    /// Iterations of this step.
    pub iterations: usize,
    /// Relative change of the measured results against the previous step.
    pub change: Option<f64>,
}

/// The laws of the model's joints, in model order.
fn joint_laws(scene: &Scene, model: &Model) -> Vec<crate::scene::JointLaw> {
    model
        .mesh
        .joints
        .iter()
        .map(|j| scene.joints[&j.name].law)
        .collect()
}

/// The iteration settings of a scene's `solver` block.
pub fn iteration_settings(scene: &Scene) -> crate::iteration::IterationSettings {
    use crate::iteration::{IterationSettings, Method};
    IterationSettings {
        method: match scene.solver.method {
            crate::scene::SolverMethod::Paper => Method::Plain,
            crate::scene::SolverMethod::Anderson => Method::Anderson { depth: 8 },
            crate::scene::SolverMethod::Newton => Method::Newton,
        },
        epsilon: scene.solver.epsilon,
        max_iterations: scene.solver.max_iterations,
        ..IterationSettings::default()
    }
}

/// The nonlinear solution with harmonics 0..=m of a linear run (its
/// factors), on `sections`: one-shot or along the load path of
/// `solver.loading`.
fn iterate(
    scene: &Scene,
    linear: &LinearRun,
    m: u32,
    sections: &crate::fourier::Sections,
    initial: Option<&InitialState>,
    progress: impl FnMut(&crate::iteration::IterationRecord),
) -> Result<(crate::iteration::Outcome, Option<LoadPath>), SolverError> {
    let start = initial.map(|i| i.joint_start(sections.len()));
    let loads: Vec<HarmonicLoads> = linear.loads.iter().filter(|h| h.m <= m).cloned().collect();
    let laws = joint_laws(scene, &linear.model);
    let settings = iteration_settings(scene);
    // linear.displacements is the elastic solution here (both callers
    // replace it only after their last iteration).
    let problem = crate::iteration::Problem {
        model: &linear.model,
        factors: &linear.factors,
        loads: &loads,
        laws: &laws,
        sections,
        elastic: Some(&linear.displacements),
    };
    let mesh = &linear.model.mesh;
    let springs: Vec<_> = linear.model.joints.iter().map(|j| j.springs).collect();
    let observe = |_lambda: f64, u: &Displacements, field: &crate::iteration::JointField| {
        let d = padded(u, &linear.loads);
        let file = crate::results::JointFieldFile::new(mesh, &springs, field);
        StepMeasure {
            faces: scene
                .loads
                .iter()
                .filter_map(|l| face_motion(mesh, l, &d))
                .collect(),
            joints: mesh
                .joints
                .iter()
                .map(|j| {
                    let (open, slip, stick) = file.state_areas(&j.name);
                    JointAreas {
                        joint: j.name.clone(),
                        open,
                        slip,
                        stick,
                    }
                })
                .collect(),
        }
    };
    let loading = scene.solver.loading.into();
    let solved = crate::iteration::solve(&problem, &settings, start.as_ref(), loading, observe, progress)?;
    let path = solved.stepped.map(|s| LoadPath {
        steps: s.steps,
        limit: s.limit,
    });
    Ok((solved.outcome, path))
}

/// The motion of a loaded face ([`FaceMotion`]); `None` if the curve has no area.
fn face_motion(mesh: &Mesh, load: &crate::scene::Load, u: &Displacements) -> Option<FaceMotion> {
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
    })
}

/// The loads of a run that reached the load factor `lambda` (borrowed at 1).
fn scaled(loads: &[HarmonicLoads], lambda: f64) -> std::borrow::Cow<'_, [HarmonicLoads]> {
    if lambda == 1.0 {
        std::borrow::Cow::Borrowed(loads)
    } else {
        std::borrow::Cow::Owned(loads.iter().map(|h| h.scaled(lambda)).collect())
    }
}

/// Pads amplitudes of harmonics 0..=m with zeros up to the run's harmonics.
fn padded(d: &Displacements, all: &[HarmonicLoads]) -> Displacements {
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

/// Compares the key results of two solutions of the same model.
fn harmonic_check(
    scene: &Scene,
    linear: &LinearRun,
    full: (&crate::iteration::Outcome, u32),
    half: (&crate::iteration::Outcome, u32),
) -> HarmonicCheck {
    let mesh = &linear.model.mesh;
    let faces = |o: &crate::iteration::Outcome| -> Vec<[f64; 3]> {
        let d = padded(&o.displacements, &linear.loads);
        scene
            .loads
            .iter()
            .filter_map(|l| face_displacement(mesh, l.on(), &d))
            .collect()
    };
    let (a, b) = (faces(full.0), faces(half.0));
    let scale = a.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a
        .iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    let springs: Vec<_> = linear.model.joints.iter().map(|j| j.springs).collect();
    let areas = |o: &crate::iteration::Outcome| -> Vec<(f64, f64, f64)> {
        let file = crate::results::JointFieldFile::new(mesh, &springs, &o.field);
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
        padded(&full.0.displacements, &linear.loads),
        padded(&half.0.displacements, &linear.loads),
    );
    let n = mesh.nodes.len();
    let u_max = max_displacement(n, &uf);
    let (face_change, note) = if scale > 1e-3 * u_max {
        (diff / scale, None)
    } else {
        let delta = Displacements {
            harmonics: uf
                .harmonics
                .iter()
                .zip(&uh.harmonics)
                .map(|(a, b)| HarmonicDisplacement {
                    m: a.m,
                    symmetric: a.symmetric.iter().zip(&b.symmetric).map(|(x, y)| x - y).collect(),
                    antisymmetric: a
                        .antisymmetric
                        .iter()
                        .zip(&b.antisymmetric)
                        .map(|(x, y)| x - y)
                        .collect(),
                })
                .collect(),
        };
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

/// Solves a scene: linear springs, then the stress-transfer iteration when a
/// joint can open or slip, and the M/2 check. `progress` sees each iteration.
pub fn solve_scene(
    scene: &Scene,
    keep_msh: Option<&Path>,
    progress: impl FnMut(&crate::iteration::IterationRecord),
) -> Result<Run, SolverError> {
    solve_scene_with(scene, keep_msh, progress, |_, _, _| {})
}

/// [`solve_scene`]; when a one-shot iteration stops without a solution,
/// `on_failure` sees the linear run with the displacements of the last
/// iterate (no reactions: it is not an equilibrium) and the error, before
/// the error is returned.
pub fn solve_scene_with(
    scene: &Scene,
    keep_msh: Option<&Path>,
    mut progress: impl FnMut(&crate::iteration::IterationRecord),
    on_failure: impl FnOnce(&LinearRun, Option<&InitialState>, &crate::iteration::IterationError),
) -> Result<Run, SolverError> {
    use crate::scene::JointLaw;
    let nonlinear = scene.joints.values().any(|j| j.law != JointLaw::Linear);
    let linear = linear_run(scene, keep_msh, nonlinear, false)?;
    let t = Instant::now();
    let initial = if scene.has_initial_phase() {
        Some(initial_phase(scene, &linear, &mut progress)?)
    } else {
        None
    };
    finish_run(scene, linear, initial, t, progress, on_failure).map_err(|f| f.0)
}

/// The rest of a run from its linear solution (the elastic solution of the
/// scene's loads) and initial state: the iteration if a joint can open or
/// slip, the M/2 check, the reactions. `t`: when the run's solve began. On
/// failure the linear run comes back with the error.
fn finish_run(
    scene: &Scene,
    mut linear: LinearRun,
    initial: Option<InitialState>,
    t: Instant,
    mut progress: impl FnMut(&crate::iteration::IterationRecord),
    on_failure: impl FnOnce(&LinearRun, Option<&InitialState>, &crate::iteration::IterationError),
) -> Result<Run, Box<(SolverError, LinearRun)>> {
    use crate::scene::JointLaw;
    let nonlinear = scene.joints.values().any(|j| j.law != JointLaw::Linear);
    if !nonlinear || linear.model.mesh.joints.is_empty() {
        linear.reactions = reactions(scene, &linear.model, &linear.loads, &linear.displacements);
        linear.timings.solve += t.elapsed().as_secs_f64();
        return Ok(Run {
            linear,
            outcome: None,
            harmonic_check: None,
            auto_steps: Vec::new(),
            load_path: None,
            initial,
        });
    }
    let sections = match scene_sections(scene, &linear.loads) {
        Ok(s) => s,
        Err(e) => return Err(Box::new((e, linear))),
    };
    let m = scene.harmonics();
    let (outcome, load_path) = match iterate(scene, &linear, m, &sections, initial.as_ref(), &mut progress) {
        Ok(v) => v,
        Err(SolverError::Iteration(e)) => {
            if let Some(last) = e.last() {
                linear.displacements = padded(&last.displacements, &linear.loads);
                linear.reactions = Vec::new();
                on_failure(&linear, initial.as_ref(), &e);
            }
            return Err(Box::new((SolverError::Iteration(e), linear)));
        }
        Err(e) => return Err(Box::new((e, linear))),
    };
    let complete = load_path.as_ref().is_none_or(|p| p.limit.is_none());
    let harmonic_check = if m >= 2 && !complete {
        Some(HarmonicCheck {
            m,
            m_half: m / 2,
            face_change: None,
            area_change: None,
            note: Some("the whole load was not reached: no comparison".into()),
        })
    } else if m >= 2 {
        Some(
            match iterate(scene, &linear, m / 2, &sections, initial.as_ref(), |_| {}) {
                Ok((_, path)) if path.as_ref().is_some_and(|p| p.limit.is_some()) => HarmonicCheck {
                    m,
                    m_half: m / 2,
                    face_change: None,
                    area_change: None,
                    note: Some(format!(
                        "the run with harmonics 0..={} reached only the load factor {:.4}",
                        m / 2,
                        path.map_or(1.0, |p| p.reached())
                    )),
                },
                Ok((half, _)) => harmonic_check(scene, &linear, (&outcome, m), (&half, m / 2)),
                Err(e) => HarmonicCheck {
                    m,
                    m_half: m / 2,
                    face_change: None,
                    area_change: None,
                    note: Some(format!("the run with harmonics 0..={} failed: {e}", m / 2)),
                },
            },
        )
    } else {
        None
    };
    linear.displacements = outcome.displacements.clone();
    linear.timings.solve += t.elapsed().as_secs_f64();
    let lambda = load_path.as_ref().map_or(1.0, LoadPath::reached);
    linear.reactions = reactions(
        scene,
        &linear.model,
        &scaled(&linear.loads, lambda),
        &linear.displacements,
    );
    Ok(Run {
        linear,
        outcome: Some(outcome),
        harmonic_check,
        auto_steps: Vec::new(),
        load_path,
        initial,
    })
}

/// Solves every load case of `scene` ([`Scene::load_cases`]) on one model
/// and one set of factors (every harmonic 0..=M, factorized once), each
/// from the same initial state. `each` sees the case's index, its scene
/// and its run or why it stopped, in order; a case that stops does not stop
/// the others. A failure before the cases (mesh, factors, initial phase) is
/// returned.
pub fn solve_cases(
    scene: &Scene,
    keep_msh: Option<&Path>,
    mut progress: impl FnMut(&crate::iteration::IterationRecord),
    mut on_failure: impl FnMut(usize, &LinearRun, Option<&InitialState>, &crate::iteration::IterationError),
    mut each: impl FnMut(usize, &Scene, Result<&Run, &SolverError>),
) -> Result<(), SolverError> {
    let mut linear = linear_run(scene, keep_msh, true, false)?;
    let t = Instant::now();
    let initial = if scene.has_initial_phase() {
        Some(initial_phase(scene, &linear, &mut progress)?)
    } else {
        None
    };
    linear.timings.solve += t.elapsed().as_secs_f64();
    let m_max = scene.harmonics();
    for k in 0..scene.load_cases.len() {
        let case = scene.case(k);
        let t = Instant::now();
        linear.timings.solve = 0.0;
        match assemble_loads(&case, &linear.model.mesh, m_max) {
            Ok(loads) => linear.loads = loads,
            Err(e) => {
                each(k, &case, Err(&SolverError::Scene(e.in_case(k))));
                continue;
            }
        }
        linear.displacements = solve_loads(&linear.model, &linear.factors, &linear.loads);
        linear.applied = load_resultants(&linear.loads, &linear.model.mesh, 0.0);
        linear.reactions = Vec::new();
        let on_fail = |l: &LinearRun, i: Option<&InitialState>, e: &crate::iteration::IterationError| {
            on_failure(k, l, i, e)
        };
        match finish_run(&case, linear, initial.clone(), t, &mut progress, on_fail) {
            Ok(run) => {
                each(k, &case, Ok(&run));
                linear = run.linear;
            }
            Err(failed) => {
                let (e, l) = *failed;
                each(k, &case, Err(&e));
                linear = l;
            }
        }
    }
    Ok(())
}

/// Chooses M automatically: a linear scene solves the harmonics its loads
/// contain; with nonlinear joints M grows 4, 8, 16, ... up to `m_max` until
/// `measure` (e.g. the cut profiles) changes by less than `tolerance`
/// relative to its largest value. Factors of lower harmonics are kept.
pub fn solve_scene_auto(
    scene: &Scene,
    keep_msh: Option<&Path>,
    tolerance: f64,
    m_max: u32,
    measure: impl Fn(&Model, &Displacements) -> Vec<f64>,
    mut progress: impl FnMut(&crate::iteration::IterationRecord),
) -> Result<(Scene, Run), SolverError> {
    use crate::scene::JointLaw;
    let nonlinear = scene.joints.values().any(|j| j.law != JointLaw::Linear);
    let seismic = scene.seismic_coefficient != 0.0 && scene.materials.values().any(|m| m.unit_weight > 0.0);
    let loaded = scene
        .loads
        .iter()
        .map(|l| l.max_harmonic())
        .max()
        .unwrap_or(0)
        .max(u32::from(seismic));
    let mut sc = scene.clone();
    if !nonlinear {
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
    let mut linear = linear_run(&sc, keep_msh, true, false)?;
    let mut steps: Vec<AutoStep> = Vec::new();
    let mut previous: Option<Vec<f64>> = None;
    let t = Instant::now();
    let initial = if sc.has_initial_phase() {
        Some(initial_phase(&sc, &linear, &mut progress)?)
    } else {
        None
    };
    loop {
        let sections = scene_sections(&sc, &linear.loads)?;
        let (outcome, load_path) = iterate(&sc, &linear, m, &sections, initial.as_ref(), &mut progress)?;
        let values = measure(&linear.model, &outcome.displacements);
        let change = previous.as_ref().map(|p| {
            let scale = values
                .iter()
                .fold(0.0f64, |a, v| a.max(v.abs()))
                .max(f64::MIN_POSITIVE);
            values
                .iter()
                .zip(p)
                .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()))
                / scale
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
            linear.displacements = outcome.displacements.clone();
            linear.timings.solve += t.elapsed().as_secs_f64();
            let lambda = load_path.as_ref().map_or(1.0, LoadPath::reached);
            linear.reactions = reactions(
                &sc,
                &linear.model,
                &scaled(&linear.loads, lambda),
                &linear.displacements,
            );
            return Ok((
                sc,
                Run {
                    linear,
                    outcome: Some(outcome),
                    harmonic_check: None,
                    auto_steps: steps,
                    load_path,
                    initial,
                },
            ));
        }
        previous = Some(values);
        // Grow M: reassemble the loads, factorize only the new harmonics and
        // solve their loads (beyond the factor memory, the factors from
        // `whole_below` on keep only their joint blocks).
        let next = 2 * m;
        sc.harmonics = next.into();
        let new: Vec<u32> = (m + 1..=next).collect();
        linear.loads = assemble_loads(&sc, &linear.model.mesh, next)?;
        let t1 = Instant::now();
        let whole_below = plan_factors(&linear.model, next as usize + 1)?;
        let model = &linear.model;
        linear.factors = std::mem::take(&mut linear.factors)
            .into_iter()
            .map(|f| {
                if f.m < whole_below {
                    f
                } else {
                    model.joint_block(f)
                }
            })
            .collect();
        for (f, d) in factorize_and_solve(&linear.model, &new, &linear.loads, whole_below)? {
            linear.factors.push(f);
            linear.displacements.harmonics.retain(|h| h.m != d.m);
            linear.displacements.harmonics.push(d);
        }
        linear.timings.factorize += t1.elapsed().as_secs_f64();
        m = next;
    }
}
