//! Theta sections and the discrete Fourier pair between harmonic amplitudes
//! and section values (the paper's steps (1) and (3); docs/theory.md sections 8 and 10).
//!
//! Synthesis: `x(theta_s) = sum_m phi_m(theta_s) a_m`; analysis:
//! `f_m = sum_s w_s phi_m(theta_s) g(theta_s)`, the trapezoid rule for the
//! consistent load `f_m = Integral(g phi_m d theta)` over the turn. Analysis
//! is the transpose of synthesis with the weights `w_s`: an exact adjoint
//! pair. The basis functions `phi_m` per family and component:
//!
//! | family | r, z | theta |
//! |---|---|---|
//! | m = 0 | 1 | 1 (torsion) |
//! | symmetric | cos m.th | sin m.th |
//! | antisymmetric | sin m.th | -cos m.th |
//!
//! A half-circle set (loads symmetric about theta = 0) stands for itself and
//! its mirror image `-theta`; its weights are those of the mirrored full set.
//! There u_theta is odd in theta, so it has no torsion: the m = 0 theta basis
//! is 0 in half mode ([`Sections::phi`]), which keeps the pair exact.

use std::f64::consts::PI;

/// Displacement family.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// `u cos, v cos, w sin` (and m = 0).
    Symmetric,
    /// `u sin, v sin, -w cos`.
    Antisymmetric,
}

/// Theta sections with trapezoid weights.
#[derive(Clone, Debug, PartialEq)]
pub struct Sections {
    /// Angles in radians, increasing.
    pub theta: Vec<f64>,
    /// Quadrature weights (radians), summing to 2 pi.
    pub weight: Vec<f64>,
    /// True when the set covers [0, pi] for symmetric loads only.
    pub half: bool,
}

impl Sections {
    /// The paper's M + 1 sections `0, pi/M, ..., pi` (one at 0 for M = 0).
    pub fn paper(m_max: u32) -> Sections {
        let m = m_max.max(1);
        Sections::half_circle((0..=m).map(|k| PI * f64::from(k) / f64::from(m)).collect())
            .expect("equispaced sections are valid")
    }

    /// `n` equispaced sections over [0, pi] (both ends included).
    pub fn half_equispaced(n: usize) -> Sections {
        let n = n.max(2);
        Sections::half_circle((0..n).map(|k| PI * k as f64 / (n - 1) as f64).collect())
            .expect("equispaced sections are valid")
    }

    /// `n` equispaced sections over the full turn, starting at 0.
    pub fn full_equispaced(n: usize) -> Sections {
        let n = n.max(1);
        Sections::full_circle((0..n).map(|k| 2.0 * PI * k as f64 / n as f64).collect())
            .expect("equispaced sections are valid")
    }

    /// Sections in [0, pi] standing for the symmetric half.
    pub fn half_circle(theta: Vec<f64>) -> Result<Sections, String> {
        check_increasing(&theta, PI)?;
        let mirror = |t: f64| t > 0.0 && t < PI;
        let mut full: Vec<f64> = theta.clone();
        full.extend(theta.iter().filter(|&&t| mirror(t)).map(|t| 2.0 * PI - t));
        full.sort_by(f64::total_cmp);
        let w = periodic_trapezoid(&full);
        let weight_of = |t: f64| {
            let i = full.iter().position(|&x| x == t).expect("listed");
            w[i]
        };
        let weight = theta
            .iter()
            .map(|&t| weight_of(t) + if mirror(t) { weight_of(2.0 * PI - t) } else { 0.0 })
            .collect();
        Ok(Sections {
            theta,
            weight,
            half: true,
        })
    }

    /// Sections in [0, 2 pi).
    pub fn full_circle(theta: Vec<f64>) -> Result<Sections, String> {
        check_increasing(&theta, 2.0 * PI - 1e-12)?;
        let weight = periodic_trapezoid(&theta);
        Ok(Sections {
            theta,
            weight,
            half: false,
        })
    }

    /// The basis of [`basis`], with no torsion on a half-circle set.
    #[inline]
    pub fn phi(&self, m: u32, family: Family, theta: f64) -> (f64, f64) {
        let (a, b) = basis(m, family, theta);
        if self.half && m == 0 {
            (a, 0.0)
        } else {
            (a, b)
        }
    }

    /// Number of sections.
    pub fn len(&self) -> usize {
        self.theta.len()
    }

    /// True if there are no sections.
    pub fn is_empty(&self) -> bool {
        self.theta.is_empty()
    }

