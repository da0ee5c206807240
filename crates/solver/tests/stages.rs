//! Loads in stages (`stages`, issue 28): each stage from the converged
//! state of the one before, the joint history carried over.
//!
//! | test | claim | tolerance |
//! |---|---|---|
//! | rod in a rigid sleeve | load, unload, reload `P`: head displacement `f(P) = P^2 / (2 EA q)` on loading, Masing's `w_max - 2 f((P_max - P) / 2)` on unloading, `w_max / 2 + 2 f(P / 2)` on reloading, at every step | 2 % of `w_max` (measured 0.25 %) |
//! | dissipation | the joints' slip work: `P^3 / (6 EA q)` on loading, the Masing loop's area `P^3 / (12 EA q)` over unloading and reloading; the applied load per step | 2 %; 1e-12 |
//! | below the capacity | nothing slips: unloaded, nothing stays | `1e-10 w_max` |
//! | a stage beyond the capacity | stops in that stage at its limit factor: the applied pull `q L` | 1 % |
//! | path | dead load then lateral load against both at once: equal where nothing slips, different where the shaft slips | `1e-6` (epsilon; measured 1e-8); > 1 % (measured 21 %) |
//! | torsion reversed | a block twisted on a cohesive joint between +-0.8 T_max: every step's twist against Masing from the virgin partial-slip curve | 2 % of the peak twist (measured 0.04 %) |
//! | shakedown | twisted to 0.9 T_max, then cycled between 0.5 and 0.9 T_max: no slip work after the first loading | `1e-9` of the first |
//! | displacement control | a rigid block's top moved sideways between +-3 Hs / K on a cohesive joint: the force follows the parallelogram (K du, capped at +-Hs); each cycle's slip work `4 Hs (u_max - Hs / K)`; the moved face where it was sent, its reaction Hs | 1 % of Hs (measured 0.03 %); 1 % (0.007 %); 1e-12; 1 % |
//! | rigid motion | a face turned and tilted by a `motion`: every node where the motion puts it; its fitted rotation; the reaction torque `k pi a^4 / 2 rz` | 1e-15; 1e-12; 1 % |
//! | cycles | a cyclic stage runs its levels `cycles` times; every peak and trough as the first (Masing) | `2e-4 w_max` (measured 4.7e-5 per cycle) |
//! | ratcheting | a stiff rod pulled at `p = 0.6 C` and twisted back and forth beyond slip (a `motion` holding r and theta, z free): the rod slides out by `4 (p / s) (a phi - s / k)` every cycle, `s = sqrt(C^2 - p^2)`; every leg's end; the full turn's sections when only a middle stage twists | 1 % of a cycle's growth (measured 0.036 % per cycle, 0.13 % after 3.5 cycles) |
//! | hold | a load on a moved face only in the components its `hold` leaves free; a motion that moves its face only in free components refused | the message names the component |
//!
//! The rod: `geo/pile_soil.geo` with `a = 0.1` (L / a = 100: a rod), E =
//! 3e4, nu = 0 (no Poisson contraction to open the shaft), in a soil 1000
//! times stiffer (a rigid sleeve); a cohesive shaft joint (`q = 2 pi a C`,
//! phi = 0), rigid until it slips; the base joint carries no tension. With
//! the shipped radius 0.5 (L / a = 20) the same path is 1 to 9 % off the
//! closed form, growing with refinement: the rod's shear lag over slip
//! zones a few radii long, which the closed form leaves out.

use axijoint_solver::run::{face_displacement, solve_scene, Run};
use axijoint_solver::scene::Scene;
use serde_json::{json, Value};
use std::f64::consts::PI;
use std::path::PathBuf;

fn geo(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../geo")
        .join(name)
}

const A: f64 = 0.1;
const C: f64 = 0.01;
const E: f64 = 3.0e4;

fn q() -> f64 {
    2.0 * PI * A * C
}

fn ea() -> f64 {
    E * PI * A * A
}

/// The pull-out head displacement of the rod at pull `p` (loading).
fn f(p: f64) -> f64 {
    p * p / (2.0 * ea() * q())
}

fn pull(p: f64) -> Value {
    json!([{"type": "resultant", "on": "pile_head", "force": [0, 0, p]}])
}

/// The rod in its sleeve with `stages`.
fn rod(stages: Value, cohesion: f64) -> Scene {
    let law =
        |c: f64| json!({"type": "mohr_coulomb", "cohesion": c, "friction_deg": 0, "tensile_strength": 0});
    let s = json!({
        "title": "rod in a rigid sleeve",
        "mesh": {"file": geo("pile_soil.geo"), "parameters": {"a": A, "size": 0.25, "coarsen": 8, "order": 2, "quads": 1}},
        "materials": {"pile": {"E": E, "nu": 0.0}, "soil": {"E": 3.0e7, "nu": 0.3}},
        "joints": {
            "pile_side": {"bottom": "pile", "top": "soil", "stiffness": "rigid", "law": law(cohesion)},
            "pile_base": {"bottom": "pile", "top": "soil", "stiffness": "rigid", "law": law(0.0)}
        },
        "supports": [{"on": "soil_outer", "fix": "all"}, {"on": "soil_bottom", "fix": "all"}],
        "stages": stages,
        "harmonics": 0,
        "solver": {"method": "newton", "epsilon": 1e-8}
    });
    Scene::from_str(&s.to_string(), geo("stages_rod.json")).expect("scene")
}

