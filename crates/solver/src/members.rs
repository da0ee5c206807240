//! Member forces ([`member_forces`]): a body read as a member along the axis
//! (a pile, an anchor, a lining), with its section resultants at stations
//! and the reaction of its surroundings, by the statics of element nodal
//! forces: every station is a free body, so the forces balance to round-off.
//!
//! | symbol | meaning |
//! |---|---|
//! | `z_k` | station k, top to bottom: the heights of the element corners on the member's surface |
//! | `N` | axial force `F_z`, tension positive |
//! | `V_x`, `V_y` | shear force `F_x`, `F_y` |
//! | `M_x`, `M_y` | bending moment about the station's axis point `(0, 0, z_k)` |
//! | `T` | torque `M_z` |
//! | `u_x`, `u_y`, `u_z` | mean displacement of the station's cross-section |
//! | `phi_x`, `phi_y`, `phi_z` | its rotation (least squares over the cross-section) |
//! | `p_x`, `p_y`, `t` | force of the surroundings on the member per unit length (x, y, z) |
//! | `m_x`, `m_y`, `t_theta` | their moment per unit length about the segment's mid-point on the axis |
//! | `H_b`, `Q_b`, `M_b` | force (horizontal, vertical) and moment of the surroundings on the base |
//!
//! `(N, V, M, T)` at `z_k` is the force and moment that the part above the
//! plane `z = z_k` exerts on the part below: the applied loads at or above
//! the plane, the weight of the cells above it and the reaction of the
//! surroundings strictly above it. So at the head it is the applied load,
//! at the base minus the base reaction. The reaction on a member node n is
//! `r_n = sum_e f_e(n) - (f_n - b_n)`, `f_e = K_e u_e - b_e` the nodal
//! forces of member cell e (harmonics 0 and 1), `f_n` the applied load at
//! n and `b_n` the body forces of every cell at n: joints, bonded cells and
//! supports alike. The stresses of an initial phase are not in `K_e u_e`:
//! member forces are those of the loads beyond the initial state.

use crate::elements::solid::{solid_stiffness, SolidScratch};
use crate::elements::CellValues;
use crate::iteration::JointField;
use crate::joint_law::JointState;
use crate::linear::Model;
use crate::loads::{add_node_resultant, cell_body_load, BodyForce, HarmonicLoads, Resultants};
use crate::scene::Scene;
use crate::solution::Displacements;
use axijoint_mesh::shapes::MAX_CELL_NODES;
use axijoint_mesh::CellKind;
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

/// The member forces of one body.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MemberForces {
    /// The body's physical name.
    pub body: String,
    /// Stations, top to bottom.
    pub stations: Vec<Station>,
    /// The surroundings' reaction between consecutive stations (one fewer
    /// than the stations).
    pub segments: Vec<Segment>,
    /// The surroundings' reaction on the base plane (the lowest station).
    pub base: BaseReaction,
    /// Where the load goes.
    pub split: CapacitySplit,
    /// The length of the shaft open all round from the top down (its
    /// joint open at every section), when a joint lines the shaft.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub open_from_top: Option<f64>,
}

/// Section resultants and motion at one station.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Station {
    /// Height.
    pub z: f64,
    /// `(V_x, V_y, N)`: of the part above on the part below.
    pub force: [f64; 3],
    /// `(M_x, M_y, T)` about `(0, 0, z)`.
    pub moment: [f64; 3],
    /// Mean `(u_x, u_y, u_z)` of the nodes on the plane.
    pub displacement: [f64; 3],
    /// `(phi_x, phi_y, phi_z)`; `None` when the plane's nodes are all on
    /// the axis (no lever arm to fit a rotation).
    pub rotation: Option<[f64; 3]>,
}

/// The surroundings' reaction on the member between two stations.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    /// Upper station.
    pub z_top: f64,
    /// Lower station.
    pub z_bottom: f64,
    /// `(F_x, F_y, F_z)` on the segment (divide by the length for `p_x`,
    /// `p_y`, `t`).
    pub force: [f64; 3],
    /// `(M_x, M_y, M_z)` about `(0, 0, (z_top + z_bottom) / 2)`.
    pub moment: [f64; 3],
}

