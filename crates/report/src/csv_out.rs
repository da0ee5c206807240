//! CSV files: cut profiles, joint fields, convergence histories
//! (columns documented in `docs/outputs.md`).

use crate::cuts::CutRow;
use crate::error::ReportError;
use crate::field::STRESS_NAMES;
use axijoint_solver::iteration::IterationRecord;
use axijoint_solver::members::MemberForces;
use axijoint_solver::results::JointFieldFile;
use axijoint_solver::results::LoadPath;
use std::path::Path;

/// Writes rows through a temporary file renamed into place, refusing
/// non-finite numbers.
fn write_atomic(
    path: &Path,
    header: &[String],
    rows: &[Vec<String>],
    numbers: &[f64],
) -> Result<(), ReportError> {
    if let Some(i) = numbers.iter().position(|v| !v.is_finite()) {
        return Err(ReportError::NotFinite {
            path: path.to_path_buf(),
            what: format!("value {i}"),
        });
    }
    axijoint_mesh::atomic::write(path, |out| {
        let mut w = csv::Writer::from_writer(out);
        w.write_record(header)?;
        for r in rows {
            w.write_record(r)?;
        }
        w.flush()
    })
    .map_err(|e| ReportError::write(path, e))
}

fn num(v: f64) -> String {
    format!("{v:.9e}")
}

/// A cut profile at one theta: `s, r, z, theta, body, sigma_r ... tau_ztheta`
/// (and `pore_pressure` with ground water).
pub fn write_cut(path: &Path, rows: &[CutRow], length: &str, stress: &str) -> Result<(), ReportError> {
    let mut header = vec![
        format!("s [{length}]"),
        format!("r [{length}]"),
        format!("z [{length}]"),
        "theta [deg]".to_string(),
        "body".to_string(),
    ];
    header.extend(STRESS_NAMES.iter().map(|n| format!("{n} [{stress}]")));
    let water = rows.iter().any(|r| r.pore_pressure.is_some());
    if water {
        header.push(format!("pore_pressure [{stress}]"));
    }
    let numbers: Vec<f64> = rows
        .iter()
        .flat_map(|r| {
            [r.s, r.r, r.z, r.theta_deg]
                .into_iter()
                .chain(r.stress)
                .chain(r.pore_pressure)
        })
        .collect();
    let body: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            let mut v = vec![
                num(r.s),
                num(r.r),
                num(r.z),
                format!("{}", r.theta_deg),
                r.body.clone(),
            ];
            v.extend(r.stress.iter().map(|&x| num(x)));
            if water {
                v.push(num(r.pore_pressure.unwrap_or(0.0)));
            }
            v
        })
        .collect();
    write_atomic(path, &header, &body, &numbers)
}

/// One joint's field at every section, ordered by section then position.
pub fn write_joint(
    path: &Path,
    field: &JointFieldFile,
    joint: &str,
    length: &str,
    stress: &str,
) -> Result<(), ReportError> {
    let header: Vec<String> = [
        format!("s [{length}]"),
        format!("r [{length}]"),
        format!("z [{length}]"),
        "theta [deg]".into(),
        format!("sigma [{stress}]"),
        format!("tau_xi [{stress}]"),
        format!("tau_theta [{stress}]"),
        format!("d_xi [{length}]"),
        format!("d_eta [{length}]"),
        format!("d_theta [{length}]"),
        format!("opening [{length}]"),
        format!("slip [{length}]"),
        "state".into(),
    ]
    .to_vec();
    let mut order: Vec<usize> = (0..field.points.len())
        .filter(|&i| field.points[i].joint == joint)
        .collect();
    order.sort_by(|&a, &b| field.points[a].s.total_cmp(&field.points[b].s));
    let mut rows = Vec::new();
    let mut numbers = Vec::new();
    for (s, theta) in field.sections_deg.iter().enumerate() {
        for &i in &order {
            let (pt, v) = (&field.points[i], &field.values[s][i]);
            let vals = [
                pt.s, pt.r, pt.z, *theta, v.p[1], v.p[0], v.p[2], v.d[0], v.d[1], v.d[2], v.opening, v.slip,
            ];
            numbers.extend_from_slice(&vals);
            let mut row: Vec<String> = vals.iter().map(|&x| num(x)).collect();
            row[3] = format!("{theta}");
            row.push(v.state.name().to_string());
            rows.push(row);
        }
    }
    write_atomic(path, &header, &rows, &numbers)
}

