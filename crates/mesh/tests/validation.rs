//! Mesh validation: the Jacobian's sign over the whole element, and the line
//! elements of used physical curves on element edges. Each malformed case
//! is a hand-written fixture with one line changed, and its error must name
//! the file, the element (or curve and line element) and the nodes; valid
//! meshes of every family, made by gmsh from the `.geo` files of `geo/`,
//! still pass.
//!
//! Fixtures (tests/fixtures/, MSH 2.2, all valid as committed):
//!
//! ```text
//!   square_t6_v22.msh         square_q8_v22.msh / square_q9_v22.msh
//!   4---8---3                 4-----7-----3
//!   |     / |                 |           |
//!   9  7    6    T6 11: 1 2 3 8     9     6    one Q8 (Q9) element 11,
//!   | /     |    T6 12: 1 3 4 |           |    [1, 3] x [0, 2]
//!   1---5---2                 1-----5-----2
//!   [1, 2] x [0, 1]; "bottom" = L3 line 10 (1 2 5) in each
//!
//!   grid_q4_v22.msh: 3 x 3 nodes on [1, 3] x [0, 2], Q4 30..33;
//!   7---8---9     "bottom" = L2 lines 20 (1 2), 21 (2 3)
//!   4---5---6     "middle" = L2 lines 22 (4 5), 23 (5 6): a joint inside
//!   1---2---3     the body
//! ```

use axijoint_mesh::geometry::{corner_and_gauss_dets, jacobian_range};
use axijoint_mesh::{
    check_curve_edges, gmsh, insert_joints, parse_msh, prepare, validate, JointSpec, Mesh, MeshError,
};
use std::path::{Path, PathBuf};

const FIXTURES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures");
const GEO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../geo");

