//! Cylindrical to Cartesian: displacements and stress tensors, the von
//! Mises stress, and the trigonometric values of an angle.

/// The cylindrical stress `(sr, sz, st, trz, trt, tzt)` as a Cartesian
/// tensor, row-major 3x3.
pub fn stress_to_cartesian(s: [f64; 6], theta: f64) -> [f64; 9] {
    let [sr, sz, st, trz, trt, tzt] = s;
    let (sn, c) = theta.sin_cos();
    let xx = sr * c * c + st * sn * sn - 2.0 * trt * sn * c;
    let yy = sr * sn * sn + st * c * c + 2.0 * trt * sn * c;
    let xy = (sr - st) * sn * c + trt * (c * c - sn * sn);
    let yz = trz * sn + tzt * c;
    let xz = trz * c - tzt * sn;
    [xx, xy, xz, xy, yy, yz, xz, yz, sz]
}

/// Von Mises equivalent of a cylindrical stress.
pub(super) fn von_mises(s: [f64; 6]) -> f64 {
    let [sr, sz, st, trz, trt, tzt] = s;
    (0.5 * ((sr - sz).powi(2) + (sz - st).powi(2) + (st - sr).powi(2))
        + 3.0 * (trz * trz + trt * trt + tzt * tzt))
        .sqrt()
}

/// `1, cos t, sin t, cos 2t, sin 2t, ..., cos Mt, sin Mt`.
pub(super) fn trig_basis(t: f64, m_max: usize) -> Vec<f64> {
    std::iter::once(1.0)
        .chain((1..=m_max).flat_map(move |m| {
            let (s, c) = (m as f64 * t).sin_cos();
            [c, s]
        }))
        .collect()
}

/// `(sin m t, cos m t)` for m = 0 ..= m_max ([`Displacements::at_trig`]).
///
/// [`Displacements::at_trig`]: axijoint_solver::solution::Displacements::at_trig
pub(super) fn trig_pairs(t: f64, m_max: usize) -> Vec<(f64, f64)> {
    (0..=m_max).map(|m| (m as f64 * t).sin_cos()).collect()
}

/// Cartesian `(ux, uy, uz)` from `(u_r, u_z, u_theta)` at the angle whose
/// `(sin, cos)` is `sc`.
pub(super) fn cartesian([ur, uz, ut]: [f64; 3], (s, c): (f64, f64)) -> [f64; 3] {
    [ur * c - ut * s, ur * s + ut * c, uz]
}
