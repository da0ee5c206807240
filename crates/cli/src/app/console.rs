//! The console: the progress display of a solve and the summary of a
//! solution folder (best effort, see [`crate::say!`]).

use axijoint_solver::iteration::IterationRecord;
use axijoint_solver::results::SolutionHeader;
use axijoint_solver::scene::{Load, Scene, SpringSource};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::path::Path;
use std::time::Duration;

/// A spinner on stderr with the elapsed time and a message (hidden when
/// `quiet`).
pub fn progress_bar(quiet: bool) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let b = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    b.set_style(ProgressStyle::with_template("{spinner} {elapsed} {msg}").expect("valid template"));
    b.enable_steady_tick(Duration::from_millis(200));
    b.set_message("meshing and factorizing");
    b
}

/// The progress line of an iteration.
pub fn progress_message(r: &IterationRecord) -> String {
    format!(
        "load factor {:.4}  iteration {:>4}  residual ratio {:.3e}  open {}  slip {}",
        r.load_factor, r.iteration, r.ratio, r.open, r.slip
    )
}

/// The summary of a solution folder on the console.
pub fn print_summary(path: &Path, scene: &Scene, header: &SolutionHeader, out: &Path) {
    crate::say!("{}: {}", path.display(), scene.title);
    crate::say!(
        "  {} nodes, {} elements, {} unknowns per harmonic, harmonics 0..={}",
        header.mesh.nodes,
        header.mesh.elements,
        header.dofs_per_harmonic,
        header.harmonics.last().copied().unwrap_or(0)
    );
    let t = &header.timings;
    crate::say!(
        "  time: setup {:.3} s, assembly + factorization {:.3} s, solve {:.3} s",
        t.setup,
        t.factorize,
        t.solve
    );
    // The springs the run computed (rigid, thickness); given ones are the scene's.
    let computed = header
        .record
        .iter()
        .flat_map(|r| &r.joint_springs)
        .filter(|(_, k)| k.source != SpringSource::Given);
    for (name, k) in computed {
        crate::say!(
            "  joint {name}: k_xi {:.4e}, k_eta {:.4e}, k_theta {:.4e} {}/{} ({})",
            k.k_xi,
            k.k_eta,
            k.k_theta,
            scene.units.stress,
            scene.units.length,
            match k.source {
                SpringSource::Rigid => "rigid",
                SpringSource::Thickness => "from the layer's thickness",
                SpringSource::Given => "given",
            }
        );
    }
    if let Some(i) = &header.initial {
        let b = &i.balance;
        crate::say!(
            "  initial phase: {}weight {:.6e} {f}, out-of-balance {:.3e} {f} ({:.2e} of the largest nodal force), {} iterations, max |u| {:.6e} {l} (displacements below are from its end)",
            if scene.water.is_some() { "buoyant " } else { "" },
            b.weight,
            b.max_force,
            b.relative,
            i.iterations,
            i.max_displacement,
            f = scene.units.force,
            l = scene.units.length,
        );
        if b.relative > 0.01 {
            crate::say!(
                "  note: the initial stresses are not in balance with the weight and supports (above 1 %); the initial phase moved the model to balance them"
            );
        }
    }
    let Some(record) = &header.record else {
        return print_faces(scene, header, out);
    };
    if let Some(h) = &record.history {
        if let Some(last) = h.last() {
            let states = if scene.joints.is_empty() {
                String::new()
            } else {
                format!(
                    "; open {}, slip {}, stick {} point-sections",
                    last.open, last.slip, last.stick
                )
            };
            crate::say!(
                "  iteration: {} iterations, residual ratio {:.3e} (epsilon {:.1e}){states}",
                h.len(),
                last.ratio,
                scene.solver.epsilon,
            );
        }
    }
    if let Some(path) = &record.load_path {
        let solves: u64 = path.steps.iter().map(|s| u64::from(s.solves)).sum();
        let cutbacks: u64 = path.steps.iter().map(|s| u64::from(s.cutbacks)).sum();
        crate::say!(
            "  load path: {} converged steps to load factor {:.4} ({} solves, {} cut-backs)",
            path.steps.len(),
            record.load_factor.unwrap_or(f64::NAN),
            solves,
            cutbacks
        );
    }
    if let Some(limit) = record.limit() {
        let what = if limit.beyond_capacity {
            "LIMIT LOAD FACTOR"
        } else {
            "STOPPED (not a limit load) at load factor"
        };
        let of = record
            .load_path
            .as_ref()
            .and_then(|p| p.stopped_in.as_ref())
            .map_or(String::new(), |m| format!(" of {}", m.label()));
        crate::say!(
            "  {what} {:.4}{of}: the load factor {:.4} failed ({}); every result below is that of the last converged step",
            limit.factor,
            limit.failed_at,
            limit.reason
        );
    }
    if let Some(Some(c)) = &record.harmonic_check {
        match (c.face_change, c.area_change) {
            (Some(f), Some(a)) => crate::say!(
                "  harmonics: 0..={} against 0..={}: {} changes {f:.2e}{} (relative)",
                c.m,
                c.m_half,
                match (c.note.is_none(), scene.loads.iter().any(|l| matches!(l, Load::Motion(_)))) {
                    (true, false) => "loaded-face displacement",
                    (true, true) => "loaded-face displacement or moved-face reaction",
                    _ => "the displacement field",
                },
                if scene.joints.is_empty() {
                    String::new()
                } else {
                    format!(", joint open/slip area {a:.2e}")
                }
            ),
            _ => crate::say!(
                "  harmonics: no comparison with 0..={}: that run did not converge (reason in solution.json, extra.harmonic_check)",
                c.m_half
            ),
        }
    }
    if let Some(a) = &record.auto_harmonics {
        let steps: Vec<String> = a
            .steps
            .iter()
            .map(|s| match s.change {
                Some(c) => format!("M={} ({:.1e})", s.m, c),
                None => format!("M={}", s.m),
            })
            .collect();
        crate::say!(
            "  harmonics chosen automatically: M = {} (change of the cut profiles, loaded faces and moved-face reactions < {}; steps {})",
            a.chosen,
            a.tolerance,
            steps.join(", ")
        );
    }
    print_faces(scene, header, out);
}

