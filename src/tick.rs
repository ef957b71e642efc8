//! Predictor stepping for simulators: a [`Tick`] is the state between two ticks (the solved
//! configuration, its rates and points) together with the sines and cosines of its angles. The
//! next tick predicts the unknowns by a second-order Taylor step, rotates the cached sines and
//! cosines by the predicted changes (no `sin_cos` call for a small step) and solves from there.
//! Generated mechanisms expose it as `tick_start` / `tick` (and `Mechanism::tick`).

// Index loops over several parallel arrays read better than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use crate::mechanism::PointMotion;
use crate::scalar::Real;
use crate::solve::NewtonReport;
use crate::trig::{TrigState, rotate};

/// Ticks after which every cached sine and cosine is recomputed, bounding rounding drift.
pub const RESYNC_TICKS: u32 = 64;

/// The state of a mechanism between ticks: inputs `x` (and their rates `xd`), unknowns `q`, `qd`,
/// `qdd`, the points and the last solve's report, plus caches the next tick reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tick<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize> {
    pub x: [T; NI],
    pub xd: [T; NI],
    pub q: [T; NU],
    pub qd: [T; NU],
    pub qdd: [T; NU],
    pub points: [PointMotion<T>; NP],
    pub report: NewtonReport<T>,
    tx: [(T, T); NI],
    tq: [(T, T); NU],
    tp: [(T, T); NPAR],
    params: [T; NPAR],
    age: u32,
}

/// The solved state a tick stores (what `solve_arrays` returns, with the trigonometry it used).
#[derive(Clone, Copy, Debug)]
pub struct Solution<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize> {
    pub x: [T; NI],
    pub xd: [T; NI],
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

impl<T: Real, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>
    Tick<T, NI, NU, NP, NPAR>
{
    /// A tick from a solution whose trigonometry was just computed with `sin_cos`.
    pub fn new(s: Solution<T, NI, NU, NP, NPAR>) -> Self {
        Tick {
            x: s.x,
            xd: s.xd,
            q: s.q,
            qd: s.qd,
            qdd: s.qdd,
            points: s.points,
            report: s.report,
            tx: s.tx,
            tq: s.tq,
            tp: s.tp,
            params: s.params,
            age: 0,
        }
    }

    /// Whether the caches may be used for the next tick: the params are unchanged and the
    /// caches are younger than [`RESYNC_TICKS`].
    pub fn fresh(&self, params: &[T; NPAR]) -> bool {
        self.age < RESYNC_TICKS && self.params == *params
    }

    /// The params' cached sines and cosines (valid when [`Tick::fresh`]).
    pub fn params_trig(&self) -> [(T, T); NPAR] {
        self.tp
    }

    /// The inputs' sines and cosines at `x`, rotated from the cached ones (`angle[i]`: input `i`
    /// appears in a sin or cos).
    pub fn inputs_trig(&self, x: &[T; NI], angle: [bool; NI]) -> [(T, T); NI] {
        let mut tx = self.tx;
        for i in 0..NI {
            if angle[i] {
                tx[i] = rotate(self.tx[i], x[i], self.x[i] - x[i]);
            }
        }
        tx
    }

    /// The guess for input `x`: q + q̇ dt + q̈ dt²/2, dt fitted to the change of the inputs over
    /// their last rates (no prediction when they were at rest), with its sines and cosines
    /// rotated from the cached ones when `fresh`, computed anew otherwise.
    pub fn predicted(&self, x: &[T; NI], angle: [bool; NU], fresh: bool) -> TrigState<T, NU> {
        let (mut num, mut den) = (T::zero(), T::zero());
        for i in 0..NI {
            num += (x[i] - self.x[i]) * self.xd[i];
            den += self.xd[i] * self.xd[i];
        }
        let dt = if den > T::zero() {
            num / den
        } else {
            T::zero()
        };
        let mut q = self.q;
        for k in 0..NU {
            q[k] += dt * (self.qd[k] + T::lit(0.5) * dt * self.qdd[k]);
        }
        if !q.iter().all(|v| v.is_finite()) {
            q = self.q;
        }
        if !fresh {
            return TrigState::new(q, angle);
        }
        let mut sc = self.tq;
        for k in 0..NU {
            if angle[k] {
                sc[k] = rotate(self.tq[k], q[k], self.q[k] - q[k]);
            }
        }
        TrigState::from_parts(q, sc, angle)
    }

    /// Stores the next solution in place; `fresh` tells whether its caches were rotated (they
    /// age) or recomputed.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn update(
        &mut self,
        x: &[T; NI],
        xd: &[T; NI],
        st: &TrigState<T, NU>,
        qd: [T; NU],
        qdd: [T; NU],
        points: [PointMotion<T>; NP],
        report: NewtonReport<T>,
        tx: [(T, T); NI],
        tp: [(T, T); NPAR],
        params: &[T; NPAR],
        fresh: bool,
    ) {
        self.x = *x;
        self.xd = *xd;
        self.q = st.q;
        self.tq = st.sc;
        self.qd = qd;
        self.qdd = qdd;
        self.points = points;
        self.report = report;
        self.tx = tx;
        if !fresh {
            self.tp = tp;
            self.params = *params;
        }
        self.age = if fresh { self.age + 1 } else { 0 };
    }
}
