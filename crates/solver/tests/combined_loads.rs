//! Combined loads (issue 29): a torque beside a lateral or axial load on a
//! pile whose shaft opens.
//!
//! Before, the history law took the cohesion of every pair that once
//! opened: at the edge of the open part of the shaft such a pair, closed
//! again at almost no normal stress, carried no shear, passed its shear to
//! its neighbour, whose normal stress the passed shear turned into tension,
//! and so on: the shaft debonded from end to end at any load (the pile in
//! soil under its axial load alone: 1080 of 1134 pairs) and a torque
//! found no equilibrium at a load factor of 0.0002. Debonding now takes the
//! tensile strength only (the paper's law), and the shear strength of an
//! opening pair fades with its opening (docs/loading.md).
//!
//! | test | claim | tolerance |
//! |---|---|---|
//! | the issue's rows | below capacity every row reaches the whole load (`"auto"`, 16 and 64 fixed steps); its displacements equal 64 steps' where the answer does not depend on the path, else they lie within a tenth of the path check's 1 % of them and 16 steps lie closer than half that (plastic slip, also of an opening pair's shear, is path-dependent: fixed steps converge to the path) | 1e-5 of max \|u\| (ten times epsilon); 1e-3 |
//! | torque alone | limit load factor `T_cap / 1 MN m`, `T_cap = 2 pi a^2 L C + 2 pi a^3 C / 3` (shaft and base at full cohesive slip) | 1 % |
//! | torque beyond capacity beside an axial (and lateral) load | the limit lies within 10 % of `T_cap` (the normal stresses add friction, the axial shear takes some strength), and where 32 fixed steps stop | 10 %, 2 % |
//! | sweep | pile in soil and Scene P: force direction {0, 90, 30 deg} x axial {0, N} x lateral {0, H} x torque {0, small, large} x moment {0, M}: every cell reaches the whole load | - |
//! | rotation | the lateral load and moment turned by 90 degrees (onto the sections) turn the loaded face's motion (u_x, u_y, u_z, a theta_z); by 30 degrees (between the 16 sections) to the sampling of the law (measured at most 5.6e-3) | 1e-6, 1e-2 of \|u\| |
//! | mirror | the torque reversed: u_y and the twist change sign, u_x and u_z stay | 1e-6 of \|u\| |
//! | superposition | C and T so large that nothing opens or slips: every combination equals the linear joints' answer, and the sum of its parts | 1e-10 |
//! | property | random loads below capacity on both scenes converge (`AXIJOINT_COMBINED_CASES`, 24 by default; `scripts/bench-combined` runs more) | - |
//!
//! Scenes: `geo/pile_soil.json` (a = 0.5, L = 10, C = 0.02 MPa, phi = 30
//! deg, no tension, k h / E = 1, no gravity; loaded face `pile_head`) and
//! `geo/pile_footing.json` (Scene P, its head bonded in the footing, the
//! load on `pile_end` 1.5 m below its lower end; the default sections).
//! Run with `--nocapture` for the measured numbers.

use axijoint_solver::iteration::PATH_TOL;
use axijoint_solver::run::{face_displacement, solve_scene, Run};
use axijoint_solver::scene::{JointLaw, Loading, Scene, ShearCheck, SolverSettings};
use axijoint_solver::solution::Displacements;
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use std::f64::consts::PI;

mod joint_cases;
use joint_cases::*;

/// The pile in soil's torque capacity: shaft and base at full cohesive slip.
fn torque_capacity() -> f64 {
    let (a, l, c) = (0.5, 10.0, 0.02);
    2.0 * PI * a * a * l * c + 2.0 * PI * a.powi(3) * c / 3.0
}

/// A scene's head load: `force`, `torque`, `moment` (Mx, My).
#[derive(Clone, Copy, Debug)]
struct Head {
    force: [f64; 3],
    torque: f64,
    moment: [f64; 2],
}

