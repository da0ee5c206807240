mod common;

use axijoint_mesh::CellKind;
use axijoint_solver::material::Elastic;
use common::*;
use std::f64::consts::PI;

#[test]
#[ignore]
fn scratch_torsion() {
    let (a, l, e, nu, t): (f64, f64, f64, f64, f64) = (0.5, 2.0, 2.0e4, 0.17, 5.0);
    let mat = Elastic::new(e, nu).unwrap();
    let (g, j) = (mat.shear_modulus(), PI * a.powi(4) / 2.0);
    for (geo_name, kinds) in [("cylinder.geo", vec![CellKind::Tri3, CellKind::Quad4])] {
        for kind in kinds {
            let (mut hs, mut emax, mut el2) = (vec![], vec![], vec![]);
            for size in [0.25, 0.125, 0.0625, 0.03125, 0.015625] {
                let mesh = mesh(geo_name, kind, &[("a", a), ("L", l), ("size", size), ("hole", 0.0)], &[]);
                let fixed = Supports::new(&mesh).curve("bottom", &[Z, TH]).point("origin", &[R]).done();
                let f = traction(&mesh, "top", 0, &|r, _z| [0.0, 0.0, t * r / j]);
                let (model, u) = solve(mesh, mat, Vec::new(), fixed, 0, &[&f]);
                let exact = |r: f64, z: f64| [0.0, 0.0, t * r * z / (g * j)];
                let (err, scale) = max_nodal_error(&model.mesh, &u[0], &[R, Z, TH], &exact);
                let (l2, x2) = l2_error(&model.mesh, &u[0], &[R, Z, TH], &exact);
                hs.push(size);
                emax.push(err / scale);
                el2.push(l2 / x2);
            }
            println!("{geo_name} {kind:?}: max {} slope {:.3} local {:.3?}; L2 {} slope {:.3} local {:.3?}", fv(&emax), slope(&hs, &emax), local_slopes(&hs, &emax), fv(&el2), slope(&hs, &el2), local_slopes(&hs, &el2));
        }
    }
}

#[test]
#[ignore]
fn scratch_lame() {
    let (ai, b, e, nu, p): (f64, f64, f64, f64, f64) = (0.5, 1.0, 1000.0, 0.3, 1.0);
    let c = (1.0 + nu) * p * ai * ai / (e * (b * b - ai * ai));
    let exact = move |r: f64| (c * ((1.0 - 2.0 * nu) * r + b * b / r), c * ((1.0 - 2.0 * nu) - b * b / (r * r)));
    let mat = Elastic::new(e, nu).unwrap();
    for kind in FAMILIES {
        let (mut hs, mut emax, mut el2, mut een) = (vec![], vec![], vec![], vec![]);
        for n in [2.0, 4.0, 8.0, 16.0, 32.0] {
            let h = (b - ai) / n;
            let mesh = mesh("thick_cylinder.geo", kind, &[("a", b), ("hole", ai), ("L", b - ai), ("size", h), ("transfinite", 1.0)], &[]);
            let fixed = Supports::new(&mesh).curve("bottom", &[Z, TH]).curve("top", &[Z]).done();
            let f = traction(&mesh, "inner", 0, &|_r, _z| [p, 0.0, 0.0]);
            let (model, u) = solve(mesh, mat, Vec::new(), fixed, 0, &[&f]);
            let ex3 = |r: f64, _z: f64| [exact(r).0, 0.0, 0.0];
            let (err, scale) = max_nodal_error(&model.mesh, &u[0], &[R, Z, TH], &ex3);
            let (l2, x2) = l2_error(&model.mesh, &u[0], &[R, Z, TH], &ex3);
            let en = radial_energy_error(&model.mesh, &u[0], &exact);
            hs.push(h);
            emax.push(err / scale);
            el2.push(l2 / x2);
            een.push(en);
        }
        println!("{kind:?}: max {} slope {:.3} local {:.3?}\n   L2 {} slope {:.3} local {:.3?}\n   energy {} slope {:.3} local {:.3?}", fv(&emax), slope(&hs, &emax), local_slopes(&hs, &emax), fv(&el2), slope(&hs, &el2), local_slopes(&hs, &el2), fv(&een), slope(&hs, &een), local_slopes(&hs, &een));
    }
}

fn fv(v: &[f64]) -> String { v.iter().map(|x| format!("{x:.3e}")).collect::<Vec<_>>().join(" ") }
