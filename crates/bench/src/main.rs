//! `bench-accuracy`: the accuracy-against-speed sweep of Scene P (see
//! `--help` and scripts/bench-accuracy).

use anyhow::{bail, Context, Result};
use axijoint_bench::chart::write_chart;
use axijoint_bench::summary::{format_ratio_table, format_table, summarize, write_summary_csv};
use axijoint_bench::sweep::{
    compute_errors, known_variant, plan, read_csv, run_job, run_peer, write_csv, Config, Outcome, Row,
};
use clap::Parser;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Default mesh sizes of axijoint (coarse to fine).
const DEFAULT_SIZES: [f64; 4] = [0.4, 0.2, 0.12, 0.07];

/// Default mesh sizes of the peer (coarse to fine).
const DEFAULT_PEER_SIZES: [f64; 3] = [0.2, 0.14, 0.1];

/// --ratio: gradings of axijoint's meshes (size / element size along the
/// pile side): the scenes' 2, and 8 (the b-b profile runs 0.25 m above
/// the re-entrant corner at the pile side, where a graded mesh reaches an
/// error at a fraction of the unknowns).
const RATIO_REFINES: [f64; 2] = [2.0, 8.0];

/// --ratio: the peer's levels: 0.1 (3.8e4-4.0e4 equations) and the finest,
/// 0.06 (1.4e5, near the level issue 16 measured its ratios at; 2.3-4.5 GB).
const RATIO_PEER_SIZES: [f64; 2] = [0.1, 0.06];

/// --ratio: axijoint's mesh sizes (coarser ones too: the peer's error is
/// reached below 0.4).
const RATIO_SIZES: [f64; 8] = [1.0, 0.8, 0.6, 0.4, 0.3, 0.2, 0.12, 0.07];

/// --plastic: the peer's sizes h at the pile (geo/pile_clay_3d.geo).
const PLASTIC_PEER_SIZES: [f64; 2] = [0.3, 0.2];

const ABOUT: &str = "Accuracy against cost of axijoint on Scene P (and of a CalculiX 3D peer)";

const LONG_ABOUT: &str = "\
Accuracy against cost of axijoint on Scene P (docs/theory.md section 14), and of a
CalculiX 3D peer. Writes OUT/accuracy.csv (one row per run), OUT/accuracy.svg
and .png (the chart) and OUT/accuracy_summary.csv, and prints the summary.

What runs:
  variants  bonded (no joint), linear (elastic joint springs: never opens or
            slips), coulomb (C = 0, phi = 30 deg), table1 (C = 0.5, phi = 30)
            from geo/pile_footing{_bonded,_linear,_coulomb,}.json
  sizes     the mesh parameter `size` of geo/pile_footing.geo (refine 2;
            DOF per harmonic in the CSV)
  M         highest harmonic (--harmonics M)
  methods   solver.method: paper, anderson, newton
The nonlinear variants (coulomb, table1) run every size x M x method. The
linear ones run once per size (M = --linear-harmonics, method irrelevant:
the harmonics above the loaded one are zero); their CSV role is `linear`.

Each run is two child processes of the axijoint binary, each measured with
wait4 (wall time, CPU time incl. gmsh, peak RSS) and with the CPUs that
other processes used meanwhile (/proc/stat; columns load_solve, load_run):
`axijoint solve` (mesh + solve + solution folder; the chart's x axis) and
`axijoint run` (mesh + solve + every output, including the run without the
joints for the comparison curves). Per-run scenes are written under
WORK/scenes: mesh.file absolute, the paper's explicit sections dropped (the
dealiased 2M + 1 default), solver.method and solver.epsilon set.

Error: relative L2 difference of the a-a (sigma_z) and b-b (sigma_r)
profiles at theta 0 and 180 from the run's cut CSVs; each body interpolated
linearly in r on its own (never across the interface r = a), trapezoid rule
on the union of the sample points:
  e = sqrt(sum Integral (s - s_ref)^2 dr / sum Integral s_ref^2 dr).
Reference (err_vs_axijoint_ref = 0, is_reference = true): for a nonlinear
variant an extra `axijoint run` at the finest size and largest M with
--ref-method at --ref-epsilon (role `reference`; if it fails, the finest
successful sweep run); for a linear variant its finest run. So the error
of the finest levels is measured against a mesh only ~1.7x finer: read it
as a self-convergence error. err_vs_peer_ref: against the peer's finest
level.
Peer rows (tool calculix; bonded, linear and coulomb only: the peer has no
cohesion) carry their error against both references; their `solve` times
are gmsh mesh + ccx (CPU: ccx CPU + mesh wall), `run` the whole peer run.