fn solve(scene: &Scene) -> Run {
    solve_scene(scene, None, |_| {}).unwrap_or_else(|e| panic!("{}: {}", scene.title, e.error))
}

/// (stage, lambda, head uz) of every converged step.
fn head_path(run: &Run) -> Vec<(String, f64, f64)> {
    let path = run.load_path.as_ref().expect("a load path");
    path.steps
        .iter()
        .map(|s| {
            let stage = s.observed.stage.as_ref().expect("a stage mark").stage.clone();
            let head = s
                .observed
                .faces
                .iter()
                .find(|f| f.on == "pile_head")
                .expect("the head");
            (stage, s.lambda, head.mean[2])
        })
        .collect()
}

#[test]
fn a_rod_in_a_rigid_sleeve_follows_masing_on_unloading_and_reloading() {
    let p = 0.04; // 0.64 q L
    let steps = json!({"steps": 4});
    let scene = rod(
        json!([
            {"name": "load", "loads": pull(p), "loading": steps},
            {"name": "unload", "loads": [], "loading": steps},
            {"name": "reload", "loads": pull(p), "loading": steps}
        ]),
        C,
    );
    let run = solve(&scene);
    let w_max = f(p);
    let mut worst = 0.0f64;
    let path = head_path(&run);
    assert_eq!(path.len(), 12);
    for (stage, lambda, w) in &path {
        let expected = match stage.as_str() {
            "load" => f(lambda * p),
            "unload" => w_max - 2.0 * f(lambda * p / 2.0),
            _ => w_max / 2.0 + 2.0 * f(lambda * p / 2.0),
        };
        let e = (w - expected) / w_max;
        println!(
            "{stage} lambda {lambda:.2}: head {w:.5e}, closed form {expected:.5e} ({:+.3} % of w_max)",
            100.0 * e
        );
        worst = worst.max(e.abs());
    }
    assert!(worst < 0.02, "worst {worst:.4} of w_max");
    // The joints' slip work: P^3 / (6 EA q) on the first loading (the work
    // of the pull, 2 P^3 / (6 EA q), less the rod's stored energy), and the
    // area of the Masing loop, P^3 / (12 EA q), over unloading and
    // reloading; on the applied load and head motion, the same loop area.
    let path_steps = &run.load_path.as_ref().unwrap().steps;
    let work = |stages: &[&str]| -> f64 {
        path_steps
            .iter()
            .filter(|s| stages.contains(&s.observed.stage.as_ref().unwrap().stage.as_str()))
            .map(|s| s.observed.dissipated.unwrap())
            .sum()
    };
    let (first, loop_) = (work(&["load"]), work(&["unload", "reload"]));
    let unit = p.powi(3) / (ea() * q());
    println!(
        "slip work: loading {:.5e} (closed form {:.5e}), loop {:.5e} ({:.5e})",
        first,
        unit / 6.0,
        loop_,
        unit / 12.0
    );
    assert!((first / (unit / 6.0) - 1.0).abs() < 0.02, "{first}");
    assert!((loop_ / (unit / 12.0) - 1.0).abs() < 0.02, "{loop_}");
    assert!(path_steps
        .iter()
        .all(|s| s.observed.dissipated.unwrap() > -1e-6 * unit));
    let applied: Vec<f64> = path_steps
        .iter()
        .map(|s| {
            s.observed
                .faces
                .iter()
                .find(|f| f.on == "pile_head")
                .unwrap()
                .applied
                .unwrap()
        })
        .collect();
    for (i, (stage, lambda, _)) in path.iter().enumerate() {
        let expected = if stage == "unload" {
            p * (1.0 - lambda)
        } else {
            p * lambda
        };
        assert!(
            (applied[i] - expected).abs() < 1e-12 * p,
            "{stage} {lambda}: {}",
            applied[i]
        );
    }
    // The loop closes: reloaded to the same pull, the same displacement.
    let (load_end, reload_end) = (path[3].2, path[11].2);
    assert!(
        (reload_end - load_end).abs() < 1e-3 * w_max,
        "{load_end} vs {reload_end}"
    );
    // Outputs at the end: the final loads and their displacements.
    let d = face_displacement(&run.problem.model.mesh, "pile_head", &run.displacements).unwrap();
    assert!((d[2] - reload_end).abs() < 1e-12 * w_max);
}

