//! The initial phase: the in-situ stress of the bodies, the initial
//! traction of the joints and the forces that are not in balance with them.
//!
//! With initial stresses `sigma_0` (per material, [`InitialStress`]), the
//! self-weight `f_b` and the joints' initial tractions `t_0`, the phase's
//! load is the out-of-balance (harmonic 0)
//!
//! ```text
//! r_0 = f_b - Integral(B^T sigma_0 dV) - Sum(N^T t_0 dA)
//! ```
//!
//! zero (to discretization error) for a geostatic state that is in
//! equilibrium with the weight and the supports. The phase solves `K u_0 =
//! r_0` with the joint law acting on `t_0 + k d`; its end is the state the
//! loads start from (docs/loading.md, "Initial phase").
//!
//! A joint's initial traction on its axes (xi tangent, eta normal from the
//! bottom face to the top face) is `t = (xi.sigma.eta, eta.sigma.eta,
//! e_theta.sigma.eta)` of the initial stress of the bodies on its faces
//! whose material gives one (the mean of both faces when both do), or the
//! joint's `initial_traction` from the scene.

use crate::elements::{add_traction_forces, stress_forces};
use crate::linear::Model;
use crate::loads::gravity_load;
use crate::scene::{InitialStress, Scene, SceneError};
use axijoint_mesh::shapes::MAX_CELL_NODES;
use serde::{Deserialize, Serialize};

/// The load and joint tractions of an initial phase.
#[derive(Clone, Debug)]
pub struct InitialLoad {
    /// Harmonic-0 nodal forces `r_0` (`3 n`, node-major).
    pub load: Vec<f64>,
    /// The initial traction `(tau_xi, sigma, tau_theta)` of every joint
    /// point, in the iteration's point order (joint, element, point).
    pub traction: Vec<[f64; 3]>,
    /// How far the initial stresses are from equilibrium.
    pub balance: Balance,
}

/// The out-of-balance of an initial state, over the unsupported degrees of
/// freedom (as Abaqus' geostatic step reports it).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Balance {
    /// Largest nodal out-of-balance force (force, a node's whole ring).
    pub max_force: f64,
    /// The same relative to the largest nodal force of the weight or of
    /// the initial stresses (0 when both are zero).
    pub relative: f64,
    /// Total weight (force, the resultant of `f_b`).
    pub weight: f64,
    /// Vertical resultant of the out-of-balance on the free degrees of
    /// freedom (force).
    pub resultant_z: f64,
}

/// The initial stress of each body (index as `mesh.bodies`) with its unit
/// weight; `None` where its material has none.
pub fn body_stresses(scene: &Scene, model: &Model) -> Vec<Option<(InitialStress, f64)>> {
    model
        .mesh
        .bodies
        .iter()
        .map(|b| {
            let m = scene.materials.get(&b.name)?;
            m.initial_stress.map(|s| (s, m.unit_weight))
        })
        .collect()
}

/// The initial-phase load of a scene with an initial phase.
pub fn initial_load(scene: &Scene, model: &Model) -> Result<InitialLoad, SceneError> {
    let mesh = &model.mesh;
    let n = mesh.nodes.len();
    let weight = gravity_load(scene, mesh)?;
    let bodies = body_stresses(scene, model);
    let water = scene.water.as_ref();
    let mut stress = vec![0.0; 3 * n];
    let mut fe = vec![0.0; 3 * MAX_CELL_NODES];
    let mut coords = Vec::with_capacity(MAX_CELL_NODES);
    let mut values = crate::elements::CellValues::with_default_rule(axijoint_mesh::CellKind::Quad9);
    for cell in &mesh.cells {
        let Some((s0, gamma)) = bodies[cell.body] else {
            continue;
        };
        if s0 == InitialStress::Gravity {
            continue;
        }
        coords.clear();
        coords.extend(cell.nodes.iter().map(|&k| mesh.nodes[k]));
        let fe = &mut fe[..3 * cell.nodes.len()];
        fe.fill(0.0);
        stress_forces(&mut values, cell.kind, &coords, |x| s0.at(x[1], gamma, water), fe);
        for (i, &k) in cell.nodes.iter().enumerate() {
            for c in 0..3 {
                stress[3 * k + c] += fe[3 * i + c];
            }
        }
    }
    // Joint tractions and their nodal forces.
    let points = crate::iteration::joint_point_infos(model);
    let mut traction = Vec::with_capacity(points.len());
    let mut joints = vec![0.0; 3 * n];
    let mut je = [0.0; 18];
    for info in &points {
        let joint = &mesh.joints[info.joint];
        let el = &joint.elements[info.element];
        let point = &info.point;
        let t = scene
            .joints
            .get(&joint.name)
            .and_then(|c| c.initial_traction)
            .unwrap_or_else(|| {
                let sides: Vec<(InitialStress, f64)> = [el.bottom_cell, el.top_cell]
                    .iter()
                    .filter_map(|&c| bodies[mesh.cells[c].body])
                    .filter(|(s, _)| s.gives_traction())
                    .collect();
                let mut t = [0.0; 3];
                for (s0, gamma) in &sides {
                    let ti = on_axes(s0.at(point.position[1], *gamma, water), point.tangent);
                    for c in 0..3 {
                        t[c] += ti[c] / sides.len() as f64;
                    }
                }
                t
            });
        let je = &mut je[..3 * info.nodes.len()];
        je.fill(0.0);
        add_traction_forces(point, t, crate::elements::c_m(0), je);
        for (a, &k) in info.nodes.iter().enumerate() {
            for c in 0..3 {
                joints[3 * k + c] += je[3 * a + c];
            }
        }
        traction.push(t);
    }
    let load: Vec<f64> = (0..3 * n).map(|i| weight[i] - stress[i] - joints[i]).collect();
    let balance = balance(model, &load, &weight, &stress);
    Ok(InitialLoad {
        load,
        traction,
        balance,
    })
}

