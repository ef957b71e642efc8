//! Generic engine, its tick ([`GenericTick`], what `DynMechanism::ticker` gives): a generated
//! `Tick`'s rule on slices. The runtime's one predictor (`tick::predict`: unknowns by Taylor,
//! closed-form unknowns kept, cached sines and cosines rotated, recomputed every
//! `RESYNC_TICKS`; `tick::inputs_trig` for the inputs), then the motion from that guess with
//! those sines and cosines (the compiled program, the walked one or the block driver), so that a
//! tick of the interpreter or the JIT has the bits of the generated tick.
//!
//! The tick keeps two states: its own and the one before it. A tick predicts from its state into
//! the other, solves there in place and, on success, makes it its own (no copies, no swaps of
//! buffers); on failure the other is left half-written and its state is unchanged. The state
//! before (the branch rule's) is the other one.

use mechgen_runtime::dyn_tick::{DynTick, StateRef};
use mechgen_runtime::dynamic::{DynMechanism, DynState, len};
use mechgen_runtime::error::SolveError;
use mechgen_runtime::guard::BranchGuard;
use mechgen_runtime::mechanism::{BodySink, InputMotion};
use mechgen_runtime::scalar::Real;
use mechgen_runtime::solve::{NewtonReport, SolveOptions, check_inputs};
use mechgen_runtime::tick::{Last, RESYNC_TICKS, inputs_trig, predict};
use mechgen_runtime::{BodyMass, Kind};

use super::driver::Rates;
use super::engine::Generic;
use super::scratch::{Scratch, Scratched, Sized};
use super::tape::Env;

#[cfg(feature = "jit")]
mod compiled;

/// A state of a tick with the sines and cosines of its inputs and unknowns (those of the others
/// stay (0, 1)).
struct Slot<T: Real> {
    state: DynState<T>,
    tx: Vec<(T, T)>,
    tq: Vec<(T, T)>,
}

impl<T: Real> Slot<T> {
    fn new(ni: usize, nu: usize, np: usize) -> Self {
        let (zeros, guess) = (vec![T::zero(); ni], vec![T::zero(); nu]);
        Slot {
            state: DynState::new(
                InputMotion::new(&zeros[..], &zeros[..], &zeros[..]),
                &guess,
                np,
            ),
            tx: vec![(T::zero(), T::one()); ni],
            tq: vec![(T::zero(), T::one()); nu],
        }
    }

    /// What the predictor reads of this state, as the last tick's.
    fn last(&self) -> Last<'_, T> {
        let s = &self.state;
        Last {
            x: &s.x,
            xd: &s.xd,
            q: &s.q,
            qd: &s.qd,
            qdd: &s.qdd,
            tq: &self.tq,
        }
    }
}

/// The tick of a [`Generic`] mechanism: its state with the sines and cosines of its inputs and
/// unknowns as the next tick rotates them, and the state before it.
pub struct GenericTick<'a, T: Real> {
    g: &'a Generic,
    /// `slots[cur]` is the tick's state, the other the one before it (where the next tick is
    /// solved).
    slots: [Slot<T>; 2],
    cur: usize,
    /// Ticks since the caches were computed afresh.
    age: u32,
    /// Which inputs are angles; which unknowns a closed form solves (kept by the predictor).
    input_angle: Vec<bool>,
    keep: Vec<bool>,
    all_closed: bool,
    /// Whether a tick may run by the compiled program with its prelude
    /// ([`GenericTick::advance_compiled`]).
    #[cfg(feature = "jit")]
    prelude: bool,
    started: bool,
    /// The stages' block work of a compiled program that needs none of its own (empty: see
    /// `Fused::uses_work`).
    idle: Idle<T>,
}

/// Block work that is never grown.
type Idle<T> = (Vec<T>, Vec<T>, Vec<Option<Sized<T>>>);

