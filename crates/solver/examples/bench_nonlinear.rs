//! Benchmark of the nonlinear joint iteration against the linear solve
//! (issue 6, time target: a nonlinear run should cost at most 1.5x the linear
//! solve of the same mesh); `scripts/bench --nonlinear` runs it.
//!
//! For each variant of Scene P (`table1` = `geo/pile_footing.json`,
//! `frictionless`, `noslip`, or a scene file) at one element size, with the
//! scene format's defaults for the iteration (the scene's explicit
//! `sections` and `solver` are dropped: dealiased 2M + 1 sections,
//! `solver.method` as given by `--methods`, `epsilon` from `--epsilon`), the
//! phases of `run::solve_scene` are timed one by one through the library:
//!
//! - the linear solve, what a linear scene costs once meshed (meshing by
//!   gmsh excluded, reported as `mesh_s`): `assemble_loads` (`loads_s`),
//!   `build_model` (pattern and symbolic factorization, `setup_s`),
//!   `Model::factorize_all(0..=M)` (assembly and numeric Cholesky of every
//!   harmonic, in parallel, `factorize_s`), the solve of the loads
//!   (`solve_s`) and the reactions (`reactions_s`); `linear_s` is their sum;
//! - per method: the nonlinear solution with harmonics 0..=M along the
//!   scene format's default load path (`{"steps": "auto"}`: stepped, the
//!   history law; `scene_sections` + `iteration::solve`,
//!   `iterate_s`), the
//!   M/2 comparison `solve_scene` runs after it (`check_s`) and the
//!   reactions of the final displacements (`final_reactions_s`).
//!
//! `ratio` = (linear + iteration) / linear (the issue's measure);
//! `ratio_scene` = (linear + iteration + M/2 check + final reactions) /
//! linear, everything `solve_scene` does after meshing; `ratio_cpu` is
//! `ratio` in CPU seconds of the process (all threads), which other
//! processes do not inflate. `sweeps` counts the back-substitutions of all
//! harmonics the iteration cost; `per_sweep_s` = `iterate_s / sweeps`.
//! From the iteration's own clock (`IterationRecord::seconds`, medians over
//! the timed runs): `first_s` up to the end of the first sweep, `sweep_s` the mean
//! cost of each later sweep, `outside_s` what `iteration::solve` and the
//! sections cost before its clock starts and after its last record (the
//! setup, with its full elastic solve, and the final full solve of the
//! displacements). `check_ratio` = (linear + iteration + M/2 check) / linear.
//! Below 2e5 DOF every phase but meshing and loads is repeated up to
//! `--reps` times (default 5, within about 2 s a phase) and the medians are
//! reported. `others_cpus` is the average number of CPUs other processes kept
//! busy meanwhile (from `/proc/stat`; above ~0.2 the wall times are
//! inflated), `peak_mb` the process's RSS high-water mark (MiB).
//!
//! `--end-to-end` also runs `run::solve_scene` itself on each variant and
//! method (meshing included: `e2e_s`) and reports its iterations
//! (`e2e_iterations`), a check that the phases above are what the library
//! does.
//!
//! ```text
//! cargo run --release -p axijoint-solver --example bench_nonlinear -- \
//!     --size 0.12 [--harmonics 4] [--epsilon 1e-6] [--variants table1,frictionless] \
//!     [--methods anderson,paper] [--reps 5] [--refine 2] [--end-to-end] [--header]
//! cargo run --release -p axijoint-solver --example bench_nonlinear -- --print-header
//! ```

use axijoint_solver::iteration::{solve, Outcome, Problem};
use axijoint_solver::linear::{HarmonicFactor, Model};
use axijoint_solver::loads::{assemble_loads, HarmonicLoads};
use axijoint_solver::run::{
    build_model, iteration_settings, mesh_scene, reactions, scene_sections, solve_loads, solve_scene,
};
use axijoint_solver::scene::{JointLaw, Scene, SolverMethod, SolverSettings};
use axijoint_solver::solution::Displacements;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[path = "../benches/support/cpu.rs"]
mod cpu;
use cpu::{cpu_seconds, machine_busy_seconds, peak_rss_mb};

