//! A scene with `load_cases`: one model, one set of factors, one initial
//! phase; each case solved from the initial state into its own solution
//! folder `OUT/<case>`, and the index `OUT/cases.json`.

use super::console::print_summary;
use super::report::write;
use super::solve::{check_limit, solved_msh, write_run, write_stopped};
use super::Options;
use anyhow::{Context, Result};
use axijoint_solver::run::solve_cases;
use axijoint_solver::scene::Scene;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The index of a load-case folder.
pub const CASES_INDEX: &str = "cases.json";

/// `cases.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CasesIndex {
    /// `axijoint-cases`.
    pub format: String,
    /// The scene file.
    pub scene: String,
    /// The scene's title.
    pub title: String,
    /// Each case, in order.
    pub cases: Vec<CaseEntry>,
}

/// A case of [`CasesIndex`]: its folder and key results, or its error.
/// Fields appear in the order of their names.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseEntry {
    /// Whether the whole load was reached (solved cases).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub complete: Option<bool>,
    /// Whether the case was solved.
    pub converged: bool,
    /// Why it stopped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Its folder, inside the output folder.
    pub folder: String,
    /// The limit load factor (solved cases; `null` unless a limit).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limit_load_factor: Option<Option<f64>>,
    /// The load factor reached (solved cases; `null` unless stepped).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub load_factor: Option<Option<f64>>,
    /// Face-average displacement of each loaded curve (solved cases).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub loaded_faces: Option<BTreeMap<String, [f64; 3]>>,
    /// Largest displacement magnitude (solved cases).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_displacement: Option<f64>,
    /// The case's name.
    pub name: String,
}

/// Solves every case of `scene` (read from `path`) into `options.output`,
/// prints each summary, reports each case when `options.report`; fails
/// with the first case that did not reach its whole load (its exit
/// status), after every case is written.
pub fn run_cases(path: &Path, scene: &Scene, options: &Options) -> Result<()> {
    let out = &options.output;
    prepare(out)?;
    let tmp = super::stale::tempdir().context("creating a temporary folder")?;
    let msh = solved_msh(scene, tmp.path());
    let cases = solve_cases(scene, Some(&msh), |_| {})?;
    let mut outcomes: Vec<(String, PathBuf, Result<()>)> = Vec::new();
    let mut index = Vec::new();
    for k in 0..cases.len() {
        let name = scene.load_cases[k].name.clone();
        let dir = out.join(&name);
        let (case, result) = cases.solve(k, |_| {});
        let written = match result {
            Ok(run) => write_run(&case, &run, &msh, &dir),
            Err(stopped) => {
                // Like a one-shot run of one scene: the last iterate, marked.
                let message = stopped.error.to_string();
                let e = write_stopped(&case, *stopped, &msh, &dir);
                eprintln!("error: load case {name}: {message}");
                index.push(CaseEntry::failed(&name, message));
                outcomes.push((name, dir, Err(e)));
                continue;
            }
        };
        let status = written.and_then(|header| {
            if options.print && !options.quiet {
                print_summary(path, &case, &header, &dir);
            }
            let record = header.record.clone().unwrap_or_default();
            index.push(CaseEntry {
                complete: Some(record.complete()),
                converged: true,
                error: None,
                folder: name.clone(),
                limit_load_factor: Some(record.limit_load_factor),
                load_factor: Some(record.load_factor),
                loaded_faces: Some(header.loaded_faces.clone()),
                max_displacement: Some(header.max_displacement),
                name: name.clone(),
            });
            check_limit(&header, &dir)
        });
        outcomes.push((name, dir, status));
    }
    let text = serde_json::to_string_pretty(&CasesIndex {
        format: "axijoint-cases".into(),
        scene: path.display().to_string(),
        title: scene.title.clone(),
        cases: index,
    })?;
    let index = out.join(CASES_INDEX);
    axijoint_mesh::atomic::write_bytes(&index, text.as_bytes())
        .with_context(|| format!("writing {}", index.display()))?;
    if options.report {
        for (_, dir, _) in &outcomes {
            if dir.join("solution.json").is_file() {
                write(dir, options.print)?;
            }
        }
    }
    if options.print {
        crate::say!(
            "  load cases: {} in {} (index: {CASES_INDEX})",
            outcomes.len(),
            out.display()
        );
    }
    match outcomes.into_iter().find(|(_, _, s)| s.is_err()) {
        Some((name, _, Err(e))) => Err(e.context(format!("load case {name}"))),
        _ => Ok(()),
    }
}

impl CaseEntry {
    /// A case that stopped.
    fn failed(name: &str, error: String) -> CaseEntry {
        CaseEntry {
            complete: None,
            converged: false,
            error: Some(error),
            folder: name.into(),
            limit_load_factor: None,
            load_factor: None,
            loaded_faces: None,
            max_displacement: None,
            name: name.into(),
        }
    }
}

/// The output folder of a case run: new, empty, or a former case folder.
fn prepare(out: &Path) -> Result<()> {
    if out.exists() {
        let empty = std::fs::read_dir(out)
            .map(|mut d| d.next().is_none())
            .unwrap_or(false);
        anyhow::ensure!(
            empty || out.join(CASES_INDEX).is_file(),
            "{}: exists and is not an axijoint load-case folder; choose another output folder",
            out.display()
        );
    }
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))
}
