//! Member forces (issue 27): the section resultants, the surroundings'
//! reaction and the capacity split of a body read as a member along the
//! axis, on real gmsh meshes of `geo/`. Statics hold to round-off (every
//! station is a free body of element nodal forces); the motion against
//! Timoshenko's beam.
//!
//! Run with `--nocapture` to see the measured numbers.

use axijoint_solver::joint_law::JointState;
use axijoint_solver::members::MemberForces;
use axijoint_solver::run::{solution_header, solve_scene};
use axijoint_solver::scene::Scene;
use std::f64::consts::PI;
use std::path::PathBuf;

fn geo(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../geo")
        .join(name)
}

fn members(scene: &Scene) -> Vec<MemberForces> {
    let run = solve_scene(scene, None, |_| {}).unwrap_or_else(|e| panic!("{}", e.error));
    solution_header(scene, &run).members
}

/// Largest `|a - b|` over three components.
fn diff(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|c| (a[c] - b[c]).abs()).fold(0.0, f64::max)
}

// The cantilever: a solid cylinder fixed at its base, a resultant at its top.
const A: f64 = 0.5;
const L: f64 = 10.0;
const E: f64 = 3.0e4;
const NU: f64 = 0.2;
const H: f64 = 0.1;
const P: f64 = -1.0;
const TORQUE: f64 = 0.05;

fn cantilever(quads: u32) -> MemberForces {
    let text = format!(
        r#"{{
      "mesh": {{"file": "cylinder.geo", "parameters": {{"a": {A}, "L": {L}, "size": 0.125, "order": 2, "quads": {quads}}}}},
      "materials": {{"body": {{"E": {E}, "nu": {NU}}}}},
      "supports": [{{"on": "bottom", "fix": "all"}}],
      "loads": [{{"type": "resultant", "on": "top", "force": [{H}, 0, {P}], "torque": {TORQUE}}}],
      "harmonics": 1,
      "outputs": {{"members": ["body"]}}
    }}"#
    );
    let scene = Scene::from_str(&text, geo("cantilever.json")).unwrap_or_else(|e| panic!("{e}"));
    members(&scene).remove(0)
}

/// A cantilever without surroundings: `N = P`, `V = H`, `T` = the torque
/// and `M_y = H (L - z)` at every station to 1e-9 of the largest; the
/// reaction all on the base plane. The tip's mean deflection and rotation
/// against Timoshenko's beam (shear coefficient of a circle
/// `6 (1 + nu) / (7 + 6 nu)`) within 0.5 % (measured 0.27 %), the twist
/// to round-off: the clamped base also holds the
/// base's Poisson contraction and warping, which a beam ignores.
#[test]
fn a_cantilever_carries_its_tip_load_by_statics_and_bends_as_timoshenko_says() {
    for quads in [1, 0] {
        let mf = cantilever(quads);
        let scale = H * L + P.abs() + TORQUE;
        let mut worst: f64 = 0.0;
        for st in &mf.stations {
            let exact_f = [H, 0.0, P];
            let exact_m = [0.0, H * (L - st.z), TORQUE];
            worst = worst.max(diff(st.force, exact_f)).max(diff(st.moment, exact_m));
        }
        println!(
            "quads {quads}: {} stations, worst statics error {:.2e} of {scale}",
            mf.stations.len(),
            worst
        );
        assert!(worst < 1e-9 * scale, "statics off by {worst:e}");
        // The side's element ends: L / size + 1 of them.
        assert!(mf.stations.len() >= 81, "{} stations", mf.stations.len());
        // Nothing touches the side: all of the reaction is on the base plane.
        assert!(diff(mf.split.shaft, [0.0; 3]) < 1e-9 * scale, "{:?}", mf.split);
        assert!(
            diff(mf.split.base, [-H, 0.0, -P]) < 1e-9 * scale,
            "{:?}",
            mf.split
        );
        assert!(
            diff(mf.base.moment, [0.0, -H * L, -TORQUE]) < 1e-9 * scale,
            "{:?}",
            mf.base
        );

        let (g, area, inertia) = (E / (2.0 * (1.0 + NU)), PI * A * A, PI * A.powi(4) / 4.0);
        let kappa = 6.0 * (1.0 + NU) / (7.0 + 6.0 * NU);
        let deflection = H * L.powi(3) / (3.0 * E * inertia) + H * L / (kappa * g * area);
        let rotation = H * L * L / (2.0 * E * inertia);
        let twist = TORQUE * L / (g * PI * A.powi(4) / 2.0);
        let shortening = P * L / (E * area);
        let tip = &mf.stations[0];
        let phi = tip.rotation.expect("rotation");
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
        println!(
            "  tip u_x {:.6e} (Timoshenko {deflection:.6e}, {:.2e}), phi_y {:.6e} ({rotation:.6e}, {:.2e}), \
             phi_z {:.6e} ({twist:.6e}, {:.2e}), u_z {:.6e} ({shortening:.6e}, {:.2e})",
            tip.displacement[0],
            rel(tip.displacement[0], deflection),
            phi[1],
            rel(phi[1], rotation),
            phi[2],
            rel(phi[2], twist),
            tip.displacement[2],
            rel(tip.displacement[2], shortening),
        );
        assert!(rel(tip.displacement[0], deflection) < 0.005);
        assert!(rel(phi[1], rotation) < 0.005);
        assert!(rel(phi[2], twist) < 1e-9);
        assert!(rel(tip.displacement[2], shortening) < 0.005);
    }
}

