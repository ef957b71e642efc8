//! [`LaneTick`]: the state of W instances between simulator ticks, in lanes, and the driver
//! that moves it: the common path of a tick in lanes (the generated `motion_lanes`), then every
//! lane that left it ticked again by the scalar tick from its unchanged state.

// Index loops over several parallel arrays read better than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use core::ops::Deref;

use super::{LaneReport, LaneTrig, Lanes};
use crate::error::SolveError;
use crate::info::PointMotion;
use crate::mechanism::State;
use crate::scalar::Real;
use crate::solve::NewtonReport;
use crate::tick::{RESYNC_TICKS, Tick};
use num_traits::Zero;

/// A fresh id for a set of lane params (never 0): a generated `Lanes` takes one whenever its
/// params are made or changed, so a tick that saw them needs not compare them again.
pub fn fresh_params_id() -> usize {
    static NEXT: core::sync::atomic::AtomicUsize = core::sync::atomic::AtomicUsize::new(1);
    NEXT.fetch_add(1, core::sync::atomic::Ordering::Relaxed)
}

/// The solved state of W instances after a lane tick: inputs, unknowns, rates and points in
/// lanes (lane `i` of each is instance `i`) and the last position solve's smallest pivot ratio
/// (the condition estimate of [`NewtonReport`]). Each instance's whole report and the status of
/// its last tick: [`LaneTick::report`], [`LaneTick::status`].
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct LaneState<L: Lanes, const NI: usize, const NU: usize, const NP: usize> {
    pub x: [L; NI],
    pub xd: [L; NI],
    pub xdd: [L; NI],
    pub q: [L; NU],
    pub qd: [L; NU],
    pub qdd: [L; NU],
    pub points: [PointMotion<L>; NP],
    pub pivot_ratio: L,
}

/// The state of W instances of a mechanism between ticks: what [`Tick`] is for one, in lanes
/// (it reads as its [`LaneState`]; [`LaneTick::lane`] gives instance `i` as a scalar [`Tick`]).
/// Made by a generated `Lanes::tick_start` and moved by `Lanes::tick`. `M` is what a scalar
/// tick state holds besides a [`Tick`] (a scene's rate history, [`crate::SceneMemo`]; `()` for
/// a mechanism), kept per lane for the ticks that run in scalar.
// `repr(C)`: what every tick reads and writes first, the caches it reads rarely (the params and
// their sines and cosines, the statuses) last, so that a fleet's ticks touch few cache lines.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct LaneTick<
    L: Lanes,
    const NI: usize,
    const NU: usize,
    const NP: usize,
    const NPAR: usize,
    M: Memo = (),
> {
    state: LaneState<L, NI, NU, NP>,
    tx: [(L, L); NI],
    tq: [(L, L); NU],
    age: L::Array<u32>,
    /// Bits of the lanes whose status is an error, that have started, and whose `iterations`
    /// or `residual` may be non-zero.
    failed: u32,
    started: u32,
    scalar_report: u32,
    /// The id of the `Lanes` whose params every lane's `params` equal (0: none known).
    params_id: usize,
    /// The rest of each lane's report (zero after the common path).
    iterations: L::Array<u32>,
    residual: L,
    /// Each lane's last status.
    status: L::Array<Result<(), SolveError>>,
    tp: [(L, L); NPAR],
    params: [L; NPAR],
    memo: L::Array<M>,
}

impl<L: Lanes, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize, M: Memo> Deref
    for LaneTick<L, NI, NU, NP, NPAR, M>
{
    type Target = LaneState<L, NI, NU, NP>;
    fn deref(&self) -> &Self::Target {
        &self.state
    }
}

/// What the common path of a lane tick reads besides the unknowns (as `Fixed` for one).
#[derive(Clone, Copy, Debug)]
pub struct LaneFixed<'a, L, const NI: usize, const NPAR: usize> {
    pub x: &'a [L; NI],
    pub xd: &'a [L; NI],
    pub xdd: &'a [L; NI],
    pub tx: &'a [(L, L); NI],
    pub tp: &'a [(L, L); NPAR],
}

/// The rates and points of a lane tick's common path: `(q̇, q̈, points)`.
pub type LaneRates<L, const NU: usize, const NP: usize> = ([L; NU], [L; NU], [PointMotion<L>; NP]);

