//! The factors of a run's harmonics within the memory budget, and the
//! elastic solves with them.

use crate::error::SolverError;
use crate::linear::{HarmonicFactor, Model};
use crate::loads::HarmonicLoads;
use crate::solution::{Displacements, HarmonicDisplacement};

/// Environment variable: the memory the whole Cholesky factors of a run's
/// harmonics may take at once, in bytes (suffix `K`, `M` or `G`: KiB, MiB,
/// GiB). When the factors of every harmonic do not fit, the lowest
/// harmonics keep whole factors, the others only their joint blocks (all
/// the stress-transfer iteration reads), and a full solve of one of those
/// reads the rest back from disk ([`crate::spill::FACTOR_DISK_ENV`]) or
/// factorizes it again, as many at once as fit beside the kept ones (at
/// least one). Unset: half the memory available when the run starts. `0`:
/// joint blocks only, one whole factor at a time.
pub const FACTOR_MEMORY_ENV: &str = "AXIJOINT_FACTOR_MEMORY";

/// The byte budget of [`FACTOR_MEMORY_ENV`].
pub fn factor_memory_budget() -> Result<u64, SolverError> {
    match std::env::var(FACTOR_MEMORY_ENV) {
        Ok(v) if !v.trim().is_empty() => axijoint_mesh::parse_bytes(v.trim()).ok_or_else(|| {
            SolverError::Solve(crate::linear::SolveError::Input(format!(
                "{FACTOR_MEMORY_ENV}={v}: give bytes, or a number with K, M or G (e.g. 4G)"
            )))
        }),
        _ => Ok(mem_available().map_or(u64::MAX, |b| b / 2)),
    }
}

/// The least memory the factors of `n` harmonics take (bytes): every
/// harmonic's joint block (all the iteration reads) and one whole factor
/// at a time beside them ([`FACTOR_MEMORY_ENV`] = 0).
pub fn least_factor_memory(model: &Model, n: usize) -> u64 {
    8 * (n as u64 * model.joint_block_len() as u64 + model.factor_len() as u64)
}

/// Environment variable: the memory a run may use, in bytes (suffix `K`,
/// `M` or `G`); unset: the memory available when it starts.
pub const MEMORY_ENV: &str = "AXIJOINT_MEMORY";

/// Refuses, before any factorization, a run of `scene` with `n`
/// harmonics whose least factor memory ([`least_factor_memory`]) exceeds
/// the memory it may use ([`MEMORY_ENV`]), naming the parameters that set
/// it; `scene.force` goes on.
pub(super) fn check_cost(scene: &crate::scene::Scene, model: &Model, n: usize) -> Result<(), SolverError> {
    let limit = match std::env::var(MEMORY_ENV) {
        Ok(v) if !v.trim().is_empty() => Some(axijoint_mesh::parse_bytes(v.trim()).ok_or_else(|| {
            SolverError::Solve(crate::linear::SolveError::Input(format!(
                "{MEMORY_ENV}={v}: give bytes, or a number with K, M or G (e.g. 4G)"
            )))
        })?),
        _ => mem_available(),
    };
    if scene.force {
        return Ok(());
    }
    let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
    if let Some(dir) = &scene.output {
        let need = output_bytes(scene, model.mesh.nodes.len());
        if let Some(free) = crate::spill::free_space(dir).filter(|&free| need > free) {
            return Err(SolverError::Solve(crate::linear::SolveError::Input(format!(
                "{}: the outputs of {} harmonics on {} nodes take about {:.1} GiB (`harmonics`, `outputs.vtu_sections`, the mesh), and the disk of {} has {:.1} GiB free: lower them, switch off `outputs.vtu` or write elsewhere; --force goes on",
                scene.path.display(),
                scene.harmonics() + 1,
                model.mesh.nodes.len(),
                gib(need),
                dir.display(),
                gib(free)
            ))));
        }
    }
    let Some(available) = limit else {
        return Ok(());
    };
    let need = least_factor_memory(model, n);
    if need <= available {
        return Ok(());
    }
    Err(SolverError::Solve(crate::linear::SolveError::Input(format!(
        "{}: the factors of {n} harmonics of {} unknowns need at least {:.1} GiB ({n} joint blocks of {:.1} MiB and one whole factor of {:.1} MiB), {:.1} GiB are available (${MEMORY_ENV}, else the machine's): lower `harmonics` (\"auto\" chooses what the answer needs) or coarsen the mesh (`mesh.parameters`); --force goes on",
        scene.path.display(),
        model.n_eq(),
        gib(need),
        8.0 * model.joint_block_len() as f64 / (1u64 << 20) as f64,
        8.0 * model.factor_len() as f64 / (1u64 << 20) as f64,
        gib(available)
    ))))
}