/// `(force, moment)` moved from the axis point at `z` to the one at `to`.
fn moved(force: [f64; 3], moment: [f64; 3], z: f64, to: f64) -> [f64; 3] {
    let d = to - z;
    [moment[0] + d * force[1], moment[1] - d * force[0], moment[2]]
}

/// The shipped pile in soil (Mohr-Coulomb joints on the shaft and the
/// base, stepped Newton, a combined head load): the head station carries
/// the applied load, each station the one above plus the reaction of the
/// shaft between them (force and moment, moved along the axis), the base
/// station minus the base reaction, and shaft plus base balance the load,
/// all to 1e-9 of the load's scale.
#[test]
fn the_pile_in_soil_balances_station_by_station() {
    let mut scene = Scene::from_path(geo("pile_soil.json")).unwrap_or_else(|e| panic!("{e}"));
    scene.outputs.members = vec!["pile".into()];
    let mf = members(&scene).remove(0);
    let (h, v): (f64, f64) = (0.05, -0.3);
    let scale = v.abs() + h * 10.0;
    let tol = 1e-9 * scale;
    let head = &mf.stations[0];
    assert!(diff(head.force, [h, 0.0, v]) < tol, "{head:?}");
    assert!(diff(head.moment, [0.0; 3]) < tol, "{head:?}");
    let mut worst: f64 = 0.0;
    for (k, seg) in mf.segments.iter().enumerate() {
        let (a, b) = (&mf.stations[k], &mf.stations[k + 1]);
        let zm = 0.5 * (seg.z_top + seg.z_bottom);
        let f = [0, 1, 2].map(|c| a.force[c] + seg.force[c]);
        let ma = moved(a.force, a.moment, a.z, b.z);
        let ms = moved(seg.force, seg.moment, zm, b.z);
        let m = [0, 1, 2].map(|c| ma[c] + ms[c]);
        worst = worst.max(diff(f, b.force)).max(diff(m, b.moment));
    }
    let toe = mf.stations.last().expect("stations");
    let balance =
        [0, 1, 2].map(|c| mf.split.applied[c] + mf.split.weight[c] + mf.split.shaft[c] + mf.split.base[c]);
    println!(
        "{} stations from z = {} to {}; worst station-to-station imbalance {worst:.2e}; split {:?}; toe {:?}",
        mf.stations.len(),
        head.z,
        toe.z,
        mf.split,
        toe
    );
    assert!(worst < tol, "{worst:e}");
    assert!(
        diff(toe.force, mf.base.force.map(|f| -f)) < tol,
        "{toe:?} {:?}",
        mf.base
    );
    assert!(
        diff(toe.moment, mf.base.moment.map(|m| -m)) < tol,
        "{toe:?} {:?}",
        mf.base
    );
    assert!(diff(balance, [0.0; 3]) < tol, "{:?}", mf.split);
    // The shaft and the base both carry part of the axial load.
    assert!(
        mf.split.shaft[2] > 0.0 && mf.split.base[2] > 0.0,
        "{:?}",
        mf.split
    );
}