impl<L: Lanes, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize, M: Memo>
    LaneTick<L, NI, NU, NP, NPAR, M>
{
    /// The status of lane `i`'s last tick: `Ok`, or its error (the lane then keeps the state of
    /// its last successful tick, or its guess when it never started); `BadLength` for `i ≥ W`.
    pub fn status(&self, i: usize) -> Result<(), SolveError> {
        match self.status.as_ref().get(i) {
            Some(s) => *s,
            None => Err(SolveError::BadLength {
                expected: L::W,
                got: i,
            }),
        }
    }

    /// Whether lane `i` has a solved state (its `tick_start` or a later tick succeeded).
    pub fn started(&self, i: usize) -> bool {
        i < L::W && self.started >> i & 1 == 1
    }

    /// Lane `i`'s last position solve report (`None` for `i ≥ W`).
    pub fn report(&self, i: usize) -> Option<NewtonReport<L::Scalar>> {
        (i < L::W).then(|| self.report_of(i))
    }

    /// [`LaneTick::report`] of a lane `i < W`.
    fn report_of(&self, i: usize) -> NewtonReport<L::Scalar> {
        NewtonReport {
            iterations: self.iterations.as_ref()[i],
            residual: self.residual.lane(i),
            pivot_ratio: self.state.pivot_ratio.lane(i),
        }
    }

    /// Instance `i` as a scalar tick: its state and caches, exactly as the scalar `tick` would
    /// have left them (`None` for `i ≥ W`).
    pub fn lane(&self, i: usize) -> Option<Tick<L::Scalar, NI, NU, NP, NPAR>> {
        (i < L::W).then(|| self.lane_of(i))
    }

    /// [`LaneTick::lane`] of a lane `i < W`.
    fn lane_of(&self, i: usize) -> Tick<L::Scalar, NI, NU, NP, NPAR> {
        let s = &self.state;
        let one = |v: &[L; NI]| core::array::from_fn(|k| v[k].lane(i));
        let un = |v: &[L; NU]| core::array::from_fn(|k| v[k].lane(i));
        let pair = |(a, b): (L, L)| (a.lane(i), b.lane(i));
        let at = |v: [L; 2]| [v[0].lane(i), v[1].lane(i)];
        Tick {
            state: State {
                x: one(&s.x),
                xd: one(&s.xd),
                xdd: one(&s.xdd),
                q: un(&s.q),
                qd: un(&s.qd),
                qdd: un(&s.qdd),
                points: core::array::from_fn(|p| PointMotion {
                    position: at(s.points[p].position),
                    velocity: at(s.points[p].velocity),
                    acceleration: at(s.points[p].acceleration),
                }),
                report: self.report_of(i),
            },
            tx: core::array::from_fn(|k| pair(self.tx[k])),
            tq: core::array::from_fn(|k| pair(self.tq[k])),
            tp: core::array::from_fn(|k| pair(self.tp[k])),
            params: core::array::from_fn(|k| self.params[k].lane(i)),
            age: self.age.as_ref()[i],
        }
    }

    /// What lane `i` holds besides its [`Tick`] (`None` for `i ≥ W`).
    pub fn memo(&self, i: usize) -> Option<M> {
        self.memo.as_ref().get(i).copied()
    }

    /// Sets instance `i < W` to the scalar tick `t` (started, status `Ok`).
    fn set_lane(&mut self, i: usize, t: &Tick<L::Scalar, NI, NU, NP, NPAR>) {
        self.store_lane(i, t);
        self.status.as_mut()[i] = Ok(());
        self.failed &= !(1 << i);
        self.started |= 1 << i;
    }

    /// Writes the state and caches of the scalar tick `t` into instance `i < W` (its status and
    /// whether it started are the caller's).
    fn store_lane(&mut self, i: usize, t: &Tick<L::Scalar, NI, NU, NP, NPAR>) {
        let s = &mut self.state;
        let set = |dst: &mut [L], src: &[L::Scalar]| {
            for (d, v) in dst.iter_mut().zip(src) {
                d.set_lane(i, *v);
            }
        };
        set(&mut s.x, &t.state.x);
        set(&mut s.xd, &t.state.xd);
        set(&mut s.xdd, &t.state.xdd);
        set(&mut s.q, &t.state.q);
        set(&mut s.qd, &t.state.qd);
        set(&mut s.qdd, &t.state.qdd);
        for (d, p) in s.points.iter_mut().zip(&t.state.points) {
            set(&mut d.position, &p.position);
            set(&mut d.velocity, &p.velocity);
            set(&mut d.acceleration, &p.acceleration);
        }
        let r = t.state.report;
        s.pivot_ratio.set_lane(i, r.pivot_ratio);
        self.residual.set_lane(i, r.residual);
        self.iterations.as_mut()[i] = r.iterations;
        self.scalar_report |= 1 << i;
        let pairs = |dst: &mut [(L, L)], src: &[(L::Scalar, L::Scalar)]| {
            for (d, v) in dst.iter_mut().zip(src) {
                d.0.set_lane(i, v.0);
                d.1.set_lane(i, v.1);
            }
        };
        pairs(&mut self.tx, &t.tx);
        pairs(&mut self.tq, &t.tq);
        pairs(&mut self.tp, &t.tp);
        set(&mut self.params, &t.params);
        self.age.as_mut()[i] = t.age;
    }
}