A failed run is reported (command and stderr tail), recorded with status
`failed: ...` and empty numbers, counted in the chart's panel title, and
the sweep goes on. The CSV is written (temp + rename) when all runs are done;
meanwhile WORK/progress.csv holds the rows so far (without the errors).

Chart: one panel per variant; x solve wall time (log), y error vs axijoint's
reference (log; the reference itself left out). Markers: every run (circles
by method, triangles the peer); thin lines: each family's own Pareto front;
thick grey step line with ringed markers: the variant's Pareto front over
all axijoint runs. Summary: the solve time each family (and `all`) needs for
1 % and 0.1 % error (log-log interpolation on its Pareto front), and per peer
run the ratio peer time / axijoint time at the peer's error (vs axijoint's
reference), wall and CPU.

--ratio: the peer ratio of the four peer variants bonded, linear,
frictionless (C = 0, phi = 0) and coulomb in one run: the peer at its levels
0.1 and 0.06 (the finest, about 1.4e5 equations), axijoint at sizes 1.0 to 0.07
with the gradings refine = 2 and 8, M = 4, 8, 16, 32, newton,
each `axijoint solve` also timed 3 times with the mesh from a warm cache
(WORK/mesh-cache; the fastest kept). Prints per variant peer time / axijoint
time at the peer's profile error, with meshing (gmsh + ccx against `solve
--no-cache`) and without (ccx alone against the warm `solve`), and whether
each reaches 1000. Writes OUT/ratio.csv, ratio.svg/.png and
ratio_summary.csv.

--plastic: the tutorial's pile in clay (docs/tutorial/pile_clay.json, head
pushed 0.1 D) by `axijoint solve` (--no-cache: gmsh included) at sizes h
0.3, 0.2, 0.15 with M = 8 for the soil laws tresca and von_mises (c_u =
0.05 MPa), and by the CalculiX peer (geo/pile_clay_3d.geo, C3D20R, Mises
sigma_y = sqrt(3) c_u: axijoint's von_mises) at its sizes 0.3, 0.2 (peak
2.2 GiB, ~30 min in all). Writes OUT/plastic_peer.csv (one row per run:
reaction at 0.01 D and 0.1 D, wall, CPU, peak memory, other processes'
load, error against the reference), OUT/plastic_peer_curves.csv (the
load-displacement curves) and OUT/plastic_peer.svg and .png, and prints
the reference: the peer extrapolated to h -> 0 from its three finest
sizes (R = R_0 + C h^p) when they converge monotonically, else axijoint's
von_mises runs so extrapolated (the same continuum problem), else the
peer's finest run; and the peer's finest run as a second reference. For
each reference and peer run: its wall time over that of the fastest
axijoint von_mises run whose reaction is at least as close to the
reference (equal accuracy), against the goal 100. With --no-peer the
CalculiX rows and curves of an existing OUT/plastic_peer.csv are kept (to
re-measure axijoint alone); --replot OUT/plastic_peer.csv runs nothing: it
recomputes the reactions (from the curves) and errors of the rows,
rewrites OUT/plastic_peer.csv, redraws the chart and prints the summary.";

/// Command line.
#[derive(Parser, Debug)]
#[command(name = "bench-accuracy", about = ABOUT, long_about = LONG_ABOUT, args_override_self = true)]
struct Cli {
    /// Development mode: sizes 0.4 and 0.2, M = 4 and 8, anderson only, the
    /// coarsest peer level (each unless given explicitly); output to
    /// WORK/quick unless --out-dir is given.
    #[arg(long)]
    quick: bool,
    /// The peer ratio of bonded, linear, frictionless and coulomb (see
    /// below); explicit options still apply.
    #[arg(long)]
    ratio: bool,
    /// The plastic comparison instead (issue 26 item 6): the tutorial's
    /// pile in clay by axijoint (tresca, von_mises) and by CalculiX's Mises
    /// plasticity (see below); --sizes, --harmonics (the first), --peer-sizes,
    /// --quick, --no-peer (keeps the peer rows of an existing
    /// plastic_peer.csv), --out-dir and --replot (of plastic_peer.csv) apply.
    #[arg(long)]
    plastic: bool,
    /// Skip the CalculiX peer.
    #[arg(long)]
    no_peer: bool,
    /// Folder of accuracy.csv, accuracy.svg/.png, accuracy_summary.csv
    /// (default: docs/performance; with --quick: WORK/quick).
    #[arg(long)]
    out_dir: Option<PathBuf>,
    /// Scratch folder (scenes, run folders, kept cut CSVs, peer runs).
    #[arg(long, default_value = "target/bench-accuracy")]
    work_dir: PathBuf,
    /// Variants, comma-separated [default: bonded,linear,coulomb,table1;
    /// --ratio: bonded,linear,frictionless,coulomb].
    #[arg(long, value_delimiter = ',')]
    variants: Vec<String>,
    /// Mesh sizes (`size` of geo/pile_footing.geo); the smallest is the
    /// reference level [default: 0.4,0.2,0.12,0.07, about 1.4e3, 4.1e3,
    /// 1.1e4 and 3.1e4 DOF per harmonic; --quick: 0.4,0.2].
    #[arg(long, value_delimiter = ',')]
    sizes: Vec<f64>,
    /// Gradings `refine` of geo/pile_footing.geo (size / element size along
    /// the pile side); the largest is the reference's [default: 2, the
    /// scenes'; --ratio: 2,8].
    #[arg(long, value_delimiter = ',')]
    refines: Vec<f64>,
    /// Highest harmonics M of the nonlinear variants; the largest is the
    /// reference's (default: 4,8,16,32; --quick: 4,8).
    #[arg(long, value_delimiter = ',')]
    harmonics: Vec<usize>,
    /// Methods of the nonlinear variants [default: paper,anderson,newton;
    /// --quick: anderson].
    #[arg(long, value_delimiter = ',')]
    methods: Vec<String>,
    /// M of the linear variants' single run per size.
    #[arg(long, default_value_t = 4)]
    linear_harmonics: usize,
    /// Convergence tolerance of the sweep (solver.epsilon).
    #[arg(long, default_value_t = 1e-6)]
    epsilon: f64,
    /// Tolerance of the nonlinear reference.
    #[arg(long, default_value_t = 1e-8)]
    ref_epsilon: f64,
    /// Method of the nonlinear reference (if it fails, the finest
    /// successful sweep run is the reference) [default: newton; --quick:
    /// anderson].
    #[arg(long)]
    ref_method: Option<String>,
    /// Peer mesh sizes (`size` of geo/pile_footing_3d.geo); the smallest is
    /// the peer's reference [default: 0.2,0.14,0.1: about 1.2e4, 1.9e4 and
    /// 3.8e4 DOF; --quick: 0.2].
    #[arg(long, value_delimiter = ',')]
    peer_sizes: Vec<f64>,
    /// The axijoint binary.
    #[arg(long, default_value = "target/release/axijoint")]
    axijoint: PathBuf,
    /// The scene folder (geo/).
    #[arg(long, default_value = "geo")]
    geo_dir: PathBuf,
    /// gmsh, for the peer.
    #[arg(long, default_value = "gmsh")]
    gmsh: PathBuf,
    /// CalculiX's ccx, for the peer.
    #[arg(long, default_value = "ccx")]
    ccx: PathBuf,
    /// Keep every run folder (default: only the cut CSVs and summary.json).
    #[arg(long)]
    keep: bool,
    /// Run nothing: redraw the chart and the summary from this accuracy.csv.
    #[arg(long)]
    replot: Option<PathBuf>,
}

fn main() {
    if let Err(e) = real_main() {
        eprintln!("bench-accuracy: error: {e:#}");
        std::process::exit(1);
    }
}

/// `name` found on PATH (or as given if it has a slash).
fn which(name: &Path) -> PathBuf {
    if name.components().count() > 1 {
        return name.to_path_buf();
    }
    std::env::var_os("PATH")
        .and_then(|paths| {
            std::env::split_paths(&paths)
                .map(|d| d.join(name))
                .find(|p| p.is_file())
        })
        .unwrap_or_else(|| name.to_path_buf())
}

fn real_main() -> Result<()> {
    let mut cli = Cli::parse();
    if cli.plastic {
        return plastic_main(&cli);
    }
    let q = cli.quick;
    let r = cli.ratio;
    if cli.variants.is_empty() {
        let v: &[&str] = if r {
            &["bonded", "linear", "frictionless", "coulomb"]
        } else {
            &["bonded", "linear", "coulomb", "table1"]
        };
        cli.variants = v.iter().map(|s| s.to_string()).collect();
    }
    if r && !q {
        if cli.sizes.is_empty() {
            cli.sizes = RATIO_SIZES.to_vec();
        }
        if cli.methods.is_empty() {
            cli.methods = vec!["newton".into()];
        }
        if cli.peer_sizes.is_empty() {
            cli.peer_sizes = RATIO_PEER_SIZES.to_vec();
        }
        if cli.refines.is_empty() {
            cli.refines = RATIO_REFINES.to_vec();
        }
    }
    if cli.sizes.is_empty() {
        cli.sizes = if q { vec![0.4, 0.2] } else { DEFAULT_SIZES.to_vec() };
    }
    if cli.refines.is_empty() {
        cli.refines = vec![axijoint_bench::sweep::DEFAULT_REFINE];
    }
    if cli.harmonics.is_empty() {
        cli.harmonics = if q { vec![4, 8] } else { vec![4, 8, 16, 32] };
    }
    if cli.methods.is_empty() {
        let m: &[&str] = if q {
            &["anderson"]
        } else {
            &["paper", "anderson", "newton"]
        };
        cli.methods = m.iter().map(|s| s.to_string()).collect();
    }
    let ref_method = cli
        .ref_method
        .clone()
        .unwrap_or_else(|| if q { "anderson" } else { "newton" }.into());
    if cli.peer_sizes.is_empty() {
        cli.peer_sizes = if q {
            DEFAULT_PEER_SIZES[..1].to_vec()
        } else {
            DEFAULT_PEER_SIZES.to_vec()
        };
    }
    let out_dir = cli.out_dir.clone().unwrap_or_else(|| {
        if cli.quick {
            cli.work_dir.join("quick")
        } else {
            PathBuf::from("docs/performance")
        }
    });
    std::fs::create_dir_all(&out_dir).with_context(|| format!("cannot create {}", out_dir.display()))?;
    let stem = if r { "ratio" } else { "accuracy" };
    let csv_path = out_dir.join(format!("{stem}.csv"));
    let variants: Vec<String> = cli.variants.clone();

    let rows: Vec<Row> = if let Some(csv) = &cli.replot {
        read_csv(csv)?
    } else {
        for m in cli.methods.iter().chain(std::iter::once(&ref_method)) {
            if !["paper", "anderson", "newton"].contains(&m.as_str()) {
                bail!("unknown method '{m}' (paper, anderson, newton)");
            }
        }
        if cli.sizes.is_empty() || cli.harmonics.is_empty() {
            bail!("--sizes and --harmonics need at least one value");
        }
        let axijoint = std::path::absolute(&cli.axijoint)?;
        if !axijoint.is_file() {
            bail!(
                "{} not found: build it with `cargo build --release -p axijoint-cli`",
                axijoint.display()
            );
        }
        let cfg = Config {
            axijoint,
            gmsh: which(&cli.gmsh),
            ccx: which(&cli.ccx),
            work_dir: std::path::absolute(&cli.work_dir)?,
            variants: cli
                .variants
                .iter()
                .map(|v| known_variant(v, &cli.geo_dir))
                .collect::<Result<_>>()?,
            sizes: cli.sizes.clone(),
            refines: cli.refines.clone(),
            harmonics: cli.harmonics.clone(),
            methods: cli.methods.clone(),
            linear_harmonics: cli.linear_harmonics,
            epsilon: cli.epsilon,
            ref_epsilon: cli.ref_epsilon,
            ref_method: ref_method.clone(),
            peer_sizes: if cli.no_peer {
                vec![]
            } else {
                cli.peer_sizes.clone()
            },
            keep: cli.keep,
            warm_solves: if r { 3 } else { 0 },
        };
        run_sweep(&cfg)?
    };
    if cli.replot.is_none() {
        write_csv(&csv_path, &rows)?;
    }
    let svg = out_dir.join(format!("{stem}.svg"));
    let png = out_dir.join(format!("{stem}.png"));
    write_chart(&rows, &variants, &svg, &png)?;
    let summary = summarize(&rows);
    let summary_path = out_dir.join(format!("{stem}_summary.csv"));
    write_summary_csv(&summary_path, &summary)?;
    println!("\n{}", format_table(&summary));
    if r {
        println!("{}", format_ratio_table(&summary));
    }
    let failed = rows.iter().filter(|r| !r.ok()).count();
    if failed > 0 {
        println!(
            "{failed} of {} runs failed (status column of the CSV)",
            rows.len()
        );
    }
    if cli.replot.is_none() {
        println!("wrote {}", csv_path.display());
    }
    println!(
        "wrote {}, {}, {}",
        svg.display(),
        png.display(),
        summary_path.display()
    );
    Ok(())
}

fn run_sweep(cfg: &Config) -> Result<Vec<Row>> {
    let jobs = plan(cfg);
    let peer_jobs: Vec<_> = cfg
        .variants
        .iter()
        .filter_map(|v| v.peer.map(|pv| (v.clone(), pv)))
        .flat_map(|(v, pv)| {
            let mut sizes = cfg.peer_sizes.clone();
            sizes.sort_by(|a, b| b.total_cmp(a));
            sizes.into_iter().map(move |s| (v.clone(), pv, s))
        })
        .collect();
    let total = jobs.len() + peer_jobs.len();
    println!(
        "== {} axijoint runs (each `solve` + `run`; the references `run` only) and {} peer runs; work folder {}",
        jobs.len(),
        peer_jobs.len(),
        cfg.work_dir.display()
    );
    let start = Instant::now();
    let mut outcomes: Vec<Outcome> = Vec::new();
    for (k, job) in jobs.iter().enumerate() {
        println!(
            "[{}/{total}] {} {} size {} M {} eps {:e} ({})",
            k + 1,
            job.variant.name,
            if job.variant.linear { "linear" } else { &job.method },
            job.size,
            job.m,
            job.epsilon,
            job.role
        );
        let o = run_job(cfg, job);
        print_outcome(&o.row);
        outcomes.push(o);
        save_progress(cfg, &outcomes);
    }
    for (k, (v, pv, size)) in peer_jobs.iter().enumerate() {
        println!("[{}/{total}] {} calculix size {size}", jobs.len() + k + 1, v.name);
        let o = run_peer(cfg, v, *pv, *size);
        print_outcome(&o.row);
        outcomes.push(o);
        save_progress(cfg, &outcomes);
    }
    compute_errors(&mut outcomes);
    println!("== all runs done in {:.0} s", start.elapsed().as_secs_f64());
    Ok(outcomes.into_iter().map(|o| o.row).collect())
}

/// The rows so far (errors not yet computed) in WORK/progress.csv, so an
/// interrupted sweep keeps its measurements.
fn save_progress(cfg: &Config, outcomes: &[Outcome]) {
    let rows: Vec<Row> = outcomes.iter().map(|o| o.row.clone()).collect();
    if let Err(e) = write_csv(&cfg.work_dir.join("progress.csv"), &rows) {
        eprintln!("   warning: {e:#}");
    }
}

fn print_outcome(r: &Row) {
    if !r.ok() {
        return;
    }
    let f = |x: Option<f64>| x.map_or("-".to_owned(), |v| format!("{v:.2}"));
    println!(
        "   solve {} s (CPU {} s, {} MiB), run {} s (CPU {} s, {} MiB), {}, {} iterations, other load {} / {} CPUs",
        f(r.solve_wall_s),
        f(r.solve_cpu_s),
        f(r.solve_peak_rss_mib),
        f(r.run_wall_s),
        f(r.run_cpu_s),
        f(r.run_peak_rss_mib),
        match (r.dof_per_harmonic, r.dof_3d) {
            (Some(d), _) => format!("{d} DOF/harmonic"),
            (None, Some(d)) => format!("{d} DOF (3D)"),
            _ => "- DOF".into(),
        },
        r.iterations.map_or("-".into(), |d| d.to_string()),
        f(r.load_solve),
        f(r.load_run),
    );
}

/// `--plastic`: the pile in clay against the CalculiX peer.
fn plastic_main(cli: &Cli) -> Result<()> {
    use axijoint_bench::plastic_bench as pb;
    let pick = |given: &[f64], quick: &[f64], full: &[f64]| -> Vec<f64> {
        if !given.is_empty() {
            given.to_vec()
        } else if cli.quick {
            quick.to_vec()
        } else {
            full.to_vec()
        }
    };
    let out_dir = cli.out_dir.clone().unwrap_or_else(|| {
        if cli.quick {
            cli.work_dir.join("plastic-quick")
        } else {
            PathBuf::from("docs/performance")
        }
    });
    let axijoint = std::path::absolute(&cli.axijoint)?;
    if cli.replot.is_none() && !axijoint.is_file() {
        bail!(
            "{} not found: build it with `cargo build --release -p axijoint-cli`",
            axijoint.display()
        );
    }
    let cfg = pb::PlasticConfig {
        axijoint,
        gmsh: which(&cli.gmsh),
        ccx: which(&cli.ccx),
        scene: std::path::absolute("docs/tutorial/pile_clay.json")?,
        work_dir: std::path::absolute(cli.work_dir.join("plastic"))?,
        sizes: pick(&cli.sizes, &[0.3], &[0.3, 0.2, 0.15]),
        harmonics: cli.harmonics.first().copied().unwrap_or(8),
        laws: vec!["tresca".into(), "von_mises".into()],
        peer_sizes: if cli.no_peer {
            vec![]
        } else {
            pick(&cli.peer_sizes, &[0.3], &PLASTIC_PEER_SIZES)
        },
        peer_growth: 1.3,
    };
    pb::command(&cfg, &out_dir, cli.replot.as_deref(), cli.no_peer)
}
