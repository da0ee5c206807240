//! `write_msh41`: a mesh with a joint written and read back by the reader
//! keeps every node (copies included) in order with bit-equal coordinates,
//! the cells of each body, the physical names, and gives the joint's
//! zero-thickness quadrangles their own physical surface.
//!
//! Fixtures: `two_squares.geo` (bodies `left`, `right`, joint curve
//! `interface` at r = 1, curve `bottom`, point `corner`), Q4 and Q9.

use axijoint_mesh::{insert_joints, parse_msh, read_msh, validate, write_msh41, JointSpec, Mesh};
use std::path::Path;

const FIXTURES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures");

fn jointed(name: &str) -> Mesh {
    let path = Path::new(FIXTURES).join(name);
    let mut mesh = read_msh(&path).unwrap();
    validate(&mut mesh, &path).unwrap();
    insert_joints(&mut mesh, &[JointSpec::new("interface")], &path).unwrap();
    mesh
}

#[test]
fn jointed_mesh_reads_back() {
    // (fixture, joint quadrangles per joint element)
    for (name, per_element) in [("quad1_v41.msh", 1), ("quad2_v41.msh", 2)] {
        let mesh = jointed(name);
        let joint = &mesh.joints[0];
        assert!(!joint.duplicated.is_empty(), "{name}: the joint splits nodes");
        let mut bytes = Vec::new();
        write_msh41(&mesh, &mut bytes).unwrap();
        let file = parse_msh(&bytes, "out.msh".as_ref()).unwrap();

        // Nodes: tag k + 1 at (r, z, 0) of node k, bit for bit.
        assert_eq!(file.nodes.len(), mesh.nodes.len(), "{name}");
        for (k, (tag, p)) in file.nodes.iter().enumerate() {
            assert_eq!(*tag, k as u64 + 1, "{name}");
            assert_eq!(*p, [mesh.nodes[k][0], mesh.nodes[k][1], 0.0], "{name}: node {k}");
        }

        // Names: the joint's curve became a surface group of its own.
        let mut names: Vec<(i32, i32, &str)> = file
            .physical_names
            .iter()
            .map(|p| (p.dim, p.tag, p.name.as_str()))
            .collect();
        names.sort();
        assert_eq!(
            names,
            [
                (0, 5, "corner"),
                (1, 3, "bottom"),
                (2, 1, "left"),
                (2, 2, "right"),
                (2, 3, "interface")
            ],
            "{name}"
        );

        // Cell c is element c + 1.
        for (c, cell) in mesh.cells.iter().enumerate() {
            let el = &file.elements[c];
            let nodes: Vec<u64> = cell.nodes.iter().map(|&n| n as u64 + 1).collect();
            assert_eq!((el.tag, &el.nodes), (c as u64 + 1, &nodes), "{name}: cell {c}");
            assert_eq!(el.physical_tags, [mesh.bodies[cell.body].tag], "{name}: cell {c}");
        }

        // Joint quadrangles: bottom nodes 0, 1 paired with top nodes 3, 2.
        let quads: Vec<&Vec<u64>> = file
            .elements
            .iter()
            .filter(|e| e.physical_tags == [3] && e.entity_dim == 2)
            .map(|e| {
                assert_eq!(e.gmsh_type, 3, "{name}");
                &e.nodes
            })
            .collect();
        assert_eq!(quads.len(), per_element * joint.elements.len(), "{name}");
        let at = |tag: u64| mesh.nodes[tag as usize - 1];
        let mut tops = std::collections::BTreeSet::new();
        for q in &quads {
            assert_eq!(at(q[0]), at(q[3]), "{name}: {q:?}");
            assert_eq!(at(q[1]), at(q[2]), "{name}: {q:?}");
            assert!(q[0] != q[3] || q[1] != q[2], "{name}: {q:?} pairs no copy");
            tops.extend([q[2] - 1, q[3] - 1]);
        }
        for (_, copy) in &joint.duplicated {
            assert!(
                tops.contains(&(*copy as u64)),
                "{name}: copy {copy} on no top face"
            );
        }

        // The reader's mesh of the file: same bodies' cells, same boundary sets.
        let back = parse_msh(&bytes, "out.msh".as_ref())
            .unwrap()
            .to_mesh("out.msh".as_ref())
            .unwrap();
        assert_eq!(back.nodes, mesh.nodes, "{name}");
        for body in ["left", "right"] {
            let cells = |m: &Mesh| -> Vec<Vec<usize>> {
                let b = m.body(body).unwrap();
                m.cells
                    .iter()
                    .filter(|c| c.body == b)
                    .map(|c| c.nodes.clone())
                    .collect()
            };
            assert_eq!(cells(&back), cells(&mesh), "{name}: {body}");
        }
        let edges = |m: &Mesh| -> Vec<Vec<usize>> {
            m.curve("bottom")
                .unwrap()
                .edges
                .iter()
                .map(|e| e.nodes.clone())
                .collect()
        };
        assert_eq!(edges(&back), edges(&mesh), "{name}");
        let mut corner = back.point("corner").unwrap().nodes.clone();
        let mut expected = mesh.point("corner").unwrap().nodes.clone();
        corner.sort_unstable();
        expected.sort_unstable();
        assert_eq!(corner, expected, "{name}");
        assert!(back.curve("interface").is_none(), "{name}");
    }
}

#[test]
fn a_body_named_like_the_joint_keeps_both_groups() {
    let mut mesh = jointed("quad1_v41.msh");
    mesh.bodies[0].name = "interface".into();
    let mut bytes = Vec::new();
    write_msh41(&mesh, &mut bytes).unwrap();
    let file = parse_msh(&bytes, "out.msh".as_ref()).unwrap();
    let surfaces: Vec<&str> = file
        .physical_names
        .iter()
        .filter(|p| p.dim == 2)
        .map(|p| p.name.as_str())
        .collect();
    assert_eq!(surfaces, ["interface", "right", "interface_joint"]);
}

#[test]
fn a_coordinate_that_is_not_finite_is_refused() {
    let mut mesh = jointed("quad1_v41.msh");
    mesh.nodes[4][1] = f64::NAN;
    let mut bytes = Vec::new();
    let e = write_msh41(&mesh, &mut bytes).unwrap_err();
    assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
    assert!(e.to_string().contains("node 4"), "{e}");
    assert!(bytes.is_empty(), "nothing written before the check");
}
