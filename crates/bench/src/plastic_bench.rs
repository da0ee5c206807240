//! `bench-accuracy --plastic`: the tutorial's pile in clay
//! (docs/tutorial/pile_clay.json) by axijoint (Tresca and von Mises at
//! c_u) and by the CalculiX 3D peer ([`crate::plastic_peer`], Mises at
//! sigma_y = sqrt(3) c_u), the load-displacement curves and the reaction at
//! 0.1 D; the wall time of the peer against axijoint's at equal accuracy.
//!
//! Equal accuracy: every run's error is the relative difference of its
//! reaction at 0.1 D from a reference R_ref ([`references`]: the peer
//! extrapolated to h -> 0 from its three finest sizes when it has them,
//! else axijoint's von_mises runs so extrapolated, and the finest peer run
//! as a second reference). A peer run is matched with the fastest
//! axijoint `von_mises` run whose error is no larger ([`ratios`]); the
//! ratio is peer wall time / that run's.

pub mod accuracy;
pub mod chart;

pub use accuracy::{
    extrapolate, extrapolated, format_summary, peer_two_point, ratios, reference, references, set_errors,
    Ratio, Reference,
};

pub use crate::csv_io::{read_rows, write_rows};

use crate::measure::run_measured;
use crate::plastic_peer::{self, deck::DeckParams, CurvePoint, PlasticPeerOptions};
use crate::sweep::machine_busy_seconds;
use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Everything the plastic comparison needs.
#[derive(Clone, Debug)]
pub struct PlasticConfig {
    /// The axijoint binary.
    pub axijoint: PathBuf,
    /// gmsh, for the peer (axijoint finds its own).
    pub gmsh: PathBuf,
    /// CalculiX's ccx.
    pub ccx: PathBuf,
    /// The tutorial's scene (docs/tutorial/pile_clay.json).
    pub scene: PathBuf,
    /// Scratch folder.
    pub work_dir: PathBuf,
    /// axijoint's element sizes h along the pile (m).
    pub sizes: Vec<f64>,
    /// axijoint's highest harmonic M.
    pub harmonics: usize,
    /// axijoint's laws ("tresca", "von_mises"), at the scene's c_u.
    pub laws: Vec<String>,
    /// The peer's element sizes at the pile (m); empty: no peer.
    pub peer_sizes: Vec<f64>,
    /// The peer's growth of the elements away from the pile.
    pub peer_growth: f64,
}

/// One run: a row of plastic_peer.csv.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct PlasticRow {
    /// "axijoint" or "calculix".
    pub code: String,
    /// "tresca" or "von_mises" (axijoint), "mises" (CalculiX).
    pub law: String,
    /// Element size at the pile (m).
    pub size: f64,
    /// axijoint's M (empty for the peer).
    pub harmonics: Option<usize>,
    /// Unknowns per harmonic (axijoint) or equations (CalculiX).
    pub unknowns: Option<usize>,
    /// "ok", or what went wrong.
    pub status: String,
    /// Wall time (s): `axijoint solve` (mesh from gmsh, no cache), or gmsh
    /// + ccx.
    pub wall_s: Option<f64>,
    /// CPU time, user + system (s).
    pub cpu_s: Option<f64>,
    /// Peak resident memory (MiB).
    pub peak_rss_mib: Option<f64>,
    /// CPUs other processes used meanwhile (of the machine's, /proc/stat).
    pub other_load: Option<f64>,
    /// Load steps (axijoint) or converged increments (CalculiX).
    pub steps: Option<usize>,
    /// Newton iterations, all steps.
    pub iterations: Option<usize>,
    /// Head reaction at 0.01 D (MN), linear between the curve's points.
    pub reaction_0p01d_mn: Option<f64>,
    /// Head reaction at 0.1 D (MN), whole pile.
    pub reaction_mn: Option<f64>,
    /// (reaction - R_ref) / R_ref, R_ref from [`reference()`].
    pub error_vs_reference: Option<f64>,
}

impl PlasticRow {
    /// True when the run reached the full push.
    pub fn ok(&self) -> bool {
        self.status == "ok"
    }
}

/// One point of a curve: a row of plastic_peer_curves.csv.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct CurveRow {
    /// As [`PlasticRow::code`].
    pub code: String,
    /// As [`PlasticRow::law`].
    pub law: String,
    /// As [`PlasticRow::size`].
    pub size: f64,
    /// Head displacement (m).
    pub displacement_m: f64,
    /// Head reaction (MN).
    pub reaction_mn: f64,
}

