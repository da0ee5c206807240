//! Shape functions, quadrature and element geometry against closed forms.
//!
//! Layer 1 of the verification: each shape is checked on its own
//! (partition of unity, Kronecker delta, derivatives against central finite
//! differences), each rule against exact monomial integrals, and the
//! geometry helpers against the shoelace area and closed-form lateral
//! integrals.

use axijoint_mesh::geometry::{
    cell_area, corner_and_gauss_dets, derivatives_rz, edge_length_and_lateral, interpolate, jacobian,
    jacobian_range,
};
use axijoint_mesh::quadrature::{default_rule, gauss_legendre, gauss_lobatto, quad_gauss, triangle};
use axijoint_mesh::{CellKind, EdgeKind};

const CELLS: [CellKind; 5] = [
    CellKind::Tri3,
    CellKind::Tri6,
    CellKind::Quad4,
    CellKind::Quad8,
    CellKind::Quad9,
];
const EDGES: [EdgeKind; 2] = [EdgeKind::Lin2, EdgeKind::Lin3];

/// Deterministic xorshift generator: uniform numbers in [0, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A random point inside the reference cell of `kind`.
    fn point(&mut self, kind: CellKind) -> [f64; 2] {
        if kind.is_triangle() {
            let (a, b) = (self.next(), self.next());
            if a + b > 1.0 {
                [1.0 - a, 1.0 - b]
            } else {
                [a, b]
            }
        } else {
            [2.0 * self.next() - 1.0, 2.0 * self.next() - 1.0]
        }
    }
}

fn factorial(n: u32) -> f64 {
    (1..=n).map(f64::from).product()
}

/// Physical nodes of a straight-sided element from its corners: mid-side
/// nodes at the edge midpoints, the Q9 centre at the bilinear centre.
fn straight(kind: CellKind, corners: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut x = Vec::with_capacity(kind.n_nodes());
    let c = kind.n_corners();
    x.extend_from_slice(&corners[..c]);
    if kind.is_quadratic() {
        for e in 0..c {
            let (a, b) = (corners[e], corners[(e + 1) % c]);
            x.push([0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]);
        }
    }
    if kind == CellKind::Quad9 {
        let s = corners.iter().fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]]);
        x.push([0.25 * s[0], 0.25 * s[1]]);
    }
    x
}

fn shoelace(p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    0.5 * (0..n)
        .map(|i| p[i][0] * p[(i + 1) % n][1] - p[(i + 1) % n][0] * p[i][1])
        .sum::<f64>()
}

const DISTORTED_QUAD: [[f64; 2]; 4] = [[1.0, 0.2], [2.3, -0.1], [2.0, 1.4], [0.9, 1.1]];
const DISTORTED_TRI: [[f64; 2]; 3] = [[1.0, 0.2], [2.3, -0.1], [1.4, 1.3]];

fn corners(kind: CellKind) -> &'static [[f64; 2]] {
    if kind.is_triangle() {
        &DISTORTED_TRI
    } else {
        &DISTORTED_QUAD
    }
}

#[test]
fn partition_of_unity_and_zero_derivative_sum_at_random_points() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let (mut n, mut dn) = ([0.0; 9], [[0.0; 2]; 9]);
    for kind in CELLS {
        for _ in 0..200 {
            let xi = rng.point(kind);
            kind.eval_n(xi, &mut n);
            kind.eval_dn(xi, &mut dn);
            let nn = kind.n_nodes();
            let sum: f64 = n[..nn].iter().sum();
            let dsum = dn[..nn]
                .iter()
                .fold([0.0, 0.0], |s, d| [s[0] + d[0], s[1] + d[1]]);
            assert!((sum - 1.0).abs() < 1e-14, "{kind:?} at {xi:?}: sum N = {sum}");
            assert!(
                dsum[0].abs() < 1e-13 && dsum[1].abs() < 1e-13,
                "{kind:?} at {xi:?}: sum dN = {dsum:?}"
            );
        }
    }
    let (mut n, mut dn) = ([0.0; 3], [0.0; 3]);
    for kind in EDGES {
        for _ in 0..200 {
            let s = 2.0 * rng.next() - 1.0;
            kind.eval_n(s, &mut n);
            kind.eval_dn(s, &mut dn);
            let nn = kind.n_nodes();
            assert!(
                (n[..nn].iter().sum::<f64>() - 1.0).abs() < 1e-14,
                "{kind:?} at {s}"
            );
            assert!(dn[..nn].iter().sum::<f64>().abs() < 1e-14, "{kind:?} at {s}");
        }
    }
}