/// What a lane keeps besides its [`Tick`] (`()`, or a scene's [`crate::SceneMemo`]).
pub trait Memo: Copy + core::fmt::Debug + Send + Sync + Default {}

impl<M: Copy + core::fmt::Debug + Send + Sync + Default> Memo for M {}

/// A scalar tick of lane `i`: `started` says whether `t` (with the lane's memo) holds a solved
/// state (then `tick` it to the inputs) or only the guess `t.q` (then `tick_start` from it into
/// `t`).
pub trait ScalarLane<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize, M>:
    FnMut(usize, &mut Tick<T, NI, NU, NP, NPAR>, &mut M, bool, [&[T; NI]; 3]) -> Result<(), SolveError>
{
}

impl<T, F, M, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>
    ScalarLane<T, NI, NU, NP, NPAR, M> for F
where
    F: FnMut(
        usize,
        &mut Tick<T, NI, NU, NP, NPAR>,
        &mut M,
        bool,
        [&[T; NI]; 3],
    ) -> Result<(), SolveError>,
{
}

/// Lane `i` of each of `v`.
fn lane_of<L: Lanes, const N: usize>(v: &[L; N], i: usize) -> [L::Scalar; N] {
    core::array::from_fn(|k| v[k].lane(i))
}

/// The first tick of W instances: each lane started by the scalar `tick_start` from its guess
/// (`scalar` with `started` false). A lane that fails keeps its guess and its error, and starts
/// again on the next tick.
pub fn tick_start<
    L: Lanes,
    const NI: usize,
    const NU: usize,
    const NP: usize,
    const NPAR: usize,
    M: Memo,
>(
    [x, xd, xdd]: [&[L; NI]; 3],
    guess: &[L; NU],
    mut scalar: impl ScalarLane<L::Scalar, NI, NU, NP, NPAR, M>,
) -> LaneTick<L, NI, NU, NP, NPAR, M> {
    let zero = L::zero();
    let unit = (zero, L::one());
    let mut t = LaneTick {
        state: LaneState {
            x: *x,
            xd: *xd,
            xdd: *xdd,
            q: *guess,
            qd: [zero; NU],
            qdd: [zero; NU],
            points: [PointMotion {
                position: [zero; 2],
                velocity: [zero; 2],
                acceleration: [zero; 2],
            }; NP],
            pivot_ratio: L::one(),
        },
        tx: [unit; NI],
        tq: [unit; NU],
        tp: [unit; NPAR],
        params: [zero; NPAR],
        params_id: 0,
        age: L::array(|_| 0),
        iterations: L::array(|_| 0),
        residual: zero,
        status: L::array(|_| Ok(())),
        failed: 0,
        started: 0,
        scalar_report: 0,
        memo: L::array(|_| M::default()),
    };
    for i in 0..L::W {
        restart(&mut t, i, [x, xd, xdd], &mut scalar);
    }
    t
}

/// Lane `i` ticked (or started) by the scalar tick; its status set. Off the common path.
#[cold]
#[inline(never)]
fn restart<
    L: Lanes,
    const NI: usize,
    const NU: usize,
    const NP: usize,
    const NPAR: usize,
    M: Memo,
>(
    t: &mut LaneTick<L, NI, NU, NP, NPAR, M>,
    i: usize,
    [x, xd, xdd]: [&[L; NI]; 3],
    scalar: &mut impl ScalarLane<L::Scalar, NI, NU, NP, NPAR, M>,
) {
    let mut s = t.lane_of(i);
    let mut memo = t.memo.as_ref()[i];
    let (xi, xdi, xddi) = (lane_of(x, i), lane_of(xd, i), lane_of(xdd, i));
    let started = t.started(i);
    let r = scalar(i, &mut s, &mut memo, started, [&xi, &xdi, &xddi]);
    t.memo.as_mut()[i] = memo;
    match r {
        Ok(()) => t.set_lane(i, &s),
        Err(e) => {
            // What the scalar tick leaves on error (a scene's tick may have made a skipped
            // angle whole before it failed), as the scalar tick state would hold it.
            if started {
                t.store_lane(i, &s);
            }
            t.status.as_mut()[i] = Err(e);
            t.failed |= 1 << i;
        }
    }
}