/// The per-run scene: the tutorial's with `mesh.file` absolute, `h`, M,
/// the soil's law (`c_u` kept), no cuts and no output files.
pub fn scene_json(tutorial: &Path, h: f64, harmonics: usize, law: &str) -> Result<serde_json::Value> {
    let text =
        std::fs::read_to_string(tutorial).with_context(|| format!("cannot read {}", tutorial.display()))?;
    let mut s: serde_json::Value =
        serde_json::from_str(&text).with_context(|| format!("{}", tutorial.display()))?;
    let dir = tutorial.parent().unwrap_or(Path::new("."));
    let geo = s["mesh"]["file"]
        .as_str()
        .context("the scene has no mesh.file")?
        .to_owned();
    let geo = std::path::absolute(dir.join(geo))?;
    s["mesh"]["file"] = geo.display().to_string().into();
    s["mesh"]["parameters"]["h"] = h.into();
    s["harmonics"] = harmonics.into();
    let p = &mut s["materials"]["soil"]["plasticity"];
    if !p.is_object() {
        bail!("{}: materials.soil has no plasticity", tutorial.display());
    }
    p["type"] = law.into();
    s["outputs"] = serde_json::json!({"csv": false, "plots": false, "vtu": false, "gmsh_views": false});
    s["cuts"] = serde_json::json!([]);
    Ok(s)
}

/// Runs `axijoint solve` on the tutorial's pile at `h` with `law`.
pub fn run_axijoint(cfg: &PlasticConfig, h: f64, law: &str) -> (PlasticRow, Vec<CurvePoint>) {
    let mut row = PlasticRow {
        code: "axijoint".into(),
        law: law.into(),
        size: h,
        harmonics: Some(cfg.harmonics),
        ..Default::default()
    };
    let busy = machine_busy_seconds();
    let result = try_axijoint(cfg, h, law, &mut row);
    row.other_load = other_load(busy, &row);
    match result {
        Ok(curve) => {
            row.status = "ok".into();
            finish_row(&mut row, &curve, 0.12);
            (row, curve)
        }
        Err(e) => {
            row.status = format!("failed: {}", first_line(&format!("{e:#}")));
            eprintln!("   {e:#}");
            (row, Vec::new())
        }
    }
}

/// CPUs that other processes used during `row`'s run (its wall and CPU
/// time), from the machine's busy seconds before it and now.
fn other_load(before: Option<f64>, row: &PlasticRow) -> Option<f64> {
    let (a, b) = (before?, machine_busy_seconds()?);
    let (wall, cpu) = (row.wall_s?, row.cpu_s?);
    (wall > 0.0).then(|| ((b - a - cpu) / wall).max(0.0))
}

fn first_line(s: &str) -> String {
    s.lines().next().unwrap_or("").replace(',', ";")
}

fn try_axijoint(cfg: &PlasticConfig, h: f64, law: &str, row: &mut PlasticRow) -> Result<Vec<CurvePoint>> {
    let tag = format!("axijoint_{law}_h{h}_m{}", cfg.harmonics).replace('.', "p");
    std::fs::create_dir_all(&cfg.work_dir)?;
    let scene = cfg.work_dir.join(format!("{tag}.json"));
    let json = scene_json(&cfg.scene, h, cfg.harmonics, law)?;
    std::fs::write(&scene, serde_json::to_string_pretty(&json)?)?;
    let out = cfg.work_dir.join(&tag);
    let m = run_measured(
        Command::new(&cfg.axijoint)
            .arg("solve")
            .arg(&scene)
            .args(["-q", "--no-cache", "-o"])
            .arg(&out),
    )?;
    row.wall_s = Some(m.wall_seconds);
    row.cpu_s = Some(m.cpu_seconds);
    row.peak_rss_mib = Some(m.peak_rss_bytes as f64 / 1048576.0);
    let path = out.join("solution.json");
    let sol: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?,
    )?;
    row.unknowns = sol["dofs_per_harmonic"].as_u64().map(|d| d as usize);
    let steps = sol["extra"]["load_path"]["steps"]
        .as_array()
        .with_context(|| format!("{}: no load path", path.display()))?;
    row.steps = Some(steps.len());
    row.iterations = Some(steps.iter().filter_map(|s| s["iterations"].as_u64()).sum::<u64>() as usize);
    let mut curve = vec![CurvePoint {
        displacement: 0.0,
        reaction: 0.0,
    }];
    for s in steps {
        let face = s["observed"]["faces"]
            .as_array()
            .and_then(|f| f.iter().find(|f| f["on"] == "pile_head"))
            .with_context(|| format!("{}: a step without the pile head", path.display()))?;
        let (Some(d), Some(r)) = (face["along"].as_f64(), face["applied"].as_f64()) else {
            bail!(
                "{}: a step without the head's displacement and reaction",
                path.display()
            );
        };
        curve.push(CurvePoint {
            displacement: d,
            reaction: r,
        });
    }
    let last = curve.last().map_or(0.0, |p| p.displacement);
    if (last - 0.12).abs() > 1e-9 {
        bail!("the push stopped at {last} m of 0.12");
    }
    Ok(curve)
}

