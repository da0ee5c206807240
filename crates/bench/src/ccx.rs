//! What the two CalculiX peers ([`crate::peer3d`], [`crate::plastic_peer`])
//! share: meshing with gmsh, running `ccx` and reading its log and `.sta`
//! file; the mesh reading ([`msh`]) and deck writing ([`deck`]) pieces.

pub mod deck;
pub mod msh;

use crate::measure::{run_measured, Measured};
use anyhow::{bail, Context, Result};
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// What one peer run cost.
#[derive(Clone, Debug)]
pub struct PeerCost {
    /// gmsh wall time (s).
    pub mesh_seconds: f64,
    /// ccx wall time (s).
    pub ccx_wall_seconds: f64,
    /// ccx CPU time (user + system) (s).
    pub ccx_cpu_seconds: f64,
    /// ccx peak resident memory (bytes).
    pub ccx_peak_rss_bytes: u64,
    /// Wall time of the whole run (mesh, deck, ccx, reading) (s).
    pub total_wall_seconds: f64,
}

impl PeerCost {
    /// The cost of a run that started at `start`, meshed in `mesh_seconds`
    /// and ran ccx as `ccx` measured.
    pub fn new(mesh_seconds: f64, ccx: &Measured, start: Instant) -> Self {
        PeerCost {
            mesh_seconds,
            ccx_wall_seconds: ccx.wall_seconds,
            ccx_cpu_seconds: ccx.cpu_seconds,
            ccx_peak_rss_bytes: ccx.peak_rss_bytes,
            total_wall_seconds: start.elapsed().as_secs_f64(),
        }
    }
}

/// Checks a peer's element size (`who` names the peer in the error) and
/// creates its work directory.
pub fn prepare(who: &str, size: f64, work_dir: &Path) -> Result<()> {
    if !(size > 0.0 && size.is_finite()) {
        bail!("{who}: size must be positive, got {size}");
    }
    std::fs::create_dir_all(work_dir)
        .with_context(|| format!("creating work directory {}", work_dir.display()))
}

/// Meshes `geo` in 3D with gmsh into `msh` (MSH 4.1), each of `params` set
/// with `-setnumber`; returns the wall time. Any `Error` line gmsh prints,
/// or a missing `msh`, is an error.
pub fn run_gmsh(gmsh: &Path, geo: &Path, params: &[(&str, f64)], msh: &Path) -> Result<f64> {
    let mut cmd = Command::new(gmsh);
    cmd.arg(geo).args(["-3", "-format", "msh41", "-nopopup"]);
    for (name, value) in params {
        cmd.args(["-setnumber", name]).arg(format!("{value}"));
    }
    let shown: Vec<String> = params.iter().map(|(n, v)| format!("{n} {v}")).collect();
    let m = run_measured(cmd.arg("-o").arg(msh))
        .with_context(|| format!("gmsh meshing {} ({})", geo.display(), shown.join(", ")))?;
    let errors: Vec<&str> = m
        .stdout
        .lines()
        .chain(m.stderr.lines())
        .filter(|l| l.contains("Error"))
        .collect();
    if !errors.is_empty() || !msh.exists() {
        bail!("gmsh meshing {} failed:\n{}", geo.display(), errors.join("\n"));
    }
    Ok(m.wall_seconds)
}

/// Runs `ccx -i job` in `dir` with OMP_NUM_THREADS =
/// CCX_NPROC_EQUATION_SOLVER = 2, its output to `dir/job.log`; returns the
/// measurement (an error if ccx could not run or failed) and the log's text.
pub fn run_ccx(ccx: &Path, job: &str, dir: &Path) -> (Result<Measured>, String) {
    // `exec` keeps the pid, so wait4 measures ccx itself; its output goes
    // to the log (ccx reports errors on stdout).
    let measured = run_measured(
        Command::new("sh")
            .args(["-c", "exec \"$0\" -i \"$1\" > \"$1.log\" 2>&1"])
            .arg(ccx)
            .arg(job)
            .current_dir(dir)
            .env("OMP_NUM_THREADS", "2")
            .env("CCX_NPROC_EQUATION_SOLVER", "2"),
    );
    let log = std::fs::read_to_string(dir.join(format!("{job}.log"))).unwrap_or_default();
    (measured, log)
}

/// The last `n` lines of `text`.
pub fn tail(text: &str, n: usize) -> String {
    let t: Vec<&str> = text.lines().rev().take(n).collect();
    t.into_iter().rev().collect::<Vec<_>>().join("\n")
}

/// The number of equations a ccx log reports (the line after "number of
/// equations").
pub fn equations(log: &str) -> Option<usize> {
    log.lines()
        .skip_while(|l| !l.contains("number of equations"))
        .nth(1)
        .and_then(|l| l.trim().parse::<usize>().ok())
}

/// Completed increments and total iterations from `.sta` text (each line of
/// a completed increment starts with four integers: step, increment,
/// attempts, iterations).
pub fn read_sta(text: &str) -> (usize, usize) {
    let mut inc = 0;
    let mut its = 0;
    for line in text.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        if f.len() >= 4 && f[..4].iter().all(|x| x.parse::<usize>().is_ok()) {
            inc += 1;
            its += f[3].parse::<usize>().unwrap_or(0);
        }
    }
    (inc, its)
}
