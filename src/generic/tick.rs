//! Generic engine, its tick ([`GenericTick`], what `DynMechanism::ticker` gives): a generated
//! `Tick`'s rule on slices. The runtime's one predictor (`tick::predict`: unknowns by Taylor,
//! closed-form unknowns kept, cached sines and cosines rotated, recomputed every
//! `RESYNC_TICKS`; `tick::inputs_trig` for the inputs), then the block driver from that guess with
//! those sines and cosines, so that a tick of the interpreter or the JIT has the bits of the
//! generated tick.

use mechgen_runtime::dyn_tick::{DynTick, StateRef};
use mechgen_runtime::dynamic::{DynMechanism, DynState, len};
use mechgen_runtime::error::{Quantity, SolveError};
use mechgen_runtime::guard::BranchGuard;
use mechgen_runtime::mechanism::{BodySink, InputMotion};
use mechgen_runtime::scalar::Real;
use mechgen_runtime::solve::{NewtonReport, SolveOptions, check_finite};
use mechgen_runtime::tick::{Last, RESYNC_TICKS, inputs_trig, predict};
use mechgen_runtime::{BodyMass, Kind, MechanismInfo};

use super::driver::Rates;
use super::engine::Generic;
use super::scratch::{Scratch, Scratched};
use super::tape::Env;

/// The tick of a [`Generic`] mechanism: its state with the sines and cosines of its inputs and
/// unknowns as the next tick rotates them.
pub struct GenericTick<'a, T: Real> {
    g: &'a Generic,
    state: DynState<T>,
    /// The unknowns and their rates before the last tick (what the branch rule checks).
    before: [Vec<T>; 3],
    tx: Vec<(T, T)>,
    tq: Vec<(T, T)>,
    next_tx: Vec<(T, T)>,
    /// Ticks since the caches were computed afresh.
    age: u32,
    /// Which inputs are angles; which unknowns a closed form solves (kept by the predictor).
    input_angle: Vec<bool>,
    keep: Vec<bool>,
    all_closed: bool,
    started: bool,
}

impl<'a, T: Scratched> GenericTick<'a, T> {
    pub fn new(g: &'a Generic) -> Self {
        let info: MechanismInfo = DynMechanism::<f64>::info(g);
        let (ni, nu) = (info.inputs.len(), info.unknowns.len());
        let mut keep = vec![false; nu];
        for b in g.blocks.iter().filter(|b| b.closed.is_some()) {
            for &u in &b.unknowns {
                keep[u] = true;
            }
        }
        let zeros = vec![T::zero(); ni];
        let guess = vec![T::zero(); nu];
        GenericTick {
            g,
            state: DynState::new(
                InputMotion::new(&zeros[..], &zeros[..], &zeros[..]),
                &guess,
                info.points.len(),
            ),
            before: [guess.clone(), guess.clone(), guess],
            tx: vec![(T::zero(), T::one()); ni],
            tq: vec![(T::zero(), T::one()); nu],
            next_tx: vec![(T::zero(), T::one()); ni],
            age: 0,
            input_angle: info.inputs.iter().map(|i| i.kind == Kind::Angle).collect(),
            all_closed: keep.iter().all(|&k| k),
            keep,
            started: false,
        }
    }

