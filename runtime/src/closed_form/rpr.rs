//! RPR kernel (part of `closed_form`): an angle q and a length s along q's own direction, with or
//! without a perpendicular offset (a slotted guide, the shaper's CB, an offset slot
//! `s e(q) + h e(q + π/2)`): `K + (M + s N) e(q) = 0`, with `M` and `N ≠ 0` rotation-scalings.
//! As complex numbers, `(s + a + i b) e^{iq} = g` with `g = −K / N` and `a + i b = M / N`: the
//! slider's offset point lies on the circle `|g|` about the pivot, on the guide's tangent line at
//! distance `|b|`. Two modes (`s + a = ±√(|g|² − b²)`); the dead point is `|g| = |b|` (the slot
//! through the pivot when `b = 0`: then `g = 0` leaves q free, `Singular`).

use super::{Modes, all_finite, angle_length, dead_point_slack};
use crate::error::{SolveError, Stage};
use crate::scalar::Real;
use crate::solve::{NewtonReport, TrigState};

/// The block reduced to the guide's frame.
struct Guide<T> {
    /// `g = −K / N`, `|g|²`, `|g|`.
    g: (T, T),
    g2: T,
    r: T,
    /// `M / N = a + i b`.
    a: T,
    b: T,
    /// `√(|g|² − b²) ≥ 0` (0 at the dead point).
    t: T,
}

/// The guide frame, or `Err(gap)` (in length) past the dead point; `Singular` for `N = 0` or
/// `g = 0 = b`; the overflow error for non-finite coefficients.
// `!(a > b)` is deliberate: a NaN must fail the test.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
#[allow(clippy::type_complexity)]
#[inline(always)]
fn guide<T: Real>(
    block: usize,
    k: [T; 2],
    m: (T, T),
    n: (T, T),
) -> Result<Result<Guide<T>, T>, SolveError> {
    if !all_finite(&[k[0], k[1], m.0, m.1, n.0, n.1]) {
        return Err(super::overflow(block));
    }
    let singular = Err(SolveError::Singular {
        block,
        stage: Stage::Position,
        pivot_ratio: 0.0,
    });
    let nn = n.0 * n.0 + n.1 * n.1;
    if !(nn > T::zero()) {
        return singular;
    }
    let inv = T::one() / nn;
    let d = (-k[0], -k[1]);
    // x / N = x conj(N) / |N|².
    let over_n = |(x, y): (T, T)| ((x * n.0 + y * n.1) * inv, (y * n.0 - x * n.1) * inv);
    let (g, (a, b)) = (over_n(d), over_n(m));
    let g2 = g.0 * g.0 + g.1 * g.1;
    if !(g2 + a * a + b * b).is_finite() {
        return Err(super::overflow(block));
    }
    let r = g2.sqrt();
    let bb = b.abs();
    // √(|g|² − b²) as √((|g| − |b|)(|g| + |b|)): the vanishing factor is a difference of two
    // lengths exact to rounding, so t is good to ε/√δ at the dead point.
    let near = r - bb;
    if near < -dead_point_slack::<T>() * bb {
        return Ok(Err((bb - r) * nn.sqrt()));
    }
    if !(g2 > T::zero()) {
        // The slot through the pivot (b = 0 within rounding): every q solves.
        return singular;
    }
    let t = if near > T::zero() {
        (near * (r + bb)).sqrt()
    } else {
        T::zero()
    };
    Ok(Ok(Guide { g, g2, r, a, b, t }))
}

impl<T: Real> Guide<T> {
    /// Mode `tau` (±1: the sign of `s + a`): `e(q) = g (x − i b) / |g|²` with `x = tau t`, and s.
    #[inline(always)]
    fn mode(&self, tau: T) -> ((T, T), T) {
        let x = tau * self.t;
        let inv = T::one() / self.g2;
        let e = (
            (self.g.0 * x + self.g.1 * self.b) * inv,
            (self.g.1 * x - self.g.0 * self.b) * inv,
        );
        (e, x - self.a)
    }
}

