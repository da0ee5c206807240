//! Joint stiffness from physics (issue 25, item 2): `"stiffness": "rigid"`
//! and `{"thickness": t}` resolved on real gmsh meshes of `geo/`, the
//! bonded answer of a stuck rigid joint, and the mesh independence of
//! rigid joints against springs chosen from the mesh; the Gauss and
//! Lobatto rules on a rigid joint that opens and slips.
//!
//! Run with `--nocapture` to see the measured numbers
//! (docs/stability.md, "Which stiffness to choose").

use axijoint_mesh::Mesh;
use axijoint_solver::run::{
    build_model, face_displacement, joint_springs, max_displacement, mesh_scene, record, solve_scene, Run,
};
use axijoint_solver::scene::{
    JointLaw, JointStiffness, MohrCoulomb, Scene, SpringSource, StiffnessSpec, RIGID_STIFFNESS,
};
use std::path::PathBuf;
use std::sync::{Mutex, MutexGuard};
use std::time::Instant;

/// One solve at a time: the run times below are measured.
fn serial() -> MutexGuard<'static, ()> {
    static LOCK: Mutex<()> = Mutex::new(());
    LOCK.lock().unwrap_or_else(|p| p.into_inner())
}

fn scene(name: &str) -> Scene {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../geo")
        .join(name);
    Scene::from_path(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// Every joint of `sc` with `law` and the stiffness `spec` (its springs removed).
fn with_joints(mut sc: Scene, law: JointLaw, spec: Option<StiffnessSpec>) -> Scene {
    for j in sc.joints.values_mut() {
        (j.k_xi, j.k_eta, j.k_theta) = (None, None, None);
        j.stiffness = spec;
        j.law = law;
    }
    sc
}

fn solve(sc: &Scene) -> Run {
    solve_scene(sc, None, |_| {}).unwrap_or_else(|e| panic!("{}: {}", sc.title, e.error))
}

/// The mean displacement `(ux, uy, uz)` of face `curve`.
fn face(run: &Run, curve: &str) -> [f64; 3] {
    face_displacement(&run.problem.model.mesh, curve, &run.displacements).expect("face")
}

fn max_u(run: &Run) -> f64 {
    max_displacement(run.problem.model.mesh.nodes.len(), &run.displacements)
}

fn sci(v: [f64; 3]) -> String {
    format!("({:.6e}, {:.6e}, {:.6e})", v[0], v[1], v[2])
}

/// `|a - b| / |b|` of two vectors.
fn rel(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d: f64 = a.iter().zip(&b).map(|(x, y)| (x - y) * (x - y)).sum();
    let n: f64 = b.iter().map(|y| y * y).sum();
    (d / n).sqrt()
}

/// The shortest joint element of `mesh`'s joint `name`, measured here
/// from its end nodes.
fn shortest(mesh: &Mesh, name: &str) -> f64 {
    let j = mesh.joints.iter().find(|j| j.name == name).expect("joint");
    let mut h = f64::INFINITY;
    for e in &j.elements {
        let (a, b) = (mesh.nodes[e.bottom[0]], mesh.nodes[e.bottom[1]]);
        h = h.min(((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt());
    }
    h
}

fn close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 1e-12 * want.abs(),
        "{what}: {got:e} against the closed form {want:e}"
    );
}

/// `"rigid"` and `{"thickness": t}` on the pile in soil (`geo/pile_soil.geo`,
/// meshed by gmsh): the springs are `1000 E_soil / h_min` and `E_oed / t`,
/// `G / t` of the soil (the softer body) to 1e-12, resolved once in the
/// model and reported in the run record with their source.
#[test]
fn rigid_and_thickness_springs_are_their_closed_forms_on_a_meshed_geo() {
    let _guard = serial();
    let base = scene("pile_soil.json");
    let (e, nu) = (50.0, 0.3); // the soil: E = 50 MPa, nu = 0.3 (the pile: 3e4)
    assert_eq!((base.materials["soil"].e, base.materials["soil"].nu), (e, nu));
    let e_oed = e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)); // 67.3077 MPa
    let g = e / (2.0 * (1.0 + nu)); // 19.2308 MPa
    let t = 0.1;
    let rigid = with_joints(base.clone(), JointLaw::Linear, Some(StiffnessSpec::Rigid));
    let (mesh, _) = mesh_scene(&rigid, None).expect("gmsh meshes the pile in soil");
    let materials: Vec<_> = mesh
        .bodies
        .iter()
        .map(|b| rigid.materials[&b.name].elastic())
        .collect();
    let layer = with_joints(base.clone(), JointLaw::Linear, Some(StiffnessSpec::Thickness(t)));
    let default = with_joints(base.clone(), JointLaw::Linear, None);
    for j in &mesh.joints {
        let h = shortest(&mesh, &j.name);
        close(j.min_length(&mesh.nodes), h, "min_length");
        assert!(h > 0.0 && h <= j.mean_length(&mesh.nodes) * (1.0 + 1e-12));
        for sc in [&rigid, &default] {
            let k = joint_springs(sc, &mesh, j, &materials).unwrap();
            let want = 1000.0 * e / h;
            for got in [k.k_xi, k.k_eta, k.k_theta] {
                close(got, want, &format!("{} rigid", j.name));
            }
        }
        let k = joint_springs(&layer, &mesh, j, &materials).unwrap();
        close(k.k_eta, e_oed / t, &format!("{} k_eta of the layer", j.name));
        close(k.k_xi, g / t, &format!("{} k_xi of the layer", j.name));
        close(k.k_theta, g / t, &format!("{} k_theta of the layer", j.name));
        println!(
            "{}: h_min {h:.6} m, rigid k = {:.6e} MPa/m; layer t = {t}: k_eta = {:.6e}, k_xi = k_theta = {:.6e}",
            j.name,
            1000.0 * e / h,
            e_oed / t,
            g / t
        );
    }
    assert_eq!(RIGID_STIFFNESS, 1000.0);
    // The given springs pass through unchanged.
    let given = joint_springs(&base, &mesh, &mesh.joints[0], &materials).unwrap();
    assert_eq!(
        JointStiffness::Given(given),
        base.joints[&mesh.joints[0].name].stiffness().unwrap()
    );
    // The model assembles the resolved springs, and the record names them.
    let model = build_model(&layer, mesh.clone()).unwrap();
    for (j, m) in mesh.joints.iter().zip(&model.joints) {
        assert_eq!(m.springs, joint_springs(&layer, &mesh, j, &materials).unwrap());
    }
    let run = solve(&rigid);
    let r = record(&rigid, &run).expect("a run with joints has a record");
    assert_eq!(r.joint_springs.len(), 2);
    for j in &mesh.joints {
        let k = &r.joint_springs[&j.name];
        assert_eq!(k.source, SpringSource::Rigid);
        close(k.k_eta, 1000.0 * e / shortest(&mesh, &j.name), "recorded k_eta");
    }
    let text = serde_json::to_string(&r).unwrap();
    assert!(
        text.contains(r#""joint_springs":{"pile_base":{"k_xi":"#),
        "{text}"
    );
    assert!(text.contains(r#""source":"rigid""#), "{text}");
}

/// (i) Scene P with a linear rigid joint against the bonded Scene P
/// (`geo/pile_footing_bonded.json`, the same mesh): the pile end's mean
/// displacement and max |u| within 1e-3.
#[test]
fn a_linear_rigid_joint_gives_the_bonded_scene_p() {
    let _guard = serial();
    let rigid = with_joints(
        scene("pile_footing.json"),
        JointLaw::Linear,
        Some(StiffnessSpec::Rigid),
    );
    let bonded = scene("pile_footing_bonded.json");
    assert_eq!(rigid.mesh, bonded.mesh);
    let (a, b) = (solve(&rigid), solve(&bonded));
    let (end_a, end_b) = (face(&a, "pile_end"), face(&b, "pile_end"));
    let end = rel(end_a, end_b);
    let max = (max_u(&a) - max_u(&b)).abs() / max_u(&b);
    println!(
        "Scene P rigid vs bonded: pile end {} vs {} ({end:.2e}), max |u| {:.6e} vs {:.6e} ({max:.2e})",
        sci(end_a),
        sci(end_b),
        max_u(&a),
        max_u(&b)
    );
    assert!(end < 1e-3, "pile end: {end:.3e}");
    assert!(max < 1e-3, "max |u|: {max:.3e}");
}

/// (ii) The pile in soil with linear rigid joints against the same scene
/// without joints (bonded): the head displacement within 1e-3.
#[test]
fn linear_rigid_joints_give_the_bonded_pile_in_soil() {
    let _guard = serial();
    let base = scene("pile_soil.json");
    let rigid = with_joints(base.clone(), JointLaw::Linear, Some(StiffnessSpec::Rigid));
    let mut bonded = base;
    bonded.joints.clear();
    let (a, b) = (solve(&rigid), solve(&bonded));
    let (head_a, head_b) = (face(&a, "pile_head"), face(&b, "pile_head"));
    let head = rel(head_a, head_b);
    let (dx, dz) = (
        (head_a[0] - head_b[0]).abs() / head_b[0].abs(),
        (head_a[2] - head_b[2]).abs() / head_b[2].abs(),
    );
    println!(
        "pile in soil rigid vs bonded: head {} vs {} ({head:.2e}; lateral {dx:.2e}, axial {dz:.2e})",
        sci(head_a),
        sci(head_b)
    );
    assert!(head < 1e-3, "head: {head:.3e}");
    assert!(dx < 1e-3 && dz < 1e-3, "lateral {dx:.3e}, axial {dz:.3e}");
    // The difference is the penalty's, about E / (k L): ten times the
    // rigid springs, given, leave about a tenth of it.
    let k = 10.0 * a.problem.model.joints[0].springs.k_eta;
    let mut stiffer = rigid.clone();
    for j in stiffer.joints.values_mut() {
        j.stiffness = None;
        (j.k_xi, j.k_eta, j.k_theta) = (Some(k), Some(k), Some(k));
    }
    let c = solve(&stiffer);
    let head_10 = rel(face(&c, "pile_head"), head_b);
    println!(
        "  with 10 x the rigid springs ({k:.3e} MPa/m): {head_10:.2e} ({:.1} times less)",
        head / head_10
    );
    assert!(head_10 < 0.2 * head, "{head_10:.3e} against {head:.3e}");
}

/// (iii) The pile in soil with its Mohr-Coulomb joints made rigid and so
/// strong that nothing yields (C = 1e4 MPa, tensile strength 1e3 MPa),
/// through the nonlinear iteration (Newton, stepped, the traction form):
/// the bonded head displacement within 1e-3, nothing open or slipping.
#[test]
fn a_rigid_mohr_coulomb_joint_that_never_yields_gives_the_bonded_pile_in_soil() {
    let _guard = serial();
    let base = scene("pile_soil.json");
    let law = JointLaw::MohrCoulomb(MohrCoulomb {
        cohesion: 1e4,
        tensile_strength: 1e3,
        ..match base.joints["pile_side"].law {
            JointLaw::MohrCoulomb(mc) => mc,
            JointLaw::Linear => panic!("pile_soil.json has Mohr-Coulomb joints"),
        }
    });
    let rigid = with_joints(base.clone(), law, Some(StiffnessSpec::Rigid));
    let mut bonded = base;
    bonded.joints.clear();
    let b = solve(&bonded);
    let t = Instant::now();
    let a = solve(&rigid);
    let seconds = t.elapsed().as_secs_f64();
    let outcome = a.outcome.as_ref().expect("the nonlinear iteration ran");
    let last = outcome.history.last().expect("a history");
    assert_eq!((last.open, last.slip), (0, 0), "nothing yields");
    let (head_a, head_b) = (face(&a, "pile_head"), face(&b, "pile_head"));
    let head = rel(head_a, head_b);
    let softened = a.problem.model.joints.iter().all(|j| j.assembled != j.springs);
    println!(
        "pile in soil, rigid Mohr-Coulomb (never yields) vs bonded: head {} vs {} ({head:.2e}); {} iterations, {seconds:.1} s, assembled with the softer reference: {softened}",
        sci(head_a),
        sci(head_b),
        outcome.history.len()
    );
    assert!(softened, "a rigid nonlinear joint is solved by the traction form");
    assert!(head < 1e-3, "head: {head:.3e}");
}

/// The pile in soil with gravity (`geo/pile_soil_gravity.json`), linear
/// joints, at size 0.25 and 0.125: the head's lateral and axial
/// displacement with rigid joints moves by less than 0.5 %, and more with
/// springs chosen from the mesh (k h / E_soil = 1 on each mesh: k doubles
/// as h halves); and with the scene's Mohr-Coulomb joints made rigid, less
/// than 0.5 % too.
#[test]
fn rigid_joints_are_mesh_independent_and_springs_from_the_mesh_are_not() {
    let _guard = serial();
    let base = scene("pile_soil_gravity.json");
    assert!(base.has_initial_phase());
    let e_soil = base.materials["soil"].e;
    let head = |sc: &Scene, size: f64| {
        let mut sc = sc.clone();
        sc.mesh.parameters.insert("size".into(), size);
        let t = Instant::now();
        let run = solve(&sc);
        let u = face(&run, "pile_head");
        println!(
            "  size {size}: head ux {:.6e}, uz {:.6e} m ({:.1} s, {} nodes)",
            u[0],
            u[2],
            t.elapsed().as_secs_f64(),
            run.problem.model.mesh.nodes.len()
        );
        u
    };
    let change =
        |a: [f64; 3], b: [f64; 3]| [(b[0] - a[0]).abs() / a[0].abs(), (b[2] - a[2]).abs() / a[2].abs()];
    println!("rigid joints:");
    let rigid = with_joints(base.clone(), JointLaw::Linear, Some(StiffnessSpec::Rigid));
    let r = change(head(&rigid, 0.25), head(&rigid, 0.125));
    println!("  change: lateral {:.3e}, axial {:.3e}", r[0], r[1]);
    // k h / E_soil = 1 on each mesh, h = `size` (the element length along
    // the joints, geo/pile_soil.json's description).
    let from_mesh = |size: f64| {
        let mut sc = with_joints(base.clone(), JointLaw::Linear, None);
        for j in sc.joints.values_mut() {
            j.stiffness = None;
            let k = e_soil / size;
            (j.k_xi, j.k_eta, j.k_theta) = (Some(k), Some(k), Some(k));
        }
        sc
    };
    println!("k h / E_soil = 1 on each mesh:");
    let m = change(head(&from_mesh(0.25), 0.25), head(&from_mesh(0.125), 0.125));
    println!("  change: lateral {:.3e}, axial {:.3e}", m[0], m[1]);
    println!("the same k = E_soil / 0.25 on both meshes:");
    let fixed = from_mesh(0.25);
    let f = change(head(&fixed, 0.25), head(&fixed, 0.125));
    println!("  change: lateral {:.3e}, axial {:.3e}", f[0], f[1]);
    assert!(r[0] < 5e-3 && r[1] < 5e-3, "rigid: {r:?}");
    assert!(m[0] > r[0] && m[1] > r[1], "from the mesh {m:?} vs rigid {r:?}");
    // The scene's own Mohr-Coulomb joints made rigid (Newton, stepped, the
    // traction form; the shaft carries its geostatic friction): measured
    // 3.7e-4 and 7.6e-4, 0.7 s and 4.9 s.
    println!("rigid Mohr-Coulomb joints:");
    let mut nonlinear = base.clone();
    for j in nonlinear.joints.values_mut() {
        (j.k_xi, j.k_eta, j.k_theta) = (None, None, None);
        j.stiffness = Some(StiffnessSpec::Rigid);
    }
    let n = change(head(&nonlinear, 0.25), head(&nonlinear, 0.125));
    println!("  change: lateral {:.3e}, axial {:.3e}", n[0], n[1]);
    assert!(n[0] < 5e-3 && n[1] < 5e-3, "rigid Mohr-Coulomb: {n:?}");
}

/// The pile in soil (`geo/pile_soil.json`, no gravity, 0.2 MN sideways)
/// with its Mohr-Coulomb joints made rigid, on the Gauss rule and on the
/// Lobatto rule (points at the nodes): both open and slip, and the head
/// displacement agrees within 5e-4 (the rules integrate the joint
/// differently; measured 4.8e-5). Lobatto's iteration is the cheaper one
/// here (docs/stability.md, "Why the traction form slows down as k
/// grows"); the answer must not depend on it.
#[test]
fn gauss_and_lobatto_rules_agree_on_a_rigid_joint_that_opens_and_slips() {
    use axijoint_solver::scene::RuleKind;
    let _guard = serial();
    let mut rigid = with_joints(
        scene("pile_soil.json"),
        scene("pile_soil.json").joints["pile_side"].law,
        Some(StiffnessSpec::Rigid),
    );
    // 0.2 MN sideways instead of 0.05: the shaft also slips.
    match &mut rigid.loads[0] {
        axijoint_solver::scene::Load::Resultant(l) => l.force[0] = 0.2,
        _ => panic!("pile_soil.json's load is a resultant"),
    }
    let on_rule = |rule: RuleKind| {
        let mut sc = rigid.clone();
        for j in sc.joints.values_mut() {
            j.rule = rule;
        }
        let t = Instant::now();
        let run = solve(&sc);
        let last = *run
            .outcome
            .as_ref()
            .expect("the nonlinear iteration ran")
            .history
            .last()
            .expect("a history");
        let u = face(&run, "pile_head");
        println!(
            "{rule:?}: head {}, {} open and {} slipping point-sections, {:.2} s",
            sci(u),
            last.open,
            last.slip,
            t.elapsed().as_secs_f64()
        );
        assert!(
            last.open > 0 && last.slip > 0,
            "{rule:?}: the joints open and slip"
        );
        u
    };
    let (gauss, lobatto) = (on_rule(RuleKind::Gauss), on_rule(RuleKind::Lobatto));
    let d = rel(lobatto, gauss);
    println!("Lobatto against Gauss: {d:.2e}");
    assert!(d < 5e-4, "the rules differ by {d:.3e}");
}