#[test]
fn kronecker_delta_at_the_nodes() {
    let mut n = [0.0; 9];
    for kind in CELLS {
        let nodes = kind.ref_coords();
        assert_eq!(nodes.len(), kind.n_nodes());
        for (j, &xj) in nodes.iter().enumerate() {
            kind.eval_n(xj, &mut n);
            for (i, &ni) in n[..kind.n_nodes()].iter().enumerate() {
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!((ni - expected).abs() < 1e-15, "{kind:?}: N{i} at node {j} = {ni}");
            }
        }
    }
    let mut n = [0.0; 3];
    for kind in EDGES {
        for (j, &sj) in kind.ref_coords().iter().enumerate() {
            kind.eval_n(sj, &mut n);
            for (i, &ni) in n[..kind.n_nodes()].iter().enumerate() {
                assert!(
                    (ni - f64::from(u8::from(i == j))).abs() < 1e-15,
                    "{kind:?}: N{i} at node {j}"
                );
            }
        }
    }
}

#[test]
fn derivatives_match_central_differences() {
    let mut rng = Rng(12345);
    let h = 1e-6;
    let (mut dn, mut np, mut nm) = ([[0.0; 2]; 9], [0.0; 9], [0.0; 9]);
    for kind in CELLS {
        for _ in 0..50 {
            let xi = rng.point(kind);
            kind.eval_dn(xi, &mut dn);
            for dir in 0..2 {
                let (mut xp, mut xm) = (xi, xi);
                xp[dir] += h;
                xm[dir] -= h;
                kind.eval_n(xp, &mut np);
                kind.eval_n(xm, &mut nm);
                for i in 0..kind.n_nodes() {
                    let fd = (np[i] - nm[i]) / (2.0 * h);
                    assert!(
                        (fd - dn[i][dir]).abs() < 1e-8,
                        "{kind:?} node {i} dir {dir}: {fd} vs {}",
                        dn[i][dir]
                    );
                }
            }
        }
    }
    let (mut d, mut np, mut nm) = ([0.0; 3], [0.0; 3], [0.0; 3]);
    for kind in EDGES {
        for _ in 0..50 {
            let s = 2.0 * rng.next() - 1.0;
            kind.eval_dn(s, &mut d);
            kind.eval_n(s + h, &mut np);
            kind.eval_n(s - h, &mut nm);
            for i in 0..kind.n_nodes() {
                let fd = (np[i] - nm[i]) / (2.0 * h);
                assert!((fd - d[i]).abs() < 1e-8, "{kind:?} node {i}: {fd} vs {}", d[i]);
            }
        }
    }
}

/// Exact integral of x^k over [-1, 1].
fn line_monomial(k: u32) -> f64 {
    if k % 2 == 1 {
        0.0
    } else {
        2.0 / f64::from(k + 1)
    }
}

#[test]
fn gauss_legendre_is_exact_to_degree_2n_minus_1_and_not_beyond() {
    for n in 1..=5u32 {
        let rule = gauss_legendre(n as usize).unwrap();
        assert_eq!(rule.len(), n as usize);
        for k in 0..=2 * n - 1 {
            let q: f64 = rule.iter().map(|(x, w)| w * x.powi(k as i32)).sum();
            assert!((q - line_monomial(k)).abs() < 1e-13, "GL{n}, x^{k}: {q}");
        }
        let k = 2 * n;
        let q: f64 = rule.iter().map(|(x, w)| w * x.powi(k as i32)).sum();
        assert!(
            (q - line_monomial(k)).abs() > 1e-3,
            "GL{n} should not integrate x^{k}"
        );
    }
    assert!(gauss_legendre(0).is_none() && gauss_legendre(6).is_none());
}

#[test]
fn gauss_lobatto_is_exact_to_degree_2n_minus_3_with_the_ends() {
    for n in 2..=5u32 {
        let rule = gauss_lobatto(n as usize).unwrap();
        assert_eq!((rule.points[0], rule.points[n as usize - 1]), (-1.0, 1.0));
        for k in 0..=2 * n - 3 {
            let q: f64 = rule.iter().map(|(x, w)| w * x.powi(k as i32)).sum();
            assert!((q - line_monomial(k)).abs() < 1e-13, "GLL{n}, x^{k}: {q}");
        }
        let k = 2 * n - 2;
        let q: f64 = rule.iter().map(|(x, w)| w * x.powi(k as i32)).sum();
        assert!(
            (q - line_monomial(k)).abs() > 1e-3,
            "GLL{n} should not integrate x^{k}"
        );
    }
    assert!(gauss_lobatto(1).is_none() && gauss_lobatto(6).is_none());
}

