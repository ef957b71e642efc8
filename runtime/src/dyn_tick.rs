//! The tick on slices, [`DynTick`]: what [`DynMechanism::ticker`] gives every engine, so that a
//! sweep (or any driver that steps a mechanism along its input) runs each engine's own tick
//! through one object-safe interface. A generated mechanism's is its [`crate::Tick`]
//! ([`StaticTick`]: the cached sines and cosines, the closed forms on the guess's side, the
//! dead-point refinement); any other engine's is [`SolveTick`]: the runtime's second-order
//! predictor ([`crate::tick::taylor`]) and one whole [`DynMechanism::solve_in_place`].

use alloc::vec;
use alloc::vec::Vec;

use crate::dynamic::{DynMechanism, DynState, arrays, len};
use crate::error::SolveError;
use crate::guard::BranchGuard;
use crate::info::PointMotion;
use crate::mechanism::{InputMotion, State, StaticMechanism};
use crate::scalar::Real;
use crate::solve::SolveOptions;
use crate::tick::{step_to, taylor};

/// A solved state seen through slices (what [`DynTick::state`] shows).
pub type StateRef<'a, T> = State<&'a [T], &'a [T], &'a [PointMotion<T>], T>;

/// A mechanism's tick on slices. Slices of the wrong length give [`SolveError::BadLength`].
pub trait DynTick<T: Real> {
    /// The first tick: a whole solve at `input` from `guess` (on the guess's branch). On error
    /// the tick has no state (until the next successful start).
    fn start(
        &mut self,
        input: InputMotion<&[T]>,
        guess: &[T],
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError>;
    /// One tick from the state to `input`: the engine's predictor from the last state, then
    /// positions, velocities, accelerations and points. On error the state is unchanged; before
    /// a start it is `SolveError::NotStarted`.
    fn tick(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError>;
    /// The state of the last successful start or tick (`None` before one).
    fn state(&self) -> Option<StateRef<'_, T>>;
    /// [`DynTick::tick`], checked by `guard` against the prediction over the time `dt`
    /// ([`BranchGuard::keeps`]): `Ok(true)` when it keeps to the branch. When not, `Ok(false)`,
    /// `before` holds the unknowns before the tick, and the tick's state is the refused one
    /// (start again from `before` to go on). On error the state is unchanged.
    fn tick_checked(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
        guard: &BranchGuard,
        dt: T,
        before: &mut [T],
    ) -> Result<bool, SolveError>;
}

/// [`DynTick`] of a generated mechanism: its own [`StaticMechanism::tick`].
pub struct StaticTick<'a, T: Real, M: StaticMechanism<T>> {
    mechanism: &'a M,
    tick: Option<M::Tick>,
}

impl<'a, T: Real, M: StaticMechanism<T>> StaticTick<'a, T, M> {
    pub fn new(mechanism: &'a M) -> Self {
        StaticTick {
            mechanism,
            tick: None,
        }
    }
}

impl<T: Real, M: StaticMechanism<T>> DynTick<T> for StaticTick<'_, T, M> {
    fn start(
        &mut self,
        input: InputMotion<&[T]>,
        guess: &[T],
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError> {
        self.tick = None;
        let input = arrays(input)?;
        let guess = crate::dynamic::arr(guess)?;
        self.tick = Some(self.mechanism.tick_start(&input, &guess, options)?);
        Ok(())
    }

    fn tick(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError> {
        let input = arrays(input)?;
        let t = self.tick.as_mut().ok_or(SolveError::NotStarted)?;
        self.mechanism.tick(t, &input, options)
    }

    fn tick_checked(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
        guard: &BranchGuard,
        dt: T,
        before: &mut [T],
    ) -> Result<bool, SolveError> {
        let input = arrays(input)?;
        let t = self.tick.as_mut().ok_or(SolveError::NotStarted)?;
        let (q, qd, qdd) = (t.q, t.qd, t.qdd);
        self.mechanism.tick(t, &input, options)?;
        if guard.keeps(q.as_ref(), qd.as_ref(), qdd.as_ref(), dt, t.q.as_ref()) {
            return Ok(true);
        }
        len(before, q.as_ref().len())?;
        before.copy_from_slice(q.as_ref());
        Ok(false)
    }

    fn state(&self) -> Option<StateRef<'_, T>> {
        self.tick.as_ref().map(|t| State {
            x: t.x.as_ref(),
            xd: t.xd.as_ref(),
            xdd: t.xdd.as_ref(),
            q: t.q.as_ref(),
            qd: t.qd.as_ref(),
            qdd: t.qdd.as_ref(),
            points: t.points.as_ref(),
            report: t.report,
        })
    }
}

/// [`DynTick`] of any [`DynMechanism`]: the runtime's predictor from the last state (closed-form
/// unknowns kept, as a generated tick keeps them) as the guess of one
/// [`DynMechanism::solve_in_place`] (allocation-free once made, if the engine's solve is).
pub struct SolveTick<'a, T: Real, M: ?Sized> {
    mechanism: &'a M,
    /// The unknowns of closed-form blocks: they keep their last values as the guess (a closed form
    /// reads the guess only for its branch, which an extrapolated guess could cross near a dead
    /// point), as a generated tick keeps them.
    keep: Vec<bool>,
    state: DynState<T>,
    /// The last good state's inputs and unknowns while a tick solves (restored on error).
    saved: DynState<T>,
    started: bool,
}

