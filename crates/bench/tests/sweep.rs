//! The accuracy sweep's pieces: the error metric against closed forms, the
//! cut CSV reader, Pareto fronts, the CSV round trip, the summary's
//! interpolation and ratios, the chart's series, and one coarse real run.

use axijoint_bench::chart::{write_chart, FRONT_LABEL, PEER_LABEL};
use axijoint_bench::errors::{read_cut_csv, read_scene_p_profiles, relative_error};
use axijoint_bench::pareto::{cost_at_error, front};
use axijoint_bench::profile::Profile;
use axijoint_bench::summary::{format_ratio_table, summarize};
use axijoint_bench::sweep::{
    compute_errors, failure_line, known_variant, plan, read_csv, run_job, write_csv, Config, Job, Row,
    Variant,
};
use std::path::{Path, PathBuf};

fn profile(cut: &str, theta: f64, bodies: &[(&str, Vec<(f64, f64)>)]) -> Profile {
    Profile::from_bodies(cut, theta, "sigma_z", bodies)
}

fn grid(n: usize, lo: f64, hi: f64, f: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    (0..=n)
        .map(|i| {
            let r = lo + (hi - lo) * i as f64 / n as f64;
            (r, f(r))
        })
        .collect()
}

#[test]
fn error_of_a_shifted_linear_profile() {
    // s_ref = r and s = r + c on [0, 1], 10 intervals: the difference is
    // the constant c (Integral c^2 = c^2 exactly); the trapezoid rule on
    // r^2 gives 1/3 + h^2/6 with h = 0.1.
    let c = 0.05;
    let reference = profile("a-a", 0.0, &[("pile", grid(10, 0.0, 1.0, |r| r))]);
    let run = profile("a-a", 0.0, &[("pile", grid(10, 0.0, 1.0, |r| r + c))]);
    let e = relative_error(&[run], &[reference]).unwrap();
    let expected = (c * c / (1.0 / 3.0 + 0.01 / 6.0)).sqrt();
    assert!((e - expected).abs() < 1e-12, "{e} vs {expected}");
}

#[test]
fn error_sums_profiles_and_bodies_and_uses_the_union_of_samples() {
    // Profile 1: pile s_ref = 2 on [0, 0.5], run 2.2; footing s_ref = 1 on
    // [0.5, 3], run 1 (run sampled on another grid). Profile 2 (theta 180):
    // footing only, s_ref = -1 on [0.5, 3], run -1.1.
    // num = 0.04 * 0.5 + 0 + 0.01 * 2.5 = 0.045
    // den = 4 * 0.5 + 1 * 2.5 + 1 * 2.5 = 7
    let reference = vec![
        profile(
            "a-a",
            0.0,
            &[
                ("pile", grid(5, 0.0, 0.5, |_| 2.0)),
                ("footing", grid(5, 0.5, 3.0, |_| 1.0)),
            ],
        ),
        profile("a-a", 180.0, &[("footing", grid(5, 0.5, 3.0, |_| -1.0))]),
    ];
    let run = vec![
        profile("a-a", 180.0, &[("footing", grid(7, 0.5, 3.0, |_| -1.1))]),
        profile(
            "a-a",
            0.0,
            &[
                ("pile", grid(3, 0.0, 0.5, |_| 2.2)),
                ("footing", grid(9, 0.5, 3.0, |_| 1.0)),
            ],
        ),
    ];
    let e = relative_error(&run, &reference).unwrap();
    assert!((e - (0.045f64 / 7.0).sqrt()).abs() < 1e-12, "{e}");
}

