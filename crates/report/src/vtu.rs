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
//!
//! The nodal stress of a body is the average, over the body's cells at that
//! node, of each cell's own stress at the node (never across bodies). Cell
//! data: `body` (index into the mesh's bodies) and `meridional_cell` (index of
//! the meridional cell the 3D cell was revolved from).
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
//! name and renamed into place; a non-finite value fails with
//! [`ReportError::NotFinite`] before anything is written.

use crate::field::{Field, STRESS_NAMES};
use crate::ReportError;
use axijoint_mesh::{CellKind, JointKind, Mesh};
use axijoint_solver::fourier::Sections;
use axijoint_solver::joint_law::JointState;
use axijoint_solver::results::JointFieldFile;
use axijoint_solver::scene::Outputs;
use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, Event};
use quick_xml::Writer;
use std::f64::consts::PI;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// VTK cell type numbers used here.
pub mod cell_type {
    /// Linear wedge (6 nodes).
    pub const WEDGE: u8 = 13;
    /// Linear hexahedron (8 nodes).
    pub const HEXAHEDRON: u8 = 12;
    /// Quadratic wedge (15 nodes).
    pub const QUADRATIC_WEDGE: u8 = 26;
    /// Quadratic (serendipity) hexahedron (20 nodes).
    pub const QUADRATIC_HEXAHEDRON: u8 = 25;
    /// Triquadratic hexahedron (27 nodes).
    pub const TRIQUADRATIC_HEXAHEDRON: u8 = 29;
    /// Linear quadrilateral (4 nodes).
    pub const QUAD: u8 = 9;
    /// Biquadratic quadrilateral (9 nodes).
    pub const BIQUADRATIC_QUAD: u8 = 28;
}

/// The VTK cell a meridional cell becomes when revolved: `(type, nodes)`.
pub fn revolved_cell_type(kind: CellKind) -> (u8, usize) {
    match kind {
        CellKind::Tri3 => (cell_type::WEDGE, 6),
        CellKind::Tri6 => (cell_type::QUADRATIC_WEDGE, 15),
        CellKind::Quad4 => (cell_type::HEXAHEDRON, 8),
        CellKind::Quad8 => (cell_type::QUADRATIC_HEXAHEDRON, 20),
        CellKind::Quad9 => (cell_type::TRIQUADRATIC_HEXAHEDRON, 27),
    }
}

/// The joint file written next to `path`: `dir/stem_joints.vtu`.
pub fn joints_path(path: &Path) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or_else(|| "view".into(), |s| s.to_string_lossy().into_owned());
    path.with_file_name(format!("{stem}_joints.vtu"))
}

/// Samples of the turn (points on a ring) that resolve harmonic `m_max`:
/// 8 per period of the highest harmonic (4 times the 2 of Nyquist's
/// criterion), 16 at least.
fn samples_per_turn(m_max: usize) -> usize {
    (8 * m_max).max(16)
}

/// The sections `outputs.vtu_sections = "auto"` gives for a field whose
/// highest harmonic is `m_max`: 8 samples of the turn per period of
/// harmonic `m_max`, 16 at least, i.e. `max(16, 8 M)` sections for linear
/// cells and half as many, `max(8, 4 M)`, when every cell is quadratic
/// (each section then has a ring at its mid angle too).
pub fn auto_sections(mesh: &Mesh, m_max: usize) -> usize {
    let quadratic = mesh.cells.iter().all(|c| !mid_ring_nodes(c.kind).is_empty());
    samples_per_turn(m_max) / if quadratic { 2 } else { 1 }
}

/// Writes the 3D field revolved over `n_sections` sections of the full turn
/// to `path` with the point arrays `fields` (names from
/// [`Outputs::VTU_FIELDS`], written in that order; see the module
/// documentation for the layout), and, when `joints` is given and the mesh
/// has joints, the joint surfaces with their state to
/// [`joints_path`]`(path)` (without a joint field no joint file is written,
/// and none already there is touched).
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
    write_vtu_with(path, field, n_sections, fields, joints, &density, Encoding::Raw)
}

/// [`write_vtu`] with the error estimate's density per cell from `density`
/// (called once the revolved grid is made: a caller that shares the
/// estimate lets it be made meanwhile), the arrays stored as `encoding`
/// says.
pub fn write_vtu_with(
    path: &Path,
    field: &Field,
    n_sections: usize,
    fields: &[&str],
    joints: Option<&JointFieldFile>,
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
    let mut solid = solid_grid(path, field, n_sections, fields)?;
    // The error estimate per cell (docs/accuracy.md), of each cell's
    // meridional cell.
    let density = density();
    let error: Vec<f64> = match solid.cell_data.iter().find(|a| a.name == "meridional_cell") {
        Some(Array {
            values: Values::I64(cells),
            ..
        }) => cells.iter().map(|&c| density[c as usize]).collect(),
        _ => Vec::new(),
    };
    solid.cell_data.push(Array::f64("error_energy", 1, error));
    let joint_grid = match joints {
        Some(jf) if !field.mesh.joints.is_empty() => {
            let jpath = joints_path(path);
            Some((joint_grid(&jpath, field, n_sections, jf)?, jpath))
        }
        _ => None,
    };
    let tmp = write_temp(path, |w| solid.write(w, encoding))?;
    let jtmp = match &joint_grid {
        Some((grid, jpath)) => match write_temp(jpath, |w| grid.write(w, encoding)) {
            Ok(t) => Some((t, jpath)),
            Err(e) => {
                let _ = std::fs::remove_file(&tmp);
                return Err(e);
            }
        },
        None => None,
    };
    if let Some((t, jpath)) = jtmp {
        commit(&t, jpath).inspect_err(|_| {
            let _ = std::fs::remove_file(&tmp);
        })?;
    }
    commit(&tmp, path)
}

// ---------------------------------------------------------------------------
// Temporary files.

/// Writes `path`'s content to a temporary file in the same folder and returns
/// its name; removes it on error.
pub(crate) fn write_temp(
    path: &Path,
    f: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> Result<PathBuf, ReportError> {
    let name = path
        .file_name()
        .ok_or_else(|| ReportError::write(path, "not a file name"))?
        .to_string_lossy();
    let tmp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| -> std::io::Result<()> {
        let mut w = BufWriter::new(File::create(&tmp)?);
        f(&mut w)?;
        // Not synced to disk, like every report file: `axijoint report`
        // rewrites them from the solution (an fsync took 3-6 ms a file).
        w.into_inner().map_err(|e| e.into_error())?;
        Ok(())
    })();
    match result {
        Ok(()) => Ok(tmp),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(ReportError::write(path, e))
        }
    }
}

