//! The report of a solution folder: every output (CSV, plots, views) and
//! the index `summary.json`, with the estimated errors on the console.

use super::solve::WITHOUT_JOINTS;
use anyhow::Result;
use axijoint_report::write_report;
use axijoint_solver::iteration::LoadStep;
use axijoint_solver::results::{
    read_joint_field, read_solution, AdaptTable, AutoHarmonics, HarmonicCheck, InitialInfo,
    JointSpringsRecord, PerProfile, StepMeasure, PLASTIC_FIELD, SOLVED_MESH,
};
use axijoint_solver::scene::{Loading, Units};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

/// `summary.json`: the index of a solution folder (docs/outputs.md). Its
/// fields appear in the order of their names.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// The cycles of an adaptive run.
    pub adapt: Option<AdaptTable>,
    /// The automatic choice of M.
    pub auto_harmonics: Option<AutoHarmonics>,
    /// Whether the whole load was reached.
    pub complete: bool,
    /// Whether the run converged (false: a last iterate).
    pub converged: bool,
    /// Unknowns per harmonic.
    pub dofs_per_harmonic: usize,
    /// Why a run stopped.
    pub error: Option<String>,
    /// Estimated error in the energy norm (`null` for a folder without a
    /// report: the comparison without joints).
    pub estimated_energy_error: Option<f64>,
    /// Estimated error of each cut profile, relative to its max |stress|.
    pub estimated_error: PerProfile,
    /// The files of the folder.
    pub files: Vec<String>,
    /// The M/2 check.
    pub harmonic_check: Option<HarmonicCheck>,
    /// Harmonics 0..=M.
    pub harmonics: Vec<u32>,
    /// The initial phase.
    pub initial: Option<InitialInfo>,
    /// Iterations of a nonlinear run.
    pub iterations: Option<usize>,
    /// Each joint's springs as solved and their source (= `extra.joint_springs`).
    #[serde(default)]
    pub joint_springs: BTreeMap<String, JointSpringsRecord>,
    /// Each joint's areas by state.
    pub joints: BTreeMap<String, JointSummary>,
    /// The limit load factor of a stepped run that found no equilibrium.
    pub limit_load_factor: Option<f64>,
    /// The load factor reached by a stepped run.
    pub load_factor: Option<f64>,
    /// The converged steps of a stepped run.
    pub load_steps: Option<Vec<LoadStep<StepMeasure>>>,
    /// Face-average displacement of each loaded curve.
    pub loaded_faces: BTreeMap<String, [f64; 3]>,
    /// How the load was applied (nonlinear runs).
    pub loading: Option<Loading>,
    /// Largest displacement magnitude.
    pub max_displacement: f64,
    /// Nodes (joints inserted).
    pub nodes: usize,
    /// What the outputs are, when not the whole load's equilibrium.
    pub note: Option<String>,
    /// The scene file.
    pub scene: String,
    /// The scene's title.
    pub title: String,
    /// The scene's units.
    pub units: Units,
    /// Plausibility warnings (docs/outputs.md, "Warnings").
    pub warnings: Vec<String>,
    /// The key numbers of each member (`outputs.members`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub members: BTreeMap<String, axijoint_solver::members::MemberSummary>,
}

/// A joint's areas by state (length^2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointSummary {
    /// Open.
    pub open_area: f64,
    /// Slipping.
    pub slip_area: f64,
    /// Sticking.
    pub stick_area: f64,
}

/// Writes the outputs and the index `summary.json`; prints the file list.
/// The comparison run `DIR/without_joints`, if there, gives the dashed
/// curves; `compare` adds other runs' convergence, every run then labelled
/// by [`run_labels`].
pub fn report(dir: &Path, compare: &[PathBuf]) -> Result<()> {
    let summary = write_outputs(dir, compare)?;
    print_estimates(&summary);
    crate::say!(
        "  report: {} files in {} (index: summary.json)",
        summary.files.len(),
        dir.display()
    );
    Ok(())
}

