//! RRP / PRR kernel (part of `closed_form`): an angle q and a length s along a fixed direction,
//! `K + M e(q) + s u = 0`. With `d = −K` and `A = M e(q) = d − s u`, the circle `|A| = |M|` meets
//! the line through `d` along `u`: two modes, symmetric about the perpendicular from the circle's
//! centre to the line; the dead point is the circle tangent to the line.

use super::{Modes, all_finite, angle_length, apply, dead_point_slack, unapply};
use crate::error::SolveError;
use crate::scalar::Real;
use crate::solve::{NewtonReport, TrigState};

/// The cut of the circle by the line.
struct Cut<T> {
    /// Foot of the perpendicular from the centre on the line (relative to the centre).
    foot: (T, T),
    /// Half the chord, ≥ 0 (0 at the dead point).
    half: T,
    /// `u / |u|`.
    unit: (T, T),
    /// `d·u / |u|²`: the `s` of the foot.
    s0: T,
    inv_ul: T,
    /// `|M|`.
    l: T,
}

/// The cut, or `Err(gap)` (the distance from the circle to the line, in length) past the dead
/// point; `Singular` for `u = 0` or `M = 0`, the overflow error for non-finite coefficients.
#[allow(clippy::type_complexity)]
fn cut<T: Real>(
    block: usize,
    k: [T; 2],
    m: (T, T),
    u: [T; 2],
) -> Result<Result<Cut<T>, T>, SolveError> {
    if !all_finite(&[k[0], k[1], m.0, m.1, u[0], u[1]]) {
        return Err(super::overflow(block));
    }
    let d = (-k[0], -k[1]);
    let uu = u[0] * u[0] + u[1] * u[1];
    let l2 = m.0 * m.0 + m.1 * m.1;
    if !(uu > T::zero() && l2 > T::zero()) {
        return Err(SolveError::Singular {
            block,
            stage: crate::error::Stage::Position,
            pivot_ratio: 0.0,
        });
    }
    if !(uu + l2 + d.0 * d.0 + d.1 * d.1).is_finite() {
        return Err(super::overflow(block));
    }
    let l = if m.1 == T::zero() {
        m.0.abs()
    } else {
        l2.sqrt()
    };
    let ul = uu.sqrt();
    let inv_ul = T::one() / ul;
    let unit = (u[0] * inv_ul, u[1] * inv_ul);
    // Signed distance of the line from the centre, along n = u⊥ / |u|.
    let h = unit.0 * d.1 - unit.1 * d.0;
    let dist = h.abs();
    // The half chord √(l² − h²) as √((l − |h|)(l + |h|)): the first factor, which vanishes at
    // the dead point, is a difference of two lengths each exact to rounding (no cancellation of
    // squares), so the half chord is good to ε/√δ there.
    let near = l - dist;
    if near < -dead_point_slack::<T>() * l {
        return Ok(Err(dist - l));
    }
    let half = if near > T::zero() {
        (near * (l + dist)).sqrt()
    } else {
        T::zero()
    };
    Ok(Ok(Cut {
        foot: (-unit.1 * h, unit.0 * h),
        half,
        unit,
        s0: (d.0 * unit.0 + d.1 * unit.1) * inv_ul,
        inv_ul,
        l,
    }))
}

impl<T: Real> Cut<T> {
    /// Mode `tau` (±1: the sign of `A·u`): the direction `e(q)` and `s`.
    fn mode(&self, m: (T, T), tau: T) -> ((T, T), T) {
        let w = tau * self.half;
        let a = (self.foot.0 + w * self.unit.0, self.foot.1 + w * self.unit.1);
        (unapply(m, a), self.s0 - w * self.inv_ul)
    }
}

/// Both modes of `K + M e(q) + s u = 0` (`m = (p, r)` of `M`): the one with `A·u ≥ 0` first;
/// one at the dead point, none past it.
pub fn rrp_modes<T: Real>(
    block: usize,
    k: [T; 2],
    m: (T, T),
    u: [T; 2],
) -> Result<Modes<T>, SolveError> {
    let mut out = Modes::none();
    if let Ok(c) = cut(block, k, m, u)? {
        let taus: &[T] = if c.half > T::zero() {
            &[T::one(), -T::one()]
        } else {
            &[T::one()]
        };
        for &tau in taus {
            let (e, s) = c.mode(m, tau);
            if !all_finite(&[e.0, e.1, s]) {
                return Err(super::overflow(block));
            }
            out.push(angle_length(e, s));
        }
    }
    Ok(out)
}

