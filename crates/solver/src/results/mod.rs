//! The solution folder: what `axijoint solve` writes and `axijoint report`
//! reads (format documented in `docs/outputs.md`).
//!
//! ```text
//! DIR/solution.json     header: scene echo, mesh reference, reactions, timings
//! DIR/displacement.f64  amplitudes, little-endian f64, shape [harmonic][family][node][component]
//! DIR/mesh.msh          the mesh that was solved (gmsh's output, or a copy of the input .msh)
//! DIR/mesh_solved.msh   that mesh with the joints inserted: node k is row k of displacement.f64
//! DIR/joints.json       joint field per point and section (nonlinear runs)
//! DIR/plastic.json      plastic bodies' field per Gauss point and section (runs with plastic bodies)
//! ```
//!
//! A folder is written beside the target under a temporary name and renamed
//! into place only when complete; an existing target is replaced only if it is
//! an earlier solution folder (it has `solution.json`) or empty.

use crate::error::{OutputFault, SolverError};
use crate::loads::Resultants;
use crate::scene::Scene;
use crate::solution::{Displacements, HarmonicDisplacement, SupportReaction, Timings};
use axijoint_mesh::{insert_joints, read_msh, validate, Mesh};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};

mod joints;
mod plastic;
mod record;

pub use joints::*;
pub use plastic::*;
pub use record::*;

/// Identifies the header.
pub const FORMAT: &str = "axijoint-solution";
/// Header version.
pub const VERSION: u32 = 1;
/// The mesh with its joints inserted, as solved (MSH 4.1 ASCII, see
/// [`axijoint_mesh::write_msh41`]): its node k is node k of the displacements.
pub const SOLVED_MESH: &str = "mesh_solved.msh";

/// Where the mesh is and how to recognise it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshRef {
    /// File name inside the folder.
    pub file: String,
    /// Nodes after joint insertion.
    pub nodes: usize,
    /// 2D elements.
    pub elements: usize,
    /// Joint names, in model order.
    pub joints: Vec<String>,
    /// FNV-1a hash of the node coordinates (hex), checked on reading.
    pub checksum: String,
}

/// A binary array beside the header.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ArrayRef {
    /// File name inside the folder.
    pub file: String,
    /// Always `f64le`.
    pub dtype: String,
    /// Dimensions, outermost first.
    pub shape: Vec<usize>,
    /// Meaning of the dimensions.
    pub layout: String,
}

/// Cartesian resultants (force, moment about the origin).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResultantsOut {
    /// `(Fx, Fy, Fz)`.
    pub force: [f64; 3],
    /// `(Mx, My, Mz)`.
    pub moment: [f64; 3],
}

impl From<Resultants> for ResultantsOut {
    fn from(r: Resultants) -> Self {
        ResultantsOut {
            force: r.force,
            moment: r.moment,
        }
    }
}

/// The header `solution.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolutionHeader {
    /// [`FORMAT`].
    pub format: String,
    /// [`VERSION`].
    pub version: u32,
    /// The scene file that was run.
    pub scene_file: String,
    /// The scene as run.
    pub scene: Scene,
    /// The mesh.
    pub mesh: MeshRef,
    /// Unknowns per harmonic.
    pub dofs_per_harmonic: usize,
    /// Harmonics 0..=M.
    pub harmonics: Vec<u32>,
    /// Displacement amplitudes.
    pub displacement: ArrayRef,
    /// Applied loads.
    pub applied: ResultantsOut,
    /// Reactions per support.
    pub reactions: Vec<SupportReaction>,
    /// Face-average Cartesian displacement `(ux, uy, uz)` of each loaded curve.
    pub loaded_faces: std::collections::BTreeMap<String, [f64; 3]>,
    /// Largest displacement magnitude over the nodes and the sections 0, pi/8, ..., 2 pi.
    pub max_displacement: f64,
    /// Wall-clock seconds.
    pub timings: Timings,
    /// What the run did beside its displacements (JSON key `extra`; `null`
    /// for a linear run).
    #[serde(rename = "extra", default)]
    pub record: Option<RunRecord>,
    /// Member forces of the bodies in `outputs.members` (a finished run's
    /// last converged state).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub members: Vec<crate::members::MemberForces>,
    /// The initial phase, if the scene has one: the displacements above are
    /// relative to its end.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial: Option<InitialInfo>,
}

/// The initial phase of a solution (docs/loading.md, "Initial phase").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InitialInfo {
    /// The displacements of the phase (harmonic 0; the stresses of the
    /// solution are the initial stresses plus those of these displacements
    /// plus those of `displacement`).
    pub displacement: ArrayRef,
    /// Out-of-balance of the initial stresses.
    pub balance: crate::initial::Balance,
    /// Largest displacement magnitude of the phase.
    pub max_displacement: f64,
    /// Iterations of the phase.
    pub iterations: usize,
}

