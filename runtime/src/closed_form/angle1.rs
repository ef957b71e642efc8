//! One-angle kernel (part of `closed_form`): a single equation in one angle,
//! `K + P cos q + Q sin q = 0` (the slider-crank's rod angle from the y equation). With
//! `w = (P, Q)` and `c = −K`, `e(q) = (c w ± √(|w|² − c²) w⊥) / |w|²`: two modes, symmetric
//! about `w`; the dead point is `|c| = |w|` (the rod perpendicular to the slide).

use super::{Mode, Modes, all_finite, dead_point_slack};
use crate::error::{SolveError, Stage};
use crate::scalar::Real;
use crate::solve::{NewtonReport, TrigState};

/// `(c, w, |w|², t, |w|)` with `t = √(|w|² − c²) ≥ 0`, or `Err(gap)` past the dead point.
// `!(a > b)` is deliberate: a NaN must fail the test.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
#[allow(clippy::type_complexity)]
#[inline(always)]
fn reduce<T: Real>(
    block: usize,
    k: T,
    w: (T, T),
) -> Result<Result<(T, (T, T), T, T, T), T>, SolveError> {
    if !all_finite(&[k, w.0, w.1]) {
        return Err(super::overflow(block));
    }
    // `P = 0` (a slide along x; in generated code the literal zero, so this folds away): `|w| =
    // |Q|` without a square root, as the dyad takes `|p|`.
    let pure = w.0 == T::zero();
    let ww = if pure {
        w.1 * w.1
    } else {
        w.0 * w.0 + w.1 * w.1
    };
    if !(ww > T::zero()) {
        return Err(SolveError::Singular {
            block,
            stage: Stage::Position,
            pivot_ratio: 0.0,
        });
    }
    if !(ww + k * k).is_finite() {
        return Err(super::overflow(block));
    }
    let (c, r) = (-k, if pure { w.1.abs() } else { ww.sqrt() });
    // √(|w|² − c²) as √((|w| − |c|)(|w| + |c|)), cancellation-free at the dead point.
    let near = r - c.abs();
    if near < -dead_point_slack::<T>() * r {
        return Ok(Err(c.abs() - r));
    }
    let t = if near > T::zero() {
        (near * (r + c.abs())).sqrt()
    } else {
        T::zero()
    };
    Ok(Ok((c, w, ww, t, r)))
}

/// `e(q)` of mode `tau` (the sign of `w⊥ · e(q)`), and the pivot ratio `t / |w|` by the
/// reciprocal `e` takes (no second division).
#[inline(always)]
fn direction<T: Real>((c, w, ww, t, r): (T, (T, T), T, T, T), tau: T) -> ((T, T), T) {
    let x = tau * t;
    if w.0 == T::zero() {
        // `w = (0, Q)`: `e = (−x, c) / Q`, one division.
        let inv = T::one() / w.1;
        return ((-x * inv, c * inv), t * inv.abs());
    }
    let inv = T::one() / ww;
    (
        ((c * w.0 - x * w.1) * inv, (c * w.1 + x * w.0) * inv),
        t * r * inv,
    )
}

/// Both modes of `K + P cos q + Q sin q = 0` (`w = (P, Q)`): `w⊥ · e(q) ≥ 0` first; one at the
/// dead point, none past it. The angle is in `values[0]`.
pub fn angle1_modes<T: Real>(block: usize, k: T, w: (T, T)) -> Result<Modes<T>, SolveError> {
    let mut out = Modes::none();
    if let Ok(red) = reduce(block, k, w)? {
        let taus: &[T] = if red.3 > T::zero() {
            &[T::one(), -T::one()]
        } else {
            &[T::one()]
        };
        for &tau in taus {
            let ((c, s), _) = direction(red, tau);
            if !all_finite(&[c, s]) {
                return Err(super::overflow(block));
            }
            out.push(Mode {
                values: [s.atan2(c), T::zero()],
                sc: [(s, c), (T::zero(), T::one())],
            });
        }
    }
    Ok(out)
}

