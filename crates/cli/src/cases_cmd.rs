//! `solve` / `run` of a scene with `load_cases`: one model, one set of
//! factors, one initial phase; each case solved from the initial state into
//! its own solution folder `OUT/<case>`, and the index `OUT/cases.json`.

use crate::solve_cmd::{
    check_limit, default_output, print_summary, write_last_iterate, write_run, CommonArgs,
};
use anyhow::{Context, Result};
use axijoint_solver::driver::{solve_cases, InitialState, LinearRun, Run};
use axijoint_solver::error::SolverError;
use axijoint_solver::iteration::IterationError;
use axijoint_solver::scene::Scene;
use serde_json::json;
use std::path::{Path, PathBuf};

/// The index of a load-case folder.
pub const CASES_INDEX: &str = "cases.json";

/// Solves every case of `scene` (read from `path`), prints each summary,
/// reports each case when `report`; fails with the first case that did
/// not reach its whole load (its exit status), after every case is written.
pub fn run(path: &Path, scene: &Scene, common: &CommonArgs, report: bool) -> Result<()> {
    let out = common.output.clone().unwrap_or_else(|| default_output(path));
    prepare(&out)?;
    let tmp = tempfile::tempdir().context("creating a temporary folder")?;
    let msh = crate::solve_cmd::solved_msh(scene, tmp.path());
    let folder = |k: usize| out.join(&scene.load_cases[k].name);
    let mut outcomes: Vec<(String, PathBuf, Result<()>)> = Vec::new();
    let mut index = Vec::new();
    let on_failure = |k: usize, linear: &LinearRun, initial: Option<&InitialState>, e: &IterationError| {
        // Like a one-shot run of one scene: the last iterate, marked.
        let _ = write_last_iterate(&scene.case(k), linear, initial, e, &msh, &folder(k));
    };
    let each = |k: usize, case: &Scene, result: Result<&Run, &SolverError>| {
        let dir = folder(k);
        let name = scene.load_cases[k].name.clone();
        let status = match result {
            Ok(run) => match write_run(case, case, run, &msh, &dir) {
                Ok(header) => {
                    if !common.quiet {
                        print_summary(path, case, &header, &dir);
                    }
                    index.push(json!({
                        "name": name,
                        "folder": name,
                        "converged": true,
                        "load_factor": header.extra.get("load_factor"),
                        "limit_load_factor": header.extra.get("limit_load_factor"),
                        "complete": header.extra.get("complete").cloned().unwrap_or(json!(true)),
                        "loaded_faces": header.loaded_faces,
                        "max_displacement": header.max_displacement,
                    }));
                    check_limit(&header, &dir)
                }
                Err(e) => Err(e),
            },
            Err(e) => {
                eprintln!("error: load case {name}: {e}");
                index.push(json!({"name": name, "folder": name, "converged": false, "error": e.to_string()}));
                Err(anyhow::anyhow!("{e}"))
            }
        };
        outcomes.push((name, dir, status));
    };
    solve_cases(scene, Some(&msh), |_| {}, on_failure, each)?;
    let text = serde_json::to_string_pretty(&json!({
        "format": "axijoint-cases",
        "scene": path.display().to_string(),
        "title": scene.title,
        "cases": index,
    }))?;
    let index = out.join(CASES_INDEX);
    axijoint_mesh::atomic::write_bytes(&index, text.as_bytes())
        .with_context(|| format!("writing {}", index.display()))?;
    if report {
        for (_, dir, _) in &outcomes {
            if dir.join("solution.json").is_file() {
                crate::report_cmd::report(dir, &[])?;
            }
        }
    }
    crate::say!(
        "  load cases: {} in {} (index: {CASES_INDEX})",
        outcomes.len(),
        out.display()
    );
    match outcomes.into_iter().find(|(_, _, s)| s.is_err()) {
        Some((name, _, Err(e))) => Err(e.context(format!("load case {name}"))),
        _ => Ok(()),
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
