//! `axijoint._native`: the Rust half of the Python package `axijoint`
//! (`crates/python/python/axijoint`, docs/python.md).
//!
//! `run` does what `axijoint run` does, with the binary's own code
//! (`axijoint_cli`): it solves a scene into a solution folder, the same
//! scene without joints beside it, and writes the report and
//! `summary.json`, with the GIL released. A failure raises
//! `axijoint.Error` (a subclass per exit status of the binary) with the
//! binary's message and `exit_status`.

use axijoint_cli::{report_cmd, solve_cmd};
use axijoint_solver::results::read_solution;
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
/// `without_joints`). `scene_text` is the scene's JSON; `None` reads
/// `scene_path`, which otherwise only names it (messages, and the folder
/// a relative `mesh.file` is resolved against).
#[pyfunction]
#[pyo3(signature = (scene_path, scene_text, output, report = true, without_joints = true))]
fn run(
    py: Python<'_>,
    scene_path: &str,
    scene_text: Option<&str>,
    output: &str,
    report: bool,
    without_joints: bool,
) -> PyResult<()> {
    let result = py.detach(|| {
        solve(
            Path::new(scene_path),
            scene_text,
            Path::new(output),
            report,
            without_joints,
        )
    });
    result.map_err(|e| to_py(py, &e))
}

fn solve(
    path: &Path,
    text: Option<&str>,
    out: &Path,
    report: bool,
    without_joints: bool,
) -> anyhow::Result<()> {
    let scene = match text {
        Some(t) => Scene::from_str(t, path)?,
        None => Scene::from_path(path)?,
    };
    if let Err(e) = solve_cmd::solve_to(&scene, out, true) {
        // As `axijoint run`: a stopped one-shot run wrote its last iterate;
        // report it too.
        if report && read_solution(out).is_ok_and(|s| s.header.extra["converged"] == false) {
            report_cmd::write_outputs(out, &[])?;
        }
        return Err(e);
    }
    if without_joints && !scene.joints.is_empty() {
        let mut bonded = scene.clone();
        bonded.joints.clear();
        bonded.title = format!("{} (without joints)", scene.title);
        solve_cmd::solve_to(&bonded, &out.join(solve_cmd::WITHOUT_JOINTS), true)?;
    }
    if report {
        report_cmd::write_outputs(out, &[])?;
    }
    Ok(())
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

// The exit statuses and their classification, as in the binary's
// `src/main.rs` (docs/outputs.md, "Exit status").
const INPUT_ERROR: u8 = 1;
const BEYOND_CAPACITY: u8 = 3;
const GMSH_FAILURE: u8 = 4;
const IO_ERROR: u8 = 5;
const NUMERICAL_FAILURE: u8 = 6;

fn exit_status(e: &anyhow::Error) -> u8 {
    e.chain().find_map(class_of).unwrap_or(INPUT_ERROR)
}

fn class_of(c: &(dyn std::error::Error + 'static)) -> Option<u8> {
    use axijoint_mesh::MeshError;
    use axijoint_report::error::ReportError;
    use axijoint_solver::error::SolverError;
    use axijoint_solver::iteration::IterationError;
    use axijoint_solver::linear::SolveError;
    use axijoint_solver::scene::SceneError;
    if let Some(l) = c.downcast_ref::<solve_cmd::LimitReached>() {
        return Some(if l.beyond_capacity {
            BEYOND_CAPACITY
        } else {
            NUMERICAL_FAILURE
        });
    }
    if let Some(e) = c.downcast_ref::<SolverError>() {
        return Some(solver_status(e));
    }
    if let Some(e) = c.downcast_ref::<IterationError>() {
        return Some(iteration_status(e));
    }
    if let Some(e) = c.downcast_ref::<MeshError>() {
        return Some(mesh_status(e));
    }
    if let Some(e) = c.downcast_ref::<SceneError>() {
        return Some(scene_status(e));
    }
    if let Some(e) = c.downcast_ref::<SolveError>() {
        return Some(solve_status(e));
    }
    if let Some(e) = c.downcast_ref::<ReportError>() {
        return Some(match e {
            ReportError::Write { .. } => IO_ERROR,
            ReportError::NotFinite { .. } => NUMERICAL_FAILURE,
            ReportError::Input(_) => INPUT_ERROR,
        });
    }
    if c.downcast_ref::<std::io::Error>().is_some() {
        return Some(IO_ERROR);
    }
    None
}

fn solver_status(e: &axijoint_solver::error::SolverError) -> u8 {
    use axijoint_solver::error::{OutputFault, SolverError};
    match e {
        SolverError::Mesh(e) => mesh_status(e),
        SolverError::Scene(e) => scene_status(e),
        SolverError::Solve(e) => solve_status(e),
        SolverError::Iteration(e) => iteration_status(e),
        SolverError::InitialPhase { beyond_capacity, .. } => {
            if *beyond_capacity {
                BEYOND_CAPACITY
            } else {
                NUMERICAL_FAILURE
            }
        }
        SolverError::Output { fault, .. } => match fault {
            OutputFault::Io => IO_ERROR,
            OutputFault::Content => INPUT_ERROR,
            OutputFault::NotFinite => NUMERICAL_FAILURE,
        },
    }
}

fn iteration_status(e: &axijoint_solver::iteration::IterationError) -> u8 {
    use axijoint_solver::iteration::IterationError;
    match e {
        IterationError::NoEquilibrium { .. } => BEYOND_CAPACITY,
        IterationError::NotConverged { .. }
        | IterationError::StiffJoint { .. }
        | IterationError::Rounds { .. } => NUMERICAL_FAILURE,
        IterationError::Setup(_) => INPUT_ERROR,
    }
}

fn mesh_status(e: &axijoint_mesh::MeshError) -> u8 {
    use axijoint_mesh::MeshError;
    match e {
        MeshError::GmshMissing { .. } | MeshError::GmshFailed { .. } => GMSH_FAILURE,
        MeshError::Io { source, .. } => io_status(source),
        MeshError::Parse { .. } | MeshError::Invalid { .. } | MeshError::UnknownName { .. } => INPUT_ERROR,
    }
}

fn scene_status(e: &axijoint_solver::scene::SceneError) -> u8 {
    use axijoint_solver::scene::SceneError;
    match e {
        SceneError::Io { source, .. } => io_status(source),
        SceneError::Parse { .. } | SceneError::Invalid { .. } | SceneError::UnknownName { .. } => INPUT_ERROR,
    }
}

fn solve_status(e: &axijoint_solver::linear::SolveError) -> u8 {
    use axijoint_solver::linear::SolveError;
    match e {
        SolveError::Singular { .. } | SolveError::Input(_) => INPUT_ERROR,
        SolveError::Factorization(_) => NUMERICAL_FAILURE,
    }
}

fn io_status(e: &std::io::Error) -> u8 {
    if e.kind() == std::io::ErrorKind::NotFound {
        INPUT_ERROR
    } else {
        IO_ERROR
    }
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
