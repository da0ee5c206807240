//! Scene loads -> nodal forces per harmonic, against closed forms.
//!
//! Mesh: Scene P (`geo/pile_footing.geo`, size 0.25) meshed by gmsh in
//! several element families; the loaded faces are the pile end (a disc
//! r = 0 .. 0.5 at z = -1.5), the footing bottom (an annulus r = 0.5 .. 3
//! at z = 0) and the pile side (r = 0.5, z = 0 .. 1).
//!
//! ```text
//!   z = 1.0  +-----+------------+ r = 3.0
//!            |pile | footing    |
//!   z = 0.0  |     +------------+  footing_bottom (annulus)
//!            |     |
//!   z =-1.5  +-----+  pile_end (disc), H = 0.5 in +x acting at z0 = -3.0
//! ```
//!
//! Resultants of nodal amplitudes (node at (r, z), `d = z - z_ref`; derived
//! in `loads.rs`: the physical force per radian of node i is `f_i / c_m`
//! times the family's cos/sin, integrated over one turn):
//!
//! ```text
//! m = 0:            Fz = sum f_z                  Mz = sum r f_th
//! m = 1 symmetric:  Fx = sum (f_r - f_th)         My = sum d (f_r - f_th) - r f_z
//! m = 1 antisym.:   Fy = sum (f_r - f_th)         Mx = sum -d (f_r - f_th) + r f_z
//! ```
//!
//! Tolerances: 1e-12 relative for resultants (the face's A and J are
//! integrated with the loads' own quadrature, so only round-off remains).

use axijoint_mesh::{prepare, JointSpec, Mesh, PointSet};
use axijoint_solver::loads::{assemble_loads, load_resultants, HarmonicLoads};
use axijoint_solver::scene::{Scene, SceneError};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

const TOL: f64 = 1e-12;

fn scene_p_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../geo/pile_footing.json")
}

fn scene_p() -> Scene {
    Scene::from_path(scene_p_path()).expect("Scene P parses")
}

/// Scene P meshed with `quads`, `order`, `serendipity`; optional joints.
fn mesh_with(quads: f64, order: f64, serendipity: f64, joints: &[JointSpec]) -> Mesh {
    let scene = scene_p();
    let mut params = scene.gmsh_parameters();
    for (name, value) in &mut params {
        match name.as_str() {
            "quads" => *value = quads,
            "order" => *value = order,
            "serendipity" => *value = serendipity,
            _ => {}
        }
    }
    prepare(&scene.mesh_path(), &params, joints, None)
        .expect("gmsh meshes Scene P")
        .0
}

/// The meshes of the tests: Q9, T6, Q8 and T3, named.
fn meshes() -> &'static [(&'static str, Mesh)] {
    static MESHES: OnceLock<Vec<(&'static str, Mesh)>> = OnceLock::new();
    MESHES.get_or_init(|| {
        vec![
            ("Q9", mesh_with(1.0, 2.0, 0.0, &[])),
            ("T6", mesh_with(0.0, 2.0, 0.0, &[])),
            ("Q8", mesh_with(1.0, 2.0, 1.0, &[])),
            ("T3", mesh_with(0.0, 1.0, 0.0, &[])),
        ]
    })
}

/// Scene P with its loads replaced by `loads` (a JSON array body) and `harmonics`.
fn scene_with_loads(loads: &str, harmonics: u32) -> Scene {
    let mut text = std::fs::read_to_string(scene_p_path()).unwrap();
    let start = text.find("\"loads\": [").unwrap();
    let end = start + text[start..].find("\n  ],").unwrap() + 5;
    text.replace_range(start..end, &format!("\"loads\": [{loads}],"));
    let text = text.replace("\"harmonics\": 4", &format!("\"harmonics\": {harmonics}"));
    Scene::from_str(&text, scene_p_path()).unwrap_or_else(|e| panic!("{e}"))
}

fn close(actual: f64, expected: f64, scale: f64, what: &str) {
    assert!(
        (actual - expected).abs() <= TOL * scale,
        "{what}: {actual} vs {expected} (difference {:e})",
        actual - expected
    );
}

/// `sum_i g(i, r_i, z_i, f_i)` over the nodes for one family vector.
fn node_sum(mesh: &Mesh, f: &[f64], g: impl Fn(f64, f64, [f64; 3]) -> f64) -> f64 {
    mesh.nodes
        .iter()
        .enumerate()
        .map(|(i, &[r, z])| g(r, z, [f[3 * i], f[3 * i + 1], f[3 * i + 2]]))
        .sum()
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |a, b| a.max(b.abs()))
}