#[test]
fn a_jump_at_the_interface_is_not_smeared() {
    // The run and the reference agree per body (pile 0, footing 1 with a
    // jump at r = 0.5) but are sampled differently: error 0.
    let reference = profile(
        "b-b",
        0.0,
        &[
            ("pile", grid(2, 0.0, 0.5, |_| 0.0)),
            ("footing", grid(5, 0.5, 3.0, |_| 1.0)),
        ],
    );
    let run = profile(
        "b-b",
        0.0,
        &[
            ("pile", grid(7, 0.0, 0.5, |_| 0.0)),
            ("footing", grid(3, 0.5, 3.0, |_| 1.0)),
        ],
    );
    assert_eq!(relative_error(&[run], &[reference]).unwrap(), 0.0);
}

#[test]
fn a_missing_profile_or_body_is_an_error() {
    let reference = vec![profile(
        "a-a",
        0.0,
        &[
            ("pile", grid(2, 0.0, 0.5, |r| r)),
            ("footing", grid(2, 0.5, 3.0, |r| r)),
        ],
    )];
    let only_pile = vec![profile("a-a", 0.0, &[("pile", grid(2, 0.0, 0.5, |r| r))])];
    assert!(relative_error(&only_pile, &reference).is_err());
    let other_angle = vec![profile("a-a", 180.0, &[("pile", grid(2, 0.0, 0.5, |r| r))])];
    assert!(relative_error(&other_angle, &reference).is_err());
}

#[test]
fn reads_an_axijoint_cut_csv() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cut_a-a_theta180.csv");
    std::fs::write(
        &path,
        "s [m],r [m],z [m],theta [deg],body,sigma_r [MPa],sigma_z [MPa],sigma_theta [MPa],tau_rz [MPa],tau_rtheta [MPa],tau_ztheta [MPa]\n\
         0,0,0.75,180,pile,1,2,3,4,5,6\n\
         5e-1,5.0e-1,0.75,180,pile,1,-2.5e0,3,4,5,6\n\
         5e-1,5.0e-1,0.75,180,footing,1,7.25,3,4,5,6\n",
    )
    .unwrap();
    let p = read_cut_csv(&path, "a-a", "sigma_z").unwrap();
    assert_eq!(p.theta_deg, 180.0);
    assert_eq!(p.component, "sigma_z");
    let got: Vec<(f64, &str, f64)> = p
        .samples
        .iter()
        .map(|s| (s.r, s.body.as_str(), s.value))
        .collect();
    assert_eq!(
        got,
        vec![(0.0, "pile", 2.0), (0.5, "pile", -2.5), (0.5, "footing", 7.25)]
    );
    assert!(read_cut_csv(&path, "a-a", "sigma_q").is_err());
}

#[test]
fn pareto_front_of_a_hand_made_set() {
    // (time, error): 0 and 3 dominated by 1; 5 dominated by 4 (same error, slower).
    let pts = [
        (2.0, 0.5),
        (1.0, 0.3),
        (4.0, 0.01),
        (3.0, 0.3),
        (5.0, 0.001),
        (6.0, 0.001),
        (0.5, 0.9),
    ];
    let f = front(&pts);
    assert_eq!(f, vec![6, 1, 2, 4]);
    let fp: Vec<(f64, f64)> = f.iter().map(|&i| pts[i]).collect();
    // Between (4, 0.01) and (5, 0.001), log-log: error 10^-2.5 at 4^0.5 5^0.5.
    let (t, bound) = cost_at_error(&fp, 10f64.powf(-2.5)).unwrap();
    assert!((t - 20f64.sqrt()).abs() < 1e-12 && !bound, "{t}");
    assert_eq!(cost_at_error(&fp, 1e-4), None);
}

fn row(variant: &str, method: &str, size: f64, t: f64, e: Option<f64>) -> Row {
    Row {
        tool: if method == "ccx" { "calculix" } else { "axijoint" }.into(),
        variant: variant.into(),
        method: method.into(),
        role: if method == "ccx" { "peer" } else { "sweep" }.into(),
        size,
        m: (method != "ccx").then_some(8),
        solve_wall_s: Some(t),
        solve_cpu_s: Some(2.0 * t),
        err_vs_axijoint_ref: e,
        status: "ok".into(),
        ..Row::default()
    }
}

