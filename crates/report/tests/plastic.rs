//! The plastic bodies' field (issue 26 item 4): `plastic.json` in the
//! solution folder and the cell arrays `yield_fraction`,
//! `plastic_strain_eq`, `plastic_section_deg` of `field.vtu`.
//!
//! Tresca's thick cylinder `0.5 <= r <= 1` (geo/thick_cylinder.geo, Q9,
//! size 1/16), plane strain, under the internal pressure that makes it
//! yield out to r = 0.75 (Hill 1950), solved through the library
//! (`solve_scene`), written with `write_solution`, read back and reported
//! with `write_report`:
//!
//! - `plastic.json` reads back equal to the run's field to 1e-15;
//! - in `field.vtu` (read back with `vtu::read_vtu`), every revolved cell
//!   of the column next to the inner face has `yield_fraction` 1 and a
//!   positive `plastic_strain_eq`, every cell of the column at the outer
//!   face 0 and 0; each cell's values are the mean over its meridional
//!   cell's Gauss points of `plastic.json` at the section it names;
//! - a radial cut's `sigma_r` and `sigma_theta` (recovered from
//!   `plastic.json` in the plastic body) within 2 % of `c_u` of Hill's
//!   closed form at every cut point, in the plastic zone and out of it;
//!   `field.vtu`'s `sigma_cyl` at the cut's nodes within 3 %, and the gmsh
//!   views' at every node of every cell within 3 %;
//! - without `plastic.json` (a folder of an elastic run, or an older one)
//!   the report still reads the folder and writes no plastic array.

use axijoint_report::vtu::read_vtu;
use axijoint_report::write_report;
use axijoint_solver::results::{
    equivalent_plastic_strain, read_plastic_field, read_solution, write_solution, PlasticFieldFile,
    PLASTIC_FIELD,
};
use axijoint_solver::run::{solution_header, solve_scene};
use axijoint_solver::scene::Scene;
use serde_json::json;
use std::path::{Path, PathBuf};

fn geo(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../geo").join(name)
}

fn scene() -> Scene {
    Scene::from_str(&scene_json().to_string(), geo("plastic_cylinder.json")).expect("scene")
}

fn scene_json() -> serde_json::Value {
    json!({
        "title": "thick cylinder",
        "mesh": {"file": geo("thick_cylinder.geo"), "parameters": {"a": 1.0, "hole": 0.5, "L": 0.25, "size": 0.0625}},
        "materials": {"body": {"E": 1000.0, "nu": 0.3, "plasticity": {"type": "tresca", "c_u": 1.0}}},
        "supports": [{"on": "bottom", "fix": ["z", "theta"]}, {"on": "top", "fix": ["z"]}],
        "loads": [{"type": "traction", "on": "inner", "harmonic": 0, "t_r": 1.2484}],
        "harmonics": 0,
        "solver": {"method": "newton", "epsilon": 1e-8, "loading": {"steps": 4}}
    })
}

/// Solves `scene` and writes its solution folder `dir` with `plastic.json`.
fn solve_into(scene: &Scene, tmp: &Path, dir: &Path) {
    let msh = tmp.join("mesh.msh");
    let run = solve_scene(scene, Some(&msh), |_| {}).unwrap_or_else(|e| panic!("{}", e.error));
    let mesh = &run.problem.model.mesh;
    let body = run
        .outcome
        .as_ref()
        .and_then(|o| o.body.as_ref())
        .expect("a body field");
    let field = PlasticFieldFile::new(mesh, body, None);
    let header = solution_header(scene, &run);
    write_solution(
        dir,
        &header,
        &run.displacements,
        None,
        &msh,
        mesh,
        None,
        Some(&field),
    )
    .unwrap();
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-15 * a.abs().max(b.abs())
}

fn assert_same(back: &PlasticFieldFile, field: &PlasticFieldFile) {
    let all = |a: &[f64], b: &[f64]| a.len() == b.len() && a.iter().zip(b).all(|(&x, &y)| close(x, y));
    assert!(all(&back.sections_deg, &field.sections_deg));
    assert!(all(&back.section_weights, &field.section_weights));
    assert_eq!(back.points.len(), field.points.len());
    for (a, b) in back.points.iter().zip(&field.points) {
        assert_eq!((&a.body, a.cell), (&b.body, b.cell));
        assert!(all(&[a.r, a.z], &[b.r, b.z]), "{a:?} {b:?}");
    }
    assert_eq!(back.values.len(), field.values.len());
    for (ra, rb) in back.values.iter().zip(&field.values) {
        assert_eq!(ra.len(), rb.len());
        for (a, b) in ra.iter().zip(rb) {
            assert!(
                all(&a.sigma, &b.sigma) && all(&a.plastic, &b.plastic),
                "{a:?} {b:?}"
            );
            assert_eq!(a.yielding, b.yielding);
        }
    }
}

