//! `axijoint solve` and `axijoint run`: the command line's arguments, read
//! into a scene and the [`app::Options`] of [`app::run`].

use crate::app;
use anyhow::Result;
use axijoint_solver::scene::Scene;
use clap::Args;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct SolveArgs {
    /// The scene file (JSON, see docs/scene-format.md).
    pub scene: PathBuf,
    #[command(flatten)]
    pub common: CommonArgs,
}

#[derive(Args)]
pub struct RunArgs {
    /// The scene file [default: the repository's geo/pile_footing.json, Scene P].
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub common: CommonArgs,
}

#[derive(Args)]
pub struct CommonArgs {
    /// Output folder [default: out/SCENE-NAME in the current folder].
    #[arg(short, long, value_name = "DIR")]
    pub output: Option<PathBuf>,
    /// Override a gmsh parameter of the scene's mesh, NAME=VALUE; repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Override the scene's highest harmonic M.
    #[arg(long, value_name = "M")]
    pub harmonics: Option<u32>,
    /// Override the convergence tolerance of the iteration.
    #[arg(long, value_name = "EPS")]
    pub epsilon: Option<f64>,
    /// No progress display.
    #[arg(short, long)]
    pub quiet: bool,
    /// Go on past the cost limits: more than 512 harmonics, factors beyond
    /// the memory available.
    #[arg(long)]
    pub force: bool,
}

/// Reads the scene and applies the command-line overrides.
pub fn load_scene(path: &Path, common: &CommonArgs) -> Result<Scene> {
    let mut scene = Scene::from_path(path)?;
    scene.force = common.force;
    for (name, value) in crate::mesh_cmd::parse_parameters(&common.set)? {
        scene.mesh.parameters.insert(name, value);
    }
    if let Some(m) = common.harmonics {
        scene.harmonics = m.into();
    }
    if let Some(e) = common.epsilon {
        anyhow::ensure!(e > 0.0 && e < 1.0, "--epsilon {e}: must lie in (0, 1)");
        scene.solver.epsilon = e;
    }
    Ok(scene)
}

/// The default output folder of a scene: `out/<stem>` under the current folder.
pub fn default_output(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    PathBuf::from("out").join(stem)
}

/// The repository's Scene P: `geo/pile_footing.json` under the current
/// folder, else next to the sources this binary was built from.
pub fn default_scene() -> Result<PathBuf> {
    let here = PathBuf::from("geo/pile_footing.json");
    if here.is_file() {
        return Ok(here);
    }
    let built = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../geo/pile_footing.json");
    anyhow::ensure!(
        built.is_file(),
        "no scene given and the default geo/pile_footing.json was not found; pass a scene file"
    );
    Ok(built)
}

/// The options of a run from the command line.
fn options(scene_path: &Path, common: &CommonArgs, scene: &Scene, run: bool) -> app::Options {
    app::Options {
        output: common
            .output
            .clone()
            .unwrap_or_else(|| default_output(scene_path)),
        quiet: common.quiet,
        compare: run && scene.outputs.compare_without_joints,
        report: run,
        print: true,
    }
}

/// `axijoint solve`: the solution folder only.
pub fn run_solve(args: &SolveArgs) -> Result<()> {
    let scene = load_scene(&args.scene, &args.common)?;
    app::run(
        &args.scene,
        &scene,
        &options(&args.scene, &args.common, &scene, false),
    )
}

/// `axijoint run`: the solution folder, the comparison without joints and
/// the report.
pub fn run_run(args: &RunArgs) -> Result<()> {
    let path = match &args.scene {
        Some(s) => s.clone(),
        None => default_scene()?,
    };
    let scene = load_scene(&path, &args.common)?;
    app::run(&path, &scene, &options(&path, &args.common, &scene, true))
}