/// Reaction at 0.01 D and at the end of the push from the curve.
fn finish_row(row: &mut PlasticRow, curve: &[CurvePoint], push: f64) {
    row.reaction_mn = curve.last().map(|p| p.reaction);
    row.reaction_0p01d_mn = reaction_at(curve, 0.1 * push);
}

/// The reaction at displacement `d`, linear between the curve's points
/// (None outside the curve).
pub fn reaction_at(curve: &[CurvePoint], d: f64) -> Option<f64> {
    curve.windows(2).find_map(|w| {
        let (a, b) = (w[0], w[1]);
        let span = b.displacement - a.displacement;
        (span > 0.0 && a.displacement <= d && d <= b.displacement)
            .then(|| a.reaction + (d - a.displacement) / span * (b.reaction - a.reaction))
    })
}

/// Recomputes each successful row's reactions at 0.01 D and 0.1 D from
/// its curve in `curves` (the curves are what the runs gave).
pub fn refresh_from_curves(rows: &mut [PlasticRow], curves: &[CurveRow], push: f64) {
    for row in rows.iter_mut().filter(|r| r.ok()) {
        let curve: Vec<CurvePoint> = curves
            .iter()
            .filter(|c| c.code == row.code && c.law == row.law && c.size == row.size)
            .map(|c| CurvePoint {
                displacement: c.displacement_m,
                reaction: c.reaction_mn,
            })
            .collect();
        if !curve.is_empty() {
            finish_row(row, &curve, push);
        }
    }
}

/// Runs the peer at `size`.
pub fn run_peer(cfg: &PlasticConfig, size: f64) -> (PlasticRow, Vec<CurvePoint>) {
    let mut row = PlasticRow {
        code: "calculix".into(),
        law: "mises".into(),
        size,
        ..Default::default()
    };
    let opts = PlasticPeerOptions {
        size,
        growth: cfg.peer_growth,
        work_dir: cfg.work_dir.join("peer"),
        ccx: cfg.ccx.clone(),
        gmsh: cfg.gmsh.clone(),
        deck: DeckParams::default(),
    };
    let busy = machine_busy_seconds();
    let t = std::time::Instant::now();
    let result = plastic_peer::run(&opts);
    let wall = t.elapsed().as_secs_f64();
    match result {
        Ok(r) => {
            row.unknowns = Some(r.dofs);
            row.wall_s = Some(r.cost.mesh_seconds + r.cost.ccx_wall_seconds);
            row.cpu_s = Some(r.cost.mesh_seconds + r.cost.ccx_cpu_seconds);
            row.peak_rss_mib = Some(r.cost.ccx_peak_rss_bytes as f64 / 1048576.0);
            row.steps = Some(r.increments);
            row.iterations = Some(r.iterations);
            row.status = if r.completed {
                "ok".into()
            } else {
                let last = r.curve.last().map_or(0.0, |p| p.displacement);
                format!("stopped at {last:.4} m")
            };
            finish_row(&mut row, &r.curve, opts.deck.push);
            // The whole run (gmsh, deck, ccx, reading) against the CPU of gmsh
            // and ccx: the deck's writing and reading count as other load.
            let own = PlasticRow {
                wall_s: Some(wall),
                ..row.clone()
            };
            row.other_load = other_load(busy, &own);
            (row, r.curve)
        }
        Err(e) => {
            row.status = format!("failed: {}", first_line(&format!("{e:#}")));
            eprintln!("   {e:#}");
            (row, Vec::new())
        }
    }
}

/// The curve rows of one run.
pub fn curve_rows(row: &PlasticRow, curve: &[CurvePoint]) -> Vec<CurveRow> {
    curve
        .iter()
        .map(|p| CurveRow {
            code: row.code.clone(),
            law: row.law.clone(),
            size: row.size,
            displacement_m: p.displacement,
            reaction_mn: p.reaction,
        })
        .collect()
}

