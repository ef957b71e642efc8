//! RRR modes (part of `closed_form`): both assembly modes of a dyad `K + M_a e(q_a) + M_b e(q_b)
//! = 0`, for branch identification; the solve on the guess's side is `crate::dyad::solve_dyad`.
//! Two circles of radii `|M_a|`, `|M_b|` whose centres are `|K|` apart meet in two points (one
//! at a dead point: the links stretched out or folded, none past it).

use super::{Mode, Modes, all_finite, dead_point_slack, unapply};
use crate::error::{SolveError, Stage};
use crate::scalar::Real;

/// Both modes of the dyad (`ma`, `mb` the `(p, r)` of `M_a`, `M_b`): `values = [q_a, q_b]`, the
/// mode with `M_a e(q_a)` to the left of `d = −K` first.
pub fn rrr_modes<T: Real>(
    block: usize,
    k: [T; 2],
    ma: (T, T),
    mb: (T, T),
) -> Result<Modes<T>, SolveError> {
    if !all_finite(&[k[0], k[1], ma.0, ma.1, mb.0, mb.1]) {
        return Err(super::overflow(block));
    }
    let d = (-k[0], -k[1]);
    let (la2, lb2, l2) = (
        ma.0 * ma.0 + ma.1 * ma.1,
        mb.0 * mb.0 + mb.1 * mb.1,
        d.0 * d.0 + d.1 * d.1,
    );
    if !(la2 > T::zero() && lb2 > T::zero() && l2 > T::zero()) {
        return Err(SolveError::Singular {
            block,
            stage: Stage::Position,
            pivot_ratio: 0.0,
        });
    }
    if !(la2 + lb2 + l2).is_finite() {
        return Err(super::overflow(block));
    }
    let (la, lb, l) = (la2.sqrt(), lb2.sqrt(), l2.sqrt());
    // The triangle (la, lb, l): its height over d is √((l+la+lb)(−l+la+lb)(l−la+lb)(l+la−lb))
    // / (2l); each factor that can vanish is a sum or difference of three lengths, exact to
    // rounding near its dead point.
    let (stretched, folded_a, folded_b) = (la + lb - l, l - la + lb, l + la - lb);
    let slack = dead_point_slack::<T>() * (la + lb + l);
    let mut out = Modes::none();
    if stretched < -slack || folded_a < -slack || folded_b < -slack {
        return Ok(out);
    }
    let clamp = |x: T| if x > T::zero() { x } else { T::zero() };
    let area4 = (l + la + lb) * clamp(stretched) * clamp(folded_a) * clamp(folded_b);
    let inv_2l2 = T::lit(0.5) / l2;
    let along = (la2 + l2 - lb2) * inv_2l2;
    let across = area4.sqrt() * inv_2l2;
    let signs: &[T] = if across > T::zero() {
        &[T::one(), -T::one()]
    } else {
        &[T::one()]
    };
    for &sign in signs {
        let a = (
            along * d.0 - sign * across * d.1,
            along * d.1 + sign * across * d.0,
        );
        let (ca, sa) = unapply(ma, a);
        let (cb, sb) = unapply(mb, (d.0 - a.0, d.1 - a.1));
        if !all_finite(&[ca, sa, cb, sb]) {
            return Err(super::overflow(block));
        }
        out.push(Mode {
            values: [sa.atan2(ca), sb.atan2(cb)],
            sc: [(sa, ca), (sb, cb)],
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::super::test_util::angle_gap;
    use super::*;

    #[test]
    fn both_modes_of_a_four_bar_loop_against_the_law_of_cosines() {
        // Links 0.6 and 0.8 (the second with an angle offset) from the origin to d = (1, 0.2).
        let (ma, mb) = ((0.6, 0.0), (0.8 * 0.3f64.cos(), 0.8 * 0.3f64.sin()));
        let d: (f64, f64) = (1.0, 0.2);
        let l = d.0.hypot(d.1);
        // The angle at the origin between d and link a: cos = (la² + l² − lb²) / (2 la l).
        let gamma = ((0.36 + l * l - 0.64) / (2.0 * 0.6 * l)).acos();
        let modes = rrr_modes(0, [-d.0, -d.1], ma, mb).unwrap();
        assert_eq!(modes.len(), 2);
        for (m, sign) in modes.as_slice().iter().zip([1.0, -1.0]) {
            let qa = d.1.atan2(d.0) + sign * gamma;
            assert!(angle_gap(m.values[0], qa) < 1e-15, "{m:?} vs {qa}");
            // Link b closes the loop from the end of link a.
            let (ax, ay) = (0.6 * qa.cos(), 0.6 * qa.sin());
            let qb = (d.1 - ay).atan2(d.0 - ax) - 0.3;
            assert!(angle_gap(m.values[1], qb) < 1e-14, "{m:?} vs {qb}");
        }
    }

    #[test]
    fn dead_points_and_beyond() {
        let one = (1.0, 0.0);
        assert_eq!(rrr_modes(0, [-2.0, 0.0], one, one).unwrap().len(), 1);
        assert!(
            rrr_modes(0, [-2.0 - 1e-9, 0.0], one, one)
                .unwrap()
                .is_empty()
        );
        assert!(
            rrr_modes(0, [-0.5, 0.0], one, (3.0, 0.0))
                .unwrap()
                .is_empty()
        );
        let l: f64 = 2.0 - 1e-12;
        let near = rrr_modes(0, [-l, 0.0], one, one).unwrap();
        assert_eq!(near.len(), 2);
        // Half the angle between the links, θ = acos(l / 2), written with 2 − l (exact in f64)
        // as 2 asin √((2 − l) / 4): each factor of the area is exact here, so θ ≈ 1e-6 is good to
        // a few ε relative.
        let theta = 2.0 * ((2.0 - l) / 4.0).sqrt().asin();
        for m in near.as_slice() {
            assert!(
                (m.values[0].abs() - theta).abs() <= 4.0 * f64::EPSILON * theta,
                "{m:?} vs {theta}"
            );
        }
        assert!(matches!(
            rrr_modes(0, [0.0, 0.0], one, one),
            Err(SolveError::Singular { .. })
        ));
        assert!(matches!(
            rrr_modes(0, [f64::NAN, 0.0], one, one),
            Err(SolveError::Overflow { .. })
        ));
    }
}