#[test]
fn tensor_rules_are_exact_to_degree_2n_minus_1_per_direction() {
    for n in 1..=5u32 {
        let rule = quad_gauss(n as usize).unwrap();
        assert_eq!(rule.len(), (n * n) as usize);
        for a in 0..=2 * n - 1 {
            for b in 0..=2 * n - 1 {
                let q: f64 = rule
                    .iter()
                    .map(|([x, y], w)| w * x.powi(a as i32) * y.powi(b as i32))
                    .sum();
                let exact = line_monomial(a) * line_monomial(b);
                assert!((q - exact).abs() < 1e-13, "Q{n}x{n}, x^{a} y^{b}: {q} vs {exact}");
            }
        }
    }
    assert!(quad_gauss(0).is_none() && quad_gauss(6).is_none());
}

#[test]
fn triangle_rules_are_exact_to_their_degree_with_interior_points_and_positive_weights() {
    for p in 1..=6u32 {
        let rule = triangle(p as usize).unwrap();
        for ([x, y], w) in rule.iter() {
            assert!(
                w > 0.0 && x > 0.0 && y > 0.0 && x + y < 1.0,
                "degree {p}: point ({x}, {y}) w {w}"
            );
        }
        for a in 0..=p {
            for b in 0..=p - a {
                let q: f64 = rule
                    .iter()
                    .map(|([x, y], w)| w * x.powi(a as i32) * y.powi(b as i32))
                    .sum();
                // Integral of x^a y^b over (0,0), (1,0), (0,1) = a! b! / (a + b + 2)!
                let exact = factorial(a) * factorial(b) / factorial(a + b + 2);
                assert!(
                    (q - exact).abs() < 1e-13,
                    "degree {p}, x^{a} y^{b}: {q} vs {exact}"
                );
            }
        }
    }
    assert_eq!(
        [1, 2, 3, 4, 5, 6].map(|p| triangle(p).unwrap().len()),
        [1, 3, 6, 6, 7, 12]
    );
    assert!(triangle(0).is_none() && triangle(7).is_none());
}

#[test]
fn default_rules_have_interior_points() {
    for kind in CELLS {
        let rule = default_rule(kind);
        let total: f64 = rule.weights.iter().sum();
        let reference = if kind.is_triangle() { 0.5 } else { 4.0 };
        assert!((total - reference).abs() < 1e-14, "{kind:?}: weights sum {total}");
        for [x, y] in rule.points.iter().copied() {
            let inside = if kind.is_triangle() {
                x > 0.0 && y > 0.0 && x + y < 1.0
            } else {
                x.abs() < 1.0 && y.abs() < 1.0
            };
            assert!(inside, "{kind:?}: point ({x}, {y})");
        }
    }
}

#[test]
fn area_of_distorted_straight_sided_elements_equals_the_shoelace_area() {
    for kind in CELLS {
        let c = corners(kind);
        let exact = shoelace(c);
        let x = straight(kind, c);
        let area = cell_area(kind, &x);
        assert!(
            (area - exact).abs() < 1e-13 * exact,
            "{kind:?}: {area} vs {exact}"
        );
        // Clockwise numbering: same area.
        let cw: Vec<[f64; 2]> = c.iter().rev().copied().collect();
        let area_cw = cell_area(kind, &straight(kind, &cw));
        assert!(
            (area_cw - exact).abs() < 1e-13 * exact,
            "{kind:?} clockwise: {area_cw}"
        );
    }
}

#[test]
fn area_of_a_curved_quadratic_edge_adds_the_parabolic_segment() {
    // Edge 0-1 of a right triangle / square bulged outwards by delta at its
    // middle node: the parabola adds 2/3 * chord * delta.
    let delta = 0.1;
    for kind in [CellKind::Tri6, CellKind::Quad8, CellKind::Quad9] {
        let c: &[[f64; 2]] = if kind.is_triangle() {
            &[[1.0, 0.0], [2.0, 0.0], [1.0, 1.0]]
        } else {
            &[[1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0]]
        };
        let mut x = straight(kind, c);
        x[c.len()][1] -= delta; // middle node of edge 0-1
        let exact = shoelace(c) + 2.0 / 3.0 * 1.0 * delta;
        let area = cell_area(kind, &x);
        assert!((area - exact).abs() < 1e-13, "{kind:?}: {area} vs {exact}");
    }
}