fn fixture_text(name: &str) -> String {
    std::fs::read_to_string(Path::new(FIXTURES).join(name)).expect("fixture exists")
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

/// The mesh of a `.msh` text, read as if from `name`.
fn mesh_of(text: &str, name: &str) -> Mesh {
    let path = Path::new(name);
    parse_msh(text.as_bytes(), path)
        .and_then(|m| m.to_mesh(path))
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The error of validating a `.msh` text read as if from `name`.
fn validation_error(text: &str, name: &str) -> MeshError {
    let mut mesh = mesh_of(text, name);
    match validate(&mut mesh, Path::new(name)) {
        Ok(_) => panic!("{name}: expected a validation error"),
        Err(e) => e,
    }
}

/// Asserts the error displays every one of `parts`.
fn assert_mentions(e: &MeshError, parts: &[&str]) {
    let shown = e.to_string();
    for p in parts {
        assert!(shown.contains(p), "error '{shown}' does not mention '{p}'");
    }
}

/// The old check (corners and Gauss points only) finds one sign for the
/// cell tagged `tag`, and `jacobian_range` finds a sign change.
fn hidden_from_corners_and_gauss_points(mesh: &Mesh, tag: u64) {
    let cell = mesh.cells.iter().find(|c| c.tag == tag).expect("cell");
    let coords = mesh.cell_coords(cell);
    let (min, max) = corner_and_gauss_dets(cell.kind, &coords);
    assert!(min * max > 0.0, "corners and Gauss points: ({min}, {max})");
    let (lo, hi) = jacobian_range(cell.kind, &coords);
    assert!(lo < 0.0 && hi > 0.0, "whole element: ({lo}, {hi})");
}

/// The issue's T6: element 12's mid-side nodes on the wrong edges (each one
/// the middle of another edge: 8 on 1-4, 7 on 4-3, 9 on 3-1). `det J` is 5
/// at its corners and positive at its 6 Gauss points, -1/3 at its centroid.
#[test]
fn t6_with_mid_side_nodes_on_the_wrong_edges_is_refused() {
    let good = fixture_text("square_t6_v22.msh");
    let mut mesh = mesh_of(&good, "square_t6_v22.msh");
    let report = validate(&mut mesh, Path::new("square_t6_v22.msh")).unwrap();
    assert_eq!(report.reoriented, 0);

    let bad = replace_line(&good, "12 9 2 1 7 1 3 4 7 8 9", "12 9 2 1 7 1 4 3 8 7 9");
    hidden_from_corners_and_gauss_points(&mesh_of(&bad, "t6.msh"), 12);
    let e = validation_error(&bad, "t6_wrong_midsides.msh");
    assert!(matches!(e, MeshError::Invalid { .. }));
    assert_mentions(
        &e,
        &[
            "t6_wrong_midsides.msh: element 12 (T6, body 'body', surface entity 7)",
            "nodes 1 at (1, 0), 4 at (1, 1), 3 at (2, 1), 8 at (1.5, 1), 7 at (1.5, 0.5), 9 at (1, 0.5)",
            "Jacobian changes sign",
            "mid-side node on the wrong edge",
        ],
    );
}

/// Q8 and Q9 on [1, 3] x [0, 2] with mid-side node 5 pulled into the
/// element: positive at the corners and the 3 x 3 Gauss points, negative
/// elsewhere.
#[test]
fn q8_and_q9_inverted_between_their_gauss_points_are_refused() {
    for (file, kind, moved) in [
        ("square_q9_v22.msh", "Q9", "5 2 0.7 0"),
        ("square_q8_v22.msh", "Q8", "5 2.45 1.5 0"),
    ] {
        let good = fixture_text(file);
        let mut mesh = mesh_of(&good, file);
        validate(&mut mesh, Path::new(file)).unwrap_or_else(|e| panic!("{e}"));

        let bad = replace_line(&good, "5 2 0 0", moved);
        hidden_from_corners_and_gauss_points(&mesh_of(&bad, file), 11);
        let e = validation_error(&bad, file);
        let node5 = format!("5 at ({})", moved[2..moved.len() - 2].replace(' ', ", "));
        assert_mentions(
            &e,
            &[
                &format!("{file}: element 11 ({kind}, body 'body'"),
                &node5,
                "Jacobian changes sign",
            ],
        );
    }
}

/// Scene P and the pile in soil meshed by gmsh in every family (coarse and
/// fine, graded towards the pile; the pile in soil mixes a few triangles
/// into its quadrilaterals): every mesh validates, every cell's
/// `det J` is proven positive over the whole cell, and every physical curve
/// lies on element edges, before and after joint insertion.
#[test]
fn gmsh_meshes_of_every_family_pass() {
    let families = [
        ("T3", 1.0, 0.0, 0.0),
        ("T6", 2.0, 0.0, 0.0),
        ("Q4", 1.0, 1.0, 0.0),
        ("Q8", 2.0, 1.0, 1.0),
        ("Q9", 2.0, 1.0, 0.0),
    ];
    for (geo, joint, sizes) in [
        ("pile_footing.geo", "pile_side", [0.5, 0.15]),
        ("pile_soil.geo", "pile_side", [0.5, 0.25]),
    ] {
        let path = PathBuf::from(GEO).join(geo);
        for (family, order, quads, serendipity) in families {
            for size in sizes {
                let what = format!("{geo} {family} size {size}");
                let params: Vec<(String, f64)> = vec![
                    ("size".into(), size),
                    ("order".into(), order),
                    ("quads".into(), quads),
                    ("serendipity".into(), serendipity),
                ];
                let mut mesh = gmsh::load(&path, &params, None).unwrap_or_else(|e| panic!("{what}: {e}"));
                validate(&mut mesh, &path).unwrap_or_else(|e| panic!("{what}: {e}"));
                // Recombination may leave a few triangles of the same order.
                assert!(mesh.cells.iter().any(|c| c.kind.name() == family), "{what}");
                assert!(
                    mesh.cells.iter().all(|c| c.kind.is_quadratic() == (order == 2.0)),
                    "{what}"
                );
                for cell in &mesh.cells {
                    let (lo, _) = jacobian_range(cell.kind, &mesh.cell_coords(cell));
                    assert!(lo > 0.0, "{what}: element {}", cell.tag);
                }
                let names: Vec<&str> = mesh.curves.iter().map(|c| c.name.as_str()).collect();
                check_curve_edges(&mesh, &names, &path).unwrap_or_else(|e| panic!("{what}: {e}"));
                insert_joints(&mut mesh, &[JointSpec::new(joint)], &path)
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                let names: Vec<&str> = mesh.curves.iter().map(|c| c.name.as_str()).collect();
                check_curve_edges(&mesh, &names, &path).unwrap_or_else(|e| panic!("{what}: {e}"));
            }
        }
    }
}

/// A line element from boundary node 3 to the interior node 5 is no edge of
/// any element: as a support or load curve (`check_curve_edges`) and as a
/// joint (`insert_joints`, `prepare`).
#[test]
fn line_element_to_an_interior_node_is_named() {
    let good = fixture_text("grid_q4_v22.msh");
    let mesh = mesh_of(&good, "grid.msh");
    check_curve_edges(&mesh, &["bottom", "middle"], Path::new("grid.msh")).unwrap();
    let mut jointed = mesh.clone();
    insert_joints(&mut jointed, &[JointSpec::new("middle")], Path::new("grid.msh")).unwrap();
    check_curve_edges(&jointed, &["bottom", "middle"], Path::new("grid.msh")).unwrap();

    let bad = replace_line(&good, "21 1 2 2 1 2 3", "21 1 2 2 1 3 5");
    let mesh = mesh_of(&bad, "grid_bad_bottom.msh");
    // The cells are fine, the curve is not: validation checks every
    // physical curve, used or not.
    let e = validate(&mut mesh.clone(), Path::new("grid_bad_bottom.msh")).unwrap_err();
    assert_mentions(
        &e,
        &[
            "grid_bad_bottom.msh: physical curve 'bottom': line element 21",
            "no element has an edge from node 3 to node 5",
        ],
    );
    check_curve_edges(&mesh, &["middle"], Path::new("grid_bad_bottom.msh")).unwrap();
    let e = check_curve_edges(&mesh, &["middle", "bottom"], Path::new("grid_bad_bottom.msh")).unwrap_err();
    assert!(matches!(e, MeshError::Invalid { .. }));
    assert_mentions(
        &e,
        &[
            "grid_bad_bottom.msh: physical curve 'bottom': line element 21 (L2, curve entity 1)",
            "nodes 3 at (3, 0), 5 at (2, 1)",
            "is not an edge of any 2D element",
            "no element has an edge from node 3 to node 5",
        ],
    );

    // The same on a joint curve, by insert_joints and by prepare (a file).
    let bad = replace_line(&good, "23 1 2 3 2 5 6", "23 1 2 3 2 5 9");
    let mut mesh = mesh_of(&bad, "grid_bad_middle.msh");
    let e = insert_joints(
        &mut mesh,
        &[JointSpec::new("middle")],
        Path::new("grid_bad_middle.msh"),
    )
    .unwrap_err();
    let parts = [
        "physical curve 'middle': line element 23 (L2, curve entity 2)",
        "nodes 5 at (2, 1), 9 at (3, 2)",
        "no element has an edge from node 5 to node 9",
    ];
    assert_mentions(&e, &parts);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("grid_bad_middle.msh");
    std::fs::write(&file, &bad).unwrap();
    let e = prepare(&file, &[], &[JointSpec::new("middle")], None).unwrap_err();
    assert_mentions(&e, &parts);
    assert!(e.to_string().starts_with(&file.display().to_string()), "{e}");

    // An end node that belongs to no element at all.
    let orphan = replace_line(&good, "21 1 2 2 1 2 3", "21 1 2 2 1 3 10")
        .replace("$Nodes\n9\n", "$Nodes\n10\n10 4 0 0\n");
    let mesh = mesh_of(&orphan, "grid_orphan.msh");
    let e = check_curve_edges(&mesh, &["bottom"], Path::new("grid_orphan.msh")).unwrap_err();
    assert_mentions(
        &e,
        &[
            "physical curve 'bottom': line element 21",
            "node 10 at (4, 0) belongs to no 2D element",
        ],
    );

    // A name that is no physical curve.
    let e = check_curve_edges(&mesh, &["botom"], Path::new("grid_orphan.msh")).unwrap_err();
    assert!(matches!(e, MeshError::UnknownName { .. }), "{e}");
    assert_mentions(&e, &["'botom'", "bottom, middle"]);
}

/// Quadratic lines: the middle node must be the edge's middle node, and an
/// L2 line cannot run along elements with 3-node edges.
#[test]
fn quadratic_line_off_its_edge_is_named() {
    let good = fixture_text("square_t6_v22.msh");
    let mesh = mesh_of(&good, "t6.msh");
    check_curve_edges(&mesh, &["bottom"], Path::new("t6.msh")).unwrap();

    let bad = replace_line(&good, "10 8 2 2 1 1 2 5", "10 8 2 2 1 1 2 9");
    let mesh = mesh_of(&bad, "t6_bad_middle.msh");
    let e = check_curve_edges(&mesh, &["bottom"], Path::new("t6_bad_middle.msh")).unwrap_err();
    assert_mentions(
        &e,
        &[
            "t6_bad_middle.msh: physical curve 'bottom': line element 10 (L3, curve entity 1)",
            "nodes 1 at (1, 0), 2 at (2, 0), 9 at (1, 0.5)",
            "edge of element 11 (T6), whose middle node is 5 at (1.5, 0), not 9",
        ],
    );

    let bad = replace_line(&good, "10 8 2 2 1 1 2 5", "10 1 2 2 1 1 2");
    let mesh = mesh_of(&bad, "t6_l2.msh");
    let e = check_curve_edges(&mesh, &["bottom"], Path::new("t6_l2.msh")).unwrap_err();
    assert_mentions(
        &e,
        &[
            "physical curve 'bottom': line element 10 (L2, curve entity 1)",
            "edge of element 11 (T6), whose edges are L3 lines",
        ],
    );
}
