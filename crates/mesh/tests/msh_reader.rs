//! The `.msh` reader: gmsh-made fixtures in every format agree, hand-written
//! edge cases parse to known meshes, and every malformed input gives an error
//! that names its culprit.
//!
//! Fixtures (tests/fixtures/): `two_squares.geo` meshed by gmsh 4.8.4 as
//! `{tri1,tri2,quad1,quad2,quad8}_{v41,v41_bin,v22}.msh` (T3, T6, Q4, Q9,
//! Q8), plus `tri1_v41_param*.msh` (-save_parametric), `tri1_*_all.msh`
//! (-save_all) and `tri1_v41_part.msh` (-part 2); hand-written
//! `sparse_*.msh`, `unassigned_v41.msh`, `tetra_v22.msh`.
//!
//! ```text
//!   z
//!   +---------+---------+      left  = [0,1]x[0,1] (transfinite 2x2)
//!   |  left   |  right  |      right = [1,2]x[0,1] (unstructured)
//!   |         i         |      i = "interface" (r = 1)
//!   o---------+---------+ r    "bottom" = z = 0, o = "corner" (0, 0)
//! ```

use axijoint_mesh::msh::{MshFormat, RawElement};
use axijoint_mesh::{parse_msh, read_msh, CellKind, EdgeKind, Mesh, MeshError, MshFile};
use std::path::{Path, PathBuf};
use std::process::Command;

const FIXTURES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures");

fn fixture(name: &str) -> PathBuf {
    Path::new(FIXTURES).join(name)
}

fn fixture_bytes(name: &str) -> Vec<u8> {
    std::fs::read(fixture(name)).expect("fixture exists")
}

fn fixture_text(name: &str) -> String {
    String::from_utf8(fixture_bytes(name)).expect("ASCII fixture")
}

/// Parses and converts, as `read_msh` does, from memory.
fn mesh_of(bytes: &[u8]) -> Result<Mesh, MeshError> {
    let path = Path::new("case.msh");
    parse_msh(bytes, path)?.to_mesh(path)
}

/// The error of a text that must fail, as displayed.
fn error_of(text: &str) -> MeshError {
    match mesh_of(text.as_bytes()) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e,
    }
}

/// The 1-based line of a parse error.
fn line_of_error(e: &MeshError) -> usize {
    match e {
        MeshError::Parse { line, .. } => *line,
        other => panic!("expected a parse error, got {other}"),
    }
}

/// 1-based line of the first line of `text` equal to `needle` (trimmed).
fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.trim() == needle)
        .map(|i| i + 1)
        .unwrap_or_else(|| panic!("no line '{needle}'"))
}

/// `text` with its one line equal to `from` (trimmed) replaced by `to`.
fn replace_line(text: &str, from: &str, to: &str) -> String {
    let mut found = 0;
    let out: Vec<&str> = text
        .lines()
        .map(|l| {
            if l.trim() == from {
                found += 1;
                to
            } else {
                l
            }
        })
        .collect();
    assert_eq!(found, 1, "line '{from}' must occur once");
    out.join("\n") + "\n"
}

/// Asserts the error displays every one of `parts`.
fn assert_mentions(e: &MeshError, parts: &[&str]) {
    let shown = e.to_string();
    for p in parts {
        assert!(shown.contains(p), "error '{shown}' does not mention '{p}'");
    }
}

fn assert_same_mesh(a: &Mesh, b: &Mesh, what: &str) {
    assert_eq!(a.nodes.len(), b.nodes.len(), "{what}: node count");
    assert_eq!(a.node_tags, b.node_tags, "{what}: node tags");
    for (i, (p, q)) in a.nodes.iter().zip(&b.nodes).enumerate() {
        let d = (p[0] - q[0]).abs().max((p[1] - q[1]).abs());
        assert!(d <= 1e-15, "{what}: node {i} at {p:?} vs {q:?}");
    }
    assert_eq!(a.cells, b.cells, "{what}: cells");
    assert_eq!(a.bodies, b.bodies, "{what}: bodies");
    assert_eq!(a.curves, b.curves, "{what}: curves");
    assert_eq!(a.points, b.points, "{what}: points");
}

/// Area of a straight-sided cell from its corners (shoelace).
fn cell_area(mesh: &Mesh, c: &axijoint_mesh::Cell) -> f64 {
    let n = c.kind.n_corners();
    (0..n)
        .map(|i| {
            let p = mesh.nodes[c.nodes[i]];
            let q = mesh.nodes[c.nodes[(i + 1) % n]];
            p[0] * q[1] - q[0] * p[1]
        })
        .sum::<f64>()
        / 2.0
}

fn curve_length(mesh: &Mesh, name: &str) -> f64 {
    let set = mesh.curve(name).expect("curve exists");
    set.edges
        .iter()
        .map(|e| {
            let (p, q) = (mesh.nodes[e.nodes[0]], mesh.nodes[e.nodes[1]]);
            (q[0] - p[0]).hypot(q[1] - p[1])
        })
        .sum()
}

/// One meshing of `two_squares.geo`.
struct Variant {
    name: &'static str,
    gmsh_args: &'static [&'static str],
    cell: CellKind,
    edge: EdgeKind,
    left_cells: usize,
}

