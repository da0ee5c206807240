//! `axijoint report`: every output of a saved solution, without solving.

use anyhow::Result;
use axijoint_report::write_report;
use axijoint_solver::results::{read_joint_field, read_solution};
use clap::Args;
use serde_json::json;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct ReportArgs {
    /// A solution folder written by `axijoint solve` or `axijoint run`.
    pub dir: PathBuf,
}

/// Writes the outputs and the index `summary.json`; prints the file list.
pub fn report(dir: &Path) -> Result<()> {
    let saved = read_solution(dir)?;
    let written = write_report(dir, &saved)?;
    let h = &saved.header;
    let joints = read_joint_field(dir)?;
    let mut joint_summary = serde_json::Map::new();
    for j in &h.mesh.joints {
        if let Some(f) = &joints {
            let (open, slip, stick) = f.state_areas(j);
            joint_summary.insert(j.clone(), json!({"open_area": open, "slip_area": slip, "stick_area": stick}));
        }
    }
    let mut files: Vec<String> = ["solution.json", "displacement.f64", "mesh.msh"].map(String::from).to_vec();
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
        "files": files,
    });
    let path = dir.join("summary.json");
    let tmp = dir.join(".summary.json.partial");
    std::fs::write(&tmp, serde_json::to_string_pretty(&summary)?)?;
    std::fs::rename(&tmp, &path)?;
    println!("  report: {} files in {} (index: summary.json)", files.len(), dir.display());
    Ok(())
}

pub fn run(args: &ReportArgs) -> Result<()> {
    report(&args.dir)
}