#[test]
fn thick_cylinder_plastic_zone_in_the_folder_and_the_vtu() {
    let scene = scene();
    let tmp = tempfile::tempdir().unwrap();
    let msh = tmp.path().join("mesh.msh");
    let run = solve_scene(&scene, Some(&msh), |_| {}).unwrap_or_else(|e| panic!("{}", e.error));
    let mesh = &run.problem.model.mesh;
    let body = run
        .outcome
        .as_ref()
        .and_then(|o| o.body.as_ref())
        .expect("a body field");
    let field = PlasticFieldFile::new(mesh, body, None);
    let dir = tmp.path().join("out");
    let header = solution_header(&scene, &run);
    write_solution(
        &dir,
        &header,
        &run.displacements,
        None,
        &msh,
        mesh,
        None,
        Some(&field),
    )
    .unwrap();

    // The file reads back as written.
    let back = read_plastic_field(&dir)
        .unwrap()
        .expect("plastic.json is written");
    assert_same(&back, &field);

    // The report's field.vtu.
    let saved = read_solution(&dir).unwrap();
    let written = write_report(&dir, &saved, None, None, &[]).unwrap();
    assert!(written.files.iter().any(|f| f == Path::new("field.vtu")));
    let vtu = read_vtu(&dir.join("field.vtu")).unwrap();
    let cell_values = |name: &str| {
        vtu.array("CellData", name)
            .unwrap_or_else(|| panic!("no cell array {name}"))
            .values()
            .unwrap()
    };
    let (fraction, strain) = (cell_values("yield_fraction"), cell_values("plastic_strain_eq"));
    let (section, cells) = (cell_values("plastic_section_deg"), cell_values("meridional_cell"));
    assert_eq!(fraction.len(), vtu.n_cells);
    let r_range = |c: usize| {
        let r = saved.mesh.cells[c].nodes.iter().map(|&n| saved.mesh.nodes[n][0]);
        (r.clone().fold(f64::INFINITY, f64::min), r.fold(0.0, f64::max))
    };
    let (mut inner, mut outer) = (0, 0);
    for i in 0..vtu.n_cells {
        let c = cells[i] as usize;
        assert!((0.0..=1.0).contains(&fraction[i]) && strain[i] >= 0.0, "cell {i}");
        // The mean over the cell's Gauss points at the section named.
        let s = back
            .sections_deg
            .iter()
            .position(|&d| d == section[i])
            .expect("a section of the file");
        let points: Vec<usize> = (0..back.points.len())
            .filter(|&q| back.points[q].cell == c)
            .collect();
        assert!(!points.is_empty());
        let v = &back.values[s];
        let n = points.len() as f64;
        let f = points.iter().filter(|&&q| v[q].yielding).count() as f64 / n;
        let e = points
            .iter()
            .map(|&q| equivalent_plastic_strain(&v[q].plastic))
            .sum::<f64>()
            / n;
        assert_eq!(fraction[i], f, "cell {i}");
        assert!((strain[i] - e).abs() <= 1e-15 * e, "cell {i}: {} {e}", strain[i]);
        let (lo, hi) = r_range(c);
        if (lo - 0.5).abs() < 1e-9 {
            inner += 1;
            assert_eq!(fraction[i], 1.0, "inner cell {i} (meridional {c})");
            assert!(strain[i] > 1e-4, "inner cell {i}: {}", strain[i]);
        }
        if (hi - 1.0).abs() < 1e-9 {
            outer += 1;
            assert_eq!(fraction[i], 0.0, "outer cell {i} (meridional {c})");
            assert_eq!(strain[i], 0.0, "outer cell {i}");
        }
    }
    let yielding = (0..vtu.n_cells).filter(|&i| fraction[i] == 1.0).count();
    println!(
        "of {} revolved cells: {yielding} all yielding, {inner} inner, {outer} outer",
        vtu.n_cells
    );
    // 4 cells along z at each face, each revolved into every slot.
    assert!(inner > 0 && inner == outer, "{inner} inner, {outer} outer");
    assert_eq!(inner % 4, 0);

    // A folder without the file (an elastic run, or written before it
    // existed) still reads, and its field.vtu has no plastic array.
    std::fs::remove_file(dir.join(PLASTIC_FIELD)).unwrap();
    assert_eq!(read_plastic_field(&dir).unwrap(), None);
    write_report(&dir, &read_solution(&dir).unwrap(), None, None, &[]).unwrap();
    let vtu = read_vtu(&dir.join("field.vtu")).unwrap();
    for name in ["yield_fraction", "plastic_strain_eq", "plastic_section_deg"] {
        assert!(vtu.array("CellData", name).is_none(), "{name}");
    }
    assert!(vtu.array("CellData", "error_energy").is_some());
}

/// Hill's closed form for the thick cylinder (c_u = 1, a = 0.5, b = 1,
/// plastic out to c = 0.75): `(sigma_r, sigma_theta)` at radius `r`.
fn hill(r: f64) -> (f64, f64) {
    let (a, b, c) = (0.5f64, 1.0f64, 0.75f64);
    let k = c * c / (b * b);
    if r <= c {
        let p = 1.0 - k + 2.0 * (c / a).ln();
        let s_r = -p + 2.0 * (r / a).ln();
        (s_r, s_r + 2.0)
    } else {
        (-k * (b * b / (r * r) - 1.0), k * (b * b / (r * r) + 1.0))
    }
}

