//! The accuracy sweep: Scene P variants x mesh sizes x harmonics x methods,
//! each run as `axijoint solve` and `axijoint run` child processes, measured
//! (wall, CPU, peak memory, other processes' load) and compared with a
//! reference run; plus the CalculiX 3D peer's runs. One [`Row`] per run,
//! written to a CSV ([`write_csv`], [`read_csv`]).
//!
//! Per-run scenes are written into the work folder (never beside the inputs):
//! the variant's scene with `mesh.file` made absolute, the paper's explicit
//! `sections` dropped (so the dealiased default 2M + 1 is used), and
//! `solver.method` and `solver.epsilon` set. The mesh size goes on the
//! command line (`--set size=S`), and so does M (`--harmonics M`).

use crate::errors::{read_scene_p_profiles, relative_error};
use crate::measure::{run_measured, Measured};
use crate::peer3d::{self as peer, PeerOptions, PeerVariant};
use crate::profile::Profile;
use anyhow::{bail, Context, Result};
use axijoint_solver::results::SolutionHeader;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A variant of Scene P.
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    /// "bonded", "linear", "coulomb", "frictionless" or "table1".
    pub name: String,
    /// The scene file (geo/...).
    pub scene: PathBuf,
    /// Linear scene: one run per mesh size (M and the method do not matter).
    pub linear: bool,
    /// The CalculiX peer's variant, if it has one (table1 has cohesion: none).
    pub peer: Option<PeerVariant>,
}

/// The known variants, scene files under `geo_dir`.
pub fn known_variant(name: &str, geo_dir: &Path) -> Result<Variant> {
    let (file, linear, peer) = match name {
        "bonded" => ("pile_footing_bonded.json", true, Some(PeerVariant::Bonded)),
        "linear" => ("pile_footing_linear.json", true, Some(PeerVariant::Linear)),
        "coulomb" => ("pile_footing_coulomb.json", false, Some(PeerVariant::Coulomb)),
        "frictionless" => (
            "pile_footing_frictionless.json",
            false,
            Some(PeerVariant::Frictionless),
        ),
        "table1" => ("pile_footing.json", false, None),
        _ => bail!("unknown variant '{name}' (known: bonded, linear, coulomb, frictionless, table1)"),
    };
    Ok(Variant {
        name: name.to_owned(),
        scene: geo_dir.join(file),
        linear,
        peer,
    })
}

/// Everything the sweep needs.
#[derive(Clone, Debug)]
pub struct Config {
    /// The axijoint binary.
    pub axijoint: PathBuf,
    /// gmsh and ccx, for the peer.
    pub gmsh: PathBuf,
    /// CalculiX's solver binary.
    pub ccx: PathBuf,
    /// Scratch folder: scenes, run folders, kept cut CSVs.
    pub work_dir: PathBuf,
    /// Variants to run.
    pub variants: Vec<Variant>,
    /// Mesh sizes (geo/pile_footing.geo `size`), any order; the smallest is
    /// the reference level.
    pub sizes: Vec<f64>,
    /// Gradings (geo/pile_footing.geo `refine`: size / element size along
    /// the pile side), any order; the largest is the reference's.
    pub refines: Vec<f64>,
    /// Highest harmonics M; the largest is the reference's.
    pub harmonics: Vec<usize>,
    /// Methods of the nonlinear variants: "paper", "anderson", "newton".
    pub methods: Vec<String>,
    /// M of the linear variants' single run per size.
    pub linear_harmonics: usize,
    /// Convergence tolerance of the sweep.
    pub epsilon: f64,
    /// Tolerance of the nonlinear reference run.
    pub ref_epsilon: f64,
    /// Method of the nonlinear reference.
    pub ref_method: String,
    /// Peer mesh sizes (empty: no peer).
    pub peer_sizes: Vec<f64>,
    /// Keep the run folders (default: only the cut CSVs are kept).
    pub keep: bool,
    /// Also time `axijoint solve` with the mesh from a warm cache this many
    /// times, keeping the fastest (0: not at all).
    pub warm_solves: usize,
}

/// The grading `refine` of geo/pile_footing.geo's scenes.
pub const DEFAULT_REFINE: f64 = 2.0;