#[test]
fn scene_p_load_reproduces_h_and_its_moment() {
    // H = 0.5 in +x at z0 = -3.0 on the face z_f = -1.5:
    // Fx = 0.5, M about the face centre = (0, 0, -1.5) x (0.5, 0, 0) = (0, -0.75, 0).
    let scene = scene_p();
    scene.check(&meshes()[0].1).unwrap();
    for (name, mesh) in meshes() {
        let loads = assemble_loads(&scene, mesh, scene.harmonics()).unwrap();
        assert_eq!(loads.len(), 5);
        let h1 = &loads[1];
        assert_eq!(h1.m, 1);
        let fx = node_sum(mesh, &h1.symmetric, |_, _, f| f[0] - f[2]);
        close(fx, 0.5, 0.5, &format!("{name}: Fx"));
        // My about z_f = -1.5: every loaded node has d = 0, so My = -sum r f_z.
        let my = node_sum(mesh, &h1.symmetric, |r, z, f| {
            (z + 1.5) * (f[0] - f[2]) - r * f[1]
        });
        close(my, -0.75, 0.75, &format!("{name}: My"));
        // Uniform shear: T_r = -T_theta, so f_r = -f_theta at every node.
        for i in 0..mesh.nodes.len() {
            assert_eq!(h1.symmetric[3 * i], -h1.symmetric[3 * i + 2], "{name}: node {i}");
        }
        // Nothing else: no antisymmetric part, no harmonic 0 or >= 2.
        assert_eq!(max_abs(&h1.antisymmetric), 0.0, "{name}");
        for h in loads.iter().filter(|h| h.m != 1) {
            assert_eq!(
                max_abs(&h.symmetric) + max_abs(&h.antisymmetric),
                0.0,
                "{name} m = {}",
                h.m
            );
        }
        // Same through load_resultants; about the point of application M = 0.
        let at_face = load_resultants(&loads, mesh, -1.5);
        let at_point = load_resultants(&loads, mesh, -3.0);
        for (a, e) in at_face.force.iter().zip([0.5, 0.0, 0.0]) {
            close(*a, e, 0.5, &format!("{name}: force"));
        }
        for (a, e) in at_face.moment.iter().zip([0.0, -0.75, 0.0]) {
            close(*a, e, 0.75, &format!("{name}: moment at face"));
        }
        for a in at_point.moment {
            close(
                a,
                0.0,
                0.75,
                &format!("{name}: moment at the point of application"),
            );
        }
        // Sign: the bending traction pushes into the pile (+z; the face's
        // outward normal is -z) at theta = 0: sum r f_z = +0.75.
        close(
            node_sum(mesh, &h1.symmetric, |r, _, f| r * f[1]),
            0.75,
            0.75,
            name,
        );
    }
}

#[test]
fn general_resultant_on_a_disc_and_an_annulus() {
    // F = (0.3, -0.2, 0.7) at z0 = z_f + dz, extra moment (0.1, 0.05), torque 0.4:
    // about the face centre M = (-dz Fy + 0.1, dz Fx + 0.05, 0.4).
    let (f, torque, extra) = ([0.3, -0.2, 0.7], 0.4, [0.1, 0.05]);
    for (curve, z_f) in [("pile_end", -1.5), ("footing_bottom", 0.0)] {
        let dz = -0.7;
        let scene = scene_with_loads(
            &format!(
                r#"{{"type": "resultant", "on": "{curve}", "force": [0.3, -0.2, 0.7], "at_z": {},
                    "torque": 0.4, "moment": [0.1, 0.05]}}"#,
                z_f + dz
            ),
            1,
        );
        let expected_m = [-dz * f[1] + extra[0], dz * f[0] + extra[1], torque];
        for (name, mesh) in meshes() {
            scene.check(mesh).unwrap();
            let loads = assemble_loads(&scene, mesh, 1).unwrap();
            let what = |c: &str| format!("{name} {curve}: {c}");
            // m = 0: Fz = sum f_z, T = sum r f_theta.
            close(
                node_sum(mesh, &loads[0].symmetric, |_, _, f| f[1]),
                f[2],
                1.0,
                &what("Fz"),
            );
            close(
                node_sum(mesh, &loads[0].symmetric, |r, _, f| r * f[2]),
                torque,
                1.0,
                &what("T"),
            );
            // m = 1: Fx, Fy and the bending moments about the face (d = 0 there).
            close(
                node_sum(mesh, &loads[1].symmetric, |_, _, f| f[0] - f[2]),
                f[0],
                1.0,
                &what("Fx"),
            );
            close(
                node_sum(mesh, &loads[1].antisymmetric, |_, _, f| f[0] - f[2]),
                f[1],
                1.0,
                &what("Fy"),
            );
            close(
                node_sum(mesh, &loads[1].symmetric, |r, _, f| -r * f[1]),
                expected_m[1],
                1.0,
                &what("My"),
            );
            close(
                node_sum(mesh, &loads[1].antisymmetric, |r, _, f| r * f[1]),
                expected_m[0],
                1.0,
                &what("Mx"),
            );
            let res = load_resultants(&loads, mesh, z_f);
            for c in 0..3 {
                close(res.force[c], f[c], 1.0, &what("force"));
                close(res.moment[c], expected_m[c], 1.0, &what("moment"));
            }
        }
    }
}