/// The traction `sigma.eta` on the axes `(xi, eta, theta)` of a joint
/// point with unit tangent `xi = (c, s)`, `eta = (-s, c)`.
pub fn on_axes(sigma: [f64; 6], tangent: [f64; 2]) -> [f64; 3] {
    let [sr, sz, _, trz, trt, tzt] = sigma;
    let [c, s] = tangent;
    let eta = [-s, c];
    // sigma.eta in (r, z, theta).
    let v = [
        sr * eta[0] + trz * eta[1],
        trz * eta[0] + sz * eta[1],
        trt * eta[0] + tzt * eta[1],
    ];
    [c * v[0] + s * v[1], eta[0] * v[0] + eta[1] * v[1], v[2]]
}

/// The out-of-balance of `load` on the free degrees of freedom.
fn balance(model: &Model, load: &[f64], weight: &[f64], stress: &[f64]) -> Balance {
    let mesh = &model.mesh;
    let size = mesh
        .nodes
        .iter()
        .fold(0.0f64, |a, p| a.max(p[0].abs()).max(p[1].abs()))
        .max(f64::MIN_POSITIVE);
    let free = |dof: usize| {
        let on_axis = mesh.nodes[dof / 3][0] <= 1e-9 * size;
        // On the axis only u_z moves in harmonic 0.
        let pinned = on_axis && dof % 3 != 1;
        !(model.fixed[dof] || pinned)
    };
    let max_free = |v: &[f64]| {
        (0..v.len())
            .filter(|&i| free(i))
            .fold(0.0f64, |a, i| a.max(v[i].abs()))
    };
    let max_force = max_free(load);
    let scale = max_free(weight).max(max_free(stress));
    Balance {
        max_force,
        relative: if scale > 0.0 { max_force / scale } else { 0.0 },
        // `0.0 -`: no weight prints as 0, not -0.
        weight: 0.0 - weight.iter().skip(1).step_by(3).sum::<f64>(),
        resultant_z: (0..load.len())
            .filter(|&i| i % 3 == 1 && free(i))
            .map(|i| load[i])
            .sum(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn traction_on_axes_of_a_vertical_and_a_horizontal_joint() {
        // sigma_r = -1, sigma_z = -2, tau_rz = 0.5.
        let s = [-1.0, -2.0, -0.5, 0.5, 0.0, 0.0];
        // Horizontal joint, xi = +r, eta = +z: (tau_rz, sigma_z, 0).
        assert_eq!(on_axes(s, [1.0, 0.0]), [0.5, -2.0, 0.0]);
        // Vertical joint, xi = +z, eta = -r: (-tau_rz, sigma_r, 0).
        let t = on_axes(s, [0.0, 1.0]);
        assert!((t[0] + 0.5).abs() < 1e-15 && (t[1] + 1.0).abs() < 1e-15 && t[2] == 0.0);
        // At 45 degrees, eta = (-h, h):
        // sigma_n = h^2 (sr - 2 trz + sz) = 0.5 (-1 - 1 - 2) = -2.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let t = on_axes(s, [h, h]);
        assert!((t[1] + 2.0).abs() < 1e-14, "{t:?}");
        // tau = xi.sigma.eta = h^2 (-sr + sz + trz - trz) = 0.5 (1 - 2) = -0.5.
        assert!((t[0] + 0.5).abs() < 1e-14, "{t:?}");
    }
}
