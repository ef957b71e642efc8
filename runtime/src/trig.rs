//! The unknowns' sines and cosines during a solve: Newton updates the unknowns through
//! [`NewtonState`], and [`TrigState`] keeps each angle's (sin, cos) in step by rotation, so the
//! generated solvers call `sin_cos` once per angle per solve.

use crate::scalar::Real;

/// What Newton updates: the unknowns, and whatever is kept in step with them.
pub trait NewtonState<T> {
    /// `q[k] -= dz`.
    fn apply(&mut self, k: usize, dz: T);
    /// `q[k]`.
    fn get(&self, k: usize) -> T;
}

impl<T: Real> NewtonState<T> for [T] {
    #[inline]
    fn apply(&mut self, k: usize, dz: T) {
        self[k] -= dz;
    }
    #[inline]
    fn get(&self, k: usize) -> T {
        self[k]
    }
}

impl<T: Real, const N: usize> NewtonState<T> for [T; N] {
    #[inline]
    fn apply(&mut self, k: usize, dz: T) {
        self[k] -= dz;
    }
    #[inline]
    fn get(&self, k: usize) -> T {
        self[k]
    }
}

/// The unknowns with the sine and cosine of each angle that appears in a sin or cos (`angle[k]`),
/// kept in step by rotation through each Newton step: no `sin_cos` call for a small step. The
/// generated solvers read their trigonometry from here.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrigState<T, const N: usize> {
    pub q: [T; N],
    /// (sin, cos) of `q[k]` where `angle[k]`; (0, 1) elsewhere.
    pub sc: [(T, T); N],
    angle: [bool; N],
}

impl<T: Real, const N: usize> TrigState<T, N> {
    #[inline]
    pub fn new(q: [T; N], angle: [bool; N]) -> Self {
        let mut sc = [(T::zero(), T::one()); N];
        for k in 0..N {
            if angle[k] {
                sc[k] = q[k].sin_cos();
            }
        }
        TrigState { q, sc, angle }
    }

    /// Sets unknown `k` to `value`, an angle's sine and cosine computed afresh.
    #[inline]
    pub fn set(&mut self, k: usize, value: T) {
        self.q[k] = value;
        if self.angle[k] {
            self.sc[k] = sin_cos_cold(value);
        }
    }

    /// From unknowns and sines and cosines already known (`sc[k]` = (sin, cos) of `q[k]` where
    /// `angle[k]`).
    #[inline]
    pub fn from_parts(q: [T; N], sc: [(T, T); N], angle: [bool; N]) -> Self {
        TrigState { q, sc, angle }
    }
}

impl<T: Real, const N: usize> NewtonState<T> for TrigState<T, N> {
    #[inline]
    fn apply(&mut self, k: usize, dz: T) {
        step(&mut self.q[k], &mut self.sc[k], self.angle[k], dz);
    }
    #[inline]
    fn get(&self, k: usize) -> T {
        self.q[k]
    }
}

/// One Newton step `q −= dz` of one unknown, an angle's sine and cosine kept in step: rotated by
/// the whole step, so they keep what the rounding of q drops near convergence (they, not q, enter
/// the residual), which helps most in f32 at a dead point. Only where q is too large to resolve a
/// milliradian is the rotation the change q actually took, so that they stay those of q.
#[inline]
fn step<T: Real>(q: &mut T, sc: &mut (T, T), angle: bool, dz: T) {
    let old = *q;
    *q -= dz;
    if angle {
        let turn = if T::EPSILON * old.abs() > T::lit(1e-3) {
            old - *q
        } else {
            dz
        };
        *sc = rotate(*sc, *q, turn);
    }
}

/// [`TrigState`] over borrowed slices of any length (the run-time engines' state): the same
/// steps, so an engine that reads its sines and cosines from `sc` computes what generated code
/// computes.
#[derive(Debug)]
pub struct TrigSlices<'a, T> {
    pub q: &'a mut [T],
    /// (sin, cos) of `q[k]` where `angle[k]`; (0, 1) elsewhere.
    pub sc: &'a mut [(T, T)],
    pub angle: &'a [bool],
}

impl<T: Real> TrigSlices<'_, T> {
    /// Every angle's sine and cosine afresh (as [`TrigState::new`]); (0, 1) elsewhere.
    #[inline]
    pub fn init(&mut self) {
        for ((q, sc), &angle) in self.q.iter().zip(self.sc.iter_mut()).zip(self.angle) {
            *sc = if angle {
                q.sin_cos()
            } else {
                (T::zero(), T::one())
            };
        }
    }

    /// Sets unknown `k` to `value`, an angle's sine and cosine computed afresh (as
    /// [`TrigState::set`]).
    #[inline]
    pub fn set(&mut self, k: usize, value: T) {
        self.q[k] = value;
        if self.angle[k] {
            self.sc[k] = sin_cos_cold(value);
        }
    }
}

