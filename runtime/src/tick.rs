//! Predictor stepping for simulators: a [`Tick`] is the state between two ticks (the solved
//! configuration, its rates and points) together with the sines and cosines of its angles. The
//! next tick predicts the unknowns by a second-order Taylor step, rotates the cached sines and
//! cosines by the predicted changes (no `sin_cos` call for a small step) and solves from there.
//! Generated mechanisms expose it as `tick_start` / `tick` (and `StaticMechanism::tick`); it
//! reads as its [`State`]. What generated code alone calls on it is the hidden [`TickCache`]
//! (reached through `__private`).

// Index loops over several parallel arrays read better than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use core::ops::Deref;

use crate::info::PointMotion;
use crate::mechanism::State;
use crate::scalar::Real;
use crate::solve::NewtonReport;
use crate::trig::{TrigState, rotate, sin_cos_cold};

/// Ticks after which every cached sine and cosine is recomputed, bounding rounding drift.
pub const RESYNC_TICKS: u32 = 64;

/// The state of a mechanism between simulator ticks, made by a generated `tick_start` and moved
/// on by `tick` (`NAME::Tick<T>` names it with the mechanism's sizes: `NI` inputs, `NU`
/// unknowns, `NP` points, `NPAR` params).
///
/// A tick reads as its [`State`] (it dereferences to one): after every successful
/// `tick_start`/`tick` (and unchanged by a failed `tick`), the inputs `x`, `xd`, `xdd` of the last
/// tick, the solved unknowns `q` (on the branch of the first guess), their rates `qd` and
/// accelerations `qdd`, every point's motion (`points`, in the order of `INFO.points`) and the
/// last position solve's `report`. Besides the state, private caches the next tick reads: the
/// sines and cosines of the inputs, unknowns and params, the params they were made with (a change
/// of params is detected and starts them afresh) and their age (recomputed every
/// [`RESYNC_TICKS`] ticks). The state cannot be written through a tick (it would not match the
/// caches): to move it, call `tick`. Use: `let mut t = mech.tick_start(&input, &guess, &options)?;`
/// once, then `mech.tick(&mut t, &input, &options)?` per step and read `t.q`, `t.qd`, `t.qdd`,
/// `t.points` (or the whole `*t`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tick<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize> {
    pub(crate) state: TickStateOf<T, NI, NU, NP>,
    pub(crate) tx: [(T, T); NI],
    pub(crate) tq: [(T, T); NU],
    pub(crate) tp: [(T, T); NPAR],
    pub(crate) params: [T; NPAR],
    pub(crate) age: u32,
}

/// The [`State`] of a tick with `NI` inputs, `NU` unknowns and `NP` points.
pub type TickStateOf<T, const NI: usize, const NU: usize, const NP: usize> =
    State<[T; NI], [T; NU], [PointMotion<T>; NP], T>;

impl<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize> Deref
    for Tick<T, NI, NU, NP, NPAR>
{
    type Target = TickStateOf<T, NI, NU, NP>;
    fn deref(&self) -> &Self::Target {
        &self.state
    }
}

/// The sines and cosines of a tick's inputs and unknowns.
pub type TrigRefs<'a, T, const NI: usize, const NU: usize> = (&'a [(T, T); NI], &'a [(T, T); NU]);

/// Params a tick had not seen, with their sines and cosines.
pub type NewParams<'a, T, const NPAR: usize> = (&'a [T; NPAR], &'a [(T, T); NPAR]);

/// The solved state a tick stores (what a whole solve returns, with the trigonometry it used).
#[derive(Clone, Copy, Debug)]
pub struct Solution<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize> {
    pub x: [T; NI],
    pub xd: [T; NI],
    pub xdd: [T; NI],
    pub q: [T; NU],
    pub qd: [T; NU],
    pub qdd: [T; NU],
    pub points: [PointMotion<T>; NP],
    pub report: NewtonReport<T>,
    /// (sin, cos) of the inputs, unknowns and params (where they appear in a sin or cos).
    pub tx: [(T, T); NI],
    pub tq: [(T, T); NU],
    pub tp: [(T, T); NPAR],
    pub params: [T; NPAR],
}

