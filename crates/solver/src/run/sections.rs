//! The theta sections of a run's joint law and plastic bodies: a half turn
//! where every stage's loads are symmetric about theta = 0, else the full
//! turn ([`Scene::theta_sections`]).

use super::motion::loads_on;
use crate::error::SolverError;
use crate::linear::Model;
use crate::loads::HarmonicLoads;
use crate::scene::Scene;

/// The theta sections of a scene's joint law for its loads (see
/// [`Scene::theta_sections`]); with stages, for every stage's loads (one
/// set for the whole path: a twist in any stage needs the full turn).
pub fn scene_sections(
    scene: &Scene,
    model: &Model,
    loads: &[HarmonicLoads],
) -> Result<crate::fourier::Sections, SolverError> {
    let mut symmetric_only = symmetric(loads);
    if symmetric_only && !scene.stages.is_empty() {
        let m_max = loads.iter().map(|h| h.m).max().unwrap_or(0);
        let mut seen: Vec<Vec<crate::scene::Load>> = Vec::new();
        for leg in scene.legs() {
            if seen.contains(&leg.loads) {
                continue;
            }
            let leg_loads = loads_on(&scene.stage_scene(leg.loads.clone()), model, m_max)?;
            symmetric_only &= symmetric(&leg_loads);
            seen.push(leg.loads);
        }
    }
    Ok(scene.theta_sections(symmetric_only)?)
}

/// Whether `loads` are symmetric about theta = 0: no antisymmetric family
/// and no torsion, in the forces and the prescribed displacements alike (a
/// twist given as a `motion` is torsion too).
fn symmetric(loads: &[HarmonicLoads]) -> bool {
    loads.iter().all(|h| {
        let mut families = vec![(&h.symmetric, &h.antisymmetric)];
        if let Some(p) = &h.prescribed {
            families.push((&p.displacement[0], &p.displacement[1]));
        }
        families.into_iter().all(|(sym, anti)| {
            anti.iter().all(|&v| v == 0.0) && (h.m > 0 || sym.iter().skip(2).step_by(3).all(|&v| v == 0.0))
        })
    })
}
