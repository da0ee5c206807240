//! Reading gmsh `.msh` files: MSH 4.1 (ASCII and binary) and MSH 2.2 (ASCII);
//! writing a mesh with its joints as MSH 4.1 ASCII ([`write_msh41`]).
//!
//! [`parse_msh`] turns the bytes into an [`MshFile`] (what the file says,
//! format differences removed); [`MshFile::to_mesh`] makes the [`Mesh`] of
//! axijoint from it; [`read_msh`] does both for a file on disk.
//!
//! | section | read as |
//! |---|---|
//! | `$MeshFormat` | [`MshFormat`]; must come before any data section |
//! | `$PhysicalNames` | [`PhysicalName`]s |
//! | `$Entities` (4.1) | [`Entity`]s with their physical tags |
//! | `$Nodes`, `$Elements` | nodes and [`RawElement`]s (sections may repeat) |
//! | anything else | skipped up to its `$End...` line |
//!
//! The parser never panics and never trusts a count in the file for an
//! allocation; every error names the file and a 1-based line (for binary
//! data: the line of the section header, and the byte offset).

mod convert;
mod cursor;
pub mod element_type;
mod types;
mod v22;
mod v41;
mod write;

use crate::{Mesh, MeshError};
use cursor::{quote, Cursor};
use std::collections::{HashMap, HashSet};
use std::path::Path;
pub use write::{joint_quads, write_msh41};

/// The flavour of a `.msh` file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MshFormat {
    /// MSH 4.1, ASCII.
    V41Ascii,
    /// MSH 4.1, binary (`$MeshFormat` says `4.1 1 8`).
    V41Binary,
    /// MSH 2.2, ASCII.
    V22Ascii,
}

/// An entry of `$PhysicalNames`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PhysicalName {
    /// Dimension of the physical group: 0 point, 1 curve, 2 surface, 3 volume.
    pub dim: i32,
    /// Physical tag.
    pub tag: i32,
    /// The name, without quotes.
    pub name: String,
}

/// A model entity of `$Entities` (MSH 4.1 only).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entity {
    /// Dimension: 0 point, 1 curve, 2 surface, 3 volume.
    pub dim: i32,
    /// Entity tag.
    pub tag: i32,
    /// Physical groups (of the same dimension) the entity belongs to.
    pub physical_tags: Vec<i32>,
}

/// An element as the file gives it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RawElement {
    /// Element tag.
    pub tag: u64,
    /// gmsh element type (2 = 3-node triangle, ...).
    pub gmsh_type: i32,
    /// Dimension of the entity the element is classified on (2.2: of the
    /// element type).
    pub entity_dim: i32,
    /// Tag of that entity (0 if a 2.2 file gives none).
    pub entity_tag: i32,
    /// Physical groups of the element: its entity's (4.1), or the physical
    /// tag of each copy of the element (2.2, where gmsh writes an element in
    /// several groups once per group; the copies are merged into this one).
    pub physical_tags: Vec<i32>,
    /// Node tags, in gmsh order.
    pub nodes: Vec<u64>,
    /// 1-based line of the element (binary: of its `$Elements` header).
    pub line: usize,
}

/// A `.msh` file as read, before any interpretation.
#[derive(Clone, Debug, PartialEq)]
pub struct MshFile {
    /// Version and encoding.
    pub format: MshFormat,
    /// `$PhysicalNames`, in file order.
    pub physical_names: Vec<PhysicalName>,
    /// `$Entities`, in file order (empty for 2.2).
    pub entities: Vec<Entity>,
    /// `(tag, [x, y, z])` of every node, in file order.
    pub nodes: Vec<(u64, [f64; 3])>,
    /// Every element, in file order.
    pub elements: Vec<RawElement>,
}

/// What the section parsers build up.
struct Builder {
    format: MshFormat,
    physical_names: Vec<PhysicalName>,
    entities: Vec<Entity>,
    /// `(dim, tag)` -> index into `entities`.
    entity_index: HashMap<(i32, i32), usize>,
    has_entities: bool,
    nodes: Vec<(u64, [f64; 3])>,
    /// Node tag -> line where it was defined.
    node_lines: HashMap<u64, usize>,
    elements: Vec<RawElement>,
    /// Element tag -> line where it was defined.
    element_lines: HashMap<u64, usize>,
    /// MSH 2.2: (type, entity, nodes) -> index into `elements`, to merge
    /// the copies gmsh writes of an element in several physical groups.
    v22_copies: HashMap<(i32, i32, Vec<u64>), usize>,
    /// MSH 2.2: (index into `elements`, physical tag) seen.
    v22_groups: HashSet<(usize, i32)>,
    has_nodes: bool,
    has_elements: bool,
    /// A `$PartitionedEntities` section was skipped.
    partitioned: bool,
}

