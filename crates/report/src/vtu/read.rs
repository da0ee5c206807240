//! Reading a `.vtu` back as [`write_vtu`](super::write_vtu) writes it, for
//! checks and tests without a VTK library.

use quick_xml::events::{BytesStart, Event};
use std::path::Path;

fn invalid(m: impl Into<String>) -> std::io::Error {
    std::io::Error::new(std::io::ErrorKind::InvalidData, m.into())
}

/// The bytes of one array of the appended data as [`write_vtu`](super::write_vtu) writes it
/// with [`Encoding::Zlib`](super::Encoding::Zlib) (UInt64 header, zlib blocks), `data` starting at
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

/// The bytes of one array of the appended data as [`write_vtu`](super::write_vtu) writes it
/// with [`Encoding::Raw`](super::Encoding::Raw): its UInt64 byte count, then the bytes.
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

/// A `.vtu` written by [`write_vtu`](super::write_vtu), read back.
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

/// Reads a `.vtu` as [`write_vtu`](super::write_vtu) writes it (one piece, raw appended
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vtu::encoding::{compress, BLOCK};

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
}
