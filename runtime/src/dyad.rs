//! Closed-form position solve of a dyad block, called by generated code: `K + M_a e(q_a) +
//! M_b e(q_b) = 0` with `M = [[p, −r], [r, p]]` (see mechgen-codegen's `dyad` stage). Two circles
//! intersect; the assembly branch is the one on the guess's side, so a solve never jumps branch.

use crate::error::{SolveError, Stage};
use crate::scalar::Real;
use crate::solve::{NewtonReport, TrigState};
use crate::trig::atan_series;

/// `M e` for `M = [[p, −r], [r, p]]` and `e = (cos, sin)`.
#[inline]
fn apply<T: Real>((p, r): (T, T), (c, s): (T, T)) -> (T, T) {
    (p * c - r * s, r * c + p * s)
}

/// Angle of `(c, s)` relative to `(cg, sg)`, in (−π, π]: a short series for the turns of up to
/// about 7° a simulator step makes, `atan2` otherwise.
#[inline(always)]
fn turn<T: Real>((cg, sg): (T, T), (c, s): (T, T)) -> T {
    let sin = cg * s - sg * c;
    let cos = cg * c + sg * s;
    // Half the turn has tangent t = sin / (1 + cos) (both directions are unit vectors).
    if cos > T::lit(0.99) {
        let t = sin / (T::one() + cos);
        if t.abs() < T::lit(0.06) {
            // 2 atan t = 2 (t − t³/3 + t⁵/5 − … + t¹³/13): truncation below 5e-19 relative.
            return T::lit(2.0) * t * atan_series(t * t, T::lit);
        }
    }
    sin.atan2(cos)
}

/// [`near`] for both angles of a dyad, the common case (two small turns) written in lockstep so
/// that it compiles to paired arithmetic.
#[inline(always)]
fn near_pair<T: Real>(
    (qa, qb): (T, T),
    (ea, eb): ((T, T), (T, T)),
    (na, nb): ((T, T), (T, T)),
    tolerance: T,
) -> (T, T) {
    let (sin_a, sin_b) = (ea.0 * na.1 - ea.1 * na.0, eb.0 * nb.1 - eb.1 * nb.0);
    let (cos_a, cos_b) = (ea.0 * na.0 + ea.1 * na.1, eb.0 * nb.0 + eb.1 * nb.1);
    let (ta, tb) = (sin_a / (T::one() + cos_a), sin_b / (T::one() + cos_b));
    let lim = T::lit(0.06);
    if cos_a > T::lit(0.99) && cos_b > T::lit(0.99) && ta.abs() < lim && tb.abs() < lim {
        // As in `turn`.
        let (acc_a, acc_b) = (atan_series(ta * ta, T::lit), atan_series(tb * tb, T::lit));
        let two = T::lit(2.0);
        let (ra, rb) = (qa + two * ta * acc_a, qb + two * tb * acc_b);
        if T::EPSILON * (ra.abs() + rb.abs()) <= tolerance {
            return (ra, rb);
        }
    }
    (near(qa, ea, na, tolerance), near(qb, eb, nb, tolerance))
}

/// The angle of `(c, s)` nearest `q` (whose direction is `e`): `q` plus the turn, unless `q` is
/// so large that the precision cannot hold the answer to `tolerance` there, then the principal
/// value in (−π, π].
#[inline(always)]
pub(crate) fn near<T: Real>(q: T, e: (T, T), (c, s): (T, T), tolerance: T) -> T {
    let q_new = q + turn(e, (c, s));
    if T::EPSILON * q_new.abs() <= tolerance {
        q_new
    } else {
        s.atan2(c)
    }
}

/// Solves the dyad block `block` with unknowns `a` and `b` in place (see [`solve_dyad_angles`]).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn solve_dyad<T: Real, const N: usize>(
    block: usize,
    st: &mut TrigState<T, N>,
    a: usize,
    b: usize,
    k: [T; 2],
    ma: (T, T),
    mb: (T, T),
    scale: impl FnOnce() -> T,
    tolerance: T,
    report: &mut NewtonReport<T>,
) -> Result<(), SolveError> {
    solve_dyad_angles(
        block, st, a, b, k, ma, mb, scale, tolerance, report, [true; 2],
    )
}

