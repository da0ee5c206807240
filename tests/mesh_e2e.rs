//! End-to-end tests of the mesh stage: real gmsh runs of `geo/pile_footing.geo`
//! (Scene P, docs/theory.md section 14), joint insertion and validation errors.
//!
//! Scene P: pile r <= 0.5, -1.5 <= z <= 1.0; footing [0, 3] x [0, 2] minus the
//! embedded pile (r <= 0.5, 0 <= z <= 1). Joint `pile_side` (r = 0.5,
//! 0 <= z <= 1) between `pile` (bottom) and `footing` (top).

mod common;

use axijoint_mesh::{prepare, JointSpec, Mesh, MeshError, Summary};
use common::*;
use std::collections::BTreeSet;
use std::f64::consts::PI;

const FAMILIES: [&str; 5] = ["T3", "T6", "Q4", "Q8", "Q9"];

fn scene_p(family: &str, size: f64) -> Mesh {
    let (mesh, _) = prepare(
        &geo("pile_footing.geo"),
        &family_params(family, size),
        &[JointSpec::new("pile_side")],
        None,
    )
    .unwrap_or_else(|e| panic!("{family}: {e}"));
    mesh
}

fn centroid(mesh: &Mesh, c: usize) -> [f64; 2] {
    let cell = &mesh.cells[c];
    let k = cell.kind.n_corners();
    let s = cell.nodes[..k].iter().fold([0.0, 0.0], |s, &n| {
        [s[0] + mesh.nodes[n][0], s[1] + mesh.nodes[n][1]]
    });
    [s[0] / k as f64, s[1] / k as f64]
}

/// Areas are exact (straight edges), the joint's lateral area is 2 pi a L =
/// pi, and every pile_side node is duplicated except the one at the pile
/// head corner (0.5, 1.0): there the joint meets the bonded pile head, the
/// cells around the node stay connected through `pile_head`, so it stays
/// shared like a crack tip. The lower end (0.5, 0) is on the free boundary
/// (footing bottom / free pile side) and splits.
#[test]
fn scene_p_areas_and_joint_in_every_family() {
    for family in FAMILIES {
        // Count pile_side nodes before insertion.
        let (plain, _) = prepare(&geo("pile_footing.geo"), &family_params(family, 0.25), &[], None).unwrap();
        let side: BTreeSet<usize> = plain
            .curve("pile_side")
            .unwrap()
            .edges
            .iter()
            .flat_map(|e| e.nodes.iter().copied())
            .collect();

        let mesh = scene_p(family, 0.25);
        assert!(
            mesh.cells.iter().all(|c| c.kind.name() == family),
            "{family}: mixed families"
        );
        let s = Summary::of(&mesh);
        let area = |b: &str| s.bodies[b].area;
        assert!(
            (area("footing") - 5.5).abs() < 1e-12,
            "{family}: footing area {}",
            area("footing")
        );
        assert!(
            (area("pile") - 1.25).abs() < 1e-12,
            "{family}: pile area {}",
            area("pile")
        );
        let j = &s.joints["pile_side"];
        assert!(
            (j.lateral_area - PI).abs() < 1e-12,
            "{family}: lateral area {}",
            j.lateral_area
        );
        assert!((j.length - 1.0).abs() < 1e-12);
        assert_eq!(j.duplicated_nodes, side.len() - 1, "{family}");
        assert_eq!(mesh.nodes.len(), plain.nodes.len() + side.len() - 1, "{family}");
        assert_eq!(j.elements, plain.curve("pile_side").unwrap().edges.len());
        let shared: Vec<[f64; 2]> = side
            .iter()
            .filter(|n| !mesh.joints[0].duplicated.iter().any(|(o, _)| o == *n))
            .map(|&n| mesh.nodes[n])
            .collect();
        assert_eq!(shared, vec![[0.5, 1.0]], "{family}: the node that stays shared");
    }
}

