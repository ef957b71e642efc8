//! Branch identification, scalar roots: every zero of a function of one angle over a whole turn
//! (a torn block's equation in its cut), by bracketing. The function may be undefined on parts of
//! the turn (a sub-block past its dead point): the edges of those parts are found by bisection and
//! sampled too. Each sign change between samples is refined by the Illinois method with forced
//! bisection steps (safeguarded, to rounding level); each local minimum of |f| without a sign
//! change is searched by golden section for a hidden sign change (two roots closer than the grid).
//! On request, the values at the local extrema of `f` (a torn block's margins along the input).

use std::f64::consts::PI;

/// Samples of the cut's turn: `GRID` cells.
pub(super) const GRID: usize = 120;

/// Every zero of `f` on (−π, π], sorted, each once.
#[cfg(test)]
pub(super) fn all_roots(f: &mut dyn FnMut(f64) -> Option<f64>) -> Vec<f64> {
    roots_and_extrema(f, None)
}

/// `all_roots`, and into `extrema` (when given) the values of `f` at its local extrema between
/// samples (parabolic estimates, in the order of the cut): where one crosses zero as the input
/// moves, a pair of roots appears or vanishes.
pub(super) fn roots_and_extrema(
    f: &mut dyn FnMut(f64) -> Option<f64>,
    extrema: Option<&mut Vec<f64>>,
) -> Vec<f64> {
    let h = 2.0 * PI / GRID as f64;
    let mut s: Vec<(f64, Option<f64>)> = Vec::with_capacity(GRID + 8);
    // One cell past π, so that the windows below see across the seam (−π and π are one angle).
    for i in 0..=GRID + 1 {
        let t = if i == GRID { PI } else { -PI + h * i as f64 };
        let v = f(t).filter(|v| v.is_finite());
        if let Some(&(t0, v0)) = s.last()
            && v0.is_some() != v.is_some()
        {
            // An edge of the defined part: bisect to it, keep the defined end.
            let (mut a, mut b) = (t0, t);
            for _ in 0..60 {
                let m = 0.5 * (a + b);
                if m <= a.min(b) || m >= a.max(b) {
                    break;
                }
                if f(m).filter(|v| v.is_finite()).is_some() == v0.is_some() {
                    a = m;
                } else {
                    b = m;
                }
            }
            let edge = if v0.is_some() { a } else { b };
            s.push((edge, f(edge).filter(|v| v.is_finite())));
        }
        s.push((t, v));
    }
    if let Some(out) = extrema {
        out.extend(s.windows(3).filter_map(extremum));
    }
    let mut roots = Vec::new();
    for w in s.windows(2) {
        let ((a, fa), (b, fb)) = (w[0], w[1]);
        // The cell past π repeats the one after −π: a root in both is kept once (below).
        let (Some(fa), Some(fb)) = (fa, fb) else {
            continue;
        };
        if fa == 0.0 {
            roots.push(a);
        } else if fa * fb < 0.0 {
            roots.push(refine(f, (a, fa), (b, fb)));
        }
    }
    // Local minima of |f| between samples of one sign.
    for w in s.windows(3) {
        let [(a, Some(fa)), (m, Some(fm)), (b, Some(fb))] = [w[0], w[1], w[2]] else {
            continue;
        };
        if fa * fm > 0.0 && fm * fb > 0.0 && fm.abs() <= fa.abs() && fm.abs() <= fb.abs() {
            hidden_pair(f, (a, fa), (m, fm), (b, fb), &mut roots);
        }
    }
    for r in &mut roots {
        if *r <= -PI {
            *r += 2.0 * PI;
        } else if *r > PI {
            *r -= 2.0 * PI;
        }
    }
    roots.sort_by(f64::total_cmp);
    // The same root found twice (the seam's cell, or a near-double root refined from both
    // sides) differs by rounding; two distinct roots this close are within ~1e-18 of a dead point.
    roots.dedup_by(|x, y| (*x - *y).abs() <= 1e-9);
    if roots.len() > 1 && roots[0] + 2.0 * PI - roots[roots.len() - 1] <= 1e-9 {
        roots.pop();
    }
    roots
}

/// The value at the vertex of the parabola through three samples whose middle one is a strict
/// local extremum, or `None`.
fn extremum(w: &[(f64, Option<f64>)]) -> Option<f64> {
    let [(x0, Some(y0)), (x1, Some(y1)), (x2, Some(y2))] = [w[0], w[1], w[2]] else {
        return None;
    };
    if (y1 - y0) * (y2 - y1) >= 0.0 || !(x0 < x1 && x1 < x2) {
        return None;
    }
    let (d1, d2) = ((y1 - y0) / (x1 - x0), (y2 - y1) / (x2 - x1));
    let c = (d2 - d1) / (x2 - x0);
    let b = d1 + c * (x1 - x0);
    let v = if c != 0.0 { y1 - b * b / (4.0 * c) } else { y1 };
    // The vertex lies between the outer samples; the estimate stays between the samples' values.
    Some(if v.is_finite() { v } else { y1 })
}