/// One row of `accuracy.csv`. Empty fields: not applicable or failed.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// "axijoint" or "calculix".
    pub tool: String,
    /// Scene P variant.
    pub variant: String,
    /// axijoint: solver.method ("-" for linear variants); calculix: "ccx".
    pub method: String,
    /// "sweep"; "linear" (one run per size: M and method irrelevant);
    /// "reference" (the nonlinear reference run); "peer".
    pub role: String,
    /// True for the run every other run of the variant is compared with.
    pub is_reference: bool,
    /// Mesh size parameter `size` (m).
    pub size: f64,
    /// axijoint: DOF per harmonic.
    pub dof_per_harmonic: Option<usize>,
    /// calculix: DOF of the 3D model.
    pub dof_3d: Option<usize>,
    /// Highest harmonic M (axijoint).
    pub m: Option<usize>,
    /// Theta sections of the joint law (axijoint, nonlinear).
    pub sections: Option<usize>,
    /// Convergence tolerance (axijoint).
    pub epsilon: Option<f64>,
    /// axijoint: iterations (Newton: steps); calculix: increments.
    pub iterations: Option<usize>,
    /// axijoint: back-substitution sweeps of all harmonics.
    pub solves: Option<usize>,
    /// `axijoint solve` (mesh + solve + solution folder) wall time (s);
    /// calculix: gmsh mesh + ccx.
    pub solve_wall_s: Option<f64>,
    /// CPU time of the same (s) (calculix: ccx CPU + mesh wall).
    pub solve_cpu_s: Option<f64>,
    /// Peak memory of the same (MiB) (calculix: ccx).
    pub solve_peak_rss_mib: Option<f64>,
    /// `axijoint run` (mesh + solve + every output) wall time (s);
    /// calculix: the whole peer run.
    pub run_wall_s: Option<f64>,
    /// CPU time of `axijoint run` (s).
    pub run_cpu_s: Option<f64>,
    /// Peak memory of `axijoint run` (MiB).
    pub run_peak_rss_mib: Option<f64>,
    /// Relative L2 error of the a-a and b-b profiles against axijoint's
    /// reference of the variant.
    pub err_vs_axijoint_ref: Option<f64>,
    /// The same against the CalculiX peer's finest run of the variant.
    pub err_vs_peer_ref: Option<f64>,
    /// CPUs used by other processes during the solve (machine load).
    pub load_solve: Option<f64>,
    /// CPUs used by other processes during the run.
    pub load_run: Option<f64>,
    /// "ok" or "failed: ..." (first line of the error).
    pub status: String,
    /// Free notes.
    pub note: String,
    /// axijoint: `axijoint solve` wall time with the mesh read from a warm
    /// cache (the fastest of `warm_solves`) (s); calculix: ccx alone.
    #[serde(default)]
    pub solve_warm_wall_s: Option<f64>,
    /// CPU time of the same run (s).
    #[serde(default)]
    pub solve_warm_cpu_s: Option<f64>,
    /// axijoint: the grading `refine` of geo/pile_footing.geo (size /
    /// element size along the pile side; 2 where the CSV has none).
    #[serde(default)]
    pub refine: Option<f64>,
}

impl Row {
    /// True when the run succeeded.
    pub fn ok(&self) -> bool {
        self.status == "ok"
    }

    /// The family on the chart: "variant method" or "variant calculix".
    pub fn family(&self) -> String {
        if self.tool == "calculix" {
            "CalculiX 3D".to_owned()
        } else if self.method == "-" {
            "linear".to_owned()
        } else {
            self.method.clone()
        }
    }
}

/// Writes the rows to `path` atomically (a temporary file beside it, renamed).
pub fn write_csv(path: &Path, rows: &[Row]) -> Result<()> {
    crate::csv_io::write_rows(path, rows)
}

/// Reads rows written by [`write_csv`].
pub fn read_csv(path: &Path) -> Result<Vec<Row>> {
    crate::csv_io::read_rows(path)
}