impl Builder {
    fn new(format: MshFormat) -> Self {
        Builder {
            format,
            physical_names: Vec::new(),
            entities: Vec::new(),
            entity_index: HashMap::new(),
            has_entities: false,
            nodes: Vec::new(),
            node_lines: HashMap::new(),
            elements: Vec::new(),
            element_lines: HashMap::new(),
            v22_copies: HashMap::new(),
            v22_groups: HashSet::new(),
            has_nodes: false,
            has_elements: false,
            partitioned: false,
        }
    }

    /// Registers a node tag read on `line`, rejecting 0 and duplicates.
    fn claim_node_tag(&mut self, cur: &Cursor, tag: u64, line: usize) -> Result<(), MeshError> {
        if tag == 0 {
            return Err(cur.error_on(line, "node tag 0 (tags must be positive)"));
        }
        if let Some(first) = self.node_lines.insert(tag, line) {
            return Err(cur.error_on(
                line,
                format!("duplicate node tag {tag} (first defined at line {first})"),
            ));
        }
        Ok(())
    }

    /// Registers an element tag read on `line`, rejecting 0 and duplicates.
    fn claim_element_tag(&mut self, cur: &Cursor, tag: u64, line: usize) -> Result<(), MeshError> {
        if tag == 0 {
            return Err(cur.error_on(line, "element tag 0 (tags must be positive)"));
        }
        if let Some(first) = self.element_lines.insert(tag, line) {
            return Err(cur.error_on(
                line,
                format!("duplicate element tag {tag} (first defined at line {first})"),
            ));
        }
        Ok(())
    }

    /// Gives each 4.1 element the physical tags of its entity.
    ///
    /// The copies may not hold more tags in all than the file has bytes:
    /// a corrupt entity with a huge tag list would otherwise multiply its
    /// size by the number of its elements.
    fn resolve_entities(&mut self, path: &Path, file_len: usize) -> Result<(), MeshError> {
        if self.format == MshFormat::V22Ascii || !self.has_entities {
            return Ok(());
        }
        let mut total: usize = 0;
        for el in &self.elements {
            let n = self
                .entity_index
                .get(&(el.entity_dim, el.entity_tag))
                .and_then(|&i| self.entities.get(i))
                .map_or(0, |e| e.physical_tags.len());
            total = total.saturating_add(n);
            if total > file_len {
                return Err(MeshError::Parse {
                    path: path.to_path_buf(),
                    line: el.line,
                    message: format!(
                        "{} entity {} gives its elements implausibly many physical tags ({n} each)",
                        dim_word(el.entity_dim),
                        el.entity_tag
                    ),
                });
            }
        }
        for el in &mut self.elements {
            let Some(&i) = self.entity_index.get(&(el.entity_dim, el.entity_tag)) else {
                return Err(MeshError::Parse {
                    path: path.to_path_buf(),
                    line: el.line,
                    message: format!(
                        "element {} is on {} entity {}, which $Entities does not list{}",
                        el.tag,
                        dim_word(el.entity_dim),
                        el.entity_tag,
                        if self.partitioned {
                            " (partitioned meshes are not supported: mesh without -part)"
                        } else {
                            ""
                        }
                    ),
                });
            };
            if let Some(entity) = self.entities.get(i) {
                el.physical_tags.clone_from(&entity.physical_tags);
            }
        }
        Ok(())
    }
}

/// Prefixes the message of a parse error with `context`.
fn with_context(e: MeshError, context: impl FnOnce() -> String) -> MeshError {
    match e {
        MeshError::Parse { path, line, message } => MeshError::Parse {
            path,
            line,
            message: format!("{}: {message}", context()),
        },
        other => other,
    }
}

/// "point", "curve", "surface" or "volume".
fn dim_word(dim: i32) -> &'static str {
    match dim {
        0 => "point",
        1 => "curve",
        2 => "surface",
        3 => "volume",
        _ => "entity",
    }
}

