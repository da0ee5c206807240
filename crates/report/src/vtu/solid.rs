//! The solid grid: every body revolved, with its point and cell arrays.

use super::encoding::{Array, Grid, Values};
use super::revolution::{mid_ring_nodes, revolve, revolved_cell_type, Rings};
use super::transform::{cartesian, stress_to_cartesian, trig_basis, trig_pairs, von_mises};
use crate::error::ReportError;
use crate::field::{Field, STRESS_NAMES};
use crate::recovery::PlasticStress;
use std::path::Path;

/// Stress of a body's nodes as trigonometric polynomials in theta: the
/// element-node values of every cell of the body, averaged per node, as the
/// coefficients `c_0, a_1, b_1, ..., a_M, b_M` of
/// `c_0 + sum a_m cos(m theta) + b_m sin(m theta)` (exact: the field has no
/// harmonic above M), from each harmonic's amplitude
/// ([`Field::stress_coefficients`]).
struct NodalStress {
    /// Number of coefficients, `2M + 1`.
    nc: usize,
    /// `coef[local node * nc + i]`.
    coef: Vec<[f64; 6]>,
}

impl NodalStress {
    fn new(field: &Field, body: usize, rings: &Rings) -> NodalStress {
        let initial = field.initial.as_ref().and_then(|i| i.u);
        let m_max = field
            .u
            .harmonics
            .iter()
            .chain(initial.iter().flat_map(|u| u.harmonics.iter()))
            .map(|h| h.m as usize)
            .max()
            .unwrap_or(0);
        let nc = 2 * m_max + 1;
        let mut coef = vec![[0.0; 6]; rings.nodes.len() * nc];
        let mut count = vec![0usize; rings.nodes.len()];
        for (c, cell) in field
            .mesh
            .cells
            .iter()
            .enumerate()
            .filter(|(_, c)| c.body == body)
        {
            for (&node, &xi) in cell.nodes.iter().zip(cell.kind.ref_coords()) {
                let l = rings.local[node];
                count[l] += 1;
                for (acc, q) in coef[l * nc..(l + 1) * nc]
                    .iter_mut()
                    .zip(field.stress_coefficients(c, xi, m_max))
                {
                    for (a, v) in acc.iter_mut().zip(q) {
                        *a += v;
                    }
                }
            }
        }
        for (l, &k) in count.iter().enumerate() {
            for c in &mut coef[l * nc..(l + 1) * nc] {
                for v in c.iter_mut() {
                    *v /= k.max(1) as f64;
                }
            }
        }
        NodalStress { nc, coef }
    }

    /// Averaged stress of local node `l` at the angle of `basis`
    /// ([`trig_basis`]).
    fn at(&self, l: usize, basis: &[f64]) -> [f64; 6] {
        let mut s = [0.0; 6];
        for (b, c) in basis.iter().zip(&self.coef[l * self.nc..(l + 1) * self.nc]) {
            for (acc, v) in s.iter_mut().zip(c) {
                *acc += b * v;
            }
        }
        s
    }
}