/// The loaded faces' motion, the largest displacement, the applied loads
/// and the reactions.
fn print_faces(scene: &Scene, header: &SolutionHeader, out: &Path) {
    let u = &scene.units;
    for (face, d) in &header.loaded_faces {
        crate::say!(
            "  {face}: mean displacement (ux, uy, uz) = ({:.6e}, {:.6e}, {:.6e}) {}",
            d[0],
            d[1],
            d[2],
            u.length
        );
    }
    crate::say!("  max |u| = {:.6e} {}", header.max_displacement, u.length);
    let a = &header.applied;
    crate::say!(
        "  applied   F = ({:+.6e}, {:+.6e}, {:+.6e})  M = ({:+.6e}, {:+.6e}, {:+.6e})",
        a.force[0],
        a.force[1],
        a.force[2],
        a.moment[0],
        a.moment[1],
        a.moment[2]
    );
    for r in &header.reactions {
        crate::say!(
            "  reaction  F = ({:+.6e}, {:+.6e}, {:+.6e})  M = ({:+.6e}, {:+.6e}, {:+.6e})  on {}",
            r.force[0],
            r.force[1],
            r.force[2],
            r.moment[0],
            r.moment[1],
            r.moment[2],
            r.on
        );
    }
    for m in &header.members {
        print_member(m, &u.force, &u.length);
    }
    crate::say!("  written to {}", out.display());
    for w in header.record.iter().flat_map(|r| &r.warnings) {
        crate::say!("  WARNING: {w}");
    }
}

/// A member's capacity split (axial when it carries an axial load, and
/// lateral along the applied lateral load) and its largest bending moment. A share is what the
/// surroundings carry, with the sign of the load it carries.
fn print_member(m: &axijoint_solver::members::MemberForces, force: &str, length: &str) {
    let s = &m.split;
    let share = |carried: f64, total: f64| {
        if total != 0.0 {
            format!("{carried:.4e} ({:.1} %)", 100.0 * carried / total)
        } else {
            format!("{carried:.4e}")
        }
    };
    let total_z = s.applied[2] + s.weight[2];
    let weight = if s.weight[2] != 0.0 {
        format!(" and weight {:.4e}", s.weight[2])
    } else {
        String::new()
    };
    let open = match m.open_from_top {
        Some(d) if d > 0.0 => format!("; the top {d:.4} {length} of the shaft open all round"),
        _ => String::new(),
    };
    if total_z != 0.0 {
        crate::say!(
            "  member {}: axial load {:.4e}{weight} {force}: shaft {}, base {}{open}",
            m.body,
            s.applied[2],
            share(-s.shaft[2], total_z),
            share(-s.base[2], total_z),
        );
    } else if !open.is_empty() {
        crate::say!("  member {}{open}", m.body);
    }
    let lateral = s.applied[0].hypot(s.applied[1]);
    let key = m.summary();
    // A bending moment above round-off of the load times the length.
    let length_of = m.stations.first().map_or(0.0, |a| a.z) - m.stations.last().map_or(0.0, |b| b.z);
    let scale = [s.applied, s.weight, s.shaft, s.base]
        .iter()
        .flatten()
        .map(|f| f.abs())
        .fold(0.0, f64::max)
        * length_of;
    if lateral == 0.0 && key.max_moment > 1e-9 * scale {
        // Bent by its surroundings alone (a lining, a pile in moving soil):
        // the lateral reactions themselves, there is no load to share.
        crate::say!(
            "  member {}: no lateral load on it; lateral reaction (Fx, Fy) on the shaft ({:+.4e}, {:+.4e}) {force}, on the base ({:+.4e}, {:+.4e}) {force}; largest bending moment {:.4e} {force} {length} at z = {:.4} {length}",
            m.body,
            s.shaft[0] + 0.0,
            s.shaft[1] + 0.0,
            s.base[0] + 0.0,
            s.base[1] + 0.0,
            key.max_moment,
            key.max_moment_z
        );
    } else if lateral > 0.0 {
        let along = |v: [f64; 3]| {
            if lateral > 0.0 {
                (v[0] * s.applied[0] + v[1] * s.applied[1]) / lateral
            } else {
                0.0
            }
        };
        crate::say!(
            "  member {}: lateral load {lateral:.4e} {force}: shaft {}, base {}; largest bending moment {:.4e} {force} {length} at z = {:.4} {length}",
            m.body,
            share(-along(s.shaft), lateral),
            share(-along(s.base), lateral),
            key.max_moment,
            key.max_moment_z
        );
    }
}
