//! `axijoint report`: every output of a saved solution, without solving.

use anyhow::Result;
use axijoint_report::write_report;
use axijoint_solver::results::{read_joint_field, read_solution, SOLVED_MESH};
use clap::Args;
use serde_json::json;
use std::path::{Component, Path, PathBuf};

#[derive(Args)]
pub struct ReportArgs {
    /// A solution folder written by `axijoint solve` or `axijoint run`.
    pub dir: PathBuf,
    /// Other solution folders whose convergence goes on the same plot
    /// (each run labelled by its folder name, or as much of its path as
    /// tells it from the others).
    #[arg(long, value_name = "DIR", num_args = 1..)]
    pub compare: Vec<PathBuf>,
}

/// Writes the outputs and the index `summary.json`; prints the file list.
/// The comparison run `DIR/without_joints`, if there, gives the dashed
/// curves; `compare` adds other runs' convergence, every run then labelled
/// by [`run_labels`].
pub fn report(dir: &Path, compare: &[PathBuf]) -> Result<()> {
    let files = write_outputs(dir, compare)?;
    print_estimates(dir);
    crate::say!(
        "  report: {} files in {} (index: summary.json)",
        files.len(),
        dir.display()
    );
    Ok(())
}

/// [`report`] without printing: returns the files of the folder, as in
/// `summary.json`.
pub fn write_outputs(dir: &Path, compare: &[PathBuf]) -> Result<Vec<String>> {
    let saved = read_solution(dir)?;
    let companion_dir = dir.join(crate::solve_cmd::WITHOUT_JOINTS);
    let companion = if companion_dir.join("solution.json").is_file() {
        Some(read_solution(&companion_dir)?)
    } else {
        None
    };
    let mut runs = Vec::new();
    let mut dirs = vec![dir.to_path_buf()];
    for other in compare {
        let o = read_solution(other)?;
        if let Some(h) = axijoint_report::history(&o)? {
            runs.push((String::new(), h));
            dirs.push(other.clone());
        }
    }
    let labels = run_labels(&dirs);
    for (run, label) in runs.iter_mut().zip(&labels[1..]) {
        run.0 = label.clone();
    }
    let label = (!runs.is_empty()).then(|| labels[0].as_str());
    let written = write_report(dir, &saved, companion.as_ref(), label, &runs)?;
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
    if let Some(i) = &h.initial {
        files.push(i.displacement.file.clone());
    }
    files.extend(written.files.iter().map(|p| p.display().to_string()));
    for f in ["adapt.csv", "adapt_size.pos"] {
        if h.extra.get("adapt").is_some() && dir.join(f).is_file() {
            files.push(f.into());
        }
    }
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
        "initial": h.initial,
        "estimated_error": estimated_error(&written.estimated_error),
        "estimated_energy_error": written.energy_error,
        "adapt": h.extra.get("adapt"),
        "files": files,
    });
    let path = dir.join("summary.json");
    axijoint_mesh::atomic::write_bytes(&path, serde_json::to_string_pretty(&summary)?.as_bytes())?;
    Ok(files)
}

/// Above this estimated error of a profile the console warns.
pub const ESTIMATE_WARNING: f64 = 0.05;

/// `cut name -> theta as in file names -> fraction`.
pub fn estimated_error(rows: &[(String, f64, f64)]) -> serde_json::Value {
    let mut map = serde_json::Map::new();
    for (cut, theta, e) in rows {
        let entry = map.entry(cut.clone()).or_insert_with(|| json!({}));
        entry[axijoint_report::fmt_angle(*theta)] = json!(e);
    }
    serde_json::Value::Object(map)
}

