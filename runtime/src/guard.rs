//! The rule that keeps a step on its branch ([`BranchGuard`]): a predicted step may not move an
//! unknown too far, and the solution may not land far from the prediction (a jump to another
//! branch). The sweep's adaptive continuation checks its tangent steps with it, and a tick's
//! step is checked against the tick's own second-order prediction ([`crate::DynTick::tick_checked`]),
//! inside the engine's tick, with nothing copied out.

use alloc::vec::Vec;

use crate::info::{Kind, MechanismInfo};
use crate::scalar::Real;
use crate::simd::Lanes;

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
    /// `p` ([`BranchGuard::jump`] at most [`MAX_JUMP`]). One pass, nothing stored. Inlined
    /// into each tick's `tick_checked`, where the unknowns' count is the mechanism's own (its
    /// loop unrolled).
    #[inline(always)]
    pub fn keeps<T: Real>(&self, before: &[T], qd: &[T], qdd: &[T], dt: T, after: &[T]) -> bool {
        let n = after.len();
        if before.len() != n || qd.len() != n || qdd.len() != n || self.length.len() != n {
            return false;
        }
        // Without length unknowns every limit is an angle's: no choice per unknown.
        if !self.any_length {
            return keeps_within(|_| T::lit(MAX_STEP), before, qd, qdd, dt, after);
        }
        let length = finite_limit(self.length_limit(before));
        let limit = |k: usize| {
            if self.length[k] {
                length
            } else {
                T::lit(MAX_STEP)
            }
        };
        keeps_within(limit, before, qd, qdd, dt, after)
    }

    /// [`BranchGuard::keeps`] of `[before, qd, qdd, after]` for an engine whose unknowns' count is
    /// known only at run time (the generic engine's tick): a count up to eight runs as a constant,
    /// so that the loop unrolls as in a generated tick's; the same operations, the same answer.
    #[inline(always)]
    pub fn keeps_any<T: Real>(&self, s: [&[T]; 4], dt: T) -> bool {
        let unrolled = match s[3].len() {
            1 => self.keeps_n::<T, 1>(s, dt),
            2 => self.keeps_n::<T, 2>(s, dt),
            3 => self.keeps_n::<T, 3>(s, dt),
            4 => self.keeps_n::<T, 4>(s, dt),
            5 => self.keeps_n::<T, 5>(s, dt),
            6 => self.keeps_n::<T, 6>(s, dt),
            7 => self.keeps_n::<T, 7>(s, dt),
            8 => self.keeps_n::<T, 8>(s, dt),
            _ => None,
        };
        let [before, qd, qdd, after] = s;
        unrolled.unwrap_or_else(|| self.keeps(before, qd, qdd, dt, after))
    }

    /// [`BranchGuard::keeps`] on arrays of `N` (`None` when a slice is not `N` long).
    #[inline(always)]
    fn keeps_n<T: Real, const N: usize>(&self, s: [&[T]; 4], dt: T) -> Option<bool> {
        let [before, qd, qdd, after] = s.map(<&[T; N]>::try_from);
        Some(self.keeps(before.ok()?, qd.ok()?, qdd.ok()?, dt, after.ok()?))
    }

    /// The length scale lengths are measured against.
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// Whether `other` is this rule for another length scale (the same unknowns' kinds).
    pub fn same_kinds(&self, other: &BranchGuard) -> bool {
        self.length == other.length
    }

    /// [`BranchGuard::keeps`] for W steps at once, one per lane, lane `i` under this rule with
    /// the length scale of lane `i` of `scale` (the same operations in the same order, so the
    /// same answer for each lane as `keeps` of the guard with that scale on that lane's
    /// numbers): the bits of the lanes whose step stays on the branch.
    #[inline(always)]
    pub fn keeps_lanes<L: Lanes>(
        &self,
        scale: L,
        before: &[L],
        qd: &[L],
        qdd: &[L],
        dt: L::Scalar,
        after: &[L],
    ) -> u32 {
        let n = after.len();
        if before.len() != n || qd.len() != n || qdd.len() != n || self.length.len() != n {
            return 0;
        }
        let max = |a: L, b: L| L::select(a.lt(b), b, a);
        let length = if self.any_length {
            let mut current = L::zero();
            for (v, _) in before.iter().zip(&self.length).filter(|(_, l)| **l) {
                current = L::select(v.is_finite(), max(current, v.abs()), current);
            }
            // As `finite_limit`: no larger than the largest finite number.
            let limit = L::lit(MAX_STEP) * max(scale, current);
            let largest = L::splat(<L::Scalar as Real>::MAX);
            L::select(limit.gt(largest), largest, limit)
        } else {
            L::lit(MAX_STEP)
        };
        let (dt, half) = (L::splat(dt), L::lit(0.5));
        let (mut moved, mut spread, mut size) = (L::zero(), L::lit(1e-12), L::zero());
        let mut good = L::all_bits();
        for k in 0..n {
            let p = before[k] + dt * (qd[k] + half * dt * qdd[k]);
            let (step, change) = ((p - before[k]).abs(), (after[k] - before[k]).abs());
            let limit = if self.length[k] {
                length
            } else {
                L::lit(MAX_STEP)
            };
            // A NaN or an infinite step or change is not below the finite limit.
            let ok = step.le(limit) & change.le(limit);
            good &= L::bits(ok);
            moved = max(moved, (after[k] - p).abs());
            spread = max(spread, max(step, change));
            size = max(size, before[k].abs());
        }
        let near = moved.lt(L::lit(1e-9) * (L::one() + size)) | moved.le(L::lit(MAX_JUMP) * spread);
        good & L::bits(near)
    }
}

