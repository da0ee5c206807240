//! `$Entities`, `$Nodes` and `$Elements` of MSH 4.1, ASCII or binary: the
//! same code reads both, the cursor's mode decides how a value is decoded.

use super::cursor::Cursor;
use super::types::type_info;
use super::{dim_word, Builder, Entity, RawElement};
use crate::MeshError;

/// A size_t (counts, node and element tags).
fn size(cur: &mut Cursor, what: &str) -> Result<u64, MeshError> {
    if cur.is_binary() {
        cur.bin_u64(what)
    } else {
        cur.parse(what)
    }
}

/// An int (dimensions, entity, physical and type tags).
fn int(cur: &mut Cursor, what: &str) -> Result<i32, MeshError> {
    if cur.is_binary() {
        cur.bin_i32(what)
    } else {
        cur.parse(what)
    }
}

/// A double.
fn float(cur: &mut Cursor, what: &str) -> Result<f64, MeshError> {
    if cur.is_binary() {
        cur.bin_f64(what)
    } else {
        cur.parse_f64(what)
    }
}

/// End of an ASCII record (one per line); nothing to check in binary.
fn end_record(cur: &mut Cursor, what: impl FnOnce() -> String) -> Result<(), MeshError> {
    if cur.is_binary() {
        Ok(())
    } else {
        cur.end_of_record(what)
    }
}

/// Fewest bytes an item takes: its binary size, or 2 in ASCII (a digit and
/// a separator). Caps allocations by what the file can still hold.
fn min_bytes(cur: &Cursor, binary: usize) -> usize {
    if cur.is_binary() {
        binary
    } else {
        2
    }
}

/// In binary, fails early if `count` items of `item_bytes` cannot fit in the
/// rest of the file.
fn check_room(cur: &Cursor, count: u64, item_bytes: u64, what: &str) -> Result<(), MeshError> {
    if !cur.is_binary() {
        return Ok(());
    }
    let needed = count.checked_mul(item_bytes);
    match needed {
        Some(n) if n <= cur.remaining() as u64 => Ok(()),
        _ => Err(cur.error(format!(
            "file truncated: {count} {what} need {} bytes, {} left",
            needed.map_or_else(|| "too many".to_string(), |n| n.to_string()),
            cur.remaining()
        ))),
    }
}

/// A dimension 0..=3.
fn dim(cur: &mut Cursor, what: &str) -> Result<i32, MeshError> {
    let d = int(cur, what)?;
    if (0..=3).contains(&d) {
        Ok(d)
    } else {
        Err(cur.error(format!("{what} {d} is not 0, 1, 2 or 3")))
    }
}

/// `$Entities`: points, curves, surfaces and volumes with their physical tags.
pub(super) fn read_entities(cur: &mut Cursor, b: &mut Builder) -> Result<(), MeshError> {
    let mut counts = [0u64; 4];
    for (d, count) in counts.iter_mut().enumerate() {
        *count = size(cur, &format!("the number of {} entities", dim_word(d as i32)))?;
    }
    end_record(cur, || "the entity counts".to_string())?;
    for (d, &count) in (0i32..).zip(counts.iter()) {
        for _ in 0..count {
            let tag = int(cur, "an entity tag")?;
            let line = cur.token_line();
            // A point gives its coordinates, other entities a bounding box.
            for _ in 0..if d == 0 { 3 } else { 6 } {
                float(cur, "an entity coordinate")?;
            }
            let n_phys = size(cur, "the number of physical tags")?;
            let mut physical_tags = Vec::with_capacity(cur.capacity(n_phys, min_bytes(cur, 4)));
            for _ in 0..n_phys {
                physical_tags.push(int(cur, "a physical tag")?);
            }
            if d > 0 {
                let n_bound = size(cur, "the number of bounding entities")?;
                for _ in 0..n_bound {
                    int(cur, "a bounding entity tag")?;
                }
            }
            end_record(cur, || format!("{} entity {tag}", dim_word(d)))?;
            if b.entity_index.insert((d, tag), b.entities.len()).is_some() {
                return Err(cur.error_on(line, format!("{} entity {tag} is listed twice", dim_word(d))));
            }
            b.entities.push(Entity {
                dim: d,
                tag,
                physical_tags,
            });
        }
    }
    b.has_entities = true;
    Ok(())
}