/// The surroundings' reaction on the base plane.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BaseReaction {
    /// The base plane's height.
    pub z: f64,
    /// `(H_bx, H_by, Q_b)`.
    pub force: [f64; 3],
    /// `(M_bx, M_by, T_b)` about `(0, 0, z)`.
    pub moment: [f64; 3],
}

/// Where the member's load goes, as forces (`x, y, z`): the applied load
/// and the weight balance the shaft and the base reactions to round-off.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CapacitySplit {
    /// The loads applied on the member.
    pub applied: [f64; 3],
    /// Its weight and other body forces.
    pub weight: [f64; 3],
    /// The surroundings' reaction above the base plane.
    pub shaft: [f64; 3],
    /// The reaction on the base plane.
    pub base: [f64; 3],
}

/// The key numbers of a member (`summary.json`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MemberSummary {
    /// Where the load goes.
    pub split: CapacitySplit,
    /// The largest bending moment `|(M_x, M_y)|` over the stations.
    pub max_moment: f64,
    /// Its station's height.
    pub max_moment_z: f64,
    /// The largest `|N|` over the stations.
    pub max_axial: f64,
    /// The top station's mean displacement.
    pub head_displacement: [f64; 3],
    /// The top station's rotation.
    pub head_rotation: Option<[f64; 3]>,
    /// [`MemberForces::open_from_top`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub open_from_top: Option<f64>,
}

impl MemberForces {
    /// The key numbers.
    pub fn summary(&self) -> MemberSummary {
        let bending = |s: &Station| s.moment[0].hypot(s.moment[1]);
        let largest = self
            .stations
            .iter()
            .max_by(|a, b| bending(a).total_cmp(&bending(b)));
        let head = self.stations.first();
        MemberSummary {
            split: self.split,
            max_moment: largest.map_or(0.0, bending),
            max_moment_z: largest.map_or(0.0, |s| s.z),
            max_axial: self.stations.iter().map(|s| s.force[2].abs()).fold(0.0, f64::max),
            head_displacement: head.map_or([0.0; 3], |s| s.displacement),
            head_rotation: head.and_then(|s| s.rotation),
            open_from_top: self.open_from_top,
        }
    }
}

/// Per node of the member: the resultants about the origin of its applied
/// surface load and of the surroundings' reaction.
struct NodeForces {
    applied: Resultants,
    reaction: Resultants,
}

fn zero() -> Resultants {
    Resultants {
        force: [0.0; 3],
        moment: [0.0; 3],
    }
}

fn add(a: &mut Resultants, b: &Resultants) {
    for c in 0..3 {
        a.force[c] += b.force[c];
        a.moment[c] += b.moment[c];
    }
}

/// `r` (about the origin) about `(0, 0, z)`.
fn about(r: &Resultants, z: f64) -> Resultants {
    let [fx, fy, fz] = r.force;
    let [mx, my, mz] = r.moment;
    Resultants {
        force: [fx, fy, fz],
        moment: [mx + z * fy, my - z * fx, mz],
    }
}