#[test]
fn joint_orientation_and_pairing() {
    for family in FAMILIES {
        let mesh = scene_p(family, 0.3);
        let joint = mesh.joint("pile_side").unwrap();
        assert_eq!(joint.bottom_bodies, vec![mesh.body("pile").unwrap()]);
        assert_eq!(joint.top_bodies, vec![mesh.body("footing").unwrap()]);
        for el in &joint.elements {
            assert_eq!(mesh.bodies[mesh.cells[el.bottom_cell].body].name, "pile");
            assert_eq!(mesh.bodies[mesh.cells[el.top_cell].body].name, "footing");
            for (b, t) in el.bottom.iter().zip(&el.top) {
                assert_eq!(mesh.nodes[*b], mesh.nodes[*t], "{family}: paired nodes");
                assert!(mesh.cells[el.bottom_cell].nodes.contains(b));
                assert!(mesh.cells[el.top_cell].nodes.contains(t));
            }
            let (a, b) = (mesh.nodes[el.bottom[0]], mesh.nodes[el.bottom[1]]);
            let eta = [-(b[1] - a[1]), b[0] - a[0]];
            let (cb, ct) = (centroid(&mesh, el.bottom_cell), centroid(&mesh, el.top_cell));
            assert!(
                eta[0] * (ct[0] - cb[0]) + eta[1] * (ct[1] - cb[1]) > 0.0,
                "{family}: normal"
            );
            // On the vertical pile side the normal is +r: xi runs down (-z).
            assert!(eta[0] > 0.0 && eta[1].abs() < 1e-12);
        }
        // No footing cell touches a bottom-face node that was split.
        let split: BTreeSet<usize> = joint.duplicated.iter().map(|p| p.0).collect();
        for cell in mesh
            .cells
            .iter()
            .filter(|c| mesh.bodies[c.body].name == "footing")
        {
            assert!(cell.nodes.iter().all(|n| !split.contains(n)));
        }
    }
}

#[test]
fn explicit_sides_flip_the_normal() {
    let (mesh, _) = prepare(
        &geo("pile_footing.geo"),
        &family_params("Q4", 0.4),
        &["pile_side:footing/pile".parse().unwrap()],
        None,
    )
    .unwrap();
    let joint = &mesh.joints[0];
    assert_eq!(joint.bottom_bodies, vec![mesh.body("footing").unwrap()]);
    for el in &joint.elements {
        let (a, b) = (mesh.nodes[el.bottom[0]], mesh.nodes[el.bottom[1]]);
        assert!(-(b[1] - a[1]) < 0.0, "normal must point to -r, into the pile");
    }
}

#[test]
fn cli_json_summary() {
    let out = axijoint(&[
        "mesh",
        geo("pile_footing.geo").to_str().unwrap(),
        "--joints",
        "pile_side",
        "--set",
        "size=0.3",
        "--json",
    ]);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert!(v["nodes"].as_u64().unwrap() > 100);
    assert!((v["bodies"]["pile"]["area"].as_f64().unwrap() - 1.25).abs() < 1e-12);
    assert!(v["bodies"]["footing"]["elements"].as_u64().unwrap() > 10);
    let j = &v["joints"]["pile_side"];
    assert!((j["lateral_area"].as_f64().unwrap() - PI).abs() < 1e-12);
    assert!(j["duplicated_nodes"].as_u64().unwrap() >= 2 * j["elements"].as_u64().unwrap());
}

fn error_of(path: &std::path::Path, params: &[(String, f64)], joints: &[&str]) -> String {
    let specs: Vec<JointSpec> = joints.iter().map(|s| s.parse().unwrap()).collect();
    match prepare(path, params, &specs, None) {
        Ok(_) => panic!("{}: expected an error", path.display()),
        Err(e) => e.to_string(),
    }
}

