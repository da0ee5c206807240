//! The joint grid: the joint surfaces revolved, with the joint field of the
//! nearest section as cell data.

use super::encoding::{Array, Grid, Values};
use super::revolution::{cell_type, mid_angle, position, Rings, SectionMap};
use crate::error::{check_finite, ReportError};
use crate::field::Field;
use axijoint_mesh::{JointKind, Mesh};
use axijoint_solver::joint_law::JointState;
use axijoint_solver::results::JointFieldFile;
use std::path::Path;

/// Joint state code: 0 stick, 1 slip, 2 open.
pub fn state_code(s: JointState) -> i32 {
    match s {
        JointState::Stick => 0,
        JointState::Slip => 1,
        JointState::Open => 2,
    }
}

/// The revolved joint surfaces.
pub(super) fn joint_grid(
    path: &Path,
    field: &Field,
    n: usize,
    jf: &JointFieldFile,
) -> Result<Grid, ReportError> {
    let mesh: &Mesh = field.mesh;
    let bad = |m: String| ReportError::Input(format!("{}: joint field: {m}", path.display()));
    if jf.sections_deg.is_empty() || jf.values.len() != jf.sections_deg.len() {
        return Err(bad(format!(
            "{} sections, {} rows of values",
            jf.sections_deg.len(),
            jf.values.len()
        )));
    }
    if let Some(s) = jf.values.iter().position(|v| v.len() != jf.points.len()) {
        return Err(bad(format!(
            "section {s} has {} values for {} points",
            jf.values[s].len(),
            jf.points.len()
        )));
    }
    // Integration points of each (joint, element).
    let mut points_of: Vec<Vec<Vec<usize>>> = mesh
        .joints
        .iter()
        .map(|j| vec![vec![]; j.elements.len()])
        .collect();
    for (i, p) in jf.points.iter().enumerate() {
        let j = mesh
            .joints
            .iter()
            .position(|j| j.name == p.joint)
            .ok_or_else(|| bad(format!("no joint '{}' in the mesh", p.joint)))?;
        let slot = points_of[j]
            .get_mut(p.element)
            .ok_or_else(|| bad(format!("joint '{}' has no element {}", p.joint, p.element)))?;
        slot.push(i);
    }
    let map = SectionMap::new(&jf.sections_deg, &jf.section_weights);
    let mut g = Grid::default();
    let (mut disp, mut disp_top) = (vec![], vec![]);
    let mut cd = JointCellData::default();
    for (j, joint) in mesh.joints.iter().enumerate() {
        // Rings of the bottom-face nodes; top partners for the displacement.
        let mut top_of = vec![usize::MAX; mesh.nodes.len()];
        let (mut used, mut needs_mid) = (vec![false; mesh.nodes.len()], vec![false; mesh.nodes.len()]);
        for e in &joint.elements {
            for (&b, &t) in e.bottom.iter().zip(&e.top) {
                used[b] = true;
                top_of[b] = t;
            }
            if e.kind == JointKind::Lin6 {
                for &b in &e.bottom {
                    needs_mid[b] = true;
                }
            }
        }
        let nodes: Vec<usize> = (0..mesh.nodes.len()).filter(|&i| used[i]).collect();
        let mids: Vec<usize> = (0..mesh.nodes.len()).filter(|&i| needs_mid[i]).collect();
        let rings = Rings::new(n, g.n_points(), mesh.nodes.len(), nodes, mids);
        for (node, theta) in rings.points() {
            let x = position(mesh.nodes[node], theta);
            let ub = field.displacement_xyz(node, theta);
            let ut = field.displacement_xyz(top_of[node], theta);
            check_finite(path, &[x.as_slice(), &ub, &ut].concat(), || {
                format!(
                    "a displacement on joint '{}' at theta = {} deg",
                    joint.name,
                    theta.to_degrees()
                )
            })?;
            g.points.extend(x);
            disp.extend(ub);
            disp_top.extend(ut);
        }
        for (e, el) in joint.elements.iter().enumerate() {
            let b = &el.bottom;
            for k in 0..n {
                let (lo, hi) = (|i: usize| rings.at(b[i], k), |i: usize| rings.at(b[i], k + 1));
                match el.kind {
                    JointKind::Lin4 => g.push_cell(cell_type::QUAD, &[lo(0), lo(1), hi(1), hi(0)]),
                    JointKind::Lin6 => {
                        let mid = |i: usize| rings.mid(b[i], k);
                        g.push_cell(
                            cell_type::BIQUADRATIC_QUAD,
                            &[lo(0), lo(1), hi(1), hi(0), lo(2), mid(1), hi(2), mid(0), mid(2)],
                        );
                    }
                }
                let (section, mirrored) = map.nearest(mid_angle(k, n));
                cd.push(path, jf, &points_of[j][e], section, mirrored, j, e, &joint.name)?;
            }
        }
    }
    g.point_data = vec![
        Array::f64("displacement", 3, disp),
        Array::f64("displacement_top", 3, disp_top),
    ];
    g.cell_data = cd.into_arrays();
    Ok(g)
}

