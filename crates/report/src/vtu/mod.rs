//! ParaView views: the meridional solution revolved into a 3D unstructured
//! grid (`.vtu`, VTK XML), and the joint surfaces in a second file.
//!
//! # The solid file
//!
//! [`write_vtu`] revolves every meridional cell over `n` sections of the full
//! turn, `theta_k = 2 pi k / n` (k = 0 .. n-1; section n is section 0 again).
//! Point `(r, z)` at angle theta is `(x, y, z) = (r cos theta, r sin theta,
//! z)`: theta = 0 is +x, as in the solver. Quadratic cells stay quadratic; the
//! revolution then needs a ring of points at the mid angles
//! `theta_{k+1/2}`, placed on the true circle. The report takes `n` from
//! `outputs.vtu_sections`, by default [`auto_sections`].
//!
//! | meridional | VTK cell (type) | nodes |
//! |---|---|---|
//! | T3 | wedge (13) | base = T3 at theta_{k+1}, top = T3 at theta_k |
//! | T6 | quadratic wedge (26) | corners k+1, corners k, mids k+1, mids k, corners at k+1/2 |
//! | Q4 | hexahedron (12) | base = Q4 at theta_{k+1}, top = Q4 at theta_k |
//! | Q8 | quadratic hexahedron (25) | corners k+1, corners k, mids k+1, mids k, corners at k+1/2 |
//! | Q9 | triquadratic hexahedron (29) | as Q8, then face centres (meridional mids 7, 5, 4, 6 at k+1/2; centre at k+1, k), centre at k+1/2 |
//!
//! Orientation follows VTK's face tables (VTK 9: every face of
//! `vtkCell::GetFace` has its normal out of the cell): the base of a
//! hexahedron `(0,1,2,3)` or of a wedge `(0,1,2)` has its right-hand normal
//! towards the top face. A counter-clockwise meridional cell has its normal
//! along -theta, so the base is the ring at theta_{k+1} and the top the ring
//! at theta_k; VTK's parametric Jacobian is then positive, and VTK's cell
//! validator and cell-size filter report valid cells with positive volumes.
//! (The old `vtkWedge` documentation describes the wedge's base the other
//! way round; VTK 9's face tables and volume computations use this one.)
//!
//! **Points** are not shared between bodies: each body has its own rings of
//! points, so the stress of each body is its own (docs/theory.md section 13, stresses and cuts). Points
//! on the axis (r = 0) are kept once per section (coincident duplicates): the
//! cells next to the axis are degenerate (a zero-area face), which ParaView
//! draws and filters without complaint, and each duplicate carries the value
//! of its own section.
//!
//! The point data holds the arrays asked for (`outputs.vtu_fields`), from:
//!
//! | point data | components |
//! |---|---|
//! | `displacement` | Cartesian `(u_x, u_y, u_z)` |
//! | `displacement_cyl` | `(u_r, u_z, u_theta)` |
//! | `stress` | Cartesian tensor, 9 components, row-major `XX XY XZ YX YY YZ ZX ZY ZZ` |
//! | `sigma_cyl` | `(sigma_r, sigma_z, sigma_theta, tau_rz, tau_rtheta, tau_ztheta)` |
//! | `von_mises` | equivalent stress |
//! | `pore_pressure` | with ground water, beside any stress array: `p` (compression positive); the stresses are total |
//!
//! The nodal stress of a body is the average, over the body's cells at that
//! node, of each cell's own stress at the node (never across bodies). Cell
//! data: `body` (index into the mesh's bodies), `meridional_cell` (index of
//! the meridional cell the 3D cell was revolved from) and `error_energy`.
//!
//! With the plastic bodies' field (`plastic.json`, [`write_vtu_with`]), the
//! cell of meridional cell c in the slot [theta_k, theta_{k+1}] also has,
//! over c's Gauss points at the section of that field nearest to the
//! slot's mid angle (as the joint file; a half-circle set stands for its
//! mirror image, where both values are the same): `yield_fraction`, the
//! share of the points that yield (0..1), `plastic_strain_eq`, the mean of
//! the equivalent plastic strain `sqrt(2/3 eps_p : eps_p)`
//! ([`equivalent_plastic_strain`](axijoint_solver::results::equivalent_plastic_strain)),
//! and `plastic_section_deg`, the section used; 0, 0 in an elastic body.
//!
//! # The joint file
//!
//! With a joint field, [`write_vtu`] also writes [`joints_path`]`(path)`
//! (`name_joints.vtu`): each joint element revolved over the same sections,
//! as quads (VTK 9, 4-node joints) or biquadratic quads (VTK 28, 6-node
//! joints), from the bottom-face nodes, oriented so that the normal is the
//! joint's eta (into the top body). Point data: `displacement` (bottom face)
//! and `displacement_top`, Cartesian. Cell data, for the cell of element e in
//! the slot [theta_k, theta_{k+1}]:
//!
//! - the joint field at the section nearest to the slot's mid angle. A set of
//!   sections in [0, pi] (the symmetric half, recognised by its weights)
//!   stands for its mirror image too: theta > pi uses the section at
//!   2 pi - theta, with `tau_theta` and `d_theta` negated (odd in theta in
//!   the symmetric family). `section_deg` names the section used.
//! - over the element's integration points at that section: `state` is the
//!   state holding the largest share of the element's area (ties go to the
//!   more severe: 0 stick, 1 slip, 2 open); `open_fraction` and
//!   `slip_fraction` are those shares; `opening`, `slip`, `sigma_n`,
//!   `tau_xi`, `tau_theta` and `d` (`d_xi, d_eta, d_theta`) are area-weighted
//!   means (plain means where all weights are zero, on the axis).
//! - `joint` (index into the mesh's joints) and `element` (within the joint).
//!
//! # Encoding
//!
//! VTK XML 1.0, `header_type="UInt64"`, little-endian: every `DataArray` is
//! `format="appended"` with its `offset` into `<AppendedData
//! encoding="raw">`, whose bytes follow its `_` marker. [`Encoding::Raw`]
//! (the default) stores an array as its UInt64 byte count and its values;
//! [`Encoding::Zlib`] names `compressor="vtkZLibDataCompressor"` and stores
//! an array as its UInt64 header `[nb][nu][np][nc_1 .. nc_nb]` (blocks,
//! 32 KiB block size, last block's size or 0, compressed sizes) then its
//! zlib blocks, as VTK writes them. `connectivity` and `offsets` are Int32
//! where they fit. [`read_vtu`] (and [`decode_array`], [`decode_raw_array`],
//! for one array) reads them back. Files are written under a temporary
//! name and renamed into place ([`axijoint_mesh::atomic`]); a non-finite
//! value fails with [`ReportError::NotFinite`] before anything is written.
//!
//! | module | holds |
//! |---|---|
//! | `revolution`, `transform` | VTK cell types, rings of points, revolved cells; cylindrical to Cartesian |
//! | `solid`, `joints` | the two grids and their arrays |
//! | `encoding`, `read` | writing a grid (raw or zlib); reading a file back |