/// What a lane tick needs to know of the mechanism (or scene) besides its values, as constant
/// masks: the params it compares (a scene: those it reads), the inputs and unknowns that are
/// angles read through their sines and cosines, and the unknowns a tick predicts (those Newton
/// solves; a closed form's keep the last tick's value).
#[derive(Clone, Copy, Debug)]
pub struct LaneShape<const NI: usize, const NU: usize, const NPAR: usize> {
    pub read: [bool; NPAR],
    pub angle_x: [bool; NI],
    pub angle_q: [bool; NU],
    pub predict: [bool; NU],
}

/// One tick of W instances to the inputs `x` (rates `xd`, `xdd`), with the params `params` (in
/// lanes, in the order of the mechanism's param array) and the mechanism's `shape`. `fast` is the
/// common path of the mechanism's tick in lanes (`None` where it has none): from the last tick's
/// unknowns (Newton's predicted as the scalar predicts them) it solves every block and the
/// rates and points, clearing in the mask each lane that leaves the common path. Each lane that
/// was not started, saw new params or non-finite inputs, or that `fast` cleared is ticked by
/// `scalar` from its state before this tick; the others store the common path's results. Every
/// lane ends with the scalar tick's result or error.
pub fn tick<
    L: Lanes,
    const NI: usize,
    const NU: usize,
    const NP: usize,
    const NPAR: usize,
    M: Memo,
>(
    t: &mut LaneTick<L, NI, NU, NP, NPAR, M>,
    (params, params_id): (&[L; NPAR], usize),
    [x, xd, xdd]: [&[L; NI]; 3],
    shape: &LaneShape<NI, NU, NPAR>,
    fast: Option<
        impl FnOnce(
            LaneFixed<'_, L, NI, NPAR>,
            &mut LaneTrig<L, NU>,
            &mut LaneReport<L>,
            &mut L::Mask,
        ) -> LaneRates<L, NU, NP>,
    >,
    mut scalar: impl ScalarLane<L::Scalar, NI, NU, NP, NPAR, M>,
) {
    let read = shape.read;
    let all = L::all_bits();
    let stale = all & !t.started;
    let mut due = 0u32;
    for i in 0..L::W {
        due |= u32::from(t.age.as_ref()[i] >= RESYNC_TICKS) << i;
    }
    // One mask for every test, turned into bits once.
    let mut ok = !L::mask(stale);
    for v in x.iter().chain(xd).chain(xdd) {
        ok = ok & v.is_finite();
    }
    // `params_id` names params that every lane's stored ones equal: nothing to compare.
    let known = params_id != 0 && t.params_id == params_id;
    if !known {
        for k in (0..NPAR).filter(|&k| read[k]) {
            ok = ok & params[k].eq(t.params[k]);
        }
    }
    let mut bad = all;
    if let Some(fast) = fast.filter(|_| stale != all) {
        let tx = super::rotate_inputs(&t.tx, &t.state.x, x, shape.angle_x, L::mask(due));
        let mut st = predicted(t, x, shape, L::mask(due));
        let mut report = LaneReport::new();
        let fixed = LaneFixed {
            x,
            xd,
            xdd,
            tx: &tx,
            tp: &t.tp,
        };
        let (qd, qdd, points) = fast(fixed, &mut st, &mut report, &mut ok);
        bad = all & !L::bits(ok);
        let good = all & !bad;
        if good != 0 {
            store(
                t,
                good,
                [x, xd, xdd],
                &st,
                (qd, qdd, points, report.pivot_ratio),
                tx,
            );
            if shape.predict.iter().any(|&p| p) {
                // Newton's report, lane by lane.
                for i in (0..L::W).filter(|i| good >> i & 1 == 1) {
                    t.iterations.as_mut()[i] = report.iterations.lane(i).to_f64() as u32;
                }
                t.residual = L::select(L::mask(good), report.residual, t.residual);
            } else {
                // The report of a closed-form solve: no iterations, no residual.
                for i in (0..L::W).filter(|i| (good & t.scalar_report) >> i & 1 == 1) {
                    t.iterations.as_mut()[i] = 0;
                    t.residual.set_lane(i, L::Scalar::zero());
                }
            }
            t.scalar_report &= !good;
            for i in (0..L::W).filter(|i| (good & t.failed) >> i & 1 == 1) {
                t.status.as_mut()[i] = Ok(());
            }
            t.failed &= !good;
            for i in 0..L::W {
                // As the scalar `update`: the caches start again after a resync.
                if good >> i & 1 == 1 {
                    let age = &mut t.age.as_mut()[i];
                    *age = if due >> i & 1 == 1 { 0 } else { *age + 1 };
                }
            }
        }
    }
    for i in (0..L::W).filter(|i| bad >> i & 1 == 1) {
        restart(t, i, [x, xd, xdd], &mut scalar);
    }
    if !known && params_id != 0 {
        let mut same = L::mask(all);
        for k in (0..NPAR).filter(|&k| read[k]) {
            same = same & params[k].eq(t.params[k]);
        }
        if L::bits(same) == all {
            t.params_id = params_id;
        }
    }
}