/// Renames a file made by [`write_temp`] into place.
pub(crate) fn commit(tmp: &Path, path: &Path) -> Result<(), ReportError> {
    std::fs::rename(tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(tmp);
        ReportError::write(path, e)
    })
}

/// Fails with [`ReportError::NotFinite`] unless every value is finite.
pub(crate) fn check_finite(
    path: &Path,
    values: &[f64],
    what: impl FnOnce() -> String,
) -> Result<(), ReportError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(ReportError::NotFinite {
            path: path.to_path_buf(),
            what: what(),
        })
    }
}

// ---------------------------------------------------------------------------
// Grid and XML.

/// How the arrays of a file are stored in its appended data.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Encoding {
    /// Each array as its byte count (UInt64) and its little-endian bytes:
    /// the fastest to write and to read.
    #[default]
    Raw,
    /// `vtkZLibDataCompressor`: each array as its UInt64 block header and
    /// zlib blocks of 32 KiB, compressed in parallel at zlib's fastest
    /// level (a fifth smaller for Float64 data, docs/outputs.md).
    Zlib,
}

/// Values of a data array.
enum Values {
    F64(Vec<f64>),
    I32(Vec<i32>),
    I64(Vec<i64>),
}

/// Borrowed values of a data array, as written.
#[derive(Clone, Copy)]
enum ValuesRef<'a> {
    F64(&'a [f64]),
    I32(&'a [i32]),
    I64(&'a [i64]),
    U8(&'a [u8]),
}

impl Values {
    fn as_ref(&self) -> ValuesRef<'_> {
        match self {
            Values::F64(v) => ValuesRef::F64(v),
            Values::I32(v) => ValuesRef::I32(v),
            Values::I64(v) => ValuesRef::I64(v),
        }
    }
}

/// Writes `values` little-endian through a stack buffer (no copy of the
/// whole array).
fn write_le<T: Copy, const N: usize>(
    out: &mut impl Write,
    values: &[T],
    bytes: impl Fn(T) -> [u8; N],
) -> std::io::Result<()> {
    let mut buf = [0u8; 8192];
    for chunk in values.chunks(8192 / N) {
        for (b, &v) in buf.chunks_exact_mut(N).zip(chunk) {
            b.copy_from_slice(&bytes(v));
        }
        out.write_all(&buf[..N * chunk.len()])?;
    }
    Ok(())
}

impl ValuesRef<'_> {
    fn type_name(&self) -> &'static str {
        match self {
            ValuesRef::F64(_) => "Float64",
            ValuesRef::I32(_) => "Int32",
            ValuesRef::I64(_) => "Int64",
            ValuesRef::U8(_) => "UInt8",
        }
    }

    /// Size in bytes.
    fn n_bytes(&self) -> usize {
        match self {
            ValuesRef::F64(v) => 8 * v.len(),
            ValuesRef::I32(v) => 4 * v.len(),
            ValuesRef::I64(v) => 8 * v.len(),
            ValuesRef::U8(v) => v.len(),
        }
    }

    /// Writes the little-endian bytes.
    fn write(&self, out: &mut impl Write) -> std::io::Result<()> {
        match *self {
            ValuesRef::F64(v) => write_le(out, v, f64::to_le_bytes),
            ValuesRef::I32(v) => write_le(out, v, i32::to_le_bytes),
            ValuesRef::I64(v) => write_le(out, v, i64::to_le_bytes),
            ValuesRef::U8(v) => out.write_all(v),
        }
    }

    /// The little-endian bytes.
    fn bytes(&self) -> Vec<u8> {
        let mut b = Vec::with_capacity(self.n_bytes());
        self.write(&mut b).expect("writing to a Vec");
        b
    }
}

/// A named data array.
struct Array {
    name: &'static str,
    components: usize,
    component_names: &'static [&'static str],
    values: Values,
}

impl Array {
    fn f64(name: &'static str, components: usize, values: Vec<f64>) -> Array {
        Array {
            name,
            components,
            component_names: &[],
            values: Values::F64(values),
        }
    }

    fn named(mut self, names: &'static [&'static str]) -> Array {
        self.component_names = names;
        self
    }
}

/// An array as written: its element's attributes and its values.
struct ArrayRef<'a> {
    name: &'static str,
    components: usize,
    component_names: &'static [&'static str],
    values: ValuesRef<'a>,
}

impl<'a> ArrayRef<'a> {
    fn of(a: &'a Array) -> ArrayRef<'a> {
        ArrayRef {
            name: a.name,
            components: a.components,
            component_names: a.component_names,
            values: a.values.as_ref(),
        }
    }

    fn plain(name: &'static str, components: usize, values: ValuesRef<'a>) -> ArrayRef<'a> {
        ArrayRef {
            name,
            components,
            component_names: &[],
            values,
        }
    }
}

/// One unstructured piece.
#[derive(Default)]
struct Grid {
    points: Vec<f64>,
    connectivity: Vec<i64>,
    offsets: Vec<i64>,
    types: Vec<u8>,
    point_data: Vec<Array>,
    cell_data: Vec<Array>,
}

impl Grid {
    fn push_cell(&mut self, vtk_type: u8, nodes: &[usize]) {
        self.connectivity.extend(nodes.iter().map(|&n| n as i64));
        self.offsets.push(self.connectivity.len() as i64);
        self.types.push(vtk_type);
    }

    fn n_points(&self) -> usize {
        self.points.len() / 3
    }