// What generated code calls on a tick: part of the generator's ABI, reached only as
// `__private::TickCache` (the generated code lives in the user's crate); users read a tick as its
// state.
/// The caches of a [`Tick`], as generated code moves them (not a public API).
#[doc(hidden)]
#[allow(clippy::too_many_arguments)]
pub trait TickCache<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>:
    Sized
{
    /// A tick from a solution whose trigonometry was just computed with `sin_cos`.
    fn new(s: Solution<T, NI, NU, NP, NPAR>) -> Self;

    /// Whether `params` are the ones the caches were made with (then they are finite too: a
    /// tick checks params it has not seen). A NaN param is never the same.
    fn same_params(&self, params: &[T; NPAR]) -> bool;

    /// [`TickCache::same_params`] over the params with `read[i]` only: a scene compares the params its
    /// code reads (the others cannot change its results, and its caches hold none of them).
    fn same_params_in(&self, params: &[T; NPAR], read: [bool; NPAR]) -> bool;

    /// The params' cached sines and cosines (valid when [`TickCache::same_params`]).
    fn params_trig(&self) -> &[(T, T); NPAR];

    /// The sines and cosines of the last tick's inputs and unknowns (those that appear in a sine
    /// or cosine; valid while the params are the same).
    fn trig(&self) -> TrigRefs<'_, T, NI, NU>;

    /// The inputs' sines and cosines at `x` (`angle[i]`: input `i` appears in a sin or cos),
    /// rotated from the cached ones, or recomputed when they are due.
    fn inputs_trig(&self, x: &[T; NI], angle: [bool; NI]) -> [(T, T); NI];

    /// The last tick's unknowns with their sines and cosines, as the guess of a tick whose
    /// blocks are all solved in closed form (nothing to predict: a closed form reads the guess
    /// only for its branch and measures its turn from it, and its sines and cosines are exact,
    /// so they need no resync and stay valid when the params change).
    fn carried(&self, angle: [bool; NU]) -> TrigState<T, NU>;

    /// Sets each unknown with `mask[k]` to the principal value of its cached sine and cosine. A
    /// scene's tick leaves the angle of a closed-form block stale when it reads only its sine and
    /// cosine; before a Newton solve predicts from it (closed forms off) it is made whole again
    /// (its whole turns are lost, which nothing of that scene reads).
    fn principal_angles(&mut self, mask: [bool; NU]);

    /// The time from the last tick to input `x` at the input rates `xd`: the change of the
    /// inputs fitted over those rates, Σ Δx·ẋ / Σ ẋ² (0 when they are at rest). The predictor
    /// takes the last tick's rates; a scene's rate estimates the current ones.
    fn step_to(&self, x: &[T; NI], xd: &[T; NI]) -> T;

    /// The guess for input `x`: q + q̇ dt + q̈ dt²/2, dt fitted to the change of the inputs over
    /// their last rates (no prediction when they were at rest), with its sines and cosines
    /// rotated from the cached ones (recomputed when due, or all of them when the params are
    /// not the same). Unknowns with `keep[k]` (those a closed form solves: it reads the guess
    /// only for its branch and measures its turn from it, and leaves exact sines and cosines)
    /// stay at the last tick's values.
    fn predicted(
        &self,
        x: &[T; NI],
        angle: [bool; NU],
        keep: [bool; NU],
        same_params: bool,
    ) -> TrigState<T, NU>;

    /// Stores the next solution in place; `new_params` are the params and their sines and
    /// cosines when they were not the cached ones (they are stored, and every cache starts
    /// afresh).
    fn update(
        &mut self,
        x: &[T; NI],
        xd: &[T; NI],
        xdd: &[T; NI],
        st: &TrigState<T, NU>,
        qd: [T; NU],
        qdd: [T; NU],
        points: [PointMotion<T>; NP],
        report: NewtonReport<T>,
        tx: [(T, T); NI],
        new_params: Option<NewParams<'_, T, NPAR>>,
    );
}

/// The time from inputs `from` to inputs `to` at the input rates `xd`: the change of the inputs
/// fitted over those rates, Σ Δx·ẋ / Σ ẋ² (0 when they are at rest). The one rule every tick's
/// predictor (generated, lanes, [`crate::dyn_tick`]) steps by.
#[inline(always)]
pub fn step_to<T: Real>(from: &[T], to: &[T], xd: &[T]) -> T {
    let (mut num, mut den) = (T::zero(), T::zero());
    for i in 0..from.len().min(to.len()).min(xd.len()) {
        num += (to[i] - from[i]) * xd[i];
        den += xd[i] * xd[i];
    }
    if den > T::zero() {
        num / den
    } else {
        T::zero()
    }
}

/// The second-order predictor of every tick: `out[k] = q + q̇ dt + q̈ dt²/2` for each unknown
/// not kept (`keep[k]`, or beyond `keep`'s length: predicted), kept ones `q[k]`; all of `q` where
/// any prediction is not finite.
#[inline(always)]
pub fn taylor<T: Real>(q: &[T], qd: &[T], qdd: &[T], dt: T, keep: &[bool], out: &mut [T]) {
    let mut finite = true;
    for k in 0..out.len() {
        out[k] = q[k];
        if !keep.get(k).copied().unwrap_or(false) {
            out[k] += dt * (qd[k] + T::lit(0.5) * dt * qdd[k]);
        }
        finite &= out[k].is_finite();
    }
    if !finite {
        out.copy_from_slice(&q[..out.len()]);
    }
}