/// The scene `name` with its resultant load replaced.
fn loaded(name: &str, head: Head) -> Scene {
    let mut sc = scene(name);
    sc.sections = None;
    sc.solver = SolverSettings::default();
    let l = resultant(&mut sc);
    (l.force, l.torque, l.moment) = (head.force, head.torque, head.moment);
    sc
}

/// The loaded face of a scene.
fn face(sc: &Scene) -> &str {
    &sc.loads[0].on().to_string().leak()[..]
}

fn run(sc: &Scene) -> Run {
    solve_scene(sc, None, |_| {}).unwrap_or_else(|e| panic!("{}: {e}", sc.title))
}

/// A change of a scene.
type Change = dyn Fn(&mut Scene);

/// The pile radius of both scenes.
const A: f64 = 0.5;

/// The loaded face's mean motion `(u_x, u_y, u_z)` and its mean twist as
/// the circumferential motion at the pile's radius, `a theta_z`.
fn motion(sc: &Scene, r: &Run) -> [f64; 4] {
    let mesh = &r.problem.model.mesh;
    let u = face_displacement(mesh, face(sc), &r.displacements).expect("face");
    [u[0], u[1], u[2], A * mean_twist(mesh, face(sc), &r.displacements)]
}

/// Whether a run reached the whole load.
fn reached(r: &Run) -> bool {
    r.load_path.as_ref().is_none_or(|p| p.limit.is_none())
}

/// `max |a - b| / max |b|` over every displacement amplitude.
fn field_difference(a: &Run, b: &Run) -> f64 {
    difference(&a.displacements, &b.displacements)
}

/// `max |a - b| / max |b|` over every amplitude of two displacements.
fn difference(a: &Displacements, b: &Displacements) -> f64 {
    let (mut diff, mut size) = (0.0f64, 0.0f64);
    for (ha, hb) in a.harmonics.iter().zip(&b.harmonics) {
        for (va, vb) in [
            (&ha.symmetric, &hb.symmetric),
            (&ha.antisymmetric, &hb.antisymmetric),
        ] {
            for (x, y) in va.iter().zip(vb.iter()) {
                diff = diff.max((x - y).abs());
                size = size.max(y.abs());
            }
        }
    }
    diff / size
}

/// Ten times the solver's epsilon: answers this close do not depend on the
/// path.
const PATH_INDEPENDENT: f64 = 1e-5;

/// Pairs that slipped in any converged step of a run.
fn slipped(r: &Run) -> usize {
    r.load_path
        .as_ref()
        .map_or(0, |p| p.steps.iter().map(|s| s.slip).max().unwrap_or(0))
}