#[test]
fn traction_linear_in_r_and_z_integrates_in_closed_form() {
    // Pile end (disc r = 0 .. a at z = -1.5), t_z = c + k r:
    //   sum f_z = c_m Integral((c + k r) r dr) = c_m (c a^2 / 2 + k a^3 / 3).
    // Pile side (r = a, z = 0 .. 1), t_r = p + q z, t_theta = 2, antisymmetric m = 3:
    //   sum f_r = pi a (p + q / 2),  sum z f_r = pi a (p / 2 + q / 3),  sum f_theta = pi a 2.
    let (a, c, k, p, q): (f64, f64, f64, f64, f64) = (0.5, 2.0, -3.0, 1.5, 4.0);
    let scene = scene_with_loads(
        r#"{"type": "traction", "on": "pile_end", "harmonic": 0, "t_z": {"c": 2.0, "r": -3.0}},
           {"type": "traction", "on": "pile_end", "harmonic": 2, "t_z": {"c": 2.0, "r": -3.0}},
           {"type": "traction", "on": "pile_side", "harmonic": 3, "family": "antisymmetric",
            "t_r": {"c": 1.5, "z": 4.0}, "t_theta": 2}"#,
        4,
    );
    let end = c * a * a / 2.0 + k * a.powi(3) / 3.0;
    for (name, mesh) in meshes() {
        scene.check(mesh).unwrap();
        let loads = assemble_loads(&scene, mesh, 4).unwrap();
        let sum = |h: &HarmonicLoads, anti: bool, g: &dyn Fn(f64, f64, [f64; 3]) -> f64| {
            node_sum(mesh, if anti { &h.antisymmetric } else { &h.symmetric }, g)
        };
        close(
            sum(&loads[0], false, &|_, _, f| f[1]),
            2.0 * PI * end,
            1.0,
            &format!("{name}: m = 0"),
        );
        close(
            sum(&loads[2], false, &|_, _, f| f[1]),
            PI * end,
            1.0,
            &format!("{name}: m = 2"),
        );
        close(
            sum(&loads[3], true, &|_, _, f| f[0]),
            PI * a * (p + q / 2.0),
            1.0,
            &format!("{name}: m = 3 f_r"),
        );
        close(
            sum(&loads[3], true, &|_, z, f| z * f[0]),
            PI * a * (p / 2.0 + q / 3.0),
            1.0,
            &format!("{name}: m = 3 z f_r"),
        );
        close(
            sum(&loads[3], true, &|_, _, f| f[2]),
            PI * a * 2.0,
            1.0,
            &format!("{name}: m = 3 f_theta"),
        );
        assert_eq!(
            max_abs(&loads[3].symmetric) + max_abs(&loads[1].symmetric),
            0.0,
            "{name}"
        );
    }
}

#[test]
fn force_in_y_is_the_antisymmetric_twin_of_force_in_x() {
    // Turning the load by 90 degrees (theta -> theta - pi/2) maps the
    // symmetric amplitudes of a force in +x onto the antisymmetric ones of
    // the same force in +y, moment included.
    let in_x = scene_with_loads(
        r#"{"type": "resultant", "on": "pile_end", "force": [0.5, 0, 0], "at_z": -3.0}"#,
        1,
    );
    let in_y = scene_with_loads(
        r#"{"type": "resultant", "on": "pile_end", "force": [0, 0.5, 0], "at_z": -3.0}"#,
        1,
    );
    for (name, mesh) in meshes() {
        let x = assemble_loads(&in_x, mesh, 1).unwrap();
        let y = assemble_loads(&in_y, mesh, 1).unwrap();
        let scale = max_abs(&x[1].symmetric);
        assert!(scale > 0.0);
        let diff = x[1]
            .symmetric
            .iter()
            .zip(&y[1].antisymmetric)
            .fold(0.0f64, |d, (a, b)| d.max((a - b).abs()));
        assert!(diff <= 1e-15 * scale, "{name}: difference {diff:e}");
        assert_eq!(max_abs(&y[1].symmetric), 0.0, "{name}");
        let res = load_resultants(&y, mesh, -1.5);
        close(res.force[1], 0.5, 0.5, name);
        close(res.moment[0], 0.75, 0.75, name); // (0, 0, -1.5) x (0, 0.5, 0) = (0.75, 0, 0)
    }
}

