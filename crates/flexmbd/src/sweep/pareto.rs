//! The Pareto front of (error, CPU time) points: the runs no other run beats on both.

/// The indices (ascending) of the points of `points` = `(error, cpu)` that no other point
/// dominates. A point dominates another when it is no worse on both and better on one.
/// Points equal on both are on the front together or off it together; a point with a
/// non-finite coordinate is never on it (nor does it take a point off it).
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].0.is_finite() && points[i].1.is_finite())
        .collect();
    // By error, then CPU: a point is dominated exactly when an earlier point (smaller
    // error, or the same error) has a smaller CPU time, or the same CPU time and a smaller
    // error.
    order.sort_by(|&a, &b| {
        points[a]
            .0
            .total_cmp(&points[b].0)
            .then(points[a].1.total_cmp(&points[b].1))
    });
    let mut front = Vec::new();
    let mut best: Option<(f64, f64)> = None; // the last point taken onto the front
    for i in order {
        let (e, c) = points[i];
        let on_front = match best {
            None => true,
            // Equal to the last front point: on the front with it.
            Some((be, bc)) if be == e && bc == c => true,
            // Earlier points have error ≤ e; the cheapest of them is the last front point.
            Some((_, bc)) => c < bc,
        };
        if on_front {
            front.push(i);
            best = Some((e, c));
        }
    }
    front.sort_unstable();
    front
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn dominates(a: (f64, f64), b: (f64, f64)) -> bool {
        a.0 <= b.0 && a.1 <= b.1 && (a.0 < b.0 || a.1 < b.1)
    }

    #[test]
    fn front_of_a_small_set() {
        // (error, cpu): 0 and 2 trade error against time, 1 is beaten by 0, 3 equals 2.
        let points = [
            (1.0, 1.0),
            (2.0, 1.5),
            (0.5, 3.0),
            (0.5, 3.0),
            (f64::NAN, 0.1),
        ];
        assert_eq!(pareto_front(&points), [0, 2, 3]);
        assert!(pareto_front(&[]).is_empty());
    }

    proptest! {
        /// No point on the front is dominated; every point off it is dominated (or not finite).
        #[test]
        fn the_front_is_exactly_the_undominated_points(
            raw in proptest::collection::vec((0u8..8, 0u8..8), 0..40)
        ) {
            // Small integer grids make ties and duplicates common.
            let points: Vec<(f64, f64)> =
                raw.iter().map(|&(e, c)| (f64::from(e), f64::from(c))).collect();
            let front = pareto_front(&points);
            for i in 0..points.len() {
                let dominated = points.iter().any(|&p| dominates(p, points[i]));
                prop_assert_eq!(front.contains(&i), !dominated, "point {} {:?}", i, points[i]);
            }
        }
    }
}