#[test]
fn csv_round_trip_keeps_empty_fields_and_failures() {
    let mut rows = vec![
        row("coulomb", "newton", 0.1, 1.5, Some(1.25e-3)),
        row("coulomb", "ccx", 0.07, 30.0, None),
    ];
    rows[0].note = "a note, with a comma".into();
    rows[0].dof_per_harmonic = Some(15174);
    rows[1].status = "failed: ccx exited with status 1".into();
    rows[1].solve_wall_s = None;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("accuracy.csv");
    write_csv(&path, &rows).unwrap();
    assert_eq!(read_csv(&path).unwrap(), rows);
    assert!(!dir.path().join("accuracy.csv.partial").exists());
}

#[test]
fn a_failure_is_summed_up_by_the_childs_error_line() {
    let msg = "\"axijoint\" \"solve\" \"x.json\" failed (status 256):\nwarning: slow\nerror: no equilibrium: stalls";
    assert_eq!(failure_line(msg), "no equilibrium: stalls");
    assert_eq!(failure_line("cannot start ccx\nmore"), "cannot start ccx");
}

#[test]
fn summary_interpolates_and_gives_the_peer_ratio() {
    let rows = vec![
        row("coulomb", "anderson", 0.4, 1.0, Some(1e-1)),
        row("coulomb", "anderson", 0.2, 100.0, Some(1e-3)),
        row("coulomb", "paper", 0.2, 200.0, Some(1e-3)),
        row("coulomb", "ccx", 0.1, 50.0, Some(1e-2)),
    ];
    let s = summarize(&rows);
    let at = |fam: &str, e: f64| {
        s.iter()
            .find(|r| r.kind == "time_to_error" && r.family == fam && r.error == e)
            .unwrap()
            .axijoint_wall_s
    };
    assert!((at("anderson", 1e-2).unwrap() - 10.0).abs() < 1e-9);
    assert!((at("anderson", 1e-3).unwrap() - 100.0).abs() < 1e-9);
    assert_eq!(at("paper", 1e-2), Some(200.0)); // its only run is already below: a bound
    let ratio = s.iter().find(|r| r.kind == "peer_ratio").unwrap();
    assert!((ratio.axijoint_wall_s.unwrap() - 10.0).abs() < 1e-9);
    assert!((ratio.ratio_wall.unwrap() - 5.0).abs() < 1e-9);
    // CPU times are twice the wall times on both sides here.
    assert!((ratio.ratio_cpu.unwrap() - 5.0).abs() < 1e-9);
}

#[test]
fn ratio_table_takes_the_peers_finest_level_and_the_warm_times() {
    let mut rows = vec![
        row("frictionless", "newton", 0.4, 0.1, Some(1e-1)),
        row("frictionless", "newton", 0.2, 1.0, Some(1e-3)),
        row("frictionless", "ccx", 0.2, 20.0, Some(1e-1)),
        row("frictionless", "ccx", 0.1, 2000.0, Some(1e-2)),
    ];
    for (r, warm) in rows.iter_mut().zip([0.01, 0.1, 10.0, 1000.0]) {
        r.solve_warm_wall_s = Some(warm);
    }
    let s = summarize(&rows);
    let finest: Vec<_> = s.iter().filter(|r| r.peer_finest).collect();
    assert_eq!(finest.len(), 1);
    assert_eq!(finest[0].family, "calculix size 0.1");
    // At 1e-2, halfway in log-log: sqrt(0.1 * 1.0) and sqrt(0.01 * 0.1).
    assert!((finest[0].ratio_wall.unwrap() - 2000.0 / 0.1f64.sqrt()).abs() < 1e-6);
    assert!((finest[0].ratio_warm_wall.unwrap() - 1000.0 / 0.001f64.sqrt()).abs() < 1e-6);
    let t = format_ratio_table(&s);
    assert_eq!(t.lines().count(), 3, "{t}");
    assert!(
        t.contains("6325") && t.contains("31623") && t.contains("yes"),
        "{t}"
    );
}