/// Parses the bytes of a `.msh` file; `path` only names the file in errors.
///
/// ```
/// use axijoint_mesh::{msh::MshFormat, parse_msh};
/// let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n\
///             $Nodes\n1\n7 0.5 1 0\n$EndNodes\n$Elements\n1\n3 15 2 4 1 7\n$EndElements\n";
/// let msh = parse_msh(text.as_bytes(), "p.msh".as_ref()).unwrap();
/// assert_eq!(msh.format, MshFormat::V22Ascii);
/// assert_eq!(msh.nodes, vec![(7, [0.5, 1.0, 0.0])]);
/// assert_eq!(msh.elements[0].physical_tags, vec![4]);
/// ```
pub fn parse_msh(bytes: &[u8], path: &Path) -> Result<MshFile, MeshError> {
    let mut cur = Cursor::new(bytes, path);
    let mut builder: Option<Builder> = None;
    while let Some((header, line)) = cur.next_line() {
        let Some(name) = header.strip_prefix(b"$") else {
            return Err(cur.error_at(
                line,
                format!(
                    "expected a section header such as $Nodes, found '{}'",
                    quote(header)
                ),
            ));
        };
        if name.starts_with(b"End") {
            return Err(cur.error_at(line, format!("'{}' closes a section never opened", quote(header))));
        }
        let Some(b) = builder.as_mut() else {
            match name {
                b"MeshFormat" => {
                    let format = read_mesh_format(&mut cur, line)?;
                    builder = Some(Builder::new(format));
                }
                b"PhysicalNames" | b"Entities" | b"Nodes" | b"Elements" => {
                    return Err(cur.error_at(
                        line,
                        format!(
                            "missing $MeshFormat: the file must start with it, not ${}",
                            quote(name)
                        ),
                    ))
                }
                _ => cur.skip_section(name, line)?,
            }
            continue;
        };
        let binary = b.format == MshFormat::V41Binary;
        match (name, b.format) {
            (b"MeshFormat", _) => {
                return Err(cur.error_at(line, "second $MeshFormat section"));
            }
            (b"PhysicalNames", _) => read_physical_names(&mut cur, b, line)?,
            (b"Entities", MshFormat::V41Ascii | MshFormat::V41Binary) => {
                in_section(&mut cur, binary, "Entities", line, |c| v41::read_entities(c, b))?;
            }
            (b"Nodes", MshFormat::V41Ascii | MshFormat::V41Binary) => {
                in_section(&mut cur, binary, "Nodes", line, |c| v41::read_nodes(c, b))?;
            }
            (b"Elements", MshFormat::V41Ascii | MshFormat::V41Binary) => {
                in_section(&mut cur, binary, "Elements", line, |c| {
                    v41::read_elements(c, b, line)
                })?;
            }
            (b"Nodes", MshFormat::V22Ascii) => {
                in_section(&mut cur, false, "Nodes", line, |c| v22::read_nodes(c, b))?;
            }
            (b"Elements", MshFormat::V22Ascii) => {
                in_section(&mut cur, false, "Elements", line, |c| v22::read_elements(c, b))?;
            }
            _ => {
                b.partitioned |= name == b"PartitionedEntities";
                cur.skip_section(name, line)?;
            }
        }
    }
    let end_line = cur.line();
    let Some(mut b) = builder else {
        return Err(cur.error_at(
            end_line,
            "missing $MeshFormat section (is this a gmsh .msh file?)",
        ));
    };
    if !b.has_nodes {
        return Err(cur.error_at(end_line, "the file has no $Nodes section"));
    }
    if !b.has_elements {
        return Err(cur.error_at(end_line, "the file has no $Elements section"));
    }
    b.resolve_entities(path, bytes.len())?;
    Ok(MshFile {
        format: b.format,
        physical_names: b.physical_names,
        entities: b.entities,
        nodes: b.nodes,
        elements: b.elements,
    })
}

/// Runs `body` on the data of section `name` (header on `line`) and checks
/// its `$End` line; binary sections switch the cursor to binary meanwhile.
fn in_section<'a>(
    cur: &mut Cursor<'a>,
    binary: bool,
    name: &str,
    line: usize,
    body: impl FnOnce(&mut Cursor<'a>) -> Result<(), MeshError>,
) -> Result<(), MeshError> {
    if binary {
        cur.begin_binary(line);
    } else {
        cur.skip_whitespace();
    }
    let result = body(cur);
    cur.end_binary();
    result?;
    cur.expect_end(name, line)
}