#[test]
fn thick_cylinder_cut_stress_is_the_returned_one() {
    let mut s = scene_json();
    s["cuts"] = json!([{"name": "radial", "from": [0.5, 0.125], "to": [1.0, 0.125],
        "spacing": 0.025, "theta_deg": [0], "component": "sigma_theta"}]);
    s["outputs"] = json!({"plots": false, "gmsh_views": true});
    let scene = Scene::from_str(&s.to_string(), geo("plastic_cylinder.json")).expect("scene");
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    solve_into(&scene, tmp.path(), &dir);
    let saved = read_solution(&dir).unwrap();
    write_report(&dir, &saved, None, None, &[]).unwrap();
    let csv = std::fs::read_to_string(dir.join("cut_radial_theta0.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h.starts_with(name))
            .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
    };
    let (ir, isr, ith) = (col("r "), col("sigma_r "), col("sigma_theta "));
    let (mut worst_r, mut worst_th, mut rows) = (0.0f64, 0.0f64, 0);
    for line in lines {
        let v: Vec<&str> = line.split(',').collect();
        let num = |i: usize| v[i].trim().parse::<f64>().unwrap();
        let r = num(ir);
        let (sr, sth) = hill(r);
        let (er, eth) = ((num(isr) - sr).abs(), (num(ith) - sth).abs());
        println!(
            "r {r:.4}: sigma_r {:+.4} ({sr:+.4}), sigma_theta {:+.4} ({sth:+.4})",
            num(isr),
            num(ith)
        );
        worst_r = worst_r.max(er);
        worst_th = worst_th.max(eth);
        rows += 1;
    }
    println!("cut: {rows} rows, worst error sigma_r {worst_r:.4}, sigma_theta {worst_th:.4} (c_u = 1)");
    assert!(rows >= 21, "{rows} rows");
    assert!(
        worst_r <= 0.02 && worst_th <= 0.02,
        "sigma_r {worst_r}, sigma_theta {worst_th}"
    );

    // field.vtu's sigma_cyl at the points of the ring theta = 0 on z = 0.125.
    let vtu = read_vtu(&dir.join("field.vtu")).unwrap();
    let values = |parent: &str, name: &str| vtu.array(parent, name).unwrap().values().unwrap();
    let (xyz, cyl) = (values("Points", "Points"), values("PointData", "sigma_cyl"));
    let (mut worst, mut count) = (0.0f64, 0);
    for i in 0..vtu.n_points {
        let [x, y, z] = [xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]];
        if y.abs() > 1e-12 || x <= 0.0 || (z - 0.125).abs() > 1e-12 {
            continue;
        }
        let (sr, sth) = hill(x);
        worst = worst
            .max((cyl[6 * i] - sr).abs())
            .max((cyl[6 * i + 2] - sth).abs());
        count += 1;
    }
    println!("field.vtu: {count} points on the cut, worst error {worst:.4}");
    assert!(count >= 9 && worst <= 0.03, "{count} points, worst {worst}");

    // field_views.msh: every cell's sigma_r and sigma_theta at its nodes.
    let msh = std::fs::read_to_string(dir.join("field_views.msh")).unwrap();
    let mut r_of = std::collections::HashMap::new();
    // The body of a `$Name ... $EndName` section.
    let section = |name: &str| {
        msh.split(&format!("${name}\n"))
            .nth(1)
            .unwrap()
            .split(&format!("$End{name}"))
            .next()
            .unwrap()
    };
    for line in section("Nodes").lines().skip(1) {
        let v: Vec<f64> = line.split_whitespace().map(|x| x.parse().unwrap()).collect();
        r_of.insert(v[0] as usize, v[1]);
    }
    let mut cell_nodes = std::collections::HashMap::new();
    for line in section("Elements").lines().skip(1) {
        let v: Vec<usize> = line.split_whitespace().map(|x| x.parse().unwrap()).collect();
        let tags = v[2];
        cell_nodes.insert(v[0], v[3 + tags..].to_vec());
    }
    let view = |name: &str| -> Vec<(usize, Vec<f64>)> {
        let head = format!("\"{name} theta=0\"");
        let block = msh
            .split(&head)
            .nth(1)
            .unwrap()
            .split("$EndElementNodeData")
            .next()
            .unwrap();
        block
            .lines()
            .skip(7)
            .map(|l| {
                let v: Vec<&str> = l.split_whitespace().collect();
                (
                    v[0].parse().unwrap(),
                    v[2..].iter().map(|x| x.parse().unwrap()).collect(),
                )
            })
            .collect()
    };
    let (mut worst, mut count) = (0.0f64, 0);
    for (which, component) in [(0, "sigma_r"), (1, "sigma_theta")] {
        for (cell, values) in view(component) {
            for (node, v) in cell_nodes[&cell].iter().zip(values) {
                let (sr, sth) = hill(r_of[node]);
                worst = worst.max((v - if which == 0 { sr } else { sth }).abs());
                count += 1;
            }
        }
    }
    println!("field_views.msh: {count} values, worst error {worst:.4}");
    assert!(count > 100 && worst <= 0.03, "{count} values, worst {worst}");
}
