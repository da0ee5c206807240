//! `mesh_solved.msh` read as a user would, with meshio and numpy alone
//! (docs/outputs.md): Scene P solved on a coarse mesh, then a Python script
//! (the interpreter of `target/venv`, made by `scripts/setup`) places
//! `displacement.f64` on the nodes of `mesh_solved.msh` and compares them
//! with `mesh.msh`, gmsh's own file; gmsh reads the file back too.

mod common;

use axijoint_mesh::parse_msh;
use common::*;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The Python of `scripts/setup`'s virtual environment.
fn python() -> PathBuf {
    root().join("target/venv/bin/python3")
}

/// Measures a solution folder (argv[1]); prints one JSON object.
const SCRIPT: &str = r#"
import json, sys
import numpy as np
import meshio

d = sys.argv[1]
header = json.load(open(f"{d}/solution.json"))
solved = meshio.read(f"{d}/mesh_solved.msh")
gmsh = meshio.read(f"{d}/mesh.msh")
n = len(solved.points)

# displacement.f64: [harmonic][family][node][u_r, u_z, u_theta], f64 LE.
u = np.fromfile(f"{d}/displacement.f64", dtype="<f8")
harmonics = header["harmonics"]
rows = u.size // (len(harmonics) * 2 * 3)
u = u.reshape(len(harmonics), 2, rows, 3)

# Every node of mesh_solved.msh on a node of mesh.msh, same coordinates.
known = {tuple(p) for p in gmsh.points}
on_gmsh_node = all(tuple(p) in known for p in solved.points)
distinct = len({tuple(p) for p in solved.points})
used = np.unique(np.concatenate(
    [c.data.ravel() for c in gmsh.cells if c.dim == 2])).size

def cells(mesh, name, dim):
    """The cells of the physical group `name`: [(type, nodes)]."""
    tag, gdim = mesh.field_data[name]
    assert gdim == dim, (name, gdim, dim)
    out = []
    for block, idx in zip(mesh.cells, mesh.cell_sets[name]):
        out.extend((block.type, block.data[i]) for i in idx)
    return out

side = cells(gmsh, "pile_side", 1)
side_nodes = np.unique(np.concatenate([c for _, c in side])).size
quads = cells(solved, "pile_side", 2)
pairs_equal = all(
    np.array_equal(solved.points[q[0]], solved.points[q[3]])
    and np.array_equal(solved.points[q[1]], solved.points[q[2]])
    for _, q in quads)
split = {int(q[k]) for _, q in quads for k in (2, 3) if q[k] != q[3 - k]}

# Fixed support: all three components zero at every harmonic.
support = np.unique(np.concatenate([c for _, c in cells(solved, "footing_outer", 1)]))
support_max = float(np.abs(u[:, :, support, :]).max())

# |u| at the nodes over 16 sections, synthesised as docs/outputs.md says.
umax = 0.0
for k in range(16):
    t = np.pi * k / 8
    s = np.zeros((rows, 3))
    for i, m in enumerate(harmonics):
        sym, anti = u[i, 0], u[i, 1]
        if m == 0:
            s += sym
            continue
        c, sn = np.cos(m * t), np.sin(m * t)
        s[:, 0] += sym[:, 0] * c + anti[:, 0] * sn
        s[:, 1] += sym[:, 1] * c + anti[:, 1] * sn
        s[:, 2] += sym[:, 2] * sn - anti[:, 2] * c
    umax = max(umax, float(np.linalg.norm(s, axis=1).max()))

print(json.dumps({
    "nodes": n,
    "rows": rows,
    "bytes_exact": u.size == len(harmonics) * 2 * rows * 3,
    "on_gmsh_node": on_gmsh_node,
    "z_zero": bool((solved.points[:, 2] == 0).all()),
    "duplicates": n - distinct,
    "gmsh_used_nodes": int(used),
    "side_lines": len(side),
    "side_line_types": sorted({t for t, _ in side}),
    "side_nodes": int(side_nodes),
    "quads": len(quads),
    "quad_types": sorted({t for t, _ in quads}),
    "pairs_equal": pairs_equal,
    "split": len(split),
    "support_nodes": int(support.size),
    "support_max": support_max,
    "max_displacement": umax,
    "names": {k: [int(v[0]), int(v[1])] for k, v in solved.field_data.items()},
}))
"#;

