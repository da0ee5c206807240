//! `axijoint._native`: the Rust half of the Python package `axijoint`
//! (`crates/python/python/axijoint`, docs/python.md).
//!
//! `run` does what `axijoint run` does, through the binary's own
//! application layer (`axijoint_cli::app::run`): it solves a scene (or
//! each of its load cases) into a solution folder, the same scene without
//! joints beside it, and writes the report and `summary.json`, with the
//! GIL released and nothing printed. A failure raises
//! `axijoint.Error` (a subclass per exit status of the binary) with the
//! binary's message and `exit_status`.

use axijoint_cli::app;
use axijoint_cli::exit::{exit_status, BEYOND_CAPACITY, GMSH_FAILURE, IO_ERROR, NUMERICAL_FAILURE};
use axijoint_solver::scene::Scene;
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use std::path::Path;

create_exception!(
    axijoint,
    Error,
    PyException,
    "A run that failed: the message is the axijoint binary's, `exit_status` its exit status."
);
create_exception!(
    axijoint,
    InputError,
    Error,
    "Exit status 1: a scene, mesh or value at fault."
);
create_exception!(
    axijoint,
    BeyondCapacity,
    Error,
    "Exit status 3: a one-shot run found no equilibrium (its last iterate is written)."
);
create_exception!(
    axijoint,
    GmshFailure,
    Error,
    "Exit status 4: gmsh failed or is missing."
);
create_exception!(
    axijoint,
    IOFailure,
    Error,
    "Exit status 5: a file could not be read or written."
);
create_exception!(
    axijoint,
    NumericalFailure,
    Error,
    "Exit status 6: the run stopped without a solution for a numerical reason."
);

/// Solves a scene into the solution folder `output` and, if `report`,
/// writes the report and `summary.json` (as `axijoint run`, which also
/// solves the scene without joints into `output/without_joints` when
/// `without_joints`, by default the scene's `outputs.compare_without_joints`).
/// `scene_text` is the scene's JSON; `None` reads
/// `scene_path`, which otherwise only names it (messages, and the folder
/// a relative `mesh.file` is resolved against). `force` goes on past the
/// cost limits (the command line's `--force`).
#[pyfunction]
#[pyo3(signature = (scene_path, scene_text, output, report = true, without_joints = None, force = false))]
fn run(
    py: Python<'_>,
    scene_path: &str,
    scene_text: Option<&str>,
    output: &str,
    report: bool,
    without_joints: Option<bool>,
    force: bool,
) -> PyResult<()> {
    let result = py.detach(|| {
        solve(
            Path::new(scene_path),
            scene_text,
            Path::new(output),
            report,
            without_joints,
            force,
        )
    });
    result.map_err(|e| to_py(py, &e))
}

fn solve(
    path: &Path,
    text: Option<&str>,
    out: &Path,
    report: bool,
    without_joints: Option<bool>,
    force: bool,
) -> anyhow::Result<()> {
    let mut scene = match text {
        // An error in text changed by overrides: its line in the file.
        Some(t) => Scene::from_str(t, path).map_err(|e| match std::fs::read_to_string(path) {
            Ok(original) => e.located_in(&original),
            Err(_) => e,
        })?,
        None => Scene::from_path(path)?,
    };
    scene.force = force;
    let options = app::Options {
        output: out.to_path_buf(),
        quiet: true,
        compare: without_joints.unwrap_or(scene.outputs.compare_without_joints),
        report,
        print: false,
    };
    match app::run(path, &scene, &options) {
        // A stepped run that stopped short is a result here (every output
        // is written; `Result.complete` tells).
        Err(e) if e.downcast_ref::<app::solve::LimitReached>().is_some() => Ok(()),
        r => r,
    }
}

/// The Python exception of a failure: its class and `exit_status` are
/// those of the binary's exit status, its message the binary's.
fn to_py(py: Python<'_>, e: &anyhow::Error) -> PyErr {
    let status = exit_status(e);
    let message = format!("{e:#}");
    let err = match status {
        BEYOND_CAPACITY => BeyondCapacity::new_err(message),
        GMSH_FAILURE => GmshFailure::new_err(message),
        IO_ERROR => IOFailure::new_err(message),
        NUMERICAL_FAILURE => NumericalFailure::new_err(message),
        _ => InputError::new_err(message),
    };
    if let Err(e) = err.value(py).setattr("exit_status", status) {
        return e;
    }
    err
}

/// Uses the mesh cache of the binary (its default folder) or none, for
/// this process's later runs.
#[pyfunction]
fn set_mesh_cache(enabled: bool) {
    use axijoint_mesh::gmsh::cache;
    cache::set_dir(if enabled { cache::default_dir() } else { None });
}

/// The module `axijoint._native`. Like the binary, it runs each
/// factorization sequentially and the harmonics in parallel, and uses
/// the mesh cache.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    axijoint_solver::linear::prefer_harmonic_parallelism();
    set_mesh_cache(true);
    let py = m.py();
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(set_mesh_cache, m)?)?;
    m.add("Error", py.get_type::<Error>())?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("BeyondCapacity", py.get_type::<BeyondCapacity>())?;
    m.add("GmshFailure", py.get_type::<GmshFailure>())?;
    m.add("IOFailure", py.get_type::<IOFailure>())?;
    m.add("NumericalFailure", py.get_type::<NumericalFailure>())?;
    Ok(())
}