    /// Highest harmonic `m` such that the discrete products of all basis
    /// functions up to `m` are exact (`sum_s w_s phi_i phi_j = c_i delta_ij`,
    /// both families on a full set, the symmetric one on a half set):
    /// computed, so it holds for uneven sections too.
    pub fn resolves_up_to(&self, m_max: u32) -> Option<u32> {
        let c = |m: u32| if m == 0 { 2.0 * PI } else { PI };
        let families: &[Family] = if self.half {
            &[Family::Symmetric]
        } else {
            &[Family::Symmetric, Family::Antisymmetric]
        };
        let exact = |i: u32, j: u32| {
            families.iter().all(|&f| {
                let (mut rz, mut th) = (0.0, 0.0);
                for (&t, &w) in self.theta.iter().zip(&self.weight) {
                    let (a, b) = (self.phi(i, f, t), self.phi(j, f, t));
                    rz += w * a.0 * b.0;
                    th += w * a.1 * b.1;
                }
                let skip_rz = f == Family::Antisymmetric && (i == 0 || j == 0);
                let want = |torsion_absent: bool| if i == j && !torsion_absent { c(i) } else { 0.0 };
                let rz_ok = skip_rz || (rz - want(skip_rz)).abs() <= 1e-9 * c(i);
                let no_theta = (i == 0 || j == 0) && (self.half || f == Family::Antisymmetric);
                let th_ok = if i == 0 && j == 0 && no_theta {
                    th.abs() <= 1e-9
                } else if no_theta {
                    true
                } else {
                    (th - want(false)).abs() <= 1e-9 * c(i)
                };
                rz_ok && th_ok
            })
        };
        let mut best = None;
        for m in 0..=m_max {
            if (0..=m).all(|j| exact(m, j)) {
                best = Some(m);
            } else {
                break;
            }
        }
        best
    }

    /// Highest harmonic the set resolves without aliasing in the analysis:
    /// the trapezoid rule on n equispaced points of the turn integrates
    /// `phi_m phi_m'` exactly for m + m' < n.
    pub fn exact_up_to(&self) -> u32 {
        let n_full = if self.half {
            2 * self.theta.len().saturating_sub(1)
        } else {
            self.theta.len()
        };
        (n_full.saturating_sub(1) / 2) as u32
    }
}

fn check_increasing(theta: &[f64], max: f64) -> Result<(), String> {
    if theta.is_empty() {
        return Err("no sections".into());
    }
    if theta
        .iter()
        .any(|t| !t.is_finite() || *t < 0.0 || *t > max + 1e-12)
    {
        return Err(format!("sections must lie in [0, {:.6}] rad", max));
    }
    if theta.windows(2).any(|w| w[1] <= w[0]) {
        return Err("sections must be strictly increasing".into());
    }
    Ok(())
}

/// Trapezoid weights of sorted points on the periodic interval [0, 2 pi).
fn periodic_trapezoid(t: &[f64]) -> Vec<f64> {
    let n = t.len();
    if n == 1 {
        return vec![2.0 * PI];
    }
    (0..n)
        .map(|i| {
            let next = if i + 1 < n { t[i + 1] } else { t[0] + 2.0 * PI };
            let prev = if i > 0 { t[i - 1] } else { t[n - 1] - 2.0 * PI };
            0.5 * (next - prev)
        })
        .collect()
}

/// `phi_m` of a family at `theta` for the in-plane components (r, z) and
/// the circumferential one: `(phi_rz, phi_theta)`.
#[inline]
pub fn basis(m: u32, family: Family, theta: f64) -> (f64, f64) {
    if m == 0 {
        return match family {
            Family::Symmetric => (1.0, 1.0),
            Family::Antisymmetric => (0.0, 0.0),
        };
    }
    let (s, c) = (f64::from(m) * theta).sin_cos();
    match family {
        Family::Symmetric => (c, s),
        Family::Antisymmetric => (s, -c),
    }
}

