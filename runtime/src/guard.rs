//! The rule that keeps a step on its branch ([`BranchGuard`]): a predicted step may not move an
//! unknown too far, and the solution may not land far from the prediction (a jump to another
//! branch). The sweep's adaptive continuation checks its tangent steps with it, and a tick's
//! step is checked against the tick's own second-order prediction ([`crate::DynTick::tick_checked`]),
//! inside the engine's tick, with nothing copied out.

use alloc::vec::Vec;

use crate::info::{Kind, MechanismInfo};
use crate::scalar::Real;

/// Largest change of an unknown one step may make: this many radians for an angle, this fraction
/// of the mechanism's length scale (or of the largest current length unknown) for a length.
pub const MAX_STEP: f64 = 0.5;

/// The largest move of a solution away from its prediction, relative to the step's change of the
/// state ([`BranchGuard::jump`]), beyond which a step is taken for a jump to another branch.
pub const MAX_JUMP: f64 = 0.25;

/// The branch rule for one mechanism: its unknowns' kinds and its length scale.
#[derive(Clone, Debug, PartialEq)]
pub struct BranchGuard {
    /// Whether each unknown is a length (else an angle).
    length: Vec<bool>,
    any_length: bool,
    scale: f64,
}

impl BranchGuard {
    /// The guard for the mechanism `info` describes, lengths measured against `scale` (its
    /// largest length param).
    pub fn new(info: &MechanismInfo, scale: f64) -> BranchGuard {
        let length: Vec<bool> = info
            .unknowns
            .iter()
            .map(|u| u.kind == Kind::Length)
            .collect();
        BranchGuard {
            any_length: length.iter().any(|&l| l),
            length,
            scale,
        }
    }

    /// The largest change one step may make of each length unknown (angles: [`MAX_STEP`]): the
    /// length scale or the largest current length unknown, whichever is larger, so that a state
    /// whose lengths are all near zero is not a stop.
    fn length_limit<T: Real>(&self, q: &[T]) -> T {
        if !self.any_length {
            return T::lit(MAX_STEP);
        }
        let current = q
            .iter()
            .zip(&self.length)
            .filter(|(v, l)| **l && v.is_finite())
            .fold(T::zero(), |m, (v, _)| m.max(v.abs()));
        T::lit(MAX_STEP) * T::lit(self.scale).max(current)
    }

    /// Whether a predicted change of the unknowns from `before` to `predicted` is too far for one
    /// step (a NaN change is too far).
    pub fn too_far<T: Real>(&self, before: &[T], predicted: &[T]) -> bool {
        let length = self.length_limit(before);
        (0..predicted.len()).any(|i| {
            let limit = if self.length.get(i) == Some(&true) {
                length
            } else {
                T::lit(MAX_STEP)
            };
            let change = (predicted[i] - before[i]).abs();
            !change.is_finite() || change > limit
        })
    }

    /// How far a solution moved from its prediction, relative to the step's change of the state;
    /// 0 for a move below 1e-9 of the state's size (a converged Newton's corrections are tiny
    /// next to a branch flip).
    pub fn jump<T: Real>(predicted: &[T], corrected: &[T], before: &[T]) -> T {
        let (mut moved, mut scale, mut size) = (T::zero(), T::lit(1e-12), T::zero());
        for i in 0..predicted.len() {
            moved = moved.max((corrected[i] - predicted[i]).abs());
            scale = scale
                .max((predicted[i] - before[i]).abs())
                .max((corrected[i] - before[i]).abs());
            size = size.max(before[i].abs());
        }
        if moved < T::lit(1e-9) * (T::one() + size) {
            T::zero()
        } else {
            moved / scale
        }
    }

    /// Whether a tick's step stays on the branch: from `before` (rates `qd`, `qdd`, per unit of
    /// the tick's time) over the time `dt`, the tick's second-order prediction `p` and its
    /// solution `after` move no unknown too far ([`BranchGuard::too_far`]), and `after` stays near
    /// `p` ([`BranchGuard::jump`] at most [`MAX_JUMP`]). One pass, nothing stored.
    #[inline]
    pub fn keeps<T: Real>(&self, before: &[T], qd: &[T], qdd: &[T], dt: T, after: &[T]) -> bool {
        let n = after.len();
        if before.len() != n || qd.len() != n || qdd.len() != n || self.length.len() != n {
            return false;
        }
        let length = self.length_limit(before);
        let (mut moved, mut scale, mut size) = (T::zero(), T::lit(1e-12), T::zero());
        for k in 0..n {
            let p = before[k] + dt * (qd[k] + T::lit(0.5) * dt * qdd[k]);
            let (step, change) = ((p - before[k]).abs(), (after[k] - before[k]).abs());
            let limit = if self.length[k] {
                length
            } else {
                T::lit(MAX_STEP)
            };
            if !step.is_finite() || !change.is_finite() || step > limit || change > limit {
                return false;
            }
            moved = moved.max((after[k] - p).abs());
            scale = scale.max(step).max(change);
            size = size.max(before[k].abs());
        }
        moved < T::lit(1e-9) * (T::one() + size) || moved <= T::lit(MAX_JUMP) * scale
    }
}