/// A monopile of our own (`geo/monopile.geo`: D = 8 m, L / D = 4, solid,
/// coarse mesh), 10 MN sideways 20 m above the ground, bonded to elastic
/// soil and with rigid Mohr-Coulomb joints (no tension, c = 0.05 MPa)
/// loaded in three steps: at every step the four PISA components (the
/// distributed load p and moment m of the shaft segments, the base shear
/// H_b and moment M_b) balance the load at the ground to 1e-9 of H e.
#[test]
fn a_monopile_s_pisa_components_balance_the_load_at_every_step() {
    let (h, e) = (10.0, 20.0);
    for joints in [false, true] {
        let joint = r#"{"bottom": "pile", "top": "soil", "law": {"type": "mohr_coulomb", "cohesion": 0.05, "friction_deg": 0, "tensile_strength": 0}}"#;
        let (joints_json, solver) = if joints {
            (
                format!(r#""joints": {{"pile_side": {joint}, "pile_base": {joint}}},"#),
                r#""solver": {"method": "newton", "loading": {"steps": 3}},"#,
            )
        } else {
            (String::new(), "")
        };
        let text = format!(
            r#"{{
          "mesh": {{"file": "monopile.geo", "parameters": {{"size": 2, "coarsen": 4}}}},
          "materials": {{"pile": {{"E": 2.0e4, "nu": 0.3}}, "soil": {{"E": 60, "nu": 0.35}}}},
          {joints_json}
          "supports": [{{"on": "soil_outer", "fix": "all"}}, {{"on": "soil_bottom", "fix": "all"}}],
          "loads": [{{"type": "resultant", "on": "pile_head", "force": [{h}, 0, 0], "at_z": {e}}}],
          "harmonics": 2,
          {solver}
          "outputs": {{"members": ["pile"]}}
        }}"#
        );
        let scene = Scene::from_str(&text, geo("monopile.json")).unwrap_or_else(|e| panic!("{e}"));
        let run = solve_scene(&scene, None, |_| {}).unwrap_or_else(|e| panic!("{}", e.error));
        let header = solution_header(&scene, &run);
        let mut states: Vec<(f64, MemberForces)> = header
            .record
            .as_ref()
            .and_then(|r| r.load_path.as_ref())
            .map(|p| {
                p.steps
                    .iter()
                    .map(|s| (s.lambda, s.observed.members[0].clone()))
                    .collect()
            })
            .unwrap_or_default();
        states.push((1.0, header.members[0].clone()));
        assert_eq!(states.len(), if joints { 4 } else { 1 });
        for (lambda, mf) in &states {
            let (hl, ml) = (lambda * h, lambda * h * e);
            let (mut f, mut m) = ([0.0; 3], [0.0; 3]);
            for seg in &mf.segments {
                let zm = 0.5 * (seg.z_top + seg.z_bottom);
                let ms = moved(seg.force, seg.moment, zm, 0.0);
                for c in 0..3 {
                    f[c] += seg.force[c];
                    m[c] += ms[c];
                }
            }
            let mb = moved(mf.base.force, mf.base.moment, mf.base.z, 0.0);
            let head = &mf.stations[0];
            println!(
                "joints {joints}, lambda {lambda}: integral p = {:.6e}, H_b = {:.6e}, moment of p and m at the ground {:.6e}, M_b {:.6e}; head (H, M) = ({:.6e}, {:.6e})",
                f[0], mf.base.force[0], m[1], mb[1], head.force[0], head.moment[1]
            );
            assert!((head.force[0] - hl).abs() < 1e-9 * ml && (head.moment[1] - ml).abs() < 1e-9 * ml);
            assert!((f[0] + mf.base.force[0] + hl).abs() < 1e-9 * ml);
            assert!((m[1] + mb[1] + ml).abs() < 1e-9 * ml);
            // The soil in front carries the load: p against the load near
            // the head, the base shear and moment small beside the shaft's.
            assert!(mf.segments[0].force[0] < 0.0);
            assert!(mf.base.moment[1].abs() < 0.25 * ml, "{:?}", mf.base);
        }
    }
}