    fn write(&self, out: &mut impl Write, encoding: Encoding) -> std::io::Result<()> {
        // Int32 cell arrays where they fit (half the bytes of Int64).
        let small = i32::try_from(self.connectivity.len().max(self.n_points())).is_ok();
        let narrow = |v: &[i64]| small.then(|| v.iter().map(|&x| x as i32).collect::<Vec<_>>());
        let (connectivity32, offsets32) = (narrow(&self.connectivity), narrow(&self.offsets));
        // Every array in file order, grouped by parent element.
        let groups: [(&str, Vec<ArrayRef>); 4] = [
            ("PointData", self.point_data.iter().map(ArrayRef::of).collect()),
            ("CellData", self.cell_data.iter().map(ArrayRef::of).collect()),
            (
                "Points",
                vec![ArrayRef::plain("Points", 3, ValuesRef::F64(&self.points))],
            ),
            (
                "Cells",
                vec![
                    ArrayRef::plain("connectivity", 1, index(&self.connectivity, &connectivity32)),
                    ArrayRef::plain("offsets", 1, index(&self.offsets, &offsets32)),
                    ArrayRef::plain("types", 1, ValuesRef::U8(&self.types)),
                ],
            ),
        ];
        // What each array puts in the appended data, and where it starts.
        let blocks: Vec<Option<Vec<u8>>> = groups
            .iter()
            .flat_map(|(_, arrays)| arrays.iter())
            .map(|a| {
                (encoding == Encoding::Zlib)
                    .then(|| compress(&a.values.bytes()))
                    .transpose()
            })
            .collect::<std::io::Result<_>>()?;
        let sizes = groups
            .iter()
            .flat_map(|(_, arrays)| arrays.iter())
            .zip(&blocks)
            .map(|(a, b)| b.as_ref().map_or(8 + a.values.n_bytes(), Vec::len));
        let starts: Vec<usize> = sizes
            .scan(0, |at, size| {
                let start = *at;
                *at += size;
                Some(start)
            })
            .collect();

        let mut w = Writer::new_with_indent(&mut *out, b' ', 2);
        w.write_event(Event::Decl(BytesDecl::new("1.0", None, None)))?;
        let mut file = BytesStart::new("VTKFile");
        file.push_attribute(("type", "UnstructuredGrid"));
        file.push_attribute(("version", "1.0"));
        file.push_attribute(("byte_order", "LittleEndian"));
        file.push_attribute(("header_type", "UInt64"));
        if encoding == Encoding::Zlib {
            file.push_attribute(("compressor", "vtkZLibDataCompressor"));
        }
        w.write_event(Event::Start(file))?;
        w.write_event(Event::Start(BytesStart::new("UnstructuredGrid")))?;
        let mut piece = BytesStart::new("Piece");
        piece.push_attribute(("NumberOfPoints", self.n_points().to_string().as_str()));
        piece.push_attribute(("NumberOfCells", self.types.len().to_string().as_str()));
        w.write_event(Event::Start(piece))?;
        let mut at = starts.iter();
        for (tag, arrays) in &groups {
            let mut el = BytesStart::new(*tag);
            if matches!(*tag, "PointData" | "CellData") {
                // The arrays ParaView shows first.
                for (role, name) in [
                    ("Scalars", "von_mises"),
                    ("Scalars", "state"),
                    ("Scalars", "body"),
                    ("Vectors", "displacement"),
                    ("Tensors", "stress"),
                ] {
                    let taken = el
                        .attributes()
                        .any(|a| a.is_ok_and(|a| a.key.as_ref() == role.as_bytes()));
                    if !taken && arrays.iter().any(|a| a.name == name) {
                        el.push_attribute((role, name));
                    }
                }
            }
            w.write_event(Event::Start(el))?;
            for a in arrays {
                write_array_element(&mut w, a, *at.next().expect("an offset per array"))?;
            }
            w.write_event(Event::End(BytesEnd::new(*tag)))?;
        }
        w.write_event(Event::End(BytesEnd::new("Piece")))?;
        w.write_event(Event::End(BytesEnd::new("UnstructuredGrid")))?;
        let mut appended = BytesStart::new("AppendedData");
        appended.push_attribute(("encoding", "raw"));
        w.write_event(Event::Start(appended))?;
        let out = w.into_inner();
        out.write_all(b"\n    _")?;
        for (a, block) in groups.iter().flat_map(|(_, arrays)| arrays.iter()).zip(&blocks) {
            match block {
                Some(b) => out.write_all(b)?,
                None => {
                    out.write_all(&(a.values.n_bytes() as u64).to_le_bytes())?;
                    a.values.write(out)?;
                }
            }
        }
        out.write_all(b"\n  </AppendedData>\n</VTKFile>\n")
    }
}

/// An index array as Int32 where it was narrowed, else as Int64.
fn index<'a>(wide: &'a [i64], narrow: &'a Option<Vec<i32>>) -> ValuesRef<'a> {
    match narrow {
        Some(v) => ValuesRef::I32(v),
        None => ValuesRef::I64(wide),
    }
}

/// Writes the `DataArray` element of `a`, its data at `offset` of the
/// appended data.
fn write_array_element<W: Write>(w: &mut Writer<W>, a: &ArrayRef, offset: usize) -> std::io::Result<()> {
    let mut el = BytesStart::new("DataArray");
    el.push_attribute(("type", a.values.type_name()));
    el.push_attribute(("Name", a.name));
    if a.components != 1 {
        el.push_attribute(("NumberOfComponents", a.components.to_string().as_str()));
    }
    let keys: Vec<String> = (0..a.component_names.len())
        .map(|i| format!("ComponentName{i}"))
        .collect();
    for (k, v) in keys.iter().zip(a.component_names) {
        el.push_attribute((k.as_str(), *v));
    }
    el.push_attribute(("format", "appended"));
    el.push_attribute(("offset", offset.to_string().as_str()));
    w.write_event(Event::Empty(el))
}

/// Uncompressed size of a compressed block (VTK's default).
const BLOCK: usize = 1 << 15;

/// `bytes` as a `vtkZLibDataCompressor` array: the UInt64 header
/// `[nb][nu][np][nc_1 .. nc_nb]`, then the zlib blocks, compressed in
/// parallel at zlib's fastest level (Float64 data barely compresses more
/// at the default level, docs/outputs.md).
fn compress(bytes: &[u8]) -> std::io::Result<Vec<u8>> {
    use flate2::{write::ZlibEncoder, Compression};
    use rayon::prelude::*;
    let blocks = bytes
        .par_chunks(BLOCK)
        .map(|chunk| {
            let mut e = ZlibEncoder::new(Vec::new(), Compression::fast());
            e.write_all(chunk)?;
            e.finish()
        })
        .collect::<std::io::Result<Vec<_>>>()?;
    let mut header: Vec<u64> = vec![blocks.len() as u64, BLOCK as u64, (bytes.len() % BLOCK) as u64];
    header.extend(blocks.iter().map(|b| b.len() as u64));
    let mut out = Vec::with_capacity(8 * header.len() + blocks.iter().map(Vec::len).sum::<usize>());
    out.extend(header.iter().flat_map(|v| v.to_le_bytes()));
    for b in &blocks {
        out.extend_from_slice(b);
    }
    Ok(out)
}