/// The member forces of body `body` at load factor `lambda` (`loads` the
/// whole load, unscaled; `u` the displacements at `lambda`; `joints` the
/// joint field there, if the model has joints).
pub fn member_forces(
    scene: &Scene,
    model: &Model,
    loads: &[HarmonicLoads],
    lambda: f64,
    u: &Displacements,
    joints: Option<&JointField>,
    body: usize,
) -> MemberForces {
    let mesh = &model.mesh;
    let n = mesh.nodes.len();
    let tol = crate::loads::tolerance(mesh);
    let gravity = !scene.has_initial_phase();
    let k_h = scene.seismic_coefficient;
    let weight_of = |b: usize| {
        scene
            .materials
            .get(&mesh.bodies[b].name)
            .map_or(0.0, |m| m.unit_weight)
    };
    let member: Vec<usize> = (0..mesh.cells.len())
        .filter(|&c| mesh.cells[c].body == body)
        .collect();
    let mut on_member = vec![false; n];
    for &c in &member {
        for &k in &mesh.cells[c].nodes {
            on_member[k] = true;
        }
    }
    // Per harmonic (0, 1) and family: the member cells' K_e u_e - b_e, and
    // the body forces b of every cell at a member node.
    let mut f = [
        [vec![0.0; 3 * n], vec![0.0; 3 * n]],
        [vec![0.0; 3 * n], vec![0.0; 3 * n]],
    ];
    let mut b = [vec![0.0; 3 * n], vec![0.0; 3 * n]];
    let mut weight = vec![zero(); mesh.cells.len()];
    let mut scratch = SolidScratch::new(CellKind::Quad9);
    let mut values = CellValues::with_default_rule(CellKind::Quad9);
    let mut ke = DMatrix::zeros(0, 0);
    let mut fe = vec![0.0; 3 * MAX_CELL_NODES];
    let mut coords = Vec::with_capacity(MAX_CELL_NODES);
    for (c, cell) in mesh.cells.iter().enumerate() {
        let mine = cell.body == body;
        if !mine && !cell.nodes.iter().any(|&k| on_member[k]) {
            continue;
        }
        coords.clear();
        coords.extend(cell.nodes.iter().map(|&k| mesh.nodes[k]));
        let nn = cell.nodes.len();
        let gamma = weight_of(cell.body);
        for m in 0..2u32 {
            let mi = m as usize;
            let fe = &mut fe[..3 * nn];
            let force = BodyForce {
                gamma,
                k_h,
                gravity,
                water: scene.water.as_ref(),
            };
            if cell_body_load(&mut values, cell.kind, &coords, m, &force, fe) {
                let mut w = zero();
                for (i, &k) in cell.nodes.iter().enumerate() {
                    let bi = [0, 1, 2].map(|j| lambda * fe[3 * i + j]);
                    for j in 0..3 {
                        b[mi][3 * k + j] += bi[j];
                        if mine {
                            f[mi][0][3 * k + j] -= bi[j];
                        }
                    }
                    add_node_resultant(m, mesh.nodes[k], bi, [0.0; 3], 0.0, &mut w);
                }
                add(&mut weight[c], &w);
            }
            if !mine || u.harmonics.len() <= mi {
                continue;
            }
            solid_stiffness(
                cell.kind,
                &coords,
                &model.materials[body],
                m,
                &mut scratch,
                &mut ke,
            );
            let h = &u.harmonics[mi];
            for (fam, ud) in [&h.symmetric, &h.antisymmetric].into_iter().enumerate() {
                if m == 0 && fam == 1 {
                    continue;
                }
                for (a, row) in ke.row_iter().enumerate() {
                    let fa: f64 = row
                        .iter()
                        .enumerate()
                        .map(|(q, k)| k * ud[3 * cell.nodes[q / 3] + q % 3])
                        .sum();
                    f[mi][fam][3 * cell.nodes[a / 3] + a % 3] += fa;
                }
            }
        }
    }
    // Per member node: applied surface load and reaction (about the origin).
    let nodes: Vec<usize> = (0..n).filter(|&k| on_member[k]).collect();
    let per_node: Vec<NodeForces> = nodes
        .iter()
        .map(|&k| {
            let (mut applied, mut reaction) = (zero(), zero());
            for (mi, h) in loads.iter().take(2).enumerate() {
                let m = h.m;
                let pick = |v: &[f64]| [0, 1, 2].map(|j| v[3 * k + j]);
                let (ls, la) = (pick(&h.symmetric), pick(&h.antisymmetric));
                let bs = pick(&b[mi]);
                let surface_s = [0, 1, 2].map(|j| lambda * ls[j] - bs[j]);
                let surface_a = la.map(|v| lambda * v);
                add_node_resultant(m, mesh.nodes[k], surface_s, surface_a, 0.0, &mut applied);
                let (fs, fa) = (pick(&f[mi][0]), pick(&f[mi][1]));
                let rs = [0, 1, 2].map(|j| fs[j] - surface_s[j]);
                let ra = [0, 1, 2].map(|j| fa[j] - surface_a[j]);
                add_node_resultant(m, mesh.nodes[k], rs, ra, 0.0, &mut reaction);
            }
            NodeForces { applied, reaction }
        })
        .collect();
    // Stations: the heights of the corners on the member's surface off
    // the axis (the ends of its boundary edges), top to bottom.
    let mut edges = std::collections::HashMap::new();
    for &c in &member {
        let cell = &mesh.cells[c];
        let nc = cell.kind.n_corners();
        for i in 0..nc {
            let (a, b) = (cell.nodes[i], cell.nodes[(i + 1) % nc]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0u32) += 1;
        }
    }
    let mut zs: Vec<f64> = edges
        .iter()
        .filter(|&(_, &count)| count == 1)
        .flat_map(|(&(a, b), _)| [a, b])
        .filter(|&k| mesh.nodes[k][0] > tol)
        .map(|k| mesh.nodes[k][1])
        .collect();
    zs.sort_by(|a, b| b.total_cmp(a));
    zs.dedup_by(|a, b| (*a - *b).abs() <= tol);
    let centroid: Vec<f64> = member
        .iter()
        .map(|&c| {
            let cell = &mesh.cells[c];
            let corners = &cell.nodes[..cell.kind.n_corners()];
            corners.iter().map(|&k| mesh.nodes[k][1]).sum::<f64>() / corners.len() as f64
        })
        .collect();
    // A node above a plane: above it, or below it with every cell above it
    // (a zigzag cut of an unstructured mesh); a node on the plane is not.
    let mut lowest_cell_z = vec![f64::INFINITY; n];
    for (i, &c) in member.iter().enumerate() {
        for &k in &mesh.cells[c].nodes {
            lowest_cell_z[k] = lowest_cell_z[k].min(centroid[i]);
        }
    }
    let above = |k: usize, z: f64| {
        let zk = mesh.nodes[k][1];
        zk > z + tol || (zk < z - tol && lowest_cell_z[k] > z)
    };
    let on_plane = |k: usize, z: f64| (mesh.nodes[k][1] - z).abs() <= tol;
    let z_base = *zs.last().unwrap_or(&0.0);
    let mut stations = Vec::with_capacity(zs.len());
    let mut split_applied = zero();
    let mut split_shaft = zero();
    let mut split_base = zero();
    for nf in &per_node {
        add(&mut split_applied, &nf.applied);
    }
    for (i, &k) in nodes.iter().enumerate() {
        if on_plane(k, z_base) && !above(k, z_base) {
            add(&mut split_base, &per_node[i].reaction);
        } else {
            add(&mut split_shaft, &per_node[i].reaction);
        }
    }
    let mut split_weight = zero();
    for &c in &member {
        add(&mut split_weight, &weight[c]);
    }
    for &z in &zs {
        let mut r = zero();
        for (i, &k) in nodes.iter().enumerate() {
            if above(k, z) {
                add(&mut r, &per_node[i].reaction);
                add(&mut r, &per_node[i].applied);
            } else if on_plane(k, z) {
                add(&mut r, &per_node[i].applied);
            }
        }
        for (i, &c) in member.iter().enumerate() {
            if centroid[i] > z {
                add(&mut r, &weight[c]);
            }
        }
        let r = about(&r, z);
        stations.push(Station {
            z,
            force: r.force,
            moment: r.moment,
            displacement: [0.0; 3],
            rotation: None,
        });
    }
    section_motion(mesh, &nodes, u, tol, &mut stations);
    let segments = zs
        .windows(2)
        .map(|w| {
            let (top, bottom) = (w[0], w[1]);
            let mut r = zero();
            for (i, &k) in nodes.iter().enumerate() {
                let base_node = bottom == z_base && on_plane(k, z_base) && !above(k, z_base);
                if above(k, bottom) && !above(k, top) && !base_node {
                    add(&mut r, &per_node[i].reaction);
                }
            }
            let r = about(&r, 0.5 * (top + bottom));
            Segment {
                z_top: top,
                z_bottom: bottom,
                force: r.force,
                moment: r.moment,
            }
        })
        .collect();
    let base = about(&split_base, z_base);
    let z_top = zs.first().copied().unwrap_or(0.0);
    let open_from_top = joints.and_then(|f| open_from_top(f, &on_member, z_top));
    MemberForces {
        body: mesh.bodies[body].name.clone(),
        stations,
        segments,
        base: BaseReaction {
            z: z_base,
            force: base.force,
            moment: base.moment,
        },
        split: CapacitySplit {
            applied: split_applied.force,
            weight: split_weight.force,
            shaft: split_shaft.force,
            base: split_base.force,
        },
        open_from_top,
    }
}

