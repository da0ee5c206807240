//! Benchmark driver of the linear solve (issue 3, item 5); `scripts/bench`
//! runs it. Meshes a scene (Scene P by default) at one element size, then
//!
//! 1. per harmonic, one harmonic at a time (the median over harmonics 1 and
//!    2, each timed several times on small models): assembly
//!    (`Model::assemble`), the numeric Cholesky alone (faer
//!    `Llt::try_new_with_symbolic` on the model's pattern and values, as
//!    `Model::factorize` calls it), `Model::factorize` (assembly + numeric
//!    Cholesky + probe solve) and one `Model::solve` call with two
//!    right-hand sides;
//! 2. the production path of `axijoint solve`: `Model::factorize_all` of
//!    harmonics 0..=M (rayon over harmonics, all factors kept) and the
//!    2-RHS solves of every harmonic in parallel (wall times);
//!
//! and prints one CSV row (`--header` prints the header first). `--par`
//! sets faer's parallelism inside one factorization or solve: `binary` (the
//! default) as the `axijoint` binary does
//! (`linear::prefer_harmonic_parallelism`), `seq` (`Par::Seq`) or `rayon`
//! (`Par::rayon(0)`, faer's own default). Times are
//! wall seconds; the `_cpu_s` columns are CPU seconds of all threads
//! (`CLOCK_PROCESS_CPUTIME_ID`), which do not grow while other processes
//! hold the CPUs; `others_cpus` is the average number of CPUs other
//! processes kept busy during steps 1 and 2 (from `/proc/stat`): above ~0.2
//! the wall times are inflated. Peak memory is the process's RSS high-water
//! mark (`VmHWM`, MiB): after step 1 (one factor alive) and at the end
//! (M + 1 factors alive). gmsh runs as a child process and is not included.
//!
//! Columns appended after `others_cpus` (for the scaling study,
//! `scripts/bench --scaling`): `setup_cpu_s` (pattern and symbolic
//! factorization), `total_s` / `total_cpu_s` = setup + `factorize_all` +
//! the 2-RHS solves of all harmonics (a linear run with every harmonic,
//! meshing excluded), `factor_mb` (8 bytes x nnz(L), one kept factor),
//! `est_peak_mb` (the peak this run was expected to reach) and
//! `mem_available_mb` (`MemAvailable` when it started).
//!
//! Before factorizing, the run estimates the memory the M + 1 kept
//! factors need (from nnz(L) of the symbolic factorization) and refuses to
//! run (exit code 3, a message on stderr) when it exceeds what the machine
//! has available less a 1 GiB reserve; `--no-mem-check` skips the check.
//! `--sample K` times harmonics 1..=K in step 1 (default 2; 1 halves the
//! time of the largest meshes).
//!
//! ```text
//! cargo run --release -p axijoint-solver --example bench_linear -- \
//!     --size 0.04 --harmonics 16 [--refine 2] [--par binary|seq|rayon] \
//!     [--scene geo/pile_footing.json] [--sample 1|2] [--no-mem-check] [--header]
//! cargo run --release -p axijoint-solver --example bench_linear -- --print-header
//! ```

use axijoint_solver::assembly::Pattern;
use axijoint_solver::run::{build_model, mesh_scene};
use axijoint_solver::scene::Scene;
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, SymbolicCholeskyRaw};
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::Side;
use rayon::prelude::*;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[path = "../benches/support/cpu.rs"]
mod cpu;
use cpu::{cpu_seconds, machine_busy_seconds, mem_available_mb, peak_rss_mb, rss_mb};

/// Exit code of a run refused for lack of memory.
const EXIT_NO_MEMORY: u8 = 3;

/// Memory kept free for the rest of the machine, MiB.
const RESERVE_MB: f64 = 1024.0;

const HEADER: &str = "scene,size,refine,M,par,threads,nodes,cells,dof,nnz_K,nnz_L,supernodal,\
mesh_s,setup_s,assemble_s,numeric_s,factorize_s,solve2_s,\
assemble_cpu_s,numeric_cpu_s,factorize_cpu_s,solve2_cpu_s,\
factorize_all_s,factorize_all_cpu_s,solve_all_s,solve_all_cpu_s,\
factorize_all_per_h_s,solve_all_per_h_s,peak_one_mb,peak_mb,others_cpus,\
setup_cpu_s,total_s,total_cpu_s,factor_mb,est_peak_mb,mem_available_mb";

