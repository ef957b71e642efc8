//! The lane tick driver: the common path of a tick in lanes (the generated `motion_lanes`), then
//! every lane that left it ticked again by the scalar tick from its unchanged state.

// Index loops over several parallel arrays read better than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use super::state::{LaneFixed, LaneRates, LaneTick, Memo};
use super::{LaneReport, LaneTrig, Lanes};
use crate::error::SolveError;
use crate::info::PointMotion;
use crate::scalar::Real;
use crate::tick::{RESYNC_TICKS, Tick};
use num_traits::Zero;

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

/// The common path of a tick in lanes (the generated `motion_lanes`): from the unknowns and their
/// sines and cosines in `st` it solves every block and the rates and points, clearing in the mask
/// each lane that leaves it.
pub trait LanePath<L: Lanes, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>:
    Fn(
    LaneFixed<'_, L, NI, NPAR>,
    &mut LaneTrig<L, NU>,
    &mut LaneReport<L>,
    &mut L::Mask,
) -> LaneRates<L, NU, NP>
{
}

impl<L: Lanes, F, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>
    LanePath<L, NI, NU, NP, NPAR> for F
where
    F: Fn(
        LaneFixed<'_, L, NI, NPAR>,
        &mut LaneTrig<L, NU>,
        &mut LaneReport<L>,
        &mut L::Mask,
    ) -> LaneRates<L, NU, NP>,
{
}

/// Lane `i` ticked (or started) by the scalar tick; its status set. Off the common path.
#[cold]
#[inline(never)]
pub(super) fn restart<
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
    let lane_of = |v: &[L; NI]| -> [L::Scalar; NI] { core::array::from_fn(|k| v[k].lane(i)) };
    let (xi, xdi, xddi) = (lane_of(x), lane_of(xd), lane_of(xdd));
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
/// masks: the params it compares (a scene: those it reads), the inputs, unknowns and params that
/// are angles read through their sines and cosines, and the unknowns a tick predicts (those Newton
/// solves; a closed form's keep the last tick's value).
#[derive(Clone, Copy, Debug)]
pub struct LaneShape<const NI: usize, const NU: usize, const NPAR: usize> {
    pub read: [bool; NPAR],
    pub angle_x: [bool; NI],
    pub angle_q: [bool; NU],
    pub angle_p: [bool; NPAR],
    pub predict: [bool; NU],
}

/// One tick of W instances to the inputs `x` (rates `xd`, `xdd`), with the params `params` (in
/// lanes, in the order of the mechanism's param array) and the mechanism's `shape`. `fast` is the
/// common path of the mechanism's tick in lanes (`None` where it has none): from the last tick's
/// unknowns (Newton's predicted as the scalar predicts them) it solves every block and the
/// rates and points, clearing in the mask each lane that leaves the common path. Each lane that
/// was not started, saw new params or non-finite inputs, or that `fast` cleared is ticked by
/// `scalar` from its state before this tick; the others store the common path's results. Every
/// lane ends with the scalar tick's result or error. Inlined always, so that a kernel run by
/// [`dispatch`](crate::simd::dispatch) compiles it with the CPU's widest vectors.
#[inline(always)]
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
    fast: Option<impl LanePath<L, NI, NU, NP, NPAR>>,
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
            } else if good & t.scalar_report != 0 {
                // The report of a closed-form solve: no iterations, no residual.
                for i in (0..L::W).filter(|i| (good & t.scalar_report) >> i & 1 == 1) {
                    t.iterations.as_mut()[i] = 0;
                    t.residual.set_lane(i, L::Scalar::zero());
                }
            }
            t.scalar_report &= !good;
            if good & t.failed != 0 {
                for i in (0..L::W).filter(|i| (good & t.failed) >> i & 1 == 1) {
                    t.status.as_mut()[i] = Ok(());
                }
            }
            t.failed &= !good;
            // As the scalar `update`: a lane's caches start again after a resync.
            if good == all && due == 0 {
                // The common case, in one vector operation.
                for age in t.age.as_mut() {
                    *age += 1;
                }
            } else {
                for (i, age) in t.age.as_mut().iter_mut().enumerate() {
                    let (g, d) = (good >> i & 1, due >> i & 1);
                    *age = if g & d == 1 { 0 } else { *age + g };
                }
            }
        }
    }
    if bad != 0 {
        for i in (0..L::W).filter(|i| bad >> i & 1 == 1) {
            restart(t, i, [x, xd, xdd], &mut scalar);
        }
    }
    if !known {
        t.learn_params_id(params, params_id, read);
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
pub(super) fn store<
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
        // Field by field (a tuple would be built first, then copied).
        s.x = *x;
        s.xd = *xd;
        s.xdd = *xdd;
        s.q = st.q;
        s.qd = qd;
        s.qdd = qdd;
        s.points = points;
        s.pivot_ratio = pivot;
        t.tx = tx;
        t.tq = st.sc;
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