/// Solves the dyad block `block` with unknowns `a` and `b` in place. `k` is `K`, `ma` and `mb` the
/// `(p, r)` of `M_a` and `M_b`, all at the current state; `scale` gives the length scale (asked
/// for only to report an error). The guess in
/// `st` picks the branch. Past a dead point (the circles do not meet): `Unassemblable`. The new
/// angles are the guess's plus the turn to the solution (so whole turns are kept), unless the
/// guess is so large that f64 (or f32) cannot hold the answer to `tolerance` there: then the
/// principal value in (−π, π].
///
/// `values[i]` says whether the caller reads angle `i` itself (`a`, then `b`); where it does
/// not, the angle is left as it was and only its sine and cosine are solved. Generated code
/// passes constants, so an angle nobody reads costs nothing: a scene whose outputs read only the
/// sines and cosines of a link (a point on it) skips the turn series (or `atan2`).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn solve_dyad_angles<T: Real, const N: usize>(
    block: usize,
    st: &mut TrigState<T, N>,
    a: usize,
    b: usize,
    k: [T; 2],
    ma: (T, T),
    mb: (T, T),
    scale: impl FnOnce() -> T,
    tolerance: T,
    report: &mut NewtonReport<T>,
    values: [bool; 2],
) -> Result<(), SolveError> {
    let (ga, gb) = (st.sc[a], st.sc[b]);
    let (ea, eb) = ((ga.1, ga.0), (gb.1, gb.0));
    // A link whose M has r = 0 (no angle offset; in generated code r is then the literal zero,
    // so these branches fold away) is a plain scaling: |M| = |p|, M⁻¹ v = v / p.
    let (pure_a, pure_b) = (ma.1 == T::zero(), mb.1 == T::zero());
    let len2 = |(p, r): (T, T), pure: bool| if pure { p * p } else { p * p + r * r };
    let (la2, lb2) = (len2(ma, pure_a), len2(mb, pure_b));
    let (la, lb) = (
        if pure_a { ma.0.abs() } else { la2.sqrt() },
        if pure_b { mb.0.abs() } else { lb2.sqrt() },
    );
    // A + B = d, |A| = la, |B| = lb. Everything on the way to A is written with |d|² (no square
    // root before the one of the area), so the dependency chain is short.
    let d = (-k[0], -k[1]);
    let l2 = d.0 * d.0 + d.1 * d.1;
    let guess_a = if pure_a {
        (ma.0 * ea.0, ma.0 * ea.1)
    } else {
        apply(ma, ea)
    };
    // One test for all three (each is a sum of squares, so none is negative).
    if !(l2 + la2 + lb2).is_finite() {
        return Err(SolveError::Overflow {
            block,
            stage: Stage::Position,
        });
    }
    if !(l2 > T::zero() && la2 > T::zero() && lb2 > T::zero()) {
        return Err(SolveError::Singular {
            block,
            stage: Stage::Position,
            pivot_ratio: 0.0,
        });
    }
    // Heron: 16 area² of the triangle (la, lb, |d|) = ((la + lb)² − |d|²)(|d|² − (la − lb)²); each
    // factor is exact to rounding near its dead point (stretched out or folded).
    let (far, folded) = ((la + lb) * (la + lb) - l2, l2 - (la - lb) * (la - lb));
    let heron = far * folded;
    // Rounding: 64 ε in length, times the other factor of each product at its dead point (at
    // most (la + lb)² and |la² − lb²|).
    let rounding = T::EPSILON * T::lit(256.0);
    if far < -rounding * (la + lb) * (la + lb) || folded < -rounding * (la2 - lb2).abs() {
        // How far apart the circles are, in length.
        let l = l2.sqrt();
        let gap = (l - la - lb).max((la - lb).abs() - l);
        return Err(SolveError::Unassemblable {
            block,
            residual: (gap / scale()).to_f64(),
            iterations: 0,
        });
    }
    let inv_2l2 = T::lit(0.5) / l2;
    // A = d (la² + |d|² − lb²) / (2|d|²) ± d⊥ √heron / (2|d|²).
    let along = (la2 + l2 - lb2) * inv_2l2;
    // (Rounding can leave heron just below zero at a dead point.)
    let across = if heron > T::zero() {
        heron.sqrt() * inv_2l2
    } else {
        T::zero()
    };
    let n = (-d.1, d.0);
    // The branch on the guess's side of d.
    let s = if n.0 * guess_a.0 + n.1 * guess_a.1 < T::zero() {
        -across
    } else {
        across
    };
    let big_a = (along * d.0 + s * n.0, along * d.1 + s * n.1);
    let big_b = (d.0 - big_a.0, d.1 - big_a.1);
    // e = M⁻¹ A with M⁻¹ = Mᵀ / |M|².
    let unapply = |(p, r): (T, T), pure: bool, (x, y): (T, T)| {
        if pure {
            let inv = T::one() / p;
            (x * inv, y * inv)
        } else {
            let inv = T::one() / (p * p + r * r);
            ((p * x + r * y) * inv, (p * y - r * x) * inv)
        }
    };
    let (ca, sa) = unapply(ma, pure_a, big_a);
    let (cb, sb) = unapply(mb, pure_b, big_b);
    // An angle not read stays as it was.
    let (value_a, value_b) = (values[0], values[1]);
    let (qa, qb) = match (value_a, value_b) {
        (true, true) => near_pair(
            (st.q[a], st.q[b]),
            (ea, eb),
            ((ca, sa), (cb, sb)),
            tolerance,
        ),
        (true, false) => (near(st.q[a], ea, (ca, sa), tolerance), st.q[b]),
        (false, true) => (st.q[a], near(st.q[b], eb, (cb, sb), tolerance)),
        (false, false) => (st.q[a], st.q[b]),
    };
    // The sines and cosines are at most 1 and the angles below tolerance / ε: the sum cannot
    // overflow, so it is finite exactly when all four are.
    if !(qa + qb + ca + sb).is_finite() {
        return Err(SolveError::Overflow {
            block,
            stage: Stage::Position,
        });
    }
    st.q[a] = qa;
    st.q[b] = qb;
    st.sc[a] = (sa, ca);
    st.sc[b] = (sb, cb);
    // The condition of J = [A⊥ B⊥]: |A × B| / (|A| |B|), the sine of the angle between the two
    // links (within a factor 2 of the pivot ratio of column-equilibrated elimination).
    let ratio = (big_a.0 * big_b.1 - big_a.1 * big_b.0).abs() / (la * lb);
    // No iteration, and B = d − A closes the loop to rounding: nothing to add to the residual.
    if ratio < report.pivot_ratio {
        report.pivot_ratio = ratio;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit links from the origin reaching `d`; guess angles `(ga, gb)`.
    fn reach(d: (f64, f64), ga: f64, gb: f64) -> Result<[f64; 2], SolveError> {
        let mut st = TrigState::new([ga, gb], [true, true]);
        let mut report = NewtonReport::new();
        let one = (1.0, 0.0);
        solve_dyad(
            0,
            &mut st,
            0,
            1,
            [-d.0, -d.1],
            one,
            one,
            || 1.0,
            1e-12,
            &mut report,
        )?;
        for k in 0..2 {
            let (s, c) = st.q[k].sin_cos();
            assert!((st.sc[k].0 - s).abs() < 1e-15 && (st.sc[k].1 - c).abs() < 1e-15);
        }
        Ok(st.q)
    }

    #[test]
    fn the_branch_on_the_guess_side() {
        let q = reach((1.0, 1.0), 0.1, 1.4).unwrap();
        assert!(q[0].abs() < 1e-15 && (q[1] - core::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let q = reach((1.0, 1.0), 1.4, 0.1).unwrap();
        assert!((q[0] - core::f64::consts::FRAC_PI_2).abs() < 1e-15 && q[1].abs() < 1e-15);
        // Angles stay near the guess, whole turns included.
        let tau = core::f64::consts::TAU;
        let q = reach((1.0, 1.0), 0.1 + 3.0 * tau, 1.4 - tau).unwrap();
        assert!(
            (q[0] - 3.0 * tau).abs() < 1e-13
                && (q[1] - core::f64::consts::FRAC_PI_2 + tau).abs() < 1e-13
        );
    }

    #[test]
    fn links_with_angle_offsets_close_the_loop() {
        // M = [[p, −r], [r, p]]: a link of length |(p, r)| at an offset atan2(r, p) from its
        // angle; both the offset and the plain-scaling (r = 0) forms, in every combination.
        let links = [(0.6, 0.8), (-1.3, 0.0), (0.9, -0.4), (1.1, 0.0)];
        for ma in links {
            for mb in links {
                let k = [-0.7, -1.1];
                for guess in [(0.2, 2.0), (2.0, 0.2)] {
                    let mut st = TrigState::new([guess.0, guess.1], [true, true]);
                    let mut report = NewtonReport::new();
                    solve_dyad(0, &mut st, 0, 1, k, ma, mb, || 1.0, 1e-12, &mut report)
                        .expect("assembles");
                    let (a, b) = (
                        apply(ma, (st.sc[0].1, st.sc[0].0)),
                        apply(mb, (st.sc[1].1, st.sc[1].0)),
                    );
                    let r = (k[0] + a.0 + b.0, k[1] + a.1 + b.1);
                    assert!(
                        r.0.abs() < 1e-15 && r.1.abs() < 1e-15,
                        "{ma:?} {mb:?}: {r:?}"
                    );
                    for i in 0..2 {
                        let (s, c) = st.q[i].sin_cos();
                        assert!((st.sc[i].0 - s).abs() < 1e-15 && (st.sc[i].1 - c).abs() < 1e-15);
                    }
                    assert!(report.pivot_ratio > 0.0 && report.pivot_ratio <= 1.0);
                }
            }
        }
    }

    #[test]
    fn past_and_at_the_dead_point() {
        assert!(matches!(
            reach((2.0 + 1e-9, 0.0), 0.1, -0.1),
            Err(SolveError::Unassemblable { .. })
        ));
        let q = reach((2.0, 0.0), 0.1, -0.1).unwrap();
        assert!(q[0].abs() < 1e-7 && q[1].abs() < 1e-7, "{q:?}");
        assert!(matches!(
            reach((0.0, 0.0), 0.1, -0.1),
            Err(SolveError::Singular { .. })
        ));
    }

    #[test]
    fn an_angle_not_read_is_left_as_it_was() {
        // Every combination gives the full solve's sines and cosines, and its angles where
        // they are read; the others keep the guess.
        let (k, ma, mb) = ([-0.7, -1.1], (0.6, 0.8), (1.1, 0.0));
        let guess = TrigState::new([0.2, 2.0], [true, true]);
        let solve = |values: [bool; 2]| {
            let mut st = guess;
            let mut report = NewtonReport::new();
            solve_dyad_angles(
                0,
                &mut st,
                0,
                1,
                k,
                ma,
                mb,
                || 1.0,
                1e-12,
                &mut report,
                values,
            )
            .expect("assembles");
            st
        };
        let full = solve([true; 2]);
        for values in [[false, false], [true, false], [false, true]] {
            let st = solve(values);
            assert_eq!(st.sc, full.sc);
            for i in 0..2 {
                let expect = if values[i] { full.q[i] } else { guess.q[i] };
                assert_eq!(st.q[i], expect, "{values:?}");
            }
        }
    }
}