/// Writes the per-run scene of `variant` with `method` and `epsilon` into
/// `dir` and returns its path.
pub fn write_scene(variant: &Variant, method: &str, epsilon: f64, dir: &Path) -> Result<PathBuf> {
    let text = std::fs::read_to_string(&variant.scene)
        .with_context(|| format!("cannot read {}", variant.scene.display()))?;
    let mut scene: serde_json::Value =
        serde_json::from_str(&text).with_context(|| format!("{}: not JSON", variant.scene.display()))?;
    let base = variant.scene.parent().unwrap_or(Path::new("."));
    let mesh_file = scene["mesh"]["file"]
        .as_str()
        .with_context(|| format!("{}: no mesh.file", variant.scene.display()))?;
    let abs = std::path::absolute(base.join(mesh_file))?;
    scene["mesh"]["file"] = abs.to_string_lossy().into_owned().into();
    if let Some(obj) = scene.as_object_mut() {
        obj.remove("sections");
    }
    scene["solver"]["method"] = method.into();
    scene["solver"]["epsilon"] = epsilon.into();
    std::fs::create_dir_all(dir)?;
    let path = dir.join(format!("{}_{method}_eps{epsilon:e}.json", variant.name));
    std::fs::write(&path, serde_json::to_string_pretty(&scene)?)?;
    Ok(path)
}

/// Busy CPU seconds of the whole machine so far (/proc/stat), if readable.
pub(crate) fn machine_busy_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/stat").ok()?;
    let line = stat.lines().next()?;
    let v: Vec<f64> = line
        .split_whitespace()
        .skip(1)
        .filter_map(|x| x.parse().ok())
        .collect();
    if v.len() < 5 {
        return None;
    }
    // user nice system idle iowait irq softirq steal ...: busy = all - idle - iowait
    // (guest time is already inside user).
    let total: f64 = v.iter().take(8).sum();
    // SAFETY: sysconf has no preconditions.
    let hz = unsafe { libc::sysconf(libc::_SC_CLK_TCK) } as f64;
    Some((total - v[3] - v[4]) / if hz > 0.0 { hz } else { 100.0 })
}

/// A measured child run with the CPUs other processes used meanwhile.
fn measured_with_load(cmd: &mut Command) -> Result<(Measured, Option<f64>)> {
    let before = machine_busy_seconds();
    let m = run_measured(cmd)?;
    let load = match (before, machine_busy_seconds()) {
        (Some(a), Some(b)) if m.wall_seconds > 0.0 => {
            Some(((b - a - m.cpu_seconds) / m.wall_seconds).max(0.0))
        }
        _ => None,
    };
    Ok((m, load))
}

const MIB: f64 = 1024.0 * 1024.0;

/// What `solution.json` says about a run.
#[derive(Clone, Debug, Default)]
struct SolutionInfo {
    dof_per_harmonic: Option<usize>,
    iterations: Option<usize>,
    solves: Option<usize>,
    sections: Option<usize>,
}

fn solution_info(dir: &Path) -> Result<SolutionInfo> {
    let path = dir.join("solution.json");
    let text = std::fs::read_to_string(&path).with_context(|| format!("cannot read {}", path.display()))?;
    let header: SolutionHeader =
        serde_json::from_str(&text).with_context(|| format!("cannot read {}", path.display()))?;
    let record = header.record.unwrap_or_default();
    Ok(SolutionInfo {
        dof_per_harmonic: Some(header.dofs_per_harmonic),
        iterations: record.iterations,
        solves: record
            .history
            .as_ref()
            .map(|h| h.iter().map(|it| it.solves as usize).sum::<usize>()),
        sections: record.sections_deg.as_ref().map(Vec::len),
    })
}

/// One axijoint configuration to run.
#[derive(Clone, Debug)]
pub struct Job {
    /// Variant.
    pub variant: Variant,
    /// Method (ignored by linear scenes).
    pub method: String,
    /// Mesh size.
    pub size: f64,
    /// Grading towards the pile side.
    pub refine: f64,
    /// Highest harmonic.
    pub m: usize,
    /// Tolerance.
    pub epsilon: f64,
    /// "sweep", "linear" or "reference".
    pub role: String,
    /// Also measure `axijoint solve` (the reference only runs `axijoint run`).
    pub measure_solve: bool,
}

impl Job {
    /// A file-name-safe label.
    pub fn label(&self) -> String {
        format!(
            "{}_{}_{}_s{}_r{}_M{}_eps{:e}",
            self.variant.name,
            self.role,
            if self.variant.linear { "-" } else { &self.method },
            self.size,
            self.refine,
            self.m,
            self.epsilon
        )
    }
}

