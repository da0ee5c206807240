//! `axijoint report`: every output of a saved solution, without solving.

use anyhow::Result;
use axijoint_report::write_report;
use axijoint_solver::results::{read_joint_field, read_solution, SOLVED_MESH};
use clap::Args;
use serde_json::json;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct ReportArgs {
    /// A solution folder written by `axijoint solve` or `axijoint run`.
    pub dir: PathBuf,
    /// Other solution folders whose convergence goes on the same plot.
    #[arg(long, value_name = "DIR", num_args = 1..)]
    pub compare: Vec<PathBuf>,
}

/// Writes the outputs and the index `summary.json`; prints the file list.
/// The comparison run `DIR/without_joints`, if there, gives the dashed
/// curves; `compare` adds other runs' convergence.
pub fn report(dir: &Path, compare: &[PathBuf]) -> Result<()> {
    let saved = read_solution(dir)?;
    let companion_dir = dir.join(crate::solve_cmd::WITHOUT_JOINTS);
    let companion = if companion_dir.join("solution.json").is_file() {
        Some(read_solution(&companion_dir)?)
    } else {
        None
    };
    let mut runs = Vec::new();
    for other in compare {
        let o = read_solution(other)?;
        if let Some(h) = axijoint_report::history(&o)? {
            runs.push((o.header.scene.title.clone(), h));
        }
    }
    let written = write_report(dir, &saved, companion.as_ref(), &runs)?;
    let h = &saved.header;
    let joints = read_joint_field(dir)?;
    let mut joint_summary = serde_json::Map::new();
    for j in &h.mesh.joints {
        if let Some(f) = &joints {
            let (open, slip, stick) = f.state_areas(j);
            joint_summary.insert(
                j.clone(),
                json!({"open_area": open, "slip_area": slip, "stick_area": stick}),
            );
        }
    }
    let mut files: Vec<String> = ["solution.json", "displacement.f64", "mesh.msh"]
        .map(String::from)
        .to_vec();
    if dir.join(SOLVED_MESH).is_file() {
        files.push(SOLVED_MESH.into());
    }
    if joints.is_some() {
        files.push("joints.json".into());
    }
    files.extend(written.files.iter().map(|p| p.display().to_string()));
    files.push("summary.json".into());
    let summary = json!({
        "scene": h.scene_file,
        "title": h.scene.title,
        "units": h.scene.units,
        "harmonics": h.harmonics,
        "nodes": h.mesh.nodes,
        "dofs_per_harmonic": h.dofs_per_harmonic,
        "iterations": h.extra.get("iterations"),
        "loaded_faces": h.loaded_faces,
        "max_displacement": h.max_displacement,
        "joints": joint_summary,
        "harmonic_check": h.extra.get("harmonic_check"),
        "auto_harmonics": h.extra.get("auto_harmonics"),
        "converged": h.extra.get("converged").cloned().unwrap_or(json!(true)),
        "error": h.extra.get("error"),
        "loading": h.extra.get("loading"),
        "load_factor": h.extra.get("load_factor"),
        "limit_load_factor": h.extra.get("limit_load_factor"),
        "complete": h.extra.get("complete").cloned().unwrap_or(json!(true)),
        "note": h.extra.get("note"),
        "load_steps": h.extra.get("load_path").map(|p| &p["steps"]),
        "files": files,
    });
    let path = dir.join("summary.json");
    let tmp = dir.join(".summary.json.partial");
    std::fs::write(&tmp, serde_json::to_string_pretty(&summary)?)?;
    std::fs::rename(&tmp, &path)?;
    println!(
        "  report: {} files in {} (index: summary.json)",
        files.len(),
        dir.display()
    );
    Ok(())
}

pub fn run(args: &ReportArgs) -> Result<()> {
    report(&args.dir, &args.compare)
}