struct Args {
    scene: PathBuf,
    size: f64,
    refine: Option<f64>,
    harmonics: u32,
    par: String,
    header: bool,
    sample: u32,
    mem_check: bool,
}

fn usage() -> String {
    "usage: bench_linear --size S --harmonics M [--refine R] [--par binary|seq|rayon] [--scene FILE]\n                    [--sample 1|2] [--no-mem-check] [--header]\n       bench_linear --print-header"
        .into()
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        scene: PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../geo/pile_footing.json"
        )),
        size: f64::NAN,
        refine: None,
        harmonics: 4,
        par: "binary".into(),
        header: false,
        sample: 2,
        mem_check: true,
    };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = |name: &str| {
            it.next()
                .ok_or_else(|| format!("{name} needs a value\n{}", usage()))
        };
        let num = |s: String, name: &str| s.parse::<f64>().map_err(|e| format!("{name}: {e}"));
        match a.as_str() {
            "--scene" => args.scene = PathBuf::from(value("--scene")?),
            "--size" => args.size = num(value("--size")?, "--size")?,
            "--refine" => args.refine = Some(num(value("--refine")?, "--refine")?),
            "--harmonics" => {
                args.harmonics = value("--harmonics")?
                    .parse()
                    .map_err(|e| format!("--harmonics: {e}"))?
            }
            "--par" => args.par = value("--par")?,
            "--header" => args.header = true,
            "--sample" => args.sample = value("--sample")?.parse().map_err(|e| format!("--sample: {e}"))?,
            "--no-mem-check" => args.mem_check = false,
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
    Ok(args)
}

