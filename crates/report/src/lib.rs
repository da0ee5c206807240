//! What the user reads: stress profiles along cuts, joint fields,
//! convergence histories, plots, and 3D views of a saved solution.
//!
//! | symbol | meaning |
//! |---|---|
//! | r, z, theta | cylindrical coordinates; theta = 0 on +x |
//! | s | distance along a cut or a joint |
//! | sigma_r ... tau_ztheta | stress components (tension positive) |
//! | sigma, tau_xi, tau_theta | joint normal and shear tractions |
//! | d_xi, d_eta, d_theta | joint relative displacement (top - bottom) |
//!
//! | main items | role |
//! |---|---|
//! | [`field::Locator`] | R-tree point location in the meridional mesh |
//! | [`field::Field`] | displacement and stress synthesized at any theta, per body |
//! | [`cuts::profile`] | a cut's rows, two per interface crossing |
//! | [`cuts::joint_crossings`], [`cut_plot`] | where a cut meets joints; a cut's plot |
//! | [`csv_out`] | CSV writers |
//! | [`plots`] | SVG and PNG plots (embedded font) |
//! | [`vtu`], [`gmsh_view`] | the field revolved for ParaView; a gmsh view |
//! | [`write_report`] | every output of a solution folder |

pub mod adapt;
pub mod csv_out;
pub mod cut_plot;
pub mod cuts;
pub mod error;
pub mod estimate;
pub mod field;
pub mod gmsh_view;
pub mod plots;
pub mod vtu;

pub use error::ReportError;

use axijoint_solver::iteration::IterationRecord;
use axijoint_solver::results::LoadPath;
use axijoint_solver::results::{read_joint_field, SavedSolution};
use axijoint_solver::scene::VtuSections;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Files written by [`write_report`], relative to the solution folder.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Written {
    /// Paths written.
    pub files: Vec<PathBuf>,
    /// The estimated error of every cut profile: `(cut, theta in degrees,
    /// fraction of the profile's max |stress|)` ([`estimate::cut_error`]).
    pub estimated_error: Vec<(String, f64, f64)>,
    /// The estimated relative error of the whole field in the energy norm.
    pub energy_error: f64,
}

/// The materials of a saved solution's bodies.
fn materials(saved: &SavedSolution) -> Result<Vec<axijoint_solver::material::Elastic>, ReportError> {
    saved
        .mesh
        .bodies
        .iter()
        .map(|b| {
            saved
                .header
                .scene
                .materials
                .get(&b.name)
                .map(|m| m.elastic())
                .ok_or_else(|| ReportError::Input(format!("no material for body '{}'", b.name)))
        })
        .collect()
}

/// The iteration history saved in a solution's header, if any.
pub fn history(saved: &SavedSolution) -> Option<&[IterationRecord]> {
    saved.header.record.as_ref()?.history.as_deref()
}

/// The load path of a stepped run, if the solution has one.
pub fn load_path(saved: &SavedSolution) -> Option<&LoadPath> {
    saved.header.record.as_ref()?.load_path.as_ref()
}

/// One output of the report: writes its files and returns their names.
type Task<'a> = Box<dyn FnOnce() -> Result<Vec<String>, ReportError> + Send + 'a>;