/// Reads `$MeshFormat` (header on `line`) up to and including its `$End`.
fn read_mesh_format(cur: &mut Cursor, line: usize) -> Result<MshFormat, MeshError> {
    cur.skip_whitespace();
    let version_tok = cur.token().unwrap_or(&[]);
    let version_line = cur.line();
    let version: Option<f64> = std::str::from_utf8(version_tok).ok().and_then(|s| s.parse().ok());
    let file_type: i32 = cur.parse("the file type (0 ASCII, 1 binary)")?;
    let data_size: i64 = cur.parse("the data size")?;
    let binary = match file_type {
        0 => false,
        1 => true,
        other => return Err(cur.error(format!("file type {other} is neither 0 (ASCII) nor 1 (binary)"))),
    };
    let format = match (version, binary) {
        (Some(4.1), false) => MshFormat::V41Ascii,
        (Some(4.1), true) => MshFormat::V41Binary,
        (Some(2.2), false) => MshFormat::V22Ascii,
        (Some(2.2), true) => {
            return Err(cur.error_at(
                version_line,
                "MSH 2.2 binary is not supported: save as MSH 4.1 (gmsh -format msh41 [-bin]) \
                 or MSH 2.2 ASCII",
            ))
        }
        _ => {
            return Err(cur.error_at(
                version_line,
                format!(
                    "unsupported MSH version '{}' (this reader handles 4.1 ASCII and binary, \
                     and 2.2 ASCII; re-save with gmsh -format msh41)",
                    quote(version_tok)
                ),
            ))
        }
    };
    if binary {
        if data_size != 8 {
            return Err(cur.error(format!(
                "binary data-size {data_size} is not supported: size_t must be 8 bytes \
                 (a file written by a 64-bit gmsh)"
            )));
        }
        cur.end_of_line(|| "the $MeshFormat line".to_string())?;
        let check_line = cur.line();
        cur.begin_binary(line);
        let one = cur.take(4, "the endianness check (the int 1)");
        cur.end_binary();
        match one? {
            [1, 0, 0, 0] => {}
            [0, 0, 0, 1] => {
                return Err(cur.error_at(
                    check_line,
                    "the file is big-endian (the endianness check reads 1 backwards): \
                     not supported, re-save it as ASCII",
                ))
            }
            other => {
                return Err(cur.error_at(
                    check_line,
                    format!("endianness check: expected the int 1, found bytes {other:02x?}"),
                ))
            }
        }
    } else if data_size <= 0 {
        return Err(cur.error(format!("data size {data_size} must be positive")));
    } else {
        cur.end_of_line(|| "the $MeshFormat line".to_string())?;
    }
    cur.expect_end("MeshFormat", line)?;
    Ok(format)
}

/// Reads `$PhysicalNames` (ASCII in every format) and its `$End`.
fn read_physical_names(cur: &mut Cursor, b: &mut Builder, line: usize) -> Result<(), MeshError> {
    cur.skip_whitespace();
    let count: u64 = cur.parse("the number of physical names")?;
    cur.end_of_record(|| "the number of physical names".to_string())?;
    let mut names = Vec::with_capacity(cur.capacity(count, 6));
    for _ in 0..count {
        let dim: i32 = cur.parse("a physical dimension (0-3)")?;
        if !(0..=3).contains(&dim) {
            return Err(cur.error(format!("physical dimension {dim} is not 0, 1, 2 or 3")));
        }
        let tag: i32 = cur.parse("a physical tag")?;
        let (rest, name_line) = cur.rest_of_line().unwrap_or((&[], cur.line()));
        let rest = cursor::trim(rest);
        let name = match rest {
            [b'"', inner @ .., b'"'] => inner,
            [b'"', ..] => {
                return Err(cur.error_at(name_line, format!("unterminated quoted name '{}'", quote(rest))));
            }
            _ if rest.is_empty() => {
                return Err(cur.error_at(name_line, format!("physical {} {tag} has no name", dim_word(dim))));
            }
            _ => rest,
        };
        names.push(PhysicalName {
            dim,
            tag,
            name: String::from_utf8_lossy(name).into_owned(),
        });
        cur.skip_whitespace();
    }
    cur.expect_end("PhysicalNames", line)?;
    b.physical_names.extend(names);
    Ok(())
}

/// Reads and converts the `.msh` file at `path`.
///
/// Errors: [`MeshError::Io`] if it cannot be read, then those of
/// [`parse_msh`] and [`MshFile::to_mesh`].
pub fn read_msh(path: &Path) -> Result<Mesh, MeshError> {
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_msh(&bytes, path)?.to_mesh(path)
}
