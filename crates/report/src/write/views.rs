//! The 3D views: the revolved `.vtu` (and its joint file) for ParaView,
//! and the gmsh view at the cuts' angles.

use super::context::Ctx;
use crate::error::ReportError;
use crate::estimate::Estimate;
use crate::field::Field;
use crate::{gmsh_view, vtu};
use axijoint_solver::results::{JointFieldFile, PlasticFieldFile};
use axijoint_solver::scene::VtuSections;
use std::sync::OnceLock;

/// Writes `field.vtu` (and `field_joints.vtu` with a joint field), the
/// cells' errors from the shared `estimate`, the plastic cell arrays with a
/// plastic bodies' field; returns the file names.
pub(super) fn write_vtu(
    ctx: Ctx,
    field: &Field,
    joints: Option<&JointFieldFile>,
    plastic: Option<&PlasticFieldFile>,
    estimate: &OnceLock<Estimate>,
) -> Result<Vec<String>, ReportError> {
    let outputs = ctx.outputs;
    let path = ctx.dir.join("field.vtu");
    let n_sections = match outputs.vtu_sections {
        VtuSections::Count(n) => n,
        VtuSections::Auto => {
            let m_max = field.u.harmonics.iter().map(|h| h.m as usize).max().unwrap_or(0);
            vtu::auto_sections(field.mesh, m_max)
        }
    };
    let fields: Vec<&str> = outputs.vtu_fields.iter().map(String::as_str).collect();
    let density = || estimate.get_or_init(|| Estimate::new(field)).cell_density();
    let encoding = if outputs.vtu_compress {
        vtu::Encoding::Zlib
    } else {
        vtu::Encoding::Raw
    };
    vtu::write_vtu_with(
        &path, field, n_sections, &fields, joints, plastic, &density, encoding,
    )?;
    let mut files = vec!["field.vtu".to_string()];
    if joints.is_some() && !ctx.saved.mesh.joints.is_empty() {
        files.push(
            vtu::joints_path(&path)
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
        );
    }
    Ok(files)
}

/// Writes `field_views.msh` at every angle of the cuts (0 without cuts),
/// the stress of a plastic body from `plastic`.
pub(super) fn write_gmsh(
    ctx: Ctx,
    field: &Field,
    plastic: Option<&crate::recovery::PlasticStress>,
) -> Result<Vec<String>, ReportError> {
    let mut thetas: Vec<f64> = ctx
        .scene
        .cuts
        .iter()
        .flat_map(|c| c.theta_deg.iter().copied())
        .collect();
    thetas.sort_by(f64::total_cmp);
    thetas.dedup();
    if thetas.is_empty() {
        thetas.push(0.0);
    }
    gmsh_view::write_gmsh_view_with(&ctx.dir.join("field_views.msh"), field, &thetas, plastic)?;
    Ok(vec!["field_views.msh".into()])
}
