//! [`CellValues`] against closed forms (layer 1 of the verification, below
//! the element matrices of `elements.rs`): at every point of every kind,
//! partition of unity (`sum N = 1`, `sum dN = 0`), `r = sum N_i r_i`, the
//! gradient of a linear field exact, and the weights summing to the cell's
//! area (straight-sided cells, off-centre mid-side nodes, one curved edge);
//! the strains at the points equal to [`strain_at`] bit for bit; degenerate
//! and folded cells refused.
//!
//! ```text
//!   z                    distorted quad          distorted triangle
//!   ^   (0.9,1.1) 3 ____ 2 (2.0,1.4)          (1.4,1.3) 2
//!   |            /        \                            /  \
//!   |  (1.0,0.2) 0 ------- 1 (2.3,-0.1)      (1.0,0.2) 0 -- 1 (2.3,-0.1)
//!   +----------------------> r
//! ```

use axijoint_mesh::quadrature::default_rule;
use axijoint_mesh::CellKind;
use axijoint_solver::elements::{point_strain, strain_at, CellError, CellValues};

const CELLS: [CellKind; 5] = [
    CellKind::Tri3,
    CellKind::Tri6,
    CellKind::Quad4,
    CellKind::Quad8,
    CellKind::Quad9,
];
const QUAD: [[f64; 2]; 4] = [[1.0, 0.2], [2.3, -0.1], [2.0, 1.4], [0.9, 1.1]];
const TRI: [[f64; 2]; 3] = [[1.0, 0.2], [2.3, -0.1], [1.4, 1.3]];

/// Shoelace area of a polygon.
fn polygon_area(p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    0.5 * (0..n)
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
}

fn lerp(a: [f64; 2], b: [f64; 2], t: f64) -> [f64; 2] {
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

/// Nodes of a straight-sided cell from its corners, each mid-side node at
/// fraction `t` along its edge (0.5: the midpoint), the Q9 centre at the
/// bilinear centre.
fn straight(kind: CellKind, t: f64) -> Vec<[f64; 2]> {
    let corners: &[[f64; 2]] = if kind.is_triangle() { &TRI } else { &QUAD };
    let c = kind.n_corners();
    let mut x = corners.to_vec();
    if kind.is_quadratic() {
        for e in 0..c {
            x.push(lerp(corners[e], corners[(e + 1) % c], t));
        }
    }
    if kind == CellKind::Quad9 {
        let s = corners.iter().fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]]);
        x.push([0.25 * s[0], 0.25 * s[1]]);
    }
    x
}

fn reinit(kind: CellKind, x: &[[f64; 2]]) -> CellValues {
    let mut v = CellValues::with_default_rule(kind);
    v.reinit(kind, x).unwrap();
    v
}

#[test]
fn partition_of_unity_and_radius_at_every_point() {
    for kind in CELLS {
        let x = straight(kind, 0.5);
        let v = reinit(kind, &x);
        assert_eq!(v.n_points(), default_rule(kind).len());
        for q in 0..v.n_points() {
            let n = v.n(q);
            assert_eq!(n.len(), kind.n_nodes());
            let sum: f64 = n.iter().sum();
            assert!((sum - 1.0).abs() < 1e-14, "{kind:?} q {q}: sum N = {sum}");
            for d in 0..2 {
                let s: f64 = v.dn(q).iter().map(|g| g[d]).sum();
                assert!(s.abs() < 1e-13, "{kind:?} q {q}: sum dN[{d}] = {s}");
            }
            let r: f64 = n.iter().zip(&x).map(|(ni, p)| ni * p[0]).sum();
            let z: f64 = n.iter().zip(&x).map(|(ni, p)| ni * p[1]).sum();
            assert!((v.r(q) - r).abs() < 1e-14, "{kind:?} q {q}");
            assert_eq!(v.position(q)[0], v.r(q));
            assert!((v.position(q)[1] - z).abs() < 1e-14, "{kind:?} q {q}");
        }
    }
}

#[test]
fn gradient_of_a_linear_field_is_exact() {
    let f = |p: [f64; 2]| 0.7 - 1.3 * p[0] + 2.9 * p[1];
    for kind in CELLS {
        for t in [0.5, 0.4] {
            let x = straight(kind, t);
            let v = reinit(kind, &x);
            for q in 0..v.n_points() {
                let mut g = [0.0; 2];
                for (d, p) in v.dn(q).iter().zip(&x) {
                    g[0] += d[0] * f(*p);
                    g[1] += d[1] * f(*p);
                }
                assert!((g[0] + 1.3).abs() < 1e-12, "{kind:?} t {t} q {q}: {g:?}");
                assert!((g[1] - 2.9).abs() < 1e-12, "{kind:?} t {t} q {q}: {g:?}");
                let value: f64 = v.n(q).iter().zip(&x).map(|(ni, p)| ni * f(*p)).sum();
                assert!((value - f(v.position(q))).abs() < 1e-13, "{kind:?} t {t} q {q}");
            }
        }
    }
}

