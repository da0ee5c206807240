//! Uplift capacity of a circular anchor plate (issue 12, item 4) against
//! the friction cylinder method.
//!
//! | test | claim | tolerance |
//! |---|---|---|
//! | friction cylinder | with the joints' normal stress held at rest, the limit load is `Q_u` below | 3 % |
//! | elastic normal stress | with `k_eta = E / h` the limit load is `W` plus the joints' strength at their own normal stresses; it is below `Q_u`, the top of the cylinder having opened | 1 % |
//! | pulled at an angle, rigid | a mechanism at the capacity is the limit, not a step: limit bracketed, the last step's displacement rate within 10x the first's | 1 % |
//!
//! `geo/anchor_plate.geo` at its defaults: a steel plate of radius b = 0.5,
//! top at depth H = 2, thickness t = 0.1, in a soil cylinder R = 6, depth 6
//! (outer side and bottom fixed), quadratic elements of 0.25 along the
//! joints. The plug of soil above the plate is a body of its own; the
//! vertical joints `cylinder` (plug / soil) and `plate_edge` (plate / soil)
//! run from the surface to the plate's bottom, H' = H + t, Mohr-Coulomb
//! (C, phi, no tension); `plate_bottom` (soil / plate) is Mohr-Coulomb
//! with C = 0 and no tension, so it opens on uplift. Soil, plug and plate
//! are geostatic with K0 and the soil's unit weight gamma (the plate counts
//! as soil in the weight); the joints start from those stresses. An upward
//! resultant F on the plate's top face is raised to the limit.
//!
//! Closed form: the friction cylinder method (a vertical slip surface
//! through the plate edge: the weight of the soil above the plate plus the
//! shear strength along the surface, here with the at-rest normal stress
//! `K0 gamma z` and cohesion C), e.g. B. M. Das, "Earth Anchors",
//! Elsevier, 1990, chapter 2 (horizontal plate anchors):
//!
//! ```text
//! Q_u = W + 2 pi b (C H' + K0 gamma tan(phi) H'^2 / 2),   W = gamma pi b^2 (H + t)
//! ```
//!
//! The soil is elastic and only the joints yield, so this mechanism is the
//! one the model contains: the comparison checks that the solver finds its
//! capacity, not that the mechanism is right for real soil.
//!
//! The closed form keeps the normal stress on the slip surface at rest. In
//! the model it is `sigma_0 + k_eta d_eta` and changes with the elastic
//! motion: the soil outside, dragged up, moves away from the axis near the
//! surface and the top 0.5 m of the cylinder opens (its shear strength
//! lost where `sigma_0` is small), while deeper the plug, compressed
//! between the plate and the shear on its side, expands (Poisson) and the
//! normal stress grows. With `k_eta = E / h` the first wins: -2.1 % at
//! h = 0.25 (measured; before issue 29, when an opened pair lost its
//! cohesion: -4.5 % at h = 0.25, -6.8 % at h = 0.125 and 0.0625, -14 % with
//! nu = 0, -0.3 % with nu = 0.45). The first test therefore gives the vertical
//! joints a normal spring 1000 times softer than `E / h` (the shear springs
//! stay at `E / h`), which holds the normal stress at rest as the closed
//! form assumes: -0.3 % at h = 0.25 and 0.125, `Q_u` inside the bracket
//! `[factor, failed_at]` of the limit load factor (docs/loading.md).

use axijoint_solver::joint_law::JointState;
use axijoint_solver::run::{solve_scene, Run};
use axijoint_solver::scene::Scene;
use std::f64::consts::PI;
use std::path::PathBuf;

const B: f64 = 0.5;
const H: f64 = 2.0;
const T: f64 = 0.1;
const SIZE: f64 = 0.25;
const E_SOIL: f64 = 50.0;
const NU: f64 = 0.3;
const GAMMA: f64 = 0.018;
const K0: f64 = 0.5;
const C: f64 = 0.01;
const PHI: f64 = 30.0;
/// Upward force on the plate (MN).
const F: f64 = 0.2;

fn geo(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../geo")
        .join(name)
}

/// The anchor with the vertical joints' normal spring `k_eta`; every other
/// spring is `E / h`.
fn anchor(k_eta: f64) -> Run {
    anchor_with(Some(k_eta), [0.0, 0.0, F], 0)
}

