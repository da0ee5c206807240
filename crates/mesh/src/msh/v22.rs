//! `$Nodes` and `$Elements` of MSH 2.2 (ASCII): one record per line.

use super::cursor::Cursor;
use super::types::type_info;
use super::{with_context, Builder, RawElement};
use crate::MeshError;

/// `$Nodes`: a count, then `tag x y z` lines.
pub(super) fn read_nodes(cur: &mut Cursor, b: &mut Builder) -> Result<(), MeshError> {
    let count: u64 = cur.parse("the number of nodes")?;
    cur.end_of_record(|| "the number of nodes".to_string())?;
    for _ in 0..count {
        let tag: u64 = cur.parse("a node tag (or $EndNodes: fewer nodes than declared?)")?;
        let line = cur.token_line();
        b.claim_node_tag(cur, tag, line)?;
        let mut xyz = [0.0; 3];
        for (c, name) in xyz.iter_mut().zip(["x", "y", "z"]) {
            *c = cur
                .parse_f64(name)
                .map_err(|e| with_context(e, || format!("coordinates of node {tag}")))?;
        }
        cur.end_of_record(|| format!("the coordinates of node {tag}"))?;
        b.nodes.push((tag, xyz));
    }
    b.has_nodes = true;
    Ok(())
}

/// `$Elements`: a count, then `tag type n-tags tags... nodes...` lines. The
/// first tag is the physical group (0: none), the second the entity.
///
/// gmsh writes an element that is in several physical groups once per
/// group, under different tags; such copies (same type, entity and nodes)
/// are merged into the first, which collects their physical tags.
pub(super) fn read_elements(cur: &mut Cursor, b: &mut Builder) -> Result<(), MeshError> {
    let count: u64 = cur.parse("the number of elements")?;
    cur.end_of_record(|| "the number of elements".to_string())?;
    for _ in 0..count {
        let tag: u64 = cur.parse("an element tag (or $EndElements: fewer elements than declared?)")?;
        let line = cur.token_line();
        b.claim_element_tag(cur, tag, line)?;
        let gmsh_type: i32 = cur.parse("an element type")?;
        let Some(info) = type_info(gmsh_type) else {
            return Err(cur.error(format!(
                "element {tag} has an unknown gmsh element type {gmsh_type}"
            )));
        };
        let n_tags: u64 = cur.parse("the number of element tags")?;
        let mut physical = 0;
        let mut entity = 0;
        for i in 0..n_tags {
            let t: i32 = cur.parse("an element tag value")?;
            match i {
                0 => physical = t,
                1 => entity = t,
                _ => {} // partitions
            }
        }
        let mut nodes = Vec::with_capacity(info.nodes);
        for _ in 0..info.nodes {
            let node: u64 = cur.parse("a node tag").map_err(|e| {
                with_context(e, || format!("element {tag} ({}) has too few nodes", info.name))
            })?;
            nodes.push(node);
        }
        cur.end_of_record(|| format!("the {} nodes of element {tag} ({})", info.nodes, info.name))?;
        let key = (gmsh_type, entity, nodes);
        if let Some(&first) = b.v22_copies.get(&key) {
            if let Some(el) = b.elements.get_mut(first) {
                if physical == 0 || !b.v22_groups.insert((first, physical)) {
                    return Err(cur.error_at(
                        line,
                        format!(
                            "element {tag} repeats element {} (line {}): same nodes and physical group",
                            el.tag, el.line
                        ),
                    ));
                }
                el.physical_tags.push(physical);
            }
            continue;
        }
        let (gmsh_type, entity_tag, nodes) = key;
        b.v22_copies
            .insert((gmsh_type, entity_tag, nodes.clone()), b.elements.len());
        b.v22_groups.insert((b.elements.len(), physical));
        b.elements.push(RawElement {
            tag,
            gmsh_type,
            entity_dim: info.dim,
            entity_tag,
            physical_tags: if physical == 0 { Vec::new() } else { vec![physical] },
            nodes,
            line,
        });
    }
    b.has_elements = true;
    Ok(())
}
