//! Iterations and time of each iteration method on the Scene P variants,
//! relative to the linear solve of the same mesh (issue: beyond the paper).
//!
//! `cargo run --release -p axijoint-solver --example methods -- [size] [eps]`

use axijoint_solver::run::{solve_linear, solve_scene};
use axijoint_solver::scene::{Scene, SolverMethod};
use std::path::Path;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let size: f64 = args.get(1).map_or(Ok(0.25), |s| s.parse())?;
    let eps: f64 = args.get(2).map_or(Ok(1e-6), |s| s.parse())?;
    let geo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../geo");
    println!("variant,method,epsilon,iterations,ratio,solve_s,linear_s,time_ratio");
    for variant in ["pile_footing", "pile_footing_noslip", "pile_footing_frictionless"] {
        let mut scene = Scene::from_path(geo.join(format!("{variant}.json")))?;
        scene.mesh.parameters.insert("size".into(), size);
        scene.solver.epsilon = eps;
        scene.solver.max_iterations = 2000;
        // The linear solve of the same mesh: all harmonics factorized, one solve.
        let t = Instant::now();
        let lin = solve_linear(&scene, None, true)?;
        let linear_s = t.elapsed().as_secs_f64();
        drop(lin);
        for method in [SolverMethod::Paper, SolverMethod::Anderson] {
            scene.solver.method = method;
            let t = Instant::now();
            let run = solve_scene(&scene, None, |_| {})?;
            let solve_s = t.elapsed().as_secs_f64();
            let h = &run.outcome.as_ref().expect("nonlinear").history;
            println!(
                "{variant},{method:?},{eps:e},{},{:.2e},{solve_s:.3},{linear_s:.3},{:.2}",
                h.len(),
                h.last().map_or(f64::NAN, |r| r.ratio),
                solve_s / linear_s
            );
        }
    }
    Ok(())
}