impl<'a, T: Scratched> GenericTick<'a, T> {
    pub fn new(g: &'a Generic) -> Self {
        let info = &g.info;
        let (ni, nu, np) = (info.inputs.len(), info.unknowns.len(), info.points.len());
        let mut keep = vec![false; nu];
        for b in g.blocks.iter().filter(|b| b.closed.is_some()) {
            for &u in &b.unknowns {
                keep[u] = true;
            }
        }
        let input_angle: Vec<bool> = info.inputs.iter().map(|i| i.kind == Kind::Angle).collect();
        let all_closed = keep.iter().all(|&k| k);
        // The compiled prelude rotates the inputs this tick would and carries the unknowns
        // exactly when this tick would not predict them.
        #[cfg(feature = "jit")]
        let prelude = g.fused.as_ref().is_some_and(|f| !f.uses_work())
            && (g.program.as_ref())
                .is_some_and(|p| p.tick.input_angle == input_angle && p.tick.carried == all_closed);
        GenericTick {
            g,
            slots: [Slot::new(ni, nu, np), Slot::new(ni, nu, np)],
            cur: 0,
            age: 0,
            input_angle,
            all_closed,
            #[cfg(feature = "jit")]
            prelude,
            keep,
            started: false,
            idle: (Vec::new(), Vec::new(), Vec::new()),
        }
    }