fn measure(dir: &Path) -> Value {
    let py = python();
    let run = Command::new(&py)
        .arg("-c")
        .arg(SCRIPT)
        .arg(dir)
        .output()
        .unwrap_or_else(|e| {
            panic!(
                "cannot run {} ({e}): run scripts/setup (it makes target/venv with meshio and numpy)",
                py.display()
            )
        });
    let (stdout, stderr) = text(&run);
    assert!(
        run.status.success(),
        "the meshio script failed (if meshio or numpy is missing, run scripts/setup):\n{stderr}"
    );
    serde_json::from_str(&stdout).unwrap_or_else(|e| panic!("{e}: {stdout}"))
}

/// Scene P at size 0.5 (Q9, quadratic joint along the pile side): the
/// solved mesh holds gmsh's nodes plus one copy per split joint node.
#[test]
fn solved_mesh_places_the_displacements() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p");
    let scene = geo("pile_footing.json");
    let run = axijoint(&[
        "solve",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--set",
        "size=0.5",
        "--quiet",
    ]);
    let (stdout, stderr) = text(&run);
    assert!(run.status.success(), "{stdout}\n{stderr}");
    let header: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("solution.json")).unwrap()).unwrap();
    let m = measure(&out);
    eprintln!("{m}");
    let int = |k: &str| m[k].as_u64().unwrap_or_else(|| panic!("{k}: {m}"));
    let yes = |k: &str| assert_eq!(m[k], Value::Bool(true), "{k}: {m}");

    // Node k of mesh_solved.msh is row k of displacement.f64.
    yes("bytes_exact");
    assert_eq!(int("nodes"), int("rows"), "{m}");
    assert_eq!(int("nodes"), header["mesh"]["nodes"].as_u64().unwrap());
    // Each node is one of gmsh's; the copies are the joint's split nodes:
    // every node of the pile side but its head end, bonded to pile_head.
    yes("on_gmsh_node");
    yes("z_zero");
    assert_eq!(int("duplicates"), int("side_nodes") - 1, "{m}");
    assert_eq!(int("nodes"), int("gmsh_used_nodes") + int("duplicates"), "{m}");
    assert_eq!(int("split"), int("duplicates"), "{m}");
    // Two zero-thickness quadrangles per quadratic joint element (one per
    // 3-node line of the curve in gmsh's mesh), faces paired node by node.
    assert_eq!(m["side_line_types"], serde_json::json!(["line3"]), "{m}");
    assert_eq!(m["quad_types"], serde_json::json!(["quad"]), "{m}");
    assert_eq!(int("quads"), 2 * int("side_lines"), "{m}");
    yes("pairs_equal");
    // Physical names kept; the joint is a surface group of its own.
    for (name, dim) in [
        ("pile", 2),
        ("footing", 2),
        ("pile_side", 2),
        ("footing_outer", 1),
        ("pile_end", 1),
    ] {
        assert_eq!(m["names"][name][1], dim, "{name}: {m}");
    }
    // The displacements on these nodes: zero on the fixed support, and the
    // header's largest |u| (16 sections) recomputed from the documented
    // layout, to 1e-12 relative.
    assert!(int("support_nodes") > 4, "{m}");
    assert_eq!(m["support_max"], 0.0, "{m}");
    let (ours, theirs) = (
        m["max_displacement"].as_f64().unwrap(),
        header["max_displacement"].as_f64().unwrap(),
    );
    assert!(
        theirs > 0.0 && (ours - theirs).abs() <= 1e-12 * theirs,
        "{ours} vs {theirs}"
    );

    // gmsh reads the file: saved again by gmsh (MSH 2.2), the same nodes.
    let resaved = dir.path().join("resaved.msh");
    let g = Command::new("gmsh")
        .arg(out.join("mesh_solved.msh"))
        .args(["-save", "-format", "msh22", "-o"])
        .arg(&resaved)
        .output()
        .expect("gmsh runs (scripts/setup installs it)");
    let (gout, gerr) = text(&g);
    assert!(
        g.status.success() && !gout.contains("Error") && !gerr.contains("Error"),
        "{gout}\n{gerr}"
    );
    let again = parse_msh(&std::fs::read(&resaved).unwrap(), &resaved).unwrap();
    assert_eq!(again.nodes.len() as u64, int("nodes"));
    let quads = again
        .elements
        .iter()
        .filter(|e| e.gmsh_type == 3 && e.entity_dim == 2)
        .count();
    assert_eq!(quads as u64, int("quads"));
}