const HEADER: &str = "variant,size,refine,M,method,sections,epsilon,nodes,dof,joint_points,\
mesh_s,loads_s,setup_s,factorize_s,solve_s,reactions_s,linear_s,\
iterations,sweeps,final_ratio,iterate_s,check_iterations,check_s,final_reactions_s,nonlinear_s,\
ratio,ratio_scene,linear_cpu_s,iterate_cpu_s,check_cpu_s,nonlinear_cpu_s,ratio_cpu,\
per_sweep_s,peak_mb,reps,others_cpus,e2e_s,e2e_iterations,status,\
sweep_s,first_s,outside_s,check_ratio";

/// Models below this many DOF per harmonic are timed several times.
const SMALL_DOF: usize = 200_000;

struct Args {
    size: f64,
    refine: Option<f64>,
    harmonics: u32,
    epsilon: f64,
    variants: Vec<String>,
    methods: Vec<SolverMethod>,
    reps: usize,
    end_to_end: bool,
    header: bool,
}

fn usage() -> String {
    "usage: bench_nonlinear --size S [--harmonics M] [--epsilon E] [--variants table1,frictionless,noslip|FILE.json]\n\
     \x20                      [--methods anderson,paper,newton] [--reps N] [--refine R] [--end-to-end] [--header]\n\
     \x20      bench_nonlinear --print-header"
        .into()
}

fn parse_method(s: &str) -> Result<SolverMethod, String> {
    match s {
        "anderson" => Ok(SolverMethod::Anderson),
        "paper" => Ok(SolverMethod::Paper),
        "newton" => Ok(SolverMethod::Newton),
        other => Err(format!(
            "unknown method {other}: expected anderson, paper or newton"
        )),
    }
}

fn method_name(m: SolverMethod) -> &'static str {
    match m {
        SolverMethod::Anderson => "anderson",
        SolverMethod::Paper => "paper",
        SolverMethod::Newton => "newton",
    }
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        size: f64::NAN,
        refine: None,
        harmonics: 4,
        epsilon: 1e-6,
        variants: vec!["table1".into(), "frictionless".into()],
        methods: vec![SolverMethod::Newton, SolverMethod::Anderson, SolverMethod::Paper],
        reps: 5,
        end_to_end: false,
        header: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = |name: &str| {
            it.next()
                .ok_or_else(|| format!("{name} needs a value\n{}", usage()))
        };
        let num = |s: String, name: &str| s.parse::<f64>().map_err(|e| format!("{name}: {e}"));
        match a.as_str() {
            "--size" => args.size = num(value("--size")?, "--size")?,
            "--refine" => args.refine = Some(num(value("--refine")?, "--refine")?),
            "--harmonics" => {
                args.harmonics = value("--harmonics")?
                    .parse()
                    .map_err(|e| format!("--harmonics: {e}"))?
            }
            "--epsilon" => args.epsilon = num(value("--epsilon")?, "--epsilon")?,
            "--variants" => args.variants = value("--variants")?.split(',').map(str::to_string).collect(),
            "--methods" => {
                args.methods = value("--methods")?
                    .split(',')
                    .map(parse_method)
                    .collect::<Result<_, _>>()?
            }
            "--reps" => args.reps = value("--reps")?.parse().map_err(|e| format!("--reps: {e}"))?,
            "--end-to-end" => args.end_to_end = true,
            "--header" => args.header = true,
            "--print-header" => {
                println!("{HEADER}");
                std::process::exit(0);
            }
            "-h" | "--help" => return Err(usage()),
            other => return Err(format!("unknown argument {other}\n{}", usage())),
        }
    }
    if args.size.is_nan() || args.size <= 0.0 {
        return Err(format!("--size must be given and positive\n{}", usage()));
    }
    if !(args.epsilon > 0.0 && args.epsilon < 1.0) {
        return Err("--epsilon must be in (0, 1)".into());
    }
    Ok(args)
}

/// The scene file of a variant name (or the name itself when it is a path).
fn scene_path(variant: &str) -> PathBuf {
    let geo = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../geo"));
    match variant {
        "table1" => geo.join("pile_footing.json"),
        "frictionless" => geo.join("pile_footing_frictionless.json"),
        "noslip" => geo.join("pile_footing_noslip.json"),
        path => PathBuf::from(path),
    }
}

/// Wall and CPU seconds of one call of `f`, and its result.
fn once<T>(f: impl FnOnce() -> T) -> (f64, f64, T) {
    let (t, c) = (Instant::now(), cpu_seconds());
    let out = f();
    (t.elapsed().as_secs_f64(), cpu_seconds() - c, out)
}

