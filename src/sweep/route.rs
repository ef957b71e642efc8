//! A walk's way from one row's input to the next in substeps of at most the largest substep
//! ([`Route`]): how many, and where each ends. The scalar walker and the lanes take it alike, so
//! both stop at the same inputs.

use super::MAX_ROUTE;

/// The substeps from `from` to `target`: `n` of equal length, the last ending at `target`
/// itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Route {
    from: f64,
    target: f64,
    distance: f64,
    n: usize,
}

impl Route {
    /// One substep when `target` lies within `h_max` of `from`, else as many as it takes at
    /// most `h_max` each; `None` when that is more than [`MAX_ROUTE`] or not a number (an input
    /// or `h_max` that is not finite, or `h_max` zero).
    pub(super) fn new(from: f64, target: f64, h_max: f64) -> Option<Route> {
        let distance = target - from;
        let n = if distance.abs() <= h_max {
            1
        } else {
            let n = (distance.abs() / h_max).ceil();
            if !(n.is_finite() && n <= MAX_ROUTE as f64) {
                return None;
            }
            n as usize
        };
        Some(Route {
            from,
            target,
            distance,
            n,
        })
    }

    /// How many substeps.
    pub(super) fn len(&self) -> usize {
        self.n
    }

    /// Where substep `j` (1 to [`Route::len`]) ends.
    pub(super) fn end(&self, j: usize) -> f64 {
        if j >= self.n {
            self.target
        } else {
            self.from + self.distance * (j as f64 / self.n as f64)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn substeps_are_equal_none_longer_than_the_largest_and_the_last_ends_at_the_target() {
        let r = Route::new(0.25, 1.0, 0.2).expect("a route");
        assert_eq!(r.len(), 4);
        let ends: Vec<f64> = (1..=4).map(|j| r.end(j)).collect();
        assert_eq!(ends, [0.4375, 0.625, 0.8125, 1.0]);
        // Downward, and within one substep.
        let down = Route::new(1.0, 0.25, 0.2).expect("a route");
        assert_eq!((down.len(), down.end(4)), (4, 0.25));
        assert_eq!(down.end(1), 0.8125);
        let one = Route::new(1.0, 1.1, 0.2).expect("a route");
        assert_eq!((one.len(), one.end(1)), (1, 1.1));
        // Too far, or not a number.
        assert_eq!(Route::new(0.0, 1.0, 1.0 / 4096.0), None);
        assert_eq!(
            Route::new(0.0, 1.0, 1.0 / 1024.0).map(|r| r.len()),
            Some(1024)
        );
        assert_eq!(Route::new(0.0, f64::NAN, 0.2), None);
        assert_eq!(Route::new(0.0, 1.0, 0.0), None);
    }
}
