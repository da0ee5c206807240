//! Shared helpers of the joint tests (nonlinear.rs, stability.rs,
//! newton.rs): scenes from geo/, face measures, the joint field along a
//! section, and the Winkler reference of the rigid-block uplift.
#![allow(dead_code)]

use axijoint_mesh::Mesh;
use axijoint_solver::elements::edge_load;
use axijoint_solver::iteration::JointField;
use axijoint_solver::scene::{Load, Scene};
use axijoint_solver::solution::Displacements;
use std::f64::consts::PI;
use std::path::PathBuf;

/// Path of a file in the workspace's `geo/` folder.
pub fn geo(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../geo")
        .join(name)
}

/// A scene file of `geo/`.
pub fn scene(name: &str) -> Scene {
    Scene::from_path(geo(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The resultant load of a scene (the block scenes have exactly one).
pub fn resultant(scene: &mut Scene) -> &mut axijoint_solver::scene::ResultantLoad {
    match &mut scene.loads[0] {
        Load::Resultant(l) => l,
        other => panic!("expected a resultant load, got {other:?}"),
    }
}

/// Block radius a of a block scene.
pub fn radius(scene: &Scene) -> f64 {
    scene.mesh.parameters["a"]
}

/// Nodal weights `w_i = c_m Integral(N_i t(r) r ds)` over a physical curve:
/// the consistent load of the traction `t` (axial component for
/// `component = 1`, circumferential for 2) in harmonic `m`.
pub fn face_weights(mesh: &Mesh, curve: &str, m: u32, component: usize, t: &dyn Fn(f64) -> f64) -> Vec<f64> {
    let mut w = vec![0.0; mesh.nodes.len()];
    let mut fe = [0.0; 9];
    let edges = &mesh
        .curve(curve)
        .unwrap_or_else(|| panic!("no curve {curve}"))
        .edges;
    for e in edges {
        let coords: Vec<[f64; 2]> = e.nodes.iter().map(|&n| mesh.nodes[n]).collect();
        edge_load(
            e.kind,
            &coords,
            m,
            &|r, _| {
                let mut v = [0.0; 3];
                v[component] = t(r);
                v
            },
            &mut fe,
        );
        for (i, &n) in e.nodes.iter().enumerate() {
            w[n] += fe[3 * i + component];
        }
    }
    w
}

/// Mean twist of a face: `Integral(u_theta r dA) / Integral(r^2 dA)` (the
/// rotation work-conjugate to a torque), from harmonic 0.
pub fn mean_twist(mesh: &Mesh, curve: &str, u: &Displacements) -> f64 {
    let w = face_weights(mesh, curve, 0, 2, &|r| r);
    let polar: f64 = w.iter().zip(&mesh.nodes).map(|(wi, p)| wi * p[0]).sum();
    let h0 = &u.harmonics[0].symmetric;
    w.iter()
        .enumerate()
        .map(|(n, wi)| wi * h0[3 * n + 2])
        .sum::<f64>()
        / polar
}

/// Mean tilt of a face about the y axis: `Integral(u_z x dA) / Integral(x^2 dA)`
/// (the rotation work-conjugate to a moment My; positive when the face
/// rises at theta = 0), from the symmetric family of harmonic 1.
pub fn mean_tilt(mesh: &Mesh, curve: &str, u: &Displacements) -> f64 {
    let w = face_weights(mesh, curve, 1, 1, &|r| r);
    let inertia: f64 = w.iter().zip(&mesh.nodes).map(|(wi, p)| wi * p[0]).sum();
    let h1 = &u.harmonics[1].symmetric;
    w.iter()
        .enumerate()
        .map(|(n, wi)| wi * h1[3 * n + 1])
        .sum::<f64>()
        / inertia
}

/// The points of section `s` as `(r, index into the field)`, sorted by r.
pub fn section_points(field: &JointField, s: usize) -> Vec<(f64, usize)> {
    let n_p = field.points.len();
    let mut pts: Vec<(f64, usize)> = (0..n_p).map(|p| (field.points[p].point.r, s * n_p + p)).collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    pts
}

/// Where `f` changes sign along sorted `(r, f)` samples (first crossing from
/// `f <= 0` to `f > 0`), linearly interpolated.
pub fn crossing(samples: &[(f64, f64)]) -> Option<f64> {
    samples
        .windows(2)
        .find(|w| w[0].1 <= 0.0 && w[1].1 > 0.0)
        .map(|w| {
            let ((r0, f0), (r1, f1)) = (w[0], w[1]);
            r0 + (r1 - r0) * (-f0) / (f1 - f0)
        })
}

/// Composite Simpson rule of `f` on [a, b] with `n` (even) intervals.
pub fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let mut s = f(a) + f(b);
    for i in 1..n {
        s += f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

/// Rigid disc of radius `a` on a tensionless Winkler foundation of modulus
/// `k`, load `P` at eccentricity `e` along +x: the pressure
/// `p = k max(0, w0 + t x)` with `Integral(p dA) = P`, `Integral(p x dA) = P e`.
/// Returns `(w0, t, x0)`: settlement of the centre, tilt, and the contact
/// boundary `x0 = -w0 / t` (contact for x > x0).
///
/// With the contact `x > x0`, `p = k t (x - x0)`; the eccentricity
/// `e(x0) = Integral((x - x0) x dA) / Integral((x - x0) dA)` over the
/// segment depends on x0 alone and grows from a/4 (x0 = -a, full contact) to
/// a: bisection on x0, then `t = P / (k Integral((x - x0) dA))`. The segment
/// integrals are over x with the chord `2 sqrt(a^2 - x^2)`, substituted
/// `x = a sin(phi)` (smooth) and integrated by Simpson's rule.
pub fn winkler_uplift(a: f64, k: f64, p: f64, e: f64) -> (f64, f64, f64) {
    assert!(e > a / 4.0 && e < a, "partial uplift needs a/4 < e < a");
    let moments = |x0: f64| {
        let lo = (x0 / a).asin();
        let chord = |phi: f64| {
            let (x, c) = (a * phi.sin(), a * phi.cos());
            (x, 2.0 * c * c) // chord * dx/dphi
        };
        let f0 = simpson(
            |phi| {
                let (x, w) = chord(phi);
                (x - x0) * w
            },
            lo,
            PI / 2.0,
            20_000,
        );
        let f1 = simpson(
            |phi| {
                let (x, w) = chord(phi);
                (x - x0) * x * w
            },
            lo,
            PI / 2.0,
            20_000,
        );
        (f0, f1)
    };
    let ecc = |x0: f64| {
        let (f0, f1) = moments(x0);
        f1 / f0
    };
    let (mut lo, mut hi) = (-a, a * (1.0 - 1e-12));
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if ecc(mid) < e {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let x0 = 0.5 * (lo + hi);
    let t = p / (k * moments(x0).0);
    (-t * x0, t, x0)
}

/// `max |a - b| / max |b|` over two amplitude sets of the same shape.
pub fn relative_difference(a: &Displacements, b: &Displacements) -> f64 {
    let (mut diff, mut scale) = (0.0f64, 0.0f64);
    for (ha, hb) in a.harmonics.iter().zip(&b.harmonics) {
        assert_eq!(ha.m, hb.m);
        for (x, y) in ha
            .symmetric
            .iter()
            .chain(&ha.antisymmetric)
            .zip(hb.symmetric.iter().chain(&hb.antisymmetric))
        {
            diff = diff.max((x - y).abs());
            scale = scale.max(y.abs());
        }
    }
    diff / scale
}
