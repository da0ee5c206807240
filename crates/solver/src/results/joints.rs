//! `joints.json`: the joint field per point and section, as written and
//! read back, and the joints' areas by state.

use super::{bad_saved, read_err};
use crate::error::SolverError;
use axijoint_mesh::Mesh;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Where a joint integration point is.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointPointOut {
    /// Joint name.
    pub joint: String,
    /// Element index within the joint.
    pub element: usize,
    /// Distance along the joint from its first end (curve order).
    pub s: f64,
    /// Position.
    pub r: f64,
    /// Position.
    pub z: f64,
    /// Area per radian `r * weight` of the point: the joint's area is
    /// `sum over sections of w_s * sum over points of da`.
    pub da: f64,
}

/// The joint's values at one point and section.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointValues {
    /// Relative displacement `(d_xi, d_eta, d_theta)`.
    pub d: [f64; 3],
    /// Traction `(tau_xi, sigma, tau_theta)`, sigma > 0 tension.
    pub p: [f64; 3],
    /// Opening `d_eta` where open, else 0.
    pub opening: f64,
    /// Slip: the inelastic shear displacement `|(d_xi - tau_xi/k_xi, d_theta - tau_theta/k_theta)|` where slipping, else 0.
    pub slip: f64,
    /// State.
    pub state: crate::joint_law::JointState,
}

/// `joints.json`: the joint field of a nonlinear run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointFieldFile {
    /// Section angles in degrees.
    pub sections_deg: Vec<f64>,
    /// Section quadrature weights in radians (sum 2 pi).
    pub section_weights: Vec<f64>,
    /// The integration points.
    pub points: Vec<JointPointOut>,
    /// `values[section][point]`.
    pub values: Vec<Vec<JointValues>>,
}

/// Start offset along the joint and direction of each element: elements are
/// chained end to end from a free end (curve order).
fn chain(mesh: &Mesh, joint: &axijoint_mesh::Joint) -> Vec<(f64, bool)> {
    let els = &joint.elements;
    let ends: Vec<[usize; 2]> = els.iter().map(|e| [e.bottom[0], e.bottom[1]]).collect();
    let len = |e: usize| {
        let (a, b) = (mesh.nodes[ends[e][0]], mesh.nodes[ends[e][1]]);
        (b[0] - a[0]).hypot(b[1] - a[1])
    };
    let degree = |n: usize| ends.iter().filter(|e| e.contains(&n)).count();
    let mut out = vec![(0.0, true); els.len()];
    let mut done = vec![false; els.len()];
    let mut offset = 0.0;
    while let Some(first) = (0..els.len()).find(|&e| !done[e]) {
        // Start a chain at a free end when there is one.
        let start = (0..els.len())
            .filter(|&e| !done[e])
            .find_map(|e| ends[e].iter().find(|&&n| degree(n) == 1).map(|&n| (e, n)))
            .unwrap_or((first, ends[first][0]));
        let (mut e, mut node) = start;
        loop {
            let forward = ends[e][0] == node;
            out[e] = (offset, forward);
            done[e] = true;
            offset += len(e);
            node = if forward { ends[e][1] } else { ends[e][0] };
            match (0..els.len()).find(|&k| !done[k] && ends[k].contains(&node)) {
                Some(k) => e = k,
                None => break,
            }
        }
    }
    out
}

impl JointFieldFile {
    /// The joint field of `field` on `mesh` with the joints' springs.
    pub fn new(
        mesh: &Mesh,
        springs: &[crate::elements::JointSprings],
        field: &crate::iteration::JointField,
    ) -> Self {
        use crate::joint_law::JointState;
        let chains: Vec<Vec<(f64, bool)>> = mesh.joints.iter().map(|j| chain(mesh, j)).collect();
        let points = field
            .points
            .iter()
            .map(|p| {
                let (offset, forward) = chains[p.joint][p.element];
                let el = &mesh.joints[p.joint].elements[p.element];
                let start = if forward {
                    mesh.nodes[el.bottom[0]]
                } else {
                    mesh.nodes[el.bottom[1]]
                };
                let [r, z] = p.point.position;
                JointPointOut {
                    joint: mesh.joints[p.joint].name.clone(),
                    element: p.element,
                    s: offset + (r - start[0]).hypot(z - start[1]),
                    r,
                    z,
                    da: p.point.area(),
                }
            })
            .collect();
        let n_p = field.points.len();
        let values = (0..field.sections.len())
            .map(|s| {
                (0..n_p)
                    .map(|i| {
                        let k = s * n_p + i;
                        let (d, p, state) = (field.d[k], field.p[k], field.state[k]);
                        let sp = springs[field.points[i].joint];
                        let plastic = |dv: f64, pv: f64, kv: f64| if kv > 0.0 { dv - pv / kv } else { 0.0 };
                        JointValues {
                            d,
                            p,
                            opening: if state == JointState::Open {
                                d[1].max(0.0)
                            } else {
                                0.0
                            },
                            slip: if state == JointState::Slip {
                                plastic(d[0], p[0], sp.k_xi).hypot(plastic(d[2], p[2], sp.k_theta))
                            } else {
                                0.0
                            },
                            state,
                        }
                    })
                    .collect()
            })
            .collect();
        JointFieldFile {
            sections_deg: field.sections.theta.iter().map(|t| t.to_degrees()).collect(),
            section_weights: field.sections.weight.clone(),
            points,
            values,
        }
    }
}

impl JointFieldFile {
    /// Swept area of `joint` in each state: `(open, slip, stick)`.
    pub fn state_areas(&self, joint: &str) -> (f64, f64, f64) {
        use crate::joint_law::JointState;
        let mut a = (0.0, 0.0, 0.0);
        for (values, w) in self.values.iter().zip(&self.section_weights) {
            for (p, v) in self.points.iter().zip(values).filter(|(p, _)| p.joint == joint) {
                let da = w * p.da;
                match v.state {
                    JointState::Open => a.0 += da,
                    JointState::Slip => a.1 += da,
                    JointState::Stick => a.2 += da,
                }
            }
        }
        a
    }
}

/// Reads `joints.json` of a solution folder, if the run had one.
pub fn read_joint_field(dir: &Path) -> Result<Option<JointFieldFile>, SolverError> {
    let path = dir.join("joints.json");
    if !path.is_file() {
        return Ok(None);
    }
    let text = std::fs::read_to_string(&path).map_err(|e| read_err(&path, e))?;
    serde_json::from_str(&text)
        .map(Some)
        .map_err(|e| bad_saved(&path, e))
}