#[test]
fn below_the_capacity_nothing_slips_and_nothing_stays() {
    let p = 0.04;
    let scene = rod(
        json!([
            {"name": "load", "loads": pull(p), "loading": {"steps": 2}},
            {"name": "unload", "loads": [], "loading": {"steps": 2}}
        ]),
        // Bonded to the rigid sleeve the rod's shear peaks at its head far
        // above the mean 0.006 MPa: a cohesion that never yields.
        1.0e5 * C,
    );
    let run = solve(&scene);
    let path = run.load_path.as_ref().unwrap();
    // The shaft never slips. (The base, with no strength at all, counts
    // its round-off shear at zero load as slip.)
    for s in &path.steps {
        let shaft = s.observed.joints.iter().find(|j| j.joint == "pile_side").unwrap();
        assert_eq!(shaft.slip, 0.0, "the shaft slipped at lambda {}", s.lambda);
    }
    let w_max = head_path(&run)[1].2;
    let d = face_displacement(&run.problem.model.mesh, "pile_head", &run.displacements).unwrap();
    println!("elastic: w_max {w_max:.4e}, after unloading {:.2e}", d[2]);
    // Nothing stays but round-off: the strengthless base slips under its
    // round-off shear at zero load, and its released force leaves about
    // 2e-16 m (1e-10 w_max; 2.06e-16 or 2.16e-16 with the order of the
    // Krylov dot products' sums).
    assert!(w_max > 0.0 && d[2].abs() < 1e-9 * w_max, "{} of {w_max}", d[2]);
}

#[test]
fn a_stage_beyond_the_capacity_stops_in_it_at_its_limit() {
    let capacity = q() * 10.0; // the shaft's; the base carries no tension
    let scene = rod(
        json!([
            {"name": "half", "loads": pull(0.5 * capacity)},
            {"name": "overload", "loads": pull(1.5 * capacity)}
        ]),
        C,
    );
    let run = solve(&scene);
    let path = run.load_path.as_ref().unwrap();
    let limit = path.limit.as_ref().expect("a limit");
    let stop = path.stopped_in.as_ref().expect("the stage it stopped in");
    assert_eq!(stop.stage, "overload");
    // 0.5 + 1.0 lambda = 1: lambda = 0.5.
    println!(
        "limit factor {:.4} in stage {}: {}",
        limit.factor, stop.stage, limit.reason
    );
    assert!((limit.factor - 0.5).abs() < 0.01, "{}", limit.factor);
    assert_eq!(path.reached(), 1.0);
    // The run's loads are those applied at the stop: the capacity.
    let r = axijoint_solver::loads::load_resultants(&run.loads, &run.problem.model.mesh, 0.0);
    assert!((r.force[2] / capacity - 1.0).abs() < 0.01, "{}", r.force[2]);
    assert!(
        (run.applied.force[2] - r.force[2]).abs() < 1e-12 * capacity,
        "{:?}",
        run.applied
    );
}

#[test]
fn a_cyclic_stage_runs_its_levels_and_closes_its_loop() {
    let p = 0.04;
    let scene = rod(
        json!([
            {"name": "cycles", "cyclic": {"loads": pull(p), "levels": [1, 0], "cycles": 3}, "loading": {"steps": 2}}
        ]),
        C,
    );
    let legs = scene.legs();
    assert_eq!(legs.len(), 6);
    assert_eq!((legs[3].cycle, legs[3].level), (2, 2));
    let run = solve(&scene);
    let path = head_path(&run);
    assert_eq!(path.len(), 12);
    // Every peak and every trough the same after the first loading: Masing
    // (the second unloading and reloading follow the first).
    let w_max = f(p);
    let peaks: Vec<f64> = [1, 5, 9].iter().map(|&i| path[i].2).collect();
    let troughs: Vec<f64> = [3, 7, 11].iter().map(|&i| path[i].2).collect();
    println!("peaks {peaks:?}, troughs {troughs:?}");
    // (Measured: 4.7e-5 w_max more each cycle, the same at epsilon 1e-6,
    // 1e-8 and 1e-10: the discrete model's creep, not the iteration's, as
    // shaft points with almost no normal stress open and close; 1.9e-4 on
    // the Lobatto rule, docs/stability.md.)
    for w in &peaks[1..] {
        assert!((w - peaks[0]).abs() < 2e-4 * w_max);
    }
    for w in &troughs[1..] {
        assert!((w - troughs[0]).abs() < 2e-4 * w_max);
    }
    assert!((troughs[0] / w_max - 0.5).abs() < 0.02);
}

/// The shipped pile in soil: a dead load, then the lateral load beside it,
/// against both at once.
fn pile(staged: bool, cohesion: f64) -> Run {
    let text = std::fs::read_to_string(geo("pile_soil.json")).unwrap();
    let mut s: Value = serde_json::from_str(&text).unwrap();
    for j in ["pile_side", "pile_base"] {
        s["joints"][j]["law"]["cohesion"] = json!(cohesion);
    }
    s["outputs"] = json!({"csv": false, "plots": false, "vtu": false, "gmsh_views": false});
    let both = json!([{"type": "resultant", "on": "pile_head", "force": [0.1, 0, -0.3]}]);
    if staged {
        s.as_object_mut().unwrap().remove("loads");
        s["stages"] = json!([
            {"name": "dead", "loads": [{"type": "resultant", "on": "pile_head", "force": [0, 0, -0.3]}]},
            {"name": "lateral", "loads": both}
        ]);
    } else {
        s["loads"] = both;
    }
    let scene = Scene::from_str(&s.to_string(), geo("pile_soil.json")).unwrap();
    solve(&scene)
}