/// FNV-1a over the bit patterns of the coordinates.
pub fn mesh_checksum(mesh: &Mesh) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for p in &mesh.nodes {
        for v in p {
            for b in v.to_bits().to_le_bytes() {
                h ^= u64::from(b);
                h = h.wrapping_mul(0x0100_0000_01b3);
            }
        }
    }
    format!("{h:016x}")
}

/// A file or folder that could not be written: the file system's fault.
/// Makes the folder an output folder `dir` goes in, and returns it; an
/// error names `dir` and, when a file stands in the way, that file.
pub fn output_parent(dir: &Path) -> Result<PathBuf, SolverError> {
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::create_dir_all(&parent).map_err(|e| {
        let file = parent.ancestors().find(|a| a.is_file());
        match file {
            Some(f) => out_err(
                dir,
                format!(
                    "cannot make the output folder: {} is a file, not a folder",
                    f.display()
                ),
            ),
            None => out_err(dir, format!("cannot make the output folder ({e})")),
        }
    })?;
    Ok(parent)
}

fn out_err(path: &Path, message: impl std::fmt::Display) -> SolverError {
    output_error(path, message, OutputFault::Io)
}

/// A solution folder's file that is not usable as read.
fn bad_saved(path: &Path, message: impl std::fmt::Display) -> SolverError {
    output_error(path, message, OutputFault::Content)
}

/// A solution folder's file that could not be read: a missing file means
/// the folder is not (or no longer) a solution, any other error is the
/// file system's.
fn read_err(path: &Path, e: std::io::Error) -> SolverError {
    let fault = if e.kind() == std::io::ErrorKind::NotFound {
        OutputFault::Content
    } else {
        OutputFault::Io
    };
    output_error(path, e, fault)
}

fn output_error(path: &Path, message: impl std::fmt::Display, fault: OutputFault) -> SolverError {
    SolverError::Output {
        path: path.to_path_buf(),
        message: message.to_string(),
        fault,
    }
}

