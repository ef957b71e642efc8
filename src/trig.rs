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
}

impl<T: Real, const N: usize> NewtonState<T> for TrigState<T, N> {
    #[inline]
    fn apply(&mut self, k: usize, dz: T) {
        self.q[k] -= dz;
        if self.angle[k] {
            self.sc[k] = rotate(self.sc[k], self.q[k], dz);
        }
    }
    #[inline]
    fn get(&self, k: usize) -> T {
        self.q[k]
    }
}

/// (sin, cos) of `q − dz` from `(s, c)` = (sin q, cos q) and the new angle `q_new`: by the
/// addition theorem with a Taylor series of `dz` when the step is small (truncation below 1e-19),
/// by `sin_cos(q_new)` otherwise.
#[inline]
pub fn rotate<T: Real>((s, c): (T, T), q_new: T, dz: T) -> (T, T) {
    if dz.abs() > T::lit(0.03) {
        return q_new.sin_cos();
    }
    let d2 = dz * dz;
    let sd = dz
        * (T::one()
            - d2 * T::lit(1.0 / 6.0)
                * (T::one() - d2 * T::lit(1.0 / 20.0) * (T::one() - d2 * T::lit(1.0 / 42.0))));
    let cd = T::one()
        - d2 * T::lit(0.5)
            * (T::one()
                - d2 * T::lit(1.0 / 12.0)
                    * (T::one() - d2 * T::lit(1.0 / 30.0) * (T::one() - d2 * T::lit(1.0 / 56.0))));
    (s * cd - c * sd, c * cd + s * sd)
}