/// The axijoint jobs of a configuration, cheapest first within each
/// variant; the nonlinear references come last. Every size runs with every
/// grading, except that with several gradings a nonlinear variant runs its
/// finest size at the largest grading only as its reference.
pub fn plan(cfg: &Config) -> Vec<Job> {
    let mut sizes = cfg.sizes.clone();
    sizes.sort_by(|a, b| b.total_cmp(a));
    let mut refines = cfg.refines.clone();
    refines.sort_by(f64::total_cmp);
    let mut ms = cfg.harmonics.clone();
    ms.sort_unstable();
    let meshes: Vec<(f64, f64)> = sizes
        .iter()
        .flat_map(|&s| refines.iter().map(move |&r| (s, r)))
        .collect();
    let mut jobs = Vec::new();
    let mut refs = Vec::new();
    for v in &cfg.variants {
        if v.linear {
            for &(size, refine) in &meshes {
                jobs.push(Job {
                    variant: v.clone(),
                    // Irrelevant to a linear scene; any valid method.
                    method: "anderson".into(),
                    size,
                    refine,
                    m: cfg.linear_harmonics,
                    epsilon: cfg.epsilon,
                    role: "linear".into(),
                    measure_solve: true,
                });
            }
            continue;
        }
        // The reference's mesh (finest size, largest grading) only for the
        // reference when there are several gradings (it is the costliest by far).
        let is_ref_mesh = |size: f64, refine: f64| {
            refines.len() > 1 && Some(&size) == sizes.last() && Some(&refine) == refines.last()
        };
        for &(size, refine) in meshes.iter().filter(|&&(s, r)| !is_ref_mesh(s, r)) {
            for &m in &ms {
                for method in &cfg.methods {
                    jobs.push(Job {
                        variant: v.clone(),
                        method: method.clone(),
                        size,
                        refine,
                        m,
                        epsilon: cfg.epsilon,
                        role: "sweep".into(),
                        measure_solve: true,
                    });
                }
            }
        }
        if let (Some(&size), Some(&refine), Some(&m)) = (sizes.last(), refines.last(), ms.last()) {
            refs.push(Job {
                variant: v.clone(),
                method: cfg.ref_method.clone(),
                size,
                refine,
                m,
                epsilon: cfg.ref_epsilon,
                role: "reference".into(),
                measure_solve: false,
            });
        }
    }
    jobs.extend(refs);
    jobs
}

/// A finished run: its row and, when it succeeded, its profiles.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The CSV row (errors still empty).
    pub row: Row,
    /// The four Scene P profiles.
    pub profiles: Option<Vec<Profile>>,
}

/// Runs one axijoint job: `solve` (measured), then `run` (measured), and
/// reads the profiles of the run. A failure becomes a failed row.
pub fn run_job(cfg: &Config, job: &Job) -> Outcome {
    let mut row = Row {
        tool: "axijoint".into(),
        variant: job.variant.name.clone(),
        method: if job.variant.linear {
            "-".into()
        } else {
            job.method.clone()
        },
        role: job.role.clone(),
        size: job.size,
        refine: Some(job.refine),
        m: Some(job.m),
        epsilon: Some(job.epsilon),
        status: "ok".into(),
        ..Row::default()
    };
    if job.variant.linear {
        row.note = "linear scene: harmonics above the loaded one are zero, the method is irrelevant: one run per size".into();
    }
    match try_job(cfg, job, &mut row) {
        Ok(profiles) => Outcome {
            row,
            profiles: Some(profiles),
        },
        Err(e) => {
            let msg = format!("{e:#}");
            eprintln!("   FAILED: {msg}");
            row.status = format!("failed: {}", failure_line(&msg));
            Outcome { row, profiles: None }
        }
    }
}

/// The line of an error message that says what went wrong: the child's
/// last `error:` line if there is one, else the first line.
pub fn failure_line(msg: &str) -> String {
    let line = msg
        .lines()
        .rev()
        .find_map(|l| l.trim_start().strip_prefix("error:"))
        .unwrap_or_else(|| msg.lines().next().unwrap_or(""));
    line.trim().to_owned()
}