fn invalid(m: impl Into<String>) -> std::io::Error {
    std::io::Error::new(std::io::ErrorKind::InvalidData, m.into())
}

/// The bytes of one array of the appended data as [`write_vtu`] writes it
/// with [`Encoding::Zlib`] (UInt64 header, zlib blocks), `data` starting at
/// the array's `offset`: the inverse of the encoding, for readers and tests
/// without a VTK library.
pub fn decode_array(data: &[u8]) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let word = |i: usize| -> std::io::Result<usize> {
        let b = data
            .get(8 * i..8 * i + 8)
            .ok_or_else(|| invalid("short header"))?;
        Ok(u64::from_le_bytes(b.try_into().unwrap()) as usize)
    };
    let (nb, nu, np) = (word(0)?, word(1)?, word(2)?);
    let mut at = 8 * (3 + nb);
    let mut out = Vec::new();
    for i in 0..nb {
        let nc = word(3 + i)?;
        let block = data.get(at..at + nc).ok_or_else(|| invalid("short data"))?;
        flate2::read::ZlibDecoder::new(block).read_to_end(&mut out)?;
        at += nc;
    }
    let expected = match nb {
        0 => 0,
        _ => (nb - 1) * nu + if np == 0 { nu } else { np },
    };
    if out.len() != expected {
        return Err(invalid("block sizes do not match the header"));
    }
    Ok(out)
}

/// The bytes of one array of the appended data as [`write_vtu`] writes it
/// with [`Encoding::Raw`]: its UInt64 byte count, then the bytes.
pub fn decode_raw_array(data: &[u8]) -> std::io::Result<Vec<u8>> {
    let n = data
        .get(..8)
        .ok_or_else(|| invalid("short header"))
        .map(|b| u64::from_le_bytes(b.try_into().unwrap()) as usize)?;
    data.get(8..8 + n)
        .map(<[u8]>::to_vec)
        .ok_or_else(|| invalid("short data"))
}

/// One array of a file read by [`read_vtu`].
#[derive(Clone, Debug)]
pub struct VtuArray {
    /// The parent element: `PointData`, `CellData`, `Points` or `Cells`.
    pub parent: String,
    /// `Name` (`Points` for the points).
    pub name: String,
    /// VTK type: `Float64`, `Int32`, `Int64` or `UInt8`.
    pub type_name: String,
    /// `NumberOfComponents`.
    pub components: usize,
    /// The values, little-endian.
    pub bytes: Vec<u8>,
}

impl VtuArray {
    /// The values as f64.
    pub fn values(&self) -> std::io::Result<Vec<f64>> {
        let b = &self.bytes;
        Ok(match self.type_name.as_str() {
            "Float64" => b
                .chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                .collect(),
            "Int64" => b
                .chunks_exact(8)
                .map(|c| i64::from_le_bytes(c.try_into().unwrap()) as f64)
                .collect(),
            "Int32" => b
                .chunks_exact(4)
                .map(|c| i32::from_le_bytes(c.try_into().unwrap()) as f64)
                .collect(),
            "UInt8" => b.iter().map(|&v| v as f64).collect(),
            t => return Err(invalid(format!("array type {t}"))),
        })
    }
}

/// A `.vtu` written by [`write_vtu`], read back.
#[derive(Clone, Debug)]
pub struct VtuFile {
    /// `NumberOfPoints`.
    pub n_points: usize,
    /// `NumberOfCells`.
    pub n_cells: usize,
    /// Every array, in file order.
    pub arrays: Vec<VtuArray>,
}

impl VtuFile {
    /// The array `name` under `parent` (`PointData`, `CellData`, `Points`,
    /// `Cells`).
    pub fn array(&self, parent: &str, name: &str) -> Option<&VtuArray> {
        self.arrays.iter().find(|a| a.parent == parent && a.name == name)
    }
}

/// Reads a `.vtu` as [`write_vtu`] writes it (one piece, raw appended
/// arrays, zlib-compressed when the file names `vtkZLibDataCompressor`).
pub fn read_vtu(path: &Path) -> std::io::Result<VtuFile> {
    let bytes = std::fs::read(path)?;
    let tag = b"<AppendedData";
    let head_end = bytes
        .windows(tag.len())
        .position(|w| w == tag)
        .ok_or_else(|| invalid("no AppendedData"))?;
    let data_start = head_end
        + bytes[head_end..]
            .iter()
            .position(|&b| b == b'_')
            .ok_or_else(|| invalid("no '_' before the appended data"))?
        + 1;
    let data = &bytes[data_start..];
    let head = std::str::from_utf8(&bytes[..head_end]).map_err(|e| invalid(e.to_string()))?;
    let attr = |e: &BytesStart, key: &str| -> Option<String> {
        e.try_get_attribute(key)
            .ok()
            .flatten()
            .map(|a| String::from_utf8_lossy(&a.value).into_owned())
    };
    let number = |e: &BytesStart, key: &str| -> std::io::Result<usize> {
        attr(e, key)
            .ok_or_else(|| invalid(format!("no {key}")))?
            .parse()
            .map_err(|_| invalid(format!("{key} is not a number")))
    };
    let mut reader = quick_xml::Reader::from_str(head);
    let mut parents: Vec<String> = Vec::new();
    let mut compressed = false;
    let mut file = VtuFile {
        n_points: 0,
        n_cells: 0,
        arrays: vec![],
    };
    loop {
        let event = reader.read_event().map_err(|e| invalid(e.to_string()))?;
        match &event {
            Event::Start(e) | Event::Empty(e) => {
                let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
                if name == "VTKFile" {
                    compressed = match attr(e, "compressor").as_deref() {
                        None => false,
                        Some("vtkZLibDataCompressor") => true,
                        Some(c) => return Err(invalid(format!("compressor {c}"))),
                    };
                } else if name == "Piece" {
                    file.n_points = number(e, "NumberOfPoints")?;
                    file.n_cells = number(e, "NumberOfCells")?;
                } else if name == "DataArray" {
                    if attr(e, "format").as_deref() != Some("appended") {
                        return Err(invalid("an array not in the appended data"));
                    }
                    let offset = number(e, "offset")?;
                    let values = data
                        .get(offset..)
                        .ok_or_else(|| invalid("offset past the data"))?;
                    file.arrays.push(VtuArray {
                        parent: parents.last().cloned().unwrap_or_default(),
                        name: attr(e, "Name").unwrap_or_default(),
                        type_name: attr(e, "type").unwrap_or_default(),
                        components: attr(e, "NumberOfComponents")
                            .map_or(Ok(1), |_| number(e, "NumberOfComponents"))?,
                        bytes: if compressed {
                            decode_array(values)?
                        } else {
                            decode_raw_array(values)?
                        },
                    });
                }
                if matches!(event, Event::Start(_)) {
                    parents.push(name);
                }
            }
            Event::End(_) => {
                parents.pop();
            }
            Event::Eof => break,
            _ => {}
        }
    }
    Ok(file)
}