#[test]
fn chart_names_every_series() {
    let mut failed = row("table1", "paper", 0.05, 10.0, None);
    failed.status = "failed: no equilibrium".into();
    let rows = vec![
        row("coulomb", "anderson", 0.4, 1.0, Some(1e-1)),
        row("coulomb", "newton", 0.2, 3.0, Some(1e-3)),
        row("coulomb", "ccx", 0.1, 50.0, Some(1e-2)),
        row("table1", "paper", 0.2, 2.0, Some(2e-2)),
        failed,
        row("linear", "-", 0.2, 0.5, Some(3e-2)),
    ];
    let dir = tempfile::tempdir().unwrap();
    let (svg, png) = (dir.path().join("a.svg"), dir.path().join("a.png"));
    let variants: Vec<String> = ["bonded", "linear", "coulomb", "table1"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    write_chart(&rows, &variants, &svg, &png).unwrap();
    let text = std::fs::read_to_string(&svg).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let texts: Vec<&str> = doc
        .descendants()
        .filter_map(|n| n.text())
        .map(str::trim)
        .collect();
    for name in [
        "axijoint, anderson",
        "axijoint, newton",
        "axijoint, paper",
        "axijoint, linear (M, method irrelevant)",
        PEER_LABEL,
        FRONT_LABEL,
        "no data",
    ] {
        assert!(texts.contains(&name), "no '{name}' in the SVG texts {texts:?}");
    }
    assert!(texts
        .iter()
        .any(|t| t.contains("table1") && t.contains("1 failed runs not shown")));
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
}

/// The axijoint binary of this workspace, if built (release, then debug).
fn axijoint_binary() -> Option<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut dirs = vec![root.join("target")];
    if let Some(t) = std::env::var_os("CARGO_TARGET_DIR") {
        dirs.insert(0, PathBuf::from(t));
    }
    dirs.iter()
        .flat_map(|d| [d.join("release/axijoint"), d.join("debug/axijoint")])
        .find(|p| p.is_file())
}

/// One size (0.5), grading 2, M = 2, newton, no peer.
fn config(axijoint: PathBuf, work_dir: PathBuf, variants: Vec<Variant>) -> Config {
    Config {
        axijoint,
        gmsh: "gmsh".into(),
        ccx: "ccx".into(),
        work_dir,
        variants,
        sizes: vec![0.5],
        refines: vec![2.0],
        harmonics: vec![2],
        methods: vec!["newton".into()],
        linear_harmonics: 2,
        epsilon: 1e-6,
        ref_epsilon: 1e-8,
        ref_method: "newton".into(),
        peer_sizes: vec![],
        keep: false,
        warm_solves: 0,
    }
}

