//! The tick state of a generated scene ([`SceneTick`]): a mechanism's [`Tick`] kept private,
//! because a scene's tick solves only what its outputs read. Generated scenes make and move it
//! through the hidden functions below (the `__private` ABI); users read it through their scene's
//! `outputs` and the accessors here.

use crate::scalar::Real;
use crate::solve::NewtonReport;
use crate::tick::{Tick, TickCache};

/// The state of a scene between simulator ticks (a generated scene's `NAME::Tick<T>`), made by
/// its `tick_start` and moved on by its `tick`; read the outputs with the scene's `outputs`
/// (`Scene::outputs`).
///
/// Inside is its mechanism's [`Tick`] for the kept blocks, with the same predictor and cached
/// sines and cosines. It is private because a scene's tick computes only what its outputs read:
/// the angle of a closed-form block whose sine and cosine alone are read (the link a point sits
/// on) is not computed, nor the direction of a link nothing reads, so those entries are stale.
/// `NI` inputs, `NU` unknowns, `NP` the scene's points, `NPAR` params, as in [`Tick`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneTick<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize> {
    state: Tick<T, NI, NU, NP, NPAR>,
    memo: SceneMemo<T>,
}

/// What a scene's tick state holds besides its mechanism's [`Tick`]: the time step of the last
/// tick, and whether the stored rate estimates hold a secant the next parabola can rest on (1)
/// or not (0: after `tick_start`, a params change, a dropped estimate): see
/// [`scene_rates_estimated`]. A scene in lanes keeps one per lane
/// ([`crate::LaneTick`]'s memo).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SceneMemo<T> {
    last_step: T,
    history: u8,
}

impl<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>
    SceneTick<T, NI, NU, NP, NPAR>
{
    /// The inputs of the last tick.
    pub fn x(&self) -> &[T; NI] {
        &self.state.x
    }

    /// Their rates.
    pub fn xd(&self) -> &[T; NI] {
        &self.state.xd
    }

    /// The last position solve's report (iterations, residual, smallest pivot ratio).
    pub fn report(&self) -> &NewtonReport<T> {
        &self.state.report
    }
}

/// A scene's tick state around a solved mechanism tick (what a scene's `tick_start` makes).
#[doc(hidden)]
pub fn scene_tick<T: Real, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>(
    state: Tick<T, NI, NU, NP, NPAR>,
) -> SceneTick<T, NI, NU, NP, NPAR> {
    SceneTick {
        state,
        memo: SceneMemo {
            last_step: T::zero(),
            history: 0,
        },
    }
}

/// A scene's tick state from its parts ([`scene_tick_parts`]), as a scene in lanes keeps them.
#[doc(hidden)]
#[inline]
pub fn scene_tick_join<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>(
    state: Tick<T, NI, NU, NP, NPAR>,
    memo: SceneMemo<T>,
) -> SceneTick<T, NI, NU, NP, NPAR> {
    SceneTick { state, memo }
}

/// The parts of a scene's tick state: its mechanism's tick and the rest.
#[doc(hidden)]
#[inline]
pub fn scene_tick_parts<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>(
    t: SceneTick<T, NI, NU, NP, NPAR>,
) -> (Tick<T, NI, NU, NP, NPAR>, SceneMemo<T>) {
    (t.state, t.memo)
}

/// The rates a scene of order below 2 does not compute, estimated by differences for the
/// unknowns with `estimate[k]`, so that its predictor is second order like the full tick's (a
/// scene with Newton blocks calls this after a successful solve to `x` at input rates `xd`, with
/// the solved `q` and the rates it computed, `qd` at order 1; the result is what its tick state
/// stores).
///
/// With `h` the time of the step to `x` at the rates `xd` ([`TickCache::step_to`]): at
/// order 0 the secant `s = Δq / h`, and when the last tick left one too (same input rates, steps
/// not nearly opposite) the parabola through the last three configurations,
/// `q̈ ≈ 2 (s − s₀) / (h₀ + h)` with `s₀ = q̇₀ − h₀ q̈₀ / 2`, and `q̇ ≈ s + h q̈ / 2`; at order 1
/// `q̈ ≈ Δq̇ / h` (same input rates). A change of params (`same_params` false) makes the step a
/// jump, not a motion: no estimate then (zero rates, history dropped). No motion (`h = 0`) keeps
/// the last estimates; a non-finite estimate is dropped (0) with the history.
#[doc(hidden)]
#[allow(clippy::needless_range_loop, clippy::too_many_arguments)]
pub fn scene_rates_estimated<
    T: Real,
    const NI: usize,
    const NU: usize,
    const NP: usize,
    const NPAR: usize,
