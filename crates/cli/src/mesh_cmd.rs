//! `axijoint mesh`.

use anyhow::{bail, Context, Result};
use axijoint_mesh::{prepare, JointSpec, Summary};
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub struct MeshArgs {
    /// A gmsh .geo (meshed with gmsh), a .msh, or a scene .json (its mesh, parameters and joints).
    pub input: PathBuf,
    /// Physical curves that become joints: CURVE or CURVE:BOTTOM/TOP, comma separated.
    #[arg(long, value_delimiter = ',')]
    pub joints: Vec<String>,
    /// gmsh parameter for a .geo, NAME=VALUE (passed as -setnumber); repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Keep gmsh's .msh at this path (never the input itself).
    #[arg(long, value_name = "FILE")]
    pub msh_out: Option<PathBuf>,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Parses `NAME=VALUE` gmsh parameters.
pub fn parse_parameters(set: &[String]) -> Result<Vec<(String, f64)>> {
    set.iter()
        .map(|s| {
            let (name, value) = s
                .split_once('=')
                .with_context(|| format!("--set '{s}': expected NAME=VALUE"))?;
            let v: f64 = value
                .trim()
                .parse()
                .with_context(|| format!("--set '{s}': '{value}' is not a number"))?;
            if !v.is_finite() {
                bail!("--set '{s}': the value must be finite");
            }
            Ok((name.trim().to_string(), v))
        })
        .collect()
}

pub fn run(args: &MeshArgs) -> Result<()> {
    let parameters = parse_parameters(&args.set)?;
    let joints: Vec<JointSpec> = args
        .joints
        .iter()
        .filter(|s| !s.trim().is_empty())
        .map(|s| s.parse().map_err(anyhow::Error::msg))
        .collect::<Result<_>>()?;
    if let Some(out) = &args.msh_out {
        if out.canonicalize().ok() == args.input.canonicalize().ok() && out.exists() {
            bail!("--msh-out {} would overwrite the input", out.display());
        }
    }
    let is_scene = args
        .input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let (mesh, validation) = if is_scene {
        let mut scene = axijoint_solver::scene::Scene::from_path(&args.input)?;
        for (name, value) in parameters {
            scene.mesh.parameters.insert(name, value);
        }
        let mut specs = scene.joint_specs();
        specs.extend(
            joints
                .into_iter()
                .filter(|j| !specs.iter().any(|s| s.curve == j.curve))
                .collect::<Vec<_>>(),
        );
        let path = scene.mesh_path();
        let mut mesh = axijoint_mesh::gmsh::load(&path, &scene.gmsh_parameters(), args.msh_out.as_deref())?;
        scene.check(&mesh)?;
        let validation = axijoint_mesh::validate(&mut mesh, &path)?;
        axijoint_mesh::insert_joints(&mut mesh, &specs, &path)?;
        (mesh, validation)
    } else {
        prepare(&args.input, &parameters, &joints, args.msh_out.as_deref())?
    };
    let summary = Summary::of(&mesh);
    if args.json {
        let mut value = serde_json::to_value(&summary)?;
        value["source"] = serde_json::json!(args.input.display().to_string());
        value["reoriented_elements"] = serde_json::json!(validation.reoriented);
        crate::say!("{}", serde_json::to_string_pretty(&value)?);
    } else {
        crate::say!("{}", args.input.display());
        if validation.reoriented > 0 {
            crate::say!(
                "note: {} elements of clockwise surfaces renumbered counter-clockwise",
                validation.reoriented
            );
        }
        crate::say_part!("{summary}");
    }
    Ok(())
}
