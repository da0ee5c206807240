//! `axijoint solve`.

use anyhow::{Context, Result};
use axijoint_solver::driver::{solution_header, solve_linear};
use axijoint_solver::results::write_solution;
use axijoint_solver::scene::Scene;
use clap::Args;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct SolveArgs {
    /// The scene file (JSON, see docs/scene-format.md).
    pub scene: PathBuf,
    /// Output folder [default: out/<scene name> in the current folder].
    #[arg(short, long, value_name = "DIR")]
    pub output: Option<PathBuf>,
    /// Override a gmsh parameter of the scene's mesh, NAME=VALUE; repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Override the scene's highest harmonic M.
    #[arg(long, value_name = "M")]
    pub harmonics: Option<u32>,
}

/// Reads the scene and applies the command-line overrides.
pub fn load_scene(path: &Path, set: &[String], harmonics: Option<u32>) -> Result<Scene> {
    let mut scene = Scene::from_path(path)?;
    for (name, value) in crate::mesh_cmd::parse_parameters(set)? {
        scene.mesh.parameters.insert(name, value);
    }
    if let Some(m) = harmonics {
        scene.harmonics = m;
    }
    Ok(scene)
}

/// The default output folder of a scene: `out/<stem>` under the current folder.
pub fn default_output(scene: &Path) -> PathBuf {
    let stem = scene.file_stem().map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    PathBuf::from("out").join(stem)
}

pub fn run(args: &SolveArgs) -> Result<()> {
    let scene = load_scene(&args.scene, &args.set, args.harmonics)?;
    let out = args.output.clone().unwrap_or_else(|| default_output(&args.scene));
    let tmp = tempfile::tempdir().context("creating a temporary folder")?;
    let is_geo = scene.mesh_path().extension().is_some_and(|e| e.eq_ignore_ascii_case("geo"));
    let msh = if is_geo { tmp.path().join("mesh.msh") } else { scene.mesh_path() };
    let run = solve_linear(&scene, Some(&msh), false)?;
    let header = solution_header(&scene, &run);
    write_solution(&out, &header, &run.displacements, &msh)?;

    println!("{}: {}", args.scene.display(), scene.title);
    println!(
        "  {} nodes, {} elements, {} unknowns per harmonic, harmonics 0..={}",
        header.mesh.nodes,
        header.mesh.elements,
        header.dofs_per_harmonic,
        scene.harmonics()
    );
    let t = &header.timings;
    println!(
        "  time: setup {:.3} s, assembly + factorization {:.3} s, solve {:.3} s",
        t.setup, t.factorize, t.solve
    );
    let u = &scene.units;
    for (face, d) in &header.loaded_faces {
        println!(
            "  {face}: mean displacement (ux, uy, uz) = ({:.6e}, {:.6e}, {:.6e}) {}",
            d[0], d[1], d[2], u.length
        );
    }
    println!("  max |u| = {:.6e} {}", header.max_displacement, u.length);
    let a = &header.applied;
    println!(
        "  applied   F = ({:+.6e}, {:+.6e}, {:+.6e})  M = ({:+.6e}, {:+.6e}, {:+.6e})",
        a.force[0], a.force[1], a.force[2], a.moment[0], a.moment[1], a.moment[2]
    );
    for r in &header.reactions {
        println!(
            "  reaction  F = ({:+.6e}, {:+.6e}, {:+.6e})  M = ({:+.6e}, {:+.6e}, {:+.6e})  on {}",
            r.force[0], r.force[1], r.force[2], r.moment[0], r.moment[1], r.moment[2], r.on
        );
    }
    println!("  written to {}", out.display());
    Ok(())
}
