//! The Pareto front of (time, error) points: those no other point beats on both.

/// Indices of the non-dominated points of `xy` (both coordinates to be minimised), ordered by increasing
/// `x` (and so by decreasing `y`). A point is dominated when another is no worse on both coordinates and
/// strictly better on one. Points with a NaN coordinate are ignored; of exact duplicates the first is kept.
pub fn front(xy: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..xy.len())
        .filter(|&i| !xy[i].0.is_nan() && !xy[i].1.is_nan())
        .collect();
    // By x, then y, then index: the first point of each x is the best one at that x.
    order.sort_by(|&a, &b| {
        xy[a]
            .0
            .total_cmp(&xy[b].0)
            .then(xy[a].1.total_cmp(&xy[b].1))
            .then(a.cmp(&b))
    });
    let mut out = Vec::new();
    let mut best_y = f64::INFINITY;
    for i in order {
        // Every earlier point has x ≤ this x; this point survives only if it is strictly better in y.
        if xy[i].1 < best_y {
            best_y = xy[i].1;
            out.push(i);
        }
    }
    out
}

/// The staircase through front points `(x, y)` sorted by increasing x: from each point go right at its
/// `y` to the next point's `x`, then down, and finally right to `x_end`; the region above and to the
/// right of the line is dominated.
pub fn staircase(front: &[(f64, f64)], x_end: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(2 * front.len() + 1);
    for (k, &(x, y)) in front.iter().enumerate() {
        out.push((x, y));
        let next_x = front.get(k + 1).map_or(x_end, |p| p.0);
        out.push((next_x, y));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn front_of_a_small_set_by_hand() {
        // (1, 10) fastest; (2, 5) better error; (3, 7) dominated by (2, 5); (4, 1) best error;
        // (4, 2) dominated by (4, 1) (same x, worse y); (5, 1) dominated (same y, slower); NaN ignored.
        let xy = [
            (3.0, 7.0),
            (1.0, 10.0),
            (4.0, 2.0),
            (2.0, 5.0),
            (4.0, 1.0),
            (5.0, 1.0),
            (f64::NAN, 0.0),
        ];
        assert_eq!(front(&xy), vec![1, 3, 4]);
    }

    #[test]
    fn duplicates_keep_the_first_and_empty_is_empty() {
        assert_eq!(front(&[(1.0, 1.0), (1.0, 1.0)]), vec![0]);
        assert!(front(&[]).is_empty());
    }

    #[test]
    fn staircase_goes_right_then_down() {
        let s = staircase(&[(1.0, 10.0), (2.0, 5.0)], 9.0);
        assert_eq!(s, vec![(1.0, 10.0), (2.0, 10.0), (2.0, 5.0), (9.0, 5.0)]);
    }
}