/// The zero of `f` in the bracket `a`, `b` (values of opposite signs).
fn refine(f: &mut dyn FnMut(f64) -> Option<f64>, a: (f64, f64), b: (f64, f64)) -> f64 {
    let ((mut a, mut fa), (mut b, mut fb)) = (a, b);
    for it in 0..200 {
        let (lo, hi) = (a.min(b), a.max(b));
        if hi - lo <= 2.0 * f64::EPSILON * lo.abs().max(hi.abs()).max(1e-300) {
            break;
        }
        let secant = (a * fb - b * fa) / (fb - fa);
        let c = if it % 4 == 3 || !(secant > lo && secant < hi) {
            0.5 * (a + b)
        } else {
            secant
        };
        if c <= lo || c >= hi {
            break;
        }
        let Some(fc) = f(c).filter(|v| v.is_finite()) else {
            break;
        };
        if fc == 0.0 {
            return c;
        }
        if fc * fb < 0.0 {
            (a, fa) = (b, fb);
        } else {
            fa *= 0.5;
        }
        (b, fb) = (c, fc);
    }
    if fa.abs() < fb.abs() { a } else { b }
}

/// Golden-section search of `sign(fm)·f` on `[a, b]` around the sample `m`: a value of the other
/// sign splits the cell into two brackets, whose roots are added.
fn hidden_pair(
    f: &mut dyn FnMut(f64) -> Option<f64>,
    (a, fa): (f64, f64),
    (m, fm): (f64, f64),
    (b, fb): (f64, f64),
    roots: &mut Vec<f64>,
) {
    let sign = fm.signum();
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut lo, mut hi) = (a, b);
    let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let mut eval = |t: f64| f(t).filter(|v| v.is_finite());
    let (Some(mut f1), Some(mut f2)) = (eval(x1), eval(x2)) else {
        return;
    };
    let _ = m;
    for _ in 0..90 {
        for (x, v) in [(x1, f1), (x2, f2)] {
            if sign * v <= 0.0 {
                if v == 0.0 {
                    roots.push(x);
                } else {
                    roots.push(refine(f, (a, fa), (x, v)));
                    roots.push(refine(f, (x, v), (b, fb)));
                }
                return;
            }
        }
        // Two roots closer than this in the cut are within rounding of a dead point's input.
        if hi - lo <= 1e-9 {
            return;
        }
        if sign * f1 < sign * f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - g * (hi - lo);
            let Some(v) = f(x1).filter(|v| v.is_finite()) else {
                return;
            };
            f1 = v;
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + g * (hi - lo);
            let Some(v) = f(x2).filter(|v| v.is_finite()) else {
                return;
            };
            f2 = v;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simple_and_close_roots_and_partial_domains() {
        // Two roots 1e-6 apart inside one grid cell, and two far apart.
        let r = all_roots(&mut |t| Some((t - 0.3) * (t - 0.3 - 1e-6) * (t + 2.0) * (t - 2.5)));
        assert_eq!(r.len(), 4, "{r:?}");
        assert!(
            (r[1] - 0.3).abs() < 1e-14 && (r[2] - 0.300001).abs() < 1e-14,
            "{r:?}"
        );
        // Defined only on (−1, 1): cos t − 0.9 has its roots ±acos 0.9 there.
        let r = all_roots(&mut |t| (t.abs() < 1.0).then(|| t.cos() - 0.9));
        assert_eq!(r.len(), 2);
        assert!((r[1] - 0.9f64.acos()).abs() < 1e-15);
        // A root at π (the seam) is found once.
        let r = all_roots(&mut |t| Some(t.sin()));
        assert_eq!(r.len(), 2, "{r:?}");
        assert!(r[0].abs() < 1e-300 && r[1] == PI, "{r:?}");
        assert!(all_roots(&mut |t| Some(t.cos() + 1.5)).is_empty());
    }

    #[test]
    fn extrema_between_samples() {
        // cos(t − 0.3) − 0.2: a maximum 0.8 at 0.3, a minimum −1.2 at 0.3 − π, off the grid.
        let mut ext = Vec::new();
        let r = roots_and_extrema(&mut |t| Some((t - 0.3).cos() - 0.2), Some(&mut ext));
        assert_eq!(r.len(), 2);
        assert_eq!(ext.len(), 2, "{ext:?}");
        assert!(
            (ext[0] + 1.2).abs() < 1e-6 && (ext[1] - 0.8).abs() < 1e-6,
            "{ext:?}"
        );
        // No extremum of a monotonic piece; none where `f` is undefined.
        let mut ext = Vec::new();
        roots_and_extrema(&mut |t| (t.abs() < 1.0).then_some(t), Some(&mut ext));
        assert!(ext.is_empty(), "{ext:?}");
    }
}