>(
    t: &mut SceneTick<T, NI, NU, NP, NPAR>,
    x: &[T; NI],
    xd: &[T; NI],
    q: &[T; NU],
    qd: [T; NU],
    order: u8,
    estimate: [bool; NU],
    same_params: bool,
) -> ([T; NU], [T; NU]) {
    let old = &t.state;
    let h = old.step_to(x, xd);
    if !same_params {
        t.memo.history = 0;
        return (
            if order == 0 { [T::zero(); NU] } else { qd },
            [T::zero(); NU],
        );
    }
    if !(h != T::zero() && h.is_finite()) {
        let qd = if order == 0 { old.qd } else { qd };
        return (qd, old.qdd);
    }
    let same_rates = (0..NI).all(|i| xd[i] == old.xd[i]);
    let h0 = t.memo.last_step;
    // The parabola is well posed when the two steps are not nearly opposite.
    let parabola = order == 0
        && t.memo.history >= 1
        && same_rates
        && (h0 + h).abs() >= T::lit(0.5) * h0.abs().max(h.abs());
    let half = T::lit(0.5);
    let (mut qd_out, mut qdd_out) = (qd, [T::zero(); NU]);
    let mut dropped = false;
    for k in 0..NU {
        if !estimate[k] {
            continue;
        }
        let (v, a) = if order == 0 {
            let s = (q[k] - old.q[k]) / h;
            if parabola {
                let s0 = old.qd[k] - half * h0 * old.qdd[k];
                let a = T::lit(2.0) * (s - s0) / (h0 + h);
                (s + half * h * a, a)
            } else {
                (s, T::zero())
            }
        } else if same_rates {
            (qd[k], (qd[k] - old.qd[k]) / h)
        } else {
            (qd[k], T::zero())
        };
        if v.is_finite() && a.is_finite() {
            (qd_out[k], qdd_out[k]) = (v, a);
        } else {
            dropped = true;
            qd_out[k] = if order == 0 { T::zero() } else { qd[k] };
        }
    }
    t.memo.last_step = h;
    // What the next tick's parabola rests on: a secant (and its parabola) were stored.
    t.memo.history = if dropped { 0 } else { 1 };
    (qd_out, qdd_out)
}

/// The mechanism tick inside (generated `outputs` read from it).
#[doc(hidden)]
#[inline(always)]
pub fn scene_tick_state<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>(
    t: &SceneTick<T, NI, NU, NP, NPAR>,
) -> &Tick<T, NI, NU, NP, NPAR> {
    &t.state
}

/// The mechanism tick inside, to move it (generated `tick`).
#[doc(hidden)]
#[inline(always)]
pub fn scene_tick_state_mut<
    T,
    const NI: usize,
    const NU: usize,
    const NP: usize,
    const NPAR: usize,