/// Writes a solution folder at `dir` (see the module doc). `msh` is the mesh
/// file to copy in, `mesh` the mesh solved from it (joints inserted);
/// `joints` and `plastic` are written when given. Nothing is written when a
/// displacement or a value of `plastic` is not finite.
#[allow(clippy::too_many_arguments)]
pub fn write_solution(
    dir: &Path,
    header: &SolutionHeader,
    u: &Displacements,
    initial: Option<&Displacements>,
    msh: &Path,
    mesh: &Mesh,
    joints: Option<&JointFieldFile>,
    plastic: Option<&PlasticFieldFile>,
) -> Result<(), SolverError> {
    for h in &u.harmonics {
        if h.symmetric.iter().chain(&h.antisymmetric).any(|v| !v.is_finite()) {
            return Err(output_error(
                dir,
                format!(
                    "harmonic {}: the displacement is not finite; nothing written",
                    h.m
                ),
                OutputFault::NotFinite,
            ));
        }
    }
    if let Some((s, p)) = plastic.and_then(PlasticFieldFile::first_non_finite) {
        let what = if s == usize::MAX {
            "a section or a point position".to_string()
        } else {
            format!("point {p}, section {s}")
        };
        return Err(output_error(
            dir,
            format!("the plastic field is not finite at {what}; nothing written"),
            OutputFault::NotFinite,
        ));
    }
    if dir.exists() {
        let reusable = dir.join("solution.json").is_file()
            || std::fs::read_dir(dir)
                .map(|mut d| d.next().is_none())
                .unwrap_or(false);
        if !reusable {
            return Err(out_err(
                dir,
                "exists and is not an axijoint solution folder; choose another output folder",
            ));
        }
    }
    let parent = output_parent(dir)?;
    let name = dir
        .file_name()
        .ok_or_else(|| out_err(dir, "not a folder name"))?
        .to_string_lossy()
        .into_owned();
    let stage = parent.join(format!(".{name}.partial-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&stage);
    std::fs::create_dir_all(&stage).map_err(|e| {
        out_err(
            dir,
            format!(
                "cannot write the output folder in {} ({e}); choose another output folder",
                parent.display()
            ),
        )
    })?;
    let result = (|| {
        std::fs::copy(msh, stage.join(&header.mesh.file)).map_err(|e| out_err(msh, e))?;
        let solved = stage.join(SOLVED_MESH);
        let file = std::fs::File::create(&solved).map_err(|e| out_err(&solved, e))?;
        let mut w = std::io::BufWriter::new(file);
        axijoint_mesh::write_msh41(mesh, &mut w)
            .and_then(|()| w.flush())
            .map_err(|e| match e.kind() {
                std::io::ErrorKind::InvalidInput => bad_saved(&solved, e),
                _ => out_err(&solved, e),
            })?;
        let arrays = [(&header.displacement.file, Some(u))]
            .into_iter()
            .chain(header.initial.as_ref().map(|i| (&i.displacement.file, initial)));
        for (file, u) in arrays {
            let bin = stage.join(file);
            let u = u.ok_or_else(|| out_err(&bin, "no values given for this array"))?;
            let mut w = std::io::BufWriter::new(std::fs::File::create(&bin).map_err(|e| out_err(&bin, e))?);
            for h in &u.harmonics {
                for v in h.symmetric.iter().chain(&h.antisymmetric) {
                    w.write_all(&v.to_le_bytes()).map_err(|e| out_err(&bin, e))?;
                }
            }
            w.flush().map_err(|e| out_err(&bin, e))?;
        }
        if let Some(field) = joints {
            let path = stage.join("joints.json");
            let text = serde_json::to_string(field).map_err(|e| out_err(&path, e))?;
            std::fs::write(&path, text).map_err(|e| out_err(&path, e))?;
        }
        if let Some(field) = plastic {
            let path = stage.join(PLASTIC_FIELD);
            write_plastic_field(&path, field).map_err(|e| out_err(&path, e))?;
        }
        let json = stage.join("solution.json");
        let text = serde_json::to_string_pretty(header).map_err(|e| out_err(&json, e))?;
        std::fs::write(&json, text).map_err(|e| out_err(&json, e))?;
        let old = parent.join(format!(".{name}.old-{}", std::process::id()));
        if dir.exists() {
            std::fs::rename(dir, &old).map_err(|e| out_err(dir, e))?;
        }
        std::fs::rename(&stage, dir).map_err(|e| out_err(dir, e))?;
        let _ = std::fs::remove_dir_all(&old);
        Ok(())
    })();
    if result.is_err() {
        let _ = std::fs::remove_dir_all(&stage);
    }
    result
}

/// A solution read back: header, mesh (joints inserted as in the run) and
/// displacement amplitudes.
pub struct SavedSolution {
    /// The header.
    pub header: SolutionHeader,
    /// The mesh, rebuilt from the saved `.msh` and the scene's joints.
    pub mesh: Mesh,
    /// Amplitudes.
    pub displacements: Displacements,
    /// The displacements of the initial phase (harmonic 0), if any.
    pub initial_displacements: Option<Displacements>,
}

/// Reads a solution folder, rebuilding and checking its mesh.
pub fn read_solution(dir: &Path) -> Result<SavedSolution, SolverError> {
    let json = dir.join("solution.json");
    let text = std::fs::read_to_string(&json).map_err(|e| read_err(&json, e))?;
    let header: SolutionHeader = serde_json::from_str(&text).map_err(|e| bad_saved(&json, e))?;
    if header.format != FORMAT || header.version != VERSION {
        return Err(bad_saved(
            &json,
            format!(
                "not an {FORMAT} version {VERSION} header ({} {})",
                header.format, header.version
            ),
        ));
    }
    let msh = dir.join(&header.mesh.file);
    let mut mesh = read_msh(&msh)?;
    validate(&mut mesh, &msh)?;
    insert_joints(&mut mesh, &header.scene.joint_specs(), &msh)?;
    if mesh.nodes.len() != header.mesh.nodes || mesh_checksum(&mesh) != header.mesh.checksum {
        return Err(bad_saved(
            &msh,
            "the mesh does not match solution.json (nodes or checksum differ)",
        ));
    }
    let n = mesh.nodes.len();
    let displacements = read_amplitudes(&dir.join(&header.displacement.file), &header.harmonics, n)?;
    let initial_displacements = match &header.initial {
        Some(i) => Some(read_amplitudes(&dir.join(&i.displacement.file), &[0], n)?),
        None => None,
    };
    Ok(SavedSolution {
        header,
        mesh,
        displacements,
        initial_displacements,
    })
}

/// Reads displacement amplitudes of `harmonics` on `n_nodes` nodes.
fn read_amplitudes(bin: &Path, harmonics: &[u32], n_nodes: usize) -> Result<Displacements, SolverError> {
    let bytes = std::fs::read(bin).map_err(|e| read_err(bin, e))?;
    let n = 3 * n_nodes;
    let expected = harmonics.len() * 2 * n * 8;
    if bytes.len() != expected {
        return Err(bad_saved(
            bin,
            format!(
                "{} bytes, expected {expected} (truncated or not this solution's)",
                bytes.len()
            ),
        ));
    }
    let values: Vec<f64> = bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect();
    if values.iter().any(|v| !v.is_finite()) {
        return Err(bad_saved(bin, "contains values that are not finite"));
    }
    let harmonics = harmonics
        .iter()
        .enumerate()
        .map(|(k, &m)| HarmonicDisplacement {
            m,
            symmetric: values[2 * k * n..(2 * k + 1) * n].to_vec(),
            antisymmetric: values[(2 * k + 1) * n..(2 * k + 2) * n].to_vec(),
        })
        .collect();
    Ok(Displacements { harmonics })
}