    /// One tick into the workspace and, on success, the state.
    fn advance(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
        ws: &mut Scratch<T>,
    ) -> Result<(), SolveError> {
        let InputMotion { x, xd, xdd } = input;
        let s = &self.state;
        check_finite(Quantity::Input, x)?;
        check_finite(Quantity::InputRate, xd)?;
        check_finite(Quantity::InputAcceleration, xdd)?;
        let resync = self.age >= RESYNC_TICKS;
        // Every angle's entry is written; the others stay (0, 1) in both caches.
        let angle = &self.input_angle;
        inputs_trig(&self.tx, &s.x, x, angle, resync, &mut self.next_tx);
        ws.trial.resize(s.q.len(), T::zero());
        copy_few(&mut ws.trial, &s.q);
        ws.trial_sc.resize(self.tq.len(), (T::zero(), T::one()));
        copy_few(&mut ws.trial_sc, &self.tq);
        // A mechanism solved in closed form throughout starts from the last tick as it is.
        if !(options.closed_forms && self.all_closed) {
            let keep: &[bool] = if options.closed_forms {
                &self.keep
            } else {
                &[]
            };
            let last = Last {
                x: &s.x,
                xd: &s.xd,
                q: &s.q,
                qd: &s.qd,
                qdd: &s.qdd,
                tq: &self.tq,
            };
            let (q, sc) = (&mut ws.trial, &mut ws.trial_sc);
            predict(last, x, &self.g.angle, keep, resync, q, sc);
        }
        // The rates are solved into the buffers of the rates before the last tick, which swap
        // with the state's on success.
        let mut qd = std::mem::take(&mut self.before[1]);
        let mut qdd = std::mem::take(&mut self.before[2]);
        let solved = self.motion(input, options, ws, [&mut qd, &mut qdd]);
        let s = &mut self.state;
        if let Ok(report) = &solved {
            std::mem::swap(&mut s.q, &mut ws.trial);
            std::mem::swap(&mut self.before[0], &mut ws.trial);
            std::mem::swap(&mut s.qd, &mut qd);
            std::mem::swap(&mut s.qdd, &mut qdd);
            copy_few(&mut s.x, x);
            copy_few(&mut s.xd, xd);
            copy_few(&mut s.xdd, xdd);
            s.report = *report;
            std::mem::swap(&mut self.tq, &mut ws.sc);
            std::mem::swap(&mut self.tx, &mut self.next_tx);
            self.age = if resync { 0 } else { self.age + 1 };
        }
        (self.before[1], self.before[2]) = (qd, qdd);
        solved.map(|_| ())
    }

    /// The motion from the prediction in `ws.trial` (sines and cosines in `ws.trial_sc`): the
    /// compiled program where there is one, else the block driver; on success the unknowns in
    /// `ws.trial`, their sines and cosines in `ws.sc`, the rates in `qd` and `qdd`, the points
    /// in the state.
    fn motion(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
        ws: &mut Scratch<T>,
        [qd, qdd]: [&mut [T]; 2],
    ) -> Result<NewtonReport<T>, SolveError> {
        let (g, sx) = (self.g, &self.next_tx);
        // Both engines walk the mechanism's program (with closed forms on): compiled, or
        // interpreted.
        if let Some(done) = super::walk::motion(g, input, sx, options, ws, [&mut *qd, &mut *qdd]) {
            let report = done?;
            Generic::set_points(&mut self.state.points, &ws.points);
            return Ok(report);
        }
        let InputMotion { x, xd, xdd } = input;
        let report = g.positions_from(g.whole(), x, sx, options, ws)?;
        let (q, sc) = (std::mem::take(&mut ws.trial), std::mem::take(&mut ws.sc));
        let env = Env {
            xd,
            xdd,
            sc: &sc,
            sx,
            ..Env::position(x, &q, &g.params)
        };
        let solved = g
            .rates(&g.order, Rates::Both, env, qd, qdd, ws)
            .and_then(|()| {
                let env = Env {
                    qd: &*qd,
                    qdd: &*qdd,
                    ..env
                };
                let Scratch { regs, points, .. } = ws;
                g.eval_points(env, &mut self.state.points, regs, points)
            });
        (ws.trial, ws.sc) = (q, sc);
        solved.map(|()| report)
    }

    fn lengths(&self, input: InputMotion<&[T]>) -> Result<(), SolveError> {
        let n = self.state.x.len();
        len(input.x, n)?;
        len(input.xd, n)?;
        len(input.xdd, n)
    }
}

