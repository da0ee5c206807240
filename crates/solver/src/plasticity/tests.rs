//! Tests of the return mapping: admissibility, the closest point, the flow
//! directions, isotropy, and the consistent tangent against finite
//! differences in every region.

use super::*;
use nalgebra::Rotation3;

/// Deterministic splitmix64 generator.
struct Rng(u64);

impl Rng {
    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        let u = ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * u
    }

    /// A random rotation of the (r, z, theta) frame.
    fn rotation(&mut self) -> Matrix3<f64> {
        let axis = Vector3::new(
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
        );
        Rotation3::from_scaled_axis(axis * 2.0).into_inner()
    }

    /// A random stress: mean in [-3 s, s], components of the deviator up to s.
    fn stress(&mut self, s: f64) -> [f64; 6] {
        let p = self.range(-3.0 * s, s);
        let mut v: [f64; 6] = std::array::from_fn(|_| self.range(-s, s));
        for x in &mut v[..3] {
            *x += p;
        }
        v
    }
}

const CLAY: Elastic = Elastic { e: 1.0e4, nu: 0.3 };

fn mc(c: f64, phi: f64, psi: f64, t: f64) -> YieldCriterion {
    YieldCriterion::MohrCoulomb {
        cohesion: c,
        friction_deg: phi,
        dilation_deg: psi,
        tension_cutoff: t,
    }
}

/// Criteria covering every region, with the plastic regions each must reach.
fn criteria() -> Vec<(YieldCriterion, Vec<Region>)> {
    use Region::*;
    let cut = vec![Face, Edge, Cutoff, CutoffEdge, CutoffApex, FaceCutoff, Corner];
    vec![
        (YieldCriterion::Tresca { c_u: 50.0 }, vec![Face, Edge]),
        (YieldCriterion::VonMises { c_u: 50.0 }, vec![Face]),
        (mc(10.0, 30.0, 30.0, f64::INFINITY), vec![Face, Edge, Apex]),
        (mc(10.0, 30.0, 10.0, f64::INFINITY), vec![Face, Edge, Apex]),
        (mc(10.0, 30.0, 30.0, 5.0), cut.clone()),
        (mc(10.0, 30.0, 10.0, 5.0), cut.clone()),
        (mc(0.0, 35.0, 5.0, f64::INFINITY), vec![Face, Edge, Apex]),
        (mc(20.0, 0.0, 0.0, 10.0), cut.clone()),
        (mc(5.0, 50.0, 0.0, 2.0), cut),
    ]
}

fn rotate(r: &Matrix3<f64>, v: &[f64; 6]) -> [f64; 6] {
    vector(&(r * tensor(v) * r.transpose()))
}

/// A strain 6-vector (engineering shears) rotated as a tensor.
fn rotate_strain(r: &Matrix3<f64>, e: &[f64; 6]) -> [f64; 6] {
    let half = [e[0], e[1], e[2], 0.5 * e[3], 0.5 * e[4], 0.5 * e[5]];
    let t = rotate(r, &half);
    [t[0], t[1], t[2], 2.0 * t[3], 2.0 * t[4], 2.0 * t[5]]
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}

fn d_of(v: &[f64; 6]) -> [f64; 6] {
    let d = CLAY.d_matrix();
    std::array::from_fn(|i| (0..6).map(|j| d[(i, j)] * v[j]).sum())
}