/// The report of `dir` ([`report`]), printed only if `print`.
pub fn write(dir: &Path, print: bool) -> Result<()> {
    if print {
        report(dir, &[])
    } else {
        write_outputs(dir, &[]).map(|_| ())
    }
}

/// [`report`] without printing: returns `summary.json`.
pub fn write_outputs(dir: &Path, compare: &[PathBuf]) -> Result<Summary> {
    let saved = read_solution(dir)?;
    let companion_dir = dir.join(WITHOUT_JOINTS);
    let companion = if companion_dir.join("solution.json").is_file() {
        Some(read_solution(&companion_dir)?)
    } else {
        None
    };
    let mut runs = Vec::new();
    let mut dirs = vec![dir.to_path_buf()];
    for other in compare {
        let o = read_solution(other)?;
        if let Some(h) = axijoint_report::history(&o) {
            runs.push((String::new(), h.to_vec()));
            dirs.push(other.clone());
        }
    }
    let labels = run_labels(&dirs);
    for (run, label) in runs.iter_mut().zip(&labels[1..]) {
        run.0 = label.clone();
    }
    let label = (!runs.is_empty()).then(|| labels[0].as_str());
    let written = write_report(dir, &saved, companion.as_ref(), label, &runs)?;
    summarize(dir, &saved, Some(&written))
}

/// `summary.json` of the comparison without joints `dir` (no report of
/// its own: its solution files and its numbers).
pub fn write_comparison_summary(dir: &Path) -> Result<Summary> {
    let saved = read_solution(dir)?;
    summarize(dir, &saved, None)
}

/// Writes and returns `summary.json` of the solution `saved` in `dir` and
/// of its report `written` (`None`: no report).
fn summarize(
    dir: &Path,
    saved: &axijoint_solver::results::SavedSolution,
    written: Option<&axijoint_report::Written>,
) -> Result<Summary> {
    let h = &saved.header;
    let joints = read_joint_field(dir)?;
    let mut joint_summary = BTreeMap::new();
    for j in &h.mesh.joints {
        if let Some(f) = &joints {
            let (open_area, slip_area, stick_area) = f.state_areas(j);
            joint_summary.insert(
                j.clone(),
                JointSummary {
                    open_area,
                    slip_area,
                    stick_area,
                },
            );
        }
    }
    let record = h.record.clone().unwrap_or_default();
    let mut files: Vec<String> = ["solution.json", "displacement.f64", "mesh.msh"]
        .map(String::from)
        .to_vec();
    if dir.join(SOLVED_MESH).is_file() {
        files.push(SOLVED_MESH.into());
    }
    if joints.is_some() {
        files.push("joints.json".into());
    }
    if dir.join(PLASTIC_FIELD).is_file() {
        files.push(PLASTIC_FIELD.into());
    }
    if let Some(i) = &h.initial {
        files.push(i.displacement.file.clone());
    }
    files.extend(
        written
            .iter()
            .flat_map(|w| &w.files)
            .map(|p| p.display().to_string()),
    );
    for f in ["adapt.csv", "adapt_size.pos"] {
        if record.adapt.is_some() && dir.join(f).is_file() {
            files.push(f.into());
        }
    }
    files.push("summary.json".into());
    let summary = Summary {
        adapt: record.adapt.clone(),
        auto_harmonics: record.auto_harmonics.clone(),
        complete: record.complete(),
        converged: record.converged(),
        dofs_per_harmonic: h.dofs_per_harmonic,
        error: record.error.clone(),
        estimated_energy_error: written.map(|w| w.energy_error),
        estimated_error: estimated_error(written.map_or(&[], |w| &w.estimated_error)),
        files,
        harmonic_check: record.harmonic_check.clone().flatten(),
        harmonics: h.harmonics.clone(),
        initial: h.initial.clone(),
        iterations: record.iterations,
        joint_springs: record.joint_springs.clone(),
        joints: joint_summary,
        limit_load_factor: record.limit_load_factor,
        load_factor: record.load_factor,
        load_steps: record.load_path.as_ref().map(|p| p.steps.clone()),
        loaded_faces: h.loaded_faces.clone(),
        loading: record.loading,
        max_displacement: h.max_displacement,
        nodes: h.mesh.nodes,
        note: record.note.clone(),
        scene: h.scene_file.clone(),
        title: h.scene.title.clone(),
        units: h.scene.units.clone(),
        warnings: record.warnings.clone(),
        members: h.members.iter().map(|m| (m.body.clone(), m.summary())).collect(),
    };
    let path = dir.join("summary.json");
    axijoint_mesh::atomic::write_bytes(&path, serde_json::to_string_pretty(&summary)?.as_bytes())?;
    Ok(summary)
}

