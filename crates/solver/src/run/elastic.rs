//! The elastic run: the scene meshed and modelled, its harmonics factorized
//! (the [`Problem`]) and its loads solved with the joints as linear springs.

use super::factors::{check_cost, factorize_and_solve, plan_factors, solve_harmonic, solve_loads};
use super::measures::reactions;
use super::model::{build_model, mesh_scene};
use super::Run;
use crate::error::SolverError;
use crate::linear::{HarmonicFactor, Model};
use crate::loads::HarmonicLoads;
use crate::scene::Scene;
use crate::solution::{Displacements, Timings};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// A model and the factors of its harmonics: what every load on it (a
/// scene's loads, each load case, each load step) is solved with.
pub struct Problem {
    /// The model (mesh, DOFs, pattern, symbolic factor).
    pub model: Model,
    /// Numeric factors of the harmonics that were factorized.
    pub factors: Vec<HarmonicFactor>,
}

/// A problem, its loads and their elastic solution.
pub(super) struct Elastic {
    /// The problem.
    pub problem: Problem,
    /// The loads and their solution.
    pub load: ElasticLoad,
}

/// Loads and their elastic solution on a problem (the start of every
/// nonlinear run).
pub(super) struct ElasticLoad {
    /// Loads per harmonic.
    pub loads: Vec<HarmonicLoads>,
    /// The elastic displacements of `loads`.
    pub u: Displacements,
    /// Setup and factorization (the solve so far in `solve`).
    pub timings: Timings,
}

/// Meshes, builds and solves a scene with its joints as linear springs,
/// reactions included. Harmonics without load are not factorized unless
/// `all_factors`.
pub fn solve_linear(scene: &Scene, keep_msh: Option<&Path>, all_factors: bool) -> Result<Run, SolverError> {
    let Elastic { problem, load } = elastic(scene, keep_msh, all_factors)?;
    let t = Instant::now();
    let reactions = reactions(scene, &problem.model, &load.loads, &load.u);
    let mut run = Run::new(Arc::new(problem), load);
    run.reactions = reactions;
    run.timings.reactions = t.elapsed().as_secs_f64();
    Ok(run)
}

/// The elastic run of a scene (no reactions: a nonlinear run computes them
/// once, at its solution).
pub(super) fn elastic(
    scene: &Scene,
    keep_msh: Option<&Path>,
    all_factors: bool,
) -> Result<Elastic, SolverError> {
    let (mesh, _) = mesh_scene(scene, keep_msh)?;
    let m_max = scene.harmonics();
    let t0 = Instant::now();
    let model = build_model(scene, mesh)?;
    let loads = super::motion::loads_on(scene, &model, m_max)?;
    let setup = t0.elapsed().as_secs_f64();
    let wanted: Vec<u32> = loads
        .iter()
        .filter(|h| all_factors || h.is_loaded() || (h.m == 0 && scene.has_initial_phase()))
        .map(|h| h.m)
        .collect();
    check_cost(scene, &model, wanted.len())?;
    let t1 = Instant::now();
    let whole_below = plan_factors(&model, wanted.len())?;
    let (factors, u, factorize, solve) = if wanted.iter().all(|&m| m < whole_below) {
        let factors = model.factorize_all(&wanted)?;
        let factorize = t1.elapsed().as_secs_f64();
        let t2 = Instant::now();
        let u = solve_loads(&model, &factors, &loads);
        (factors, u, factorize, t2.elapsed().as_secs_f64())
    } else {
        // Each harmonic solved while its factor is whole (the solves are
        // counted in the factorization time).
        let solved = factorize_and_solve(&model, &wanted, &loads, whole_below)?;
        let (factors, solved): (Vec<_>, Vec<_>) = solved.into_iter().unzip();
        let harmonics = loads
            .iter()
            .map(|h| match solved.iter().find(|d| d.m == h.m) {
                Some(d) => d.clone(),
                None => solve_harmonic(&model, None, h),
            })
            .collect();
        (
            factors,
            Displacements { harmonics },
            t1.elapsed().as_secs_f64(),
            0.0,
        )
    };
    Ok(Elastic {
        problem: Problem { model, factors },
        load: ElasticLoad {
            loads,
            u,
            timings: Timings {
                setup,
                factorize,
                solve,
                reactions: 0.0,
            },
        },
    })
}