fn dot(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Stress scale of a trial for tolerances.
fn scale(trial: &[f64; 6]) -> f64 {
    max_abs(trial).max(50.0)
}

#[test]
fn elastic_trial_is_unchanged() {
    let trial = [-20.0, -25.0, -22.0, 1.0, 0.5, -0.3];
    let d = to_array(&CLAY.d_matrix());
    for (crit, _) in criteria() {
        assert!(yield_value(&crit, trial) < 0.0, "{crit:?}");
        let r = return_map(&CLAY, &crit, trial);
        assert_eq!(r.region, Region::Elastic, "{crit:?}");
        assert_eq!(r.stress, trial);
        assert_eq!(r.plastic_strain, [0.0; 6]);
        assert_eq!(r.tangent, d);
    }
}

#[test]
fn returned_stress_is_admissible() {
    let mut rng = Rng(7);
    for (crit, regions) in criteria() {
        let mut seen = Vec::new();
        for _ in 0..20_000 {
            let trial = rng.stress(80.0);
            let r = return_map(&CLAY, &crit, trial);
            let s = scale(&trial);
            // Admissible within 1e-10 of the stress scale.
            assert!(
                yield_value(&crit, r.stress) <= 1e-10 * s,
                "{crit:?} {trial:?} {r:?}"
            );
            if r.region == Region::Elastic {
                assert!(yield_value(&crit, trial) <= 1e-10 * s);
            } else {
                assert!(yield_value(&crit, trial) > 0.0);
            }
            // The plastic strain is D^-1 (trial - stress), to 1e-12.
            let back = d_of(&r.plastic_strain);
            let released: [f64; 6] = std::array::from_fn(|k| trial[k] - r.stress[k]);
            assert!(max_diff(&back, &released) <= 1e-12 * s);
            if !seen.contains(&r.region) {
                seen.push(r.region);
            }
        }
        for region in regions {
            assert!(
                seen.contains(&region),
                "{crit:?}: {region:?} never reached ({seen:?})"
            );
        }
    }
}

/// A random admissible stress on or inside the surface: a random stress
/// pulled towards `inner` (admissible) to the surface if it is outside.
fn admissible_stress(rng: &mut Rng, crit: &YieldCriterion, inner: f64) -> [f64; 6] {
    let outer = rng.stress(80.0);
    if yield_value(crit, outer) <= 0.0 {
        return outer;
    }
    let at = |l: f64| -> [f64; 6] {
        std::array::from_fn(|k| l * outer[k] + (1.0 - l) * if k < 3 { inner } else { 0.0 })
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if yield_value(crit, at(mid)) <= 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    at(lo)
}

#[test]
fn associated_return_is_closest_point() {
    // Associated criteria and an admissible hydrostatic stress of each.
    let cases = [
        (YieldCriterion::Tresca { c_u: 50.0 }, -10.0),
        (YieldCriterion::VonMises { c_u: 50.0 }, -10.0),
        (mc(10.0, 30.0, 30.0, 5.0), 0.0),
        (mc(10.0, 30.0, 30.0, f64::INFINITY), 0.0),
        (mc(20.0, 0.0, 0.0, 10.0), 0.0),
    ];
    let mut rng = Rng(11);
    for (crit, inner) in cases {
        let others: Vec<[f64; 6]> = (0..2000)
            .map(|_| admissible_stress(&mut rng, &crit, inner))
            .collect();
        let mut checked = 0;
        while checked < 100 {
            let trial = rng.stress(80.0);
            let r = return_map(&CLAY, &crit, trial);
            if r.region == Region::Elastic {
                continue;
            }
            checked += 1;
            let ep = r.plastic_strain;
            // Energy distance^2 = (trial - s) . D^-1 (trial - s).
            let dist = |s: &[f64; 6]| -> f64 {
                let ds: [f64; 6] = std::array::from_fn(|k| trial[k] - s[k]);
                dot(&ds, &compliance(&CLAY, &ds))
            };
            let own = dist(&r.stress);
            for tau in &others {
                // (trial - s) : D^-1 : (tau - s) <= 0 for every admissible tau ...
                let dt: [f64; 6] = std::array::from_fn(|k| tau[k] - r.stress[k]);
                let norm = dot(&ep, &ep).sqrt() * dot(&dt, &dt).sqrt();
                assert!(dot(&ep, &dt) <= 1e-9 * norm, "{crit:?} {trial:?} {tau:?}");
                // ... so none is closer in the energy norm.
                assert!(dist(tau) >= own * (1.0 - 1e-12), "{crit:?} {trial:?} {tau:?}");
            }
        }
    }
}

/// The plastic strain in the trial's principal axes (engineering shears
/// halved to tensor components), sorted like the trial.
fn principal_plastic_strain(trial: &[f64; 6], ep: &[f64; 6]) -> Matrix3<f64> {
    let (_, q) = principal(trial);
    let half = [ep[0], ep[1], ep[2], 0.5 * ep[3], 0.5 * ep[4], 0.5 * ep[5]];
    q.transpose() * tensor(&half) * q
}

/// Checks that the principal plastic strains of the face returns of `crit`
/// are proportional to `(1 + sin a) : 0 : -(1 - sin a)`.
fn face_flow_follows(crit: YieldCriterion, angle_deg: f64) {
    let sin_a = angle_deg.to_radians().sin();
    let mut rng = Rng(13);
    let mut checked = 0;
    while checked < 500 {
        let trial = rng.stress(80.0);
        let r = return_map(&CLAY, &crit, trial);
        if r.region != Region::Face {
            continue;
        }
        checked += 1;
        let e = principal_plastic_strain(&trial, &r.plastic_strain);
        let size = e.abs().max();
        assert!(size > 0.0);
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            assert!(e[(i, j)].abs() <= 1e-10 * size, "not coaxial: {e}");
        }
        let g = e[(0, 0)] / (1.0 + sin_a);
        assert!((e[(2, 2)] + g * (1.0 - sin_a)).abs() <= 1e-10 * size, "{e}");
        assert!(e[(1, 1)].abs() <= 1e-10 * size, "{e}");
    }
}

#[test]
fn associated_plastic_strain_is_normal() {
    face_flow_follows(mc(10.0, 30.0, 30.0, 5.0), 30.0);
    face_flow_follows(YieldCriterion::Tresca { c_u: 50.0 }, 0.0);
}

#[test]
fn non_associated_flow_follows_potential() {
    face_flow_follows(mc(10.0, 30.0, 10.0, 5.0), 10.0);
    face_flow_follows(mc(5.0, 40.0, 0.0, f64::INFINITY), 0.0);
}

#[test]
fn cutoff_flow_is_the_first_principal_direction() {
    let mut rng = Rng(17);
    let mut checked = 0;
    while checked < 200 {
        let trial = rng.stress(80.0);
        let r = return_map(&CLAY, &mc(10.0, 30.0, 10.0, 5.0), trial);
        if r.region != Region::Cutoff {
            continue;
        }
        checked += 1;
        let e = principal_plastic_strain(&trial, &r.plastic_strain);
        let size = e.abs().max();
        assert!(e[(0, 0)] > 0.0);
        assert!(
            (e - Matrix3::from_diagonal(&Vector3::new(e[(0, 0)], 0.0, 0.0)))
                .abs()
                .max()
                <= 1e-10 * size
        );
        let (s, _) = principal(&r.stress);
        assert!((s[0] - 5.0).abs() <= 1e-12 * scale(&trial));
    }
}

#[test]
fn tresca_is_mohr_coulomb_without_friction() {
    let tresca = YieldCriterion::Tresca { c_u: 50.0 };
    let mohr = mc(50.0, 0.0, 0.0, f64::INFINITY);
    let mut rng = Rng(19);
    for _ in 0..5000 {
        let trial = rng.stress(100.0);
        let (a, b) = (return_map(&CLAY, &tresca, trial), return_map(&CLAY, &mohr, trial));
        assert_eq!(a.region, b.region);
        assert!(max_diff(&a.stress, &b.stress) <= 1e-12 * scale(&trial));
        let (ta, tb) = (a.tangent.concat(), b.tangent.concat());
        assert!(max_diff(&ta, &tb) <= 1e-12 * CLAY.e);
        assert!((yield_value(&tresca, trial) - yield_value(&mohr, trial)).abs() <= 1e-12 * scale(&trial));
    }
    // Closed form: s1 - s3 = 200 -> 100, the mean and s2 kept.
    let r = return_map(&CLAY, &tresca, [0.0, -200.0, -60.0, 0.0, 0.0, 0.0]);
    assert_eq!(r.region, Region::Face);
    assert!(max_diff(&r.stress, &[-50.0, -150.0, -60.0, 0.0, 0.0, 0.0]) < 1e-11);
    // Pure shear 80 -> 50.
    let r = return_map(&CLAY, &tresca, [0.0, 0.0, 0.0, 0.0, 80.0, 0.0]);
    assert!(max_diff(&r.stress, &[0.0, 0.0, 0.0, 0.0, 50.0, 0.0]) < 1e-11);
}

#[test]
fn von_mises_radial_return() {
    let vm = YieldCriterion::VonMises { c_u: 50.0 };
    let r = return_map(&CLAY, &vm, [0.0, 0.0, 0.0, 80.0, 0.0, 0.0]);
    assert_eq!(r.region, Region::Face);
    assert!(max_diff(&r.stress, &[0.0, 0.0, 0.0, 50.0, 0.0, 0.0]) < 1e-12);
    let mut rng = Rng(23);
    for _ in 0..1000 {
        let trial = rng.stress(100.0);
        let r = return_map(&CLAY, &vm, trial);
        let q = sqrt_j2(&trial);
        if q <= 50.0 {
            assert_eq!(r.region, Region::Elastic);
            continue;
        }
        let p = (trial[0] + trial[1] + trial[2]) / 3.0;
        let expect: [f64; 6] = std::array::from_fn(|k| {
            if k < 3 {
                p + (trial[k] - p) * 50.0 / q
            } else {
                trial[k] * 50.0 / q
            }
        });
        assert!(max_diff(&r.stress, &expect) <= 1e-12 * scale(&trial));
        assert!((sqrt_j2(&r.stress) - 50.0).abs() <= 1e-12 * scale(&trial));
    }
}

#[test]
fn return_is_isotropic() {
    let mut rng = Rng(29);
    for (crit, _) in criteria() {
        for _ in 0..2000 {
            let trial = rng.stress(80.0);
            let rot = rng.rotation();
            let (a, b) = (
                return_map(&CLAY, &crit, trial),
                return_map(&CLAY, &crit, rotate(&rot, &trial)),
            );
            let s = scale(&trial);
            assert_eq!(a.region, b.region, "{crit:?} {trial:?}");
            assert!(
                max_diff(&rotate(&rot, &a.stress), &b.stress) <= 1e-10 * s,
                "{crit:?} {trial:?}"
            );
            let ep = rotate_strain(&rot, &a.plastic_strain);
            assert!(max_diff(&ep, &b.plastic_strain) <= 1e-10 * s / CLAY.e);
        }
    }
}

/// A region, a stress on its planes, the planes and their multipliers.
type Case = (Region, [f64; 3], &'static [usize], &'static [f64]);

/// Trials built backwards: a stress `target` on the planes `set` plus
/// `D n dgamma`, in a random frame; with the region they must return to.
fn constructed(crit: &YieldCriterion, rng: &mut Rng) -> Vec<(Region, [f64; 6], [f64; 6])> {
    let planes = Planes::new(crit).unwrap();
    let dp = CLAY.d_matrix().fixed_view::<3, 3>(0, 0).into_owned();
    let YieldCriterion::MohrCoulomb {
        cohesion: c,
        friction_deg,
        dilation_deg,
        ..
    } = *crit
    else {
        unreachable!()
    };
    let (sin_phi, cos_phi) = friction_deg.to_radians().sin_cos();
    // s1 on the main plane for s3, and s3 for s1.
    let s1_of = |s3: f64| (2.0 * c * cos_phi + (1.0 - sin_phi) * s3) / (1.0 + sin_phi);
    let s3_of = |s1: f64| ((1.0 + sin_phi) * s1 - 2.0 * c * cos_phi) / (1.0 - sin_phi);
    let t = planes.b[CUTOFF];
    let (f, s3c) = (s1_of(-40.0), s3_of(t));
    use Region::*;
    let mut cases: Vec<Case> = vec![
        (Face, [f, -20.0, -40.0], &[0], &[4e-3]),
        (Edge, [f, -40.0, -40.0], &[0, 1], &[6e-3, 2e-3]),
        (Edge, [f, f, -40.0], &[0, 2], &[6e-3, 2e-3]),
    ];
    if planes.cutoff_at_apex {
        // With psi = 0 the Mohr-Coulomb flows at the apex span only
        // the deviatoric plane there (a region boundary).
        if dilation_deg > 0.0 {
            cases.push((Apex, [t; 3], &[0, 1, 2], &[6e-3, 4e-3, 2e-3]));
        }
        cases.push((Apex, [t; 3], &[3, 4, 5], &[6e-3, 4e-3, 2e-3]));
    } else {
        cases.extend_from_slice(&[
            (Cutoff, [t, -2.0, -10.0], &[3][..], &[3e-3][..]),
            (CutoffEdge, [t, t, -10.0], &[3, 4], &[4e-3, 2e-3]),
            (CutoffApex, [t; 3], &[3, 4, 5], &[6e-3, 4e-3, 2e-3]),
            (FaceCutoff, [t, 0.5 * (t + s3c), s3c], &[0, 3], &[4e-3, 3e-3]),
            (Corner, [t, s3c, s3c], &[0, 1, 3], &[6e-3, 2e-3, 3e-3]),
            (Corner, [t, t, s3c], &[0, 3, 4], &[5e-3, 6e-3, 1.5e-3]),
        ]);
    }
    cases
        .into_iter()
        .map(|(region, target, set, gamma)| {
            let mut x = Vector3::from(target);
            for (&k, &g) in set.iter().zip(gamma) {
                x += dp * Vector3::from(planes.n[k]) * g;
            }
            let rot = rng.rotation();
            let diag = |v: [f64; 3]| [v[0], v[1], v[2], 0.0, 0.0, 0.0];
            (
                region,
                rotate(&rot, &diag([x[0], x[1], x[2]])),
                rotate(&rot, &diag(target)),
            )
        })
        .collect()
}

fn constructed_criteria() -> [YieldCriterion; 5] {
    [
        mc(10.0, 30.0, 10.0, 5.0),
        mc(10.0, 30.0, 30.0, 5.0),
        mc(10.0, 30.0, 10.0, f64::INFINITY),
        mc(10.0, 30.0, 0.0, f64::INFINITY),
        mc(20.0, 0.0, 0.0, 10.0),
    ]
}

#[test]
fn constructed_trials_return_to_their_region() {
    let mut rng = Rng(31);
    for crit in constructed_criteria() {
        for (region, trial, target) in constructed(&crit, &mut rng) {
            let r = return_map(&CLAY, &crit, trial);
            assert_eq!(r.region, region, "{crit:?} {target:?}");
            assert!(
                max_diff(&r.stress, &target) <= 1e-11 * scale(&trial),
                "{crit:?} {r:?} {target:?}"
            );
        }
    }
}

/// max |tangent - central differences| / E over the columns, or None
/// when a perturbed trial changes region.
fn tangent_error(crit: &YieldCriterion, trial: &[f64; 6]) -> Option<f64> {
    let r = return_map(&CLAY, crit, *trial);
    let strain = compliance(&CLAY, trial);
    let h = 1e-6 * max_abs(&strain);
    let mut err: f64 = 0.0;
    for j in 0..6 {
        let at = |sign: f64| {
            let mut e = strain;
            e[j] += sign * h;
            return_map(&CLAY, crit, d_of(&e))
        };
        let (plus, minus) = (at(1.0), at(-1.0));
        if plus.region != r.region || minus.region != r.region {
            return None;
        }
        for i in 0..6 {
            let fd = (plus.stress[i] - minus.stress[i]) / (2.0 * h);
            err = err.max((r.tangent[i][j] - fd).abs() / CLAY.e);
        }
    }
    Some(err)
}

/// Eigenvalues of the trial at least 1 apart (no coincident ones).
fn distinct(trial: &[f64; 6]) -> bool {
    let (x, _) = principal(trial);
    x[0] - x[1] > 1.0 && x[1] - x[2] > 1.0
}

#[test]
fn tangent_matches_finite_differences() {
    let mut rng = Rng(37);
    let mut seen = Vec::new();
    for crit in constructed_criteria() {
        for (region, trial, _) in constructed(&crit, &mut rng) {
            assert!(distinct(&trial), "{crit:?} {region:?} {trial:?}");
            let err = tangent_error(&crit, &trial).expect("inside its region");
            assert!(err <= 1e-6, "{crit:?} {region:?}: {err:e}");
            seen.push(region);
        }
    }
    // Random trials of every criterion, away from region boundaries.
    for (crit, _) in criteria() {
        let mut checked = 0;
        while checked < 300 {
            let trial = rng.stress(80.0);
            if !distinct(&trial) {
                continue;
            }
            let Some(err) = tangent_error(&crit, &trial) else {
                continue;
            };
            checked += 1;
            assert!(err <= 1e-6, "{crit:?} {trial:?}: {err:e}");
            seen.push(return_map(&CLAY, &crit, trial).region);
        }
    }
    use Region::*;
    for region in [
        Elastic, Face, Edge, Apex, Cutoff, CutoffEdge, CutoffApex, FaceCutoff, Corner,
    ] {
        assert!(seen.contains(&region), "{region:?}");
    }
}

#[test]
fn tangent_with_coincident_eigenvalues() {
    // Triaxial trials (two equal principal stresses) inside regions that
    // keep them equal: the limit of the spin term, checked by differences.
    let cases = [
        (
            mc(10.0, 30.0, 10.0, 5.0),
            [20.0, -10.0, -10.0, 0.0, 0.0, 0.0],
            Region::Cutoff,
        ),
        (
            mc(10.0, 30.0, 10.0, 5.0),
            [-30.0, -30.0, -30.0, 0.0, 0.0, 0.0],
            Region::Elastic,
        ),
        (
            mc(10.0, 30.0, 10.0, 5.0),
            [-10.0, -90.0, -10.0, 0.0, 0.0, 0.0],
            Region::Edge,
        ),
        (
            YieldCriterion::Tresca { c_u: 50.0 },
            [-100.0, -300.0, -100.0, 0.0, 0.0, 0.0],
            Region::Edge,
        ),
        (
            YieldCriterion::VonMises { c_u: 50.0 },
            [100.0, -50.0, -50.0, 0.0, 0.0, 0.0],
            Region::Face,
        ),
    ];
    for (crit, trial, region) in cases {
        assert_eq!(return_map(&CLAY, &crit, trial).region, region);
        let err = tangent_error(&crit, &trial).expect("inside its region");
        assert!(err <= 1e-6, "{crit:?} {trial:?}: {err:e}");
    }
}

#[test]
fn yield_values_in_stress_units() {
    let rot = Rng(41).rotation();
    let s = rotate(&rot, &[10.0, -30.0, -90.0, 0.0, 0.0, 0.0]);
    assert!((yield_value(&YieldCriterion::Tresca { c_u: 20.0 }, s) - 30.0).abs() < 1e-12);
    let q = ((40f64.powi(2) + 60f64.powi(2) + 100f64.powi(2)) / 6.0).sqrt();
    assert!((yield_value(&YieldCriterion::VonMises { c_u: 20.0 }, s) - (q - 20.0)).abs() < 1e-12);
    // (s1 - s3)/2 + (s1 + s3)/2 sin 30 - 10 cos 30 = 50 - 20 - 8.66; s1 - t = 10 - 5.
    let f = 50.0 - 20.0 - 10.0 * 30f64.to_radians().cos();
    assert!((yield_value(&mc(10.0, 30.0, 10.0, 5.0), s) - f).abs() < 1e-12);
    let hydro = [20.0, 20.0, 20.0, 0.0, 0.0, 0.0];
    assert!((yield_value(&mc(10.0, 30.0, 10.0, 5.0), hydro) - 15.0).abs() < 1e-12);
    // A cut-off beyond the apex c / tan(phi) = 17.32 acts at the apex.
    let apex = 10.0 / 30f64.to_radians().tan();
    assert!((yield_value(&mc(10.0, 30.0, 10.0, 100.0), hydro) - (20.0 - apex)).abs() < 1e-12);
    let r = return_map(&CLAY, &mc(10.0, 30.0, 10.0, 100.0), hydro);
    assert_eq!(r.region, Region::Apex);
    assert!(max_diff(&r.stress, &[apex, apex, apex, 0.0, 0.0, 0.0]) < 1e-12);
    assert_eq!(r.tangent, [[0.0; 6]; 6]);
}

#[test]
fn validation_names_the_parameter() {
    let message = |c: YieldCriterion| c.validate().unwrap_err().to_string();
    assert!(message(YieldCriterion::Tresca { c_u: -1.0 }).contains("undrained strength c_u = -1"));
    assert!(message(YieldCriterion::VonMises { c_u: f64::NAN }).contains("c_u = NaN"));
    assert!(message(YieldCriterion::Tresca { c_u: f64::INFINITY }).contains("c_u = inf"));
    assert!(message(mc(-2.0, 30.0, 0.0, 0.0)).contains("cohesion c = -2"));
    assert!(message(mc(1.0, 90.0, 0.0, 0.0)).contains("friction angle phi = 90 deg"));
    assert!(message(mc(1.0, -5.0, 0.0, 0.0)).contains("friction angle phi = -5 deg"));
    assert!(message(mc(1.0, 30.0, 35.0, 0.0)).contains("dilation angle psi = 35 deg"));
    assert!(message(mc(1.0, 30.0, -1.0, 0.0)).contains("dilation angle psi = -1 deg"));
    assert!(message(mc(0.0, 0.0, 0.0, 0.0)).contains("cohesion c = 0 with friction angle phi = 0"));
    assert!(message(mc(1.0, 30.0, 0.0, -1.0)).contains("tension cut-off t = -1"));
    assert!(message(mc(1.0, 30.0, 0.0, f64::NAN)).contains("tension cut-off t = NaN"));
    assert_eq!(YieldCriterion::Tresca { c_u: 0.0 }.validate(), Ok(()));
    assert_eq!(mc(0.0, 35.0, 35.0, f64::INFINITY).validate(), Ok(()));
    for (crit, _) in criteria() {
        assert_eq!(crit.validate(), Ok(()), "{crit:?}");
    }
}