#[test]
fn unknown_joint_name_is_named() {
    let e = error_of(&geo("pile_footing.geo"), &family_params("Q4", 0.5), &["pile_sde"]);
    assert!(e.contains("pile_sde") && e.contains("pile_side"), "{e}");
    let e = error_of(
        &geo("pile_footing.geo"),
        &family_params("Q4", 0.5),
        &["pile_side:pile/soil"],
    );
    assert!(e.contains("'soil'") && e.contains("footing"), "{e}");
}

#[test]
fn joint_on_the_boundary_is_refused() {
    let e = error_of(
        &geo("pile_footing.geo"),
        &family_params("Q4", 0.5),
        &["footing_outer"],
    );
    assert!(e.contains("footing_outer") && e.contains("one side only"), "{e}");
}

#[test]
fn cli_errors_exit_nonzero_and_name_the_culprit() {
    let out = axijoint(&["mesh", "no/such/file.geo"]);
    let (_, err) = text(&out);
    assert_eq!(out.status.code(), Some(1));
    assert!(err.contains("no/such/file.geo"), "{err}");

    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.geo");
    std::fs::write(&bad, "Point(1) = {0, 0, 0;\n").unwrap();
    let out = axijoint(&["mesh", bad.to_str().unwrap()]);
    let (_, err) = text(&out);
    assert_eq!(out.status.code(), Some(4), "a gmsh failure");
    assert!(err.contains("bad.geo") && err.contains("syntax error"), "{err}");

    let out = axijoint(&[
        "mesh",
        geo("pile_footing.geo").to_str().unwrap(),
        "--set",
        "size=abc",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out).1.contains("size=abc"));
}

/// A square at r < 0 (gmsh x < 0).
#[test]
fn negative_radius_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let geo = dir.path().join("left.geo");
    std::fs::write(
        &geo,
        "Point(1)={-1,0,0,0.5}; Point(2)={0,0,0,0.5}; Point(3)={0,1,0,0.5}; Point(4)={-1,1,0,0.5};\n\
         Line(1)={1,2}; Line(2)={2,3}; Line(3)={3,4}; Line(4)={4,1};\n\
         Curve Loop(1)={1,2,3,4}; Plane Surface(1)={1}; Physical Surface(\"body\")={1};\n",
    )
    .unwrap();
    let e = error_of(&geo, &[], &[]);
    assert!(
        e.contains("left.geo") && e.contains("r < 0") && e.contains("node"),
        "{e}"
    );
}

/// A surface meshed clockwise is renumbered, not refused.
#[test]
fn clockwise_surface_is_reoriented() {
    let dir = tempfile::tempdir().unwrap();
    let geo = dir.path().join("cw.geo");
    std::fs::write(
        &geo,
        "Point(1)={1,0,0,0.5}; Point(2)={2,0,0,0.5}; Point(3)={2,1,0,0.5}; Point(4)={1,1,0,0.5};\n\
         Line(1)={1,4}; Line(2)={4,3}; Line(3)={3,2}; Line(4)={2,1};\n\
         Curve Loop(1)={1,2,3,4}; Plane Surface(1)={1}; Physical Surface(\"body\")={1};\n\
         Mesh.ElementOrder = 2;\n",
    )
    .unwrap();
    let (mesh, report) = prepare(&geo, &[], &[], None).unwrap();
    assert_eq!(report.reoriented, mesh.cells.len());
    assert!((Summary::of(&mesh).bodies["body"].area - 1.0).abs() < 1e-12);
}