// ---------------------------------------------------------------------------
// Revolution.

/// Point numbering of revolved meridional nodes: `n` rings at theta_k, then
/// (for the nodes that need one) `n` rings at theta_{k+1/2}.
struct Rings {
    n: usize,
    base: usize,
    /// Meridional nodes with a full ring, in point order.
    nodes: Vec<usize>,
    /// Meridional nodes with a mid-angle ring, in point order.
    mids: Vec<usize>,
    /// Mesh node -> position in `nodes`.
    local: Vec<usize>,
    /// Mesh node -> position in `mids`.
    local_mid: Vec<usize>,
}

impl Rings {
    fn new(n: usize, base: usize, n_mesh_nodes: usize, nodes: Vec<usize>, mids: Vec<usize>) -> Rings {
        let mut local = vec![usize::MAX; n_mesh_nodes];
        let mut local_mid = vec![usize::MAX; n_mesh_nodes];
        for (i, &m) in nodes.iter().enumerate() {
            local[m] = i;
        }
        for (i, &m) in mids.iter().enumerate() {
            local_mid[m] = i;
        }
        Rings {
            n,
            base,
            nodes,
            mids,
            local,
            local_mid,
        }
    }

    /// Point of mesh node `node` at theta_k (k taken modulo n).
    fn at(&self, node: usize, k: usize) -> usize {
        self.base + (k % self.n) * self.nodes.len() + self.local[node]
    }

    /// Point of mesh node `node` at theta_{k+1/2}.
    fn mid(&self, node: usize, k: usize) -> usize {
        self.base + self.n * self.nodes.len() + k * self.mids.len() + self.local_mid[node]
    }

    fn len(&self) -> usize {
        self.n * (self.nodes.len() + self.mids.len())
    }

    /// `(theta, mesh nodes)` of every ring, in point order.
    fn by_angle(&self) -> impl Iterator<Item = (f64, &[usize])> + '_ {
        let n = self.n;
        let full = (0..n).map(move |k| (ring_angle(k, n), self.nodes.as_slice()));
        let half = (0..n).map(move |k| (mid_angle(k, n), self.mids.as_slice()));
        full.chain(half)
    }

    /// `(mesh node, theta)` of every point, in point order.
    fn points(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        let n = self.n;
        let full = (0..n).flat_map(move |k| self.nodes.iter().map(move |&m| (m, ring_angle(k, n))));
        let half = (0..n).flat_map(move |k| self.mids.iter().map(move |&m| (m, mid_angle(k, n))));
        full.chain(half)
    }
}

fn ring_angle(k: usize, n: usize) -> f64 {
    2.0 * PI * k as f64 / n as f64
}

fn mid_angle(k: usize, n: usize) -> f64 {
    2.0 * PI * (k as f64 + 0.5) / n as f64
}

/// VTK node list of meridional cell `nodes` revolved over slot k.
fn revolve(kind: CellKind, nodes: &[usize], k: usize, rings: &Rings) -> Vec<usize> {
    let lo = |i: usize| rings.at(nodes[i], k);
    let hi = |i: usize| rings.at(nodes[i], k + 1);
    let mid = |i: usize| rings.mid(nodes[i], k);
    let mut v = Vec::with_capacity(27);
    match kind {
        CellKind::Tri3 => {
            v.extend((0..3).map(hi));
            v.extend((0..3).map(lo));
        }
        CellKind::Tri6 => {
            v.extend((0..3).map(hi));
            v.extend((0..3).map(lo));
            v.extend((3..6).map(hi));
            v.extend((3..6).map(lo));
            v.extend((0..3).map(mid));
        }
        CellKind::Quad4 => {
            v.extend((0..4).map(hi));
            v.extend((0..4).map(lo));
        }
        CellKind::Quad8 | CellKind::Quad9 => {
            v.extend((0..4).map(hi));
            v.extend((0..4).map(lo));
            v.extend((4..8).map(hi));
            v.extend((4..8).map(lo));
            v.extend((0..4).map(mid));
            if kind == CellKind::Quad9 {
                // Face centres: faces (0,4,7,3), (1,2,6,5), (0,1,5,4),
                // (3,2,6,7) hold meridional edges 3-0, 1-2, 0-1, 2-3; then
                // base (ring k+1) and top (ring k); then the centre.
                v.extend([7, 5, 4, 6].map(mid));
                v.push(hi(8));
                v.push(lo(8));
                v.push(mid(8));
            }
        }
    }
    v
}

/// Local nodes of a cell that need a mid-angle ring.
fn mid_ring_nodes(kind: CellKind) -> std::ops::Range<usize> {
    match kind {
        CellKind::Tri3 | CellKind::Quad4 => 0..0,
        CellKind::Tri6 | CellKind::Quad8 => 0..kind.n_corners(),
        CellKind::Quad9 => 0..9,
    }
}

/// Cartesian position of `(r, z)` at `theta`.
fn position(p: [f64; 2], theta: f64) -> [f64; 3] {
    let (s, c) = theta.sin_cos();
    [p[0] * c, p[0] * s, p[1]]
}

/// The cylindrical stress `(sr, sz, st, trz, trt, tzt)` as a Cartesian
/// tensor, row-major 3x3.
pub fn stress_to_cartesian(s: [f64; 6], theta: f64) -> [f64; 9] {
    let [sr, sz, st, trz, trt, tzt] = s;
    let (sn, c) = theta.sin_cos();
    let xx = sr * c * c + st * sn * sn - 2.0 * trt * sn * c;
    let yy = sr * sn * sn + st * c * c + 2.0 * trt * sn * c;
    let xy = (sr - st) * sn * c + trt * (c * c - sn * sn);
    let yz = trz * sn + tzt * c;
    let xz = trz * c - tzt * sn;
    [xx, xy, xz, xy, yy, yz, xz, yz, sz]
}