/// Solves the RRP block `K + M e(q) + s u = 0` in place: `q` and `s` index `st`, whose angle
/// `q` (with its sine and cosine) picks the mode: the side of the perpendicular foot on which
/// `M e(q)` lies. `scale` gives the length scale (asked for only to report an error). Past the
/// dead point (the circle misses the line): `Unassemblable` with the relative gap; a non-finite
/// guess of `q`: `NonFinite`. The pivot ratio reported is the cosine between `M e(q)` and `u`.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn solve_rrp<T: Real, const N: usize>(
    block: usize,
    st: &mut TrigState<T, N>,
    q: usize,
    s: usize,
    k: [T; 2],
    m: (T, T),
    u: [T; 2],
    scale: impl FnOnce() -> T,
    tolerance: T,
    report: &mut NewtonReport<T>,
    value: bool,
) -> Result<(), SolveError> {
    super::check_guess(st, q)?;
    let c = super::closes(block, cut(block, k, m, u)?, scale)?;
    let (sg, cg) = st.sc[q];
    let a = apply(m, (cg, sg));
    let tau = super::side(a.0 * u[0] + a.1 * u[1]);
    let (e, len) = c.mode(m, tau);
    if !all_finite(&[e.0, e.1, len]) {
        return Err(super::overflow(block));
    }
    super::set_angle(st, q, e, tolerance, value);
    st.q[s] = len;
    let ratio = c.half / c.l;
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

    /// `K` of the configuration (q, s): −(M e(q) + s u), written with an explicit angle offset
    /// and length instead of the rotation-scaling.
    fn k_of(m: (f64, f64), u: [f64; 2], q: f64, s: f64) -> [f64; 2] {
        let (len, off) = (m.0.hypot(m.1), m.1.atan2(m.0));
        [
            -(len * (q + off).cos() + s * u[0]),
            -(len * (q + off).sin() + s * u[1]),
        ]
    }

    fn solve(
        k: [f64; 2],
        m: (f64, f64),
        u: [f64; 2],
        guess: f64,
    ) -> Result<(f64, f64), SolveError> {
        let mut st = TrigState::new([guess, 0.0], [true, false]);
        let mut report = NewtonReport::new();
        solve_rrp(0, &mut st, 0, 1, k, m, u, || 1.0, 1e-12, &mut report, true)?;
        let (sn, cs) = st.q[0].sin_cos();
        // Exact to the rounding of q itself.
        let tol = 1e-15 + 2.0 * f64::EPSILON * st.q[0].abs();
        assert!((st.sc[0].0 - sn).abs() < tol && (st.sc[0].1 - cs).abs() < tol);
        Ok((st.q[0], st.q[1]))
    }

    #[test]
    fn slider_crank_like_blocks_on_both_sides() {
        // The shaper's ram: l4 e(q4) − sE (1, 0) = −K. Configurations on either side of the foot.
        for m in [(0.15, 0.0), (0.1, -0.07), (-0.2, 0.05)] {
            for u in [[-1.0, 0.0], [0.6, 0.8], [0.0, 2.5]] {
                for (q, s) in [(2.9, 0.1), (0.4, -0.3), (-1.2, 0.7)] {
                    let k = k_of(m, u, q, s);
                    let (q1, s1) = solve(k, m, u, q + 0.2).unwrap();
                    assert!(
                        (q1 - q).abs() < 1e-14 && (s1 - s).abs() < 1e-14,
                        "{m:?} {u:?}"
                    );
                    // The other mode: the mirror image of M e(q) in the perpendicular to u.
                    let (len, off) = (m.0.hypot(m.1), m.1.atan2(m.0));
                    let a = (len * (q + off).cos(), len * (q + off).sin());
                    let ul = u[0].hypot(u[1]);
                    let un = (u[0] / ul, u[1] / ul);
                    let along = a.0 * un.0 + a.1 * un.1;
                    let mirror = (a.0 - 2.0 * along * un.0, a.1 - 2.0 * along * un.1);
                    let q_other = mirror.1.atan2(mirror.0) - off;
                    let s_other = s + 2.0 * along / ul;
                    let modes = rrp_modes(0, k, m, u).unwrap();
                    assert_eq!(modes.len(), 2);
                    let found = modes.as_slice().iter().any(|md| {
                        angle_gap(md.values[0], q_other) < 1e-14
                            && (md.values[1] - s_other).abs() < 1e-14
                    });
                    assert!(found, "{m:?} {u:?} {q} {s}: {modes:?}");
                    let (q2, s2) = solve(k, m, u, q_other).unwrap();
                    assert!(angle_gap(q2, q_other) < 1e-14 && (s2 - s_other).abs() < 1e-14);
                }
            }
        }
    }

    #[test]
    fn whole_turns_are_kept() {
        let (m, u) = ((0.2, 0.0), [1.0, 0.0]);
        let k = k_of(m, u, 1.0, 0.3);
        let (q, s) = solve(k, m, u, 1.1 + 3.0 * TAU).unwrap();
        assert!((q - 1.0 - 3.0 * TAU).abs() < 1e-13 && (s - 0.3).abs() < 1e-15);
        let (q, _) = solve(k, m, u, 0.9 - 2.0 * TAU).unwrap();
        assert!((q - 1.0 + 2.0 * TAU).abs() < 1e-13);
    }

    #[test]
    fn near_at_and_past_the_dead_point() {
        // Unit circle, horizontal line y = 1 − δ: the chord's half is √(2δ − δ²).
        let (m, u) = ((1.0, 0.0), [1.0, 0.0]);
        let mut worst: f64 = 0.0;
        for nominal in [1e-2f64, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14] {
            // δ as the f64 data holds it (1 − (1 − δ) is exact).
            let y = 1.0 - nominal;
            let delta = 1.0 - y;
            let half = (delta * (1.0 + y)).sqrt();
            let (q, s) = solve([0.0, -y], m, u, FRAC_PI_2 - 0.1).unwrap();
            // A = (half, y) = e(q), s = −half.
            let scale = f64::EPSILON / delta.sqrt();
            let err = ((s + half).abs() / scale).max((q - y.atan2(half)).abs() / scale);
            assert!(err <= 4.0, "δ = {delta}: {q} {s}");
            worst = worst.max(err);
        }
        std::eprintln!("RRP: largest error near the dead point {worst:.2} ε/√δ");
        let (q, s) = solve([0.0, -1.0], m, u, 1.0).unwrap();
        assert!((q - FRAC_PI_2).abs() < 1e-15 && s.abs() < 1e-15);
        assert_eq!(rrp_modes(0, [0.0, -1.0], m, u).unwrap().len(), 1);
        match solve([0.0, -(1.0 + 1e-9)], m, u, 1.0) {
            Err(SolveError::Unassemblable { residual, .. }) => {
                assert!((residual - 1e-9).abs() < 1e-15, "{residual}")
            }
            other => panic!("{other:?}"),
        }
        assert!(rrp_modes(0, [0.0, -(1.0 + 1e-9)], m, u).unwrap().is_empty());
    }

    #[test]
    fn degenerate_and_non_finite_arguments_are_errors() {
        let singular = |r: Result<_, SolveError>| matches!(r, Err(SolveError::Singular { .. }));
        assert!(singular(solve([0.1, 0.2], (1.0, 0.0), [0.0, 0.0], 0.0)));
        assert!(singular(solve([0.1, 0.2], (0.0, 0.0), [1.0, 0.0], 0.0)));
        assert!(matches!(
            solve([f64::NAN, 0.2], (1.0, 0.0), [1.0, 0.0], 0.0),
            Err(SolveError::Overflow { .. })
        ));
        assert!(matches!(
            solve([0.1, 0.2], (1.0, 0.0), [1.0, 0.0], f64::INFINITY),
            Err(SolveError::NonFinite { index: 0, .. })
        ));
        assert!(matches!(
            solve([1e300, 1e300], (1e300, 0.0), [1e300, 0.0], 0.0),
            Err(SolveError::Overflow { .. })
        ));
    }
}