/// Hand-written MSH 2.2: two T3 in one surface entity, the second clockwise.
#[test]
fn inverted_element_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let msh = dir.path().join("inverted.msh");
    std::fs::write(
        &msh,
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"body\"\n$EndPhysicalNames\n\
         $Nodes\n4\n1 1 0 0\n2 2 0 0\n3 2 1 0\n4 1 1 0\n$EndNodes\n\
         $Elements\n2\n10 2 2 1 7 1 2 3\n11 2 2 1 7 1 3 4\n$EndElements\n",
    )
    .unwrap();
    let (mesh, _) = prepare(&msh, &[], &[], None).unwrap();
    assert_eq!(mesh.cells.len(), 2);
    std::fs::write(
        &msh,
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"body\"\n$EndPhysicalNames\n\
         $Nodes\n4\n1 1 0 0\n2 2 0 0\n3 2 1 0\n4 1 1 0\n$EndNodes\n\
         $Elements\n2\n10 2 2 1 7 1 2 3\n11 2 2 1 7 1 4 3\n$EndElements\n",
    )
    .unwrap();
    let e = error_of(&msh, &[], &[]);
    assert!(
        e.contains("inverted.msh") && e.contains("element 11") && e.contains("inverted"),
        "{e}"
    );

    // A collinear triangle is degenerate.
    std::fs::write(
        &msh,
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"body\"\n$EndPhysicalNames\n\
         $Nodes\n3\n1 1 0 0\n2 2 0 0\n3 3 0 0\n$EndNodes\n\
         $Elements\n1\n12 2 2 1 7 1 2 3\n$EndElements\n",
    )
    .unwrap();
    let e = error_of(&msh, &[], &[]);
    assert!(e.contains("element 12") && e.contains("degenerate"), "{e}");
}

/// A quadrilateral folded over itself (a "bow tie").
#[test]
fn folded_quad_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let msh = dir.path().join("folded.msh");
    std::fs::write(
        &msh,
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"body\"\n$EndPhysicalNames\n\
         $Nodes\n4\n1 1 0 0\n2 2 0 0\n3 1 1 0\n4 2 1 0\n$EndNodes\n\
         $Elements\n1\n21 3 2 1 7 1 2 3 4\n$EndElements\n",
    )
    .unwrap();
    let e = error_of(&msh, &[], &[]);
    assert!(
        e.contains("element 21") && e.contains("Jacobian changes sign"),
        "{e}"
    );
}

/// An element outside every physical surface (MSH 2.2 physical tag 0).
#[test]
fn element_in_no_physical_surface_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let msh = dir.path().join("orphan.msh");
    std::fs::write(
        &msh,
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"body\"\n$EndPhysicalNames\n\
         $Nodes\n4\n1 1 0 0\n2 2 0 0\n3 2 1 0\n4 1 1 0\n$EndNodes\n\
         $Elements\n2\n10 2 2 1 7 1 2 3\n11 2 2 0 8 1 3 4\n$EndElements\n",
    )
    .unwrap();
    let e = error_of(&msh, &[], &[]);
    assert!(
        e.contains("orphan.msh") && e.contains("11") && e.contains("no physical surface"),
        "{e}"
    );
}

#[test]
fn missing_file_error_is_io() {
    let r = prepare(std::path::Path::new("/no/such.msh"), &[], &[], None);
    assert!(matches!(r, Err(MeshError::Io { .. })));
}