/// Median wall and CPU seconds of `f` over up to `reps` calls (fewer once
/// `budget` seconds are spent), and its last result.
fn timed<T>(reps: usize, budget: f64, mut f: impl FnMut() -> T) -> (f64, f64, T) {
    let (mut wall, mut cpu) = (Vec::new(), Vec::new());
    let start = Instant::now();
    loop {
        let (w, c, out) = once(&mut f);
        wall.push(w);
        cpu.push(c);
        if wall.len() >= reps.max(1) || start.elapsed().as_secs_f64() >= budget {
            return (median(wall), median(cpu), out);
        }
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The stress-transfer iteration with harmonics 0..=m, as a run does it.
/// The elastic solution `elastic` is reused, as a run does.
#[allow(clippy::too_many_arguments)]
fn iterate(
    scene: &Scene,
    model: &Model,
    factors: &[HarmonicFactor],
    loads: &[HarmonicLoads],
    laws: &[JointLaw],
    elastic: &Displacements,
    m: u32,
) -> Result<Outcome, String> {
    let sections = scene_sections(scene, model, loads).map_err(|e| e.to_string())?;
    let loads: Vec<HarmonicLoads> = loads.iter().filter(|h| h.m <= m).cloned().collect();
    let settings = iteration_settings(scene);
    let problem = Problem {
        model,
        factors,
        loads: &loads,
        laws,
        sections: &sections,
        elastic: Some(elastic),
        whole_up_to: None,
        from: None,
        cancel: None,
    };
    let stepping = scene.solver.loading.into();
    let result = solve(&problem, &settings, None, stepping, |_, _, _, _| (), |_| {}).map(|s| s.outcome);
    result.map_err(|e| {
        let h = e.history();
        format!(
            "{e} (after {} iterations, ratio {:.2e})",
            h.len(),
            h.last().map_or(f64::NAN, |r| r.ratio)
        )
    })
}

fn run_variant(args: &Args, variant: &str, rows: &mut Vec<Row>) -> Result<(), String> {
    let path = scene_path(variant);
    let mut scene = Scene::from_path(&path).map_err(|e| e.to_string())?;
    scene.mesh.parameters.insert("size".into(), args.size);
    if let Some(r) = args.refine {
        scene.mesh.parameters.insert("refine".into(), r);
    }
    scene.harmonics = args.harmonics.into();
    // The scene format's defaults: dealiased sections, default solver.
    scene.sections = None;
    scene.solver = SolverSettings {
        epsilon: args.epsilon,
        ..SolverSettings::default()
    };
    let refine = scene.mesh.parameters.get("refine").copied().unwrap_or(f64::NAN);
    let m_max = args.harmonics;
    if !scene.is_nonlinear() {
        return Err(format!("{variant}: no nonlinear joint"));
    }

    let (mesh_s, _, meshed) = once(|| mesh_scene(&scene, None));
    let (mesh, _) = meshed.map_err(|e| e.to_string())?;
    let (nodes, dof_guess) = (mesh.nodes.len(), 3 * mesh.nodes.len());
    let small = dof_guess < SMALL_DOF;
    let (reps, budget) = if small { (args.reps, 2.0) } else { (1, 0.0) };
    let since = (machine_busy_seconds(), cpu_seconds(), Instant::now());

    // The linear solve.
    let (loads_s, loads_c, loads) = once(|| assemble_loads(&scene, &mesh, m_max));
    let loads = loads.map_err(|e| e.to_string())?;
    let (setup_s, setup_c, model) = if small {
        timed(reps, budget, || build_model(&scene, mesh.clone()))
    } else {
        once(|| build_model(&scene, mesh))
    };
    let model = model.map_err(|e| e.to_string())?;
    let ms: Vec<u32> = (0..=m_max).collect();
    let (factorize_s, factorize_c, factors) = timed(reps, budget, || model.factorize_all(&ms));
    let factors = factors.map_err(|e| e.to_string())?;
    let (solve_s, solve_c, u_linear) = timed(reps, budget, || solve_loads(&model, &factors, &loads));
    let (reactions_s, reactions_c, _) = timed(reps, budget, || reactions(&scene, &model, &loads, &u_linear));
    let linear_s = loads_s + setup_s + factorize_s + solve_s + reactions_s;
    let linear_c = loads_c + setup_c + factorize_c + solve_c + reactions_c;
    let laws: Vec<JointLaw> = model
        .mesh
        .joints
        .iter()
        .map(|j| scene.joints[&j.name].law)
        .collect();
    let n_sections = scene_sections(&scene, &model, &loads)
        .map_err(|e| e.to_string())?
        .len();
    eprintln!(
        "bench_nonlinear: {variant}, size {} M {m_max}: {} DOF per harmonic, {n_sections} sections; \
         mesh {mesh_s:.2} s; linear {linear_s:.3} s (loads {loads_s:.3}, setup {setup_s:.3}, \
         factorize all {factorize_s:.3}, solve {solve_s:.4}, reactions {reactions_s:.3})",
        args.size,
        model.n_eq()
    );

    let mut base = Row::default();
    base.set("variant", variant);
    base.set("size", args.size);
    base.set("refine", refine);
    base.set("M", m_max);
    base.set("sections", n_sections);
    base.set("epsilon", format!("{:e}", args.epsilon));
    base.set("nodes", nodes);
    base.set("dof", model.n_eq());
    base.set("mesh_s", format!("{mesh_s:.4}"));
    base.set("loads_s", format!("{loads_s:.4}"));
    base.set("setup_s", format!("{setup_s:.4}"));
    base.set("factorize_s", format!("{factorize_s:.4}"));
    base.set("solve_s", format!("{solve_s:.5}"));
    base.set("reactions_s", format!("{reactions_s:.4}"));
    base.set("linear_s", format!("{linear_s:.4}"));
    base.set("linear_cpu_s", format!("{linear_c:.4}"));
    base.set("reps", reps);

    let first = rows.len();
    for &method in &args.methods {
        scene.solver.method = method;
        let name = method_name(method);
        let mut row = base.clone();
        row.set("method", name);
        // Per timed run: (first_s, sweep_s, outside_s) from the iteration's clock.
        let mut clock: Vec<(f64, f64, f64)> = Vec::new();
        let (iterate_s, iterate_c, outcome) = timed(reps, budget, || {
            let t = Instant::now();
            let out = iterate(&scene, &model, &factors, &loads, &laws, &u_linear, m_max);
            let wall = t.elapsed().as_secs_f64();
            if let Ok(o) = &out {
                let first = o.history.first().map_or(f64::NAN, |r| r.seconds);
                let last = o.history.last().map_or(f64::NAN, |r| r.seconds);
                let later: u32 = o.history.iter().skip(1).map(|r| r.solves).sum();
                let sweep = if later > 0 {
                    (last - first) / f64::from(later)
                } else {
                    f64::NAN
                };
                clock.push((first, sweep, wall - last));
            }
            out
        });
        row.set("iterate_s", format!("{iterate_s:.4}"));
        row.set("iterate_cpu_s", format!("{iterate_c:.4}"));
        let outcome = match outcome {
            Ok(o) => o,
            Err(e) => {
                eprintln!("  {name}: failed: {e}");
                row.set("status", format!("failed: {e}"));
                row.set("peak_mb", format!("{:.1}", peak_rss_mb()));
                row.set("others_cpus", format!("{:.2}", cpu::others_cpus(since)));
                rows.push(row);
                continue;
            }
        };
        let iterations = outcome.history.len();
        let sweeps: u32 = outcome.history.iter().map(|r| r.solves).sum();
        let final_ratio = outcome.history.last().map_or(f64::NAN, |r| r.ratio);
        // The M/2 comparison of `solve_scene` (M >= 2).
        let (check_s, check_c, check_iterations, status) = if m_max >= 2 {
            let (s, c, half) = timed(reps, budget, || {
                iterate(&scene, &model, &factors, &loads, &laws, &u_linear, m_max / 2)
            });
            match half {
                Ok(h) => (s, c, h.history.len().to_string(), "ok".to_string()),
                Err(e) => (s, c, String::new(), format!("M/2 check failed: {e}")),
            }
        } else {
            (0.0, 0.0, String::new(), "ok".to_string())
        };
        let (final_reactions_s, final_reactions_c, _) = timed(reps, budget, || {
            reactions(&scene, &model, &loads, &outcome.displacements)
        });
        let nonlinear_s = linear_s + iterate_s + check_s + final_reactions_s;
        let nonlinear_c = linear_c + iterate_c + check_c + final_reactions_c;
        let ratio = (linear_s + iterate_s) / linear_s;
        let ratio_scene = nonlinear_s / linear_s;
        let ratio_cpu = (linear_c + iterate_c) / linear_c;
        let per_sweep = iterate_s / f64::from(sweeps.max(1));
        let first_s = median(clock.iter().map(|c| c.0).collect());
        let sweep_s = median(clock.iter().map(|c| c.1).collect());
        let outside_s = median(clock.iter().map(|c| c.2).collect());
        let check_ratio = (linear_s + iterate_s + check_s) / linear_s;
        eprintln!(
            "  {name}: {iterations} iterations ({sweeps} sweeps, ratio {final_ratio:.1e}) {iterate_s:.3} s \
             (first sweep at {:.1} ms, then {:.2} ms a sweep, {:.1} ms outside the loop); M/2 check {check_s:.3} s ({check_iterations} it.); final reactions \
             {final_reactions_s:.3} s; (linear + iteration) / linear = {ratio:.2} (CPU {ratio_cpu:.2}); \
             whole solve_scene / linear = {ratio_scene:.2}{}",
            1e3 * first_s,
            1e3 * sweep_s,
            1e3 * outside_s,
            if status == "ok" {
                String::new()
            } else {
                format!("; {status}")
            }
        );
        row.set("joint_points", outcome.field.points.len());
        row.set("iterations", iterations);
        row.set("sweeps", sweeps);
        row.set("final_ratio", format!("{final_ratio:.3e}"));
        row.set("check_iterations", check_iterations);
        row.set("check_s", format!("{check_s:.4}"));
        row.set("check_cpu_s", format!("{check_c:.4}"));
        row.set("final_reactions_s", format!("{final_reactions_s:.4}"));
        row.set("nonlinear_s", format!("{nonlinear_s:.4}"));
        row.set("nonlinear_cpu_s", format!("{nonlinear_c:.4}"));
        row.set("ratio", format!("{ratio:.3}"));
        row.set("ratio_scene", format!("{ratio_scene:.3}"));
        row.set("ratio_cpu", format!("{ratio_cpu:.3}"));
        row.set("per_sweep_s", format!("{per_sweep:.6}"));
        row.set("sweep_s", format!("{sweep_s:.6}"));
        row.set("first_s", format!("{first_s:.5}"));
        row.set("outside_s", format!("{outside_s:.5}"));
        row.set("check_ratio", format!("{check_ratio:.3}"));
        row.set("peak_mb", format!("{:.1}", peak_rss_mb()));
        row.set("others_cpus", format!("{:.2}", cpu::others_cpus(since)));
        row.set("status", status);
        rows.push(row);
    }
    drop(factors);
    drop(model);

    // The library's own path, meshing included.
    if args.end_to_end {
        for (row, &method) in rows[first..].iter_mut().zip(&args.methods) {
            scene.solver.method = method;
            let (s, _, run) = once(|| solve_scene(&scene, None, |_| {}));
            row.set("e2e_s", format!("{s:.4}"));
            if let Ok(Some(o)) = run.map(|r| r.outcome) {
                row.set("e2e_iterations", o.history.len());
            }
        }
    }
    Ok(())
}

/// One CSV row, by column name (the header's order; missing values empty).
#[derive(Clone, Default)]
struct Row(std::collections::HashMap<&'static str, String>);

impl Row {
    fn set(&mut self, key: &'static str, value: impl ToString) {
        debug_assert!(HEADER.split(',').any(|k| k == key), "no column {key}");
        // Commas would shift the columns.
        self.0.insert(key, value.to_string().replace(',', ";"));
    }

    fn csv(&self) -> String {
        HEADER
            .split(',')
            .map(|k| self.0.get(k).map_or("", String::as_str))
            .collect::<Vec<_>>()
            .join(",")
    }
}

fn main() -> ExitCode {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    // As the `axijoint` binary: faer sequential inside each harmonic.
    axijoint_solver::linear::prefer_harmonic_parallelism();
    if args.header {
        println!("{HEADER}");
    }
    let mut failed = false;
    for variant in &args.variants {
        let mut rows = Vec::new();
        if let Err(e) = run_variant(&args, variant, &mut rows) {
            eprintln!("bench_nonlinear: {e}");
            failed = true;
        }
        for row in rows {
            println!("{}", row.csv());
        }
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
