//! Axes: ranges, tick labels, log-axis ticks, and the chart margins.

use super::canvas::Area;
use plotters::prelude::*;

/// A tick label: plain decimals for moderate magnitudes, else `1.5e-4`.
pub(super) fn tick(v: f64) -> String {
    let a = v.abs();
    if a < 1e-12 {
        "0".to_owned()
    } else if (1e-3..1e5).contains(&a) {
        let s = format!("{v:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        if s == "-0" {
            "0".to_owned()
        } else {
            s.to_owned()
        }
    } else {
        let s = format!("{v:.2e}");
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let m = m.trim_end_matches('0').trim_end_matches('.');
        format!("{m}e{e}")
    }
}

/// `[min, max]` of the values, or `None` when empty.
pub(super) fn extent(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values.fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// A range of non-zero width around `[lo, hi]`, widened by `margin` of it.
pub(super) fn padded((lo, hi): (f64, f64), margin: f64) -> (f64, f64) {
    if hi > lo {
        let m = (hi - lo) * margin;
        (lo - m, hi + m)
    } else {
        let m = (lo.abs() * 0.1).max(1.0);
        (lo - m, hi + m)
    }
}

/// Ticks of a log axis from `y0` to `y1` (both powers of ten): each decade,
/// plus 2 and 5 times it when the range is 3 decades or less; `true` marks
/// the decades.
pub(super) fn log_ticks(y0: f64, y1: f64) -> Vec<(f64, bool)> {
    let (d0, d1) = (y0.log10().round() as i32, y1.log10().round() as i32);
    let every = ((d1 - d0 + 11) / 12).max(1);
    let mults: &[u32] = if d1 - d0 <= 3 { &[1, 2, 5] } else { &[1] };
    let mut ticks = Vec::new();
    for d in (d0..=d1).step_by(every as usize) {
        for &m in mults {
            let v: f64 = format!("{m}e{d}").parse().unwrap_or(f64::NAN);
            if v <= y1 * (1.0 + 1e-9) {
                ticks.push((v, m == 1));
            }
        }
    }
    ticks
}

/// Whole decades around the positive ratios; one decade lower when some
/// ratio <= 0 is to be drawn on the bottom edge.
pub(super) fn log_range(positive: Option<(f64, f64)>, any_clipped: bool) -> (f64, f64) {
    let Some((lo, hi)) = positive else {
        return (0.1, 1.0);
    };
    let mut d0 = lo.log10().floor();
    let mut d1 = hi.log10().ceil();
    if any_clipped {
        d0 -= 1.0;
    }
    if d1 <= d0 {
        d1 = d0 + 1.0;
    }
    let decade = |d: f64| format!("1e{}", d.clamp(-300.0, 300.0)).parse().unwrap_or(1.0);
    (decade(d0), decade(d1))
}

pub(super) fn chart_builder<'a, 'b, DB: DrawingBackend>(area: &'a Area<DB>) -> ChartBuilder<'a, 'b, DB> {
    let mut b = ChartBuilder::on(area);
    b.margin_top(10)
        .margin_left(10)
        .margin_right(25)
        .margin_bottom(10)
        .x_label_area_size(60)
        .y_label_area_size(95);
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels() {
        assert_eq!(tick(0.0), "0");
        assert_eq!(tick(1.0), "1");
        assert_eq!(tick(-2.5), "-2.5");
        assert_eq!(tick(0.001), "0.001");
        assert_eq!(tick(1e-5), "1e-5");
        assert_eq!(tick(2.5e6), "2.5e6");
        assert_eq!(tick(0.30000000000000004), "0.3");
    }

    #[test]
    fn log_range_decades() {
        assert_eq!(log_range(Some((0.02, 1.0)), false), (0.01, 1.0));
        assert_eq!(log_range(Some((0.02, 1.0)), true), (0.001, 1.0));
        assert_eq!(log_range(Some((1.0, 1.0)), false), (1.0, 10.0));
        assert_eq!(log_range(None, true), (0.1, 1.0));
    }

    #[test]
    fn log_axis_ticks() {
        let v: Vec<f64> = log_ticks(0.01, 1.0).into_iter().map(|t| t.0).collect();
        assert_eq!(v, [0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0]);
        let t = log_ticks(1e-5, 1.0);
        assert_eq!(t.len(), 6);
        assert!(t.iter().all(|t| t.1));
    }
}
