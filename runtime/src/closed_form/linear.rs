//! Linear kernels (part of `closed_form`): two lengths in one loop, `K + s1 u1 + s2 u2 = 0`
//! (Cramer on the column-equilibrated 2×2, with the elimination's singularity test), and one
//! length in one equation, `K + a s = 0`. One solution each; a singular block is `Singular`.

use super::{Mode, Modes, all_finite};
use crate::error::{SolveError, Stage};
use crate::scalar::Real;
use crate::solve::{NewtonReport, TrigState};

fn singular(block: usize, pivot_ratio: f64) -> SolveError {
    SolveError::Singular {
        block,
        stage: Stage::Position,
        pivot_ratio,
    }
}

fn lengths<T: Real>(s: [T; 2]) -> Mode<T> {
    Mode {
        values: s,
        sc: [(T::zero(), T::one()); 2],
    }
}

/// `(s1, s2, pivot ratio)` of `K + s1 u1 + s2 u2 = 0`.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
fn cramer<T: Real>(
    block: usize,
    k: [T; 2],
    u1: [T; 2],
    u2: [T; 2],
) -> Result<(T, T, T), SolveError> {
    if !all_finite(&[k[0], k[1], u1[0], u1[1], u2[0], u2[1]]) {
        return Err(super::overflow(block));
    }
    // Column equilibration (as the elimination does): each column divided by its largest entry.
    let (m1, m2) = (u1[0].abs().max(u1[1].abs()), u2[0].abs().max(u2[1].abs()));
    if !(m1 > T::zero() && m2 > T::zero()) {
        return Err(singular(block, 0.0));
    }
    let (i1, i2) = (T::one() / m1, T::one() / m2);
    let (a, b) = ((u1[0] * i1, u1[1] * i1), (u2[0] * i2, u2[1] * i2));
    let det = a.0 * b.1 - a.1 * b.0;
    // The elimination's test: its pivots are 1 and |det| (after equilibration).
    if !(det.abs() > T::EPSILON * T::lit(2.0)) {
        return Err(singular(block, det.abs().to_f64()));
    }
    let d = (-k[0], -k[1]);
    let inv = T::one() / det;
    let s1 = (d.0 * b.1 - d.1 * b.0) * inv * i1;
    let s2 = (a.0 * d.1 - a.1 * d.0) * inv * i2;
    if !all_finite(&[s1, s2]) {
        return Err(super::overflow(block));
    }
    let r = det.abs();
    Ok((s1, s2, if r <= T::one() { r } else { T::one() / r }))
}

/// The one solution of `K + s1 u1 + s2 u2 = 0` (`values = [s1, s2]`), or `Singular`.
pub fn linear2_modes<T: Real>(
    block: usize,
    k: [T; 2],
    u1: [T; 2],
    u2: [T; 2],
) -> Result<Modes<T>, SolveError> {
    let (s1, s2, _) = cramer(block, k, u1, u2)?;
    let mut out = Modes::none();
    out.push(lengths([s1, s2]));
    Ok(out)
}

/// Solves `K + s1 u1 + s2 u2 = 0` for the lengths `st.q[a]`, `st.q[b]` (the guess is not
/// needed); `Singular` when `u1` and `u2` are parallel to working precision. The pivot ratio is
/// the elimination's.
#[inline]
pub fn solve_linear2<T: Real, const N: usize>(
    block: usize,
    st: &mut TrigState<T, N>,
    (a, b): (usize, usize),
    k: [T; 2],
    u1: [T; 2],
    u2: [T; 2],
    report: &mut NewtonReport<T>,
) -> Result<(), SolveError> {
    let (s1, s2, ratio) = cramer(block, k, u1, u2)?;
    st.q[a] = s1;
    st.q[b] = s2;
    if ratio < report.pivot_ratio {
        report.pivot_ratio = ratio;
    }
    Ok(())
}

#[inline(always)]
fn divide<T: Real>(block: usize, k: T, a: T) -> Result<T, SolveError> {
    if !all_finite(&[k, a]) {
        return Err(super::overflow(block));
    }
    if a == T::zero() {
        return Err(singular(block, 0.0));
    }
    let s = -k / a;
    if s.is_finite() {
        Ok(s)
    } else {
        Err(super::overflow(block))
    }
}

