//! The error estimate against closed forms (docs/accuracy.md): the
//! plane-strain Lame tube with a small bore (r in [0.1, 1], stresses
//! `~ 1/r^2`, steep at the bore) under internal pressure, every element
//! family, structured and unstructured meshes of `geo/thick_cylinder.geo`.
//!
//! - effectivity (estimated / true error in the energy norm of the 3D
//!   field) within [0.5, 2] on every mesh;
//! - the estimated error of a cut's profile (`sigma_theta` along r) within
//!   a factor 2 of its true error, both relative to the profile's max.
//!
//! Measured (printed with `--nocapture`): effectivity 0.86 to 1.10, the
//! cut's estimate 1.04 to 1.75 times its true error.

use axijoint_mesh::geometry::{interpolate, jacobian};
use axijoint_mesh::shapes::MAX_CELL_NODES;
use axijoint_report::estimate::{cut_error, Estimate};
use axijoint_report::field::{Field, Locator};
use axijoint_solver::material::Elastic;
use axijoint_solver::run::solve_linear;
use axijoint_solver::scene::Scene;
use std::f64::consts::PI;
use std::path::Path;

const RI: f64 = 0.1;
const RO: f64 = 1.0;
const P: f64 = 1.0;
const E: f64 = 1000.0;
const NU: f64 = 0.3;

/// The plane-strain Lame stresses `(sigma_r, sigma_z, sigma_theta, 0, 0, 0)`.
fn lame(r: f64) -> [f64; 6] {
    let a = P * RI * RI / (RO * RO - RI * RI);
    let b = a * RO * RO;
    [a - b / (r * r), 2.0 * NU * a, a + b / (r * r), 0.0, 0.0, 0.0]
}

/// `s^T D^-1 s`.
fn energy(mat: &Elastic, s: &[f64; 6]) -> f64 {
    let n = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) / mat.e
        - 2.0 * mat.nu / mat.e * (s[0] * s[1] + s[1] * s[2] + s[2] * s[0]);
    n + (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]) / mat.shear_modulus()
}

/// One measurement: `(label, DOF, true relative energy error, effectivity,
/// true cut error, estimated cut error)`.
type Row = (String, usize, f64, f64, f64, f64);

fn measure(order: u32, quads: u32, size: f64, transfinite: u32) -> Row {
    let text = format!(
        r#"{{
      "mesh": {{"file": "thick_cylinder.geo", "parameters": {{"a": {RO}, "hole": {RI}, "L": 0.2, "size": {size},
               "order": {order}, "quads": {quads}, "transfinite": {transfinite}}}}},
      "materials": {{"body": {{"E": {E}, "nu": {NU}}}}},
      "supports": [{{"on": "bottom", "fix": ["z", "theta"]}}, {{"on": "top", "fix": ["z"]}}],
      "loads": [{{"type": "traction", "on": "inner", "harmonic": 0, "t_r": {P}}}],
      "harmonics": 0
    }}"#
    );
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../geo");
    let scene = Scene::from_str(&text, dir.join("estimate_lame.json")).expect("scene");
    let run = solve_linear(&scene, None, false).expect("Lame tube");
    let mesh = &run.problem.model.mesh;
    let mats = vec![Elastic::new(E, NU).unwrap()];
    let field = Field {
        mesh,
        materials: &mats,
        u: &run.displacements,
        initial: None,
    };
    let est = Estimate::new(&field);
    // True error and norm, on a finer rule than the element's.
    let (mut err2, mut norm2) = (0.0, 0.0);
    for (c, cell) in mesh.cells.iter().enumerate() {
        let coords = mesh.cell_coords(cell);
        let nn = cell.kind.n_nodes();
        let rule = if cell.kind.is_triangle() {
            axijoint_mesh::quadrature::triangle(6).unwrap()
        } else {
            axijoint_mesh::quadrature::quad_gauss(5).unwrap()
        };
        let (mut n, mut dn) = ([0.0; MAX_CELL_NODES], [[0.0; 2]; MAX_CELL_NODES]);
        for (xi, w) in rule.iter() {
            cell.kind.eval_n(xi, &mut n[..nn]);
            cell.kind.eval_dn(xi, &mut dn[..nn]);
            let (_, det) = jacobian(cell.kind, &coords, &dn[..nn]);
            let x = interpolate(&coords, &n[..nn]);
            let exact = lame(x[0]);
            let h = field.stress(c, xi, 0.0);
            let d: Vec<f64> = exact.iter().zip(&h).map(|(a, b)| a - b).collect();
            let d: [f64; 6] = d.try_into().unwrap();
            let wq = 2.0 * PI * w * det.abs() * x[0];
            err2 += wq * energy(&mats[0], &d);
            norm2 += wq * energy(&mats[0], &exact);
        }
    }
    let effectivity = est.error() / err2.sqrt();
    // The cut: sigma_theta along r at mid-height.
    let loc = Locator::new(mesh);
    let (from, to) = ([RI, 0.1], [RO, 0.1]);
    let est_cut = cut_error(&field, &est, &loc, &[from, to], 0.01, 0.0, 2);
    let (mut e, mut m) = (0.0f64, 0.0f64);
    for (_, p) in axijoint_report::cuts::sample_positions(mesh, &[from, to], 0.01) {
        for l in loc.locate_all(mesh, p) {
            let h = field.stress(l.cell, l.xi, 0.0)[2];
            e = e.max((lame(p[0])[2] - h).abs());
            m = m.max(h.abs());
        }
    }
    let label = format!(
        "{}{} size {size}{}",
        if quads == 1 { "Q" } else { "T" },
        if quads == 1 {
            [4, 9][order as usize - 1]
        } else {
            [3, 6][order as usize - 1]
        },
        if transfinite == 1 {
            " structured"
        } else {
            " unstructured"
        }
    );
    (
        label,
        3 * mesh.nodes.len(),
        (err2 / norm2).sqrt(),
        effectivity,
        e / m,
        est_cut,
    )
}

#[test]
fn effectivity_on_the_lame_tube_with_a_small_bore() {
    let mut rows = Vec::new();
    for (order, quads) in [(1, 0), (1, 1), (2, 0), (2, 1)] {
        for transfinite in [1, 0] {
            let sizes: &[f64] = if order == 1 {
                &[0.05, 0.025]
            } else {
                &[0.1, 0.05, 0.025]
            };
            for &size in sizes {
                rows.push(measure(order, quads, size, transfinite));
            }
        }
    }
    println!("| mesh | DOF | true error | effectivity | cut: true | cut: estimated | ratio |");
    for (label, dof, err, eff, cut_true, cut_est) in &rows {
        println!(
            "| {label} | {dof} | {err:.2e} | {eff:.3} | {cut_true:.2e} | {cut_est:.2e} | {:.2} |",
            cut_est / cut_true
        );
    }
    for (label, _, _, eff, cut_true, cut_est) in &rows {
        assert!((0.5..=2.0).contains(eff), "{label}: effectivity {eff}");
        let ratio = cut_est / cut_true;
        assert!(
            (0.5..=2.0).contains(&ratio),
            "{label}: cut estimate / true = {ratio}"
        );
    }
}