/// Von Mises equivalent of a cylindrical stress.
fn von_mises(s: [f64; 6]) -> f64 {
    let [sr, sz, st, trz, trt, tzt] = s;
    (0.5 * ((sr - sz).powi(2) + (sz - st).powi(2) + (st - sr).powi(2))
        + 3.0 * (trz * trz + trt * trt + tzt * tzt))
        .sqrt()
}

/// Stress of a body's nodes as trigonometric polynomials in theta: the
/// element-node values of every cell of the body, averaged per node, as the
/// coefficients `c_0, a_1, b_1, ..., a_M, b_M` of
/// `c_0 + sum a_m cos(m theta) + b_m sin(m theta)` (exact: the field has no
/// harmonic above M), from each harmonic's amplitude
/// ([`Field::stress_coefficients`]).
struct NodalStress {
    /// Number of coefficients, `2M + 1`.
    nc: usize,
    /// `coef[local node * nc + i]`.
    coef: Vec<[f64; 6]>,
}

impl NodalStress {
    fn new(field: &Field, body: usize, rings: &Rings) -> NodalStress {
        let initial = field.initial.as_ref().and_then(|i| i.u);
        let m_max = field
            .u
            .harmonics
            .iter()
            .chain(initial.iter().flat_map(|u| u.harmonics.iter()))
            .map(|h| h.m as usize)
            .max()
            .unwrap_or(0);
        let nc = 2 * m_max + 1;
        let mut coef = vec![[0.0; 6]; rings.nodes.len() * nc];
        let mut count = vec![0usize; rings.nodes.len()];
        for (c, cell) in field
            .mesh
            .cells
            .iter()
            .enumerate()
            .filter(|(_, c)| c.body == body)
        {
            for (&node, &xi) in cell.nodes.iter().zip(cell.kind.ref_coords()) {
                let l = rings.local[node];
                count[l] += 1;
                for (acc, q) in coef[l * nc..(l + 1) * nc]
                    .iter_mut()
                    .zip(field.stress_coefficients(c, xi, m_max))
                {
                    for (a, v) in acc.iter_mut().zip(q) {
                        *a += v;
                    }
                }
            }
        }
        for (l, &k) in count.iter().enumerate() {
            for c in &mut coef[l * nc..(l + 1) * nc] {
                for v in c.iter_mut() {
                    *v /= k.max(1) as f64;
                }
            }
        }
        NodalStress { nc, coef }
    }

    /// Averaged stress of local node `l` at the angle of `basis`
    /// ([`trig_basis`]).
    fn at(&self, l: usize, basis: &[f64]) -> [f64; 6] {
        let mut s = [0.0; 6];
        for (b, c) in basis.iter().zip(&self.coef[l * self.nc..(l + 1) * self.nc]) {
            for (acc, v) in s.iter_mut().zip(c) {
                *acc += b * v;
            }
        }
        s
    }
}

/// `1, cos t, sin t, cos 2t, sin 2t, ..., cos Mt, sin Mt`.
fn trig_basis(t: f64, m_max: usize) -> Vec<f64> {
    std::iter::once(1.0)
        .chain((1..=m_max).flat_map(move |m| {
            let (s, c) = (m as f64 * t).sin_cos();
            [c, s]
        }))
        .collect()
}

/// `(sin m t, cos m t)` for m = 0 ..= m_max ([`Displacements::at_trig`]).
///
/// [`Displacements::at_trig`]: axijoint_solver::solution::Displacements::at_trig
fn trig_pairs(t: f64, m_max: usize) -> Vec<(f64, f64)> {
    (0..=m_max).map(|m| (m as f64 * t).sin_cos()).collect()
}

/// Cartesian `(ux, uy, uz)` from `(u_r, u_z, u_theta)` at the angle whose
/// `(sin, cos)` is `sc`.
fn cartesian([ur, uz, ut]: [f64; 3], (s, c): (f64, f64)) -> [f64; 3] {
    [ur * c - ut * s, ur * s + ut * c, uz]
}

/// The revolved bodies, with the point arrays `fields`.
fn solid_grid(path: &Path, field: &Field, n: usize, fields: &[&str]) -> Result<Grid, ReportError> {
    let mesh = field.mesh;
    let want = |name: &str| fields.contains(&name);
    let needs_stress = ["stress", "sigma_cyl", "von_mises"].iter().any(|f| want(f));
    let mut g = Grid::default();
    let (mut disp, mut disp_cyl, mut stress, mut cyl, mut vm) = (vec![], vec![], vec![], vec![], vec![]);
    let (mut body_of, mut cell_of) = (vec![], vec![]);
    for body in 0..mesh.bodies.len() {
        let (mut used, mut needs_mid) = (vec![false; mesh.nodes.len()], vec![false; mesh.nodes.len()]);
        for cell in mesh.cells.iter().filter(|c| c.body == body) {
            for &node in &cell.nodes {
                used[node] = true;
            }
            for i in mid_ring_nodes(cell.kind) {
                needs_mid[cell.nodes[i]] = true;
            }
        }
        let nodes: Vec<usize> = (0..mesh.nodes.len()).filter(|&i| used[i]).collect();
        let mids: Vec<usize> = (0..mesh.nodes.len()).filter(|&i| needs_mid[i]).collect();
        let rings = Rings::new(n, g.n_points(), mesh.nodes.len(), nodes, mids);
        let nodal = needs_stress.then(|| NodalStress::new(field, body, &rings));
        let m_disp = field.u.harmonics.iter().map(|h| h.m as usize).max().unwrap_or(0);
        let m_stress = nodal.as_ref().map_or(0, |st| (st.nc - 1) / 2);
        // The points ring by ring: the trigonometric values once per angle.
        let mut ring_start = g.n_points();
        for (theta, nodes) in rings.by_angle() {
            let (trig, basis) = (trig_pairs(theta, m_disp), trig_basis(theta, m_stress));
            let (sc, mut finite) = (theta.sin_cos(), true);
            for &node in nodes {
                let p = mesh.nodes[node];
                let x = [p[0] * sc.1, p[0] * sc.0, p[1]];
                let uc = field.u.at_trig(node, &trig);
                let u = cartesian(uc, sc);
                let s = nodal
                    .as_ref()
                    .map_or([0.0; 6], |st| st.at(rings.local[node], &basis));
                finite &= x.iter().chain(&u).chain(&s).all(|v| v.is_finite());
                g.points.extend(x);
                disp.extend(u);
                disp_cyl.extend(uc);
                if want("stress") {
                    stress.extend(stress_to_cartesian(s, theta));
                }
                cyl.extend(s);
                vm.push(von_mises(s));
            }
            if !finite {
                // The first point of the ring with a value that is not.
                let bad = (ring_start..g.n_points())
                    .zip(nodes)
                    .find(|&(i, _)| {
                        let at = |v: &[f64], k: usize| v[k * i..k * i + k].iter().all(|x| x.is_finite());
                        !(at(&g.points, 3) && at(&disp, 3) && at(&cyl, 6))
                    })
                    .map_or(nodes[0], |(_, &node)| node);
                return Err(ReportError::NotFinite {
                    path: path.to_path_buf(),
                    what: format!(
                        "a value at node {} (r = {}, z = {}) of body '{}', theta = {} deg",
                        bad,
                        mesh.nodes[bad][0],
                        mesh.nodes[bad][1],
                        mesh.bodies[body].name,
                        theta.to_degrees()
                    ),
                });
            }
            ring_start = g.n_points();
        }
        debug_assert_eq!(g.n_points(), rings.base + rings.len());
        for (c, cell) in mesh.cells.iter().enumerate().filter(|(_, c)| c.body == body) {
            let (t, _) = revolved_cell_type(cell.kind);
            for k in 0..n {
                g.push_cell(t, &revolve(cell.kind, &cell.nodes, k, &rings));
                body_of.push(body as i32);
                cell_of.push(c as i64);
            }
        }
    }
    g.point_data = [
        Array::f64("displacement", 3, disp),
        Array::f64("displacement_cyl", 3, disp_cyl).named(&["u_r", "u_z", "u_theta"]),
        Array::f64("stress", 9, stress),
        Array::f64("sigma_cyl", 6, cyl).named(&STRESS_NAMES),
        Array::f64("von_mises", 1, vm),
    ]
    .into_iter()
    .filter(|a| want(a.name))
    .collect();
    g.cell_data = vec![
        Array {
            name: "body",
            components: 1,
            component_names: &[],
            values: Values::I32(body_of),
        },
        Array {
            name: "meridional_cell",
            components: 1,
            component_names: &[],
            values: Values::I64(cell_of),
        },
    ];
    Ok(g)
}