/// Solves the one-angle block `K + P cos q + Q sin q = 0` in place (`w = (P, Q)`); the guessed
/// angle `st.q[q]` (with its sine and cosine) picks the mode: the side of `w` it lies on. `scale`
/// gives the length scale (asked for only to report an error). Past the dead point:
/// `Unassemblable` with the relative gap; a non-finite guess: `NonFinite`. The pivot ratio
/// reported is `t / |w| = |sin|` of the angle between `e(q)` and its dead position (the
/// derivative `−P sin q + Q cos q` over its largest value `|w|`): 0 at the dead point, as
/// the RPR's, where elimination's pivot ratio of a 1×1 block would be 1 everywhere and the
/// sweep could not tell that its branch ends there.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn solve_angle1<T: Real, const N: usize>(
    block: usize,
    st: &mut TrigState<T, N>,
    q: usize,
    k: T,
    w: (T, T),
    scale: impl FnOnce() -> T,
    tolerance: T,
    report: &mut NewtonReport<T>,
    value: bool,
) -> Result<(), SolveError> {
    super::check_guess(st, q)?;
    let red = super::closes(block, reduce(block, k, w)?, scale)?;
    let (sg, cg) = st.sc[q];
    let tau = super::side(w.0 * sg - w.1 * cg);
    let (e, ratio) = direction(red, tau);
    if !all_finite(&[e.0, e.1]) {
        return Err(super::overflow(block));
    }
    super::set_angle(st, q, e, tolerance, value);
    if ratio < report.pivot_ratio {
        report.pivot_ratio = ratio;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::test_util::angle_gap;
    use super::*;
    use std::f64::consts::{FRAC_PI_2, TAU};

    fn solve(k: f64, w: (f64, f64), guess: f64) -> Result<f64, SolveError> {
        let mut st = TrigState::new([guess], [true]);
        let mut report = NewtonReport::new();
        solve_angle1(0, &mut st, 0, k, w, || 1.0, 1e-12, &mut report, true)?;
        let (sn, cs) = st.q[0].sin_cos();
        // Exact to the rounding of q itself.
        let tol = 1e-15 + 2.0 * f64::EPSILON * st.q[0].abs();
        assert!((st.sc[0].0 - sn).abs() < tol && (st.sc[0].1 - cs).abs() < tol);
        Ok(st.q[0])
    }

    #[test]
    fn both_modes_against_acos() {
        // R cos(q − φ) = c: q = φ ± acos(c / R).
        for w in [(0.0f64, 0.2f64), (0.3, -0.4), (-1.0, 0.5)] {
            for ratio in [0.0f64, 0.3, -0.7, 0.95] {
                let (r, phi) = (w.0.hypot(w.1), w.1.atan2(w.0));
                let k = -ratio * r;
                for sign in [1.0, -1.0] {
                    let q = phi + sign * ratio.acos();
                    let got = solve(k, w, q + 0.05).unwrap();
                    assert!((got - q).abs() < 1e-14, "{w:?} {ratio}: {got} vs {q}");
                }
                let modes = angle1_modes(0, k, w).unwrap();
                assert_eq!(modes.len(), 2);
                for sign in [1.0, -1.0] {
                    let q = phi + sign * ratio.acos();
                    assert!(
                        modes
                            .as_slice()
                            .iter()
                            .any(|m| angle_gap(m.values[0], q) < 1e-14)
                    );
                }
            }
        }
    }

    #[test]
    fn whole_turns_are_kept() {
        let got = solve(-0.5, (1.0, 0.0), FRAC_PI_2 - 0.4 + 5.0 * TAU).unwrap();
        assert!((got - (0.5f64.acos() + 5.0 * TAU)).abs() < 1e-13);
    }

    #[test]
    fn near_at_and_past_the_dead_point() {
        // sin q = 1 − δ: q = π/2 ± √(2δ) (1 + δ/12 + …), from acos written as 2 asin √(δ/2).
        let mut worst: f64 = 0.0;
        for nominal in [1e-2f64, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14] {
            // δ as the f64 equation holds it (1 − (1 − δ) is exact).
            let c = 1.0 - nominal;
            let delta = 1.0 - c;
            let q = FRAC_PI_2 - 2.0 * (delta / 2.0).sqrt().asin();
            let got = solve(-c, (0.0, 1.0), 1.0).unwrap();
            let err = (got - q).abs() * delta.sqrt() / f64::EPSILON;
            assert!(err <= 4.0, "δ = {delta}: {got} vs {q}");
            worst = worst.max(err);
        }
        std::eprintln!("one angle: largest error near the dead point {worst:.2} ε/√δ");
        assert!((solve(-1.0, (0.0, 1.0), 1.0).unwrap() - FRAC_PI_2).abs() < 1e-15);
        assert_eq!(angle1_modes(0, -1.0, (0.0, 1.0)).unwrap().len(), 1);
        match solve(-(1.0 + 1e-9), (0.0, 1.0), 1.0) {
            Err(SolveError::Unassemblable { residual, .. }) => {
                assert!((residual - 1e-9).abs() < 1e-15)
            }
            other => panic!("{other:?}"),
        }
        assert!(
            angle1_modes(0, -(1.0 + 1e-9), (0.0, 1.0))
                .unwrap()
                .is_empty()
        );
    }

    #[test]
    fn degenerate_and_non_finite_arguments_are_errors() {
        assert!(matches!(
            solve(0.5, (0.0, 0.0), 0.0),
            Err(SolveError::Singular { .. })
        ));
        assert!(matches!(
            solve(f64::NAN, (1.0, 0.0), 0.0),
            Err(SolveError::Overflow { .. })
        ));
        assert!(matches!(
            solve(0.5, (1.0, 0.0), f64::NEG_INFINITY),
            Err(SolveError::NonFinite { .. })
        ));
    }

    /// The pivot ratio is the derivative `−P sin q + Q cos q` of the solution over `|w|` (the
    /// sine of the angle from the dead position), 0 at the dead point; only ever lowered.
    #[test]
    fn the_pivot_ratio_is_the_scaled_derivative() {
        for (k, w, guess) in [
            (-0.5, (1.0, 0.0), 1.0),
            (0.3, (0.3, -0.4), 2.0),
            (-0.2, (-1.0, 0.5), -1.0),
            (0.999, (0.0, -1.0), 0.5),
        ] {
            let mut st = TrigState::new([guess], [true]);
            let mut report = NewtonReport::new();
            solve_angle1(0, &mut st, 0, k, w, || 1.0, 1e-12, &mut report, true).unwrap();
            let (sn, cs) = st.q[0].sin_cos();
            let want = (-w.0 * sn + w.1 * cs).abs() / w.0.hypot(w.1);
            assert!(
                (report.pivot_ratio - want).abs() < 1e-13,
                "{k} {w:?}: {} {want}",
                report.pivot_ratio
            );
            let below = report.pivot_ratio;
            solve_angle1(0, &mut st, 0, 0.0, w, || 1.0, 1e-12, &mut report, true).unwrap();
            assert_eq!(
                report.pivot_ratio, below,
                "a larger ratio leaves the report"
            );
        }
        let mut st = TrigState::new([1.0], [true]);
        let mut report = NewtonReport::new();
        solve_angle1(
            0,
            &mut st,
            0,
            -1.0,
            (0.0, 1.0),
            || 1.0,
            1e-12,
            &mut report,
            true,
        )
        .unwrap();
        assert_eq!(report.pivot_ratio, 0.0);
        assert_eq!(report.condition(), f64::INFINITY);
    }
}
