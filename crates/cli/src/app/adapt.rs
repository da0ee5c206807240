//! `mesh.adapt`: solve, estimate the error, re-mesh the `.geo` with a
//! background size view, until every cut profile's estimated error is
//! below the target and the profiles moved by less than the target since
//! the cycle before, or the cycles run out (docs/accuracy.md).

use super::solve::solve_to_then;
use anyhow::{ensure, Context, Result};
use axijoint_report::adapt::{mesh_with_background, new_sizes, write_background};
use axijoint_report::cuts::profile;
use axijoint_report::estimate::{profile_estimates, Estimate};
use axijoint_report::field::{Field, Initial, Locator};
use axijoint_report::fmt_angle;
use axijoint_solver::results::{read_solution, AdaptCycle, AdaptTable, PerProfile, SolutionHeader};
use axijoint_solver::scene::Scene;
use std::collections::HashMap;
use std::path::Path;
use std::time::Instant;

/// The table of cycles, one CSV row per cycle.
pub const CYCLES_CSV: &str = "adapt.csv";

/// The last size view, for gmsh.
pub const SIZE_VIEW: &str = "adapt_size.pos";

/// One cycle: its mesh, the estimates on it, its time.
struct Cycle {
    nodes: usize,
    dofs: usize,
    energy: f64,
    /// `(cut, theta in degrees, estimated error)`.
    profiles: Vec<(String, f64, f64)>,
    /// Each profile's largest change from the cycle before, as a fraction
    /// of its max |stress| on this cycle (`None` on the first cycle).
    changes: Option<Vec<f64>>,
    seconds: f64,
}

/// A profile's values by (position along the cut in 1e-9, body).
type Samples = HashMap<(i64, String), f64>;

/// The samples of every (cut, theta) of `cuts` on `field`, in
/// [`profile_estimates`]' order.
fn samples(field: &Field, locator: &Locator, cuts: &[axijoint_solver::scene::Cut]) -> Vec<Samples> {
    let mut out = Vec::new();
    for cut in cuts {
        let c = cut.component_index().unwrap_or(1);
        for &t in &cut.theta_deg {
            let rows = profile(field, locator, &[cut.from, cut.to], cut.spacing, &[t]);
            out.push(
                rows.into_iter()
                    .map(|r| (((r.s * 1e9).round() as i64, r.body), r.stress[c]))
                    .collect(),
            );
        }
    }
    out
}

/// The largest change from `before` to `now` at the samples both have, as
/// a fraction of `now`'s max |value|.
fn change(before: &Samples, now: &Samples) -> f64 {
    let max = now.values().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = now
        .iter()
        .filter_map(|(k, v)| before.get(k).map(|b| (v - b).abs()))
        .fold(0.0f64, f64::max);
    if max > 0.0 {
        diff / max
    } else {
        0.0
    }
}

/// Solves `scene` (with `mesh.adapt`) into `out`, re-meshing until the
/// target is met; the solution left in `out` is the last cycle's, with the
/// table of cycles in `extra.adapt` and in [`CYCLES_CSV`]. `iterating`:
/// as in [`super::solve_to_then`].
pub fn solve_adaptive(
    scene: &Scene,
    out: &Path,
    quiet: bool,
    iterating: &dyn Fn(),
) -> Result<SolutionHeader> {
    let adapt = scene.mesh.adapt.context("no mesh.adapt")?;
    ensure!(
        adapt.target > 0.0 && adapt.target < 1.0,
        "mesh.adapt.target {}: must lie in (0, 1) (a fraction: 0.01 = 1 %)",
        adapt.target
    );
    let geo = scene.mesh_path();
    ensure!(
        geo.extension().is_some_and(|e| e.eq_ignore_ascii_case("geo")),
        "mesh.adapt re-meshes a .geo with gmsh; {} is not one",
        geo.display()
    );
    ensure!(
        !scene.cuts.is_empty(),
        "mesh.adapt: its target is on the cuts' profiles; the scene has no cuts"
    );
    let params = scene.gmsh_parameters();
    let tmp = super::stale::tempdir().context("creating a temporary folder")?;
    let mut current = scene.clone();
    let mut cycles: Vec<Cycle> = Vec::new();
    let mut last_view = None;
    let mut start = Instant::now();
    // The profiles of the cycle before, and the sizing target's factor.
    let mut before: Option<Vec<Samples>> = None;
    let mut tighten = 1.0;
    let mut header = loop {
        let header = solve_to_then(&current, out, quiet, iterating)?;
        let saved = read_solution(out)?;
        let materials: Vec<_> = saved
            .mesh
            .bodies
            .iter()
            .map(|b| scene.materials[&b.name].elastic())
            .collect();
        let field = Field {
            mesh: &saved.mesh,
            materials: &materials,
            u: &saved.displacements,
            initial: Initial::of(&saved),
        };
        let estimate = Estimate::new(&field);
        let locator = Locator::new(&saved.mesh);
        let rows = profile_estimates(&field, &estimate, &locator, &scene.cuts);
        let worst = rows.iter().map(|r| r.2).fold(0.0, f64::max);
        let now = samples(&field, &locator, &scene.cuts);
        let changes = before
            .as_ref()
            .map(|b| b.iter().zip(&now).map(|(b, n)| change(b, n)).collect::<Vec<_>>());
        let moved = changes.as_ref().map(|c| c.iter().copied().fold(0.0, f64::max));
        before = Some(now);
        cycles.push(Cycle {
            nodes: saved.mesh.nodes.len(),
            dofs: header.dofs_per_harmonic,
            energy: estimate.relative(),
            profiles: rows.iter().map(|r| (r.0.clone(), r.1, r.2)).collect(),
            changes,
            seconds: start.elapsed().as_secs_f64(),
        });
        let k = cycles.len() - 1;
        print_cycle(k, &cycles[k]);
        let confirmed = moved.is_some_and(|m| m <= adapt.target);
        if (worst <= adapt.target && confirmed) || k >= adapt.max_cycles as usize {
            break header;
        }
        // The estimate says the target is met but the profiles still move
        // (or there is no cycle before to tell): the estimate is low
        // somewhere (near a singular point it is, by up to 2): ask for more.
        if worst <= adapt.target {
            tighten *= 0.5;
        }
        start = Instant::now();
        let scale = rows
            .iter()
            .map(|r| r.3)
            .filter(|&m| m > 0.0)
            .fold(f64::INFINITY, f64::min);
        let sizes = new_sizes(&field, &estimate, scale, tighten * adapt.target);
        let view = tmp.path().join(format!("size_{k}.pos"));
        write_background(&view, &saved.mesh, &sizes)
            .with_context(|| format!("writing {}", view.display()))?;
        let msh = tmp.path().join(format!("adapt_{}.msh", k + 1));
        mesh_with_background(&geo, &params, &view, &msh)?;
        last_view = Some(view);
        current.mesh.file = msh.to_string_lossy().into_owned();
        current.mesh.parameters.clear();
        current.mesh.adapt = None;
    };
    let reached = cycles.last().is_some_and(|c| {
        c.profiles.iter().all(|p| p.2 <= adapt.target)
            && c.changes
                .as_ref()
                .is_some_and(|m| m.iter().all(|&m| m <= adapt.target))
    });
    if !reached {
        crate::say!(
            "  WARNING: mesh.adapt did not reach {} % on every profile, confirmed by a change below it from the cycle before, in {} cycles (docs/accuracy.md)",
            100.0 * adapt.target,
            adapt.max_cycles
        );
    }
    // The table: CSV, solution.json extra.adapt, and the header returned.
    let table = AdaptTable {
        target: adapt.target,
        max_cycles: adapt.max_cycles,
        reached,
        cycles: cycles
            .iter()
            .enumerate()
            .map(|(k, c)| adapt_cycle(k, c))
            .collect(),
    };
    write_csv(&out.join(CYCLES_CSV), &cycles)?;
    if let Some(view) = last_view {
        std::fs::copy(&view, out.join(SIZE_VIEW)).with_context(|| format!("writing {}", out.display()))?;
    }
    header.record.get_or_insert_with(Default::default).adapt = Some(table);
    let path = out.join("solution.json");
    axijoint_mesh::atomic::write_bytes(&path, serde_json::to_string_pretty(&header)?.as_bytes())?;
    Ok(header)
}

