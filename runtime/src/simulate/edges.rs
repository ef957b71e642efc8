//! The edges of loads that act over a range of the input: where a simulated input stands against
//! each range (inside, outside, on an edge), the first edge a step crosses, and the one way to
//! leave an edge (or stay on it) that the forces on its two sides allow. A load is switched on or
//! off only between steps, at an edge the step was shortened to land on, so that no step's stages
//! straddle the jump in the equation of motion.

use super::{Effort, Simulation, resolution};
use crate::dynamics::PointLoad;
use crate::error::SolveError;
use crate::scalar::Real;

impl<T: Real> Simulation<'_, T> {
    /// The loads that act through the next step, from `on`.
    pub(super) fn switch(&mut self) {
        self.active.clear();
        for (l, _) in self.loads.iter().zip(&self.on).filter(|(_, on)| **on) {
            self.active.push(PointLoad::new(l.point, l.force));
        }
    }

    /// Which loads act through the next step, from where the input stands against each one's
    /// range and, on an edge, which way it leaves (or that it rests there: [`Self::held`]); then
    /// the acceleration there.
    pub(super) fn set_modes(&mut self, effort: &mut Effort<'_, T>) -> Result<(), SolveError> {
        self.held = false;
        for i in 0..self.loads.len() {
            match side(&self.loads[i], self.y[0]) {
                Side::Inside => self.on[i] = true,
                Side::Outside => self.on[i] = false,
                Side::Edge { at, inward } => {
                    self.y[0] = at;
                    let (t, y) = (self.t, self.y);
                    let way = leave(inward, y[1], |on| {
                        self.on[i] = on;
                        self.switch();
                        self.eval(t, y, effort).ok().map(|r| r.0)
                    });
                    self.on[i] = way.unwrap_or(true);
                    self.held |= way.is_none();
                }
            }
        }
        self.switch();
        if self.held {
            self.y[1] = T::zero();
        }
        let (acc, _) = self.eval(self.t, self.y, effort)?;
        self.acc = if self.held { T::zero() } else { acc };
        Ok(())
    }

    /// One try of size `h`: when its error is within the tolerances the state moves to the
    /// step's end or, where the step would cross the edge of a load's range, to that edge (the
    /// step shortened to land on it; the loads switched there). Returns the error estimate and
    /// the time advanced (0 for a refused try). A step too small for the time to resolve:
    /// `StepTooSmall`.
    pub(super) fn advance(
        &mut self,
        h: T,
        effort: &mut Effort<'_, T>,
    ) -> Result<(T, T), SolveError> {
        if h <= resolution(self.t) {
            return Err(SolveError::StepTooSmall {
                time: self.t.to_f64(),
                step: h.to_f64(),
            });
        }
        let (y_new, acc_new, err) = self.try_step(h, effort)?;
        if err > T::one() {
            return Ok((err, T::zero()));
        }
        let x0 = self.y[0];
        let edge = self
            .loads
            .iter()
            .filter_map(|l| first_edge(l, x0, y_new[0]))
            .min_by(|a, b| {
                let (da, db) = ((*a - x0).abs(), (*b - x0).abs());
                da.partial_cmp(&db).unwrap_or(core::cmp::Ordering::Equal)
            });
        let Some(e) = edge else {
            self.t += h;
            self.y = y_new;
            self.acc = acc_new;
            return Ok((err, h));
        };
        let taken = self.land_on(e, (h, y_new[0]), effort)?;
        self.set_modes(effort)?;
        Ok((err, taken))
    }

    /// The step from the current state that lands on `x = e`, given a step `h` that ends at `x1`
    /// past it: its size by regula falsi (the Illinois variant), the state moved there.
    fn land_on(
        &mut self,
        e: T,
        (h, x1): (T, T),
        effort: &mut Effort<'_, T>,
    ) -> Result<T, SolveError> {
        let tol = tolerance(e);
        let (mut lo, mut f_lo) = (T::zero(), self.y[0] - e);
        let (mut hi, mut f_hi) = (h, x1 - e);
        let mut kept = 0i8;
        let mut best = None;
        for _ in 0..60 {
            let hm = lo - f_lo * (hi - lo) / (f_hi - f_lo);
            let (y, acc, _) = self.try_step(hm, effort)?;
            let f = y[0] - e;
            if (f < T::zero()) == (f_lo < T::zero()) {
                (lo, f_lo) = (hm, f);
                best = Some((hm, y, acc));
                if kept == 1 {
                    f_hi *= T::lit(0.5);
                }
                kept = 1;
            } else {
                (hi, f_hi) = (hm, f);
                if kept == -1 {
                    f_lo *= T::lit(0.5);
                }
                kept = -1;
            }
            if f.abs() <= tol {
                self.t += hm;
                self.y = [e, y[1]];
                self.acc = acc;
                return Ok(hm);
            }
        }
        // Not closer than `tol` (a flat approach): the last step short of the edge.
        let (hm, y, acc) = best.unwrap_or((T::zero(), self.y, self.acc));
        self.t += hm;
        self.y = y;
        self.acc = acc;
        Ok(hm)
    }
}

