//! CSV files: cut profiles, joint fields, convergence histories
//! (columns documented in `docs/outputs.md`).

use crate::cuts::CutRow;
use crate::error::ReportError;
use crate::field::STRESS_NAMES;
use axijoint_solver::iteration::IterationRecord;
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

/// A cut profile at one theta: `s, r, z, theta, body, sigma_r ... tau_ztheta`.
pub fn write_cut(path: &Path, rows: &[CutRow], length: &str, stress: &str) -> Result<(), ReportError> {
    let mut header = vec![
        format!("s [{length}]"),
        format!("r [{length}]"),
        format!("z [{length}]"),
        "theta [deg]".to_string(),
        "body".to_string(),
    ];
    header.extend(STRESS_NAMES.iter().map(|n| format!("{n} [{stress}]")));
    let numbers: Vec<f64> = rows
        .iter()
        .flat_map(|r| [r.s, r.r, r.z, r.theta_deg].into_iter().chain(r.stress))
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
pub fn write_load_path(path: &Path, load_path: &LoadPath, length: &str) -> Result<(), ReportError> {
    let Some(first) = load_path.steps.first() else {
        return write_atomic(path, &["lambda [-]".to_string()], &[], &[]);
    };
    let mut header = vec!["lambda [-]".to_string()];
    for f in &first.observed.faces {
        for c in ["ux", "uy", "uz", "along_load"] {
            header.push(format!("{}_{c} [{length}]", f.on));
        }
        header.push(format!("{}_rotation [rad]", f.on));
    }
    for j in &first.observed.joints {
        for c in ["open", "slip", "stick"] {
            header.push(format!("{}_{c}_area [{length}^2]", j.joint));
        }
    }
    header.extend(["iterations [-]", "solves [-]", "rounds [-]", "cutbacks [-]"].map(String::from));
    let mut numbers = Vec::new();
    let rows = load_path
        .steps
        .iter()
        .map(|s| {
            let mut v = vec![s.lambda];
            for f in &s.observed.faces {
                v.extend(f.mean);
                v.push(f.along);
                v.push(f.rotation);
            }
            for j in &s.observed.joints {
                v.extend([j.open, j.slip, j.stick]);
            }
            numbers.extend(&v);
            let mut row: Vec<String> = v.into_iter().map(num).collect();
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
