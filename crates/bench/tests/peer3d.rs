//! The CalculiX 3D peer of Scene P, run for real with gmsh and ccx (each
//! test skips with a note when a tool is absent). Meshes are small: each
//! test takes well under a minute on two cores.

use axijoint_bench::peer3d::{self, load, model::Model3d, PeerOptions, PeerRun, PeerVariant};
use axijoint_bench::profile::{Profile, Sample};
use std::path::{Path, PathBuf};
use std::process::Command;

const H: f64 = 0.5;

fn tools() -> Option<(PathBuf, PathBuf)> {
    let ccx = PathBuf::from("/usr/bin/ccx");
    let gmsh = PathBuf::from("/usr/bin/gmsh");
    if !ccx.exists() || !gmsh.exists() {
        eprintln!("NOTE: skipping: /usr/bin/ccx or /usr/bin/gmsh is not installed");
        return None;
    }
    Some((ccx, gmsh))
}

fn options(size: f64, dir: &Path) -> Option<PeerOptions> {
    let (ccx, gmsh) = tools()?;
    Some(PeerOptions {
        size,
        work_dir: dir.to_path_buf(),
        ccx,
        gmsh,
    })
}

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The axijoint CLI: $AXIJOINT_BIN, $CARGO_TARGET_DIR/release/axijoint or
/// target/release/axijoint (build it with `cargo build --release -p
/// axijoint-cli`).
fn axijoint_bin() -> Option<PathBuf> {
    let mut c: Vec<PathBuf> = Vec::new();
    if let Ok(p) = std::env::var("AXIJOINT_BIN") {
        c.push(p.into());
    }
    if let Ok(t) = std::env::var("CARGO_TARGET_DIR") {
        c.push(Path::new(&t).join("release/axijoint"));
    }
    c.push(workspace().join("target/release/axijoint"));
    let found = c.into_iter().find(|p| p.exists());
    if found.is_none() {
        eprintln!("NOTE: skipping the axijoint comparison: no release build of axijoint-cli");
    }
    found
}

/// Scene P's JSON with the joint law replaced (None: the bonded scene),
/// written to `dir` with an absolute mesh path and a fine 2D mesh (size
/// 0.05, refine 2: its profiles are within ~0.3 % of the converged ones,
/// while the default size 0.25 is ~7 % off on b-b near the pile corner).
fn scene(dir: &Path, law: Option<serde_json::Value>) -> PathBuf {
    let name = if law.is_some() {
        "pile_footing.json"
    } else {
        "pile_footing_bonded.json"
    };
    let text = std::fs::read_to_string(workspace().join("geo").join(name)).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let geo = workspace().join("geo/pile_footing.geo").canonicalize().unwrap();
    v["mesh"]["file"] = serde_json::Value::String(geo.to_string_lossy().into_owned());
    v["mesh"]["parameters"]["size"] = serde_json::json!(0.05);
    if let Some(law) = law {
        v["joints"]["pile_side"]["law"] = law;
        v["harmonics"] = serde_json::json!(8);
        let sections: Vec<f64> = (0..=8).map(|k| 22.5 * k as f64).collect();
        v["sections"] = serde_json::json!({ "theta_deg": sections });
    }
    let path = dir.join("scene.json");
    std::fs::write(&path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    path
}

/// Runs axijoint on a scene and reads the four cut profiles.
fn axijoint_profiles(bin: &Path, scene: &Path, out: &Path) -> Vec<Profile> {
    let st = Command::new(bin)
        .arg("run")
        .arg(scene)
        .arg("-o")
        .arg(out)
        .arg("-q")
        .status()
        .unwrap();
    assert!(st.success(), "axijoint run {} failed", scene.display());
    let mut v = Vec::new();
    for (cut, component) in [("a-a", "sigma_z"), ("b-b", "sigma_r")] {
        for theta in [0.0, 180.0] {
            let path = out.join(format!("cut_{cut}_theta{theta}.csv"));
            v.push(read_cut(&path, cut, theta, component));
        }
    }
    v
}

fn read_cut(path: &Path, cut: &str, theta: f64, component: &str) -> Profile {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| h.starts_with(name)).unwrap();
    let (r, body, val) = (col("r ["), col("body"), col(&format!("{component} [")));
    let samples = lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            Sample {
                r: f[r].parse().unwrap(),
                body: f[body].to_string(),
                value: f[val].parse().unwrap(),
            }
        })
        .collect();
    Profile {
        cut: cut.into(),
        theta_deg: theta,
        component: component.into(),
        samples,
    }
}