#[test]
fn a_dead_load_first_differs_where_the_shaft_slips_only() {
    let head =
        |run: &Run| face_displacement(&run.problem.model.mesh, "pile_head", &run.displacements).unwrap();
    let change = |a: [f64; 3], b: [f64; 3]| {
        let size = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        a.iter().zip(&b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / size
    };
    // Cohesion 10 MPa: nothing slips, the path does not matter.
    let (s, p) = (pile(true, 10.0), pile(false, 10.0));
    assert!(s.load_path.as_ref().unwrap().steps.iter().all(|x| x.slip == 0));
    let same = change(head(&s), head(&p));
    // Cohesion 0.002 MPa: the shaft slips under the dead load, and the
    // lateral load then meets a shaft already slipping.
    let (s, p) = (pile(true, 0.002), pile(false, 0.002));
    let different = change(head(&s), head(&p));
    println!(
        "head displacement, staged against proportional: {same:.2e} (elastic), {different:.3} (slipping)"
    );
    // Equal to the iteration's tolerance (epsilon 1e-6; measured 1e-8).
    assert!(same < 1e-6, "{same}");
    assert!(different > 0.01, "{different}");
}

#[test]
fn mistakes_in_stages_are_refused_naming_the_stage() {
    let base = |stages: Value, extra: &[(&str, Value)]| -> String {
        let mut s = json!({
            "mesh": {"file": geo("pile_soil.geo"), "parameters": {"a": A, "size": 0.5, "coarsen": 8}},
            "materials": {"pile": {"E": E, "nu": 0.0}, "soil": {"E": 3.0e7, "nu": 0.3}},
            "joints": {"pile_side": {"stiffness": "rigid", "law": {"type": "mohr_coulomb", "cohesion": C, "friction_deg": 0}}},
            "supports": [{"on": "soil_outer", "fix": "all"}],
            "stages": stages,
            "harmonics": 0
        });
        for (k, v) in extra {
            s[*k] = v.clone();
        }
        let scene = match Scene::from_str(&s.to_string(), geo("stages_bad.json")) {
            Ok(scene) => scene,
            Err(e) => return e.to_string(),
        };
        match solve_scene(&scene, None, |_| {}) {
            Ok(_) => "accepted".into(),
            Err(e) => e.error.to_string(),
        }
    };
    let one = json!([{"name": "a", "loads": pull(0.01)}]);
    let cases = [
        (base(one.clone(), &[("loads", pull(0.01))]), "give either `loads` (one stage) or `stages`"),
        (
            base(one.clone(), &[("solver", json!({"loading": "one_shot"}))]),
            "solver.loading: stages are stepped",
        ),
        (base(json!([{"name": "a b", "loads": []}]), &[]), "stages[0].name: 'a b' is not allowed"),
        (
            base(json!([{"name": "a", "loads": []}, {"name": "a", "loads": []}]), &[]),
            "stages[1].name: 'a' is used twice",
        ),
        (
            base(json!([{"name": "a", "cyclic": {"loads": pull(0.01), "levels": []}}]), &[]),
            "stages[0].cyclic.levels",
        ),
        (
            base(json!([{"name": "a", "cyclic": {"loads": pull(0.01), "levels": [1, -1], "cycles": 6000}}]), &[]),
            "12000 stages and levels in all, more than 10000",
        ),
        (
            base(json!([{"name": "a", "loads": []}, {"name": "b", "loads": [{"type": "resultant", "on": "pile_haed", "force": [0, 0, 1]}]}]), &[]),
            "stages[1].loads[0].on: the mesh has no physical curve named 'pile_haed'; did you mean 'pile_head'?",
        ),
        (
            base(json!([{"name": "a", "loads": [{"type": "resultant", "on": "pile_head", "force": [0, 0]}]}]), &[]),
            "stages[0].loads[0].force",
        ),
        (
            base(json!([{"name": "a", "loads": [{"type": "motion", "on": "soil_outer", "displacement": [0, 0, 0.01]}]}]), &[]),
            "supports[0].on: 'soil_outer' is moved by a `motion` load",
        ),
        (
            base(
                json!([
                    {"name": "a", "loads": [{"type": "motion", "on": "pile_head", "displacement": [0, 0, 0.001]}]},
                    {"name": "b", "loads": pull(0.01)}
                ]),
                &[],
            ),
            "stages[1].loads[0].on: 'pile_head' is held in z by a `motion` load elsewhere",
        ),
        (
            base(json!([{"name": "a", "loads": [{"type": "motion", "on": "pile_head", "force": [0, 0, 1]}]}]), &[]),
            "key `force` does not belong to a motion load (it takes: type, on, displacement, rotation, at_z, hold)",
        ),
        (
            base(json!([{"name": "a", "loads": [{"type": "motion", "on": "pile_head", "displacement": [0, 1]}]}]), &[]),
            "stages[0].loads[0].displacement: 2 numbers given, give three: [ux, uy, uz]",
        ),
        (
            base(json!([{"name": "a", "loads": [{"type": "motion", "on": "pile_head", "displacement": [0.001, 0, 0]}]}]), &[]),
            "the load has a part of harmonic 1 but `harmonics` is 0",
        ),
    ];
    for (message, expected) in cases {
        assert!(message.contains(expected), "expected '{expected}' in: {message}");
    }
}

/// The twist of a rigid block on a cohesive Winkler joint (stiffness
/// `k`, strength `c`, radius `a`) under a torque `t >= 0` from rest:
/// elastic, `t / (k pi a^4 / 2)`, up to `t = pi c a^3 / 2` (the rim at `c`);
/// beyond, the stick radius `r_s` from `t = 2 pi c (a^3 / 3 - r_s^3 / 12)`
/// and the twist `c / (k r_s)`.
fn virgin_twist(t: f64, c: f64, k: f64, a: f64) -> f64 {
    if t <= PI * c * a.powi(3) / 2.0 {
        return t / (k * PI * a.powi(4) / 2.0);
    }
    let rs = (12.0 * (a.powi(3) / 3.0 - t / (2.0 * PI * c))).cbrt();
    c / (k * rs)
}

/// geo/block_torsion.json in two stages: its compression, then beside it
/// a torque `t` cycled at `levels`.
fn twisted(t: f64, levels: &[f64], cycles: u32) -> Scene {
    let text = std::fs::read_to_string(geo("block_torsion.json")).unwrap();
    let mut s: Value = serde_json::from_str(&text).unwrap();
    s.as_object_mut().unwrap().remove("loads");
    s["solver"] = json!({"method": "newton", "epsilon": 1e-8});
    let dead = json!({"type": "resultant", "on": "block_top", "force": [0, 0, -0.1]});
    s["stages"] = json!([
        {"name": "dead", "loads": [dead]},
        {"name": "twist", "loads": [dead],
         "cyclic": {"loads": [{"type": "resultant", "on": "block_top", "force": [0, 0, 0], "torque": t}], "levels": levels, "cycles": cycles},
         "loading": {"steps": 4}}
    ]);
    Scene::from_str(&s.to_string(), geo("block_torsion.json")).unwrap()
}

#[test]
fn a_twisted_block_reversed_follows_masing() {
    // geo/block_torsion.json: a = 0.5, C = 0.1, k_theta = 100, a constant
    // compression; the torque cycled between +-0.8 T_max (each point's
    // reversal range 2 C: Masing holds, the loop is symmetric).
    let (a, c, k): (f64, f64, f64) = (0.5, 0.1, 100.0);
    let t_max = 2.0 * PI * c * a.powi(3) / 3.0;
    let t1 = 0.8 * t_max;
    let run = solve(&twisted(t1, &[1.0, -1.0], 2));
    let steps = &run.load_path.as_ref().unwrap().steps;
    let beta1 = virgin_twist(t1, c, k, a);
    let mut worst = 0.0f64;
    let mut peak = (0.0, 0.0); // (torque, twist) at the last reversal
    for st in steps {
        let mark = st.observed.stage.as_ref().unwrap();
        if mark.stage == "dead" {
            continue;
        }
        let target = if mark.level == 1 { t1 } else { -t1 };
        let start = if mark.cycle == 1 && mark.level == 1 {
            0.0
        } else {
            -target
        };
        let t = start + st.lambda * (target - start);
        let beta = st.observed.faces[0].rotation;
        // The face's applied load is the cycling torque.
        assert!((st.observed.faces[0].applied.unwrap() - t).abs() < 1e-12 * t1);
        let expected = if mark.cycle == 1 && mark.level == 1 {
            virgin_twist(t, c, k, a)
        } else {
            // Masing from the last reversal (the peak before).
            let d = peak.0 - t;
            peak.1 - d.signum() * 2.0 * virgin_twist(d.abs() / 2.0, c, k, a)
        };
        let e = (beta - expected) / beta1;
        println!(
            "cycle {} level {} T {t:+.5}: twist {beta:+.5e}, Masing {expected:+.5e} ({:+.2} %)",
            mark.cycle,
            mark.level,
            100.0 * e
        );
        worst = worst.max(e.abs());
        if st.lambda == 1.0 {
            peak = (t, beta);
        }
    }
    assert!(worst < 0.02, "worst {worst:.4} of the peak twist");
}

#[test]
fn a_block_twisted_past_first_slip_then_cycled_below_shakes_down() {
    // Loaded to 0.9 T_max (the rim annulus slips), then cycled between 0.5
    // and 0.9 T_max: a reversal of 0.4 T_max moves the rim's shear by less
    // than its range 2 C (elastic up to 1.5 T_max), so after the first
    // loading no cycle dissipates.
    let t_max = 2.0 * PI * 0.1 * 0.5f64.powi(3) / 3.0;
    let run = solve(&twisted(0.9 * t_max, &[1.0, 5.0 / 9.0, 1.0], 3));
    let steps = &run.load_path.as_ref().unwrap().steps;
    let work = |cycle: u32, level: u32| -> f64 {
        steps
            .iter()
            .filter(|s| {
                s.observed
                    .stage
                    .as_ref()
                    .is_some_and(|m| m.cycle == cycle && m.level == level)
            })
            .map(|s| s.observed.dissipated.unwrap())
            .sum()
    };
    let first = work(1, 1);
    let later: f64 = (1..=3)
        .flat_map(|c| (1..=3).map(move |l| (c, l)))
        .filter(|&cl| cl != (1, 1))
        .map(|(c, l)| work(c, l).abs())
        .sum();
    println!("slip work: first loading {first:.4e}, the cycles after {later:.2e}");
    assert!(first > 0.0);
    assert!(later < 1e-9 * first, "{later} after {first}");
}

/// geo/block_torsion.json's block on its base, the contact cohesive
/// (C = 0.1, phi = 0, a tensile strength that round-off never reaches),
/// its top face moved sideways by `stages`.
fn pushed(stages: Value) -> Scene {
    let text = std::fs::read_to_string(geo("block_torsion.json")).unwrap();
    let mut s: Value = serde_json::from_str(&text).unwrap();
    s.as_object_mut().unwrap().remove("loads");
    s["joints"]["contact"]["law"]["tensile_strength"] = json!(10.0);
    s["harmonics"] = json!(1);
    s["solver"] = json!({"method": "newton", "epsilon": 1e-8});
    s["stages"] = stages;
    Scene::from_str(&s.to_string(), geo("block_torsion.json")).unwrap()
}

fn push(u: f64) -> Value {
    json!([{"type": "motion", "on": "block_top", "displacement": [u, 0, 0]}])
}

#[test]
fn a_block_pushed_back_and_forth_past_sliding_draws_the_rectangular_loop() {
    // Rigid block on a joint of stiffness k over the area pi a^2 (K = k pi
    // a^2), strength C: sliding at Hs = C pi a^2 once u > Hs / K; moved
    // between +-u_max the force follows the parallelogram, and each cycle
    // dissipates 4 Hs (u_max - Hs / K).
    let (a, c, k) = (0.5f64, 0.1, 100.0);
    let (hs, stiffness) = (c * PI * a * a, k * PI * a * a);
    let u_max = 3.0 * hs / stiffness;
    let scene = pushed(json!([
        {"name": "push", "loads": push(u_max), "loading": {"steps": 6}},
        {"name": "cycles", "cyclic": {"loads": push(u_max), "levels": [-1, 1], "cycles": 2}, "loading": {"steps": 12}}
    ]));
    let run = solve(&scene);
    let path = run.load_path.as_ref().unwrap();
    assert!(path.limit.is_none(), "{:?}", path.limit);
    let mut worst = 0.0f64;
    let mut last_u = 0.0;
    for st in &path.steps {
        let face = &st.observed.faces[0];
        let (u, h) = (face.mean[0], face.applied.unwrap());
        // The parallelogram: the force follows K du from the last reversal,
        // capped at +-Hs.
        let moving_up = u >= last_u;
        let expected = if st.observed.stage.as_ref().unwrap().stage == "push" {
            (stiffness * u).min(hs)
        } else if moving_up {
            (-hs + stiffness * (u + u_max)).min(hs)
        } else {
            (hs - stiffness * (u_max - u)).max(-hs)
        };
        worst = worst.max((h - expected).abs() / hs);
        last_u = u;
    }
    println!("worst force error {:.3} % of Hs", 100.0 * worst);
    assert!(worst < 0.01, "{worst}");
    let stages = |cycle: u32| -> f64 {
        path.steps
            .iter()
            .filter(|s| s.observed.stage.as_ref().is_some_and(|m| m.cycle == cycle))
            .map(|s| s.observed.dissipated.unwrap())
            .sum()
    };
    let per_cycle = 4.0 * hs * (u_max - hs / stiffness);
    for cycle in [1, 2] {
        let w = stages(cycle);
        println!("cycle {cycle}: slip work {w:.5e}, closed form {per_cycle:.5e}");
        assert!((w / per_cycle - 1.0).abs() < 0.01, "cycle {cycle}: {w}");
    }
    // The moved face is where it was sent, and its reaction is reported.
    let top = face_displacement(&run.problem.model.mesh, "block_top", &run.displacements).unwrap();
    assert!((top[0] - u_max).abs() < 1e-12 * u_max, "{top:?}");
    let r = run
        .reactions
        .iter()
        .find(|r| r.on == "block_top")
        .expect("the moved face's reaction");
    assert!((r.force[0] / hs - 1.0).abs() < 0.01, "{:?}", r.force);
}

#[test]
fn a_moved_face_takes_the_rigid_motion_it_is_given() {
    // Twist and tilt of the block's top face about its centre: every node
    // of the face where the motion puts it (harmonic 0: u_theta = rz r;
    // harmonic 1 symmetric: u_z = -ry r, u_r = -u_theta = ry (z - z_c) = 0
    // on the face), the fitted rotation = rz.
    let (rz, ry) = (1e-3, 2e-4);
    let scene = pushed(json!([
        {"name": "turn", "loads": [{"type": "motion", "on": "block_top", "rotation": [0, ry, rz]}]}
    ]));
    let run = solve(&scene);
    let mesh = &run.problem.model.mesh;
    let nodes = axijoint_solver::run::support_nodes(mesh, "block_top");
    let h0 = run.displacements.harmonics.iter().find(|h| h.m == 0).unwrap();
    let h1 = run.displacements.harmonics.iter().find(|h| h.m == 1).unwrap();
    for &k in &nodes {
        let r = mesh.nodes[k][0];
        assert!(
            (h0.symmetric[3 * k + 2] - rz * r).abs() < 1e-15,
            "u_theta at r = {r}"
        );
        assert!((h1.symmetric[3 * k + 1] + ry * r).abs() < 1e-15, "u_z at r = {r}");
        assert!(h1.symmetric[3 * k].abs() < 1e-15 && h1.symmetric[3 * k + 2].abs() < 1e-15);
    }
    let face = &run
        .load_path
        .as_ref()
        .unwrap()
        .steps
        .last()
        .unwrap()
        .observed
        .faces[0];
    assert!((face.rotation - rz).abs() < 1e-12, "{}", face.rotation);
    // Its reaction: a torque and a moment about y, no force.
    let r = run.reactions.iter().find(|r| r.on == "block_top").unwrap();
    println!("turned face: reaction {:?} {:?}", r.force, r.moment);
    assert!(r.moment[2] > 0.0 && r.moment[1] > 0.0);
    // Below first slip the twist is elastic: T = k J rz, J = pi a^4 / 2
    // (a rigid block on the Winkler joint).
    let torque = 100.0 * PI * 0.5f64.powi(4) / 2.0 * rz;
    assert!(
        (r.moment[2] / torque - 1.0).abs() < 0.01,
        "{} vs {torque}",
        r.moment[2]
    );
}

/// A stiff rod (E = 3e8) in its rigid sleeve on a cohesive shaft joint of
/// stiffness `k` (both shear components), pulled by `p_frac` of the
/// shaft's strength and, beside the pull, twisted at its head (a `motion`
/// that holds r and theta and leaves z free) between `+-phi`, `cycles`
/// times, then turned back to 0 (the last stage without the twist).
fn ratchet(p_frac: f64, k: f64, phi: f64, cycles: u32) -> Scene {
    let law = |c: f64| json!({"type": "mohr_coulomb", "cohesion": c, "friction_deg": 0, "tensile_strength": 0, "shear_check": "resultant"});
    let pull = p_frac * C * 2.0 * PI * A * 10.0;
    let twist =
        |w: f64| json!({"type": "motion", "on": "pile_head", "rotation": [0, 0, w], "hold": ["r", "theta"]});
    let head = json!({"type": "resultant", "on": "pile_head", "force": [0, 0, pull]});
    let s = json!({
        "title": "a pulled rod twisted back and forth",
        "mesh": {"file": geo("pile_soil.geo"), "parameters": {"a": A, "size": 0.25, "coarsen": 8, "order": 2, "quads": 1}},
        "materials": {"pile": {"E": 3.0e8, "nu": 0.0}, "soil": {"E": 3.0e11, "nu": 0.3}},
        "joints": {
            "pile_side": {"bottom": "pile", "top": "soil", "k_xi": k, "k_eta": 1e3 * k, "k_theta": k, "law": law(C)},
            "pile_base": {"bottom": "pile", "top": "soil", "k_xi": k, "k_eta": 1e3 * k, "k_theta": k, "law": law(0.0)}
        },
        "supports": [{"on": "soil_outer", "fix": "all"}, {"on": "soil_bottom", "fix": "all"}],
        "stages": [
            {"name": "pull", "loads": [head], "loading": {"steps": 2}},
            {"name": "twist", "loads": [head, twist(phi)], "loading": {"steps": 3}},
            {"name": "cycles", "loads": [head], "cyclic": {"loads": [twist(phi)], "levels": [-1, 1], "cycles": cycles}, "loading": {"steps": 3}},
            {"name": "untwist", "loads": [head], "loading": {"steps": 3}}
        ],
        "harmonics": 0,
        "solver": {"method": "newton", "epsilon": 1e-9}
    });
    Scene::from_str(&s.to_string(), geo("stages_ratchet.json")).expect("scene")
}

#[test]
fn a_pulled_rod_twisted_back_and_forth_ratchets_out_by_the_closed_form() {
    // Every point of the shaft sees the same traction: the pull's
    // p = P / (2 pi a L) along the rod and, once the twist slips, the
    // rest of the strength s = sqrt(C^2 - p^2) around it. Slip runs along
    // the traction (the resultant check), so each reversal of the twist,
    // 2 a phi less the elastic 2 s / k, slides the rod out by p / s times
    // the circumferential slip: per cycle `4 (p / s) (a phi - s / k)`.
    let (p_frac, k) = (0.6, 80.0);
    let (p, s) = (p_frac * C, C * (1.0 - p_frac * p_frac).sqrt());
    let phi = 3.0 * s / k / A;
    let cycles = 3;
    let run = solve(&ratchet(p_frac, k, phi, cycles));
    let path = head_path(&run);
    assert_eq!(path.len(), 2 + 3 + 6 * cycles as usize + 3);
    // The last stage has no twist: the sections are still the full turn's
    // (a half set has no torsion).
    let sections = &run.outcome.as_ref().unwrap().field.sections;
    assert!(!sections.half, "{} sections over the half turn", sections.len());
    let slide = |travel: f64| (p / s) * (travel - 2.0 * s / k).max(0.0);
    // At the end of each leg: pulled, twisted to +phi, then each level.
    let mut expected = vec![p / k, p / k + slide(A * phi + s / k)];
    for _ in 0..2 * cycles {
        let last = *expected.last().unwrap();
        expected.push(last + slide(2.0 * A * phi));
    }
    expected.push(expected.last().unwrap() + slide(A * phi));
    let ends: Vec<f64> = [1usize, 4]
        .into_iter()
        .chain((0..2 * cycles as usize + 1).map(|l| 7 + 3 * l))
        .map(|i| path[i].2)
        .collect();
    let per_cycle = 4.0 * (p / s) * (A * phi - s / k);
    for (i, (w, e)) in ends.iter().zip(&expected).enumerate() {
        println!(
            "leg end {i}: head uz {w:.6e}, closed form {e:.6e} ({:+.3} % of a cycle's growth)",
            100.0 * (w - e) / per_cycle
        );
        assert!((w - e).abs() < 0.01 * per_cycle, "leg end {i}: {w} vs {e}");
    }
    // The growth per cycle: the same every cycle, the closed form.
    for c in 1..cycles as usize {
        let growth = ends[2 + 2 * c + 1] - ends[2 * c + 1];
        println!("cycle {c}: growth {growth:.6e}, closed form {per_cycle:.6e}");
        assert!(
            (growth / per_cycle - 1.0).abs() < 0.01,
            "cycle {c}: {growth} vs {per_cycle}"
        );
    }
}

#[test]
fn a_motion_and_a_load_on_one_face_must_not_meet_in_a_component() {
    let text = |hold: Value, force: [f64; 3]| {
        json!({
            "title": "held",
            "mesh": {"file": geo("pile_soil.geo"), "parameters": {"a": A, "size": 0.5, "coarsen": 8}},
            "materials": {"pile": {"E": 3.0e4, "nu": 0.0}, "soil": {"E": 3.0e7, "nu": 0.3}},
            "supports": [{"on": "soil_outer", "fix": "all"}],
            "harmonics": 1,
            "loads": [
                {"type": "motion", "on": "pile_head", "rotation": [0, 0, 1e-3], "hold": hold},
                {"type": "resultant", "on": "pile_head", "force": force}
            ]
        })
        .to_string()
    };
    let path = geo("held.json");
    let checked = |t: String| Scene::from_str(&t, &path).and_then(|s| s.check_values().map(|_| s));
    // z left free: an axial force may act there.
    if let Err(e) = checked(text(json!(["r", "theta"]), [0.0, 0.0, 1.0])) {
        panic!("{e}");
    }
    // Held in z, or a sideways force on a face held in r: refused, naming
    // the component.
    for (hold, force, comp) in [
        (json!("all"), [0.0, 0.0, 1.0], "z"),
        (json!(["r", "theta"]), [1.0, 0.0, 0.0], "r"),
    ] {
        let e = checked(text(hold, force)).unwrap_err().to_string();
        println!("{e}");
        assert!(
            e.contains("loads[1].on") && e.contains(&format!("held in {comp}")),
            "{e}"
        );
    }
    // A motion that moves its face only in free components: refused by the
    // run (it would prescribe nothing).
    let scene = checked(text(json!(["r", "z"]), [0.0, 0.0, 0.0]));
    let e = match scene {
        Ok(s) => solve_scene(&s, None, |_| {})
            .err()
            .expect("refused")
            .error
            .to_string(),
        Err(e) => e.to_string(),
    };
    println!("{e}");
    assert!(e.contains("hold") && e.contains("prescribes nothing"), "{e}");
}