/// `axijoint SUB`; `cached`: with the mesh cache WORK/mesh-cache, else
/// without any (gmsh meshes every time).
fn axijoint_cmd(cfg: &Config, sub: &str, scene: &Path, out: &Path, job: &Job, cached: bool) -> Command {
    let mut c = Command::new(&cfg.axijoint);
    c.arg(sub)
        .arg(scene)
        .arg("-o")
        .arg(out)
        .arg("-q")
        .arg("--harmonics")
        .arg(job.m.to_string())
        .arg("--set")
        .arg(format!("size={}", job.size))
        .arg("--set")
        .arg(format!("refine={}", job.refine))
        .env("RUST_BACKTRACE", "0");
    if cached {
        c.env("AXIJOINT_CACHE", cfg.work_dir.join("mesh-cache"));
    } else {
        c.arg("--no-cache");
    }
    c
}

fn try_job(cfg: &Config, job: &Job, row: &mut Row) -> Result<Vec<Profile>> {
    let scene = write_scene(
        &job.variant,
        &job.method,
        job.epsilon,
        &cfg.work_dir.join("scenes"),
    )?;
    let base = cfg.work_dir.join("runs").join(job.label());
    if base.exists() {
        std::fs::remove_dir_all(&base).with_context(|| format!("cannot clear {}", base.display()))?;
    }
    std::fs::create_dir_all(&base)?;
    let (solve_dir, run_dir) = (base.join("solve"), base.join("run"));
    let mut info = None;
    if job.measure_solve {
        let (m, load) = measured_with_load(&mut axijoint_cmd(cfg, "solve", &scene, &solve_dir, job, false))?;
        row.solve_wall_s = Some(m.wall_seconds);
        row.solve_cpu_s = Some(m.cpu_seconds);
        row.solve_peak_rss_mib = Some(m.peak_rss_bytes as f64 / MIB);
        row.load_solve = load;
        info = Some(solution_info(&solve_dir)?);
        if cfg.warm_solves > 0 {
            // The first fills the cache, untimed.
            run_measured(&mut axijoint_cmd(cfg, "solve", &scene, &solve_dir, job, true))?;
            for _ in 0..cfg.warm_solves {
                let m = run_measured(&mut axijoint_cmd(cfg, "solve", &scene, &solve_dir, job, true))?;
                if row.solve_warm_wall_s.is_none_or(|w| m.wall_seconds < w) {
                    row.solve_warm_wall_s = Some(m.wall_seconds);
                    row.solve_warm_cpu_s = Some(m.cpu_seconds);
                }
            }
        }
        if !cfg.keep {
            let _ = std::fs::remove_dir_all(&solve_dir);
        }
    }
    let (m, load) = measured_with_load(&mut axijoint_cmd(cfg, "run", &scene, &run_dir, job, false))?;
    row.run_wall_s = Some(m.wall_seconds);
    row.run_cpu_s = Some(m.cpu_seconds);
    row.run_peak_rss_mib = Some(m.peak_rss_bytes as f64 / MIB);
    row.load_run = load;
    let info = match info {
        Some(i) => i,
        None => solution_info(&run_dir)?,
    };
    row.dof_per_harmonic = info.dof_per_harmonic;
    row.iterations = info.iterations;
    row.solves = info.solves;
    row.sections = if job.variant.linear { None } else { info.sections };
    let profiles = read_scene_p_profiles(&run_dir)?;
    // Keep the cut CSVs (small), drop the rest unless asked to keep it.
    let kept = base.join("cuts");
    std::fs::create_dir_all(&kept)?;
    for entry in std::fs::read_dir(&run_dir)? {
        let p = entry?.path();
        let name = p
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        if (name.starts_with("cut_") && name.ends_with(".csv")) || name == "summary.json" {
            std::fs::copy(&p, kept.join(&name))?;
        }
    }
    if !cfg.keep {
        let _ = std::fs::remove_dir_all(&run_dir);
    }
    Ok(profiles)
}