/// `$Nodes`: entity blocks of node tags, then their coordinates.
pub(super) fn read_nodes(cur: &mut Cursor, b: &mut Builder) -> Result<(), MeshError> {
    let n_blocks = size(cur, "the number of node blocks")?;
    let total = size(cur, "the number of nodes")?;
    size(cur, "the smallest node tag")?;
    size(cur, "the largest node tag")?;
    end_record(cur, || "the $Nodes counts".to_string())?;
    let mut seen: u64 = 0;
    for _ in 0..n_blocks {
        let entity_dim = dim(cur, "the node block's entity dimension")?;
        let entity_tag = int(cur, "the node block's entity tag")?;
        let parametric = int(cur, "the parametric flag (0 or 1)")?;
        let n = size(cur, "the number of nodes in the block")?;
        end_record(cur, || {
            format!("the header of node block {} {entity_tag}", dim_word(entity_dim))
        })?;
        // Parametric nodes carry u (curves), u v (surfaces), u v w (volumes).
        let n_param = match parametric {
            0 => 0,
            1 => entity_dim as u64,
            p => return Err(cur.error(format!("parametric flag {p} is neither 0 nor 1"))),
        };
        seen = seen.saturating_add(n);
        if seen > total {
            return Err(cur.error(format!(
                "the node blocks hold more nodes than the {total} the $Nodes header declares"
            )));
        }
        check_room(cur, n, 8 * (4 + n_param), "nodes")?;
        let mut tags = Vec::with_capacity(cur.capacity(n, min_bytes(cur, 8)));
        for _ in 0..n {
            let tag = size(cur, "a node tag")?;
            let line = cur.token_line();
            end_record(cur, || format!("node tag {tag}"))?;
            b.claim_node_tag(cur, tag, line)?;
            tags.push(tag);
        }
        for tag in tags {
            let mut xyz = [0.0; 3];
            for (c, name) in xyz.iter_mut().zip(["x", "y", "z"]) {
                *c = float(cur, name)
                    .map_err(|e| super::with_context(e, || format!("coordinates of node {tag}")))?;
            }
            for _ in 0..n_param {
                float(cur, "a parametric coordinate")?;
            }
            end_record(cur, || format!("the coordinates of node {tag}"))?;
            b.nodes.push((tag, xyz));
        }
    }
    if seen != total {
        return Err(cur.error(format!(
            "the $Nodes header declares {total} nodes but its blocks hold {seen}"
        )));
    }
    b.has_nodes = true;
    Ok(())
}

/// `$Elements`: entity blocks of elements of one type. `header_line` is the
/// section's line (the line of binary elements).
pub(super) fn read_elements(cur: &mut Cursor, b: &mut Builder, header_line: usize) -> Result<(), MeshError> {
    let n_blocks = size(cur, "the number of element blocks")?;
    let total = size(cur, "the number of elements")?;
    size(cur, "the smallest element tag")?;
    size(cur, "the largest element tag")?;
    end_record(cur, || "the $Elements counts".to_string())?;
    let mut seen: u64 = 0;
    for _ in 0..n_blocks {
        let entity_dim = dim(cur, "the element block's entity dimension")?;
        let entity_tag = int(cur, "the element block's entity tag")?;
        let gmsh_type = int(cur, "an element type")?;
        let n = size(cur, "the number of elements in the block")?;
        end_record(cur, || {
            format!(
                "the header of element block {} {entity_tag}",
                dim_word(entity_dim)
            )
        })?;
        let Some(info) = type_info(gmsh_type) else {
            return Err(cur.error(format!(
                "unknown gmsh element type {gmsh_type} (block on {} entity {entity_tag})",
                dim_word(entity_dim)
            )));
        };
        if info.dim != entity_dim {
            return Err(cur.error(format!(
                "element type {gmsh_type} ({}) is {}D, but its block is on {} entity {entity_tag}",
                info.name,
                info.dim,
                dim_word(entity_dim)
            )));
        }
        seen = seen.saturating_add(n);
        if seen > total {
            return Err(cur.error(format!(
                "the element blocks hold more elements than the {total} the $Elements header declares"
            )));
        }
        check_room(cur, n, 8 * (1 + info.nodes as u64), "elements")?;
        for _ in 0..n {
            let tag = size(cur, "an element tag")?;
            let line = if cur.is_binary() {
                header_line
            } else {
                cur.token_line()
            };
            b.claim_element_tag(cur, tag, line)?;
            let mut nodes = Vec::with_capacity(info.nodes);
            for _ in 0..info.nodes {
                let node = size(cur, "a node tag").map_err(|e| {
                    super::with_context(e, || format!("element {tag} ({}) has too few nodes", info.name))
                })?;
                nodes.push(node);
            }
            end_record(cur, || {
                format!("the {} nodes of element {tag} ({})", info.nodes, info.name)
            })?;
            b.elements.push(RawElement {
                tag,
                gmsh_type,
                entity_dim,
                entity_tag,
                physical_tags: Vec::new(),
                nodes,
                line,
            });
        }
    }
    if seen != total {
        return Err(cur.error(format!(
            "the $Elements header declares {total} elements but its blocks hold {seen}"
        )));
    }
    b.has_elements = true;
    Ok(())
}