/// A bonded pile in elastic soil (`geo/pile_soil.json` without its joints,
/// its head load 0.05 MN sideways only): the largest bending moment
/// against Randolph's (1981) flexible-pile estimate `M_max = 0.1 H l_c`
/// (homogeneous soil, free head), `l_c = D (E_p / G*)^(2/7)`,
/// `G* = G (1 + 3 nu / 4)`, within 10 %; its depth within Randolph's
/// moment profile's peak, 0.2 to 0.4 `l_c` (the Winkler analogue puts it
/// at 0.24 `l_c`).
#[test]
fn a_bonded_pile_s_largest_moment_is_randolph_s() {
    let path = geo("pile_soil.json");
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).expect("scene")).expect("json");
    doc.as_object_mut().expect("object").remove("joints");
    doc["loads"] = serde_json::json!([{"type": "resultant", "on": "pile_head", "force": [0.05, 0, 0]}]);
    doc["harmonics"] = serde_json::json!(1);
    doc["outputs"]["members"] = serde_json::json!(["pile"]);
    let scene = Scene::from_str(&doc.to_string(), &path).unwrap_or_else(|e| panic!("{e}"));
    let mf = members(&scene).remove(0);
    let (d, e_p, e_s, nu, h): (f64, f64, f64, f64, f64) = (1.0, 3.0e4, 50.0, 0.3, 0.05);
    let g_star = e_s / (2.0 * (1.0 + nu)) * (1.0 + 0.75 * nu);
    let l_c = d * (e_p / g_star).powf(2.0 / 7.0);
    let m_randolph = 0.1 * h * l_c;
    let key = mf.summary();
    let depth = -key.max_moment_z;
    println!(
        "l_c = {l_c:.3} m: M_max {:.5e} against Randolph {m_randolph:.5e} ({:+.2} %), at {depth:.3} m = {:.3} l_c",
        key.max_moment,
        100.0 * (key.max_moment / m_randolph - 1.0),
        depth / l_c
    );
    assert!((key.max_moment / m_randolph - 1.0).abs() < 0.10);
    assert!(
        (0.2..=0.4).contains(&(depth / l_c)),
        "depth {depth} m, l_c {l_c} m"
    );
}

/// The pile in soil pulled up 0.4 MN (no weight, joints without tensile
/// strength): the shaft opens from the top down; the length the member
/// reports holds only open points at every section above it, and the
/// shaft point next below is closed somewhere. The shaft carries the pull.
#[test]
fn a_pulled_pile_reports_how_far_its_shaft_is_open_all_round() {
    let mut scene = Scene::from_path(geo("pile_soil.json")).unwrap_or_else(|e| panic!("{e}"));
    scene.outputs.members = vec!["pile".into()];
    let text = serde_json::to_string(&scene).expect("scene");
    let text = text.replace("\"force\":[0.05,0.0,-0.3]", "\"force\":[0.0,0.0,0.4]");
    let scene = Scene::from_str(&text, geo("pile_soil.json")).unwrap_or_else(|e| panic!("{e}"));
    assert!(text.contains("[0.0,0.0,0.4]"), "the pull is applied");
    let run = solve_scene(&scene, None, |_| {}).unwrap_or_else(|e| panic!("{}", e.error));
    let mf = solution_header(&scene, &run).members.remove(0);
    let d = mf.open_from_top.expect("a joint lines the shaft");
    let field = run.joint_field(&scene).expect("field").expect("joints");
    let n_p = field.points.len();
    let z_top = mf.stations[0].z;
    let mut above = 0;
    let mut next_below: Option<(f64, bool)> = None;
    for (p, info) in field.points.iter().enumerate() {
        let [tr, tz] = info.point.tangent;
        if tz.abs() <= tr.abs() {
            continue;
        }
        let z = info.point.position[1];
        let open = (0..field.sections.len()).all(|s| field.state[s * n_p + p] == JointState::Open);
        if z > z_top - d {
            assert!(open, "a point at z = {z} above the open length {d} is closed");
            above += 1;
        } else if next_below.is_none_or(|(zb, _)| z > zb) {
            next_below = Some((z, open));
        }
    }
    println!(
        "open from the top: {d:.4} m over {above} points; next below {next_below:?}; split {:?}",
        mf.split
    );
    assert!(above > 0 && d > 0.0 && d < 10.0);
    assert_eq!(next_below.map(|(_, open)| open), Some(false));
    assert!(-mf.split.shaft[2] > 0.95 * 0.4, "{:?}", mf.split);
}