// ---------------------------------------------------------------------------
// Joints.

/// Joint state code: 0 stick, 1 slip, 2 open.
pub fn state_code(s: JointState) -> i32 {
    match s {
        JointState::Stick => 0,
        JointState::Slip => 1,
        JointState::Open => 2,
    }
}

/// Maps an angle to a section of the joint field: `(section, mirrored)`.
struct SectionMap {
    theta: Vec<f64>,
    half: bool,
}

impl SectionMap {
    fn new(jf: &JointFieldFile) -> SectionMap {
        let theta: Vec<f64> = jf.sections_deg.iter().map(|d| d.to_radians()).collect();
        // A half-circle set is recognised by its weights (each interior
        // section stands for +theta and -theta).
        let half = Sections::half_circle(theta.clone()).is_ok_and(|s| {
            s.weight.len() == jf.section_weights.len()
                && s.weight
                    .iter()
                    .zip(&jf.section_weights)
                    .all(|(a, b)| (a - b).abs() <= 1e-9 * (1.0 + b.abs()))
        });
        SectionMap { theta, half }
    }

    fn nearest(&self, t: f64) -> (usize, bool) {
        let t = t.rem_euclid(2.0 * PI);
        let (t, mirrored) = if self.half && t > PI {
            (2.0 * PI - t, true)
        } else {
            (t, false)
        };
        let dist = |a: f64| {
            if self.half {
                (a - t).abs()
            } else {
                let d = (a - t).rem_euclid(2.0 * PI);
                d.min(2.0 * PI - d)
            }
        };
        let best = (0..self.theta.len())
            .min_by(|&a, &b| dist(self.theta[a]).total_cmp(&dist(self.theta[b])))
            .unwrap_or(0);
        (best, mirrored)
    }
}

/// The revolved joint surfaces.
fn joint_grid(path: &Path, field: &Field, n: usize, jf: &JointFieldFile) -> Result<Grid, ReportError> {
    let mesh: &Mesh = field.mesh;
    let bad = |m: String| ReportError::Input(format!("{}: joint field: {m}", path.display()));
    if jf.sections_deg.is_empty() || jf.values.len() != jf.sections_deg.len() {
        return Err(bad(format!(
            "{} sections, {} rows of values",
            jf.sections_deg.len(),
            jf.values.len()
        )));
    }
    if let Some(s) = jf.values.iter().position(|v| v.len() != jf.points.len()) {
        return Err(bad(format!(
            "section {s} has {} values for {} points",
            jf.values[s].len(),
            jf.points.len()
        )));
    }
    // Integration points of each (joint, element).
    let mut points_of: Vec<Vec<Vec<usize>>> = mesh
        .joints
        .iter()
        .map(|j| vec![vec![]; j.elements.len()])
        .collect();
    for (i, p) in jf.points.iter().enumerate() {
        let j = mesh
            .joints
            .iter()
            .position(|j| j.name == p.joint)
            .ok_or_else(|| bad(format!("no joint '{}' in the mesh", p.joint)))?;
        let slot = points_of[j]
            .get_mut(p.element)
            .ok_or_else(|| bad(format!("joint '{}' has no element {}", p.joint, p.element)))?;
        slot.push(i);
    }
    let map = SectionMap::new(jf);
    let mut g = Grid::default();
    let (mut disp, mut disp_top) = (vec![], vec![]);
    let mut cd = JointCellData::default();
    for (j, joint) in mesh.joints.iter().enumerate() {
        // Rings of the bottom-face nodes; top partners for the displacement.
        let mut top_of = vec![usize::MAX; mesh.nodes.len()];
        let (mut used, mut needs_mid) = (vec![false; mesh.nodes.len()], vec![false; mesh.nodes.len()]);
        for e in &joint.elements {
            for (&b, &t) in e.bottom.iter().zip(&e.top) {
                used[b] = true;
                top_of[b] = t;
            }
            if e.kind == JointKind::Lin6 {
                for &b in &e.bottom {
                    needs_mid[b] = true;
                }
            }
        }
        let nodes: Vec<usize> = (0..mesh.nodes.len()).filter(|&i| used[i]).collect();
        let mids: Vec<usize> = (0..mesh.nodes.len()).filter(|&i| needs_mid[i]).collect();
        let rings = Rings::new(n, g.n_points(), mesh.nodes.len(), nodes, mids);
        for (node, theta) in rings.points() {
            let x = position(mesh.nodes[node], theta);
            let ub = field.displacement_xyz(node, theta);
            let ut = field.displacement_xyz(top_of[node], theta);
            check_finite(path, &[x.as_slice(), &ub, &ut].concat(), || {
                format!(
                    "a displacement on joint '{}' at theta = {} deg",
                    joint.name,
                    theta.to_degrees()
                )
            })?;
            g.points.extend(x);
            disp.extend(ub);
            disp_top.extend(ut);
        }
        for (e, el) in joint.elements.iter().enumerate() {
            let b = &el.bottom;
            for k in 0..n {
                let (lo, hi) = (|i: usize| rings.at(b[i], k), |i: usize| rings.at(b[i], k + 1));
                match el.kind {
                    JointKind::Lin4 => g.push_cell(cell_type::QUAD, &[lo(0), lo(1), hi(1), hi(0)]),
                    JointKind::Lin6 => {
                        let mid = |i: usize| rings.mid(b[i], k);
                        g.push_cell(
                            cell_type::BIQUADRATIC_QUAD,
                            &[lo(0), lo(1), hi(1), hi(0), lo(2), mid(1), hi(2), mid(0), mid(2)],
                        );
                    }
                }
                let (section, mirrored) = map.nearest(mid_angle(k, n));
                cd.push(path, jf, &points_of[j][e], section, mirrored, j, e, &joint.name)?;
            }
        }
    }
    g.point_data = vec![
        Array::f64("displacement", 3, disp),
        Array::f64("displacement_top", 3, disp_top),
    ];
    g.cell_data = cd.into_arrays();
    Ok(g)
}