/// The anchor with the vertical joints' normal spring `k_eta` (`None`:
/// every joint rigid, no stiffness given), the resultant `force` on the
/// plate's top and harmonics 0..=`m`.
fn anchor_with(k_eta: Option<f64>, force: [f64; 3], m: u32) -> Run {
    let [fx, fy, fz] = force;
    let k = E_SOIL / SIZE;
    let initial = format!(
        r#""unit_weight": {GAMMA}, "initial_stress": {{"type": "geostatic", "surface_z": 0, "K0": {K0}}}"#
    );
    let joint = |bottom: &str, top: &str, c: f64, k_eta: Option<f64>| {
        let springs = match k_eta {
            Some(k_eta) => format!(r#""k_xi": {k}, "k_eta": {k_eta}, "k_theta": {k},"#),
            None => String::new(),
        };
        format!(
            r#"{{"bottom": "{bottom}", "top": "{top}", {springs}
          "law": {{"type": "mohr_coulomb", "cohesion": {c}, "friction_deg": {PHI}, "tensile_strength": 0}}}}"#
        )
    };
    let text = format!(
        r#"{{
      "mesh": {{"file": "anchor_plate.geo", "parameters": {{"b": {B}, "H": {H}, "t": {T}, "size": {SIZE}}}}},
      "materials": {{
        "soil": {{"E": {E_SOIL}, "nu": {NU}, {initial}}},
        "plug": {{"E": {E_SOIL}, "nu": {NU}, {initial}}},
        "plate": {{"E": 2.1e5, "nu": 0.3, {initial}}}
      }},
      "joints": {{
        "cylinder": {},
        "plate_edge": {},
        "plate_bottom": {}
      }},
      "supports": [{{"on": "soil_outer", "fix": "all"}}, {{"on": "soil_bottom", "fix": "all"}}],
      "loads": [{{"type": "resultant", "on": "plate_top", "force": [{fx}, {fy}, {fz}]}}],
      "harmonics": {m}
    }}"#,
        joint("plug", "soil", C, k_eta),
        joint("plate", "soil", C, k_eta),
        joint("soil", "plate", 0.0, k_eta.map(|_| k)),
    );
    let scene = Scene::from_str(&text, geo("anchor.json")).unwrap_or_else(|e| panic!("{e}"));
    solve_scene(&scene, None, |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

/// `(W, Q_u)` of the friction cylinder method.
fn friction_cylinder() -> (f64, f64) {
    let h = H + T;
    let w = GAMMA * PI * B * B * h;
    (
        w,
        w + 2.0 * PI * B * (C * h + K0 * GAMMA * PHI.to_radians().tan() * h * h / 2.0),
    )
}

/// The limit load (force) of a run, checked to be a limit and to have
/// opened the whole plate bottom.
fn limit_load(run: &Run) -> f64 {
    let init = run.initial.as_ref().expect("an initial phase");
    assert!(init.balance.relative < 1e-10, "{:?}", init.balance);
    let path = run.load_path.as_ref().expect("a stepped run");
    let limit = path.limit.as_ref().expect("a limit load");
    assert!(limit.beyond_capacity, "{}", limit.reason);
    let last = path.steps.last().expect("a converged step");
    let bottom = last
        .observed
        .joints
        .iter()
        .find(|j| j.joint == "plate_bottom")
        .expect("plate_bottom");
    assert!((bottom.open / (PI * B * B) - 1.0).abs() < 1e-9, "{bottom:?}");
    let (_, q_u) = friction_cylinder();
    println!(
        "limit factor {:.5} (failed at {:.5}), {} steps, uplift {:.3e} m: {:.5} MN, Q_u {q_u:.5} MN ({:+.2} %)",
        limit.factor,
        limit.failed_at,
        path.steps.len(),
        last.observed.faces[0].along,
        limit.factor * F,
        100.0 * (limit.factor * F / q_u - 1.0)
    );
    limit.factor * F
}

#[test]
fn uplift_capacity_is_the_friction_cylinder_estimate() {
    let run = anchor(1e-3 * E_SOIL / SIZE);
    let reached = limit_load(&run);
    let (_, q_u) = friction_cylinder();
    assert!((reached / q_u - 1.0).abs() < 0.03, "{reached} vs {q_u}");
}

#[test]
fn elastic_normal_stresses_change_the_capacity() {
    let run = anchor(E_SOIL / SIZE);
    let reached = limit_load(&run);
    let (w, q_u) = friction_cylinder();
    // Strength of the vertical joints at the last converged step, at their
    // own normal stresses (axisymmetric: the first section is every one).
    let mesh = &run.problem.model.mesh;
    let field = &run.outcome.as_ref().expect("a nonlinear run").field;
    let tan_phi = PHI.to_radians().tan();
    let (mut strength, mut open_top) = (0.0, false);
    for (i, point) in field.points.iter().enumerate() {
        let name = &mesh.joints[point.joint].name;
        if name == "plate_bottom" {
            continue;
        }
        // Closed: Mohr-Coulomb at the normal stress carried; opening: the
        // shear it carries (its strength fades with the opening).
        let p = field.p[i];
        let tau_y = if field.state[i] == JointState::Open {
            p[0].hypot(p[2])
        } else {
            C - p[1] * tan_phi
        };
        strength += 2.0 * PI * point.point.r * point.point.weight * tau_y.max(0.0);
        open_top |= name == "cylinder" && point.point.position[1] > -SIZE && field.debonded[i];
    }
    println!(
        "W + strength at the joints' stresses {:.5} MN, closed form Q_u {q_u:.5} MN",
        w + strength
    );
    assert!(
        (reached / (w + strength) - 1.0).abs() < 0.01,
        "{reached} vs {}",
        w + strength
    );
    assert!(open_top, "the top of the cylinder stays closed");
    assert!(reached < q_u, "{reached} vs {q_u}");
}

/// An anchor pulled at an angle (0.4 MN up, 0.05 MN sideways, M = 4, the
/// joints at `k_eta = E / h`), with the default settings: near its capacity
/// Newton creeps, and at 500 sweeps the failed load read "not converged"
/// (a stop that is not a limit load); the retry with 4 times the budget
/// shows the stall, so the run ends at a limit load. The vertical load it
/// carries there is the vertical-only capacity within 3 % (an eighth of it
/// sideways barely changes the uplift capacity; measured 1.2 % less).
#[test]
fn an_anchor_pulled_at_an_angle_ends_at_a_limit_load() {
    let (v, h) = (0.4, 0.05);
    let run = anchor_with(Some(E_SOIL / SIZE), [h, 0.0, v], 4);
    let path = run.load_path.as_ref().expect("a stepped run");
    let limit = path.limit.as_ref().expect("beyond the capacity");
    assert!(limit.beyond_capacity, "{}", limit.reason);
    let vertical = limit_load(&anchor(E_SOIL / SIZE));
    println!(
        "pulled at an angle: limit factor {:.5} (failed at {:.5}), {:.5} MN up against {vertical:.5} MN alone",
        limit.factor,
        limit.failed_at,
        limit.factor * v
    );
    assert!((limit.factor * v / vertical - 1.0).abs() < 0.03);
}

/// The anchor pulled at an angle (0.4 MN up, 0.1 MN sideways, M = 4) with
/// rigid interfaces. At its capacity every interface point of plug and
/// plate opens or slides: they carry their strength whatever the plate's
/// motion, so the residual converges with an arbitrary displacement (a
/// step at 0.3574 of the load was accepted with the plate 19.6 km up, the
/// step before at 3.4 mm). Such a step is the limit, not a step: the run
/// ends at a limit load, bracketed to 1 %, with the failed load named a
/// mechanism and every step's displacement bounded.
#[test]
fn a_rigid_anchor_pulled_at_an_angle_ends_at_its_limit_not_at_a_runaway() {
    let (v, h) = (0.4, 0.1);
    let run = anchor_with(None, [h, 0.0, v], 4);
    let path = run.load_path.as_ref().expect("a stepped run");
    let limit = path.limit.as_ref().expect("beyond the capacity");
    assert!(limit.beyond_capacity, "{}", limit.reason);
    assert!(
        limit.failed_at - limit.factor <= 0.01 * limit.factor,
        "{} .. {}",
        limit.factor,
        limit.failed_at
    );
    let along: Vec<f64> = path.steps.iter().map(|s| s.observed.faces[0].along).collect();
    println!(
        "rigid, pulled at an angle: limit factor {:.5} (failed at {:.5}: {}), along the load {along:?} m",
        limit.factor, limit.failed_at, limit.reason
    );
    // Softening before the capacity, not a runaway: the last step moves at
    // most 10 times the first's rate.
    let rate = |i: usize| along[i] / path.steps[i].lambda;
    assert!(rate(along.len() - 1) <= 10.0 * rate(0), "{along:?}");
}