const VARIANTS: [Variant; 5] = [
    Variant {
        name: "tri1",
        gmsh_args: &[],
        cell: CellKind::Tri3,
        edge: EdgeKind::Lin2,
        left_cells: 8,
    },
    Variant {
        name: "tri2",
        gmsh_args: &["-order", "2"],
        cell: CellKind::Tri6,
        edge: EdgeKind::Lin3,
        left_cells: 8,
    },
    Variant {
        name: "quad1",
        gmsh_args: &["-setnumber", "Mesh.RecombineAll", "1"],
        cell: CellKind::Quad4,
        edge: EdgeKind::Lin2,
        left_cells: 4,
    },
    Variant {
        name: "quad2",
        gmsh_args: &["-setnumber", "Mesh.RecombineAll", "1", "-order", "2"],
        cell: CellKind::Quad9,
        edge: EdgeKind::Lin3,
        left_cells: 4,
    },
    Variant {
        name: "quad8",
        gmsh_args: &[
            "-setnumber",
            "Mesh.RecombineAll",
            "1",
            "-setnumber",
            "Mesh.SecondOrderIncomplete",
            "1",
            "-order",
            "2",
        ],
        cell: CellKind::Quad8,
        edge: EdgeKind::Lin3,
        left_cells: 4,
    },
];

const FORMATS: [(&str, MshFormat); 3] = [
    ("v41", MshFormat::V41Ascii),
    ("v41_bin", MshFormat::V41Binary),
    ("v22", MshFormat::V22Ascii),
];

/// What holds for any mesh of `two_squares.geo`, whatever the gmsh version.
fn check_two_squares(mesh: &Mesh, v: &Variant, what: &str) {
    let names: Vec<&str> = mesh.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["left", "right"], "{what}");
    assert_eq!((mesh.bodies[0].tag, mesh.bodies[1].tag), (1, 2), "{what}");
    let curves: Vec<(&str, i32)> = mesh.curves.iter().map(|c| (c.name.as_str(), c.tag)).collect();
    assert_eq!(curves, [("bottom", 3), ("interface", 4)], "{what}");
    assert!(mesh.cells.iter().all(|c| c.kind == v.cell), "{what}: cell kinds");
    let left = mesh.body("left").unwrap();
    let n_left = mesh.cells.iter().filter(|c| c.body == left).count();
    assert_eq!(n_left, v.left_cells, "{what}: cells of the transfinite square");
    for (b, body) in mesh.bodies.iter().enumerate() {
        let area: f64 = mesh
            .cells
            .iter()
            .filter(|c| c.body == b)
            .map(|c| cell_area(mesh, c))
            .sum();
        assert!(
            (area - 1.0).abs() < 1e-12,
            "{what}: area of {} = {area}",
            body.name
        );
    }
    assert!((curve_length(mesh, "bottom") - 2.0).abs() < 1e-12, "{what}");
    assert!((curve_length(mesh, "interface") - 1.0).abs() < 1e-12, "{what}");
    let interface = mesh.curve("interface").unwrap();
    assert_eq!(
        interface.edges.len(),
        2,
        "{what}: 3 transfinite nodes on the interface"
    );
    for e in mesh.curves.iter().flat_map(|c| &c.edges) {
        assert_eq!(e.kind, v.edge, "{what}");
        if e.kind == EdgeKind::Lin3 {
            let [p, q, m] = [0, 1, 2].map(|i| mesh.nodes[e.nodes[i]]);
            let mid = [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
            assert!(
                (m[0] - mid[0]).abs() + (m[1] - mid[1]).abs() < 1e-12,
                "{what}: L3 middle"
            );
        }
    }
    assert!(interface
        .edges
        .iter()
        .flat_map(|e| &e.nodes)
        .all(|&n| mesh.nodes[n][0] == 1.0));
    let corner = mesh.point("corner").expect("corner");
    assert_eq!(corner.nodes.len(), 1, "{what}");
    assert_eq!(mesh.nodes[corner.nodes[0]], [0.0, 0.0], "{what}");
    // Every node is used by a cell (no orphan kept).
    let mut used = vec![false; mesh.nodes.len()];
    mesh.cells
        .iter()
        .flat_map(|c| &c.nodes)
        .for_each(|&n| used[n] = true);
    assert!(used.iter().all(|&u| u), "{what}: unused node kept");
}

#[test]
fn gmsh_fixtures_have_the_expected_meshes() {
    // (variant, nodes, cells) of the committed gmsh 4.8.4 files.
    let expected = [
        ("tri1", 18, 22),
        ("tri2", 57, 22),
        ("quad1", 17, 10),
        ("quad2", 53, 10),
        ("quad8", 43, 10),
    ];
    for (v, (name, n_nodes, n_cells)) in VARIANTS.iter().zip(expected) {
        assert_eq!(v.name, name);
        for (suffix, format) in FORMATS {
            let file = format!("{name}_{suffix}.msh");
            let bytes = fixture_bytes(&file);
            let msh = parse_msh(&bytes, &fixture(&file)).unwrap();
            assert_eq!(msh.format, format, "{file}");
            let mesh = read_msh(&fixture(&file)).unwrap();
            assert_eq!((mesh.nodes.len(), mesh.cells.len()), (n_nodes, n_cells), "{file}");
            assert_eq!(mesh.curve("bottom").unwrap().edges.len(), 4, "{file}");
            check_two_squares(&mesh, v, &file);
        }
    }
}

#[test]
fn gmsh_fixtures_agree_across_formats() {
    for v in &VARIANTS {
        let reference = read_msh(&fixture(&format!("{}_v41.msh", v.name))).unwrap();
        for suffix in ["v41_bin", "v22"] {
            let file = format!("{}_{suffix}.msh", v.name);
            assert_same_mesh(&reference, &read_msh(&fixture(&file)).unwrap(), &file);
        }
    }
}