fn find<'a>(v: &'a [Profile], cut: &str, theta: f64) -> &'a Profile {
    v.iter().find(|p| p.cut == cut && p.theta_deg == theta).unwrap()
}

/// Relative L2 differences peer vs axijoint of the four profiles.
fn differences(peer: &PeerRun, ax: &[Profile]) -> Vec<(String, f64)> {
    let mut d = Vec::new();
    for a in ax {
        let p = find(&peer.profiles, &a.cut, a.theta_deg);
        let e = peer3d::relative_l2(p, a).unwrap();
        d.push((format!("{} theta {}", a.cut, a.theta_deg), e));
    }
    d
}

#[test]
fn end_load_nodal_forces_are_consistent() {
    let dir = tempfile::tempdir().unwrap();
    let Some(opts) = options(0.2, dir.path()) else {
        return;
    };
    let msh = dir.path().join("m.msh");
    peer3d::mesh(&opts, &msh).unwrap();
    let model = Model3d::from_msh(&msh).unwrap();
    let end = load::end_load(&model);
    let (f, m) = load::resultant(&model, &end.forces, -1.5);
    // Resultant (H/2, 0, 0) and M_y of H/2 acting at z = -3 about (0, 0, -1.5).
    assert!((f[0] - H / 2.0).abs() <= 1e-10 * H / 2.0, "{f:?}");
    assert!(f[1].abs() <= 1e-12 && f[2].abs() <= 1e-10 * H / 2.0, "{f:?}");
    let my = -H / 2.0 * 1.5;
    assert!((m[1] - my).abs() <= 1e-10 * my.abs(), "{m:?}");
    // The half disc: M_x = 0 and M_z = -t_x * 2 a^3 / 3 of the continuous
    // tractions, up to the (small) asymmetry and faceting of the mesh.
    assert!(m[0].abs() < 1e-3 * my.abs(), "{m:?}");
    let mz = -H / (std::f64::consts::PI * 0.25) * 2.0 * 0.125 / 3.0;
    assert!((m[2] - mz).abs() < 1e-2 * mz.abs(), "{m:?} vs {mz}");
    // The same resultant about the load point: no moment left there.
    let (_, m3) = load::resultant(&model, &end.forces, -3.0);
    assert!(m3[1].abs() <= 1e-10 * my.abs(), "{m3:?}");
    // The discrete face is the half disc of radius 0.5.
    let half = std::f64::consts::PI * 0.25 / 2.0;
    assert!((end.area - half).abs() < 1e-2 * half, "{} vs {half}", end.area);
}

#[test]
fn frictionless_deck_is_coulombs_without_friction() {
    let dir = tempfile::tempdir().unwrap();
    let Some(opts) = options(0.3, dir.path()) else {
        return;
    };
    let msh = dir.path().join("m.msh");
    peer3d::mesh(&opts, &msh).unwrap();
    let model = Model3d::from_msh(&msh).unwrap();
    let end = load::end_load(&model);
    let coulomb = peer3d::deck::write_deck(&model, &end, PeerVariant::Coulomb);
    let frictionless = peer3d::deck::write_deck(&model, &end, PeerVariant::Frictionless);
    assert!(coulomb.contains("*FRICTION\n"));
    assert!(!frictionless.contains("*FRICTION"));
    let without: Vec<&str> = coulomb
        .lines()
        .skip(1)
        .filter(|l| !l.starts_with("*FRICTION") && !l.starts_with("0.577"))
        .collect();
    assert_eq!(without, frictionless.lines().skip(1).collect::<Vec<_>>());
}

