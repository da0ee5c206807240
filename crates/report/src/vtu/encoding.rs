//! Writing a grid: data arrays, the XML, and the appended data, raw or
//! zlib-compressed as VTK does (see the [`vtu`](super) documentation).

use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, Event};
use quick_xml::Writer;
use std::io::Write;

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
pub(super) enum Values {
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
pub(super) struct Array {
    pub(super) name: &'static str,
    pub(super) components: usize,
    pub(super) component_names: &'static [&'static str],
    pub(super) values: Values,
}

impl Array {
    pub(super) fn f64(name: &'static str, components: usize, values: Vec<f64>) -> Array {
        Array {
            name,
            components,
            component_names: &[],
            values: Values::F64(values),
        }
    }

    pub(super) fn named(mut self, names: &'static [&'static str]) -> Array {
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
pub(super) struct Grid {
    pub(super) points: Vec<f64>,
    connectivity: Vec<i64>,
    offsets: Vec<i64>,
    types: Vec<u8>,
    pub(super) point_data: Vec<Array>,
    pub(super) cell_data: Vec<Array>,
}

impl Grid {
    pub(super) fn push_cell(&mut self, vtk_type: u8, nodes: &[usize]) {
        self.connectivity.extend(nodes.iter().map(|&n| n as i64));
        self.offsets.push(self.connectivity.len() as i64);
        self.types.push(vtk_type);
    }

    pub(super) fn n_points(&self) -> usize {
        self.points.len() / 3
    }

    pub(super) fn write(&self, out: &mut impl Write, encoding: Encoding) -> std::io::Result<()> {
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
pub(super) const BLOCK: usize = 1 << 15;

/// `bytes` as a `vtkZLibDataCompressor` array: the UInt64 header
/// `[nb][nu][np][nc_1 .. nc_nb]`, then the zlib blocks, compressed in
/// parallel at zlib's fastest level (Float64 data barely compresses more
/// at the default level, docs/outputs.md).
pub(super) fn compress(bytes: &[u8]) -> std::io::Result<Vec<u8>> {
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
