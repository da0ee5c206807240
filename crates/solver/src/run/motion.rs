//! Prescribed displacements (`"type": "motion"` loads): the faces they move
//! are held by the model ([`Scene::all_supports`]); each harmonic's loads
//! carry the faces' displacements and the forces `-K_m u_s` equivalent to
//! them on the free DOFs ([`crate::loads::Prescribed`]).
//!
//! A face moved by `t + w x (x - (0, 0, z_c))` has, at a node `(r, z)`,
//! `z' = z - z_c`, the amplitudes `(u_r, u_z, u_theta)` (as the loads':
//! crate::loads, the module doc):
//!
//! | harmonic, family | amplitudes |
//! |---|---|
//! | 0 | `(0, t_z, w_z r)` |
//! | 1 symmetric | `(A, -w_y r, -A)`, `A = t_x + w_y z'` |
//! | 1 antisymmetric | `(B, w_x r, -B)`, `B = t_y - w_x z'` |

use crate::error::SolverError;
use crate::linear::Model;
use crate::loads::{assemble_loads, HarmonicLoads, Prescribed};
use crate::scene::{Load, Scene};

/// The loads of `scene` on `model`, harmonics 0..=`m_max`: the forces, and
/// the faces its `motion` loads move.
pub(crate) fn loads_on(scene: &Scene, model: &Model, m_max: u32) -> Result<Vec<HarmonicLoads>, SolverError> {
    let mut loads = assemble_loads(scene, &model.mesh, m_max)?;
    add_motions(scene, model, &mut loads)?;
    Ok(loads)
}

/// Adds the displacements of the faces `scene.loads` move, and their
/// equivalent forces, to `loads`: in the components each motion's `hold`
/// holds (the others are left to the solution: a smooth rigid pile is
/// held in r only). A motion that would prescribe nothing that way is
/// refused.
fn add_motions(scene: &Scene, model: &Model, loads: &mut [HarmonicLoads]) -> Result<(), SolverError> {
    let mesh = &model.mesh;
    let n = 3 * mesh.nodes.len();
    let mut any = false;
    for (i, load) in scene.loads.iter().enumerate() {
        let Load::Motion(mo) = load else { continue };
        let held = mo.hold.components();
        let mut moves_held = false;
        let moving = mo.displacement != [0.0; 3] || mo.rotation != [0.0; 3];
        let nodes = super::model::support_nodes(mesh, &mo.on);
        if nodes.is_empty() {
            continue;
        }
        let z_c = mo
            .at_z
            .unwrap_or_else(|| nodes.iter().map(|&k| mesh.nodes[k][1]).sum::<f64>() / nodes.len() as f64);
        let [tx, ty, tz] = mo.displacement;
        let [wx, wy, wz] = mo.rotation;
        for h in loads.iter_mut().filter(|h| h.m <= 1) {
            let p = h.prescribed.get_or_insert_with(|| {
                Box::new(Prescribed {
                    displacement: [vec![0.0; n], vec![0.0; n]],
                    equivalent: [vec![0.0; n], vec![0.0; n]],
                })
            });
            for &k in &nodes {
                let [r, z] = mesh.nodes[k];
                let zp = z - z_c;
                let (mut sym, mut anti) = if h.m == 0 {
                    ([0.0, tz, wz * r], [0.0; 3])
                } else {
                    let (a, b) = (tx + wy * zp, ty - wx * zp);
                    ([a, -wy * r, -a], [b, wx * r, -b])
                };
                // A free component is left to the solution.
                for (c, &is_held) in held.iter().enumerate() {
                    let moves = sym[c] != 0.0 || anti[c] != 0.0;
                    if is_held {
                        moves_held |= moves;
                    } else {
                        sym[c] = 0.0;
                        anti[c] = 0.0;
                    }
                }
                p.displacement[0][3 * k..3 * k + 3].copy_from_slice(&sym);
                p.displacement[1][3 * k..3 * k + 3].copy_from_slice(&anti);
            }
            any = true;
        }
        if moving && !moves_held && !nodes.is_empty() {
            return Err(scene
                .invalid(
                    format!("loads[{i}].hold"),
                    format!(
                        "the motion moves '{}' only in components its `hold` ({}) leaves free, so it prescribes nothing: hold the components it moves",
                        mo.on,
                        mo.hold.names().join(", ")
                    ),
                )
                .into());
        }
    }
    if !any {
        return Ok(());
    }
    for h in loads.iter_mut() {
        let Some(p) = h.prescribed.as_mut() else { continue };
        for k in 0..2 {
            let ku = model.internal_forces(h.m, &p.displacement[k]);
            for (dof, (e, f)) in p.equivalent[k].iter_mut().zip(ku).enumerate() {
                *e = if model.fixed[dof] { 0.0 } else { -f };
            }
        }
    }
    Ok(())
}