#[test]
fn the_issues_rows_below_capacity_converge_on_the_fine_path() {
    let lateral = |h: [f64; 2], t: f64| Head {
        force: [h[0], h[1], 0.0],
        torque: t,
        moment: [0.0; 2],
    };
    let rows: Vec<(&str, Head, Option<&Change>)> = vec![
        ("lateral 0.05", lateral([0.05, 0.0], 0.0), None),
        ("lateral 0.05 + torque 0.03", lateral([0.05, 0.0], 0.03), None),
        ("lateral 0.05 + torque 0.1", lateral([0.05, 0.0], 0.1), None),
        (
            "lateral 0.05 along y + torque 0.1",
            lateral([0.0, 0.05], 0.1),
            None,
        ),
        (
            "lateral 0.05 + torque 0.1, component check",
            lateral([0.05, 0.0], 0.1),
            Some(&|sc: &mut Scene| {
                for j in sc.joints.values_mut() {
                    if let JointLaw::MohrCoulomb(mc) = &mut j.law {
                        mc.shear_check = ShearCheck::Components;
                    }
                }
            }),
        ),
        (
            "lateral 0.05 + torque 0.1, T = 0.03",
            lateral([0.05, 0.0], 0.1),
            Some(&|sc: &mut Scene| {
                for j in sc.joints.values_mut() {
                    if let JointLaw::MohrCoulomb(mc) = &mut j.law {
                        mc.tensile_strength = 0.03;
                    }
                }
            }),
        ),
        (
            "axial 0.3 + torque 0.1",
            Head {
                force: [0.0, 0.0, -0.3],
                torque: 0.1,
                moment: [0.0; 2],
            },
            None,
        ),
    ];
    let mut failures = Vec::new();
    for (name, head, change) in rows {
        let mut sc = loaded("pile_soil.json", head);
        if let Some(change) = change {
            change(&mut sc);
        }
        let stepped = |n: u32| {
            let mut fixed = sc.clone();
            fixed.solver.loading = Loading::Steps(n);
            run(&fixed)
        };
        let (auto, mid, fine) = (run(&sc), stepped(16), stepped(64));
        let (d, d16) = (field_difference(&auto, &fine), field_difference(&mid, &fine));
        println!(
            "{name}: auto {} steps ({} pairs slip at most), against 64 steps {d:.2e}, 16 steps {d16:.2e}; head {:.4e}",
            auto.load_path.as_ref().map_or(0, |p| p.steps.len()),
            slipped(&auto),
            motion(&sc, &auto)[0]
        );
        // Path-independent to the solve's accuracy, or a path that the
        // fixed steps converge to.
        let on_path = d < PATH_INDEPENDENT || (d < PATH_TOL / 10.0 && d16 < 0.5 * d);
        if !reached(&auto) || !reached(&mid) || !reached(&fine) || !on_path {
            failures.push(format!(
                "{name}: reached {} / {} / {}, against 64 steps {d:.2e}, 16 steps {d16:.2e}",
                reached(&auto),
                reached(&mid),
                reached(&fine)
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn torque_alone_ends_at_the_torsional_capacity() {
    let sc = loaded(
        "pile_soil.json",
        Head {
            force: [0.0; 3],
            torque: 1.0,
            moment: [0.0; 2],
        },
    );
    let r = run(&sc);
    let limit = r
        .load_path
        .as_ref()
        .and_then(|p| p.limit.clone())
        .expect("a limit load");
    println!(
        "torque 1: limit {:.5} (T_cap {:.5})",
        limit.factor,
        torque_capacity()
    );
    assert!(limit.beyond_capacity, "{}", limit.reason);
    assert!(
        (limit.factor / torque_capacity() - 1.0).abs() < 0.01,
        "{}",
        limit.factor
    );
}

#[test]
fn a_torque_beyond_capacity_beside_other_loads_ends_near_the_torsional_capacity() {
    for force in [[0.0, 0.0, -0.3], [0.05, 0.0, -0.3]] {
        let head = Head {
            force,
            torque: 1.0,
            moment: [0.0; 2],
        };
        let sc = loaded("pile_soil.json", head);
        let limit = |sc: &Scene| {
            let r = run(sc);
            let l = r
                .load_path
                .as_ref()
                .and_then(|p| p.limit.clone())
                .expect("a limit load");
            assert!(l.beyond_capacity, "{force:?}: {}", l.reason);
            l.factor
        };
        let auto = limit(&sc);
        let mut stepped = sc.clone();
        stepped.solver.loading = Loading::Steps(32);
        let fine = limit(&stepped);
        println!(
            "{force:?} + torque 1: limit {auto:.4} ({:+.1} % of T_cap), 32 steps {fine:.4}",
            100.0 * (auto / torque_capacity() - 1.0)
        );
        assert!((auto / torque_capacity() - 1.0).abs() < 0.1, "{force:?}: {auto}");
        assert!((auto / fine - 1.0).abs() < 0.02, "{force:?}: {auto} vs {fine}");
    }
}

/// The loads of the sweep on a scene: axial `n` (down), lateral `h`,
/// torques (small, large), moment `m`.
struct Sweep {
    name: &'static str,
    n: f64,
    h: f64,
    torques: [f64; 2],
    m: f64,
}

const SWEEPS: [Sweep; 2] = [
    // Torque: 10 % and 30 % of T_cap = 0.3194; the soil is elastic, so the
    // pile has no lateral, axial (compression) or bending capacity to scale
    // from: the shipped loads, the moment of H one metre above the head.
    Sweep {
        name: "pile_soil.json",
        n: 0.3,
        h: 0.05,
        torques: [0.032, 0.096],
        m: 0.05,
    },
    // Scene P: table1's H; the head is bonded, so no capacity either: the
    // torques are 10 % and 30 % of the socket's cohesive one, 2 pi a^2 L C = 0.785.
    Sweep {
        name: "pile_footing.json",
        n: 0.5,
        h: 0.5,
        torques: [0.0785, 0.236],
        m: 0.5,
    },
];

/// The head load of a sweep cell: lateral and moment turned by `deg`.
fn cell(s: &Sweep, deg: f64, axial: bool, lateral: bool, torque: f64, moment: bool) -> Head {
    let (sin, cos) = deg.to_radians().sin_cos();
    let h = if lateral { s.h } else { 0.0 };
    let m = if moment { s.m } else { 0.0 };
    Head {
        force: [h * cos, h * sin, if axial { -s.n } else { 0.0 }],
        torque,
        moment: [-m * sin, m * cos],
    }
}

#[test]
fn combined_load_sweep_converges_turns_and_mirrors() {
    let mut failures = Vec::new();
    for s in &SWEEPS {
        let mut cells = 0;
        for axial in [false, true] {
            for torque in [0.0, s.torques[0], s.torques[1]] {
                for (lateral, moment) in [(false, false), (true, false), (false, true), (true, true)] {
                    let solve = |deg: f64, t: f64| {
                        let sc = loaded(s.name, cell(s, deg, axial, lateral, t, moment));
                        let r = run(&sc);
                        (reached(&r), motion(&sc, &r))
                    };
                    let what = format!(
                        "{}: axial {axial}, lateral {lateral}, moment {moment}, torque {torque}",
                        s.name
                    );
                    let (ok, u) = solve(0.0, torque);
                    cells += 1;
                    if !ok {
                        failures.push(format!("{what}: stopped"));
                        continue;
                    }
                    let size = u.iter().map(|v| v * v).sum::<f64>().sqrt();
                    // The torque reversed mirrors the motion about the x-z plane.
                    if torque != 0.0 {
                        let (ok, v) = solve(0.0, -torque);
                        cells += 1;
                        let mirrored = [u[0], -u[1], u[2], -u[3]];
                        let off = (0..4).map(|c| (v[c] - mirrored[c]).abs()).fold(0.0, f64::max) / size;
                        if !ok || off > 1e-6 {
                            failures.push(format!("{what}: reversed torque: {ok}, {off:.1e}"));
                        }
                    }
                    if !(lateral || moment) {
                        continue;
                    }
                    // Turned by 90 degrees (onto the sections: exact) and by 30
                    // (between them: the law is sampled at 16 sections).
                    for (deg, tol) in [(90.0, 1e-6), (30.0, 1e-2)] {
                        let (ok, v) = solve(deg, torque);
                        cells += 1;
                        let (sin, cos) = f64::to_radians(deg).sin_cos();
                        let turned = [cos * u[0] - sin * u[1], sin * u[0] + cos * u[1], u[2], u[3]];
                        let off = (0..4).map(|c| (v[c] - turned[c]).abs()).fold(0.0, f64::max) / size;
                        println!("{what}, turned {deg}: {off:.1e}");
                        if !ok || off > tol {
                            failures.push(format!("{what}: turned {deg}: {ok}, {off:.1e}"));
                        }
                    }
                }
            }
        }
        println!("{}: {cells} cells", s.name);
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn where_nothing_yields_every_combination_is_the_linear_answer() {
    let strong = |head: Head| {
        let mut sc = loaded("pile_soil.json", head);
        for j in sc.joints.values_mut() {
            if let JointLaw::MohrCoulomb(mc) = &mut j.law {
                (mc.cohesion, mc.tensile_strength) = (10.0, 5.0);
            }
        }
        sc
    };
    let linear = |mut sc: Scene| {
        for j in sc.joints.values_mut() {
            j.law = JointLaw::Linear;
        }
        run(&sc)
    };
    let parts = [
        Head {
            force: [0.05, 0.0, 0.0],
            torque: 0.0,
            moment: [0.0; 2],
        },
        Head {
            force: [0.0, 0.0, -0.3],
            torque: 0.0,
            moment: [0.0; 2],
        },
        Head {
            force: [0.0; 3],
            torque: 0.5,
            moment: [0.0; 2],
        },
        Head {
            force: [0.0; 3],
            torque: 0.0,
            moment: [0.0, 0.2],
        },
    ];
    let sum = |mask: u32| {
        let mut h = Head {
            force: [0.0; 3],
            torque: 0.0,
            moment: [0.0; 2],
        };
        for p in parts
            .iter()
            .enumerate()
            .filter(|(k, _)| mask & (1 << k) != 0)
            .map(|(_, p)| p)
        {
            for c in 0..3 {
                h.force[c] += p.force[c];
            }
            h.torque += p.torque;
            h.moment[0] += p.moment[0];
            h.moment[1] += p.moment[1];
        }
        h
    };
    let alone: Vec<Run> = (0..4).map(|k| linear(strong(sum(1 << k)))).collect();
    for mask in [0b0011u32, 0b0101, 0b1110, 0b1111] {
        let sc = strong(sum(mask));
        let r = run(&sc);
        let field = r.outcome.as_ref().expect("nonlinear joints").field.clone();
        assert!(field
            .state
            .iter()
            .all(|s| *s == axijoint_solver::joint_law::JointState::Stick));
        let d = field_difference(&r, &linear(sc.clone()));
        // The sum of the parts.
        let mut summed = alone[0].displacements.clone();
        for (k, h) in summed.harmonics.iter_mut().enumerate() {
            for (family, values) in [&mut h.symmetric, &mut h.antisymmetric].into_iter().enumerate() {
                for (n, v) in values.iter_mut().enumerate() {
                    *v = (0..alone.len())
                        .filter(|p| mask & (1 << p) != 0)
                        .map(|p| {
                            let hp = &alone[p].displacements.harmonics[k];
                            [&hp.symmetric, &hp.antisymmetric][family][n]
                        })
                        .sum();
                }
            }
        }
        let s = difference(&r.displacements, &summed);
        println!("parts {mask:04b}: against linear joints {d:.1e}, against the sum of the parts {s:.1e}");
        assert!(d < 1e-10 && s < 1e-10, "{mask:04b}: {d:.1e}, {s:.1e}");
    }
}

/// Random loads below capacity: both scenes, `AXIJOINT_COMBINED_CASES`
/// cases each (24 by default).
#[test]
fn random_loads_below_capacity_converge() {
    let cases = std::env::var("AXIJOINT_COMBINED_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(24);
    for s in &SWEEPS {
        let mut runner = TestRunner::new(Config {
            cases,
            failure_persistence: None,
            ..Config::default()
        });
        // Axial from 0.5 N uplift to 2 N down; lateral up to 2 H; torque up to
        // 5 times the sweep's small one either way (half the pile in soil's
        // T_cap); moment up to 2 M either way; any direction.
        let t = 5.0 * s.torques[0];
        let loads = (
            -0.5..2.0f64,
            0.0..2.0f64,
            -1.0..1.0f64,
            -2.0..2.0f64,
            0.0..360.0f64,
        );
        let result = runner.run(&loads, |(n, h, tq, m, deg)| {
            let (sin, cos) = deg.to_radians().sin_cos();
            let head = Head {
                force: [h * s.h * cos, h * s.h * sin, -n * s.n],
                torque: tq * t,
                moment: [-m * s.m * sin, m * s.m * cos],
            };
            let sc = loaded(s.name, head);
            let r =
                solve_scene(&sc, None, |_| {}).map_err(|e| TestCaseError::fail(format!("{head:?}: {e}")))?;
            prop_assert!(
                reached(&r),
                "{}: {head:?} stopped: {:?}",
                s.name,
                r.load_path.as_ref().and_then(|p| p.limit.clone())
            );
            Ok(())
        });
        println!("{}: {cases} random cases", s.name);
        if let Err(e) = result {
            panic!("{}: {e}", s.name);
        }
    }
}