/// Where an input value stands against a load's range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Side<T> {
    Inside,
    Outside,
    /// On an edge: its value nearest the input, and the direction (+1 or −1) in which the range
    /// lies from it.
    Edge {
        at: T,
        inward: T,
    },
}

/// How near an edge (in the input's units, relative to its size) counts as on it.
pub(super) fn tolerance<T: Real>(x: T) -> T {
    T::lit(1e-11) * x.abs().max(T::one())
}

/// `v` modulo a turn, in `[0, τ)`.
fn turn<T: Real>(v: T) -> T {
    let tau = core::f64::consts::TAU;
    let r = v.to_f64() % tau;
    T::lit(if r < 0.0 { r + tau } else { r })
}

/// The range's edges (from, to) when the load has a range shorter than a turn.
fn edges<T: Real>(l: &PointLoad<T>) -> Option<[T; 2]> {
    let [a, b] = l.range?;
    (b - a < T::lit(core::f64::consts::TAU)).then_some([a, b])
}

/// Where `x` stands against `l`'s range (a load without a range, or one of a whole turn, is
/// always inside).
pub(super) fn side<T: Real>(l: &PointLoad<T>, x: T) -> Side<T> {
    let Some(range) = edges(l) else {
        return Side::Inside;
    };
    let (tol, half) = (tolerance(x), T::lit(core::f64::consts::PI));
    for (e, inward) in range.into_iter().zip([T::one(), -T::one()]) {
        // The signed distance from the edge's value nearest x, in (−π, π].
        let mut d = turn(x - e);
        if d > half {
            d -= T::lit(core::f64::consts::TAU);
        }
        if d.abs() <= tol {
            return Side::Edge { at: x - d, inward };
        }
    }
    if l.acts_at(x) {
        Side::Inside
    } else {
        Side::Outside
    }
}

/// The first edge of `l`'s range met going from `x0` to `x1` (not the one `x0` stands on).
pub(super) fn first_edge<T: Real>(l: &PointLoad<T>, x0: T, x1: T) -> Option<T> {
    let range = edges(l)?;
    let tol = tolerance(x0);
    let up = x1 > x0;
    range
        .into_iter()
        .map(|e| {
            // The distance to the edge's next value in the direction of motion, in [0, τ).
            let d = if up { turn(e - x0) } else { turn(x0 - e) };
            if d <= tol {
                d + T::lit(core::f64::consts::TAU)
            } else {
                d
            }
        })
        .filter(|&d| d <= (x1 - x0).abs())
        .min_by(|a, b| a.partial_cmp(b).unwrap_or(core::cmp::Ordering::Equal))
        .map(|d| if up { x0 + d } else { x0 - d })
}

/// Whether a load on an edge acts through the next step, from the input's rate `v` there and,
/// at rest, the accelerations with the load on and off: `Some(on)`, or `None` when the forces on
/// both sides push into the edge (the input rests on it: the load there takes whatever value
/// between off and on holds it).
pub(super) fn leave<T: Real>(
    inward: T,
    v: T,
    mut acc: impl FnMut(bool) -> Option<T>,
) -> Option<bool> {
    if v.abs() > T::lit(1e-10) {
        return Some((v > T::zero()) == (inward > T::zero()));
    }
    if acc(true).is_some_and(|a| inward * a > T::zero()) {
        return Some(true);
    }
    if acc(false).is_some_and(|a| inward * a < T::zero()) {
        return Some(false);
    }
    None
}
