//! Pareto fronts of (cost, error) points and the cost to reach an error.
//!
//! A point is on the front when no other point is at least as cheap and at
//! least as accurate, and strictly better in one of the two. The front is
//! returned in order of increasing cost (so of decreasing error).

/// Indices of the non-dominated points of `(cost, error)`, by increasing
/// cost. Points with a non-finite or non-positive coordinate are ignored.
/// Of two identical points only the first is kept.
pub fn front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..points.len())
        .filter(|&i| {
            let (c, e) = points[i];
            c.is_finite() && e.is_finite() && c > 0.0 && e > 0.0
        })
        .collect();
    // By cost, then by error: a sweep keeps every point that beats the best
    // error seen so far.
    idx.sort_by(|&a, &b| {
        points[a]
            .0
            .total_cmp(&points[b].0)
            .then(points[a].1.total_cmp(&points[b].1))
            .then(a.cmp(&b))
    });
    let mut out = Vec::new();
    let mut best = f64::INFINITY;
    for i in idx {
        if points[i].1 < best {
            best = points[i].1;
            out.push(i);
        }
    }
    out
}

/// The cost needed to reach `error` on a front (points `(cost, error)` by
/// increasing cost, decreasing error), interpolated linearly in log-log
/// between the two front points around it.
///
/// Returns `None` when the front never gets below `error`, and
/// `Some((cost, true))` with the cheapest point's cost when even that point
/// is below `error` (an upper bound: the real cost may be less).
pub fn cost_at_error(front: &[(f64, f64)], error: f64) -> Option<(f64, bool)> {
    let first = front.first()?;
    if first.1 <= error {
        return Some((first.0, true));
    }
    for w in front.windows(2) {
        let ((c0, e0), (c1, e1)) = (w[0], w[1]);
        if e1 <= error && error <= e0 {
            if e0 == e1 {
                return Some((c0, false));
            }
            let t = (error.ln() - e0.ln()) / (e1.ln() - e0.ln());
            return Some(((c0.ln() + t * (c1.ln() - c0.ln())).exp(), false));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn front_of_a_small_set() {
        let pts = [
            (1.0, 0.1),
            (2.0, 0.2),
            (2.0, 0.01),
            (3.0, 0.01),
            (0.5, 0.5),
            (4.0, 0.001),
        ];
        assert_eq!(front(&pts), vec![4, 0, 2, 5]);
    }

    #[test]
    fn log_log_interpolation() {
        let f = [(1.0, 0.1), (100.0, 0.001)];
        let (c, bound) = cost_at_error(&f, 0.01).unwrap();
        assert!((c - 10.0).abs() < 1e-12 && !bound);
        assert_eq!(cost_at_error(&f, 0.5), Some((1.0, true)));
        assert_eq!(cost_at_error(&f, 1e-4), None);
    }
}