#[test]
fn parametric_and_save_all_files_give_the_same_mesh() {
    let reference = read_msh(&fixture("tri1_v41.msh")).unwrap();
    for file in ["tri1_v41_param.msh", "tri1_v41_param_bin.msh"] {
        assert_same_mesh(&reference, &read_msh(&fixture(file)).unwrap(), file);
    }
    // -save_all also writes the lines and points of no physical group (and
    // numbers them first, so element tags shift by 13).
    let all = parse_msh(&fixture_bytes("tri1_v41_all.msh"), Path::new("a.msh")).unwrap();
    assert_eq!(all.elements.len(), 42);
    assert_eq!(all.entities.len(), 6 + 7 + 2);
    let mut all = all.to_mesh(Path::new("a.msh")).unwrap();
    for c in &mut all.cells {
        c.tag -= 13;
    }
    assert_eq!(all.cells, reference.cells);
    let untagged = |m: &Mesh| -> Vec<Vec<(Vec<usize>, i32)>> {
        m.curves
            .iter()
            .map(|c| c.edges.iter().map(|e| (e.nodes.clone(), e.entity)).collect())
            .collect()
    };
    assert_eq!(untagged(&all), untagged(&reference));
    assert_eq!(all.nodes, reference.nodes);
    assert_eq!(all.points, reference.points);
}

/// gmsh quirk: with -save_all, MSH 2.2 writes physical tag 0 on every
/// element, so the physical groups are lost and the reader must refuse.
#[test]
fn msh22_save_all_loses_the_physical_groups() {
    let e = read_msh(&fixture("tri1_v22_all.msh")).unwrap_err();
    assert!(matches!(e, MeshError::Invalid { .. }));
    assert_mentions(
        &e,
        &[
            "tri1_v22_all.msh",
            "element 21 (surface entity 1, line 55)",
            "no physical surface",
        ],
    );
}

