//! Benchmark of the three-term assembly `K_m = c_m (A + m B + m^2 C)`
//! (issue 16, item 1): `Model::factorize_all(0..=M)` as it is (the
//! [`StiffnessTerms`] assembled once, then each harmonic formed from them)
//! against the element-by-element path it replaced (each harmonic
//! assembled by `Model::assemble`, then `Model::factorize_values`), on a
//! fresh model each round (so the terms are assembled inside the timing),
//! the two interleaved round by round. Also, one at a time and sequential:
//! `Model::assemble` of one harmonic, `StiffnessTerms::assemble`, and one
//! harmonic formed from the terms. Prints medians (wall and CPU seconds of
//! the process) and the share of assembly in `factorize_all`:
//!
//! ```text
//! before = (M + 1) assemble / factorize_all(element by element)
//! after  = (terms + (M + 1) form) / factorize_all(three terms)   (CPU)
//! ```
//!
//! ```text
//! cargo run --release -p axijoint-solver --example bench_terms -- \
//!     --size 0.1 --harmonics 8 [--rounds 5] [--scene geo/pile_footing.json]
//! ```

use axijoint_solver::assembly::StiffnessTerms;
use axijoint_solver::linear::Model;
use axijoint_solver::run::{build_model, mesh_scene};
use axijoint_solver::scene::Scene;
use rayon::prelude::*;
use std::path::PathBuf;
use std::time::Instant;

#[path = "../benches/support/cpu.rs"]
mod cpu;
use cpu::cpu_seconds;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Wall and CPU seconds of `f`, and its result.
fn timed<T>(f: impl FnOnce() -> T) -> (f64, f64, T) {
    let (t, c) = (Instant::now(), cpu_seconds());
    let out = f();
    (t.elapsed().as_secs_f64(), cpu_seconds() - c, out)
}

/// The element-by-element path of `factorize_all` before the terms.
fn factorize_all_direct(model: &Model, ms: &[u32]) {
    let factors: Vec<_> = ms
        .par_iter()
        .map(|&m| {
            let (values, pinned) = model.assemble(m);
            model.factorize_values(m, &values, pinned).expect("factor")
        })
        .collect();
    assert_eq!(factors.len(), ms.len());
}

fn main() {
    axijoint_solver::linear::prefer_harmonic_parallelism();
    let mut scene_path = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../geo/pile_footing.json"
    ));
    let (mut size, mut m_max, mut rounds) = (0.1, 8u32, 5usize);
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let v = it.next().unwrap_or_else(|| panic!("{a} needs a value"));
        match a.as_str() {
            "--scene" => scene_path = PathBuf::from(v),
            "--size" => size = v.parse().expect("--size"),
            "--harmonics" => m_max = v.parse().expect("--harmonics"),
            "--rounds" => rounds = v.parse().expect("--rounds"),
            other => panic!("unknown argument {other}"),
        }
    }
    let mut scene = Scene::from_path(&scene_path).expect("scene");
    scene.mesh.parameters.insert("size".into(), size);
    let (mesh, _) = mesh_scene(&scene, None).expect("mesh");
    let ms: Vec<u32> = (0..=m_max).collect();
    let h = ms.len() as f64;

    let (mut before, mut after) = (Vec::new(), Vec::new());
    let (mut asm, mut terms, mut form) = (Vec::new(), Vec::new(), Vec::new());
    let mut dof = 0;
    for round in 0..rounds {
        let model = build_model(&scene, mesh.clone()).expect("model");
        dof = model.n_eq();
        // Alternate which path goes first.
        let run_direct = |v: &mut Vec<(f64, f64)>| {
            let (w, c, ()) = timed(|| factorize_all_direct(&model, &ms));
            v.push((w, c));
        };
        if round % 2 == 0 {
            run_direct(&mut before);
        }
        let (w, c, f) = timed(|| model.factorize_all(&ms).expect("factors"));
        drop(f);
        after.push((w, c));
        if round % 2 == 1 {
            run_direct(&mut before);
        }
        let (w, c, _) = timed(|| model.assemble(2));
        asm.push((w, c));
        let (w, c, t) = timed(|| {
            StiffnessTerms::assemble(
                &model.mesh,
                (&model.materials, &model.mixed()),
                &model.joints,
                &model.dofs,
                model.pattern(),
            )
        });
        drop(t);
        terms.push((w, c));
        let (w, c, _) = timed(|| model.assemble_from_terms(2));
        form.push((w, c));
    }
    let wall = |v: &[(f64, f64)]| median(v.iter().map(|x| x.0).collect());
    let cpu = |v: &[(f64, f64)]| median(v.iter().map(|x| x.1).collect());
    println!(
        "# {} size {size}, M = {m_max}: {dof} DOF per harmonic, {rounds} rounds, {} rayon threads",
        scene_path.display(),
        rayon::current_num_threads()
    );
    println!("one harmonic, sequential (wall / CPU s):");
    println!(
        "  Model::assemble                  {:.4} / {:.4}",
        wall(&asm),
        cpu(&asm)
    );
    println!(
        "  StiffnessTerms::assemble         {:.4} / {:.4}",
        wall(&terms),
        cpu(&terms)
    );
    println!(
        "  K_m formed from the terms        {:.4} / {:.4}",
        wall(&form),
        cpu(&form)
    );
    println!(
        "  terms / assemble {:.2} (CPU {:.2}); form / assemble {:.3} (CPU {:.3})",
        wall(&terms) / wall(&asm),
        cpu(&terms) / cpu(&asm),
        wall(&form) / wall(&asm),
        cpu(&form) / cpu(&asm)
    );
    println!("factorize_all(0..=M), all harmonics in parallel (wall / CPU s):");
    println!(
        "  element by element (before)      {:.4} / {:.4}",
        wall(&before),
        cpu(&before)
    );
    println!(
        "  three terms (after)              {:.4} / {:.4}",
        wall(&after),
        cpu(&after)
    );
    println!(
        "  after / before: wall {:.2}, CPU {:.2}",
        wall(&after) / wall(&before),
        cpu(&after) / cpu(&before)
    );
    println!(
        "share of assembly in factorize_all (CPU): before {:.2}, after {:.2}",
        h * cpu(&asm) / cpu(&before),
        (cpu(&terms) + h * cpu(&form)) / cpu(&after)
    );
}