/// The iteration history.
pub fn write_convergence(path: &Path, history: &[IterationRecord]) -> Result<(), ReportError> {
    let header: Vec<String> = ["iteration", "residual_ratio", "open", "slip", "stick", "seconds"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let numbers: Vec<f64> = history.iter().flat_map(|h| [h.ratio, h.seconds]).collect();
    let rows = history
        .iter()
        .map(|h| {
            vec![
                h.iteration.to_string(),
                num(h.ratio),
                h.open.to_string(),
                h.slip.to_string(),
                h.stick.to_string(),
                num(h.seconds),
            ]
        })
        .collect::<Vec<_>>();
    write_atomic(path, &header, &rows, &numbers)
}

/// The load path: one row per converged step; units in the header.
pub fn write_load_path(
    path: &Path,
    load_path: &LoadPath,
    length: &str,
    applied_units: &[String],
) -> Result<(), ReportError> {
    let Some(first) = load_path.steps.first() else {
        return write_atomic(path, &["lambda [-]".to_string()], &[], &[]);
    };
    let staged = first.observed.stage.is_some();
    let mut header = Vec::new();
    if staged {
        header.extend(["leg [-]", "stage", "cycle [-]", "level [-]"].map(String::from));
    }
    header.push("lambda [-]".to_string());
    // The load on each face along its direction: with stages, and on a face
    // a motion moves (its reaction).
    let with_applied: Vec<bool> = first
        .observed
        .faces
        .iter()
        .map(|f| staged || f.applied.is_some())
        .collect();
    for (k, f) in first.observed.faces.iter().enumerate() {
        for c in ["ux", "uy", "uz", "along_load"] {
            header.push(format!("{}_{c} [{length}]", f.on));
        }
        header.push(format!("{}_rotation [rad]", f.on));
        if with_applied[k] {
            let unit = applied_units.get(k).map_or("-", String::as_str);
            header.push(format!("{}_applied [{unit}]", f.on));
        }
    }
    for j in &first.observed.joints {
        for c in ["open", "slip", "stick"] {
            header.push(format!("{}_{c}_area [{length}^2]", j.joint));
        }
    }
    if staged {
        let unit = applied_units.first().map_or("-", String::as_str);
        header.push(format!("dissipated [{unit} {length}]"));
    }
    let plastic = first.observed.plastic_volume.is_some();
    if plastic {
        header.push(format!("plastic_volume [{length}^3]"));
    }
    header.extend(["iterations [-]", "solves [-]", "rounds [-]", "cutbacks [-]"].map(String::from));
    let mut numbers = Vec::new();
    let rows = load_path
        .steps
        .iter()
        .map(|s| {
            let mut v = vec![s.lambda];
            for (f, &applied) in s.observed.faces.iter().zip(&with_applied) {
                v.extend(f.mean);
                v.push(f.along);
                v.push(f.rotation);
                if applied {
                    v.push(f.applied.unwrap_or(0.0));
                }
            }
            for j in &s.observed.joints {
                v.extend([j.open, j.slip, j.stick]);
            }
            if staged {
                v.push(s.observed.dissipated.unwrap_or(0.0));
            }
            if plastic {
                v.push(s.observed.plastic_volume.unwrap_or(0.0));
            }
            numbers.extend(&v);
            let mut row: Vec<String> = match &s.observed.stage {
                Some(m) if staged => vec![
                    m.leg.to_string(),
                    m.stage.clone(),
                    m.cycle.to_string(),
                    m.level.to_string(),
                ],
                _ => Vec::new(),
            };
            row.extend(v.into_iter().map(num));
            row.extend(
                [
                    s.iterations as u64,
                    s.solves as u64,
                    s.rounds as u64,
                    s.cutbacks as u64,
                ]
                .map(|n| n.to_string()),
            );
            row
        })
        .collect::<Vec<_>>();
    write_atomic(path, &header, &rows, &numbers)
}

/// The stages of a staged load path, one row per stage (per cycle of a
/// cyclic stage): the joints' slip work over it, each loaded face's
/// displacement along its load and applied load at its end, and its
/// displacement where its applied load last crossed zero within it (empty
/// if it did not): the residual displacement at zero load.
pub fn write_stages(
    path: &Path,
    load_path: &LoadPath,
    length: &str,
    applied_units: &[String],
) -> Result<(), ReportError> {
    /// One row in the making.
    struct Group {
        stage: String,
        cycle: u32,
        steps: usize,
        work: f64,
        end: Vec<[f64; 2]>,
        zero: Vec<Option<f64>>,
    }
    let Some(first) = load_path.steps.first() else {
        return Ok(());
    };
    let work_unit = applied_units.first().map_or("-", String::as_str);
    let mut header: Vec<String> = ["stage", "cycle [-]", "steps [-]"].map(String::from).to_vec();
    header.push(format!("dissipated [{work_unit} {length}]"));
    for (k, f) in first.observed.faces.iter().enumerate() {
        let unit = applied_units.get(k).map_or("-", String::as_str);
        header.push(format!("{}_along_load_end [{length}]", f.on));
        header.push(format!("{}_applied_end [{unit}]", f.on));
        header.push(format!("{}_at_zero_load [{length}]", f.on));
    }
    let mut rows: Vec<Vec<String>> = Vec::new();
    let mut numbers = Vec::new();
    let mut flush = |g: Group, rows: &mut Vec<Vec<String>>| {
        numbers.push(g.work);
        let mut row = vec![g.stage, g.cycle.to_string(), g.steps.to_string(), num(g.work)];
        for (e, z) in g.end.iter().zip(&g.zero) {
            numbers.extend(e);
            row.extend(e.map(num));
            row.push(z.map_or(String::new(), |v| {
                numbers.push(v);
                num(v)
            }));
        }
        rows.push(row);
    };
    let mut group: Option<Group> = None;
    // Each face's (along, applied) at the step before: the unloaded state
    // before the first.
    let mut before: Vec<[f64; 2]> = vec![[0.0; 2]; first.observed.faces.len()];
    for s in &load_path.steps {
        let Some(m) = &s.observed.stage else { continue };
        let now: Vec<[f64; 2]> = s
            .observed
            .faces
            .iter()
            .map(|f| [f.along, f.applied.unwrap_or(0.0)])
            .collect();
        if group
            .as_ref()
            .is_none_or(|g| g.stage != m.stage || g.cycle != m.cycle)
        {
            if let Some(g) = group.take() {
                flush(g, &mut rows);
            }
            group = Some(Group {
                stage: m.stage.clone(),
                cycle: m.cycle,
                steps: 0,
                work: 0.0,
                end: Vec::new(),
                zero: vec![None; now.len()],
            });
        }
        let Some(g) = group.as_mut() else { continue };
        for (k, (&[a0, p0], &[a1, p1])) in before.iter().zip(&now).enumerate() {
            if p1 == 0.0 {
                g.zero[k] = Some(a1);
            } else if p0 * p1 < 0.0 {
                g.zero[k] = Some(a0 + p0 / (p0 - p1) * (a1 - a0));
            }
        }
        g.steps += 1;
        g.work += s.observed.dissipated.unwrap_or(0.0);
        g.end.clone_from(&now);
        before = now;
    }
    if let Some(g) = group.take() {
        flush(g, &mut rows);
    }
    write_atomic(path, &header, &rows, &numbers)
}

/// A member's stations, top to bottom: section forces (of the part above
/// on the part below; N tension positive; moments about the station's
/// axis point), the mean displacement and the rotation of the cross-section
/// (empty when the plane has no node off the axis).
pub fn write_member(
    path: &Path,
    member: &MemberForces,
    length: &str,
    force: &str,
) -> Result<(), ReportError> {
    let header: Vec<String> = [
        format!("z [{length}]"),
        format!("N [{force}]"),
        format!("V_x [{force}]"),
        format!("V_y [{force}]"),
        format!("M_x [{force} {length}]"),
        format!("M_y [{force} {length}]"),
        format!("T [{force} {length}]"),
        format!("u_x [{length}]"),
        format!("u_y [{length}]"),
        format!("u_z [{length}]"),
        "phi_x [rad]".to_string(),
        "phi_y [rad]".to_string(),
        "phi_z [rad]".to_string(),
    ]
    .into();
    let mut numbers = Vec::new();
    let rows: Vec<Vec<String>> = member
        .stations
        .iter()
        .map(|s| {
            let v = [
                s.z,
                s.force[2],
                s.force[0],
                s.force[1],
                s.moment[0],
                s.moment[1],
                s.moment[2],
                s.displacement[0],
                s.displacement[1],
                s.displacement[2],
            ];
            numbers.extend(v);
            let mut row: Vec<String> = v.into_iter().map(num).collect();
            match s.rotation {
                Some(phi) => {
                    numbers.extend(phi);
                    row.extend(phi.map(num));
                }
                None => row.extend(["", "", ""].map(String::from)),
            }
            row
        })
        .collect();
    write_atomic(path, &header, &rows, &numbers)
}

/// The surroundings' reaction on a member: one row per segment between
/// stations (`part` = shaft: per unit length and the segment's totals,
/// moments about its mid-point on the axis), then the base plane (`part` =
/// base: totals only, moments about its point on the axis).
pub fn write_reaction(
    path: &Path,
    member: &MemberForces,
    length: &str,
    force: &str,
) -> Result<(), ReportError> {
    let mut header = vec![
        "part".to_string(),
        format!("z_top [{length}]"),
        format!("z_bottom [{length}]"),
    ];
    header.extend(reaction_columns(length, force));
    let mut numbers = Vec::new();
    let mut rows: Vec<Vec<String>> = member
        .segments
        .iter()
        .map(|s| {
            let mut v = vec![s.z_top, s.z_bottom];
            v.extend(segment_values(s));
            numbers.extend(&v);
            std::iter::once("shaft".to_string())
                .chain(v.into_iter().map(num))
                .collect()
        })
        .collect();
    let b = &member.base;
    let totals: Vec<f64> = b.force.into_iter().chain(b.moment).collect();
    numbers.push(b.z);
    numbers.extend(&totals);
    let mut row = vec!["base".to_string(), num(b.z), num(b.z)];
    row.extend(std::iter::repeat_n(String::new(), 6));
    row.extend(totals.into_iter().map(num));
    rows.push(row);
    write_atomic(path, &header, &rows, &numbers)
}

/// The reaction curves of a member over a load path: per converged step
/// (`lambda`) one row per shaft segment (`part` = shaft: the segment's
/// mean motion, its reaction per unit length and in total) and one for the
/// base plane (`part` = base: the base's motion, the totals only). The
/// motions are from the unloaded state; a segment's is the mean of its two
/// stations'.
pub fn write_reaction_curves(
    path: &Path,
    steps: &[(f64, &MemberForces)],
    length: &str,
    force: &str,
) -> Result<(), ReportError> {
    let mut header = vec![
        "lambda [-]".to_string(),
        "part".to_string(),
        format!("z_top [{length}]"),
        format!("z_bottom [{length}]"),
        format!("u_x [{length}]"),
        format!("u_y [{length}]"),
        format!("u_z [{length}]"),
        "phi_x [rad]".to_string(),
        "phi_y [rad]".to_string(),
        "phi_z [rad]".to_string(),
    ];
    header.extend(reaction_columns(length, force));
    let mut numbers = Vec::new();
    let mut rows = Vec::new();
    let fmt_rotation = |phi: Option<[f64; 3]>, numbers: &mut Vec<f64>| -> Vec<String> {
        match phi {
            Some(p) => {
                numbers.extend(p);
                p.map(num).to_vec()
            }
            None => vec![String::new(); 3],
        }
    };
    for &(lambda, m) in steps {
        for (k, s) in m.segments.iter().enumerate() {
            let (a, b) = (&m.stations[k], &m.stations[k + 1]);
            let u = [0, 1, 2].map(|c| 0.5 * (a.displacement[c] + b.displacement[c]));
            let phi = a
                .rotation
                .zip(b.rotation)
                .map(|(p, q)| [0, 1, 2].map(|c| 0.5 * (p[c] + q[c])));
            let head = [lambda, s.z_top, s.z_bottom].into_iter().chain(u);
            let mut row = vec![num(lambda), "shaft".to_string()];
            let head: Vec<f64> = head.collect();
            numbers.extend(&head);
            row.extend(head[1..].iter().map(|&v| num(v)));
            row.extend(fmt_rotation(phi, &mut numbers));
            let tail = segment_values(s);
            numbers.extend(&tail);
            row.extend(tail.into_iter().map(num));
            rows.push(row);
        }
        if let Some(toe) = m.stations.last() {
            let b = &m.base;
            let head = [lambda, b.z, b.z]
                .into_iter()
                .chain(toe.displacement)
                .collect::<Vec<_>>();
            numbers.extend(&head);
            let mut row = vec![num(lambda), "base".to_string()];
            row.extend(head[1..].iter().map(|&v| num(v)));
            row.extend(fmt_rotation(toe.rotation, &mut numbers));
            row.extend(std::iter::repeat_n(String::new(), 6));
            let totals: Vec<f64> = b.force.into_iter().chain(b.moment).collect();
            numbers.extend(&totals);
            row.extend(totals.into_iter().map(num));
            rows.push(row);
        }
    }
    write_atomic(path, &header, &rows, &numbers)
}

/// The reaction columns of a segment or base row: per unit length
/// `p_x, p_y, t, m_x, m_y, t_theta`, totals `F_x .. M_z`.
fn reaction_columns(length: &str, force: &str) -> Vec<String> {
    vec![
        format!("p_x [{force}/{length}]"),
        format!("p_y [{force}/{length}]"),
        format!("t [{force}/{length}]"),
        format!("m_x [{force}]"),
        format!("m_y [{force}]"),
        format!("t_theta [{force}]"),
        format!("F_x [{force}]"),
        format!("F_y [{force}]"),
        format!("F_z [{force}]"),
        format!("M_x [{force} {length}]"),
        format!("M_y [{force} {length}]"),
        format!("M_z [{force} {length}]"),
    ]
}

/// A segment's values in [`reaction_columns`] order.
fn segment_values(s: &axijoint_solver::members::Segment) -> Vec<f64> {
    let l = s.z_top - s.z_bottom;
    s.force
        .map(|f| f / l)
        .into_iter()
        .chain(s.moment.map(|m| m / l))
        .chain(s.force)
        .chain(s.moment)
        .collect()
}