mod encoding;
mod joints;
mod plastic;
mod read;
pub(crate) mod revolution;
mod solid;
mod transform;

pub use encoding::Encoding;
pub use joints::state_code;
pub use read::{decode_array, decode_raw_array, read_vtu, VtuArray, VtuFile};
pub use revolution::{auto_sections, cell_type, revolved_cell_type};
pub use transform::stress_to_cartesian;

use crate::error::ReportError;
use crate::field::Field;
use crate::recovery::PlasticStress;
use axijoint_mesh::atomic;
use axijoint_solver::results::{JointFieldFile, PlasticFieldFile};
use axijoint_solver::scene::Outputs;
use encoding::{Array, Values};
use joints::joint_grid;
use solid::solid_grid;
use std::path::{Path, PathBuf};

/// The joint file written next to `path`: `dir/stem_joints.vtu`.
pub fn joints_path(path: &Path) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or_else(|| "view".into(), |s| s.to_string_lossy().into_owned());
    path.with_file_name(format!("{stem}_joints.vtu"))
}

/// Writes the 3D field revolved over `n_sections` sections of the full turn
/// to `path` with the point arrays `fields` (names from
/// [`Outputs::VTU_FIELDS`], written in that order; see the module
/// documentation for the layout), and, when `joints` is given and the mesh
/// has joints, the joint surfaces with their state to
/// [`joints_path`]`(path)` (without a joint field no joint file is written,
/// and none already there is touched). No plastic cell arrays: see
/// [`write_vtu_with`].
///
/// `n_sections` must be at least 3. Nothing is written when a value is not
/// finite ([`ReportError::NotFinite`]), a field name is unknown or the joint
/// field does not match the mesh ([`ReportError::Input`]).
pub fn write_vtu(
    path: &Path,
    field: &Field,
    n_sections: usize,
    fields: &[&str],
    joints: Option<&JointFieldFile>,
) -> Result<(), ReportError> {
    let density = || crate::estimate::Estimate::new(field).cell_density();
    write_vtu_with(
        path,
        field,
        n_sections,
        fields,
        joints,
        None,
        &density,
        Encoding::Raw,
    )
}