/// The revolved bodies, with the point arrays `fields`; the stress of a
/// point of a plastic body from `plastic` when given: the mean over the
/// plastic cells sharing its node of their recovered stress
/// ([`PlasticStress::at`]) at the ring's angle.
pub(super) fn solid_grid(
    path: &Path,
    field: &Field,
    n: usize,
    fields: &[&str],
    plastic: Option<&PlasticStress>,
) -> Result<Grid, ReportError> {
    let mesh = field.mesh;
    let want = |name: &str| fields.contains(&name);
    let needs_stress = ["stress", "sigma_cyl", "von_mises"].iter().any(|f| want(f));
    let mut g = Grid::default();
    let (mut disp, mut disp_cyl, mut stress, mut cyl, mut vm) = (vec![], vec![], vec![], vec![], vec![]);
    let (mut body_of, mut cell_of) = (vec![], vec![]);
    for body in 0..mesh.bodies.len() {
        let (mut used, mut needs_mid) = (vec![false; mesh.nodes.len()], vec![false; mesh.nodes.len()]);
        for cell in mesh.cells.iter().filter(|c| c.body == body) {
            for &node in &cell.nodes {
                used[node] = true;
            }
            for i in mid_ring_nodes(cell.kind) {
                needs_mid[cell.nodes[i]] = true;
            }
        }
        let nodes: Vec<usize> = (0..mesh.nodes.len()).filter(|&i| used[i]).collect();
        let mids: Vec<usize> = (0..mesh.nodes.len()).filter(|&i| needs_mid[i]).collect();
        let rings = Rings::new(n, g.n_points(), mesh.nodes.len(), nodes, mids);
        let nodal = needs_stress.then(|| NodalStress::new(field, body, &rings));
        // The plastic cells of each node (none without `plastic`).
        let mut plastic_cells: Vec<Vec<usize>> = vec![Vec::new(); rings.nodes.len()];
        if let (Some(ps), true) = (plastic, needs_stress) {
            for (c, cell) in mesh.cells.iter().enumerate().filter(|(_, c)| c.body == body) {
                if ps.has(c) {
                    for &node in &cell.nodes {
                        plastic_cells[rings.local[node]].push(c);
                    }
                }
            }
        }
        let m_disp = field.u.harmonics.iter().map(|h| h.m as usize).max().unwrap_or(0);
        let m_stress = nodal.as_ref().map_or(0, |st| (st.nc - 1) / 2);
        // The points ring by ring: the trigonometric values once per angle.
        let mut ring_start = g.n_points();
        for (theta, nodes) in rings.by_angle() {
            let (trig, basis) = (trig_pairs(theta, m_disp), trig_basis(theta, m_stress));
            let (sc, mut finite) = (theta.sin_cos(), true);
            for &node in nodes {
                let p = mesh.nodes[node];
                let x = [p[0] * sc.1, p[0] * sc.0, p[1]];
                let uc = field.u.at_trig(node, &trig);
                let u = cartesian(uc, sc);
                let cells = &plastic_cells[rings.local[node]];
                let s = match plastic.filter(|_| !cells.is_empty()) {
                    Some(ps) => {
                        let mut s = [0.0; 6];
                        for &c in cells {
                            let v = ps.at(c, p, theta).unwrap_or([0.0; 6]);
                            for (a, x) in s.iter_mut().zip(v) {
                                *a += x / cells.len() as f64;
                            }
                        }
                        s
                    }
                    None => nodal
                        .as_ref()
                        .map_or([0.0; 6], |st| st.at(rings.local[node], &basis)),
                };
                finite &= x.iter().chain(&u).chain(&s).all(|v| v.is_finite());
                g.points.extend(x);
                disp.extend(u);
                disp_cyl.extend(uc);
                if want("stress") {
                    stress.extend(stress_to_cartesian(s, theta));
                }
                cyl.extend(s);
                vm.push(von_mises(s));
            }
            if !finite {
                // The first point of the ring with a value that is not.
                let bad = (ring_start..g.n_points())
                    .zip(nodes)
                    .find(|&(i, _)| {
                        let at = |v: &[f64], k: usize| v[k * i..k * i + k].iter().all(|x| x.is_finite());
                        !(at(&g.points, 3) && at(&disp, 3) && at(&cyl, 6))
                    })
                    .map_or(nodes[0], |(_, &node)| node);
                return Err(ReportError::NotFinite {
                    path: path.to_path_buf(),
                    what: format!(
                        "a value at node {} (r = {}, z = {}) of body '{}', theta = {} deg",
                        bad,
                        mesh.nodes[bad][0],
                        mesh.nodes[bad][1],
                        mesh.bodies[body].name,
                        theta.to_degrees()
                    ),
                });
            }
            ring_start = g.n_points();
        }
        debug_assert_eq!(g.n_points(), rings.base + rings.len());
        for (c, cell) in mesh.cells.iter().enumerate().filter(|(_, c)| c.body == body) {
            let (t, _) = revolved_cell_type(cell.kind);
            for k in 0..n {
                g.push_cell(t, &revolve(cell.kind, &cell.nodes, k, &rings));
                body_of.push(body as i32);
                cell_of.push(c as i64);
            }
        }
    }
    g.point_data = [
        Array::f64("displacement", 3, disp),
        Array::f64("displacement_cyl", 3, disp_cyl).named(&["u_r", "u_z", "u_theta"]),
        Array::f64("stress", 9, stress),
        Array::f64("sigma_cyl", 6, cyl).named(&STRESS_NAMES),
        Array::f64("von_mises", 1, vm),
    ]
    .into_iter()
    .filter(|a| want(a.name))
    .collect();
    if let (Some(w), true) = (field.water(), needs_stress) {
        let p = g.points.chunks_exact(3).map(|x| w.pressure(x[2])).collect();
        g.point_data.push(Array::f64("pore_pressure", 1, p));
    }
    g.cell_data = vec![
        Array {
            name: "body",
            components: 1,
            component_names: &[],
            values: Values::I32(body_of),
        },
        Array {
            name: "meridional_cell",
            components: 1,
            component_names: &[],
            values: Values::I64(cell_of),
        },
    ];
    Ok(g)
}
