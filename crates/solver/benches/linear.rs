//! Micro-measurements of the linear solve on Scene P (issue 3, item 5 and
//! the solver settings of item 3). A `harness = false` bench:
//!
//! ```text
//! cargo bench -p axijoint-solver --bench linear
//! AXIJOINT_BENCH_SIZE=0.039 AXIJOINT_BENCH_REPS=5 cargo bench -p axijoint-solver --bench linear
//! ```
//!
//! `AXIJOINT_BENCH_SIZE` is the gmsh element size (default 0.12, about 1.1e4
//! DOF per harmonic), `AXIJOINT_BENCH_REPS` the rounds (default 15),
//! `AXIJOINT_BENCH_M` the highest harmonic of the `factorize_all` case
//! (default 4), `AXIJOINT_BENCH_PATIENCE` how long a group may wait for a
//! quiet machine (default 120 s), `AXIJOINT_BENCH_ONLY` a comma list of the
//! groups to run (`assembly`, `factorization`, `solves`; default all). The cases of a group run interleaved,
//! round by round, so a load change hits all of them alike; a round counts
//! only if other processes used less than 0.1 CPU meanwhile (from
//! `/proc/stat`), unless fewer than 3 rounds were quiet (then all count and
//! the group says so). Each case reports the minimum and median wall time
//! and the median CPU time (`CLOCK_PROCESS_CPUTIME_ID`, all threads); the
//! ratios are of medians, wall and CPU.
//!
//! Groups:
//! - assembly of one harmonic: `Model::assemble`, the element matrices
//!   alone, a copy of the library's scatter (binary search per entry in
//!   `Pattern::slot`) and the same scatter through slots looked up once;
//! - numeric Cholesky of one harmonic with faer `Par::Seq` and
//!   `Par::rayon(0)` (faer's default), on the model's pattern;
//!   `Model::factorize` (assembly + numeric + probe) and
//!   `Model::factorize_all(0..=M)` (rayon over harmonics) with both settings;
//! - solves: one call with 2 right-hand sides against two calls with 1,
//!   through `Model::solve` and through faer directly, with both settings.

use axijoint_solver::assembly::Pattern;
use axijoint_solver::elements::{joint_stiffness, solid_stiffness, SolidScratch};
use axijoint_solver::linear::Model;
use axijoint_solver::run::{build_model, mesh_scene};
use axijoint_solver::scene::Scene;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Mat, Par, Side};
use nalgebra::DMatrix;
use std::hint::black_box;
use std::time::Instant;

#[path = "support/cpu.rs"]
mod cpu;
use cpu::{cpu_seconds, machine_busy_seconds};

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Average number of CPUs other processes kept busy over `seconds` of wall
/// time, from the machine's busy time and this process's CPU time.
fn others_cores(busy: f64, own_cpu: f64, seconds: f64) -> f64 {
    ((busy - own_cpu) / seconds).max(0.0)
}

/// Waits (up to `until`) for a second in which other processes use less
/// than `QUIET` of a CPU.
fn wait_for_quiet(until: Instant) {
    while Instant::now() < until {
        let (b0, c0) = (machine_busy_seconds(), cpu_seconds());
        std::thread::sleep(std::time::Duration::from_millis(1000));
        if others_cores(machine_busy_seconds() - b0, cpu_seconds() - c0, 1.0) < QUIET {
            return;
        }
    }
}

/// Rounds in which other processes used less than this many CPUs on average
/// are "quiet"; the statistics use only those when there are enough.
const QUIET: f64 = 0.1;

/// One measured case: a name, a faer setting and the work.
struct Case<'a> {
    name: &'static str,
    par: Par,
    work: Box<dyn FnMut() + 'a>,
    /// (wall, CPU) per round, seconds.
    times: Vec<(f64, f64)>,
}