>(
    t: &mut SceneTick<T, NI, NU, NP, NPAR>,
) -> &mut Tick<T, NI, NU, NP, NPAR> {
    &mut t.state
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::info::PointMotion;
    use crate::tick::Solution;

    /// q(t) = 0.3 + 1.7 t − 2.5 t²: a parabola, which the estimates must reproduce to rounding.
    fn q(t: f64) -> f64 {
        0.3 + 1.7 * t - 2.5 * t * t
    }
    fn qd(t: f64) -> f64 {
        1.7 - 5.0 * t
    }

    /// The solved state at `t` with unknown `q` and rate `qd` (input rate 1, no acceleration).
    fn solution(t: f64, q: [f64; 1], qd: [f64; 1]) -> Solution<f64, 1, 1, 0, 0> {
        let points: [PointMotion<f64>; 0] = [];
        Solution {
            x: [t],
            xd: [1.0],
            xdd: [0.0],
            q,
            qd,
            qdd: [0.0],
            points,
            report: NewtonReport::new(),
            tx: [(0.0, 1.0)],
            tq: [(0.0, 1.0)],
            tp: [],
            params: [],
        }
    }

    fn start(t: f64, rate: f64) -> SceneTick<f64, 1, 1, 0, 0> {
        scene_tick(Tick::new(solution(t, [q(t)], [rate])))
    }

    /// One tick to `t` at `order`, stored as a scene's tick stores it.
    fn tick(s: &mut SceneTick<f64, 1, 1, 0, 0>, t: f64, order: u8) -> (f64, f64) {
        let rate = if order == 0 { 0.0 } else { qd(t) };
        let (v, a) = scene_rates_estimated(s, &[t], &[1.0], &[q(t)], [rate], order, [true], true);
        let st = scene_tick_state_mut(s);
        let mut solution = solution(t, [q(t)], v);
        solution.qdd = a;
        *st = Tick::new(solution);
        (v[0], a[0])
    }

    #[test]
    fn order_0_rates_come_from_the_parabola_through_three_ticks() {
        // Uneven steps: 0.1, then 0.25, then 0.05.
        let mut s = start(0.0, 0.0);
        let (v, a) = tick(&mut s, 0.1, 0);
        // One step: the secant only.
        assert!((v - (q(0.1) - q(0.0)) / 0.1).abs() < 1e-14 && a == 0.0);
        for t in [0.35, 0.4] {
            let (v, a) = tick(&mut s, t, 0);
            assert!((v - qd(t)).abs() < 1e-13, "q̇({t}) = {v}");
            assert!((a + 5.0).abs() < 1e-12, "q̈({t}) = {a}");
        }
    }

    #[test]
    fn order_1_accelerations_are_differences_of_the_rates() {
        let mut s = start(0.0, qd(0.0));
        for t in [0.1, 0.35] {
            let (v, a) = tick(&mut s, t, 1);
            assert_eq!(v, qd(t));
            assert!((a + 5.0).abs() < 1e-13, "q̈({t}) = {a}");
        }
    }

    #[test]
    fn no_motion_keeps_the_estimates_and_unestimated_unknowns_get_none() {
        let mut s = start(0.0, 0.0);
        tick(&mut s, 0.1, 0);
        let before = (s.state.qd, s.state.qdd);
        let (v, a) =
            scene_rates_estimated(&mut s, &[0.1], &[1.0], &[q(0.1)], [0.0], 0, [true], true);
        assert_eq!((v, a), before);
        let (v, a) =
            scene_rates_estimated(&mut s, &[0.2], &[1.0], &[q(0.2)], [0.0], 0, [false], true);
        assert_eq!((v, a), ([0.0], [0.0]));
    }

    #[test]
    fn jumps_reversals_and_new_rates_are_not_differenced_into_a_parabola() {
        // A change of params: the step is a jump, so no rates at all and no history.
        let mut s = start(0.0, 0.0);
        tick(&mut s, 0.1, 0);
        let (v, a) =
            scene_rates_estimated(&mut s, &[0.2], &[1.0], &[q(0.2)], [0.0], 0, [true], false);
        assert_eq!((v, a, s.memo.history), ([0.0], [0.0], 0));
        // Steps out and nearly back (h₀ + h ≈ 0): the secant alone.
        let mut s = start(0.0, 0.0);
        tick(&mut s, 0.8, 0);
        let back = 0.8 - 0.7999999;
        let (v, a) = tick(&mut s, back, 0);
        assert!((v - (q(back) - q(0.8)) / (back - 0.8)).abs() < 1e-9 && a == 0.0);
        // New input rates: the step's time is measured with them, and no parabola.
        let mut s = start(0.0, 0.0);
        tick(&mut s, 0.1, 0);
        let (v, a) =
            scene_rates_estimated(&mut s, &[0.3], &[2.0], &[q(0.3)], [0.0], 0, [true], true);
        assert!((v[0] - 2.0 * (q(0.3) - q(0.1)) / 0.2).abs() < 1e-12 && a[0] == 0.0);
    }
}