/// Runs the CalculiX peer of `variant` at `size`; a failure becomes a failed row.
pub fn run_peer(cfg: &Config, variant: &Variant, pv: PeerVariant, size: f64) -> Outcome {
    let mut row = Row {
        tool: "calculix".into(),
        variant: variant.name.clone(),
        method: "ccx".into(),
        role: "peer".into(),
        size,
        status: "ok".into(),
        note: "solve = gmsh mesh + ccx (CPU: ccx CPU + mesh wall); run = the whole peer run".into(),
        ..Row::default()
    };
    let opts = PeerOptions {
        size,
        work_dir: cfg
            .work_dir
            .join("peer")
            .join(format!("{}_s{size}", variant.name)),
        ccx: cfg.ccx.clone(),
        gmsh: cfg.gmsh.clone(),
    };
    let before = machine_busy_seconds();
    match peer::run(pv, &opts) {
        Ok(p) => {
            row.dof_3d = Some(p.dofs);
            row.iterations = Some(p.increments);
            row.solve_wall_s = Some(p.cost.mesh_seconds + p.cost.ccx_wall_seconds);
            row.solve_cpu_s = Some(p.cost.ccx_cpu_seconds + p.cost.mesh_seconds);
            row.solve_peak_rss_mib = Some(p.cost.ccx_peak_rss_bytes as f64 / MIB);
            row.solve_warm_wall_s = Some(p.cost.ccx_wall_seconds);
            row.solve_warm_cpu_s = Some(p.cost.ccx_cpu_seconds);
            row.run_wall_s = Some(p.cost.total_wall_seconds);
            if let (Some(a), Some(b)) = (before, machine_busy_seconds()) {
                if p.cost.total_wall_seconds > 0.0 {
                    let own = p.cost.ccx_cpu_seconds + p.cost.mesh_seconds;
                    row.load_run = Some(((b - a - own) / p.cost.total_wall_seconds).max(0.0));
                }
            }
            row.note = format!("{}; {} nodes, {} elements", row.note, p.nodes, p.elements);
            Outcome {
                row,
                profiles: Some(p.profiles),
            }
        }
        Err(e) => {
            let msg = format!("{e:#}");
            eprintln!("   FAILED: {msg}");
            row.status = format!("failed: {}", failure_line(&msg));
            Outcome { row, profiles: None }
        }
    }
}

/// Fills `err_vs_axijoint_ref` and `err_vs_peer_ref` of every successful
/// outcome and marks the references. The axijoint reference of a variant
/// is its "reference" run, else (a linear variant, or a failed reference)
/// its successful run of smallest size, then largest grading, then largest
/// M, then smallest epsilon; the peer's is its run of smallest size.
pub fn compute_errors(outcomes: &mut [Outcome]) {
    let refine = |r: &Row| r.refine.unwrap_or(DEFAULT_REFINE);
    let mut variants: Vec<String> = outcomes.iter().map(|o| o.row.variant.clone()).collect();
    variants.dedup();
    variants.sort();
    variants.dedup();
    for v in &variants {
        let pick = |tool: &str| -> Option<usize> {
            outcomes
                .iter()
                .enumerate()
                .filter(|(_, o)| o.row.variant == *v && o.row.tool == tool && o.profiles.is_some())
                .min_by(|(_, a), (_, b)| {
                    let (a, b) = (&a.row, &b.row);
                    (b.role == "reference")
                        .cmp(&(a.role == "reference"))
                        .then(a.size.total_cmp(&b.size))
                        .then(refine(b).total_cmp(&refine(a)))
                        .then(b.m.cmp(&a.m))
                        .then(a.epsilon.unwrap_or(1.0).total_cmp(&b.epsilon.unwrap_or(1.0)))
                })
                .map(|(i, _)| i)
        };
        let ax_ref = pick("axijoint");
        let peer_ref = pick("calculix");
        for (tool_ref, is_ax) in [(ax_ref, true), (peer_ref, false)] {
            let Some(ri) = tool_ref else { continue };
            outcomes[ri].row.is_reference = true;
            let reference = outcomes[ri].profiles.clone().unwrap_or_default();
            for o in outcomes.iter_mut().filter(|o| o.row.variant == *v) {
                let Some(p) = &o.profiles else { continue };
                match relative_error(p, &reference) {
                    Ok(e) if is_ax => o.row.err_vs_axijoint_ref = Some(e),
                    Ok(e) => o.row.err_vs_peer_ref = Some(e),
                    Err(err) => {
                        let what = if is_ax { "axijoint" } else { "peer" };
                        o.row.note = format!("{} [no error vs {what} reference: {err:#}]", o.row.note);
                    }
                }
            }
        }
    }
}
