//! [`LaneTick`]: the state of W instances between simulator ticks, in lanes (what a [`Tick`] is
//! for one), with each lane's status, report and memo; moved by the driver in `tick.rs`.

use core::ops::Deref;

use super::Lanes;
use crate::error::SolveError;
use crate::info::PointMotion;
use crate::mechanism::State;
use crate::solve::NewtonReport;
use crate::tick::Tick;

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
    pub(super) state: LaneState<L, NI, NU, NP>,
    pub(super) tx: [(L, L); NI],
    pub(super) tq: [(L, L); NU],
    pub(super) age: L::Array<u32>,
    /// Bits of the lanes whose status is an error, that have started, and whose `iterations`
    /// or `residual` may be non-zero.
    pub(super) failed: u32,
    pub(super) started: u32,
    pub(super) scalar_report: u32,
    /// The id of the `Lanes` whose params every lane's `params` equal (0: none known).
    pub(super) params_id: usize,
    /// The rest of each lane's report (zero after the common path).
    pub(super) iterations: L::Array<u32>,
    pub(super) residual: L,
    /// Each lane's last status.
    pub(super) status: L::Array<Result<(), SolveError>>,
    pub(super) tp: [(L, L); NPAR],
    pub(super) params: [L; NPAR],
    pub(super) memo: L::Array<M>,
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
    pub(super) fn lane_of(&self, i: usize) -> Tick<L::Scalar, NI, NU, NP, NPAR> {
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

    /// Takes `params_id` (not 0) as the id of the params every lane holds when each lane's
    /// params (those in `read`) equal `params`, so that the next tick need not compare them.
    pub(super) fn learn_params_id(
        &mut self,
        params: &[L; NPAR],
        params_id: usize,
        read: [bool; NPAR],
    ) {
        if params_id == 0 {
            return;
        }
        let all = L::all_bits();
        let mut same = L::mask(all);
        for k in (0..NPAR).filter(|&k| read[k]) {
            same = same & params[k].eq(self.params[k]);
        }
        if L::bits(same) == all {
            self.params_id = params_id;
        }
    }

    /// Sets instance `i < W` to the scalar tick `t` (started, status `Ok`).
    pub(super) fn set_lane(&mut self, i: usize, t: &Tick<L::Scalar, NI, NU, NP, NPAR>) {
        self.store_lane(i, t);
        self.status.as_mut()[i] = Ok(());
        self.failed &= !(1 << i);
        self.started |= 1 << i;
    }

    /// Writes the state and caches of the scalar tick `t` into instance `i < W` (its status and
    /// whether it started are the caller's).
    pub(super) fn store_lane(&mut self, i: usize, t: &Tick<L::Scalar, NI, NU, NP, NPAR>) {
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

/// What a sweep reads of W instances after a lane tick, without making their scalar ticks: the
/// [`LaneMechanism::Tick`](crate::LaneMechanism::Tick) of every generated mechanism and scene.
pub trait LaneView<L: Lanes> {
    /// The unknowns, their rates and their accelerations, in lanes.
    fn lanes_q(&self) -> (&[L], &[L], &[L]);
    /// The bits of the lanes whose last tick succeeded.
    fn ok_bits(&self) -> u32;
    /// Instance `i`'s last status and its condition estimate (what its scalar tick's
    /// [`NewtonReport::condition`] gives); `BadLength` and ∞ for `i ≥ W`.
    fn lane_status(&self, i: usize) -> (Result<(), SolveError>, L::Scalar);
    /// Every instance's unknowns, rates, accelerations and points at once: instance `i`'s
    /// unknowns at `q[i·NU..]` (rates, accelerations likewise) and its points at
    /// `points[i·NP..]`; slices of W·NU and W·NP values (nothing written otherwise).
    fn all_numbers(
        &self,
        q: &mut [L::Scalar],
        qd: &mut [L::Scalar],
        qdd: &mut [L::Scalar],
        points: &mut [PointMotion<L::Scalar>],
    );
    /// Instance `i`'s unknowns, their rates and accelerations and its points, each written into
    /// the slice given, up to its length (nothing for `i ≥ W`).
    fn lane_numbers(
        &self,
        i: usize,
        q: &mut [L::Scalar],
        qd: &mut [L::Scalar],
        qdd: &mut [L::Scalar],
        points: &mut [PointMotion<L::Scalar>],
    );
}

impl<L: Lanes, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize, M: Memo>
    LaneView<L> for LaneTick<L, NI, NU, NP, NPAR, M>
{
    fn lanes_q(&self) -> (&[L], &[L], &[L]) {
        (&self.state.q, &self.state.qd, &self.state.qdd)
    }

    #[inline]
    fn all_numbers(
        &self,
        q: &mut [L::Scalar],
        qd: &mut [L::Scalar],
        qdd: &mut [L::Scalar],
        points: &mut [PointMotion<L::Scalar>],
    ) {
        let w = L::W;
        if q.len() != w * NU || qd.len() != w * NU || qdd.len() != w * NU || points.len() != w * NP
        {
            return;
        }
        let s = &self.state;
        for k in 0..NU {
            let (a, b, c) = (s.q[k], s.qd[k], s.qdd[k]);
            for i in 0..w {
                q[i * NU + k] = a.lane(i);
                qd[i * NU + k] = b.lane(i);
                qdd[i * NU + k] = c.lane(i);
            }
        }
        for (k, p) in s.points.iter().enumerate() {
            for i in 0..w {
                let at = |v: [L; 2]| [v[0].lane(i), v[1].lane(i)];
                points[i * NP + k] = PointMotion {
                    position: at(p.position),
                    velocity: at(p.velocity),
                    acceleration: at(p.acceleration),
                };
            }
        }
    }

    fn ok_bits(&self) -> u32 {
        let ok = self.status.as_ref().iter().enumerate();
        ok.filter(|(_, s)| s.is_ok())
            .fold(0, |m, (i, _)| m | 1 << i)
    }

    fn lane_status(&self, i: usize) -> (Result<(), SolveError>, L::Scalar) {
        match self.report(i) {
            Some(r) => (self.status(i), r.condition()),
            None => (self.status(i), crate::scalar::Real::lit(f64::INFINITY)),
        }
    }

    fn lane_numbers(
        &self,
        i: usize,
        q: &mut [L::Scalar],
        qd: &mut [L::Scalar],
        qdd: &mut [L::Scalar],
        points: &mut [PointMotion<L::Scalar>],
    ) {
        if i >= L::W {
            return;
        }
        let s = &self.state;
        for (d, v) in q.iter_mut().zip(&s.q) {
            *d = v.lane(i);
        }
        for (d, v) in qd.iter_mut().zip(&s.qd) {
            *d = v.lane(i);
        }
        for (d, v) in qdd.iter_mut().zip(&s.qdd) {
            *d = v.lane(i);
        }
        for (d, p) in points.iter_mut().zip(&s.points) {
            let at = |v: [L; 2]| [v[0].lane(i), v[1].lane(i)];
            *d = PointMotion {
                position: at(p.position),
                velocity: at(p.velocity),
                acceleration: at(p.acceleration),
            };
        }
    }
}