#[test]
fn bonded_coarse_equilibrium_and_antisymmetry() {
    let dir = tempfile::tempdir().unwrap();
    let Some(opts) = options(0.2, dir.path()) else {
        return;
    };
    let (run, det) = peer3d::run_detailed(PeerVariant::Bonded, &opts).unwrap();
    eprintln!(
        "bonded size 0.2: {} nodes, {} elements, {} equations, ccx {:.1} s, RF {:?}",
        run.nodes, run.elements, run.dofs, run.cost.ccx_wall_seconds, det.reaction_total
    );
    // Global equilibrium: the reactions of r = 3 balance H/2 (the symmetry
    // plane takes only y forces).
    let rf = det.reaction_total;
    assert!((rf[0] + H / 2.0).abs() <= 1e-6 * H / 2.0, "{rf:?}");
    assert!(rf[2].abs() <= 1e-6 * H / 2.0, "{rf:?}");
    assert_eq!(run.profiles.len(), 4);
    assert_eq!(run.increments, 1);
    // Harmonic 1: sigma_z(theta = 180) = -sigma_z(theta = 0) on a-a.
    let p0 = find(&run.profiles, "a-a", 0.0);
    let p180 = find(&run.profiles, "a-a", 180.0);
    let neg = Profile {
        samples: p180
            .samples
            .iter()
            .map(|s| Sample {
                value: -s.value,
                ..s.clone()
            })
            .collect(),
        ..p180.clone()
    };
    let e = peer3d::relative_l2(&neg, p0).unwrap();
    assert!(e < 0.1, "a-a antisymmetry {e}");
    // Bonded: both bodies report r = 0.5 with nearly the same stress.
    for p in &run.profiles {
        let at = |b: &str| {
            p.samples
                .iter()
                .find(|s| s.r == 0.5 && s.body == b)
                .unwrap()
                .value
        };
        let scale = p.samples.iter().map(|s| s.value.abs()).fold(0.0, f64::max);
        assert!(
            (at("pile") - at("footing")).abs() < 0.35 * scale,
            "{} {}",
            p.cut,
            p.theta_deg
        );
    }
}

#[test]
fn coulomb_converges_and_opens_at_theta_pi() {
    let dir = tempfile::tempdir().unwrap();
    let Some(opts) = options(0.2, dir.path()) else {
        return;
    };
    let (run, det) = peer3d::run_detailed(PeerVariant::Coulomb, &opts).unwrap();
    eprintln!(
        "coulomb size 0.2: {} increments, {} iterations, ccx {:.1} s",
        run.increments, det.iterations, run.cost.ccx_wall_seconds
    );
    let rf = det.reaction_total;
    assert!((rf[0] + H / 2.0).abs() <= 1e-5 * H / 2.0, "{rf:?}");
    let plane: Vec<_> = det
        .contact
        .iter()
        .filter(|c| c.position[1].abs() < 1e-6)
        .collect();
    for c in &plane {
        eprintln!(
            "x {:+.2} z {:.3}: p {:+.4} gap {:+.3e} shear {:.4} slip {:.3e}",
            c.position[0], c.position[2], c.pressure, c.gap, c.shear, c.slip
        );
    }
    // theta = pi, upper part of the joint: open (gap > 0), no pressure.
    let top_back: Vec<_> = plane
        .iter()
        .filter(|c| c.position[0] < 0.0 && c.position[2] >= 0.5)
        .collect();
    assert!(!top_back.is_empty());
    for c in &top_back {
        assert!(
            c.pressure.abs() < 1e-9,
            "pressure {} at z {}",
            c.pressure,
            c.position[2]
        );
        assert!(c.gap > 0.0, "gap {} at z {}", c.gap, c.position[2]);
    }
    // theta = 0 at the footing bottom: the pile bears on the footing.
    let bearing = plane
        .iter()
        .find(|c| c.position[0] > 0.0 && c.position[2].abs() < 1e-9)
        .unwrap();
    assert!(bearing.pressure > 1.0 && bearing.gap < 0.0, "{bearing:?}");
    // Nowhere tension.
    assert!(det.contact.iter().all(|c| c.pressure >= -1e-9));
}