/// Median wall and CPU times of `f`, repeated until `budget` seconds are
/// spent (at least once, at most `max_reps` times), and its last result.
fn timed<T>(budget: f64, max_reps: usize, mut f: impl FnMut() -> T) -> (f64, f64, T) {
    let (mut wall, mut cpu) = (Vec::new(), Vec::new());
    let start = Instant::now();
    loop {
        let (t, c) = (Instant::now(), cpu_seconds());
        let out = f();
        wall.push(t.elapsed().as_secs_f64());
        cpu.push(cpu_seconds() - c);
        if wall.len() >= max_reps || start.elapsed().as_secs_f64() >= budget {
            return (median(wall), median(cpu), out);
        }
        drop(out);
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Deterministic node-DOF load vectors (the solve cost does not depend on them).
fn loads(n_dofs: usize) -> (Vec<f64>, Vec<f64>) {
    let a = (0..n_dofs)
        .map(|i| ((i as f64 + 1.0) * 0.754_877_666).fract() - 0.5)
        .collect();
    let b = (0..n_dofs)
        .map(|i| ((i as f64 + 1.0) * 0.569_840_291).fract() - 0.5)
        .collect();
    (a, b)
}

fn pattern_ref(p: &Pattern) -> SymbolicSparseColMatRef<'_, usize> {
    SymbolicSparseColMatRef::new_checked(p.n, p.n, &p.col_ptr, None, &p.row_idx)
}

/// Entries of the Cholesky factor and whether faer chose the supernodal kind.
fn factor_size(pattern: &Pattern) -> (usize, bool) {
    match factorize_symbolic_cholesky(
        pattern_ref(pattern),
        Side::Upper,
        Default::default(),
        Default::default(),
    ) {
        Ok(s) => (s.len_val(), matches!(s.raw(), SymbolicCholeskyRaw::Supernodal(_))),
        Err(_) => (0, false),
    }
}

/// Why a run failed: an error, or not enough memory (exit code 3).
enum Failure {
    Error(String),
    NoMemory(String),
}

impl From<String> for Failure {
    fn from(e: String) -> Self {
        Failure::Error(e)
    }
}

impl From<&str> for Failure {
    fn from(e: &str) -> Self {
        Failure::Error(e.into())
    }
}

fn run(args: &Args) -> Result<String, Failure> {
    match args.par.as_str() {
        // As the `axijoint` binary sets it.
        "binary" => axijoint_solver::linear::prefer_harmonic_parallelism(),
        "seq" => faer::set_global_parallelism(faer::Par::Seq),
        "rayon" => faer::set_global_parallelism(faer::Par::rayon(0)),
        other => return Err(format!("--par {other}: expected binary, seq or rayon").into()),
    }
    let mut scene = Scene::from_path(&args.scene).map_err(|e| e.to_string())?;
    scene.mesh.parameters.insert("size".into(), args.size);
    if let Some(r) = args.refine {
        scene.mesh.parameters.insert("refine".into(), r);
    }
    scene.harmonics = args.harmonics.into();
    let refine = scene.mesh.parameters.get("refine").copied().unwrap_or(f64::NAN);
    let m_max = args.harmonics;

    let t = Instant::now();
    let (mesh, _) = mesh_scene(&scene, None).map_err(|e| e.to_string())?;
    let mesh_s = t.elapsed().as_secs_f64();
    let (nodes, cells) = (mesh.nodes.len(), mesh.cells.len());
    let mem_available = mem_available_mb();
    let (t, c) = (Instant::now(), cpu_seconds());
    let model = build_model(&scene, mesh).map_err(|e| e.to_string())?;
    let setup_s = t.elapsed().as_secs_f64();
    let setup_cpu_s = cpu_seconds() - c;
    let pattern = model.pattern().clone();
    if pattern.nnz() != model.nnz() {
        return Err("the model's own pattern differs from the model's".into());
    }
    let (nnz_l, supernodal) = factor_size(&pattern);
    eprintln!(
        "bench_linear: size {} M {m_max}: {} DOF per harmonic, nnz(K) {}, nnz(L) {nnz_l}; mesh {mesh_s:.2} s, setup {setup_s:.2} s",
        args.size,
        model.n_eq(),
        model.nnz()
    );
    // Memory: M + 1 kept factors (8 bytes per entry of L; measured 0.94-1.0
    // of that per extra harmonic) and two harmonics' values in flight.
    let mib = 1024.0 * 1024.0;
    let factor_mb = 8.0 * nnz_l as f64 / mib;
    let in_flight = 2.0 * 8.0 * model.nnz() as f64 / mib;
    let need = (f64::from(m_max) + 1.0) * factor_mb + in_flight;
    let est_peak = rss_mb() + need;
    let available_now = mem_available_mb();
    // 10 % margin: the kept factors measured 0.94-1.0 of 8 nnz(L) each, and
    // at 1e6 DOF the peak exceeded this estimate by 8 % (faer's workspace).
    if args.mem_check && available_now.is_finite() && 1.1 * need > available_now - RESERVE_MB {
        return Err(Failure::NoMemory(format!(
            "not enough memory for {} kept factors of {} DOF: they need about {:.1} GiB \
             ({:.2} GiB each, nnz(L) = {nnz_l}, plus 10 %), {:.1} GiB are available (less a {:.0} GiB reserve); \
             lower M or the mesh size, or free memory (--no-mem-check to try anyway)",
            m_max + 1,
            model.n_eq(),
            1.1 * need / 1024.0,
            factor_mb / 1024.0,
            available_now / 1024.0,
            RESERVE_MB / 1024.0
        )));
    }
    let (fa, fb) = loads(3 * nodes);

    // CPUs used by other processes while we measure (phases 1 and 2).
    let (busy0, cpu0, t0) = (machine_busy_seconds(), cpu_seconds(), Instant::now());

    // 1. Per harmonic, one at a time (harmonics 1 and 2: every harmonic has
    //    the same pattern and cost).
    let small = model.n_eq() < 200_000;
    let (budget, reps) = if small { (1.0, 9) } else { (0.0, 1) };
    // (wall, CPU) per sampled harmonic.
    let (mut asm, mut num, mut fac, mut sol) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    {
        let symbolic =
            SymbolicLlt::try_new(pattern_ref(&pattern), Side::Upper).map_err(|e| format!("{e:?}"))?;
        let sample: Vec<u32> = if m_max == 0 {
            vec![0]
        } else {
            (1..=m_max.min(args.sample.max(1))).collect()
        };
        for m in sample {
            let (ta, ca, (values, _)) = timed(budget, reps, || model.assemble(m));
            let mat = SparseColMatRef::new(pattern_ref(&pattern), &values);
            let (tn, cn, llt) = timed(budget, reps, || {
                Llt::try_new_with_symbolic(symbolic.clone(), mat, Side::Upper)
            });
            llt.map_err(|e| format!("harmonic {m}: {e:?}"))?;
            let (tf, cf, factor) = timed(budget, reps, || model.factorize(m));
            let factor = factor.map_err(|e| e.to_string())?;
            let (ts, cs, _) = timed(budget, reps.max(3), || model.solve(&factor, &[&fa, &fb]));
            eprintln!(
                "  m = {m}: assemble {ta:.4} s ({ca:.4} CPU s), numeric Cholesky {tn:.4} s ({cn:.4}), \
                 Model::factorize {tf:.4} s ({cf:.4}), solve(2 RHS) {ts:.4} s ({cs:.4})"
            );
            asm.push((ta, ca));
            num.push((tn, cn));
            fac.push((tf, cf));
            sol.push((ts, cs));
        }
    }
    drop(pattern);
    let wall = |v: &[(f64, f64)]| median(v.iter().map(|x| x.0).collect());
    let cpu = |v: &[(f64, f64)]| median(v.iter().map(|x| x.1).collect());
    let peak_one = peak_rss_mb();

    // 2. The production path: all harmonics, in parallel, factors kept.
    let ms: Vec<u32> = (0..=m_max).collect();
    let (t, c) = (Instant::now(), cpu_seconds());
    let factors = model.factorize_all(&ms).map_err(|e| e.to_string())?;
    let fall = t.elapsed().as_secs_f64();
    let fall_cpu = cpu_seconds() - c;
    let (t, c) = (Instant::now(), cpu_seconds());
    let solved: usize = factors
        .par_iter()
        .map(|f| model.solve(f, &[&fa, &fb]).len())
        .sum();
    let sall = t.elapsed().as_secs_f64();
    let sall_cpu = cpu_seconds() - c;
    assert_eq!(solved, 2 * ms.len());
    let peak = peak_rss_mb();
    let others = cpu::others_cpus((busy0, cpu0, t0));
    eprintln!("  all {} harmonics: factorize_all {fall:.3} s ({fall_cpu:.2} CPU s), solves {sall:.3} s, peak {peak:.0} MiB", ms.len());
    drop(factors);

    let h = ms.len() as f64;
    let scene_name = args
        .scene
        .file_stem()
        .map_or("?".into(), |s| s.to_string_lossy().into_owned());
    Ok(format!(
        "{scene_name},{},{refine},{m_max},{},{},{nodes},{cells},{},{},{nnz_l},{},{mesh_s:.4},{setup_s:.4},\
         {:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{fall:.4},{fall_cpu:.4},{sall:.4},{sall_cpu:.4},{:.6},{:.6},{peak_one:.1},{peak:.1},{others:.2},\
         {setup_cpu_s:.4},{:.4},{:.4},{factor_mb:.1},{est_peak:.1},{mem_available:.0}",
        args.size,
        args.par,
        rayon::current_num_threads(),
        model.n_eq(),
        model.nnz(),
        u8::from(supernodal),
        wall(&asm),
        wall(&num),
        wall(&fac),
        wall(&sol),
        cpu(&asm),
        cpu(&num),
        cpu(&fac),
        cpu(&sol),
        fall / h,
        sall / h,
        setup_s + fall + sall,
        setup_cpu_s + fall_cpu + sall_cpu,
    ))
}

fn main() -> ExitCode {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    if args.header {
        println!("{HEADER}");
    }
    match run(&args) {
        Ok(row) => {
            println!("{row}");
            ExitCode::SUCCESS
        }
        Err(Failure::Error(e)) => {
            eprintln!("bench_linear: {e}");
            ExitCode::FAILURE
        }
        Err(Failure::NoMemory(e)) => {
            eprintln!("bench_linear: refused: {e}");
            ExitCode::from(EXIT_NO_MEMORY)
        }
    }
}