/// Runs axijoint (each law and size) and the peer (each size, coarse to
/// fine); writes nothing. Progress goes to stdout, and the rows so far to
/// WORK/plastic_progress.csv.
pub fn run_all(cfg: &PlasticConfig) -> Result<(Vec<PlasticRow>, Vec<CurveRow>)> {
    let mut rows = Vec::new();
    let mut curves = Vec::new();
    let mut sizes = cfg.sizes.clone();
    sizes.sort_by(|a, b| b.total_cmp(a));
    let mut peer_sizes = cfg.peer_sizes.clone();
    peer_sizes.sort_by(|a, b| b.total_cmp(a));
    let total = sizes.len() * cfg.laws.len() + peer_sizes.len();
    let mut k = 0;
    let mut report = |row: PlasticRow, curve: Vec<CurvePoint>| -> Result<()> {
        let f = |x: Option<f64>, d: usize| x.map_or("-".to_owned(), |v| format!("{v:.d$}"));
        println!(
            "   {}: {} unknowns, {} s, {} MiB, {} steps, {} iterations, R(0.1 D) = {} MN, other load {} CPUs",
            row.status,
            row.unknowns.map_or("-".into(), |u| u.to_string()),
            f(row.wall_s, 1),
            f(row.peak_rss_mib, 0),
            row.steps.map_or("-".into(), |u| u.to_string()),
            row.iterations.map_or("-".into(), |u| u.to_string()),
            f(row.reaction_mn, 4),
            f(row.other_load, 2),
        );
        curves.extend(curve_rows(&row, &curve));
        rows.push(row);
        write_rows(&cfg.work_dir.join("plastic_progress.csv"), &rows)
    };
    for law in &cfg.laws {
        for &h in &sizes {
            k += 1;
            println!("[{k}/{total}] axijoint {law} h {h} M {}", cfg.harmonics);
            let (row, curve) = run_axijoint(cfg, h, law);
            report(row, curve)?;
        }
    }
    for &h in &peer_sizes {
        k += 1;
        println!("[{k}/{total}] calculix mises h {h}");
        let (row, curve) = run_peer(cfg, h);
        report(row, curve)?;
    }
    Ok((rows, curves))
}

/// The whole `--plastic` command: runs [`run_all`] (or, with `replot`,
/// reads its rows and curves back), recomputes the reactions from the
/// curves and the errors against [`reference()`], writes
/// `out_dir/plastic_peer.csv`, `plastic_peer_curves.csv` (not when
/// replotting) and the chart `plastic_peer.svg` and `.png`, and prints
/// [`format_summary`]. With `keep_peer` (no peer run) the CalculiX rows and
/// curves already in `out_dir` are kept.
pub fn command(cfg: &PlasticConfig, out_dir: &Path, replot: Option<&Path>, keep_peer: bool) -> Result<()> {
    std::fs::create_dir_all(out_dir).with_context(|| format!("cannot create {}", out_dir.display()))?;
    let csv_path = out_dir.join("plastic_peer.csv");
    let curves_path = out_dir.join("plastic_peer_curves.csv");
    let (mut rows, curves) = if let Some(csv) = replot {
        let curves = csv.with_file_name("plastic_peer_curves.csv");
        (read_rows(csv)?, read_rows(&curves)?)
    } else {
        let (mut rows, mut curves) = run_all(cfg)?;
        if keep_peer && csv_path.is_file() && curves_path.is_file() {
            let old: Vec<PlasticRow> = read_rows(&csv_path)?;
            let old_curves: Vec<CurveRow> = read_rows(&curves_path)?;
            rows.extend(old.into_iter().filter(|r| r.code == "calculix"));
            curves.extend(old_curves.into_iter().filter(|r| r.code == "calculix"));
            println!("kept the CalculiX rows of {}", csv_path.display());
        }
        (rows, curves)
    };
    refresh_from_curves(&mut rows, &curves, plastic_peer::deck::PUSH);
    if let Some(r) = reference(&rows) {
        set_errors(&mut rows, &r);
    }
    // Replotting rewrites the rows too: their reactions and errors are
    // derived from the curves.
    write_rows(&csv_path, &rows)?;
    println!("wrote {}", csv_path.display());
    if replot.is_none() {
        write_rows(&curves_path, &curves)?;
        println!("wrote {}", curves_path.display());
    }
    let svg = out_dir.join("plastic_peer.svg");
    chart::write_chart(&rows, &curves, &svg)?;
    println!("wrote {} and .png", svg.display());
    println!("\n{}", format_summary(&rows, "von_mises"));
    Ok(())
}