/// Runs the peer at size 0.1 and axijoint (fine 2D mesh) and compares.
fn agree_with_axijoint(variant: PeerVariant, law: Option<serde_json::Value>) {
    let Some(bin) = axijoint_bin() else { return };
    let dir = tempfile::tempdir().unwrap();
    let Some(opts) = options(0.1, dir.path()) else {
        return;
    };
    let sub = dir.path().join(variant.name());
    std::fs::create_dir_all(&sub).unwrap();
    let ax = axijoint_profiles(&bin, &scene(&sub, law), &sub.join("axijoint"));
    let (run, det) = peer3d::run_detailed(variant, &opts).unwrap();
    eprintln!(
        "{} size 0.1: {} nodes, {} equations, ccx {:.1} s wall {:.1} s CPU {:.0} MB, {} increments / {} iterations",
        variant.name(),
        run.nodes,
        run.dofs,
        run.cost.ccx_wall_seconds,
        run.cost.ccx_cpu_seconds,
        run.cost.ccx_peak_rss_bytes as f64 / 1e6,
        run.increments,
        det.iterations
    );
    // Measured at size 0.1: bonded 2.3 % (a-a) and 5.9 % (b-b), linear
    // 0.5 % and 1.7 %; bonded b-b falls to 2.5 % at size 0.06. b-b lies
    // 0.25 m above the re-entrant corner (r = 0.5, z = 0) where the
    // bonded stress is singular: 2-3 tetrahedra cover that distance at
    // size 0.1, and the joint springs soften the singularity.
    let tol = if variant == PeerVariant::Bonded {
        0.08
    } else {
        0.04
    };
    for (what, e) in differences(&run, &ax) {
        eprintln!("  {what}: relative L2 difference {:.2} %", 100.0 * e);
        assert!(e < tol, "{} {what}: {e}", variant.name());
    }
    if variant == PeerVariant::Linear {
        // Tied contact carries tension: somewhere the pressure is < 0.
        assert!(
            det.contact.iter().any(|c| c.pressure < -0.05),
            "no tension in the tied joint"
        );
    }
}

#[test]
fn bonded_agrees_with_axijoint() {
    agree_with_axijoint(PeerVariant::Bonded, None);
}

#[test]
fn linear_agrees_with_axijoint() {
    agree_with_axijoint(PeerVariant::Linear, Some(serde_json::json!({"type": "linear"})));
}

/// The study of the report: sizes x variants with costs and differences
/// against axijoint. Slow (minutes): `cargo test -p axijoint-bench --test
/// peer3d study -- --ignored --nocapture`; sizes from $PEER3D_SIZES
/// (default "0.2,0.1,0.06").
#[test]
#[ignore]
fn study() {
    let Some(bin) = axijoint_bin() else { return };
    let dir = std::env::var("PEER3D_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| std::env::temp_dir().join("peer3d-study"));
    let sizes: Vec<f64> = std::env::var("PEER3D_SIZES")
        .unwrap_or_else(|_| "0.2,0.1,0.06".into())
        .split(',')
        .map(|s| s.trim().parse().unwrap())
        .collect();
    let coulomb = serde_json::json!({"type": "mohr_coulomb", "cohesion": 0, "friction_deg": 30, "tensile_strength": 0, "shear_check": "resultant"});
    for (variant, law) in [
        (PeerVariant::Bonded, None),
        (PeerVariant::Linear, Some(serde_json::json!({"type": "linear"}))),
        (PeerVariant::Coulomb, Some(coulomb)),
    ] {
        let only = std::env::var("PEER3D_VARIANTS").unwrap_or_else(|_| "bonded,linear,coulomb".into());
        if !only.split(',').any(|v| v == variant.name()) {
            continue;
        }
        let sub = dir.join(variant.name());
        std::fs::create_dir_all(&sub).unwrap();
        let ax = axijoint_profiles(&bin, &scene(&sub, law), &sub.join("axijoint"));
        for &size in &sizes {
            let Some(opts) = options(size, &sub) else { return };
            let (run, det) = peer3d::run_detailed(variant, &opts).unwrap();
            for p in &run.profiles {
                let mut csv = String::from("r,body,value\n");
                for s in &p.samples {
                    csv += &format!("{},{},{}\n", s.r, s.body, s.value);
                }
                std::fs::write(
                    sub.join(format!("peer_{size}_{}_{}.csv", p.cut, p.theta_deg)),
                    csv,
                )
                .unwrap();
            }
            let d: Vec<String> = differences(&run, &ax)
                .iter()
                .map(|(w, e)| format!("{w} {:.2}%", 100.0 * e))
                .collect();
            println!(
                "STUDY {} size {size}: nodes {} elements {} equations {} | gmsh {:.1} s | ccx wall {:.1} s CPU {:.1} s RSS {:.0} MB | increments {} iterations {} | total {:.1} s | RF {:?} | {}",
                variant.name(),
                run.nodes,
                run.elements,
                run.dofs,
                run.cost.mesh_seconds,
                run.cost.ccx_wall_seconds,
                run.cost.ccx_cpu_seconds,
                run.cost.ccx_peak_rss_bytes as f64 / 1e6,
                run.increments,
                det.iterations,
                run.cost.total_wall_seconds,
                det.reaction_total,
                d.join(", ")
            );
        }
    }
}
