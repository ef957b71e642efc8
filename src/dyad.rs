//! Closed-form position solve of a dyad block, called by generated code: `K + M_a e(q_a) +
//! M_b e(q_b) = 0` with `M = [[p, −r], [r, p]]` (see mechgen-codegen's `dyad` stage). Two circles
//! intersect; the assembly branch is the one on the guess's side, so a solve never jumps branch.

use crate::error::{SolveError, Stage};
use crate::scalar::Real;
use crate::solve::{NewtonReport, TrigState};

/// `M e` for `M = [[p, −r], [r, p]]` and `e = (cos, sin)`.
#[inline]
fn apply<T: Real>((p, r): (T, T), (c, s): (T, T)) -> (T, T) {
    (p * c - r * s, r * c + p * s)
}

/// `M⁻¹ v` for a rotation-scaling `M = [[p, −r], [r, p]]`.
#[inline]
fn unapply<T: Real>((p, r): (T, T), (x, y): (T, T)) -> (T, T) {
    let inv = T::one() / (p * p + r * r);
    ((p * x + r * y) * inv, (p * y - r * x) * inv)
}

/// Angle of `(c, s)` relative to `(cg, sg)`, in (−π, π]: a short series for the small turns of a
/// simulator step, `atan2` otherwise.
#[inline(always)]
fn turn<T: Real>((cg, sg): (T, T), (c, s): (T, T)) -> T {
    let sin = cg * s - sg * c;
    let cos = cg * c + sg * s;
    if cos > T::zero() && sin.abs() < T::lit(0.03) {
        // Both directions are unit vectors, so the turn is asin(sin): s + s³/6 + 3s⁵/40 + 5s⁷/112
        // + 35s⁹/1152 + 63s¹¹/2816 (truncation below 3e-22 for |s| < 0.03; no division).
        let s2 = sin * sin;
        let mut acc = T::lit(63.0 / 2816.0);
        for c in [35.0 / 1152.0, 5.0 / 112.0, 3.0 / 40.0, 1.0 / 6.0, 1.0] {
            acc = T::lit(c) + s2 * acc;
        }
        sin * acc
    } else {
        sin.atan2(cos)
    }
}

/// Solves the dyad block `block` with unknowns `a` and `b` in place. `k` is `K`, `ma` and `mb` the
/// `(p, r)` of `M_a` and `M_b`, all at the current state; `scale` the length scale. The guess in
/// `st` picks the branch. Past a dead point (the circles do not meet): `Unassemblable`. The new
/// angles are the guess's plus the turn to the solution (so whole turns are kept), unless the
/// guess is so large that f64 (or f32) cannot hold the answer to `tolerance` there: then the
/// principal value in (−π, π].
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
    scale: T,
    tolerance: T,
    report: &mut NewtonReport<T>,
) -> Result<(), SolveError> {
    let (ga, gb) = (st.sc[a], st.sc[b]);
    let (ea, eb) = ((ga.1, ga.0), (gb.1, gb.0));
    let (la, lb) = (
        (ma.0 * ma.0 + ma.1 * ma.1).sqrt(),
        (mb.0 * mb.0 + mb.1 * mb.1).sqrt(),
    );
    // A + B = d, |A| = la, |B| = lb.
    let d = (-k[0], -k[1]);
    let l = (d.0 * d.0 + d.1 * d.1).sqrt();
    let guess_a = apply(ma, ea);
    let inv_scale = T::one() / scale;
    if !(l.is_finite() && la.is_finite() && lb.is_finite() && guess_a.0.is_finite()) {
        return Err(SolveError::Unassemblable {
            block,
            residual: f64::INFINITY,
            iterations: 0,
        });
    }
    if !(l > T::zero() && la > T::zero() && lb > T::zero()) {
        return Err(SolveError::Singular {
            block,
            stage: Stage::Position,
            pivot_ratio: 0.0,
        });
    }
    // Heron: 16 area² of the triangle (la, lb, l), each factor exact to rounding near a dead point.
    let (f1, f2, f3) = (la + lb - l, l + la - lb, l + lb - la);
    let heron = (la + lb + l) * f1 * f2 * f3;
    let gap = (-f1).max(-f2).max(-f3);
    let rounding = T::EPSILON * T::lit(64.0) * (la + lb + l);
    if gap > rounding {
        return Err(SolveError::Unassemblable {
            block,
            residual: (gap * inv_scale).to_f64(),
            iterations: 0,
        });
    }
    let inv_l = T::one() / l;
    // la·cos φ and la·sin φ, φ the angle between d and A.
    let along = (la * la + l * l - lb * lb) * T::lit(0.5) * inv_l;
    let across = heron.max(T::zero()).sqrt() * T::lit(0.5) * inv_l;
    let u = (d.0 * inv_l, d.1 * inv_l);
    let n = (-u.1, u.0);
    // The branch on the guess's side of d.
    let side = if n.0 * guess_a.0 + n.1 * guess_a.1 < T::zero() {
        -T::one()
    } else {
        T::one()
    };
    let s = side * across;
    let big_a = (along * u.0 + s * n.0, along * u.1 + s * n.1);
    let big_b = (d.0 - big_a.0, d.1 - big_a.1);
    let (ca, sa) = unapply(ma, big_a);
    let (cb, sb) = unapply(mb, big_b);
    let near = |q: T, e: (T, T), (c, s): (T, T)| {
        let q_new = q + turn(e, (c, s));
        if T::EPSILON * q_new.abs() <= tolerance {
            q_new
        } else {
            s.atan2(c)
        }
    };
    let (qa, qb) = (near(st.q[a], ea, (ca, sa)), near(st.q[b], eb, (cb, sb)));
    if !(qa.is_finite() && qb.is_finite() && ca.is_finite() && sb.is_finite()) {
        return Err(SolveError::Unassemblable {
            block,
            residual: f64::INFINITY,
            iterations: 0,
        });
    }
    st.q[a] = qa;
    st.q[b] = qb;
    st.sc[a] = (sa, ca);
    st.sc[b] = (sb, cb);
    // The pivot ratio column-equilibrated elimination would find for J = [A⊥ B⊥].
    let (ja, jb) = ((-big_a.1, big_a.0), (-big_b.1, big_b.0));
    let (na, nb) = (ja.0.abs().max(ja.1.abs()), jb.0.abs().max(jb.1.abs()));
    let det = ((ja.0 * jb.1 - ja.1 * jb.0) / (na * nb)).abs();
    let ratio = if det <= T::one() { det } else { T::one() / det };
    // No iteration, and B = d − A closes the loop to rounding: nothing to add to the residual.
    report.pivot_ratio = report.pivot_ratio.min(ratio);
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
            1.0,
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
        assert!(q[0].abs() < 1e-15 && (q[1] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let q = reach((1.0, 1.0), 1.4, 0.1).unwrap();
        assert!((q[0] - std::f64::consts::FRAC_PI_2).abs() < 1e-15 && q[1].abs() < 1e-15);
        // Angles stay near the guess, whole turns included.
        let tau = std::f64::consts::TAU;
        let q = reach((1.0, 1.0), 0.1 + 3.0 * tau, 1.4 - tau).unwrap();
        assert!(
            (q[0] - 3.0 * tau).abs() < 1e-13
                && (q[1] - std::f64::consts::FRAC_PI_2 + tau).abs() < 1e-13
        );
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
}