/// The one solution of `K + a s = 0` (`values[0]`), or `Singular` for `a = 0`.
pub fn length1_modes<T: Real>(block: usize, k: T, a: T) -> Result<Modes<T>, SolveError> {
    let s = divide(block, k, a)?;
    let mut out = Modes::none();
    out.push(lengths([s, T::zero()]));
    Ok(out)
}

/// Solves `K + a s = 0` for the length `st.q[s]`; `Singular` for `a = 0`. (The pivot ratio of a
/// 1×1 block is 1: the report is left as it is.)
#[inline(always)]
pub fn solve_length1<T: Real, const N: usize>(
    block: usize,
    st: &mut TrigState<T, N>,
    s: usize,
    k: T,
    a: T,
) -> Result<(), SolveError> {
    st.q[s] = divide(block, k, a)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_lengths_against_the_inverse_written_out() {
        // s = −U⁻¹ K with U⁻¹ = adj(U) / det(U), columns of mixed scale included.
        let cases = [
            ([1.0, 0.0], [0.0, 1.0]),
            ([0.6, 0.8], [-0.3, 2.0]),
            ([1e-6, 3e-7], [4e5, -1e6]),
        ];
        for (u1, u2) in cases {
            let k = [0.37, -1.9];
            let det = u1[0] * u2[1] - u2[0] * u1[1];
            let want = [
                -(u2[1] * k[0] - u2[0] * k[1]) / det,
                -(-u1[1] * k[0] + u1[0] * k[1]) / det,
            ];
            let mut st = TrigState::new([5.0, 7.0, 9.0], [false; 3]);
            let mut report = NewtonReport::new();
            solve_linear2(0, &mut st, (2, 0), k, u1, u2, &mut report).unwrap();
            for (got, w) in [(st.q[2], want[0]), (st.q[0], want[1])] {
                assert!((got - w).abs() <= 1e-14 * w.abs().max(1.0), "{got} vs {w}");
            }
            assert_eq!(st.q[1], 7.0);
            let m = linear2_modes(0, k, u1, u2).unwrap();
            assert_eq!(m.as_slice(), &[lengths([st.q[2], st.q[0]])]);
        }
    }

    #[test]
    fn parallel_columns_are_singular() {
        let mut st = TrigState::new([0.0, 0.0], [false; 2]);
        let mut report = NewtonReport::new();
        let r = solve_linear2(
            3,
            &mut st,
            (0, 1),
            [1.0, 1.0],
            [1.0, 2.0],
            [-2.0, -4.0],
            &mut report,
        );
        assert!(
            matches!(r, Err(SolveError::Singular { block: 3, .. })),
            "{r:?}"
        );
        let r = solve_linear2(
            0,
            &mut st,
            (0, 1),
            [1.0, 1.0],
            [0.0, 0.0],
            [1.0, 0.0],
            &mut report,
        );
        assert!(matches!(r, Err(SolveError::Singular { .. })));
        let r = solve_linear2(
            0,
            &mut st,
            (0, 1),
            [f64::NAN, 1.0],
            [1.0, 0.0],
            [0.0, 1.0],
            &mut report,
        );
        assert!(matches!(r, Err(SolveError::Overflow { .. })));
        assert_eq!(st.q, [0.0, 0.0]);
    }

    #[test]
    fn one_length() {
        let mut st = TrigState::new([1.0], [false]);
        solve_length1(0, &mut st, 0, 0.75, -0.5).unwrap();
        assert_eq!(st.q[0], 1.5);
        assert_eq!(
            length1_modes(0, 0.75, -0.5).unwrap().as_slice()[0].values[0],
            1.5
        );
        assert!(matches!(
            solve_length1(0, &mut st, 0, 0.75, 0.0),
            Err(SolveError::Singular { .. })
        ));
        assert!(matches!(
            solve_length1(0, &mut st, 0, 1e300, 1e-300),
            Err(SolveError::Overflow { .. })
        ));
        assert!(matches!(
            solve_length1(0, &mut st, 0, f64::INFINITY, 1.0),
            Err(SolveError::Overflow { .. })
        ));
        assert_eq!(st.q[0], 1.5);
    }
}