/// The guess of a lane tick, as the scalar tick's `predicted` makes it for lanes with the same
/// params: the unknowns with `shape.predict` moved along their last rates over the time the
/// inputs took (`step_to`), their sines and cosines rotated (afresh in the lanes of `fresh`);
/// a lane whose prediction is not finite keeps its last unknowns. The others as they were.
#[inline(always)]
fn predicted<
    L: Lanes,
    const NI: usize,
    const NU: usize,
    const NP: usize,
    const NPAR: usize,
    M: Memo,
>(
    t: &LaneTick<L, NI, NU, NP, NPAR, M>,
    x: &[L; NI],
    shape: &LaneShape<NI, NU, NPAR>,
    fresh: L::Mask,
) -> LaneTrig<L, NU> {
    let s = &t.state;
    let mut st = LaneTrig { q: s.q, sc: t.tq };
    if !shape.predict.iter().any(|&p| p) {
        return st;
    }
    let zero = L::zero();
    let (mut num, mut den) = (zero, zero);
    for i in 0..NI {
        num = num + (x[i] - s.x[i]) * s.xd[i];
        den = den + s.xd[i] * s.xd[i];
    }
    let dt = L::select(den.gt(zero), num / den, zero);
    let mut finite = L::mask(L::all_bits());
    for k in 0..NU {
        if shape.predict[k] {
            st.q[k] = st.q[k] + dt * (s.qd[k] + L::lit(0.5) * dt * s.qdd[k]);
        }
        finite = finite & st.q[k].is_finite();
    }
    for k in 0..NU {
        st.q[k] = L::select(finite, st.q[k], s.q[k]);
        if shape.predict[k] && shape.angle_q[k] {
            st.sc[k] = super::rotate(t.tq[k], st.q[k], s.q[k] - st.q[k], fresh);
        }
    }
    st
}

/// Stores the common path's results in the lanes with a bit in `good` (all of them: plain
/// stores; some: a select per value).
#[inline(always)]
fn store<
    L: Lanes,
    const NI: usize,
    const NU: usize,
    const NP: usize,
    const NPAR: usize,
    M: Memo,
>(
    t: &mut LaneTick<L, NI, NU, NP, NPAR, M>,
    good: u32,
    [x, xd, xdd]: [&[L; NI]; 3],
    st: &LaneTrig<L, NU>,
    (qd, qdd, points, pivot): ([L; NU], [L; NU], [PointMotion<L>; NP], L),
    tx: [(L, L); NI],
) {
    let s = &mut t.state;
    if good == L::all_bits() {
        (s.x, s.xd, s.xdd) = (*x, *xd, *xdd);
        (s.q, s.qd, s.qdd, s.points) = (st.q, qd, qdd, points);
        s.pivot_ratio = pivot;
        (t.tx, t.tq) = (tx, st.sc);
        return;
    }
    let m = L::mask(good);
    s.pivot_ratio = L::select(m, pivot, s.pivot_ratio);
    let merge = |dst: &mut [L], src: &[L]| {
        for (d, s) in dst.iter_mut().zip(src) {
            *d = L::select(m, *s, *d);
        }
    };
    merge(&mut s.x, x);
    merge(&mut s.xd, xd);
    merge(&mut s.xdd, xdd);
    merge(&mut s.q, &st.q);
    merge(&mut s.qd, &qd);
    merge(&mut s.qdd, &qdd);
    for (d, p) in s.points.iter_mut().zip(&points) {
        merge(&mut d.position, &p.position);
        merge(&mut d.velocity, &p.velocity);
        merge(&mut d.acceleration, &p.acceleration);
    }
    let pairs = |dst: &mut [(L, L)], src: &[(L, L)]| {
        for (d, s) in dst.iter_mut().zip(src) {
            *d = (L::select(m, s.0, d.0), L::select(m, s.1, d.1));
        }
    };
    pairs(&mut t.tx, &tx);
    pairs(&mut t.tq, &st.sc);
}