#[test]
fn loads_after_joint_insertion_are_unchanged() {
    let scene = scene_p();
    let jointed = mesh_with(1.0, 2.0, 0.0, &scene.joint_specs());
    assert_eq!(jointed.joints.len(), 1);
    scene.check(&jointed).unwrap();
    let loads = assemble_loads(&scene, &jointed, 4).unwrap();
    let res = load_resultants(&loads, &jointed, -1.5);
    close(res.force[0], 0.5, 0.5, "Fx");
    close(res.moment[1], -0.75, 0.75, "My");
}

#[test]
fn harmonic_beyond_the_run_is_refused() {
    let scene = scene_p();
    let e = assemble_loads(&scene, &meshes()[0].1, 0).unwrap_err();
    assert_eq!(e.key(), Some("loads[0].force"), "{e}");
    assert!(e.to_string().contains("harmonics 0..=0"), "{e}");
}

/// A mesh of bare nodes with physical points: ring and point loads need no cells.
fn points_mesh() -> Mesh {
    let set = |name: &str, nodes: Vec<usize>| PointSet {
        name: name.into(),
        tag: 1,
        nodes,
    };
    Mesh {
        nodes: vec![[0.0, 1.0], [2.0, 0.5], [2.0, 0.5], [3.0, 0.0]],
        points: vec![
            set("apex", vec![0]),
            set("split", vec![1, 2]),
            set("rim", vec![3]),
        ],
        ..Mesh::default()
    }
}

fn scene_for_points(loads: &str, harmonics: u32) -> Scene {
    let text = format!(
        r#"{{"mesh": {{"file": "points.msh"}}, "materials": {{}}, "loads": [{loads}], "harmonics": {harmonics}}}"#
    );
    Scene::from_str(&text, "points.json").unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn ring_loads_scale_with_the_circumference() {
    // Ring at r = 3, f_z = 1.5 (m = 0): nodal 2 pi r f_z = total axial force.
    // Ring at r = 3, f_r = 0.7 (m = 1 symmetric): nodal pi r f_r = Fx.
    // Ring on a split node (r = 2): the two copies share the load equally.
    let mesh = points_mesh();
    let scene = scene_for_points(
        r#"{"type": "ring", "on": "rim", "harmonic": 0, "f_z": 1.5},
           {"type": "ring", "on": "rim", "harmonic": 1, "f_r": 0.7},
           {"type": "ring", "on": "split", "harmonic": 2, "family": "antisymmetric", "f_theta": 1.0}"#,
        2,
    );
    scene.check(&mesh).unwrap();
    let loads = assemble_loads(&scene, &mesh, 2).unwrap();
    close(
        loads[0].symmetric[3 * 3 + 1],
        2.0 * PI * 3.0 * 1.5,
        1.0,
        "m = 0 ring",
    );
    close(loads[1].symmetric[3 * 3], PI * 3.0 * 0.7, 1.0, "m = 1 ring");
    let res = load_resultants(&loads, &mesh, 0.0);
    close(res.force[2], 2.0 * PI * 3.0 * 1.5, 10.0, "Fz");
    close(res.force[0], PI * 3.0 * 0.7, 10.0, "Fx");
    for copy in [1, 2] {
        close(
            loads[2].antisymmetric[3 * copy + 2],
            0.5 * PI * 2.0,
            1.0,
            "split ring",
        );
    }
}

#[test]
fn point_load_on_the_axis() {
    // (Fx, Fy, Fz) = (1, 2, 3) at (0, 0, 1): resultant force (1, 2, 3) and,
    // about z_ref = 0, moment (0, 0, 1) x F = (-2, 1, 0).
    let mesh = points_mesh();
    let scene = scene_for_points(r#"{"type": "point", "on": "apex", "force": [1, 2, 3]}"#, 1);
    scene.check(&mesh).unwrap();
    let loads = assemble_loads(&scene, &mesh, 1).unwrap();
    let res = load_resultants(&loads, &mesh, 0.0);
    for c in 0..3 {
        close(res.force[c], [1.0, 2.0, 3.0][c], 3.0, "force");
        close(res.moment[c], [-2.0, 1.0, 0.0][c], 3.0, "moment");
    }
}

#[test]
fn ring_on_the_axis_and_point_off_the_axis_are_refused() {
    let mesh = points_mesh();
    let cases = [
        (
            r#"{"type": "ring", "on": "apex", "harmonic": 0, "f_z": 1}"#,
            "point load",
        ),
        (r#"{"type": "point", "on": "rim", "force": [0, 0, 1]}"#, "r = 3"),
    ];
    for (load, word) in cases {
        let scene = scene_for_points(load, 1);
        let errors: [SceneError; 2] = [
            assemble_loads(&scene, &mesh, 1).unwrap_err(),
            scene.check(&mesh).unwrap_err(),
        ];
        for e in errors {
            assert_eq!(e.key(), Some("loads[0].on"), "{e}");
            assert!(e.to_string().contains(word), "{e}");
        }
    }
}