/// A limit that is a finite number: `step <= limit` then fails for a step that is not finite
/// (NaN or infinite), so no step needs a test of its own. An infinite limit (a length scale
/// that is) becomes the largest finite number, which every finite step stays below, as it did
/// below infinity (a NaN limit, which no step is below, stays).
#[inline(always)]
fn finite_limit<T: Real>(limit: T) -> T {
    if limit > T::MAX { T::MAX } else { limit }
}

/// [`BranchGuard::keeps`] on slices of one length, unknown `k`'s limit `limit(k)` (finite).
#[inline(always)]
fn keeps_within<T: Real>(
    limit: impl Fn(usize) -> T,
    before: &[T],
    qd: &[T],
    qdd: &[T],
    dt: T,
    after: &[T],
) -> bool {
    let (mut moved, mut scale, mut size) = (T::zero(), T::lit(1e-12), T::zero());
    // Every unknown checked, without a branch per unknown (as in the lanes): the answer is false
    // if any is not finite or moves too far, whatever the sums below then hold.
    let mut good = true;
    for k in 0..after.len() {
        let p = before[k] + dt * (qd[k] + T::lit(0.5) * dt * qdd[k]);
        let (step, change) = ((p - before[k]).abs(), (after[k] - before[k]).abs());
        // A NaN or an infinite step or change is not below the finite limit.
        let limit = limit(k);
        good &= (step <= limit) & (change <= limit);
        // Where every number is finite (a NaN or infinite `before`, `p` or `after` makes `step`
        // or `change` so, and `good` false), a plain comparison is the largest.
        let larger = |a: T, b: T| if a < b { b } else { a };
        moved = larger(moved, (after[k] - p).abs());
        // The step's larger part first: one comparison a step on the chain carried from step
        // to step (on finite numbers, the order of the largest is no matter).
        scale = larger(scale, larger(step, change));
        size = larger(size, before[k].abs());
    }
    good & (moved < T::lit(1e-9) * (T::one() + size) || moved <= T::lit(MAX_JUMP) * scale)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::info::CoordDesc;
    use crate::simd::Vf64;
    use alloc::string::String;

    /// `keeps_lanes` answers as `keeps` on each lane, and `keeps` as its definition (neither
    /// step too far, `too_far`, and no jump, `jump`): steps of every size around the limits, a
    /// jump off the prediction, a NaN or infinite solution, an infinite length scale, lengths
    /// and angles, each lane its scale; and on a mechanism of angles alone.
    #[test]
    fn lanes_keep_what_each_lane_keeps() {
        let unknown = |name: &str, kind| CoordDesc {
            name: name.into(),
            kind,
            start: 0.0,
        };
        for second in [Kind::Length, Kind::Angle] {
            keeps_as_defined(unknown("a", Kind::Angle), unknown("s", second));
        }
    }

    /// A mechanism of these unknowns and nothing else.
    fn with_unknowns(unknowns: Vec<CoordDesc>) -> MechanismInfo {
        MechanismInfo {
            name: "test".into(),
            description: String::new(),
            inputs: Vec::new(),
            unknowns,
            params: Vec::new(),
            points: Vec::new(),
            blocks: Vec::new(),
            closed: Vec::new(),
            bodies: Vec::new(),
        }
    }

    /// Uniform numbers in [0, 1) from a xorshift generator seeded with `seed`.
    fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// `keeps_any` (a count up to eight as a constant) answers as `keeps` for every count from
    /// one to ten, lengths and angles mixed, steps kept and refused, and slices of unequal
    /// lengths (refused by both).
    #[test]
    fn any_count_keeps_what_keeps_keeps() {
        let mut next = uniform(0x9e37_79b9_7f4a_7c15);
        let mut seen = [0usize; 2];
        for n in 1..=10 {
            let unknowns = (0..n)
                .map(|k| CoordDesc {
                    name: alloc::format!("u{k}"),
                    kind: if k % 3 == 1 {
                        Kind::Length
                    } else {
                        Kind::Angle
                    },
                    start: 0.0,
                })
                .collect();
            let info = with_unknowns(unknowns);
            let guard = BranchGuard::new(&info, 2.0);
            for case in 0..300 {
                let dt = 0.2 * next();
                let mut v = |scale: f64| {
                    (0..n)
                        .map(|_| scale * (2.0 * next() - 1.0))
                        .collect::<Vec<_>>()
                };
                let (before, qd, qdd) = (v(3.0), v(1.0), v(1.0));
                let mut after: Vec<f64> = (0..n)
                    .map(|k| before[k] + dt * (qd[k] + 0.5 * dt * qdd[k]))
                    .collect();
                let k = case % n;
                after[k] += [1e-6, 0.3, 3.0, f64::NAN][case % 4];
                let one = guard.keeps(&before, &qd, &qdd, dt, &after);
                assert_eq!(
                    guard.keeps_any([&before, &qd, &qdd, &after], dt),
                    one,
                    "n {n}, case {case}"
                );
                seen[usize::from(one)] += 1;
                let short = &before[..n - 1];
                assert!(!guard.keeps_any([short, &qd, &qdd, &after], dt));
            }
        }
        assert!(seen[0] > 300 && seen[1] > 300, "kept and refused: {seen:?}");
    }

    fn keeps_as_defined(first: CoordDesc, second: CoordDesc) {
        let info = with_unknowns(alloc::vec![first, second]);
        let mut next = uniform(0x2545_f491_4f6c_dd1d);
        let mut seen = [0usize; 2];
        for case in 0..4000 {
            let dt = 0.3 * next();
            let mut lanes: [[f64; 9]; 8] = [[0.0; 9]; 8];
            for lane in &mut lanes {
                let big = if case % 7 == 0 { 40.0 } else { 1.0 };
                for v in lane.iter_mut() {
                    *v = big * (2.0 * next() - 1.0);
                }
                lane[8] = 0.5 + 3.0 * next();
                if case % 11 == 0 {
                    lane[7] = f64::NAN;
                }
                // An infinite solution, under a finite and under an infinite length scale.
                if case % 13 == 0 {
                    lane[7] = f64::INFINITY;
                }
                if case % 17 == 0 {
                    lane[6] = f64::INFINITY;
                }
                if case % 2 == 0 && (case % 13 == 0 || case % 5 == 0) {
                    lane[8] = f64::INFINITY;
                }
                if case % 3 == 0 {
                    // `after` on the prediction, give or take a little.
                    for k in 0..2 {
                        let p = lane[k] + dt * (lane[2 + k] + 0.5 * dt * lane[4 + k]);
                        lane[6 + k] = p + 1e-3 * (next() - 0.5);
                    }
                }
            }
            let col = |k: usize| Vf64::<8>::from_fn(|i| lanes[i][k]);
            let guard = BranchGuard::new(&info, 1.0);
            let bits = guard.keeps_lanes(
                col(8),
                &[col(0), col(1)],
                &[col(2), col(3)],
                &[col(4), col(5)],
                dt,
                &[col(6), col(7)],
            );
            for (i, l) in lanes.iter().enumerate() {
                let g = BranchGuard::new(&info, l[8]);
                let one = g.keeps(&l[0..2], &l[2..4], &l[4..6], dt, &l[6..8]);
                assert_eq!(bits >> i & 1 == 1, one, "case {case}, lane {i}: {l:?}");
                let any = g.keeps_any([&l[0..2], &l[2..4], &l[4..6], &l[6..8]], dt);
                assert_eq!(any, one, "case {case}, lane {i}: {l:?}");
                let p: Vec<f64> = (0..2)
                    .map(|k| l[k] + dt * (l[2 + k] + 0.5 * dt * l[4 + k]))
                    .collect();
                let (before, after) = (&l[0..2], &l[6..8]);
                let defined = !g.too_far(before, &p)
                    && !g.too_far(before, after)
                    && BranchGuard::jump(&p, after, before) <= MAX_JUMP;
                assert_eq!(one, defined, "case {case}, lane {i}: {l:?}");
                seen[usize::from(one)] += 1;
            }
        }
        assert!(
            seen[0] > 1000 && seen[1] > 1000,
            "kept and refused: {seen:?}"
        );
    }
}