/// Re-meshes `two_squares.geo` with the installed gmsh in the three formats
/// and checks that they read to the same mesh.
#[test]
fn regenerated_gmsh_files_agree_across_formats() {
    let gmsh = Path::new("/usr/bin/gmsh");
    if !gmsh.exists() {
        println!("skipped: /usr/bin/gmsh is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for v in &VARIANTS {
        let mut meshes = Vec::new();
        for (suffix, format) in FORMATS {
            let out = dir.path().join(format!("{}_{suffix}.msh", v.name));
            let mut cmd = Command::new(gmsh);
            cmd.arg(fixture("two_squares.geo"))
                .args(["-2", "-v", "1"])
                .args(v.gmsh_args);
            cmd.args(["-format", if suffix == "v22" { "msh22" } else { "msh41" }]);
            if suffix == "v41_bin" {
                cmd.arg("-bin");
            }
            let status = cmd.arg("-o").arg(&out).status().unwrap();
            assert!(status.success(), "gmsh failed for {out:?}");
            let bytes = std::fs::read(&out).unwrap();
            assert_eq!(parse_msh(&bytes, &out).unwrap().format, format);
            let mesh = read_msh(&out).unwrap();
            check_two_squares(&mesh, v, &out.display().to_string());
            meshes.push(mesh);
        }
        assert_same_mesh(
            &meshes[0],
            &meshes[1],
            &format!("{}: 4.1 ASCII vs binary", v.name),
        );
        assert_same_mesh(&meshes[0], &meshes[2], &format!("{}: 4.1 vs 2.2", v.name));
    }
}

/// The mesh both `sparse_*.msh` files describe.
fn check_sparse(mesh: &Mesh, what: &str) {
    // Node 1000 is used by no element: dropped (its z = 0.3 is not checked).
    assert_eq!(mesh.node_tags, [100, 7, 55, 42, 3], "{what}");
    assert_eq!(
        mesh.nodes,
        [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        "{what}"
    );
    assert_eq!(mesh.bodies.len(), 1, "{what}");
    assert_eq!(
        (mesh.bodies[0].name.as_str(), mesh.bodies[0].tag),
        ("plate", 5),
        "{what}"
    );
    assert_eq!(mesh.cells.len(), 2, "{what}");
    assert_eq!(mesh.cells[0].kind, CellKind::Quad4);
    assert_eq!(mesh.cells[0].nodes, [0, 1, 3, 4], "{what}");
    assert_eq!(
        (mesh.cells[0].tag, mesh.cells[0].entity, mesh.cells[0].body),
        (20, 1, 0)
    );
    assert_eq!(mesh.cells[1].kind, CellKind::Tri3);
    assert_eq!(mesh.cells[1].nodes, [1, 2, 3], "{what}");
    // Curves in tag order; the unnamed one gets "curve_9"; line 12 (no
    // physical group) is dropped; line 11 is in both groups.
    let curves: Vec<(&str, i32, usize)> = mesh
        .curves
        .iter()
        .map(|c| (c.name.as_str(), c.tag, c.edges.len()))
        .collect();
    assert_eq!(curves, [("curve_9", 9, 1), ("base", 10, 1)], "{what}");
    for c in &mesh.curves {
        assert_eq!((c.edges[0].tag, c.edges[0].entity), (11, 1), "{what}");
        assert_eq!(c.edges[0].nodes, [0, 1], "{what}");
    }
    let origin = mesh.point("axis origin").expect("name with a space");
    assert_eq!((origin.tag, origin.nodes.as_slice()), (20, &[0][..]), "{what}");
    assert!(mesh.joints.is_empty());
}

#[test]
fn sparse_unordered_tags_and_skipped_sections() {
    let v41 = read_msh(&fixture("sparse_v41.msh")).unwrap();
    check_sparse(&v41, "4.1");
    let v22 = read_msh(&fixture("sparse_v22.msh")).unwrap();
    check_sparse(&v22, "2.2");
    assert_eq!(v41, v22);

    let msh = parse_msh(&fixture_bytes("sparse_v41.msh"), Path::new("s.msh")).unwrap();
    assert_eq!(msh.nodes.len(), 6);
    assert_eq!(msh.entities.len(), 4);
    assert_eq!(msh.entities[1].physical_tags, [9, 10]);
    assert_eq!(msh.physical_names[0].name, "axis origin");
    let line11 = line_of(&fixture_text("sparse_v41.msh"), "11 100 7");
    assert_eq!(
        msh.elements[1],
        RawElement {
            tag: 11,
            gmsh_type: 1,
            entity_dim: 1,
            entity_tag: 1,
            physical_tags: vec![9, 10],
            nodes: vec![100, 7],
            line: line11,
        }
    );
    // 2.2: the copy of line 11 in group 10 (tag 13) is merged into it.
    let msh = parse_msh(&fixture_bytes("sparse_v22.msh"), Path::new("s.msh")).unwrap();
    assert_eq!(msh.elements.len(), 5);
    assert_eq!(
        (msh.elements[1].tag, &msh.elements[1].physical_tags[..]),
        (11, &[9, 10][..])
    );
    assert!(msh.entities.is_empty());
}

#[test]
fn crlf_line_endings_read_the_same() {
    for file in ["sparse_v41.msh", "sparse_v22.msh"] {
        let crlf = fixture_text(file).replace('\n', "\r\n");
        check_sparse(&mesh_of(crlf.as_bytes()).unwrap(), file);
    }
}

#[test]
fn element_in_no_physical_surface() {
    let e = read_msh(&fixture("unassigned_v41.msh")).unwrap_err();
    assert!(matches!(e, MeshError::Invalid { .. }));
    let line = line_of(&fixture_text("unassigned_v41.msh"), "17 2 4 3");
    assert_mentions(
        &e,
        &[
            "unassigned_v41.msh",
            &format!("element 17 (surface entity 3, line {line}) is in no physical surface"),
        ],
    );
}

#[test]
fn msh41_without_entities_has_no_physical_groups() {
    let text = fixture_text("unassigned_v41.msh");
    let start = line_of(&text, "$Entities");
    let end = line_of(&text, "$EndEntities");
    let cut: String = text
        .lines()
        .enumerate()
        .filter(|(i, _)| *i + 1 < start || *i + 1 > end)
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    let msh = parse_msh(cut.as_bytes(), Path::new("n.msh")).unwrap();
    assert!(msh.entities.is_empty() && msh.elements.iter().all(|e| e.physical_tags.is_empty()));
    let e = msh.to_mesh(Path::new("n.msh")).unwrap_err();
    assert_mentions(&e, &["element 16 (surface entity 1", "no $Entities section"]);
}

#[test]
fn element_in_two_physical_surfaces() {
    let text = replace_line(
        &fixture_text("unassigned_v41.msh"),
        "3 1 0 0 2 1 0 0 0",
        "3 1 0 0 2 1 0 2 1 2 0",
    );
    let e = error_of(&text);
    assert_mentions(
        &e,
        &[
            "element 17 (surface entity 3",
            "more than one physical surface",
            "'body' (1) and 'other' (2)",
        ],
    );
    // The same in 2.2: two copies of one triangle in groups 1 and 2.
    let v22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n\
               $Elements\n2\n5 2 2 1 3 1 2 3\n6 2 2 2 3 1 2 3\n$EndElements\n";
    assert_mentions(
        &error_of(v22),
        &["element 5 (surface entity 3, line 12)", "surface_1", "surface_2"],
    );
    // ... while a repeat in the same group is a duplicate element.
    let e = error_of(&v22.replace("6 2 2 2 3", "6 2 2 1 3"));
    assert_eq!(line_of_error(&e), 13);
    assert_mentions(&e, &["element 6 repeats element 5 (line 12)"]);
}

#[test]
fn unknown_and_unsupported_element_types() {
    let text = fixture_text("unassigned_v41.msh");
    let e = error_of(&replace_line(&text, "2 3 2 1", "2 3 99 1"));
    assert_eq!(line_of_error(&e), line_of(&text, "2 3 2 1"));
    assert_mentions(&e, &["unknown gmsh element type 99", "surface entity 3"]);
    // A 4-node tetrahedron is known (it can be read past) but not usable.
    let e = read_msh(&fixture("tetra_v22.msh")).unwrap_err();
    assert_eq!(line_of_error(&e), 14);
    assert_mentions(
        &e,
        &["tetra_v22.msh:14", "element 2", "type 4 (4-node tetrahedron)"],
    );
    // A 1D type in a block on a surface.
    let e = error_of(&replace_line(&text, "2 3 2 1", "2 3 1 1"));
    assert_mentions(&e, &["element type 1 (2-node line) is 1D", "surface entity 3"]);
    // 2.2 unknown type.
    let v22 = fixture_text("sparse_v22.msh");
    let e = error_of(&replace_line(&v22, "21 2 2 5 1 7 55 42", "21 77 2 5 1 7 55 42"));
    assert_eq!(line_of_error(&e), line_of(&v22, "21 2 2 5 1 7 55 42"));
    assert_mentions(&e, &["element 21", "unknown gmsh element type 77"]);
}

#[test]
fn node_referenced_but_not_defined() {
    for file in ["sparse_v41.msh", "sparse_v22.msh"] {
        let text = fixture_text(file);
        let (from, to) = if file.contains("v41") {
            ("21 7 55 42", "21 7 55 43")
        } else {
            ("21 2 2 5 1 7 55 42", "21 2 2 5 1 7 55 43")
        };
        let e = error_of(&replace_line(&text, from, to));
        assert_eq!(line_of_error(&e), line_of(&text, from), "{file}");
        assert_mentions(&e, &["element 21", "node 43", "does not define"]);
    }
}

#[test]
fn node_off_the_z0_plane() {
    let text = replace_line(&fixture_text("sparse_v22.msh"), "42 1 1 0", "42 1 1 0.25");
    let e = error_of(&text);
    assert!(matches!(e, MeshError::Invalid { .. }));
    assert_mentions(
        &e,
        &[
            "node 42 at (1.0, 1.0, 0.25), used by element 20 (surface entity 1, line ",
            "z = 0",
        ],
    );
    // Within 1e-10 of the model's extent (here 2) counts as 0.
    let text = replace_line(&fixture_text("sparse_v22.msh"), "42 1 1 0", "42 1 1 1e-10");
    assert_eq!(mesh_of(text.as_bytes()).unwrap().nodes[3], [1.0, 1.0]);
}

#[test]
fn duplicate_node_and_element_tags() {
    let v22 = fixture_text("sparse_v22.msh");
    let e = error_of(&replace_line(&v22, "55 2 0 0", "7 2 0 0"));
    assert_eq!(line_of_error(&e), line_of(&v22, "55 2 0 0"));
    assert_mentions(
        &e,
        &[&format!(
            "duplicate node tag 7 (first defined at line {})",
            line_of(&v22, "7 1 0 0")
        )],
    );

    let v41 = fixture_text("sparse_v41.msh");
    let e = error_of(&replace_line(&v41, "55", "100"));
    assert_eq!(line_of_error(&e), line_of(&v41, "55"));
    assert_mentions(&e, &["duplicate node tag 100"]);

    let e = error_of(&replace_line(&v41, "21 7 55 42", "20 7 55 42"));
    assert_eq!(line_of_error(&e), line_of(&v41, "21 7 55 42"));
    assert_mentions(&e, &["duplicate element tag 20"]);

    let e = error_of(&replace_line(&v41, "55", "0"));
    assert_mentions(&e, &["node tag 0"]);
}

#[test]
fn missing_end_markers() {
    let v22 = fixture_text("sparse_v22.msh");
    let e = error_of(&replace_line(&v22, "$EndNodes", ""));
    assert_eq!(line_of_error(&e), line_of(&v22, "$Periodic"));
    assert_mentions(&e, &["expected $EndNodes", "found '$Periodic'"]);

    let v41 = fixture_text("sparse_v41.msh");
    let e = error_of(&replace_line(&v41, "$EndNodes", ""));
    assert_mentions(&e, &["expected $EndNodes", "found '$Elements'"]);

    let e = error_of(&replace_line(&v41, "$EndNodeData", ""));
    assert_mentions(&e, &["file ends inside $NodeData", "no $EndNodeData"]);

    let cut = v22.replace("$EndElements\n", "");
    let e = error_of(&cut);
    assert_mentions(&e, &["file ends inside $Elements", "no $EndElements"]);

    let e = error_of(&replace_line(&v22, "$EndPeriodic", "$EndPeriod"));
    assert_mentions(&e, &["no $EndPeriodic"]);
}

/// Every proper prefix of a valid file (cut after any line) is an error,
/// except the one that ends with `$EndElements` (sparse_v41.msh has a
/// `$NodeData` section after it).
#[test]
fn truncated_at_every_line_is_an_error() {
    for file in [
        "sparse_v41.msh",
        "sparse_v22.msh",
        "tri2_v41.msh",
        "quad8_v22.msh",
        "tri1_v41_param.msh",
    ] {
        let text = fixture_text(file);
        let lines: Vec<&str> = text.lines().collect();
        let complete = line_of(&text, "$EndElements");
        for k in 0..=lines.len() {
            let prefix = lines[..k].join("\n");
            let result = mesh_of(prefix.as_bytes());
            assert_eq!(
                result.is_ok(),
                k == complete || k == lines.len(),
                "{file} cut after {k} lines"
            );
        }
    }
}

/// Every prefix of a binary file (cut at any byte) is an error; only the
/// final newline may go.
#[test]
fn binary_truncated_at_every_byte_is_an_error() {
    for file in ["tri1_v41_bin.msh", "quad2_v41_bin.msh"] {
        let bytes = fixture_bytes(file);
        for k in 0..bytes.len() - 1 {
            assert!(mesh_of(&bytes[..k]).is_err(), "{file} cut at byte {k}");
        }
        assert!(mesh_of(&bytes[..bytes.len() - 1]).is_ok(), "{file}");
    }
}

#[test]
fn wrong_counts() {
    let v41 = fixture_text("sparse_v41.msh");
    let header = line_of(&v41, "3 6 3 1000");
    let e = error_of(&replace_line(&v41, "3 6 3 1000", "3 7 3 1000"));
    assert_mentions(&e, &["declares 7 nodes but its blocks hold 6"]);
    let e = error_of(&replace_line(&v41, "3 6 3 1000", "3 5 3 1000"));
    assert_mentions(&e, &["more nodes than the 5"]);
    // A block claiming 2 nodes where there are 3: the third tag is read as
    // coordinates, and the line holding them has too few.
    let e = error_of(&replace_line(&v41, "2 1 0 3", "2 1 0 2"));
    assert!(line_of_error(&e) > header);
    // More node blocks than there are.
    let e = error_of(&replace_line(&v41, "3 6 3 1000", "4 6 3 1000"));
    assert_mentions(
        &e,
        &["expected the node block's entity dimension, found '$EndNodes'"],
    );
    let e = error_of(&replace_line(&v41, "5 5 11 500", "5 6 11 500"));
    assert_mentions(&e, &["declares 6 elements but its blocks hold 5"]);
    let e = error_of(&replace_line(&v41, "5 5 11 500", "5 4 11 500"));
    assert_mentions(&e, &["more elements than the 4"]);
    // A block claiming 2 quadrangles reads the next block header as one.
    let e = error_of(&replace_line(&v41, "2 1 3 1", "2 1 3 2"));
    assert_eq!(line_of_error(&e), line_of(&v41, "2 1 2 1"));
    assert_mentions(
        &e,
        &[
            "element 2 (4-node quadrangle) has too few nodes",
            "found the end of the line",
        ],
    );
    // An element line with one node too many.
    let e = error_of(&replace_line(&v41, "21 7 55 42", "21 7 55 42 3"));
    assert_eq!(line_of_error(&e), line_of(&v41, "21 7 55 42"));
    assert_mentions(
        &e,
        &["unexpected '3' after the 3 nodes of element 21 (3-node triangle)"],
    );

    let v22 = fixture_text("sparse_v22.msh");
    let e = error_of(&v22.replacen("$Nodes\n6\n", "$Nodes\n7\n", 1));
    assert_eq!(line_of_error(&e), line_of(&v22, "$EndNodes"));
    assert_mentions(
        &e,
        &[
            "expected a node tag",
            "fewer nodes than declared",
            "found '$EndNodes'",
        ],
    );
    let nodes5 = v22.replacen("$Nodes\n6\n", "$Nodes\n5\n", 1);
    let e = error_of(&nodes5);
    assert_eq!(line_of_error(&e), line_of(&v22, "1000 5 5 0.3"));
    assert_mentions(
        &e,
        &[
            "expected $EndNodes",
            "found '1000 5 5 0.3'",
            "more data than its counts declare",
        ],
    );
    let elements7 = v22.replacen("$Elements\n6\n", "$Elements\n7\n", 1);
    assert_mentions(
        &error_of(&elements7),
        &["fewer elements than declared", "found '$EndElements'"],
    );
    // A triangle with 2 nodes.
    let e = error_of(&replace_line(&v22, "21 2 2 5 1 7 55 42", "21 2 2 5 1 7 55"));
    assert_eq!(line_of_error(&e), line_of(&v22, "21 2 2 5 1 7 55 42"));
    assert_mentions(
        &e,
        &[
            "element 21 (3-node triangle) has too few nodes",
            "found the end of the line",
        ],
    );
    // Too few physical names.
    let e = error_of(&replace_line(&v22, "3", "4"));
    assert_eq!(line_of_error(&e), line_of(&v22, "$EndPhysicalNames"));
}

#[test]
fn bad_numbers() {
    let v22 = fixture_text("sparse_v22.msh");
    let line = line_of(&v22, "42 1 1 0");
    let cases = [
        ("42 1 1.0e 0", "coordinates of node 42: expected y, found '1.0e'"),
        ("abc 1 1 0", "found 'abc'"),
        ("42 1 nan 0", "non-finite"),
        ("42 1 1e999 0", "non-finite"),
        ("-42 1 1 0", "found '-42'"),
        ("42.0 1 1 0", "found '42.0'"),
        (
            "42 1 1",
            "coordinates of node 42: expected z, found the end of the line",
        ),
        ("42 1 1 0 0", "unexpected '0' after the coordinates of node 42"),
    ];
    for (bad, culprit) in cases {
        let e = error_of(&replace_line(&v22, "42 1 1 0", bad));
        assert_eq!(line_of_error(&e), line, "{bad}");
        assert_mentions(&e, &["case.msh", culprit]);
    }
    let e = error_of(&replace_line(
        &v22,
        "20 3 2 5 1 100 7 42 3",
        "20 3 2 5 1 100 7 x 3",
    ));
    assert_mentions(
        &e,
        &["element 20 (4-node quadrangle) has too few nodes: expected a node tag, found 'x'"],
    );

    let v41 = fixture_text("sparse_v41.msh");
    let e = error_of(&replace_line(&v41, "1 1 0 2", "1 1 0 -2"));
    assert_eq!(line_of_error(&e), line_of(&v41, "1 1 0 2"));
    assert_mentions(&e, &["number of nodes in the block", "found '-2'"]);
    let e = error_of(&replace_line(&v41, "1 1 0 2", "1 1 2 2"));
    assert_mentions(&e, &["parametric flag 2"]);
    let e = error_of(&replace_line(&v41, "1 1 0 2", "5 1 0 2"));
    assert_mentions(&e, &["entity dimension 5 is not 0, 1, 2 or 3"]);
    let e = error_of(&replace_line(&v41, "2 1 3 1", "2 1 3 1x"));
    assert_mentions(&e, &["found '1x'"]);
    let e = error_of(&replace_line(&v41, "2 5 \"plate\"", "2 5 \"plate"));
    assert_mentions(&e, &["unterminated quoted name"]);
}

#[test]
fn missing_or_unsupported_mesh_format() {
    let v22 = fixture_text("sparse_v22.msh");
    let headless: String = v22.lines().skip(3).map(|l| format!("{l}\n")).collect();
    let e = error_of(&headless);
    assert_eq!(line_of_error(&e), 1);
    assert_mentions(&e, &["missing $MeshFormat", "$PhysicalNames"]);
    assert_mentions(&error_of(""), &["case.msh:1:", "missing $MeshFormat"]);
    assert_mentions(
        &error_of("$Comments\nhi\n$EndComments\n"),
        &["missing $MeshFormat"],
    );
    assert_mentions(
        &error_of("solid cube\n"),
        &["case.msh:1:", "expected a section header", "'solid cube'"],
    );
    assert_mentions(
        &error_of("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"),
        &["no $Nodes section"],
    );

    for (version, culprit) in [
        ("3.0 0 8", "unsupported MSH version '3.0'"),
        ("4 0 8", "unsupported MSH version '4'"),
        ("4.0 0 8", "unsupported MSH version '4.0'"),
        ("2.2 1 8", "MSH 2.2 binary is not supported"),
        ("4.1 2 8", "file type 2"),
        ("4.1 0 0", "data size 0"),
        ("4.1", "expected the file type"),
    ] {
        let e = error_of(&replace_line(&v22, "2.2 0 8", version));
        assert_eq!(line_of_error(&e), 2, "{version}");
        assert_mentions(&e, &[culprit]);
    }
    let e = error_of(&replace_line(
        &v22,
        "$MeshFormat",
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$MeshFormat",
    ));
    assert_mentions(&e, &["second $MeshFormat"]);
    let e = error_of(&format!("{v22}garbage\n"));
    assert_mentions(&e, &["expected a section header", "'garbage'"]);
    let e = error_of(&format!("{v22}$EndNodes\n"));
    assert_mentions(&e, &["'$EndNodes' closes a section never opened"]);
}

/// Byte offset of `needle` in `hay`.
fn find(hay: &[u8], needle: &[u8]) -> usize {
    hay.windows(needle.len())
        .position(|w| w == needle)
        .expect("found")
}

#[test]
fn binary_errors() {
    let bytes = fixture_bytes("tri1_v41_bin.msh");
    let text_line = |at: usize| 1 + bytes[..at].iter().filter(|&&b| b == b'\n').count();
    let nodes = find(&bytes, b"$Nodes\n");

    // Truncated inside the $Nodes data.
    let e = mesh_of(&bytes[..nodes + 100]).unwrap_err();
    assert_eq!(line_of_error(&e), text_line(nodes));
    assert_mentions(&e, &["truncated", "byte offset"]);

    // data-size 4 (a 32-bit size_t).
    let mut four = bytes.clone();
    four[find(&bytes, b"4.1 1 8") + 6] = b'4';
    assert_mentions(&mesh_of(&four).unwrap_err(), &["case.msh:2:", "data-size 4"]);

    // The endianness int.
    let mut endian = bytes.clone();
    let one = find(&bytes, b"4.1 1 8\n") + 8;
    endian[one..one + 4].copy_from_slice(&[0, 0, 0, 1]);
    assert_mentions(&mesh_of(&endian).unwrap_err(), &["big-endian"]);
    endian[one..one + 4].copy_from_slice(&[7, 0, 0, 0]);
    assert_mentions(&mesh_of(&endian).unwrap_err(), &["endianness check", "07"]);

    // A huge node count in the first block: refused before any allocation.
    let mut huge = bytes.clone();
    let block = nodes + 7 + 32 + 12; // header, 4 size_t, 3 ints
    huge[block..block + 8].copy_from_slice(&u64::MAX.to_le_bytes());
    let e = mesh_of(&huge).unwrap_err();
    assert_eq!(line_of_error(&e), text_line(nodes));
    assert_mentions(&e, &["more nodes than the 18"]);
    let mut huge_total = huge.clone();
    huge_total[nodes + 15..nodes + 23].copy_from_slice(&u64::MAX.to_le_bytes());
    assert_mentions(
        &mesh_of(&huge_total).unwrap_err(),
        &["file truncated", "nodes need too many bytes"],
    );

    // A NaN coordinate.
    let mut nan = bytes.clone();
    let coords = block + 8 + 8; // the first block has 1 node: its tag, then x
    nan[coords..coords + 8].copy_from_slice(&f64::NAN.to_le_bytes());
    assert_mentions(&mesh_of(&nan).unwrap_err(), &["x is not a finite number"]);

    // Binary element type unknown: cannot even be skipped.
    let elements = find(&bytes, b"$Elements\n");
    let mut unknown = bytes.clone();
    let first_type = elements + 10 + 32 + 8;
    assert_eq!(unknown[first_type..first_type + 4], 15i32.to_le_bytes());
    unknown[first_type..first_type + 4].copy_from_slice(&1234i32.to_le_bytes());
    let e = mesh_of(&unknown).unwrap_err();
    assert_eq!(line_of_error(&e), text_line(elements));
    assert_mentions(&e, &["unknown gmsh element type 1234", "byte offset"]);
}

#[test]
fn entity_missing_from_entities() {
    let text = fixture_text("unassigned_v41.msh");
    let e = error_of(&replace_line(&text, "2 1 2 1", "2 8 2 1"));
    assert_eq!(line_of_error(&e), line_of(&text, "16 1 2 3"));
    assert_mentions(
        &e,
        &["element 16 is on surface entity 8, which $Entities does not list"],
    );
    let e = error_of(&replace_line(&text, "3 1 0 0 2 1 0 0 0", "1 1 0 0 2 1 0 0 0"));
    assert_mentions(&e, &["surface entity 1 is listed twice"]);
}

#[test]
fn physical_names_must_be_unique_per_dimension() {
    let v22 = fixture_text("sparse_v22.msh");
    let e = error_of(
        &replace_line(&v22, "1 10 \"base\"", "1 10 \"plate\"")
            .replace("0 20 \"axis origin\"", "2 20 \"plate\""),
    );
    assert!(matches!(e, MeshError::Invalid { .. }));
    assert_mentions(&e, &["physical surfaces 5 and 20 are both named 'plate'"]);
    let e = error_of(&replace_line(&v22, "3", "4").replace("2 5 \"plate\"", "2 5 \"plate\"\n2 5 \"slab\""));
    assert_mentions(&e, &["physical surface 5 is named both 'plate' and 'slab'"]);
    // Same name in two dimensions is fine.
    let ok = replace_line(&v22, "1 10 \"base\"", "1 10 \"plate\"");
    assert_eq!(mesh_of(ok.as_bytes()).unwrap().curves[1].name, "plate");
}

#[test]
fn read_msh_reports_io_errors() {
    let e = read_msh(Path::new("/nonexistent/dir/file.msh")).unwrap_err();
    assert!(matches!(e, MeshError::Io { .. }));
    assert_mentions(&e, &["/nonexistent/dir/file.msh"]);
}

#[test]
fn msh_file_can_be_built_by_hand() {
    // to_mesh re-checks what parse_msh guarantees, for hand-made files.
    let msh = MshFile {
        format: MshFormat::V41Ascii,
        physical_names: vec![],
        entities: vec![],
        nodes: vec![(1, [0.0, 0.0, 0.0]), (1, [1.0, 0.0, 0.0])],
        elements: vec![],
    };
    assert_mentions(
        &msh.to_mesh(Path::new("h.msh")).unwrap_err(),
        &["node tag 1 is defined twice"],
    );
    let msh = MshFile {
        nodes: vec![(1, [0.0, 0.0, 0.0]), (2, [1.0, 0.0, 0.0])],
        elements: vec![RawElement {
            tag: 4,
            gmsh_type: 2,
            entity_dim: 2,
            entity_tag: 1,
            physical_tags: vec![1],
            nodes: vec![1, 2],
            line: 9,
        }],
        ..msh
    };
    let e = msh.to_mesh(Path::new("h.msh")).unwrap_err();
    assert_eq!(line_of_error(&e), 9);
    assert_mentions(&e, &["element 4", "has 2 nodes, its type needs 3"]);
}

#[test]
fn huge_physical_tag_lists_are_not_copied_to_every_element() {
    // A surface entity in 3000 physical groups, with 2000 triangles: copying
    // its list to each element would take 6 million tags from 30 kB.
    let tags: Vec<String> = (1..=3000).map(|t| t.to_string()).collect();
    let mut text = format!(
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 1 0\n1 0 0 0 1 1 0 3000 {} 0\n$EndEntities\n\
         $Nodes\n1 3 1 3\n2 1 0 3\n1\n2\n3\n0 0 0\n1 0 0\n0 1 0\n$EndNodes\n$Elements\n1 2000 1 2000\n2 1 2 2000\n",
        tags.join(" ")
    );
    for t in 1..=2000 {
        text.push_str(&format!("{t} 1 2 3\n"));
    }
    text.push_str("$EndElements\n");
    let e = error_of(&text);
    assert_mentions(
        &e,
        &["surface entity 1 gives its elements implausibly many physical tags (3000 each)"],
    );
}

/// gmsh -part 2: MSH 4.1 puts the elements on partition entities, listed
/// in $PartitionedEntities only; MSH 2.2 just adds partition tags.
#[test]
fn partitioned_meshes() {
    let e = read_msh(&fixture("tri1_v41_part.msh")).unwrap_err();
    assert_mentions(
        &e,
        &[
            "element 1 is on point entity 7",
            "partitioned meshes are not supported",
        ],
    );
    let text = fixture_text("tri1_v22.msh");
    // Each element line `tag type 2 phys entity nodes...` gets the tags
    // `4 phys entity 1 2` (one partition, number 2).
    let (start, end) = (line_of(&text, "$Elements") + 1, line_of(&text, "$EndElements"));
    let partitioned: String = text
        .lines()
        .enumerate()
        .map(|(i, l)| {
            let t: Vec<&str> = l.split_whitespace().collect();
            if i + 1 > start && i + 1 < end {
                format!("{} {} 4 {} {} 1 2 {}\n", t[0], t[1], t[3], t[4], t[5..].join(" "))
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    assert_ne!(partitioned, text);
    assert_same_mesh(
        &mesh_of(text.as_bytes()).unwrap(),
        &mesh_of(partitioned.as_bytes()).unwrap(),
        "2.2 with partition tags",
    );
}