/// About the bytes a run of `scene` on a mesh of `nodes` nodes writes:
/// the displacements of every harmonic (`solve`), and with the report the
/// revolved `field.vtu` (about 120 bytes per node and ring of points:
/// `max(16, 8 M)` rings by default, two per section of
/// `outputs.vtu_sections` at most) and the gmsh views (about 700 bytes per
/// node), and with plastic bodies their field (`plastic.json`, about 230
/// bytes per Gauss point and section). Measured on Scene P; the CSV files
/// and plots are small beside them.
pub fn output_bytes(scene: &crate::scene::Scene, nodes: usize) -> u64 {
    use crate::scene::VtuSections;
    let (n, m) = (nodes as u64, scene.harmonics() as u64);
    let mut bytes = 48 * n * (m + 1);
    if scene.outputs.vtu {
        let rings = match scene.outputs.vtu_sections {
            VtuSections::Auto => (8 * m).max(16),
            VtuSections::Count(k) => 2 * k as u64,
        };
        bytes += 120 * n * rings;
    }
    if scene.outputs.gmsh_views {
        bytes += 700 * n;
    }
    if scene.has_plastic_bodies() {
        // plastic.json: about 230 B per (Gauss point, section) pair, 2.25
        // Gauss points per node (Q9), 4M sections (or one).
        bytes += 230 * 9 * n / 4 * (4 * m).max(1);
    }
    bytes
}

/// `MemAvailable` of `/proc/meminfo`, in bytes.
fn mem_available() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// For the factors of `n` harmonics (0..n unless all fit) within the
/// budget of [`FACTOR_MEMORY_ENV`]: the harmonics below the returned one
/// keep whole factors (`u32::MAX`: all), and the model's
/// [`Model::set_lean_at_once`] is set to what fits beside them.
pub(super) fn plan_factors(model: &Model, n: usize) -> Result<u32, SolverError> {
    let one = (8 * model.factor_len() as u64).max(1);
    let fit = (factor_memory_budget()? / one).min(u32::MAX as u64) as usize;
    if n <= 1 || fit >= n {
        return Ok(u32::MAX);
    }
    let at_once = fit.clamp(1, rayon::current_num_threads().max(1));
    model.set_lean_at_once(at_once);
    Ok((fit - fit.min(at_once)) as u32)
}

/// Solves harmonic `h` of the loads with `factor` (zero when unloaded).
pub(super) fn solve_harmonic(
    model: &Model,
    factor: Option<&HarmonicFactor>,
    h: &HarmonicLoads,
) -> HarmonicDisplacement {
    match factor {
        Some(f) if h.is_loaded() => {
            let mut u = model.solve(f, &[&h.rhs(0), &h.rhs(1)]);
            let mut antisymmetric = u.pop().unwrap_or_default();
            let mut symmetric = u.pop().unwrap_or_default();
            h.add_prescribed(0, &mut symmetric);
            h.add_prescribed(1, &mut antisymmetric);
            HarmonicDisplacement {
                m: h.m,
                symmetric,
                antisymmetric,
            }
        }
        _ => {
            let n = h.symmetric.len();
            HarmonicDisplacement {
                m: h.m,
                symmetric: vec![0.0; n],
                antisymmetric: vec![0.0; n],
            }
        }
    }
}

/// Factorizes harmonics `ms` and solves their `loads` (each harmonic of
/// `ms` must be in `loads`); harmonics from `whole_below` on keep only
/// their joint blocks (each solved while whole).
pub(super) fn factorize_and_solve(
    model: &Model,
    ms: &[u32],
    loads: &[HarmonicLoads],
    whole_below: u32,
) -> Result<Vec<(HarmonicFactor, HarmonicDisplacement)>, SolverError> {
    let load_of = |m: u32| {
        loads
            .iter()
            .find(|h| h.m == m)
            .expect("the loads of every harmonic")
    };
    Ok(model.factorize_all_with(
        ms,
        |m| m < whole_below,
        |f| solve_harmonic(model, Some(f), load_of(f.m)),
    )?)
}

/// Displacements of `loads`: each loaded harmonic solved with its factor in
/// `factors` (both families in one solve), the others zero.
/// A factor that keeps only its joint block is factorized again for its solve.
pub fn solve_loads(model: &Model, factors: &[HarmonicFactor], loads: &[HarmonicLoads]) -> Displacements {
    let factor_of = |i: usize| factors.iter().find(|f| f.m == loads[i].m);
    let harmonics = model.map_bounded(
        loads.len(),
        |i| factor_of(i).is_some_and(|f| !f.is_full()),
        |i| solve_harmonic(model, factor_of(i), &loads[i]),
    );
    Displacements { harmonics }
}