/// [`write_vtu`] with, when `plastic` is given, its cell arrays
/// `yield_fraction`, `plastic_strain_eq` and `plastic_section_deg` (see the
/// module documentation), the error estimate's density per cell from
/// `density` (called once the revolved grid is made: a caller that shares
/// the estimate lets it be made meanwhile), the arrays stored as
/// `encoding` says. A plastic field that does not match the mesh fails
/// with [`ReportError::Input`] before anything is written.
#[allow(clippy::too_many_arguments)]
pub fn write_vtu_with(
    path: &Path,
    field: &Field,
    n_sections: usize,
    fields: &[&str],
    joints: Option<&JointFieldFile>,
    plastic: Option<&PlasticFieldFile>,
    density: &dyn Fn() -> Vec<f64>,
    encoding: Encoding,
) -> Result<(), ReportError> {
    if n_sections < 3 {
        return Err(ReportError::Input(format!(
            "{}: a revolved view needs at least 3 sections, not {n_sections}",
            path.display()
        )));
    }
    if let Some(f) = fields.iter().find(|f| !Outputs::VTU_FIELDS.contains(f)) {
        return Err(ReportError::Input(format!(
            "{}: unknown array '{f}' (known: {})",
            path.display(),
            Outputs::VTU_FIELDS.join(", ")
        )));
    }
    let recovery = plastic
        .map(|pf| PlasticStress::new(field.mesh, pf))
        .transpose()
        .map_err(|e| ReportError::Input(format!("{}: plastic field: {e}", path.display())))?;
    let mut solid = solid_grid(path, field, n_sections, fields, recovery.as_ref())?;
    // The error estimate per cell (docs/accuracy.md), of each cell's
    // meridional cell.
    let density = density();
    let cells: &[i64] = match solid.cell_data.iter().find(|a| a.name == "meridional_cell") {
        Some(Array {
            values: Values::I64(cells),
            ..
        }) => cells,
        _ => &[],
    };
    let error: Vec<f64> = cells.iter().map(|&c| density[c as usize]).collect();
    let plastic = match plastic {
        Some(pf) => plastic::plastic_arrays(path, field.mesh, pf, cells, n_sections)?,
        None => Vec::new(),
    };
    solid.cell_data.push(Array::f64("error_energy", 1, error));
    solid.cell_data.extend(plastic);
    let joint_grid = match joints {
        Some(jf) if !field.mesh.joints.is_empty() => {
            let jpath = joints_path(path);
            Some((joint_grid(&jpath, field, n_sections, jf)?, jpath))
        }
        _ => None,
    };
    // Both files are whole before either is renamed into place.
    let write = |e: std::io::Error, p: &Path| ReportError::write(p, e);
    let staged = atomic::stage(path, |w| solid.write(w, encoding)).map_err(|e| write(e, path))?;
    if let Some((grid, jpath)) = &joint_grid {
        atomic::stage(jpath, |w| grid.write(w, encoding))
            .and_then(atomic::Staged::commit)
            .map_err(|e| write(e, jpath))?;
    }
    staged.commit().map_err(|e| write(e, path))
}