/// The estimated errors of `dir/summary.json` on the console
/// (docs/accuracy.md), a warning for each profile above
/// [`ESTIMATE_WARNING`].
fn print_estimates(dir: &Path) {
    let Some(summary) = std::fs::read(dir.join("summary.json"))
        .ok()
        .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
    else {
        return;
    };
    let energy = summary["estimated_energy_error"].as_f64().unwrap_or(f64::NAN);
    let mut rows = Vec::new();
    for (cut, per_theta) in summary["estimated_error"].as_object().into_iter().flatten() {
        for (t, e) in per_theta.as_object().into_iter().flatten() {
            rows.push((cut.clone(), t.clone(), e.as_f64().unwrap_or(f64::NAN)));
        }
    }
    let parts: Vec<String> = rows
        .iter()
        .map(|(cut, t, e)| format!("{cut} theta {t}: {:.2} %", 100.0 * e))
        .collect();
    crate::say!(
        "  estimated error: {}{:.2} % in the energy norm",
        if parts.is_empty() {
            String::new()
        } else {
            format!("{} (of each profile's max |stress|); ", parts.join(", "))
        },
        100.0 * energy
    );
    for (cut, t, e) in rows.iter().filter(|r| r.2 > ESTIMATE_WARNING || r.2.is_nan()) {
        crate::say!(
            "  WARNING: cut {cut} at theta {t} deg: estimated error {:.1} % of its max |stress| (above {} %): refine the mesh there or set mesh.adapt (docs/accuracy.md)",
            100.0 * e,
            100.0 * ESTIMATE_WARNING
        );
    }
}

pub fn run(args: &ReportArgs) -> Result<()> {
    report(&args.dir, &args.compare)
}

/// Legend labels that tell folders apart: each folder's name, or as many
/// of the last components of its absolute path as make it differ from the
/// others (the whole path, from `/`, when nothing less does). A folder
/// given twice gets ` (2)`, ` (3)` after its label.
pub fn run_labels(dirs: &[PathBuf]) -> Vec<String> {
    let parts: Vec<Vec<String>> = dirs
        .iter()
        .map(|d| {
            let abs = d
                .canonicalize()
                .or_else(|_| std::path::absolute(d))
                .unwrap_or_else(|_| d.clone());
            abs.components()
                .filter_map(|c| match c {
                    Component::Normal(s) => Some(s.to_string_lossy().into_owned()),
                    _ => None,
                })
                .collect()
        })
        .collect();
    let label = |p: &[String], depth: usize| {
        let tail = p[p.len().saturating_sub(depth)..].join("/");
        if depth >= p.len() {
            format!("/{tail}")
        } else {
            tail
        }
    };
    let mut depth = vec![1; dirs.len()];
    let base = loop {
        let labels: Vec<String> = parts.iter().zip(&depth).map(|(p, &d)| label(p, d)).collect();
        let mut deeper = false;
        for (i, d) in depth.iter_mut().enumerate() {
            let shared = (0..labels.len()).any(|j| parts[j] != parts[i] && labels[j] == labels[i]);
            if shared && *d < parts[i].len() {
                *d += 1;
                deeper = true;
            }
        }
        if !deeper {
            break labels;
        }
    };
    let mut labels = base.clone();
    for i in 1..labels.len() {
        let same = base[..i].iter().filter(|l| **l == base[i]).count();
        if same > 0 {
            labels[i] = format!("{} ({})", base[i], same + 1);
        }
    }
    labels
}

#[cfg(test)]
mod tests {
    use super::run_labels;

    #[test]
    fn labels_tell_folders_apart() {
        let tmp = tempfile::tempdir().unwrap();
        let root = tmp.path().canonicalize().unwrap();
        for d in ["a/run", "b/run", "x/p", "x/q", "deep/b/run"] {
            std::fs::create_dir_all(root.join(d)).unwrap();
        }
        let l = |ds: &[&str]| run_labels(&ds.iter().map(|d| root.join(d)).collect::<Vec<_>>());
        assert_eq!(l(&["x/p", "x/q"]), ["p", "q"]);
        assert_eq!(l(&["a/run", "b/run"]), ["a/run", "b/run"]);
        assert_eq!(l(&["a/run", "b/run", "x/p"]), ["a/run", "b/run", "p"]);
        let tmp_name = root.file_name().unwrap().to_string_lossy();
        assert_eq!(
            l(&["b/run", "deep/b/run"]),
            [format!("{tmp_name}/b/run"), "deep/b/run".to_owned()]
        );
        // One folder twice, the second time by another spelling of its path.
        assert_eq!(l(&["x/p", "a/../x/p"]), ["p", "p (2)"]);
    }
}