impl<T: Real> NewtonState<T> for TrigSlices<'_, T> {
    #[inline]
    fn apply(&mut self, k: usize, dz: T) {
        step(&mut self.q[k], &mut self.sc[k], self.angle[k], dz);
    }
    #[inline]
    fn get(&self, k: usize) -> T {
        self.q[k]
    }
}

/// The largest turn [`rotate`] (and the lane and JIT ticks, which repeat it) takes by its
/// series; a larger one, or a NaN, is computed afresh.
pub const SERIES_TURN: f64 = 0.1;

/// (sin, cos) of `q − dz` from `(s, c)` = (sin q, cos q) and the new angle `q_new`: by the
/// addition theorem with Taylor series of `dz` when `|dz|` ≤ [`SERIES_TURN`] (sin to dz⁹, cos to dz¹⁰:
/// truncation below 3e-19), by `sin_cos(q_new)` otherwise.
// `!(a <= b)` is deliberate: a NaN step takes the `sin_cos` path.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
#[inline]
pub fn rotate<T: Real>((s, c): (T, T), q_new: T, dz: T) -> (T, T) {
    if !(dz.abs() <= T::lit(SERIES_TURN)) {
        return sin_cos_cold(q_new);
    }
    let (sd, cd) = turn_series(dz, T::lit);
    (s * cd - c * sd, c * cd + s * sd)
}

/// (sin dz, cos dz) by their Taylor series for a small turn `dz`: sin to dz⁹, cos to dz¹⁰, each
/// polynomial in dz² evaluated by Estrin's scheme (pairs of terms, then powers dz⁴ and dz⁸ of
/// it), whose longest chain of dependent operations is about half of Horner's: the rotation
/// of a tick's input is the first thing its solve waits for. For scalars and lanes alike (`lit`
/// makes a constant), so that both round alike.
#[inline(always)]
pub fn turn_series<V>(dz: V, lit: impl Fn(f64) -> V) -> (V, V)
where
    V: Copy + core::ops::Add<Output = V> + core::ops::Mul<Output = V>,
{
    let u = dz * dz;
    let (u2, pair) = (u * u, |a: f64, b: f64| lit(a) + u * lit(b));
    let u4 = u2 * u2;
    // 1 − u/3! + u²/5! − u³/7! + u⁴/9!
    let s =
        pair(1.0, -1.0 / 6.0) + u2 * pair(1.0 / 120.0, -1.0 / 5040.0) + u4 * lit(1.0 / 362880.0);
    // 1 − u/2! + u²/4! − u³/6! + u⁴/8! − u⁵/10!
    let c = pair(1.0, -0.5)
        + u2 * pair(1.0 / 24.0, -1.0 / 720.0)
        + u4 * pair(1.0 / 40320.0, -1.0 / 3628800.0);
    (dz * s, c)
}

/// atan(t) / t for a small `t` (|t| < 0.06: truncation below 5e-19 relative) from `u` = t²:
/// 1 − u/3 + u²/5 − u³/7 + u⁴/9 − u⁵/11 + u⁶/13, by Estrin's scheme as [`turn_series`] (a dyad's
/// turn waits for it). For scalars and lanes alike.
#[inline(always)]
pub fn atan_series<V>(u: V, lit: impl Fn(f64) -> V) -> V
where
    V: Copy + core::ops::Add<Output = V> + core::ops::Sub<Output = V> + core::ops::Mul<Output = V>,
{
    let pair = |a: f64, b: f64| lit(a) - u * lit(b);
    let u2 = u * u;
    let u4 = u2 * u2;
    pair(1.0, 1.0 / 3.0)
        + u2 * pair(1.0 / 5.0, 1.0 / 7.0)
        + u4 * (pair(1.0 / 9.0, 1.0 / 11.0) + u2 * lit(1.0 / 13.0))
}

/// `x.sin_cos()` behind a call the optimizer does not speculate. `sin` and `cos` are
/// speculatable intrinsics to LLVM, so `if rare { x.sin_cos() } else { cheap }` would otherwise
/// compile to both branches on every call (seen in the tick: a `sin_cos` per tick that was meant
/// for one tick in 64).
#[cold]
#[inline(never)]
pub fn sin_cos_cold<T: Real>(x: T) -> (T, T) {
    x.sin_cos()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_matches_sin_cos() {
        let mut worst = 0.0f64;
        for i in -200..=200 {
            let dz = f64::from(i) * 0.0005;
            for q in [0.3, -2.0, 5.0, 1e3] {
                // The step q actually took (exact), as Newton passes it.
                let q_new = q - dz;
                let (s, c) = rotate(q.sin_cos(), q_new, q - q_new);
                let (se, ce) = q_new.sin_cos();
                worst = worst.max((s - se).abs()).max((c - ce).abs());
            }
        }
        assert!(worst < 4e-16, "{worst:e}");
        // Beyond 0.1 rad: sin_cos of the new angle itself.
        assert_eq!(rotate((0.0, 1.0), 0.5, 0.2), 0.5f64.sin_cos());
    }
}