impl<T: Scratched> DynTick<T> for GenericTick<'_, T>
where
    Generic: DynMechanism<T>,
{
    fn start(
        &mut self,
        input: InputMotion<&[T]>,
        guess: &[T],
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError> {
        self.started = false;
        self.lengths(input)?;
        len(guess, self.state.q.len())?;
        let s = &mut self.state;
        s.x.copy_from_slice(input.x);
        s.xd.copy_from_slice(input.xd);
        s.xdd.copy_from_slice(input.xdd);
        s.q.copy_from_slice(guess);
        self.g.solve_in_place(s, options)?;
        // The caches afresh, as a generated tick's start makes them.
        for ((t, x), &angle) in self.tx.iter_mut().zip(&s.x).zip(&self.input_angle) {
            *t = if angle {
                x.sin_cos()
            } else {
                (T::zero(), T::one())
            };
        }
        for ((t, q), &angle) in self.tq.iter_mut().zip(&s.q).zip(&self.g.angle) {
            *t = if angle {
                q.sin_cos()
            } else {
                (T::zero(), T::one())
            };
        }
        self.age = 0;
        self.started = true;
        Ok(())
    }

    fn tick(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError> {
        if !self.started {
            return Err(SolveError::NotStarted);
        }
        self.lengths(input)?;
        T::with_scratch(|ws| self.advance(input, options, ws))
    }

    fn tick_checked(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
        guard: &BranchGuard,
        dt: T,
        before: &mut [T],
    ) -> Result<bool, SolveError> {
        self.tick(input, options)?;
        let [q, qd, qdd] = &self.before;
        len(before, q.len())?;
        before.copy_from_slice(q);
        Ok(guard.keeps(q, qd, qdd, dt, &self.state.q))
    }

    fn state(&self) -> Option<StateRef<'_, T>> {
        self.started.then(|| self.state.view())
    }

    /// The tick, then gravity and every body at its state, on the sines and cosines it keeps (as
    /// a generated tick computes them in its own body: the same values).
    fn tick_with_sink(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
        sink: &mut dyn BodySink<T>,
    ) -> Result<bool, SolveError> {
        self.tick(input, options)?;
        let (g, s) = (self.g, &self.state);
        let env = Env {
            xd: &s.xd,
            qd: &s.qd,
            xdd: &s.xdd,
            qdd: &s.qdd,
            sc: &self.tq,
            sx: &self.tx,
            ..Env::position(&s.x, &s.q, &g.params)
        };
        T::with_scratch(|ws| {
            let Scratch {
                regs,
                out: m,
                points: b,
                ..
            } = ws;
            m.resize(g.masses.outputs(), T::zero());
            g.masses
                .eval(&Env::position(&[], &[], &g.params), regs, m)?;
            b.resize(g.bodies.outputs(), T::zero());
            g.bodies.eval(&env, regs, b)?;
            let (gravity, m) = if g.gravity {
                ([m[0], m[1]], &m[2..])
            } else {
                ([T::zero(); 2], &m[..])
            };
            sink.gravity(gravity);
            for (k, (m, c)) in m.chunks_exact(2).zip(b.chunks_exact(9)).enumerate() {
                let mass = BodyMass {
                    mass: m[0],
                    inertia: m[1],
                };
                sink.body(k, mass, Generic::body_motion(c));
            }
            Ok(true)
        })
    }
}

/// `dst = src` for slices of the same length (a tick's inputs and unknowns, a few values each):
/// up to four by plain moves, where a call of `memcpy` costs more than the copy.
#[inline(always)]
fn copy_few<U: Copy>(dst: &mut [U], src: &[U]) {
    match (dst, src) {
        ([d], [a]) => *d = *a,
        ([d, e], [a, b]) => (*d, *e) = (*a, *b),
        ([d, e, f], [a, b, c]) => (*d, *e, *f) = (*a, *b, *c),
        ([d, e, f, g], [a, b, c, h]) => (*d, *e, *f, *g) = (*a, *b, *c, *h),
        (dst, src) => dst.copy_from_slice(src),
    }
}