#[test]
fn weights_sum_to_the_area() {
    for kind in CELLS {
        let corners: &[[f64; 2]] = if kind.is_triangle() { &TRI } else { &QUAD };
        let area = polygon_area(corners);
        // Mid-side nodes at the midpoints and off-centre on straight edges
        // (the same cell, another map).
        for t in [0.5, 0.4] {
            let v = reinit(kind, &straight(kind, t));
            let sum: f64 = (0..v.n_points()).map(|q| v.weight(q)).sum();
            assert!(
                (sum - area).abs() < 1e-13 * area,
                "{kind:?} t {t}: {sum} vs {area}"
            );
            for q in 0..v.n_points() {
                assert!(v.det(q) > 0.0);
                assert_eq!(v.weight(q), v.w_gauss(q) * v.det(q).abs());
            }
        }
        // Clockwise: the same weights.
        let x = straight(kind, 0.5);
        let mut cw = x.clone();
        let c = kind.n_corners();
        cw[..c].reverse();
        if kind.is_quadratic() {
            // edge e of the reversed cell runs between old corners c-1-e and c-2-e
            for e in 0..c {
                cw[c + e] = x[c + (2 * c - 2 - e) % c];
            }
        }
        let v = reinit(kind, &cw);
        let sum: f64 = (0..v.n_points()).map(|q| v.weight(q)).sum();
        assert!((sum - area).abs() < 1e-13 * area, "{kind:?} clockwise: {sum}");
        assert!((0..v.n_points()).all(|q| v.det(q) < 0.0));
    }
}

#[test]
fn weights_sum_to_the_area_with_a_curved_edge() {
    // Edge 0 of the quadratic cells bulges outwards (downwards) by d at its
    // middle node: a parabola, adding 2/3 chord d to the polygon.
    let d = 0.15;
    for kind in [CellKind::Tri6, CellKind::Quad8, CellKind::Quad9] {
        let mut x = straight(kind, 0.5);
        let c = kind.n_corners();
        let (a, b) = (x[0], x[1]);
        let chord = (b[0] - a[0]).hypot(b[1] - a[1]);
        let normal = [(b[1] - a[1]) / chord, -(b[0] - a[0]) / chord];
        x[c] = [x[c][0] + d * normal[0], x[c][1] + d * normal[1]];
        if kind == CellKind::Quad9 {
            // keep the centre node where the Q8 map puts the centre
            let m = [x[4], x[5], x[6], x[7]];
            let corner = [x[0], x[1], x[2], x[3]];
            for k in 0..2 {
                x[8][k] = 0.5 * m.iter().map(|p| p[k]).sum::<f64>()
                    - 0.25 * corner.iter().map(|p| p[k]).sum::<f64>();
            }
        }
        let corners: &[[f64; 2]] = if kind.is_triangle() { &TRI } else { &QUAD };
        let area = polygon_area(corners) + 2.0 / 3.0 * chord * d;
        let v = reinit(kind, &x);
        let sum: f64 = (0..v.n_points()).map(|q| v.weight(q)).sum();
        assert!((sum - area).abs() < 1e-13 * area, "{kind:?}: {sum} vs {area}");
    }
}

#[test]
fn strains_at_the_points_are_those_of_strain_at() {
    for kind in CELLS {
        let x = straight(kind, 0.4);
        let v = reinit(kind, &x);
        let u: Vec<f64> = (0..3 * kind.n_nodes())
            .map(|i| (0.37 * i as f64).sin() * 1e-3)
            .collect();
        for m in [0, 1, 3] {
            for (q, xi) in v.rule().points.iter().enumerate() {
                let a = point_strain(&v, q, m, &u);
                let b = strain_at(kind, &x, m, &u, *xi);
                assert_eq!(a, b, "{kind:?} m {m} q {q}");
            }
        }
    }
}

#[test]
fn reinit_switches_kind_and_reuses_the_values() {
    let mut v = CellValues::with_default_rule(CellKind::Quad9);
    for kind in CELLS.into_iter().chain(CELLS.into_iter().rev()) {
        let x = straight(kind, 0.5);
        v.reinit(kind, &x).unwrap();
        assert_eq!(v.kind(), kind);
        let fresh = reinit(kind, &x);
        for q in 0..v.n_points() {
            assert_eq!(v.n(q), fresh.n(q));
            assert_eq!(v.dn(q), fresh.dn(q));
            assert_eq!(v.weight(q), fresh.weight(q));
        }
    }
}

#[test]
fn degenerate_and_folded_cells_are_refused() {
    // All nodes on one line: det J = 0 everywhere.
    let flat = [[1.0, 0.0], [2.0, 0.0], [3.0, 0.0], [1.5, 0.0]];
    let mut v = CellValues::with_default_rule(CellKind::Quad4);
    let e = v.reinit(CellKind::Quad4, &flat).unwrap_err();
    assert!(matches!(e, CellError::Degenerate { point: 0, .. }), "{e:?}");
    assert!(e.to_string().contains("degenerate"), "{e}");
    // A bow tie: det J changes sign between the Gauss points.
    let bow = [[1.0, 0.0], [2.0, 0.0], [1.0, 1.0], [2.0, 1.0]];
    let e = v.reinit(CellKind::Quad4, &bow).unwrap_err();
    match e {
        CellError::Folded { dets: [a, b], .. } => assert!(a * b < 0.0, "{e:?}"),
        _ => panic!("{e:?}"),
    }
    assert!(e.to_string().contains("inverted"), "{e}");
}