/// How far down from `z_top` the joint points on the member's shaft (the
/// points of joint elements with a member node, their tangent steeper than
/// 45 degrees) are open at every section: to midway between the lowest
/// such point and the next one down; `None` without shaft points.
fn open_from_top(field: &JointField, on_member: &[bool], z_top: f64) -> Option<f64> {
    let n_p = field.points.len();
    let mut shaft: Vec<(f64, bool)> = field
        .points
        .iter()
        .enumerate()
        .filter(|(_, info)| {
            let [tr, tz] = info.point.tangent;
            tz.abs() > tr.abs() && info.nodes.iter().any(|&k| on_member[k])
        })
        .map(|(p, info)| {
            let open = (0..field.sections.len()).all(|s| field.state[s * n_p + p] == JointState::Open);
            (info.point.position[1], open)
        })
        .collect();
    shaft.sort_by(|a, b| b.0.total_cmp(&a.0));
    let first_closed = shaft.iter().position(|&(_, open)| !open);
    Some(match first_closed {
        None => z_top - shaft.last()?.0,
        Some(0) => 0.0,
        Some(k) => z_top - 0.5 * (shaft[k - 1].0 + shaft[k].0),
    })
}

/// The mean displacement and the rotation of each station's cross-section
/// from the member nodes on its plane: `integral(g r dr)` by the trapezoid
/// rule over their radii.
fn section_motion(
    mesh: &axijoint_mesh::Mesh,
    nodes: &[usize],
    u: &Displacements,
    tol: f64,
    stations: &mut [Station],
) {
    let get = |m: usize, fam: usize, k: usize| -> [f64; 3] {
        u.harmonics.get(m).map_or([0.0; 3], |h| {
            let v = if fam == 0 { &h.symmetric } else { &h.antisymmetric };
            [v[3 * k], v[3 * k + 1], v[3 * k + 2]]
        })
    };
    for st in stations {
        let mut plane: Vec<usize> = nodes
            .iter()
            .copied()
            .filter(|&k| (mesh.nodes[k][1] - st.z).abs() <= tol)
            .collect();
        plane.sort_by(|&a, &b| mesh.nodes[a][0].total_cmp(&mesh.nodes[b][0]));
        plane.dedup_by(|a, b| (mesh.nodes[*a][0] - mesh.nodes[*b][0]).abs() <= tol);
        let r: Vec<f64> = plane.iter().map(|&k| mesh.nodes[k][0]).collect();
        // Trapezoid weights of integral(g r dr); one node: weight 1.
        let w: Vec<f64> = if r.len() < 2 {
            vec![1.0; r.len()]
        } else {
            (0..r.len())
                .map(|i| {
                    let left = if i > 0 { r[i] - r[i - 1] } else { 0.0 };
                    let right = if i + 1 < r.len() { r[i + 1] - r[i] } else { 0.0 };
                    0.5 * (left + right) * r[i]
                })
                .collect()
        };
        let area: f64 = w.iter().sum();
        if plane.is_empty() || area <= 0.0 {
            continue;
        }
        let (mut ux, mut uy, mut uz) = (0.0, 0.0, 0.0);
        let (mut sy, mut sx, mut sz, mut rr) = (0.0, 0.0, 0.0, 0.0);
        for ((&k, &wi), &ri) in plane.iter().zip(&w).zip(&r) {
            let (s0, s1, a1) = (get(0, 0, k), get(1, 0, k), get(1, 1, k));
            uz += wi * s0[1];
            ux += wi * 0.5 * (s1[0] - s1[2]);
            uy += wi * 0.5 * (a1[0] - a1[2]);
            sy += wi * s1[1] * ri;
            sx += wi * a1[1] * ri;
            sz += wi * s0[2] * ri;
            rr += wi * ri * ri;
        }
        st.displacement = [ux / area, uy / area, uz / area];
        // u_z = -phi_y x + phi_x y, u_theta = phi_z r (least squares).
        st.rotation = (rr > 0.0).then(|| [sx / rr, -sy / rr, sz / rr]);
    }
}