/// The inputs' sines and cosines at `x` into `out` (`angle[i]`: input `i` appears in a sin or
/// cos; the others are left as they are): rotated from `tx`, the cached ones at `x_last`, or
/// recomputed when `resync`. The one rule of every tick (a generated `Tick` on arrays, the
/// generic engine's on slices).
#[inline(always)]
pub fn inputs_trig<T: Real>(
    tx: &[(T, T)],
    x_last: &[T],
    x: &[T],
    angle: &[bool],
    resync: bool,
    out: &mut [(T, T)],
) {
    for i in 0..out.len().min(angle.len()) {
        if angle[i] {
            out[i] = if resync {
                sin_cos_cold(x[i])
            } else {
                rotate(tx[i], x[i], x_last[i] - x[i])
            };
        }
    }
}

/// What the predictor reads of the last tick: its inputs and their rates, its unknowns with
/// their rates, and the unknowns' cached sines and cosines.
#[derive(Clone, Copy, Debug)]
pub struct Last<'a, T> {
    pub x: &'a [T],
    pub xd: &'a [T],
    pub q: &'a [T],
    pub qd: &'a [T],
    pub qdd: &'a [T],
    pub tq: &'a [(T, T)],
}

/// The guess for input `x` into `q` and `sc` (which hold the last tick's unknowns and their
/// sines and cosines): q + q̇ dt + q̈ dt²/2 ([`taylor`], dt by [`step_to`]), the sines and
/// cosines of the predicted angles rotated from the cached ones (recomputed when `fresh`).
/// Unknowns with `keep[k]` (a closed form's: it reads the guess only for its branch and measures
/// its turn from it, and leaves exact sines and cosines) stay as they are. The one predictor of
/// every tick.
#[inline(always)]
pub fn predict<T: Real>(
    last: Last<'_, T>,
    x: &[T],
    angle: &[bool],
    keep: &[bool],
    fresh: bool,
    q: &mut [T],
    sc: &mut [(T, T)],
) {
    let dt = step_to(last.x, x, last.xd);
    taylor(last.q, last.qd, last.qdd, dt, keep, q);
    for k in 0..q.len().min(sc.len()).min(angle.len()) {
        if angle[k] && !keep.get(k).copied().unwrap_or(false) {
            sc[k] = if fresh {
                sin_cos_cold(q[k])
            } else {
                rotate(last.tq[k], q[k], last.q[k] - q[k])
            };
        }
    }
}

impl<T: Real, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>
    Tick<T, NI, NU, NP, NPAR>
{
    /// Whether the rotated caches are due to be recomputed ([`RESYNC_TICKS`]).
    #[inline]
    fn resync(&self) -> bool {
        self.age >= RESYNC_TICKS
    }
}