#[test]
fn lateral_integral_of_a_slanted_edge_matches_the_closed_form() {
    let (a, b): ([f64; 2], [f64; 2]) = ([0.5, -0.3], [2.0, 1.7]);
    let length = (b[0] - a[0]).hypot(b[1] - a[1]);
    // Integral(r ds) over a straight segment = L (r_a + r_b) / 2
    let lateral = length * 0.5 * (a[0] + b[0]);
    let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
    let off = [a[0] + 0.3 * (b[0] - a[0]), a[1] + 0.3 * (b[1] - a[1])];
    for (kind, x) in [
        (EdgeKind::Lin2, vec![a, b]),
        (EdgeKind::Lin3, vec![a, b, mid]),
        (EdgeKind::Lin3, vec![a, b, off]),
    ] {
        let (l, lat) = edge_length_and_lateral(kind, &x);
        assert!(
            (l - length).abs() < 1e-13 * length,
            "{kind:?}: length {l} vs {length}"
        );
        assert!(
            (lat - lateral).abs() < 1e-13 * lateral,
            "{kind:?}: lateral {lat} vs {lateral}"
        );
    }
}

#[test]
fn physical_derivatives_reproduce_linear_fields() {
    // For any isoparametric element, sum_i x_i dN_i/dx = identity.
    let mut rng = Rng(777);
    let (mut n, mut dn, mut drz) = ([0.0; 9], [[0.0; 2]; 9], [[0.0; 2]; 9]);
    for kind in CELLS {
        let mut x = straight(kind, corners(kind));
        if kind.is_quadratic() {
            x[kind.n_corners()][1] -= 0.05; // a curved edge
        }
        for _ in 0..20 {
            let xi = rng.point(kind);
            kind.eval_n(xi, &mut n);
            kind.eval_dn(xi, &mut dn);
            let (jac, det) = jacobian(kind, &x, &dn);
            assert!(det > 0.0);
            derivatives_rz(&jac, det, &dn[..kind.n_nodes()], &mut drz);
            let p = interpolate(&x, &n[..kind.n_nodes()]);
            let f = |q: [f64; 2]| 3.0 * q[0] - 2.0 * q[1] + 0.5;
            let (mut fr, mut fz, mut fv) = (0.0, 0.0, 0.0);
            for i in 0..kind.n_nodes() {
                fv += n[i] * f(x[i]);
                fr += drz[i][0] * f(x[i]);
                fz += drz[i][1] * f(x[i]);
            }
            assert!((fv - f(p)).abs() < 1e-13, "{kind:?}: value");
            assert!(
                (fr - 3.0).abs() < 1e-12 && (fz + 2.0).abs() < 1e-12,
                "{kind:?}: gradient ({fr}, {fz})"
            );
        }
    }
}

#[test]
fn corner_and_gauss_dets_flag_orientation_and_inversion() {
    for kind in CELLS {
        let c = corners(kind);
        let (min, max) = corner_and_gauss_dets(kind, &straight(kind, c));
        assert!(min > 0.0 && max >= min, "{kind:?} ccw: ({min}, {max})");
        let cw: Vec<[f64; 2]> = c.iter().rev().copied().collect();
        let (min, max) = corner_and_gauss_dets(kind, &straight(kind, &cw));
        assert!(max < 0.0, "{kind:?} cw: ({min}, {max})");
    }
    // Q8 unit square with the middle node of edge 0-1 moved along the edge
    // closer to node 0 than the quarter point: det J < 0 at corner 0.
    let mut x = straight(CellKind::Quad8, &[[1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0]]);
    x[4] = [1.1, 0.0];
    let (min, max) = corner_and_gauss_dets(CellKind::Quad8, &x);
    assert!(min < 0.0 && max > 0.0, "folded Q8: ({min}, {max})");
    // Affine T3: det J = 2 * area everywhere.
    let (min, max) = corner_and_gauss_dets(CellKind::Tri3, &DISTORTED_TRI);
    let two_a = 2.0 * shoelace(&DISTORTED_TRI);
    assert!((min - two_a).abs() < 1e-14 && (max - two_a).abs() < 1e-14);
}

/// `det J` on a dense lattice of the reference cell (65 points a side):
/// `(min, max, min |det J|)`.
fn sampled_dets(kind: CellKind, x: &[[f64; 2]]) -> (f64, f64, f64) {
    const N: usize = 64;
    let mut dn = [[0.0; 2]; 9];
    let (mut lo, mut hi, mut small) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY);
    for i in 0..=N {
        for j in 0..=N {
            let (u, v) = (i as f64 / N as f64, j as f64 / N as f64);
            let xi = if kind.is_triangle() {
                if i + j > N {
                    continue;
                }
                [u, v]
            } else {
                [2.0 * u - 1.0, 2.0 * v - 1.0]
            };
            kind.eval_dn(xi, &mut dn);
            let d = jacobian(kind, x, &dn).1;
            lo = lo.min(d);
            hi = hi.max(d);
            small = small.min(d.abs());
        }
    }
    (lo, hi, small)
}