/// geo/joint_junctions.geo: joints that end on the free boundary, inside a
/// body (crack tips), at another joint, and on the axis.
#[test]
fn joint_ends_junctions_tips_and_axis() {
    for (order, quads) in [(1.0, 0.0), (2.0, 0.0), (2.0, 1.0)] {
        let params = vec![("order".to_string(), order), ("quads".to_string(), quads)];
        let path = geo("joint_junctions.geo");
        let (plain, _) = prepare(&path, &params, &[], None).unwrap();
        let specs: Vec<JointSpec> = ["ab", "top", "crack"]
            .iter()
            .map(|s| s.parse().unwrap())
            .collect();
        let (mesh, _) = prepare(&path, &params, &specs, None).unwrap();
        let nodes_of = |m: &Mesh, name: &str| -> BTreeSet<usize> {
            m.curve(name)
                .unwrap()
                .edges
                .iter()
                .flat_map(|e| e.nodes.iter().copied())
                .collect()
        };
        let copies_at = |p: [f64; 2]| mesh.nodes.iter().filter(|q| **q == p).count();
        // Junction of three bodies at (1, 1): three copies.
        assert_eq!(copies_at([1.0, 1.0]), 3, "order {order}");
        // The axis end of "top", the free ends of "ab" and "top": two copies.
        for p in [[0.0, 1.0], [1.0, 0.0], [2.0, 1.0]] {
            assert_eq!(copies_at(p), 2, "order {order}: {p:?}");
        }
        // Crack tips inside C stay shared.
        assert_eq!(copies_at([0.5, 1.5]), 1);
        assert_eq!(copies_at([1.5, 1.5]), 1);
        // Node count: every joint node gets one copy except the crack tips
        // (none) and the junction (two).
        let joint_nodes: BTreeSet<usize> = ["ab", "top", "crack"]
            .iter()
            .flat_map(|n| nodes_of(&plain, n))
            .collect();
        assert_eq!(mesh.nodes.len(), plain.nodes.len() + joint_nodes.len() - 2 + 1);
        // Sides: "top" between A/B (bottom, lower tag) and C; crack inside C.
        let top = mesh.joint("top").unwrap();
        let body = |n: &str| mesh.body(n).unwrap();
        assert_eq!(top.bottom_bodies, vec![body("A"), body("B")]);
        assert_eq!(top.top_bodies, vec![body("C")]);
        let crack = mesh.joint("crack").unwrap();
        assert_eq!(
            (&crack.bottom_bodies, &crack.top_bodies),
            (&vec![body("C")], &vec![body("C")])
        );
        for j in &mesh.joints {
            for el in &j.elements {
                let (a, b) = (mesh.nodes[el.bottom[0]], mesh.nodes[el.bottom[1]]);
                let eta = [-(b[1] - a[1]), b[0] - a[0]];
                let (cb, ct) = (centroid(&mesh, el.bottom_cell), centroid(&mesh, el.top_cell));
                assert!(
                    eta[0] * (ct[0] - cb[0]) + eta[1] * (ct[1] - cb[1]) > 0.0,
                    "{}",
                    j.name
                );
                for (p, q) in el.bottom.iter().zip(&el.top) {
                    assert_eq!(mesh.nodes[*p], mesh.nodes[*q]);
                }
            }
        }
        // The crack runs r = 0.5 -> 1.5 in gmsh; the bottom is on its right (z < 1.5).
        for el in &crack.elements {
            assert!(centroid(&mesh, el.bottom_cell)[1] < 1.5);
        }
    }
}

/// `axijoint mesh` on a scene file meshes its geometry with its parameters
/// and inserts its joints.
#[test]
fn cli_mesh_of_a_scene_file() {
    let out = axijoint(&[
        "mesh",
        geo("pile_footing.json").to_str().unwrap(),
        "--set",
        "size=0.4",
        "--json",
    ]);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert!((v["joints"]["pile_side"]["lateral_area"].as_f64().unwrap() - PI).abs() < 1e-12);
    assert!((v["bodies"]["footing"]["area"].as_f64().unwrap() - 5.5).abs() < 1e-12);
}