impl<'a, T: Real, M: DynMechanism<T> + ?Sized> SolveTick<'a, T, M> {
    pub fn new(mechanism: &'a M) -> Self {
        let info = mechanism.info();
        let (ni, nu) = (info.inputs.len(), info.unknowns.len());
        let mut keep = vec![false; nu];
        for (block, closed) in info.blocks.iter().zip(&info.closed) {
            for &k in block.iter().filter(|_| *closed) {
                if let Some(v) = keep.get_mut(k) {
                    *v = true;
                }
            }
        }
        let zeros = vec![T::zero(); ni];
        let guess: Vec<T> = vec![T::zero(); nu];
        let state = DynState::new(
            InputMotion::new(&zeros[..], &zeros[..], &zeros[..]),
            &guess,
            info.points.len(),
        );
        SolveTick {
            mechanism,
            keep,
            saved: state.clone(),
            state,
            started: false,
        }
    }
}

impl<T: Real, M: DynMechanism<T> + ?Sized> DynTick<T> for SolveTick<'_, T, M> {
    fn start(
        &mut self,
        input: InputMotion<&[T]>,
        guess: &[T],
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError> {
        self.started = false;
        let s = &mut self.state;
        len(input.x, s.x.len())?;
        len(input.xd, s.x.len())?;
        len(input.xdd, s.x.len())?;
        len(guess, s.q.len())?;
        s.x.copy_from_slice(input.x);
        s.xd.copy_from_slice(input.xd);
        s.xdd.copy_from_slice(input.xdd);
        s.q.copy_from_slice(guess);
        self.mechanism.solve_in_place(s, options)?;
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
        let s = &mut self.state;
        len(input.x, s.x.len())?;
        len(input.xd, s.x.len())?;
        len(input.xdd, s.x.len())?;
        copy_state(&mut self.saved, s);
        let dt = step_to(&s.x, input.x, &s.xd);
        let keep: &[bool] = if options.closed_forms {
            &self.keep
        } else {
            &[]
        };
        taylor(&self.saved.q, &s.qd, &s.qdd, dt, keep, &mut s.q);
        s.x.copy_from_slice(input.x);
        s.xd.copy_from_slice(input.xd);
        s.xdd.copy_from_slice(input.xdd);
        let solved = self.mechanism.solve_in_place(s, options);
        if solved.is_err() {
            core::mem::swap(&mut self.state, &mut self.saved);
        }
        solved
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
        let (b, s) = (&self.saved, &self.state);
        if guard.keeps(&b.q, &b.qd, &b.qdd, dt, &s.q) {
            return Ok(true);
        }
        len(before, b.q.len())?;
        before.copy_from_slice(&b.q);
        Ok(false)
    }

    fn state(&self) -> Option<StateRef<'_, T>> {
        let s = &self.state;
        self.started.then(|| State {
            x: &s.x[..],
            xd: &s.xd[..],
            xdd: &s.xdd[..],
            q: &s.q[..],
            qd: &s.qd[..],
            qdd: &s.qdd[..],
            points: &s.points[..],
            report: s.report,
        })
    }
}

/// `src` into `dst` (of the same sizes) without allocating.
fn copy_state<T: Real>(dst: &mut DynState<T>, src: &DynState<T>) {
    dst.x.copy_from_slice(&src.x);
    dst.xd.copy_from_slice(&src.xd);
    dst.xdd.copy_from_slice(&src.xdd);
    dst.q.copy_from_slice(&src.q);
    dst.qd.copy_from_slice(&src.qd);
    dst.qdd.copy_from_slice(&src.qdd);
    dst.points.copy_from_slice(&src.points);
    dst.report = src.report;
}
