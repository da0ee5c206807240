//! Cost of mesh validation on a `.msh` file: reading it, `validate` (the
//! whole-element Jacobian check), the Jacobian pass alone against the old
//! corner-and-Gauss-point one, and the curve-edge check of every physical
//! curve. Best of `REPS` runs (default 5), single-threaded.
//!
//! ```text
//! gmsh geo/pile_footing.geo -2 -setnumber size 0.022 -o /tmp/q9.msh
//! cargo run --release -p axijoint-mesh --example validate_cost -- /tmp/q9.msh [REPS]
//! ```
//!
//! Scene P at about 1e5 nodes (gmsh 4.8.4; `order`, `quads`, `serendipity`
//! and `size` set per family), best of 7, ms:
//!
//! | family (size) | read_msh | validate | Jacobian pass: corners + Gauss | whole element | curve edges (8 curves) |
//! |---|---|---|---|---|---|
//! | T3 (0.011) | 62.2 | 5.8 | 7.5 | 3.0 | 1.6 |
//! | T6 (0.022) | 27.1 | 9.1 | 6.9 | 5.7 | 0.3 |
//! | Q4 (0.011) | 37.7 | 4.8 | 5.8 | 2.2 | 0.8 |
//! | Q8 (0.019) | 24.7 | 8.4 | 4.9 | 4.3 | 0.3 |
//! | Q9 (0.022) | 20.7 | 7.3 | 3.6 | 3.4 | 0.3 |

use axijoint_mesh::geometry::{corner_and_gauss_dets, jacobian_range};
use axijoint_mesh::{check_curve_edges, read_msh, validate};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;

/// Best wall time of `reps` runs of `f`, in seconds.
fn best<T>(reps: usize, mut f: impl FnMut() -> T) -> f64 {
    (0..reps)
        .map(|_| {
            let t = Instant::now();
            black_box(f());
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = PathBuf::from(args.next().ok_or("usage: validate_cost FILE.msh [REPS]")?);
    let reps: usize = args.next().map(|r| r.parse()).transpose()?.unwrap_or(5);
    let mesh = read_msh(&path)?;
    let kinds: std::collections::BTreeSet<&str> = mesh.cells.iter().map(|c| c.kind.name()).collect();
    println!(
        "{}: {} nodes, {} cells ({})",
        path.display(),
        mesh.nodes.len(),
        mesh.cells.len(),
        kinds.into_iter().collect::<Vec<_>>().join(", ")
    );
    let read = best(reps, || read_msh(&path).map(|m| m.nodes.len()));
    let whole = best(reps, || {
        let mut m = mesh.clone();
        let t = Instant::now();
        validate(&mut m, &path).map(|_| ())?;
        Ok::<_, axijoint_mesh::MeshError>(t.elapsed())
    });
    let clone = best(reps, || mesh.clone());
    let validate_s = whole - clone;
    let old = best(reps, || {
        mesh.cells
            .iter()
            .map(|c| corner_and_gauss_dets(c.kind, &mesh.cell_coords(c)).0)
            .fold(f64::INFINITY, f64::min)
    });
    let new = best(reps, || {
        mesh.cells
            .iter()
            .map(|c| jacobian_range(c.kind, &mesh.cell_coords(c)).0)
            .fold(f64::INFINITY, f64::min)
    });
    let names: Vec<&str> = mesh.curves.iter().map(|c| c.name.as_str()).collect();
    let curves = best(reps, || check_curve_edges(&mesh, &names, &path).is_ok());
    let ms = |s: f64| s * 1e3;
    println!("read_msh                          {:8.2} ms", ms(read));
    println!("validate (clone subtracted)       {:8.2} ms", ms(validate_s));
    println!("  Jacobian pass, corners + Gauss  {:8.2} ms", ms(old));
    println!("  Jacobian pass, whole element    {:8.2} ms", ms(new));
    println!(
        "check_curve_edges, {} curves     {:8.2} ms",
        names.len(),
        ms(curves)
    );
    println!("whole-element / corner+Gauss pass {:8.3}", new / old);
    println!(
        "validate (new) / validate with the old pass  {:.3}",
        validate_s / (validate_s - new + old)
    );
    println!(
        "(read + validate + curves) / (read + validate with the old pass)  {:.3}",
        (read + validate_s + curves) / (read + validate_s - new + old)
    );
    Ok(())
}