/// Cell data of the joint file.
#[derive(Default)]
struct JointCellData {
    state: Vec<i32>,
    open_fraction: Vec<f64>,
    slip_fraction: Vec<f64>,
    opening: Vec<f64>,
    slip: Vec<f64>,
    sigma_n: Vec<f64>,
    tau_xi: Vec<f64>,
    tau_theta: Vec<f64>,
    d: Vec<f64>,
    section_deg: Vec<f64>,
    joint: Vec<i32>,
    element: Vec<i32>,
}

impl JointCellData {
    /// Adds the cell of element `e` of joint `j` at `section`.
    #[allow(clippy::too_many_arguments)]
    fn push(
        &mut self,
        path: &Path,
        jf: &JointFieldFile,
        points: &[usize],
        section: usize,
        mirrored: bool,
        j: usize,
        e: usize,
        name: &str,
    ) -> Result<(), ReportError> {
        let values = &jf.values[section];
        let total_da: f64 = points.iter().map(|&i| jf.points[i].da.max(0.0)).sum();
        let weight = |i: usize| {
            if total_da > 0.0 {
                jf.points[i].da.max(0.0) / total_da
            } else {
                1.0 / points.len().max(1) as f64
            }
        };
        let mut share = [0.0; 3];
        let (mut opening, mut slip) = (0.0, 0.0);
        let (mut p, mut d) = ([0.0; 3], [0.0; 3]);
        for &i in points {
            let (v, w) = (&values[i], weight(i));
            share[state_code(v.state) as usize] += w;
            opening += w * v.opening;
            slip += w * v.slip;
            for a in 0..3 {
                p[a] += w * v.p[a];
                d[a] += w * v.d[a];
            }
        }
        if mirrored {
            p[2] = -p[2];
            d[2] = -d[2];
        }
        check_finite(path, &[opening, slip, p[0], p[1], p[2], d[0], d[1], d[2]], || {
            format!(
                "a value of joint '{name}', element {e}, section {} deg",
                jf.sections_deg[section]
            )
        })?;
        // Largest share; ties to the more severe state.
        let state = (0..3)
            .rev()
            .max_by(|&a, &b| share[a].total_cmp(&share[b]))
            .unwrap_or(0);
        self.state.push(if points.is_empty() { 0 } else { state as i32 });
        self.open_fraction.push(share[2]);
        self.slip_fraction.push(share[1]);
        self.opening.push(opening);
        self.slip.push(slip);
        self.sigma_n.push(p[1]);
        self.tau_xi.push(p[0]);
        self.tau_theta.push(p[2]);
        self.d.extend(d);
        self.section_deg.push(jf.sections_deg[section]);
        self.joint.push(j as i32);
        self.element.push(e as i32);
        Ok(())
    }

    fn into_arrays(self) -> Vec<Array> {
        let int = |name, v| Array {
            name,
            components: 1,
            component_names: &[],
            values: Values::I32(v),
        };
        vec![
            int("state", self.state),
            Array::f64("opening", 1, self.opening),
            Array::f64("slip", 1, self.slip),
            Array::f64("sigma_n", 1, self.sigma_n),
            Array::f64("tau_xi", 1, self.tau_xi),
            Array::f64("tau_theta", 1, self.tau_theta),
            Array::f64("d", 3, self.d).named(&["d_xi", "d_eta", "d_theta"]),
            Array::f64("open_fraction", 1, self.open_fraction),
            Array::f64("slip_fraction", 1, self.slip_fraction),
            Array::f64("section_deg", 1, self.section_deg),
            int("joint", self.joint),
            int("element", self.element),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The zlib encoding reads back, for no data, one partial block, whole
    /// blocks only, and whole blocks and a partial one.
    #[test]
    fn compressed_arrays_read_back() {
        for len in [0, 5, BLOCK, 2 * BLOCK, 3 * BLOCK + 17] {
            let data: Vec<u8> = (0..len).map(|i| (i * 7 % 251) as u8).collect();
            assert_eq!(
                decode_array(&compress(&data).unwrap()).unwrap(),
                data,
                "{len} bytes"
            );
        }
    }

    /// Sections for the highest harmonic: 8 samples of the turn per period
    /// of harmonic M, 16 at least.
    #[test]
    fn automatic_sections() {
        assert_eq!(samples_per_turn(0), 16);
        assert_eq!(samples_per_turn(1), 16);
        assert_eq!(samples_per_turn(2), 16);
        assert_eq!(samples_per_turn(4), 32);
        assert_eq!(samples_per_turn(5), 40);
    }
}