/// Above this estimated error of a profile the console warns.
pub const ESTIMATE_WARNING: f64 = 0.05;

/// `cut name -> theta as in file names -> fraction`.
pub fn estimated_error(rows: &[(String, f64, f64)]) -> PerProfile {
    let mut map = PerProfile::new();
    for (cut, theta, e) in rows {
        map.entry(cut.clone())
            .or_default()
            .insert(axijoint_report::fmt_angle(*theta), *e);
    }
    map
}

/// The estimated errors of `dir/summary.json` on the console
/// (docs/accuracy.md), a warning for each profile above
/// [`ESTIMATE_WARNING`].
fn print_estimates(summary: &Summary) {
    for line in estimate_lines(summary) {
        crate::say!("{line}");
    }
}

/// Profiles listed per cut on the console; beyond, the worst of them.
pub const LISTED: usize = 4;

/// The console lines of the estimated errors: per cut its profiles in
/// order of angle (the [`LISTED`] - 1 worst when it has more, with how
/// many are left out), the energy norm; then a warning per profile above
/// [`ESTIMATE_WARNING`] (one per cut when more than [`LISTED`] are; none
/// with plastic bodies, where the estimate is not the mesh's error).
pub fn estimate_lines(summary: &Summary) -> Vec<String> {
    let angle = |t: &str| t.replace('m', "-").parse::<f64>().unwrap_or(f64::NAN);
    let mut parts = Vec::new();
    let mut warnings = Vec::new();
    for (cut, per_theta) in &summary.estimated_error {
        let mut rows: Vec<(&str, f64)> = per_theta.iter().map(|(t, e)| (t.as_str(), *e)).collect();
        rows.sort_by(|a, b| angle(a.0).total_cmp(&angle(b.0)));
        let above: Vec<_> = rows
            .iter()
            .filter(|r| r.1 > ESTIMATE_WARNING || r.1.is_nan())
            .collect();
        let mut shown = rows.clone();
        let mut rest = String::new();
        if rows.len() > LISTED {
            let mut worst = rows.clone();
            worst.sort_by(|a, b| b.1.total_cmp(&a.1));
            let cut_at = worst[LISTED - 1].1;
            worst.truncate(LISTED - 1);
            shown.retain(|r| worst.iter().any(|w| w.0 == r.0));
            rest = format!(
                " and {} more up to {:.2} %",
                rows.len() - shown.len(),
                100.0 * cut_at
            );
        }
        let listed: Vec<String> = shown
            .iter()
            .map(|(t, e)| format!("{cut} theta {t}: {:.2} %", 100.0 * e))
            .collect();
        parts.push(format!("{}{rest}", listed.join(", ")));
        if above.len() > LISTED {
            let worst = above.iter().fold(above[0], |w, r| if r.1 > w.1 { r } else { w });
            warnings.push(format!(
                "  WARNING: cut {cut}: estimated error above {} % of the max |stress| at {} of {} angles (worst {:.1} % at theta {} deg): refine the mesh there or set mesh.adapt (docs/accuracy.md)",
                100.0 * ESTIMATE_WARNING,
                above.len(),
                rows.len(),
                100.0 * worst.1,
                worst.0
            ));
        } else {
            for (t, e) in above {
                warnings.push(format!(
                    "  WARNING: cut {cut} at theta {t} deg: estimated error {:.1} % of its max |stress| (above {} %): refine the mesh there or set mesh.adapt (docs/accuracy.md)",
                    100.0 * e,
                    100.0 * ESTIMATE_WARNING
                ));
            }
        }
    }
    // (The recovery is of the elastic stress of the displacements: where a
    // body yields it measures the plastic strain, not the mesh's error.)
    let plastic = summary.files.iter().any(|f| f == "plastic.json");
    let energy = summary.estimated_energy_error.map_or_else(
        || "no estimate".to_string(),
        |e| {
            format!(
                "{:.2} % in the energy norm{}",
                100.0 * e,
                if plastic {
                    " (of the elastic stress: where the soil yields it measures the plastic strain, not the mesh's error)"
                } else {
                    ""
                }
            )
        },
    );
    if plastic {
        // Not the mesh's error where the soil yields: no advice to refine.
        warnings.clear();
    }
    let mut lines = vec![format!(
        "  estimated error: {}{energy}",
        if parts.is_empty() {
            String::new()
        } else {
            format!("{} (of each profile's max |stress|); ", parts.join(", "))
        },
    )];
    lines.extend(warnings);
    lines
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
    use super::{estimate_lines, Summary};

    /// A summary with the estimates `rows` (cut, angle as in file names, error).
    fn summary(rows: &[(&str, &str, f64)]) -> Summary {
        let mut s: Summary = serde_json::from_str(
            r#"{"adapt": null, "auto_harmonics": null, "complete": true, "converged": true,
                "dofs_per_harmonic": 1, "error": null, "estimated_energy_error": 0.01,
                "estimated_error": {}, "files": [], "harmonic_check": null, "harmonics": [0],
                "initial": null, "iterations": null, "joints": {}, "limit_load_factor": null,
                "load_factor": null, "load_steps": null, "loaded_faces": {}, "loading": null,
                "max_displacement": 0.0, "nodes": 1, "note": null, "scene": "s.json",
                "title": "t", "units": {"length": "m", "force": "MN", "stress": "MPa"},
                "warnings": []}"#,
        )
        .unwrap();
        for (cut, t, e) in rows {
            s.estimated_error
                .entry(cut.to_string())
                .or_default()
                .insert(t.to_string(), *e);
        }
        s
    }

    #[test]
    fn estimates_are_listed_by_angle_and_shortened() {
        let two = estimate_lines(&summary(&[("a", "180", 0.006), ("a", "0", 0.016)]));
        assert_eq!(
            two,
            ["  estimated error: a theta 0: 1.60 %, a theta 180: 0.60 % (of each profile's max |stress|); 1.00 % in the energy norm"]
        );
        // 16 angles, named as strings would sort them (112.5 before 22.5).
        let angles = [
            0.0, 22.5, 45.0, 67.5, 90.0, 112.5, 135.0, 157.5, 180.0, 202.5, 225.0, 247.5, 270.0, 292.5,
            315.0, 337.5,
        ];
        let names: Vec<String> = angles.iter().map(|t: &f64| format!("{t}")).collect();
        let rows: Vec<(&str, &str, f64)> = names
            .iter()
            .zip(angles)
            .map(|(n, t)| ("b", n.as_str(), 0.01 + 0.1 * (t / 360.0)))
            .collect();
        let lines = estimate_lines(&summary(&rows));
        assert!(
            lines[0].contains(
                "b theta 292.5: 9.12 %, b theta 315: 9.75 %, b theta 337.5: 10.38 % and 13 more up to 8.50 %"
            ),
            "{lines:?}"
        );
        // 9 above 5 % (from 157.5 deg on): one warning for the cut, naming the worst.
        assert_eq!(lines.len(), 2, "{lines:?}");
        assert!(
            lines[1].contains("at 9 of 16 angles (worst 10.4 % at theta 337.5 deg)"),
            "{lines:?}"
        );
    }

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