/// The table row of cycle `k`.
fn adapt_cycle(k: usize, c: &Cycle) -> AdaptCycle {
    let mut per_cut = PerProfile::new();
    let mut moved = PerProfile::new();
    for (i, (cut, t, e)) in c.profiles.iter().enumerate() {
        per_cut.entry(cut.clone()).or_default().insert(fmt_angle(*t), *e);
        if let Some(m) = &c.changes {
            moved.entry(cut.clone()).or_default().insert(fmt_angle(*t), m[i]);
        }
    }
    AdaptCycle {
        cycle: k,
        nodes: c.nodes,
        dofs_per_harmonic: c.dofs,
        estimated_error: per_cut,
        change: c.changes.is_some().then_some(moved),
        estimated_energy_error: c.energy,
        seconds: c.seconds,
    }
}

/// One line per cycle on the console.
fn print_cycle(k: usize, c: &Cycle) {
    let parts: Vec<String> = c
        .profiles
        .iter()
        .enumerate()
        .map(|(i, (cut, t, e))| match &c.changes {
            Some(m) => format!("{cut} {t}: {:.2} % (moved {:.2} %)", 100.0 * e, 100.0 * m[i]),
            None => format!("{cut} {t}: {:.2} %", 100.0 * e),
        })
        .collect();
    crate::say!(
        "  adapt cycle {k}: {} unknowns per harmonic ({} nodes); estimated {}; energy norm {:.2} %; {:.2} s",
        c.dofs,
        c.nodes,
        parts.join(", "),
        100.0 * c.energy,
        c.seconds
    );
}

/// `cycle, nodes, dofs_per_harmonic, <cut>_theta<deg>..., energy, seconds,
/// <cut>_theta<deg>_change...` (the changes empty on the first cycle).
fn write_csv(path: &Path, cycles: &[Cycle]) -> Result<()> {
    let mut text = String::from("cycle,nodes,dofs_per_harmonic");
    let names: Vec<String> = cycles.first().map_or_else(Vec::new, |c| {
        c.profiles
            .iter()
            .map(|(cut, t, _)| format!("{cut}_theta{}", fmt_angle(*t)))
            .collect()
    });
    for name in &names {
        text += &format!(",{name}");
    }
    text += ",energy_norm,seconds";
    for name in &names {
        text += &format!(",{name}_change");
    }
    text += "\n";
    for (k, c) in cycles.iter().enumerate() {
        text += &format!("{k},{},{}", c.nodes, c.dofs);
        for (_, _, e) in &c.profiles {
            text += &format!(",{e:.9e}");
        }
        text += &format!(",{:.9e},{:.3}", c.energy, c.seconds);
        for i in 0..c.profiles.len() {
            match &c.changes {
                Some(m) => text += &format!(",{:.9e}", m[i]),
                None => text += ",",
            }
        }
        text += "\n";
    }
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
}
