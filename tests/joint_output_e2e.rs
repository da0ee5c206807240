//! Joint outputs of linear joints (issue 14 item 1): a run whose joints are
//! all linear writes `joints.json`, the joint CSVs, `field_joints.vtu` and the
//! joint areas of `summary.json` like a nonlinear run, with the traction
//! `t0 + k d` (t0: the end of the initial phase, if any) and the state stick.
//!
//! Scene P linear (gmsh, size 0.5): the relative displacement at every joint
//! point and section is recomputed from `displacement.f64` and
//! `mesh_solved.msh` alone (their documented layouts, our own quadratic
//! shape functions and synthesis); the joint output's `d` and `p = k d`
//! match it to 1e-9 relative. Two stacked cylinders on a linear joint under
//! a uniform pressure p: `sigma = -p`, no shear, `d_eta = -p / k_eta`; with
//! an initial stress `sigma_z = -q` that the initial phase relieves, the same
//! (the joint ends the phase at `t0 + k d_0 = 0`).

mod common;

use axijoint_mesh::parse_msh;
use common::*;
use serde_json::{json, Value};
use std::path::Path;

fn read_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

fn run(scene: &Path, out: &Path, extra: &[&str]) {
    let mut args = vec!["run", scene.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"];
    args.extend_from_slice(extra);
    let r = axijoint(&args);
    let (stdout, stderr) = text(&r);
    assert!(r.status.success(), "{stdout}\n{stderr}");
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn vec3(v: &Value) -> [f64; 3] {
    [f(&v[0]), f(&v[1]), f(&v[2])]
}

/// The joint CSV rows as numbers (the state column dropped) and the states.
fn read_joint_csv(path: &Path) -> (Vec<[f64; 12]>, Vec<String>) {
    let mut reader = csv::Reader::from_path(path).unwrap();
    let mut rows = Vec::new();
    let mut states = Vec::new();
    for rec in reader.records() {
        let rec = rec.unwrap();
        let mut row = [0.0; 12];
        for (k, v) in row.iter_mut().enumerate() {
            *v = rec[k].parse().unwrap();
        }
        rows.push(row);
        states.push(rec[12].to_string());
    }
    (rows, states)
}

/// `NumberOfCells` of a `.vtu` and whether it names the array `name`.
fn vtu_cells(path: &Path, name: &str) -> (usize, bool) {
    // The XML part (binary appended data may follow).
    let text = String::from_utf8_lossy(&std::fs::read(path).unwrap()).into_owned();
    let key = "NumberOfCells=\"";
    let at = text.find(key).expect("NumberOfCells") + key.len();
    let cells = text[at..at + text[at..].find('"').unwrap()].parse().unwrap();
    (cells, text.contains(&format!("Name=\"{name}\"")))
}

/// Scene P with a linear joint: every output of the joint, and its `d` and
/// `p` against an independent recomputation.
#[test]
fn linear_joint_outputs_match_the_displacements() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p");
    run(&geo("pile_footing_linear.json"), &out, &["--set", "size=0.5"]);
    for file in [
        "joints.json",
        "joint_pile_side.csv",
        "joint_pile_side_states.svg",
        "field_joints.vtu",
    ] {
        assert!(out.join(file).is_file(), "{file} missing");
    }
    let scene = read_json(&geo("pile_footing_linear.json"));
    let joint = &scene["joints"]["pile_side"];
    let k = [f(&joint["k_xi"]), f(&joint["k_eta"]), f(&joint["k_theta"])];

    // summary.json: the whole pile side (r = a = 0.5, z in [0, 1]) sticks.
    let summary = read_json(&out.join("summary.json"));
    let areas = &summary["joints"]["pile_side"];
    let side = 2.0 * std::f64::consts::PI * 0.5 * 1.0;
    assert!((f(&areas["stick_area"]) - side).abs() < 1e-12 * side, "{areas}");
    assert_eq!(f(&areas["open_area"]), 0.0);
    assert_eq!(f(&areas["slip_area"]), 0.0);
    assert!(summary["files"]
        .as_array()
        .unwrap()
        .contains(&json!("field_joints.vtu")));

    // displacement.f64: [harmonic][family][node][u_r, u_z, u_theta].
    let header = read_json(&out.join("solution.json"));
    let harmonics: Vec<u32> = header["harmonics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m.as_u64().unwrap() as u32)
        .collect();
    let raw = std::fs::read(out.join("displacement.f64")).unwrap();
    let u: Vec<f64> = raw
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect();
    let n = u.len() / (harmonics.len() * 6);
    let amp = |h: usize, family: usize, node: usize, c: usize| u[((2 * h + family) * n + node) * 3 + c];
    // Node `node` (row of displacement.f64) at theta: (u_r, u_z, u_theta).
    let at = |node: usize, theta: f64| {
        let mut v = [0.0; 3];
        for (h, &m) in harmonics.iter().enumerate() {
            if m == 0 {
                for (c, x) in v.iter_mut().enumerate() {
                    *x += amp(h, 0, node, c);
                }
                continue;
            }
            let (s, c) = (f64::from(m) * theta).sin_cos();
            for (i, x) in v.iter_mut().take(2).enumerate() {
                *x += amp(h, 0, node, i) * c + amp(h, 1, node, i) * s;
            }
            v[2] += amp(h, 0, node, 2) * s - amp(h, 1, node, 2) * c;
        }
        v
    };

    // mesh_solved.msh: node tag k + 1 is row k; a 6-node joint element e is
    // the quadrangles 2e [b0, b2, t2, t0] and 2e + 1 [b2, b1, t1, t2].
    let msh_path = out.join("mesh_solved.msh");
    let msh = parse_msh(&std::fs::read(&msh_path).unwrap(), &msh_path).unwrap();
    assert_eq!(msh.nodes.len(), n);
    let xy = |node: usize| {
        let (tag, x) = msh.nodes[node];
        assert_eq!(tag as usize, node + 1);
        [x[0], x[1]]
    };
    let tag = msh
        .physical_names
        .iter()
        .find(|p| p.name == "pile_side" && p.dim == 2)
        .unwrap()
        .tag;
    let quads: Vec<Vec<usize>> = msh
        .elements
        .iter()
        .filter(|e| e.gmsh_type == 3 && e.physical_tags.contains(&tag))
        .map(|e| e.nodes.iter().map(|&t| t as usize - 1).collect())
        .collect();
    assert!(quads.len() >= 4 && quads.len() % 2 == 0, "{}", quads.len());
    // (bottom b0, b1, b2; top t0, t1, t2) of element e.
    let element = |e: usize| {
        let (q, w) = (&quads[2 * e], &quads[2 * e + 1]);
        assert_eq!((w[0], w[3]), (q[1], q[2]));
        ([q[0], w[1], q[1]], [q[3], w[2], q[2]])
    };

    // The pile (bottom) is inside r = a, the footing (top) outside: eta =
    // +r points into the top body, xi = (eta_z, -eta_r) = -z.
    let field = read_json(&out.join("joints.json"));
    let points = field["points"].as_array().unwrap();
    let sections: Vec<f64> = field["sections_deg"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| f(t).to_radians())
        .collect();
    assert_eq!(sections.len(), 5);
    let (mut d_max, mut d_err, mut p_max, mut p_err) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut checked = 0;
    for (s, &theta) in sections.iter().enumerate() {
        for (i, pt) in points.iter().enumerate() {
            let (bottom, top) = element(pt["element"].as_u64().unwrap() as usize);
            let [x0, x1, x2] = bottom.map(xy);
            for a in 0..2 {
                assert!(
                    (x2[a] - 0.5 * (x0[a] + x1[a])).abs() < 1e-12,
                    "mid node off the middle"
                );
                assert_eq!(x0[0], 0.5);
            }
            let (r, z) = (f(&pt["r"]), f(&pt["z"]));
            assert!((r - 0.5).abs() < 1e-12);
            let sp = 2.0 * (z - x0[1]) / (x1[1] - x0[1]) - 1.0;
            assert!(sp.abs() < 1.0);
            let shape = [0.5 * sp * (sp - 1.0), 0.5 * sp * (sp + 1.0), 1.0 - sp * sp];
            let mut jump = [0.0; 3];
            for a in 0..3 {
                let (ub, ut) = (at(bottom[a], theta), at(top[a], theta));
                for c in 0..3 {
                    jump[c] += shape[a] * (ut[c] - ub[c]);
                }
            }
            let d = [-jump[1], jump[0], jump[2]];
            let v = &field["values"][s][i];
            assert_eq!(v["state"], "stick");
            let (dj, pj) = (vec3(&v["d"]), vec3(&v["p"]));
            for c in 0..3 {
                d_max = d_max.max(d[c].abs());
                d_err = d_err.max((dj[c] - d[c]).abs());
                p_max = p_max.max((k[c] * d[c]).abs());
                p_err = p_err.max((pj[c] - k[c] * d[c]).abs());
            }
            checked += 1;
        }
    }
    eprintln!(
        "{checked} point-sections: |d| max {d_max:.6e}, error {:.3e}; |p| max {p_max:.6e}, error {:.3e} (relative)",
        d_err / d_max,
        p_err / p_max
    );
    assert!(checked >= 5 * 12, "{checked}");
    assert!(d_max > 1e-5 && p_max > 0.1, "{d_max} {p_max}");
    assert!(d_err <= 1e-9 * d_max, "d: {d_err:e} of {d_max:e}");
    assert!(p_err <= 1e-9 * p_max, "p: {p_err:e} of {p_max:e}");

    // The CSV: one row per point and section, the values of joints.json
    // (written to 10 digits).
    let (rows, states) = read_joint_csv(&out.join("joint_pile_side.csv"));
    assert_eq!(rows.len(), checked);
    assert!(states.iter().all(|s| s == "stick"));
    let mut csv_err = 0.0f64;
    for row in &rows {
        let s = sections
            .iter()
            .position(|t| (t.to_degrees() - row[3]).abs() < 1e-9)
            .unwrap();
        let i = points
            .iter()
            .position(|p| (f(&p["z"]) - row[2]).abs() < 1e-9 * (1.0 + row[2].abs()))
            .unwrap();
        let v = &field["values"][s][i];
        let (p, d) = (vec3(&v["p"]), vec3(&v["d"]));
        for (ours, theirs, scale) in [
            (row[4], p[1], p_max),
            (row[5], p[0], p_max),
            (row[6], p[2], p_max),
            (row[7], d[0], d_max),
            (row[8], d[1], d_max),
            (row[9], d[2], d_max),
        ] {
            csv_err = csv_err.max((ours - theirs).abs() / scale);
        }
    }
    assert!(csv_err < 1e-9, "CSV against joints.json: {csv_err:e}");

    // field_joints.vtu: the joint's elements revolved, with their tractions.
    let (cells, named) = vtu_cells(&out.join("field_joints.vtu"), "sigma_n");
    assert!(named && cells >= quads.len() / 2, "{cells} cells");
}

/// Two stacked cylinders (radius 0.5, lower z in [0, 1], upper [1, 2]) on
/// a linear joint at z = 1, roller at the bottom, pressure p on the top:
/// uniaxial compression, so `sigma = -p`, `tau = 0`, `d_eta = -p / k_eta` at
/// every joint point. With `initial_stress` `sigma_z = -q` in both bodies
/// the initial phase relieves it (the top is free) and the joint ends the
/// phase at `-q + k_eta q / k_eta = 0`: the same values.
#[test]
fn pressure_on_a_linear_joint_is_exact() {
    let (p, q, k_eta): (f64, f64, f64) = (2.0, 3.0, 500.0);
    for initial in [false, true] {
        let dir = tempfile::tempdir().unwrap();
        let material = if initial {
            json!({"E": 1000.0, "nu": 0.25,
                   "initial_stress": {"type": "constant", "sigma_r": 0.0, "sigma_z": -q, "sigma_theta": 0.0}})
        } else {
            json!({"E": 1000.0, "nu": 0.25})
        };
        let scene = json!({
            "title": "stacked cylinders on a linear joint under a uniform pressure",
            "units": {"length": "m", "force": "MN", "stress": "MPa"},
            "mesh": {"file": geo("stacked_cylinders.geo").to_str().unwrap(),
                     "parameters": {"a": 0.5, "L1": 1.0, "L2": 1.0, "size": 0.25, "order": 2, "quads": 1}},
            "materials": {"lower": material, "upper": material},
            "joints": {"interface": {"bottom": "lower", "top": "upper",
                       "k_xi": 300.0, "k_eta": k_eta, "k_theta": 200.0, "law": {"type": "linear"}}},
            "supports": [{"on": "bottom", "fix": ["z", "theta"]}],
            "loads": [{"type": "traction", "on": "top", "harmonic": 0, "t_z": -p}],
            "harmonics": 0,
            "outputs": {"csv": true, "plots": false, "vtu": true, "gmsh_views": false}
        });
        let path = dir.path().join("stack.json");
        std::fs::write(&path, scene.to_string()).unwrap();
        let out = dir.path().join("out");
        run(&path, &out, &[]);
        assert_eq!(out.join("initial_displacement.f64").is_file(), initial);
        if initial {
            // The relief: the top edge moves q (L1 + L2) / E + q / k_eta up
            // and nu q a / E out.
            let header = read_json(&out.join("solution.json"));
            let moved = f(&header["initial"]["max_displacement"]);
            assert!(
                (moved - (q * 2.0 / 1000.0 + q / k_eta).hypot(0.25 * q * 0.5 / 1000.0)).abs() < 1e-9,
                "{moved}"
            );
        }
        let (cells, named) = vtu_cells(&out.join("field_joints.vtu"), "sigma_n");
        assert!(named && cells > 0);
        let (rows, states) = read_joint_csv(&out.join("joint_interface.csv"));
        assert!(rows.len() >= 4, "{}", rows.len());
        assert!(states.iter().all(|s| s == "stick"));
        let field = read_json(&out.join("joints.json"));
        let (mut sigma_err, mut tau_max, mut d_err) = (0.0f64, 0.0f64, 0.0f64);
        for values in field["values"].as_array().unwrap() {
            for v in values.as_array().unwrap() {
                let (pj, dj) = (vec3(&v["p"]), vec3(&v["d"]));
                sigma_err = sigma_err.max((pj[1] + p).abs());
                tau_max = tau_max.max(pj[0].abs()).max(pj[2].abs());
                d_err = d_err.max((dj[1] + p / k_eta).abs());
            }
        }
        eprintln!(
            "initial phase {initial}: |sigma + p| {sigma_err:.3e}, |tau| {tau_max:.3e}, |d_eta + p/k_eta| {d_err:.3e}"
        );
        assert!(sigma_err < 1e-9 * p, "{sigma_err:e}");
        assert!(tau_max < 1e-9 * p, "{tau_max:e}");
        assert!(d_err < 1e-9 * p / k_eta, "{d_err:e}");
        // The CSV to its 10 digits.
        for row in &rows {
            assert!((row[4] + p).abs() < 1e-8 * p, "{row:?}");
        }
    }
}