impl<T: Real, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>
    TickCache<T, NI, NU, NP, NPAR> for Tick<T, NI, NU, NP, NPAR>
{
    fn new(s: Solution<T, NI, NU, NP, NPAR>) -> Self {
        Tick {
            state: State {
                x: s.x,
                xd: s.xd,
                xdd: s.xdd,
                q: s.q,
                qd: s.qd,
                qdd: s.qdd,
                points: s.points,
                report: s.report,
            },
            tx: s.tx,
            tq: s.tq,
            tp: s.tp,
            params: s.params,
            age: 0,
        }
    }

    #[inline]
    fn same_params(&self, params: &[T; NPAR]) -> bool {
        self.same_params_in(params, [true; NPAR])
    }

    #[inline(always)]
    fn same_params_in(&self, params: &[T; NPAR], read: [bool; NPAR]) -> bool {
        // Branch-free, so that it compiles to a few compares (none for a param not read).
        let mut same = true;
        for i in 0..NPAR {
            if read[i] {
                same &= self.params[i] == params[i];
            }
        }
        same
    }

    #[inline]
    fn trig(&self) -> TrigRefs<'_, T, NI, NU> {
        (&self.tx, &self.tq)
    }

    #[inline]
    fn params_trig(&self) -> &[(T, T); NPAR] {
        &self.tp
    }

    #[inline]
    fn inputs_trig(&self, x: &[T; NI], angle: [bool; NI]) -> [(T, T); NI] {
        let mut tx = self.tx;
        inputs_trig(&self.tx, &self.state.x, x, &angle, self.resync(), &mut tx);
        tx
    }

    #[inline(always)]
    fn carried(&self, angle: [bool; NU]) -> TrigState<T, NU> {
        TrigState::from_parts(self.state.q, self.tq, angle)
    }

    #[inline]
    fn principal_angles(&mut self, mask: [bool; NU]) {
        for k in 0..NU {
            if mask[k] {
                self.state.q[k] = self.tq[k].0.atan2(self.tq[k].1);
            }
        }
    }

    #[inline(always)]
    fn step_to(&self, x: &[T; NI], xd: &[T; NI]) -> T {
        step_to(&self.state.x, x, xd)
    }

    #[inline(always)]
    fn predicted(
        &self,
        x: &[T; NI],
        angle: [bool; NU],
        keep: [bool; NU],
        same_params: bool,
    ) -> TrigState<T, NU> {
        if same_params && !self.resync() && keep.iter().all(|&k| k) {
            // Nothing to predict: every unknown is solved in closed form.
            return TrigState::from_parts(self.state.q, self.tq, angle);
        }
        let (mut q, mut sc) = (self.state.q, self.tq);
        let fresh = !same_params || self.resync();
        let s = &self.state;
        let last = Last {
            x: &s.x,
            xd: &s.xd,
            q: &s.q,
            qd: &s.qd,
            qdd: &s.qdd,
            tq: &self.tq,
        };
        predict(last, x, &angle, &keep, fresh, &mut q, &mut sc);
        TrigState::from_parts(q, sc, angle)
    }

    #[inline]
    fn update(
        &mut self,
        x: &[T; NI],
        xd: &[T; NI],
        xdd: &[T; NI],
        st: &TrigState<T, NU>,
        qd: [T; NU],
        qdd: [T; NU],
        points: [PointMotion<T>; NP],
        report: NewtonReport<T>,
        tx: [(T, T); NI],
        new_params: Option<NewParams<'_, T, NPAR>>,
    ) {
        self.state.x = *x;
        self.state.xd = *xd;
        self.state.xdd = *xdd;
        self.state.q = st.q;
        self.tq = st.sc;
        self.state.qd = qd;
        self.state.qdd = qdd;
        self.state.points = points;
        self.state.report = report;
        self.tx = tx;
        self.age = if new_params.is_none() && !self.resync() {
            self.age + 1
        } else {
            0
        };
        if let Some((params, tp)) = new_params {
            self.params = *params;
            self.tp = *tp;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tick whose unknown 0 (a closed form's angle, true value 2.0) holds a stale value, as a
    /// scene leaves it, with the exact sine and cosine; unknown 1 is predicted (rate 1).
    fn stale_tick() -> Tick<f64, 1, 2, 0, 1> {
        Tick::new(Solution {
            x: [0.0],
            xd: [1.0],
            xdd: [0.0],
            q: [0.0, 1.0],
            qd: [0.0, 1.0],
            qdd: [0.0, 0.0],
            points: [],
            report: NewtonReport::new(),
            tx: [(0.0, 1.0)],
            tq: [2.0f64.sin_cos(), 1.0f64.sin_cos()],
            tp: [(0.0, 1.0)],
            params: [1.0],
        })
    }

    #[test]
    fn kept_unknowns_keep_their_sines_and_cosines_when_the_params_change() {
        let t = stale_tick();
        assert!(t.same_params(&[1.0]) && !t.same_params(&[2.0]));
        for same in [true, false] {
            let st = t.predicted(&[0.1], [true, true], [true, false], same);
            assert_eq!(
                (st.q[0], st.sc[0]),
                (0.0, 2.0f64.sin_cos()),
                "same = {same}"
            );
            let (s, c) = 1.1f64.sin_cos();
            assert!((st.q[1] - 1.1).abs() < 1e-15);
            assert!((st.sc[1].0 - s).abs() < 1e-15 && (st.sc[1].1 - c).abs() < 1e-15);
        }
        assert_eq!(
            t.carried([true, true]).sc,
            [2.0f64.sin_cos(), 1.0f64.sin_cos()]
        );
    }

    #[test]
    fn principal_angles_come_from_the_cached_sines_and_cosines() {
        let mut t = stale_tick();
        t.principal_angles([true, false]);
        assert!((t.q[0] - 2.0).abs() < 1e-15);
        assert_eq!(t.q[1], 1.0);
    }

    #[test]
    fn only_the_params_read_are_compared() {
        let t = stale_tick();
        assert!(t.same_params_in(&[5.0], [false]));
        assert!(!t.same_params_in(&[5.0], [true]));
        assert!(!t.same_params_in(&[f64::NAN], [true]));
    }
}