/// `jacobian_range` against a dense lattice on randomly distorted elements
/// of every family: a proven sign is the sign of every sample and bounds
/// them (T3, Q4, T6: the exact extremes, within the lattice's resolution);
/// a sign change is seen by the lattice too (or a sample near zero). The
/// quadratic families include elements whose corners and Gauss points all
/// have one sign but whose `det J` changes sign elsewhere: the old check
/// passed them, `jacobian_range` does not.
#[test]
fn jacobian_range_covers_the_whole_element() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for kind in CELLS {
        let base = straight(kind, corners(kind));
        let (mut proven, mut changes, mut hidden) = (0, 0, 0);
        for trial in 0..3000 {
            // Corners moved by up to 0.05 .. 0.5, mid-side and centre nodes
            // by up to 0.08 .. 0.8 (the element is about 1.3 wide).
            let t = (trial % 10 + 1) as f64 / 10.0;
            let x: Vec<[f64; 2]> = base
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let a = if i < kind.n_corners() { 0.5 * t } else { 0.8 * t };
                    [
                        p[0] + a * (2.0 * rng.next() - 1.0),
                        p[1] + a * (2.0 * rng.next() - 1.0),
                    ]
                })
                .collect();
            let (lo, hi) = jacobian_range(kind, &x);
            let (smin, smax, small) = sampled_dets(kind, &x);
            let scale = smin.abs().max(smax.abs());
            let what = format!("{kind:?} trial {trial} {x:?}: range ({lo}, {hi}), samples ({smin}, {smax})");
            if lo * hi > 0.0 {
                proven += 1;
                assert!(smin * smax > 0.0 && smin * lo > 0.0, "{what}");
                assert!(lo <= smin + 1e-12 * scale && hi >= smax - 1e-12 * scale, "{what}");
                if !matches!(kind, CellKind::Quad8 | CellKind::Quad9) {
                    // Exact extremes: the lattice comes within its resolution.
                    assert!(smin - lo <= 1e-2 * scale && hi - smax <= 1e-2 * scale, "{what}");
                }
            } else {
                changes += 1;
                assert!(smin * smax <= 0.0 || small <= 1e-3 * scale, "{what}");
                assert!(
                    lo >= smin - 1e-2 * scale && hi <= smax + 1e-2 * scale,
                    "{what}: witnesses"
                );
                let (cmin, cmax) = corner_and_gauss_dets(kind, &x);
                if cmin * cmax > 0.0 {
                    hidden += 1;
                }
            }
        }
        println!("{kind:?}: {proven} proven, {changes} sign changes ({hidden} hidden from corners and Gauss points)");
        assert!(proven > 100, "{kind:?}: {proven} proven");
        if kind.is_quadratic() {
            assert!(changes > 100, "{kind:?}: {changes} sign changes");
            assert!(
                hidden > 10,
                "{kind:?}: only {hidden} sign changes hidden from corners and Gauss points"
            );
        } else {
            assert_eq!(hidden, 0, "{kind:?}: det J is affine, its corners decide");
        }
    }
}

/// The T6: mid-side nodes on the wrong edges (each one the middle
/// of another edge of the triangle). `det J` is 5 at the corners and
/// positive at the 6 Gauss points but -1/3 at the centroid.
#[test]
fn t6_with_mid_side_nodes_on_the_wrong_edges() {
    let (a, b, c) = ([1.0, 0.0], [1.0, 1.0], [2.0, 1.0]);
    let mid = |p: [f64; 2], q: [f64; 2]| [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
    // Edges 0-1, 1-2, 2-0 get the middles of 1-2, 2-0, 0-1.
    let x = [a, b, c, mid(b, c), mid(c, a), mid(a, b)];
    let (cmin, cmax) = corner_and_gauss_dets(CellKind::Tri6, &x);
    assert!(cmin > 0.0 && (cmax - 5.0).abs() < 1e-12, "({cmin}, {cmax})");
    let mut dn = [[0.0; 2]; 6];
    CellKind::Tri6.eval_dn([1.0 / 3.0, 1.0 / 3.0], &mut dn);
    assert!((jacobian(CellKind::Tri6, &x, &dn).1 + 1.0 / 3.0).abs() < 1e-12);
    let (lo, hi) = jacobian_range(CellKind::Tri6, &x);
    assert!(lo < 0.0 && (hi - 5.0).abs() < 1e-12, "({lo}, {hi})");
}