fn med(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

impl<'a> Case<'a> {
    fn new(name: &'static str, par: Par, work: impl FnMut() + 'a) -> Self {
        Case {
            name,
            par,
            work: Box::new(work),
            times: Vec::new(),
        }
    }
    fn min(&self) -> f64 {
        self.times.iter().map(|t| t.0).fold(f64::INFINITY, f64::min)
    }
    fn median(&self) -> f64 {
        med(self.times.iter().map(|t| t.0).collect())
    }
    fn cpu(&self) -> f64 {
        med(self.times.iter().map(|t| t.1).collect())
    }
}

/// Runs the cases interleaved, round by round (after one warm-up round),
/// until `reps` rounds were quiet (other processes below `QUIET` CPUs) or
/// `patience` seconds have passed; after a busy round it waits for a quiet
/// second before the next. Prints the minimum and median wall time and the
/// median CPU time (all threads; rayon's idle workers spin a little, which
/// counts) over the quiet rounds, or over all rounds if fewer than 3 were
/// quiet.
fn run_group(title: &str, reps: usize, patience: f64, cases: &mut [Case<'_>]) {
    let until = Instant::now() + std::time::Duration::from_secs_f64(patience);
    let mut raw: Vec<Vec<(f64, f64)>> = vec![Vec::new(); cases.len()];
    let mut quiet_flags = Vec::new();
    let mut others_sum = 0.0;
    let mut round = 0;
    loop {
        let (b0, c0, t0) = (machine_busy_seconds(), cpu_seconds(), Instant::now());
        for (c, r) in cases.iter_mut().zip(raw.iter_mut()) {
            faer::set_global_parallelism(c.par);
            let c0 = cpu_seconds();
            let t = Instant::now();
            (c.work)();
            let dt = t.elapsed().as_secs_f64();
            let c1 = cpu_seconds();
            if round > 0 {
                r.push((dt, c1 - c0));
            }
        }
        let wall = t0.elapsed().as_secs_f64();
        let others = others_cores(machine_busy_seconds() - b0, cpu_seconds() - c0, wall);
        let quiet = others < QUIET;
        if round > 0 {
            quiet_flags.push(quiet);
            others_sum += others;
        }
        round += 1;
        let n_quiet = quiet_flags.iter().filter(|&&q| q).count();
        let timed_out = Instant::now() >= until;
        if round > reps && (n_quiet >= reps || timed_out) {
            break;
        }
        if !quiet && !timed_out {
            wait_for_quiet(until);
        }
    }
    faer::set_global_parallelism(Par::rayon(0));
    let n_quiet = quiet_flags.iter().filter(|&&q| q).count();
    let use_quiet = n_quiet >= 3.min(reps);
    for (c, r) in cases.iter_mut().zip(raw) {
        c.times = r
            .into_iter()
            .zip(&quiet_flags)
            .filter(|(_, &q)| q || !use_quiet)
            .map(|(t, _)| t)
            .collect();
    }
    println!(
        "\n## {title} ({} of {} rounds quiet, other processes {:.2} CPUs on average; statistics over {})",
        n_quiet,
        quiet_flags.len(),
        others_sum / quiet_flags.len() as f64,
        if use_quiet {
            "the quiet rounds"
        } else {
            "ALL rounds: the machine was busy, wall times are inflated"
        }
    );
    println!("{:<52} {:>9} {:>9} {:>9}", "case", "min ms", "wall ms", "CPU ms");
    for c in cases.iter() {
        println!(
            "{:<52} {:>9.3} {:>9.3} {:>9.3}",
            c.name,
            1e3 * c.min(),
            1e3 * c.median(),
            1e3 * c.cpu()
        );
    }
}

fn median_of(cases: &[Case<'_>], name: &str) -> f64 {
    cases
        .iter()
        .find(|c| c.name == name)
        .map_or(f64::NAN, Case::median)
}

fn cpu_of(cases: &[Case<'_>], name: &str) -> f64 {
    cases.iter().find(|c| c.name == name).map_or(f64::NAN, Case::cpu)
}

/// `a / b` of the median wall times, and of the median CPU times.
fn ratio(cases: &[Case<'_>], a: &str, b: &str) -> String {
    format!(
        "{:.2} (CPU {:.2})",
        median_of(cases, a) / median_of(cases, b),
        cpu_of(cases, a) / cpu_of(cases, b)
    )
}

/// Every element's stiffness of harmonic `m`, handed to `f(element, nodes, K_e)`
/// (cells, then joint elements, as the library's loop).
fn for_each_element(model: &Model, m: u32, mut f: impl FnMut(usize, &[usize], &DMatrix<f64>)) {
    let mesh = &model.mesh;
    let mut scratch = SolidScratch::new(axijoint_mesh::CellKind::Quad9);
    let mut ke = DMatrix::zeros(0, 0);
    let mut coords: Vec<[f64; 2]> = Vec::with_capacity(9);
    let mut nodes: Vec<usize> = Vec::with_capacity(12);
    let mut index = 0;
    for cell in &mesh.cells {
        coords.clear();
        coords.extend(cell.nodes.iter().map(|&n| mesh.nodes[n]));
        solid_stiffness(
            cell.kind,
            &coords,
            &model.materials[cell.body],
            m,
            &mut scratch,
            &mut ke,
        );
        f(index, &cell.nodes, &ke);
        index += 1;
    }
    for (joint, props) in mesh.joints.iter().zip(&model.joints) {
        for el in &joint.elements {
            coords.clear();
            coords.extend(el.bottom.iter().map(|&n| mesh.nodes[n]));
            joint_stiffness(el.kind, &coords, &props.springs, m, props.rule, &mut ke);
            nodes.clear();
            nodes.extend_from_slice(&el.bottom);
            nodes.extend_from_slice(&el.top);
            f(index, &nodes, &ke);
            index += 1;
        }
    }
}

/// Per element, the slots of its (a, term, b, term) pairs with `ea <= eb`,
/// in the scatter's order: looked up once, reused by every harmonic.
struct SlotTable {
    start: Vec<usize>,
    entries: Vec<(u32, u32, f64)>, // (local a * 64 + b, equation ea, coefficient)
    slots: Vec<u32>,
}

impl SlotTable {
    fn new(pattern: &Pattern, model: &Model) -> SlotTable {
        let dofs = &model.dofs;
        let mut table = SlotTable {
            start: vec![0],
            entries: Vec::new(),
            slots: Vec::new(),
        };
        let mut visit = |nodes: &[usize]| {
            let nd = 3 * nodes.len();
            for a in 0..nd {
                let da = 3 * nodes[a / 3] + a % 3;
                for (ea, ca) in dofs.terms(da) {
                    for b in 0..nd {
                        let db = 3 * nodes[b / 3] + b % 3;
                        for (eb, cb) in dofs.terms(db) {
                            if ea <= eb {
                                table.entries.push(((a * 64 + b) as u32, ea as u32, ca * cb));
                                table.slots.push(pattern.slot(ea, eb) as u32);
                            }
                        }
                    }
                }
            }
            table.start.push(table.slots.len());
        };
        for c in &model.mesh.cells {
            visit(&c.nodes);
        }
        for j in &model.mesh.joints {
            for e in &j.elements {
                let nodes: Vec<usize> = e.bottom.iter().chain(&e.top).copied().collect();
                visit(&nodes);
            }
        }
        table
    }

    /// Scatter of element `index` (pinned rows and columns skipped).
    fn scatter(&self, index: usize, pinned_slot: &[bool], ke: &DMatrix<f64>, values: &mut [f64]) {
        for k in self.start[index]..self.start[index + 1] {
            let slot = self.slots[k] as usize;
            if pinned_slot[slot] {
                continue;
            }
            let (ab, _, c) = self.entries[k];
            let (a, b) = ((ab / 64) as usize, (ab % 64) as usize);
            values[slot] += c * ke[(a, b)];
        }
    }
}

/// Slots in a pinned row or column of harmonic `m`.
fn pinned_slots(pattern: &Pattern, pinned: &[bool]) -> Vec<bool> {
    let mut out = vec![false; pattern.nnz()];
    for col in 0..pattern.n {
        for k in pattern.col_ptr[col]..pattern.col_ptr[col + 1] {
            out[k] = pinned[col] || pinned[pattern.row_idx[k]];
        }
    }
    out
}

fn main() {
    let size: f64 = env_or("AXIJOINT_BENCH_SIZE", 0.12);
    let reps: usize = env_or("AXIJOINT_BENCH_REPS", 15);
    let m_max: u32 = env_or("AXIJOINT_BENCH_M", 4);
    let patience: f64 = env_or("AXIJOINT_BENCH_PATIENCE", 120.0);
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../geo/pile_footing.json");
    let mut scene = Scene::from_path(path).expect("Scene P");
    scene.mesh.parameters.insert("size".into(), size);
    scene.harmonics = m_max.into();
    let (mesh, _) = mesh_scene(&scene, None).expect("gmsh meshes Scene P");
    let model = build_model(&scene, mesh).expect("model");
    let pattern = model.pattern().clone();
    assert_eq!(pattern.nnz(), model.nnz(), "the bench's pattern is the model's");
    let n = model.n_eq();
    println!(
        "# axijoint linear micro-benchmark: Scene P, size {size}, {} nodes, {} cells, {n} DOF per harmonic, nnz(K upper) {}, {} rayon threads",
        model.mesh.nodes.len(),
        model.mesh.cells.len(),
        model.nnz(),
        rayon::current_num_threads()
    );
    if let Ok(l) = std::fs::read_to_string("/proc/loadavg") {
        println!("# load average at start: {}", l.trim());
    }
    let m = 2;
    let only = std::env::var("AXIJOINT_BENCH_ONLY").unwrap_or_default();
    let want = |group: &str| only.is_empty() || only.split(',').any(|g| g.trim() == group);

    // Assembly.
    let asm_cpu = if want("assembly") {
        let pinned = model.dofs.pinned(m);
        let table = SlotTable::new(&pattern, &model);
        let pinned_slot = pinned_slots(&pattern, &pinned);
        {
            // The slot-table scatter gives the library's values.
            let (lib, _) = model.assemble(m);
            let mut mine = vec![0.0; pattern.nnz()];
            for_each_element(&model, m, |i, _, ke| {
                table.scatter(i, &pinned_slot, ke, &mut mine)
            });
            let worst = lib
                .iter()
                .zip(&mine)
                .enumerate()
                .filter(|(k, _)| !pinned_slot[*k])
                .map(|(_, (a, b))| (a - b).abs() / a.abs().max(1e-300))
                .filter(|r| r.is_finite())
                .fold(0.0f64, f64::max);
            assert!(
                worst < 1e-9,
                "slot-table scatter differs from Model::assemble: {worst:e}"
            );
        }
        // K_m / c_m is a quadratic polynomial in m (B_m = B_a + m B_b): three
        // value arrays, from harmonics 2, 3, 4, give every harmonic m >= 2.
        let poly: [Vec<f64>; 3] = {
            let v: Vec<Vec<f64>> = (2..=4)
                .map(|k| {
                    let c = axijoint_solver::elements::c_m(k);
                    model.assemble(k).0.iter().map(|x| x / c).collect()
                })
                .collect();
            let c2: Vec<f64> = (0..v[0].len())
                .map(|i| (v[2][i] - 2.0 * v[1][i] + v[0][i]) / 2.0)
                .collect();
            let c1: Vec<f64> = (0..v[0].len()).map(|i| v[1][i] - v[0][i] - 5.0 * c2[i]).collect();
            let c0: Vec<f64> = (0..v[0].len())
                .map(|i| v[0][i] - 2.0 * c1[i] - 4.0 * c2[i])
                .collect();
            [c0, c1, c2]
        };
        let from_poly = |k: u32| -> Vec<f64> {
            let (c, x) = (axijoint_solver::elements::c_m(k), f64::from(k));
            (0..poly[0].len())
                .map(|i| c * (poly[0][i] + x * poly[1][i] + x * x * poly[2][i]))
                .collect()
        };
        {
            let k = m_max.max(4) + 3;
            let (lib, _) = model.assemble(k);
            let pinned_k = pinned_slots(&pattern, &model.dofs.pinned(k));
            let scale = lib.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let worst = lib
                .iter()
                .zip(from_poly(k))
                .zip(&pinned_k)
                .filter(|(_, &p)| !p)
                .map(|((a, b), _)| (a - b).abs() / scale)
                .fold(0.0f64, f64::max);
            println!("# K_m from the three arrays of m = 2, 3, 4 vs Model::assemble({k}): max error {worst:.1e} of max |K|");
        }
        let mut asm = [
            Case::new("assemble: Model::assemble", Par::Seq, || {
                black_box(model.assemble(m));
            }),
            Case::new("assemble: element matrices only", Par::Seq, || {
                let mut s = 0.0;
                for_each_element(&model, m, |_, _, ke| s += ke[(0, 0)]);
                black_box(s);
            }),
            Case::new("assemble: elements + scatter (binary search)", Par::Seq, || {
                let mut values = vec![0.0; pattern.nnz()];
                for_each_element(&model, m, |_, nodes, ke| {
                    axijoint_solver::assembly::scatter(&pattern, &model.dofs, &pinned, nodes, ke, &mut values)
                });
                black_box(values);
            }),
            Case::new("assemble: elements + scatter (slot table)", Par::Seq, || {
                let mut values = vec![0.0; pattern.nnz()];
                for_each_element(&model, m, |i, _, ke| {
                    table.scatter(i, &pinned_slot, ke, &mut values)
                });
                black_box(values);
            }),
            Case::new(
                "assemble: K_m = c_m (K_0 + m K_1 + m^2 K_2), stored",
                Par::Seq,
                || {
                    black_box(from_poly(m));
                },
            ),
        ];
        run_group(&format!("assembly of harmonic {m}"), reps, patience, &mut asm);
        let lib = "assemble: Model::assemble";
        println!(
            "element matrices / Model::assemble: {}",
            ratio(&asm, "assemble: element matrices only", lib)
        );
        println!(
            "copy of the library (elements + binary-search scatter) / Model::assemble: {}",
            ratio(&asm, "assemble: elements + scatter (binary search)", lib)
        );
        println!(
            "slot-table scatter / binary-search scatter (whole assembly): {}",
            ratio(
                &asm,
                "assemble: elements + scatter (slot table)",
                "assemble: elements + scatter (binary search)"
            )
        );
        println!(
            "stored polynomial / Model::assemble: {}",
            ratio(&asm, "assemble: K_m = c_m (K_0 + m K_1 + m^2 K_2), stored", lib)
        );
        println!(
            "slot table: {} entries, {:.1} MiB",
            table.slots.len(),
            (table.slots.len() * 4 + table.entries.len() * 16) as f64 / 1048576.0
        );

        Some(cpu_of(&asm, lib))
    } else {
        None
    };

    // Numeric factorization (the symbolic analysis and one harmonic's values
    // are shared with the solves).
    let sym_ref = SymbolicSparseColMatRef::new_checked(n, n, &pattern.col_ptr, None, &pattern.row_idx);
    let symbolic = SymbolicLlt::try_new(sym_ref, Side::Upper).expect("symbolic");
    let (values, _) = model.assemble(m);
    let mat = SparseColMatRef::new(sym_ref, &values);
    let numeric = || Llt::try_new_with_symbolic(symbolic.clone(), mat, Side::Upper).expect("SPD");
    let fac_res = if want("factorization") {
        let ms: Vec<u32> = (0..=m_max).collect();
        let mut fac = [
            Case::new("numeric Cholesky, Par::Seq", Par::Seq, || {
                black_box(numeric());
            }),
            Case::new("numeric Cholesky, Par::rayon(0)", Par::rayon(0), || {
                black_box(numeric());
            }),
            Case::new("Model::factorize, Par::Seq", Par::Seq, || {
                black_box(model.factorize(m).expect("factor"));
            }),
            Case::new("Model::factorize, Par::rayon(0)", Par::rayon(0), || {
                black_box(model.factorize(m).expect("factor"));
            }),
            Case::new("Model::factorize_all(0..=M), Par::Seq", Par::Seq, || {
                black_box(model.factorize_all(&ms).expect("factors"));
            }),
            Case::new(
                "Model::factorize_all(0..=M), Par::rayon(0)",
                Par::rayon(0),
                || {
                    black_box(model.factorize_all(&ms).expect("factors"));
                },
            ),
        ];
        run_group(
            &format!("factorization (harmonic {m}; factorize_all: M = {m_max})"),
            reps,
            patience,
            &mut fac,
        );
        let t_fz_seq = median_of(&fac, "Model::factorize, Par::Seq");
        let t_all_seq = median_of(&fac, "Model::factorize_all(0..=M), Par::Seq");
        let t_all_ray = median_of(&fac, "Model::factorize_all(0..=M), Par::rayon(0)");
        println!(
            "rayon(0) / Seq: numeric {}, Model::factorize {}, factorize_all {}",
            ratio(
                &fac,
                "numeric Cholesky, Par::rayon(0)",
                "numeric Cholesky, Par::Seq"
            ),
            ratio(
                &fac,
                "Model::factorize, Par::rayon(0)",
                "Model::factorize, Par::Seq"
            ),
            ratio(
                &fac,
                "Model::factorize_all(0..=M), Par::rayon(0)",
                "Model::factorize_all(0..=M), Par::Seq"
            )
        );
        println!(
            "factorize_all(0..=M) / (M + 1) / Model::factorize (wall; 0.5 = perfect on 2 idle cores): Seq {:.2}, rayon(0) {:.2}",
            t_all_seq / ms.len() as f64 / t_fz_seq,
            t_all_ray / ms.len() as f64 / median_of(&fac, "Model::factorize, Par::rayon(0)")
        );

        Some((cpu_of(&fac, "numeric Cholesky, Par::Seq"), t_fz_seq))
    } else {
        None
    };

    // Solves.
    let sol_cpu = if want("solves") {
        let factor = model.factorize(m).expect("factor");
        let llt = {
            faer::set_global_parallelism(Par::Seq);
            numeric()
        };
        let n_dofs = 3 * model.mesh.nodes.len();
        let fa: Vec<f64> = (0..n_dofs)
            .map(|i| ((i as f64 + 1.0) * 0.754_877_666).fract() - 0.5)
            .collect();
        let fb: Vec<f64> = (0..n_dofs)
            .map(|i| ((i as f64 + 1.0) * 0.569_840_291).fract() - 0.5)
            .collect();
        let ba = Mat::from_fn(n, 1, |i, _| fa[i]);
        let bb = Mat::from_fn(n, 1, |i, _| fb[i]);
        let b2 = Mat::from_fn(n, 2, |i, j| if j == 0 { fa[i] } else { fb[i] });
        let mut probe = vec![0.0; n];
        let mut sol = [
            Case::new("Model::solve, 1 call x 2 RHS, Seq", Par::Seq, || {
                black_box(model.solve(&factor, &[&fa, &fb]));
            }),
            Case::new("Model::solve, 2 calls x 1 RHS, Seq", Par::Seq, || {
                black_box(model.solve(&factor, &[&fa]));
                black_box(model.solve(&factor, &[&fb]));
            }),
            Case::new("Model::solve, 1 call x 2 RHS, rayon(0)", Par::rayon(0), || {
                black_box(model.solve(&factor, &[&fa, &fb]));
            }),
            Case::new("Model::solve, 2 calls x 1 RHS, rayon(0)", Par::rayon(0), || {
                black_box(model.solve(&factor, &[&fa]));
                black_box(model.solve(&factor, &[&fb]));
            }),
            Case::new("faer solve_in_place, n x 2, Seq", Par::Seq, || {
                let mut r = b2.clone();
                llt.solve_in_place(r.as_mut());
                black_box(r);
            }),
            Case::new("faer solve_in_place, 2 x (n x 1), Seq", Par::Seq, || {
                let (mut r1, mut r2) = (ba.clone(), bb.clone());
                llt.solve_in_place(r1.as_mut());
                llt.solve_in_place(r2.as_mut());
                black_box((r1, r2));
            }),
            Case::new(
                "probe of Model::factorize (matvec + 1 RHS), Seq",
                Par::Seq,
                || {
                    pattern.sym_matvec(&values, &fa[..n], &mut probe);
                    let mut r = Mat::from_fn(n, 1, |i, _| probe[i]);
                    llt.solve_in_place(r.as_mut());
                    black_box(r);
                },
            ),
        ];
        let solve_reps = if n < 200_000 { reps.max(30) } else { reps.max(3) };
        run_group(&format!("solves (harmonic {m})"), solve_reps, patience, &mut sol);
        println!(
            "2 calls x 1 RHS / 1 call x 2 RHS: Model::solve Seq {}, rayon(0) {}; faer alone {}",
            ratio(
                &sol,
                "Model::solve, 2 calls x 1 RHS, Seq",
                "Model::solve, 1 call x 2 RHS, Seq"
            ),
            ratio(
                &sol,
                "Model::solve, 2 calls x 1 RHS, rayon(0)",
                "Model::solve, 1 call x 2 RHS, rayon(0)"
            ),
            ratio(
                &sol,
                "faer solve_in_place, 2 x (n x 1), Seq",
                "faer solve_in_place, n x 2, Seq"
            )
        );
        println!(
            "rayon(0) / Seq, Model::solve 2 RHS: {}",
            ratio(
                &sol,
                "Model::solve, 1 call x 2 RHS, rayon(0)",
                "Model::solve, 1 call x 2 RHS, Seq"
            )
        );
        if let Some((_, t_fz_seq)) = fac_res {
            println!(
                "probe / Model::factorize (Seq): {:.2}",
                median_of(&sol, "probe of Model::factorize (matvec + 1 RHS), Seq") / t_fz_seq
            );
        }
        Some(cpu_of(&sol, "Model::solve, 1 call x 2 RHS, Seq"))
    } else {
        None
    };

    // Shares from CPU times: all three run on one thread here, so their CPU
    // time is what they cost, whatever else the machine does.
    if let (Some(a), Some((f, _)), Some(so)) = (asm_cpu, fac_res, sol_cpu) {
        let total = a + f + so;
        println!(
            "\nshare of one harmonic (Par::Seq CPU time; assembly + numeric Cholesky + 2-RHS solve = {:.1} ms): assembly {:.0} %, numeric {:.0} %, solve {:.0} %",
            1e3 * total,
            100.0 * a / total,
            100.0 * f / total,
            100.0 * so / total
        );
    }
}