/// `d/dtheta` of [`basis`]: `(-m sin, m cos)` symmetric, `(m cos, m sin)`
/// antisymmetric, zero for m = 0.
pub fn basis_derivative(m: u32, family: Family, theta: f64) -> (f64, f64) {
    if m == 0 {
        return (0.0, 0.0);
    }
    let mf = f64::from(m);
    let (s, c) = (mf * theta).sin_cos();
    match family {
        Family::Symmetric => (-mf * s, mf * c),
        Family::Antisymmetric => (mf * c, mf * s),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_sections_and_weights() {
        let s = Sections::paper(4);
        assert_eq!(s.len(), 5);
        let q = PI / 4.0;
        let expect = [q, 2.0 * q, 2.0 * q, 2.0 * q, q];
        for (w, e) in s.weight.iter().zip(expect) {
            assert!((w - e).abs() < 1e-15);
        }
        assert!((s.weight.iter().sum::<f64>() - 2.0 * PI).abs() < 1e-14);
        // M + 1 sections resolve harmonics up to M - 1 exactly.
        assert_eq!(s.exact_up_to(), 3);
        assert_eq!(Sections::half_equispaced(9).exact_up_to(), 7);
    }

    /// sum_s w_s phi_m phi_m' = c_m delta_mm' for m + m' < n (both families),
    /// and the Nyquist aliasing of the paper's set is what it should be.
    #[test]
    fn discrete_orthogonality() {
        let c = |m: u32| if m == 0 { 2.0 * PI } else { PI };
        for sections in [Sections::full_equispaced(9), Sections::half_equispaced(9)] {
            let fams: &[Family] = if sections.half {
                &[Family::Symmetric]
            } else {
                &[Family::Symmetric, Family::Antisymmetric]
            };
            let top = sections.exact_up_to();
            for &f in fams {
                for m in 0..=top {
                    for k in 0..=top {
                        if f == Family::Antisymmetric && (m == 0 || k == 0) {
                            continue;
                        }
                        for comp in 0..2 {
                            let sum: f64 = sections
                                .theta
                                .iter()
                                .zip(&sections.weight)
                                .map(|(&t, &w)| {
                                    let (a, b) = (sections.phi(m, f, t), sections.phi(k, f, t));
                                    w * if comp == 0 { a.0 * b.0 } else { a.1 * b.1 }
                                })
                                .sum();
                            let torsion = m == 0 && k == 0 && comp == 1;
                            let expect = match () {
                                _ if torsion && sections.half => 0.0,
                                _ if m == k => c(m),
                                _ => 0.0,
                            };
                            assert!(
                                (sum - expect).abs() < 1e-12,
                                "{f:?} m {m} k {k} comp {comp}: {sum}"
                            );
                        }
                    }
                }
            }
        }
        // The paper's M + 1 sections: cos(M th) is counted twice, sin(M th) not at all.
        let s = Sections::paper(4);
        let (mut cc, mut ss) = (0.0, 0.0);
        for (&t, &w) in s.theta.iter().zip(&s.weight) {
            let (a, b) = basis(4, Family::Symmetric, t);
            cc += w * a * a;
            ss += w * b * b;
        }
        assert!((cc - 2.0 * PI).abs() < 1e-12 && ss.abs() < 1e-12);
    }

    /// Analysis is the weighted transpose of synthesis: <S a, W g> = <a, A g>.
    #[test]
    fn exact_adjoint_pair() {
        let s = Sections::full_equispaced(7);
        let a: Vec<f64> = (0..5).map(|m| 0.3 + f64::from(m)).collect();
        let g: Vec<f64> = (0..s.len()).map(|i| (i as f64 * 1.7).sin()).collect();
        let synth: Vec<f64> = s
            .theta
            .iter()
            .map(|&t| {
                (0..5u32)
                    .map(|m| basis(m, Family::Symmetric, t).0 * a[m as usize])
                    .sum()
            })
            .collect();
        let lhs: f64 = synth
            .iter()
            .zip(&g)
            .zip(&s.weight)
            .map(|((x, y), w)| x * y * w)
            .sum();
        let rhs: f64 = (0..5u32)
            .map(|m| {
                let fm: f64 = s
                    .theta
                    .iter()
                    .zip(&s.weight)
                    .zip(&g)
                    .map(|((&t, &w), &gv)| w * basis(m, Family::Symmetric, t).0 * gv)
                    .sum();
                a[m as usize] * fm
            })
            .sum();
        assert!((lhs - rhs).abs() < 1e-13 * lhs.abs().max(1.0));
    }

    #[test]
    fn resolution_is_computed_not_assumed() {
        assert_eq!(Sections::paper(4).resolves_up_to(10), Some(3));
        assert_eq!(Sections::half_equispaced(9).resolves_up_to(10), Some(7));
        assert_eq!(Sections::full_equispaced(9).resolves_up_to(10), Some(4));
        // Uneven: 0, 90, 180 degrees as a full-turn set misses the other half.
        let uneven = Sections::full_circle(vec![0.0, PI / 2.0, PI]).unwrap();
        assert_eq!(uneven.resolves_up_to(4), Some(0));
    }

    #[test]
    fn bad_sections_are_refused() {
        assert!(Sections::half_circle(vec![0.0, 1.0, 0.5]).is_err());
        assert!(Sections::half_circle(vec![0.0, 4.0]).is_err());
        assert!(Sections::full_circle(vec![]).is_err());
    }
}