/// A scene whose support or joint curve has a line element that is no edge
/// of any element (here from boundary node 3 to the interior node 5 of a
/// 2 x 2 grid of Q4): `axijoint mesh scene.json` names the scene key, the
/// mesh file, the curve, the line element and its nodes.
#[test]
fn scene_curve_off_the_element_edges_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let grid = std::fs::read_to_string(root().join("crates/mesh/tests/fixtures/grid_q4_v22.msh")).unwrap();
    let msh = dir.path().join("grid.msh");
    let scene = dir.path().join("scene.json");
    let write_scene = |extra: &str| {
        std::fs::write(
            &scene,
            format!(
                r#"{{"mesh": {{"file": "grid.msh"}}, "materials": {{"body": {{"E": 1000, "nu": 0.3}}}},
                    "supports": [{{"on": "bottom", "fix": "all"}}], "harmonics": 0{extra}}}"#
            ),
        )
        .unwrap();
    };
    let run = || {
        let out = axijoint(&["mesh", scene.to_str().unwrap()]);
        let (stdout, stderr) = text(&out);
        (out.status.success(), stdout, stderr)
    };
    let joint = r#", "joints": {"middle": {"k_xi": 1, "k_eta": 1, "k_theta": 1, "law": {"type": "linear"}}}"#;

    std::fs::write(&msh, &grid).unwrap();
    write_scene(joint);
    let (ok, stdout, stderr) = run();
    assert!(ok && stdout.contains("middle"), "{stdout}{stderr}");

    std::fs::write(&msh, grid.replace("\n21 1 2 2 1 2 3\n", "\n21 1 2 2 1 3 5\n")).unwrap();
    write_scene("");
    let (ok, _, stderr) = run();
    assert!(!ok);
    for part in [
        "scene.json: supports[0].on: ",
        "grid.msh: physical curve 'bottom': line element 21 (L2, curve entity 1) with nodes 3 at (3, 0), 5 at (2, 1) is not an edge of any 2D element",
    ] {
        assert!(stderr.contains(part), "'{stderr}' does not mention '{part}'");
    }

    std::fs::write(&msh, grid.replace("\n23 1 2 3 2 5 6\n", "\n23 1 2 3 2 5 9\n")).unwrap();
    write_scene(joint);
    let (ok, _, stderr) = run();
    assert!(!ok);
    for part in [
        "scene.json: joints.middle: ",
        "physical curve 'middle': line element 23 (L2, curve entity 2) with nodes 5 at (2, 1), 9 at (3, 2)",
    ] {
        assert!(stderr.contains(part), "'{stderr}' does not mention '{part}'");
    }
}

/// gmsh dies with `axijoint`: a run killed while gmsh meshes (SIGTERM to
/// `axijoint` alone, as a scheduler or a user's `kill` sends it) leaves no
/// gmsh meshing on as an orphan.
#[cfg(target_os = "linux")]
#[test]
fn gmsh_dies_with_a_killed_run() {
    use std::time::{Duration, Instant};
    // The children of `pid` (from /proc), and whether `pid` still runs
    // (a zombie does not).
    let children = |pid: u32| -> Vec<u32> {
        std::fs::read_to_string(format!("/proc/{pid}/task/{pid}/children"))
            .unwrap_or_default()
            .split_whitespace()
            .filter_map(|p| p.parse().ok())
            .collect()
    };
    let running = |pid: u32| {
        std::fs::read_to_string(format!("/proc/{pid}/stat"))
            .ok()
            .and_then(|s| {
                s.rsplit(") ")
                    .next()
                    .map(|r| !r.starts_with('Z') && !r.starts_with('X'))
            })
            .unwrap_or(false)
    };
    // A mesh gmsh takes well over the seconds this test needs.
    let mut run = std::process::Command::new(env!("CARGO_BIN_EXE_axijoint"))
        .args(["--no-cache", "mesh"])
        .arg(geo("pile_footing.geo"))
        .args(["--set", "size=0.005"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let gmsh = loop {
        if let Some(&g) = children(run.id()).first() {
            break g;
        }
        assert!(start.elapsed() < Duration::from_secs(30), "gmsh did not start");
        std::thread::sleep(Duration::from_millis(20));
    };
    std::thread::sleep(Duration::from_millis(300));
    assert!(running(gmsh), "gmsh meshes");
    // SIGTERM to axijoint alone.
    terminate(run.id());
    run.wait().unwrap();
    let start = Instant::now();
    // Killed with its parent it stops at once; without that it went on
    // until its next write to the closed pipe (4.5 s measured here).
    while running(gmsh) {
        assert!(
            start.elapsed() < Duration::from_secs(1),
            "gmsh (pid {gmsh}) still meshes after axijoint was killed"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// `kill -TERM pid` (the command, so the test needs no unsafe code).
#[cfg(target_os = "linux")]
fn terminate(pid: u32) {
    let ok = std::process::Command::new("kill")
        .args(["-TERM", &pid.to_string()])
        .status()
        .unwrap()
        .success();
    assert!(ok, "kill -TERM {pid}");
}