/// Writes every report output of a saved solution into `dir` (the solution
/// folder itself), as the scene's `outputs` asks: cut, joint and
/// convergence CSVs; plots of the cuts (with `companion`, the run without
/// joints, dashed), of the joint states and of the convergence (with the
/// `compare` runs' histories on the same axis, this run's labelled `label`,
/// default its scene's title), PNG copies with `outputs.png`; the revolved
/// `.vtu` and the gmsh view. The outputs are independent and written in
/// parallel (rayon), the error estimate alongside; the file list keeps the
/// order above.
pub fn write_report(
    dir: &Path,
    saved: &SavedSolution,
    companion: Option<&SavedSolution>,
    label: Option<&str>,
    compare: &[(String, Vec<IterationRecord>)],
) -> Result<Written, ReportError> {
    let scene = &saved.header.scene;
    let outputs = &scene.outputs;
    let mats = materials(saved)?;
    let field = field::Field {
        mesh: &saved.mesh,
        materials: &mats,
        u: &saved.displacements,
        initial: field::Initial::of(saved),
    };
    // The initial state alone (its own cut files).
    let no_displacement = axijoint_solver::solution::Displacements {
        harmonics: Vec::new(),
    };
    let initial_field = field.initial.as_ref().map(|init| field::Field {
        mesh: &saved.mesh,
        materials: &mats,
        u: init.u.unwrap_or(&no_displacement),
        initial: Some(field::Initial {
            stress: init.stress.clone(),
            u: None,
        }),
    });
    let locator = field::Locator::new(&saved.mesh);
    let (length, stress) = (&scene.units.length, &scene.units.stress);
    let png = |name: &str| outputs.png.then(|| dir.join(format!("{name}.png")));
    let plot_files = |name: &str| {
        let mut f = vec![format!("{name}.svg")];
        if outputs.png {
            f.push(format!("{name}.png"));
        }
        f
    };
    let joints = read_joint_field(dir).map_err(|e| ReportError::Input(e.to_string()))?;
    let history = history(saved);
    let path = load_path(saved);
    // One estimate for the cut errors and the `.vtu`'s cell errors.
    let estimate = OnceLock::new();
    // A cut's files; `other`: the run without joints and its locator.
    let write_cut = |cut: &axijoint_solver::scene::Cut,
                     other: Option<(&field::Field, &field::Locator)>|
     -> Result<Vec<String>, ReportError> {
        let mut files = Vec::new();
        let mut series = Vec::new();
        for (k, &t) in cut.theta_deg.iter().enumerate() {
            let rows = cuts::profile(&field, &locator, &[cut.from, cut.to], cut.spacing, &[t]);
            if outputs.csv {
                let name = format!("cut_{}_theta{}.csv", cut.name, fmt_angle(t));
                csv_out::write_cut(&dir.join(&name), &rows, length, stress)?;
                files.push(name);
                if let Some(f) = &initial_field {
                    let rows = cuts::profile(f, &locator, &[cut.from, cut.to], cut.spacing, &[t]);
                    let name = format!("cut_{}_theta{}_initial.csv", cut.name, fmt_angle(t));
                    csv_out::write_cut(&dir.join(&name), &rows, length, stress)?;
                    files.push(name);
                }
            }
            if !outputs.plots {
                continue;
            }
            let c = cut.component_index().unwrap_or(1);
            let with_joints = !saved.mesh.joints.is_empty();
            series.extend(by_body(
                &rows,
                c,
                t,
                k,
                &saved.mesh,
                if with_joints { "with joint" } else { "" },
                false,
            ));
            if let Some((f, loc)) = other {
                let rows = cuts::profile(f, loc, &[cut.from, cut.to], cut.spacing, &[t]);
                series.extend(by_body(&rows, c, t, k, f.mesh, "without joint", true));
            }
        }
        if outputs.plots {
            files.extend(cut_plot::write(
                dir,
                cut,
                &saved.mesh,
                series,
                length,
                stress,
                outputs.png,
            )?);
        }
        Ok(files)
    };
    let mut tasks: Vec<Task> = Vec::new();
    if let Some(jf) = &joints {
        for j in &saved.mesh.joints {
            let (png, plot_files) = (&png, &plot_files);
            tasks.push(Box::new(move || {
                let mut files = Vec::new();
                if outputs.csv {
                    let name = format!("joint_{}.csv", j.name);
                    csv_out::write_joint(&dir.join(&name), jf, &j.name, length, stress)?;
                    files.push(name);
                }
                if outputs.plots {
                    let mut order: Vec<usize> = (0..jf.points.len())
                        .filter(|&i| jf.points[i].joint == j.name)
                        .collect();
                    order.sort_by(|&a, &b| jf.points[a].s.total_cmp(&jf.points[b].s));
                    order.dedup_by(|a, b| jf.points[*a].s == jf.points[*b].s);
                    let s: Vec<f64> = order.iter().map(|&i| jf.points[i].s).collect();
                    let states: Vec<Vec<_>> = jf
                        .values
                        .iter()
                        .map(|v| order.iter().map(|&i| v[i].state).collect())
                        .collect();
                    let name = format!("joint_{}_states", j.name);
                    plots::plot_joint_map(
                        &dir.join(format!("{name}.svg")),
                        png(&name).as_deref(),
                        &format!("Joint {}: state over s ({length}) and theta", j.name),
                        &s,
                        &jf.sections_deg,
                        &states,
                    )?;
                    files.extend(plot_files(&name));
                }
                Ok(files)
            }));
        }
    }
    if let Some(history) = &history {
        let (png, plot_files) = (&png, &plot_files);
        tasks.push(Box::new(move || {
            let mut files = Vec::new();
            if outputs.csv {
                csv_out::write_convergence(&dir.join("convergence.csv"), history)?;
                files.push("convergence.csv".into());
            }
            if outputs.plots {
                let mut runs = vec![(
                    label.unwrap_or(&scene.title).to_owned(),
                    history.iter().map(|r| (r.iteration, r.ratio)).collect(),
                )];
                runs.extend(
                    compare.iter().map(|(label, h)| {
                        (label.clone(), h.iter().map(|r| (r.iteration, r.ratio)).collect())
                    }),
                );
                plots::plot_convergence(
                    &dir.join("convergence.svg"),
                    png("convergence").as_deref(),
                    "Residual ratio (Eq. 12) against iteration",
                    &runs,
                )?;
                files.extend(plot_files("convergence"));
            }
            Ok(files)
        }));
    }
    if let Some(path) = &path {
        let (png, plot_files) = (&png, &plot_files);
        tasks.push(Box::new(move || {
            let mut files = Vec::new();
            if outputs.csv {
                csv_out::write_load_path(&dir.join("load_path.csv"), path, length)?;
                files.push("load_path.csv".into());
            }
            if outputs.plots && !path.steps.is_empty() {
                // Pushover curves: lambda against each loaded face's displacement
                // along its load, from the unloaded state.
                let n_faces = path.steps[0].observed.faces.len();
                let series: Vec<plots::Series> = (0..n_faces)
                    .map(|k| plots::Series {
                        label: format!("{}, along the load", path.steps[0].observed.faces[k].on),
                        points: std::iter::once((0.0, 0.0))
                            .chain(path.steps.iter().map(|s| (s.observed.faces[k].along, s.lambda)))
                            .collect(),
                        color: k,
                        dash: 0,
                    })
                    .collect();
                let title = match &path.limit {
                    Some(l) => format!(
                        "Load path: limit load factor {:.4} (failed at {:.4})",
                        l.factor, l.failed_at
                    ),
                    None => "Load path: load factor against displacement".to_string(),
                };
                plots::plot_profile(
                    &dir.join("load_path.svg"),
                    png("load_path").as_deref(),
                    &title,
                    &format!("displacement along the load ({length})"),
                    "load factor lambda (-)",
                    &series,
                )?;
                files.extend(plot_files("load_path"));
            }
            Ok(files)
        }));
    }
    let views = tasks.len();
    if outputs.vtu {
        let (field, joints, estimate) = (&field, &joints, &estimate);
        tasks.push(Box::new(move || {
            let path = dir.join("field.vtu");
            let n_sections = match outputs.vtu_sections {
                VtuSections::Count(n) => n,
                VtuSections::Auto => {
                    let m_max = field.u.harmonics.iter().map(|h| h.m as usize).max().unwrap_or(0);
                    vtu::auto_sections(field.mesh, m_max)
                }
            };
            let fields: Vec<&str> = outputs.vtu_fields.iter().map(String::as_str).collect();
            let density = || {
                estimate
                    .get_or_init(|| estimate::Estimate::new(field))
                    .cell_density()
            };
            let encoding = if outputs.vtu_compress {
                vtu::Encoding::Zlib
            } else {
                vtu::Encoding::Raw
            };
            vtu::write_vtu_with(
                &path,
                field,
                n_sections,
                &fields,
                joints.as_ref(),
                &density,
                encoding,
            )?;
            let mut files = vec!["field.vtu".to_string()];
            if joints.is_some() && !saved.mesh.joints.is_empty() {
                files.push(
                    vtu::joints_path(&path)
                        .file_name()
                        .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
                );
            }
            Ok(files)
        }));
    }
    if outputs.gmsh_views {
        let field = &field;
        tasks.push(Box::new(move || {
            let mut thetas: Vec<f64> = scene
                .cuts
                .iter()
                .flat_map(|c| c.theta_deg.iter().copied())
                .collect();
            thetas.sort_by(f64::total_cmp);
            thetas.dedup();
            if thetas.is_empty() {
                thetas.push(0.0);
            }
            gmsh_view::write_gmsh_view(&dir.join("field_views.msh"), field, &thetas)?;
            Ok(vec!["field_views.msh".into()])
        }));
    }
    // The cuts, with the run without joints when there is one.
    let write_cuts = |other: Option<&SavedSolution>| -> Result<Vec<String>, ReportError> {
        use rayon::prelude::*;
        let parts = match other {
            Some(c) => Some((c, materials(c)?, field::Locator::new(&c.mesh))),
            None => None,
        };
        let other = parts.as_ref().map(|(c, m, loc)| {
            let f = field::Field {
                mesh: &c.mesh,
                materials: m,
                u: &c.displacements,
                initial: field::Initial::of(c),
            };
            (f, loc)
        });
        let files = scene
            .cuts
            .par_iter()
            .map(|cut| write_cut(cut, other.as_ref().map(|(f, l)| (f, *l))))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(files.concat())
    };
    // The revolved views take longest: spawned first, the estimate's cut
    // errors last (the `.vtu` makes the estimate); every worker takes the
    // oldest task left.
    let slots: Vec<OnceLock<Result<Vec<String>, ReportError>>> =
        tasks.iter().map(|_| OnceLock::new()).collect();
    let (cut_files, estimated) = (OnceLock::new(), OnceLock::new());
    rayon::scope_fifo(|s| {
        let mut tasks: Vec<Option<Task>> = tasks.into_iter().map(Some).collect();
        let mut spawn = |k: usize| {
            if let Some(t) = tasks[k].take() {
                let slot = &slots[k];
                s.spawn_fifo(move |_| {
                    let _ = slot.set(t());
                });
            }
        };
        (views..slots.len()).for_each(&mut spawn);
        let (write_cuts, cut_files) = (&write_cuts, &cut_files);
        s.spawn_fifo(move |_| {
            let _ = cut_files.set(write_cuts(companion));
        });
        (0..views).for_each(spawn);
        let (field, locator, estimate, estimated) = (&field, &locator, &estimate, &estimated);
        s.spawn_fifo(move |_| {
            let estimate = estimate.get_or_init(|| estimate::Estimate::new(field));
            let _ = estimated.set((
                estimate::cut_errors(field, estimate, locator, &scene.cuts),
                estimate.relative(),
            ));
        });
    });
    let cut_files = cut_files.into_inner().expect("the cuts were written")?;
    let (estimated_error, energy_error) = estimated.into_inner().expect("the estimate ran");
    let mut written = Written {
        files: cut_files.into_iter().map(PathBuf::from).collect(),
        estimated_error,
        energy_error,
    };
    for slot in slots {
        let files = slot.into_inner().expect("every task ran")?;
        written.files.extend(files.into_iter().map(PathBuf::from));
    }
    Ok(written)
}

/// One plot series per body of a cut's rows (a jump at an interface shows
/// as two lines), as `(s, value)`; colour slot `k * bodies + body`, dash 1
/// when `dashed`.
fn by_body(
    rows: &[cuts::CutRow],
    component: usize,
    theta: f64,
    k: usize,
    mesh: &axijoint_mesh::Mesh,
    variant: &str,
    dashed: bool,
) -> Vec<plots::Series> {
    mesh.bodies
        .iter()
        .enumerate()
        .filter_map(|(b, body)| {
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.body == body.name)
                .map(|r| (r.s, r.stress[component]))
                .collect();
            let sep = if variant.is_empty() { "" } else { ", " };
            (!points.is_empty()).then(|| plots::Series {
                label: format!("theta {theta} deg, {}{sep}{variant}", body.name),
                points,
                color: k * mesh.bodies.len() + b,
                dash: usize::from(dashed),
            })
        })
        .collect()
}

/// An angle for file names: `0`, `180`, `22.5`.
pub fn fmt_angle(t: f64) -> String {
    let s = format!("{t}");
    s.replace('-', "m")
}