#[test]
fn one_coarse_real_run() {
    let Some(axijoint) = axijoint_binary() else {
        eprintln!("skipped: no axijoint binary (cargo build --release -p axijoint-cli)");
        return;
    };
    if std::process::Command::new("gmsh")
        .arg("--version")
        .output()
        .is_err()
    {
        eprintln!("skipped: no gmsh");
        return;
    }
    let work = tempfile::tempdir().unwrap();
    let geo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../geo");
    let variant = known_variant("coulomb", &geo).unwrap();
    let cfg = config(axijoint, work.path().to_path_buf(), vec![variant.clone()]);
    let job = |eps: f64, role: &str| Job {
        variant: variant.clone(),
        method: "newton".into(),
        size: 0.5,
        refine: 2.0,
        m: 2,
        epsilon: eps,
        role: role.into(),
        measure_solve: role == "sweep",
    };
    let mut outcomes = vec![
        run_job(&cfg, &job(1e-3, "sweep")),
        run_job(&cfg, &job(1e-8, "reference")),
    ];
    for o in &outcomes {
        assert!(o.row.ok(), "{}", o.row.status);
    }
    let r = &outcomes[0].row;
    assert!(r.dof_per_harmonic.unwrap() > 100);
    assert_eq!(r.sections, Some(5)); // the dealiased default 2M + 1
    assert!(r.iterations.unwrap() >= 1);
    assert!(r.solve_wall_s.unwrap() > 0.0 && r.run_wall_s.unwrap() >= r.solve_wall_s.unwrap() * 0.5);
    assert!(r.run_peak_rss_mib.unwrap() > 1.0);
    // The run's cut CSVs were kept and read back.
    let kept = work
        .path()
        .join("runs")
        .join(job(1e-3, "sweep").label())
        .join("cuts");
    let p = read_scene_p_profiles(&kept).unwrap();
    assert_eq!(p.len(), 4);
    assert!(p.iter().all(|p| p.samples.iter().any(|s| s.body == "footing")));
    // The linear scene (geo/pile_footing_linear.json): no iteration, no
    // sections; its springs carry the tension that the coulomb joint cuts
    // off, so the profiles differ by more than 10 %.
    let linear = known_variant("linear", &geo).unwrap();
    let lin = run_job(
        &cfg,
        &Job {
            variant: linear,
            role: "linear".into(),
            ..job(1e-6, "sweep")
        },
    );
    assert!(lin.row.ok(), "{}", lin.row.status);
    assert_eq!((lin.row.method.as_str(), lin.row.sections), ("-", None));
    assert_eq!(lin.row.dof_per_harmonic, r.dof_per_harmonic);
    let d = relative_error(
        lin.profiles.as_ref().unwrap(),
        outcomes[1].profiles.as_ref().unwrap(),
    )
    .unwrap();
    assert!(d > 0.1, "{d}");
    compute_errors(&mut outcomes);
    assert!(outcomes[1].row.is_reference && outcomes[1].row.err_vs_axijoint_ref == Some(0.0));
    let e = outcomes[0].row.err_vs_axijoint_ref.unwrap();
    assert!(e > 0.0 && e < 0.05, "{e}");
}

#[test]
fn the_plan_crosses_sizes_gradings_and_harmonics_and_refers_to_the_finest() {
    let geo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../geo");
    let variants = vec![
        known_variant("coulomb", &geo).unwrap(),
        known_variant("bonded", &geo).unwrap(),
    ];
    let cfg = Config {
        sizes: vec![0.3, 0.5],
        refines: vec![8.0, 2.0],
        harmonics: vec![4, 2],
        linear_harmonics: 4,
        ..config("axijoint".into(), "unused".into(), variants)
    };
    let jobs = plan(&cfg);
    // coulomb: 2 sizes x 2 gradings x 2 M but the reference's mesh, then
    // its reference; bonded: one run per mesh.
    assert_eq!(jobs.len(), 6 + 4 + 1);
    assert!(!jobs
        .iter()
        .any(|j| j.role == "sweep" && (j.size, j.refine) == (0.3, 8.0)));
    let reference: Vec<_> = jobs.iter().filter(|j| j.role == "reference").collect();
    assert_eq!(reference.len(), 1);
    assert_eq!(
        (reference[0].size, reference[0].refine, reference[0].m),
        (0.3, 8.0, 4)
    );
    let bonded: Vec<(f64, f64)> = jobs
        .iter()
        .filter(|j| j.role == "linear")
        .map(|j| (j.size, j.refine))
        .collect();
    assert_eq!(bonded, [(0.5, 2.0), (0.5, 8.0), (0.3, 2.0), (0.3, 8.0)]);
    // Every job's label (its folder) is its own.
    let mut labels: Vec<String> = jobs.iter().map(|j| j.label()).collect();
    labels.sort();
    labels.dedup();
    assert_eq!(labels.len(), jobs.len());
}
