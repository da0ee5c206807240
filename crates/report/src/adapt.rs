//! Mesh adaptation from the error estimate (docs/accuracy.md): new element
//! sizes, written as a gmsh background mesh (a `.pos` view), and gmsh
//! re-meshing the same `.geo` with it (`-bgm`).

use crate::estimate::{order, Estimate};
use crate::field::Field;
use axijoint_mesh::gmsh::gmsh_program;
use axijoint_mesh::{Mesh, MeshError};
use std::io::Write;
use std::path::Path;
use std::process::Command;

/// Bounds of the size change of one cycle, `h_new / h`.
pub const SIZE_CHANGE: (f64, f64) = (0.25, 2.0);

/// A cell's size: the mean length of its corner-to-corner edges.
pub fn cell_size(mesh: &Mesh, cell: usize) -> f64 {
    let c = &mesh.cells[cell];
    let k = c.kind.n_corners();
    (0..k)
        .map(|i| {
            let (a, b) = (mesh.nodes[c.nodes[i]], mesh.nodes[c.nodes[(i + 1) % k]]);
            (b[0] - a[0]).hypot(b[1] - a[1])
        })
        .sum::<f64>()
        / k as f64
}

/// The share of the target a cell's RMS error is sized for: a profile's
/// estimate is a maximum over points, about twice the RMS of the cells it
/// crosses.
pub const SAFETY: f64 = 0.5;

/// New cell sizes `h_new = h (SAFETY target / local)^(1/p)`, bounded by
/// [`SIZE_CHANGE`]. `local` is the cell's RMS stress error,
/// `sqrt(E eta_e^2 / V_e)`, relative to `scale` (the smallest max |stress|
/// of the profiles); p the cell's order.
pub fn new_sizes(field: &Field, estimate: &Estimate, scale: f64, target: f64) -> Vec<f64> {
    let target = SAFETY * target;
    let mesh = field.mesh;
    let density = estimate.cell_density();
    (0..mesh.cells.len())
        .map(|c| {
            let e = field.materials[mesh.cells[c].body].e;
            let local = (e * density[c]).max(0.0).sqrt() / scale;
            let p = f64::from(order(mesh.cells[c].kind));
            let f = if local > 0.0 {
                (target / local).powf(1.0 / p)
            } else {
                SIZE_CHANGE.1
            };
            cell_size(mesh, c) * f.clamp(SIZE_CHANGE.0, SIZE_CHANGE.1)
        })
        .collect()
}

/// Writes `sizes` (one per cell) as a gmsh list-based view (`ST`/`SQ` on
/// the cells' corners, each corner the mean size of the cells there).
pub fn write_background(path: &Path, mesh: &Mesh, sizes: &[f64]) -> std::io::Result<()> {
    let (mut sum, mut count) = (vec![0.0; mesh.nodes.len()], vec![0usize; mesh.nodes.len()]);
    for (c, cell) in mesh.cells.iter().enumerate() {
        for &n in &cell.nodes[..cell.kind.n_corners()] {
            sum[n] += sizes[c];
            count[n] += 1;
        }
    }
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(out, "View \"size\" {{")?;
    for cell in &mesh.cells {
        let corners = &cell.nodes[..cell.kind.n_corners()];
        let tag = if corners.len() == 3 { "ST" } else { "SQ" };
        let xyz: Vec<String> = corners
            .iter()
            .map(|&n| format!("{:e},{:e},0", mesh.nodes[n][0], mesh.nodes[n][1]))
            .collect();
        let v: Vec<String> = corners
            .iter()
            .map(|&n| format!("{:e}", sum[n] / count[n].max(1) as f64))
            .collect();
        writeln!(out, "{tag}({}){{{}}};", xyz.join(","), v.join(","))?;
    }
    writeln!(out, "}};")?;
    out.flush()
}

/// Meshes `geo` with gmsh in 2D into `msh` (MSH 4.1), with the background
/// mesh `bgm` (`-bgm`) and `parameters` as `-setnumber`. Sizes from the
/// geometry's points, from the boundary and from curvature are switched
/// off first, so the view alone sets the sizes, unless the `.geo` sets
/// those options itself (it is read after them); a `Background Field` of
/// the `.geo` is replaced by the view.
pub fn mesh_with_background(
    geo: &Path,
    parameters: &[(String, f64)],
    bgm: &Path,
    msh: &Path,
) -> Result<(), MeshError> {
    let mut cmd = Command::new(gmsh_program());
    for option in [
        "Mesh.MeshSizeFromPoints",
        "Mesh.MeshSizeExtendFromBoundary",
        "Mesh.MeshSizeFromCurvature",
    ] {
        cmd.arg("-setnumber").arg(option).arg("0");
    }
    cmd.arg(geo)
        .args(["-2", "-format", "msh41", "-o"])
        .arg(msh)
        .arg("-bgm")
        .arg(bgm);
    for (name, value) in parameters {
        cmd.arg("-setnumber").arg(name).arg(format!("{value:?}"));
    }
    let failed = |status: String, output: String| MeshError::GmshFailed {
        path: geo.to_path_buf(),
        status,
        output,
    };
    let out = axijoint_mesh::gmsh::run_bounded(cmd, geo, parameters)?;
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let errors: Vec<&str> = text.lines().filter(|l| l.starts_with("Error")).collect();
    if !out.status.success() || !errors.is_empty() || !msh.is_file() {
        return Err(failed(out.status.to_string(), errors.join("\n")));
    }
    Ok(())
}