/// Cell data of the joint file.
#[derive(Default)]
struct JointCellData {
    state: Vec<i32>,
    open_fraction: Vec<f64>,
    slip_fraction: Vec<f64>,
    opening: Vec<f64>,
    slip: Vec<f64>,
    sigma_n: Vec<f64>,
    tau_xi: Vec<f64>,
    tau_theta: Vec<f64>,
    d: Vec<f64>,
    section_deg: Vec<f64>,
    joint: Vec<i32>,
    element: Vec<i32>,
}

impl JointCellData {
    /// Adds the cell of element `e` of joint `j` at `section`.
    #[allow(clippy::too_many_arguments)]
    fn push(
        &mut self,
        path: &Path,
        jf: &JointFieldFile,
        points: &[usize],
        section: usize,
        mirrored: bool,
        j: usize,
        e: usize,
        name: &str,
    ) -> Result<(), ReportError> {
        let values = &jf.values[section];
        let total_da: f64 = points.iter().map(|&i| jf.points[i].da.max(0.0)).sum();
        let weight = |i: usize| {
            if total_da > 0.0 {
                jf.points[i].da.max(0.0) / total_da
            } else {
                1.0 / points.len().max(1) as f64
            }
        };
        let mut share = [0.0; 3];
        let (mut opening, mut slip) = (0.0, 0.0);
        let (mut p, mut d) = ([0.0; 3], [0.0; 3]);
        for &i in points {
            let (v, w) = (&values[i], weight(i));
            share[state_code(v.state) as usize] += w;
            opening += w * v.opening;
            slip += w * v.slip;
            for a in 0..3 {
                p[a] += w * v.p[a];
                d[a] += w * v.d[a];
            }
        }
        if mirrored {
            p[2] = -p[2];
            d[2] = -d[2];
        }
        check_finite(path, &[opening, slip, p[0], p[1], p[2], d[0], d[1], d[2]], || {
            format!(
                "a value of joint '{name}', element {e}, section {} deg",
                jf.sections_deg[section]
            )
        })?;
        // Largest share; ties to the more severe state.
        let state = (0..3)
            .rev()
            .max_by(|&a, &b| share[a].total_cmp(&share[b]))
            .unwrap_or(0);
        self.state.push(if points.is_empty() { 0 } else { state as i32 });
        self.open_fraction.push(share[2]);
        self.slip_fraction.push(share[1]);
        self.opening.push(opening);
        self.slip.push(slip);
        self.sigma_n.push(p[1]);
        self.tau_xi.push(p[0]);
        self.tau_theta.push(p[2]);
        self.d.extend(d);
        self.section_deg.push(jf.sections_deg[section]);
        self.joint.push(j as i32);
        self.element.push(e as i32);
        Ok(())
    }

    fn into_arrays(self) -> Vec<Array> {
        let int = |name, v| Array {
            name,
            components: 1,
            component_names: &[],
            values: Values::I32(v),
        };
        vec![
            int("state", self.state),
            Array::f64("opening", 1, self.opening),
            Array::f64("slip", 1, self.slip),
            Array::f64("sigma_n", 1, self.sigma_n),
            Array::f64("tau_xi", 1, self.tau_xi),
            Array::f64("tau_theta", 1, self.tau_theta),
            Array::f64("d", 3, self.d).named(&["d_xi", "d_eta", "d_theta"]),
            Array::f64("open_fraction", 1, self.open_fraction),
            Array::f64("slip_fraction", 1, self.slip_fraction),
            Array::f64("section_deg", 1, self.section_deg),
            int("joint", self.joint),
            int("element", self.element),
        ]
    }
}