    /// One tick into the other slot and, on success, that slot becomes the state.
    fn advance(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError> {
        #[cfg(feature = "jit")]
        if self.prelude
            && options.closed_forms
            && let Some(done) = self.advance_compiled(input, options)
        {
            return done;
        }
        let InputMotion { x, xd, xdd } = input;
        // One branch-free pass over the three (of one length: `lengths`); the checks in their
        // order only when it finds a number that is not finite, to name it.
        let inputs = || x.iter().zip(xd).zip(xdd);
        let finite = inputs().fold(true, |ok, ((a, b), c)| {
            ok & a.is_finite() & b.is_finite() & c.is_finite()
        });
        if !finite {
            check_inputs(x, xd, xdd)?;
        }
        let resync = self.age >= RESYNC_TICKS;
        let predicts = !(options.closed_forms && self.all_closed);
        let (g, angle, keep) = (self.g, &self.input_angle[..], &self.keep[..]);
        let [a, b] = &mut self.slots;
        let (old, new) = if self.cur == 0 { (&*a, b) } else { (&*b, a) };
        let s = &old.state;
        // Every angle's entry is written; the others stay (0, 1) in both slots.
        inputs_trig(&old.tx, &s.x, x, angle, resync, &mut new.tx);
        // The predictor writes every unknown; without it they start as the last tick's.
        if !predicts {
            copy_few(&mut new.state.q, &s.q);
        }
        copy_few(&mut new.tq, &old.tq);
        // A mechanism solved in closed form throughout starts from the last tick as it is.
        if predicts {
            let keep: &[bool] = if options.closed_forms { keep } else { &[] };
            let (q, sc) = (&mut new.state.q, &mut new.tq);
            predict(old.last(), x, &g.angle, keep, resync, q, sc);
        }
        let report = motion(g, input, options, new, &mut self.idle)?;
        let s = &mut new.state;
        // The three in one loop (a copy each would dispatch on the length three times).
        let to = s.x.iter_mut().zip(&mut s.xd).zip(&mut s.xdd);
        for (((d, e), f), ((a, b), c)) in to.zip(inputs()) {
            (*d, *e, *f) = (*a, *b, *c);
        }
        s.report = report;
        self.cur ^= 1;
        self.age = if resync { 0 } else { self.age + 1 };
        Ok(())
    }

    fn lengths(&self, input: InputMotion<&[T]>) -> Result<(), SolveError> {
        let n = self.slots[self.cur].state.x.len();
        len(input.x, n)?;
        len(input.xd, n)?;
        len(input.xdd, n)
    }
}

/// The motion from the prediction in `at` (its unknowns with their sines and cosines, its
/// inputs' sines and cosines at `input`): the compiled program where there is one, straight in
/// `at`; else the walked program or the block driver in the workspace, copied back. On success
/// `at` holds the unknowns, their sines and cosines, the rates and the points (its inputs and
/// report are the caller's to write).
fn motion<T: Scratched>(
    g: &Generic,
    input: InputMotion<&[T]>,
    options: &SolveOptions<T>,
    at: &mut Slot<T>,
    idle: &mut Idle<T>,
) -> Result<NewtonReport<T>, SolveError> {
    // A compiled program that needs no block work runs without the thread's workspace.
    #[cfg(feature = "jit")]
    if g.fused.as_ref().is_some_and(|f| !f.uses_work()) {
        let (regs, out, by_size) = idle;
        if let Some(done) = at.compiled(g, input, options, (regs, out, by_size)) {
            return done;
        }
    }
    #[cfg(not(feature = "jit"))]
    let _ = idle;
    T::with_scratch(|ws| {
        #[cfg(feature = "jit")]
        {
            let work = (&mut ws.regs, &mut ws.out, &mut ws.by_size);
            if let Some(done) = at.compiled(g, input, options, work) {
                return done;
            }
        }
        let Slot {
            state: s,
            tx: sx,
            tq,
        } = at;
        ws.trial.clear();
        ws.trial.extend_from_slice(&s.q);
        ws.trial_sc.clear();
        ws.trial_sc.extend_from_slice(tq);
        let rates = [&mut s.qd[..], &mut s.qdd[..]];
        // Both engines walk the mechanism's program (with closed forms on).
        let report = if let Some(done) = super::walk::motion(g, input, sx, options, ws, rates) {
            let report = done?;
            Generic::set_points(&mut s.points, &ws.points);
            report
        } else {
            driven(g, input, sx, options, ws, s)?
        };
        copy_few(&mut s.q, &ws.trial);
        copy_few(tq, &ws.sc);
        Ok(report)
    })
}

/// The motion by the block driver (no program, or closed forms off), from the guess in
/// `ws.trial`: the unknowns left there and their sines and cosines in `ws.sc`, the rates and
/// points in `s`.
fn driven<T: Scratched>(
    g: &Generic,
    input: InputMotion<&[T]>,
    sx: &[(T, T)],
    options: &SolveOptions<T>,
    ws: &mut Scratch<T>,
    s: &mut DynState<T>,
) -> Result<NewtonReport<T>, SolveError> {
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
    let (qd, qdd) = (&mut s.qd[..], &mut s.qdd[..]);
    let solved = g
        .rates(&g.order, Rates::Both, env, qd, qdd, ws)
        .and_then(|()| {
            let env = Env {
                qd: &*qd,
                qdd: &*qdd,
                ..env
            };
            let Scratch { regs, points, .. } = ws;
            g.eval_points(env, &mut s.points, regs, points)
        });
    (ws.trial, ws.sc) = (q, sc);
    solved.map(|()| report)
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
        let Slot { state: s, tx, tq } = &mut self.slots[self.cur];
        len(guess, s.q.len())?;
        s.x.copy_from_slice(input.x);
        s.xd.copy_from_slice(input.xd);
        s.xdd.copy_from_slice(input.xdd);
        s.q.copy_from_slice(guess);
        self.g.solve_in_place(s, options)?;
        // The caches afresh, as a generated tick's start makes them.
        for ((t, x), &angle) in tx.iter_mut().zip(&s.x).zip(&self.input_angle) {
            *t = if angle {
                x.sin_cos()
            } else {
                (T::zero(), T::one())
            };
        }
        for ((t, q), &angle) in tq.iter_mut().zip(&s.q).zip(&self.g.angle) {
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
        self.advance(input, options)
    }

    fn tick_checked(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
        guard: &BranchGuard,
        dt: T,
        before: &mut [T],
    ) -> Result<Option<T>, SolveError> {
        self.tick(input, options)?;
        let (old, now) = (&self.slots[self.cur ^ 1].state, &self.slots[self.cur].state);
        len(before, old.q.len())?;
        copy_few(before, &old.q);
        let kept = guard.keeps_any([&old.q, &old.qd, &old.qdd, &now.q], dt);
        Ok(kept.then(|| now.report.condition()))
    }

    fn state(&self) -> Option<StateRef<'_, T>> {
        self.started.then(|| self.slots[self.cur].state.view())
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
        let (g, slot) = (self.g, &self.slots[self.cur]);
        let s = &slot.state;
        let env = Env {
            xd: &s.xd,
            qd: &s.qd,
            xdd: &s.xdd,
            qdd: &s.qdd,
            sc: &slot.tq,
            sx: &slot.tx,
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