/// Both modes of `K + (M + s N) e(q) = 0` (`m`, `n` the `(p, r)` of `M`, `N`): `s + a ≥ 0` first;
/// one at the dead point, none past it.
pub fn rpr_modes<T: Real>(
    block: usize,
    k: [T; 2],
    m: (T, T),
    n: (T, T),
) -> Result<Modes<T>, SolveError> {
    let mut out = Modes::none();
    if let Ok(gd) = guide(block, k, m, n)? {
        let taus: &[T] = if gd.t > T::zero() {
            &[T::one(), -T::one()]
        } else {
            &[T::one()]
        };
        for &tau in taus {
            let (e, s) = gd.mode(tau);
            if !all_finite(&[e.0, e.1, s]) {
                return Err(super::overflow(block));
            }
            out.push(angle_length(e, s));
        }
    }
    Ok(out)
}

/// Solves the RPR block `K + (M + s N) e(q) = 0` in place: `q` and `s` index `st`, whose angle
/// `q` (with its sine and cosine) picks the mode: the side of the pivot the offset point lies on
/// along the guide at the guessed angle (the sign of `Re(g e^{−iq})`). `scale` gives the length
/// scale (asked for only to report an error). Past the dead point: `Unassemblable` with the
/// relative gap; a non-finite guess of `q`: `NonFinite`. The pivot ratio reported is the cosine
/// between the guide and the pivot-to-slider line, `|s + a| / |g|`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn solve_rpr<T: Real, const N: usize>(
    block: usize,
    st: &mut TrigState<T, N>,
    q: usize,
    s: usize,
    k: [T; 2],
    m: (T, T),
    n: (T, T),
    scale: impl FnOnce() -> T,
    tolerance: T,
    report: &mut NewtonReport<T>,
    value: bool,
) -> Result<(), SolveError> {
    super::check_guess(st, q)?;
    let gd = super::closes(block, guide(block, k, m, n)?, scale)?;
    let (sg, cg) = st.sc[q];
    let tau = super::side(gd.g.0 * cg + gd.g.1 * sg);
    let (e, len) = gd.mode(tau);
    if !all_finite(&[e.0, e.1, len]) {
        return Err(super::overflow(block));
    }
    super::set_angle(st, q, e, tolerance, value);
    st.q[s] = len;
    let ratio = gd.t / gd.r;
    if ratio < report.pivot_ratio {
        report.pivot_ratio = ratio;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::test_util::angle_gap;
    use super::*;
    use std::f64::consts::TAU;

    /// `K` of (q, s) for a guide at the angle `alpha` from q whose slider sits `p0` along and `h`
    /// across it: `−((s + p0) e(q + α) + h e(q + α + π/2))`, i.e. `N = e(α)`, `M = (p0 + i h) e(α)`.
    fn k_of(alpha: f64, p0: f64, h: f64, q: f64, s: f64) -> [f64; 2] {
        let along = s + p0;
        let (c, sn) = ((q + alpha).cos(), (q + alpha).sin());
        [-(along * c - h * sn), -(along * sn + h * c)]
    }

    fn mn(alpha: f64, p0: f64, h: f64) -> ((f64, f64), (f64, f64)) {
        let n = (alpha.cos(), alpha.sin());
        ((p0 * n.0 - h * n.1, p0 * n.1 + h * n.0), n)
    }

    fn solve(
        k: [f64; 2],
        m: (f64, f64),
        n: (f64, f64),
        guess: f64,
    ) -> Result<(f64, f64), SolveError> {
        let mut st = TrigState::new([0.0, guess], [false, true]);
        let mut report = NewtonReport::new();
        solve_rpr(0, &mut st, 1, 0, k, m, n, || 1.0, 1e-12, &mut report, true)?;
        let (sn, cs) = st.q[1].sin_cos();
        // Exact to the rounding of q itself.
        let tol = 1e-15 + 2.0 * f64::EPSILON * st.q[1].abs();
        assert!((st.sc[1].0 - sn).abs() < tol && (st.sc[1].1 - cs).abs() < tol);
        assert!(report.pivot_ratio >= 0.0 && report.pivot_ratio <= 1.0);
        Ok((st.q[1], st.q[0]))
    }

    #[test]
    fn slots_with_and_without_offsets_on_both_sides() {
        for (alpha, p0, h) in [
            (0.0, 0.0, 0.0),
            (0.0, 0.0, 0.05),
            (0.4, 0.1, -0.07),
            (-2.0, -0.2, 0.3),
        ] {
            let (m, n) = mn(alpha, p0, h);
            for (q, s) in [(1.1, 0.3), (-2.5, 0.8), (0.3, -0.6)] {
                let k = k_of(alpha, p0, h, q, s);
                let (q1, s1) = solve(k, m, n, q - 0.3).unwrap();
                assert!(
                    angle_gap(q1, q) < 1e-14 && (s1 - s).abs() < 1e-14,
                    "{alpha} {h}: {q1} {s1}"
                );
                // The other mode: x = s + p0 → −x, the guide turned so that it still passes at h.
                let x = s + p0;
                let q_other = q + h.atan2(x) - h.atan2(-x);
                let s_other = -x - p0;
                let (q2, s2) = solve(k, m, n, q_other + 0.1).unwrap();
                assert!(angle_gap(q2, q_other) < 1e-14 && (s2 - s_other).abs() < 1e-14);
                let modes = rpr_modes(0, k, m, n).unwrap();
                assert_eq!(modes.len(), 2);
                for (qq, ss) in [(q, s), (q_other, s_other)] {
                    assert!(
                        modes
                            .as_slice()
                            .iter()
                            .any(|md| angle_gap(md.values[0], qq) < 1e-14
                                && (md.values[1] - ss).abs() < 1e-14)
                    );
                }
            }
        }
    }

    #[test]
    fn whole_turns_are_kept() {
        let (m, n) = mn(0.0, 0.0, 0.0);
        let k = k_of(0.0, 0.0, 0.0, 1.2, 0.3);
        let (q, s) = solve(k, m, n, 1.0 - 4.0 * TAU).unwrap();
        assert!((q - 1.2 + 4.0 * TAU).abs() < 1e-13 && (s - 0.3).abs() < 1e-15);
    }

    #[test]
    fn near_at_and_past_the_dead_point() {
        // Offset h = 1, pivot-to-slider (t, 1) at q = 0: s = t exactly, |g| − |b| ≈ t²/2.
        let (m, n) = mn(0.0, 0.0, 1.0);
        let mut worst: f64 = 0.0;
        for t in [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7] {
            let (q, s) = solve([-t, -1.0], m, n, 0.05).unwrap();
            // δ = |g| − |b| ≈ t²/2: ε/√δ ≈ √2 ε / t.
            let scale = f64::EPSILON * 2f64.sqrt() / t;
            let err = (s - t).abs().max(q.abs()) / scale;
            assert!(err <= 4.0, "t = {t}: {q} {s}");
            worst = worst.max(err);
        }
        std::eprintln!("RPR: largest error near the dead point {worst:.2} ε/√δ");
        let (q, s) = solve([0.0, -1.0], m, n, 0.05).unwrap();
        assert!(q.abs() < 1e-15 && s.abs() < 1e-15);
        assert_eq!(rpr_modes(0, [0.0, -1.0], m, n).unwrap().len(), 1);
        match solve([0.0, -(1.0 - 1e-9)], m, n, 0.0) {
            Err(SolveError::Unassemblable { residual, .. }) => {
                assert!((residual - 1e-9).abs() < 1e-15, "{residual}")
            }
            other => panic!("{other:?}"),
        }
        assert!(rpr_modes(0, [0.0, -(1.0 - 1e-9)], m, n).unwrap().is_empty());
        // No offset: the slot through the pivot leaves q free.
        let (m0, n0) = mn(0.0, 0.0, 0.0);
        assert!(matches!(
            solve([0.0, 0.0], m0, n0, 0.3),
            Err(SolveError::Singular { .. })
        ));
    }

    #[test]
    fn degenerate_and_non_finite_arguments_are_errors() {
        assert!(matches!(
            solve([0.1, 0.2], (1.0, 0.0), (0.0, 0.0), 0.0),
            Err(SolveError::Singular { .. })
        ));
        assert!(matches!(
            solve([0.1, f64::INFINITY], (1.0, 0.0), (1.0, 0.0), 0.0),
            Err(SolveError::Overflow { .. })
        ));
        assert!(matches!(
            solve([0.1, 0.2], (0.0, 0.0), (1.0, 0.0), f64::NAN),
            Err(SolveError::NonFinite { index: 1, .. })
        ));
    }
}
