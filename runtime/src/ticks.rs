//! The two ticks on slices ([`DynTick`]): [`StaticTick`], a generated mechanism's own
//! [`crate::Tick`], with which every [`StaticMechanism`] is a [`DynMechanism`] (the blanket impl
//! here), and [`SolveTick`], the runtime's predictor with a whole
//! [`DynMechanism::solve_in_place`], for any other engine.

use alloc::boxed::Box;
use alloc::vec;
use alloc::vec::Vec;

use crate::dyn_tick::{DynTick, StateRef};
use crate::dynamic::{DynMechanism, DynState, arr, arrays, len, put};
use crate::error::SolveError;
use crate::guard::BranchGuard;
use crate::info::{BodyMass, BodyMotion, MechanismInfo, PointMotion};
use crate::mechanism::{BodySink, InputMotion, RowMajor, State, StaticMechanism};
use crate::scalar::Real;
use crate::solve::{NewtonReport, SolveOptions};
use crate::tick::{step_to, taylor};

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
        let guess = arr(guess)?;
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

    fn tick_with_sink(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
        mut sink: &mut dyn BodySink<T>,
    ) -> Result<bool, SolveError> {
        let input = arrays(input)?;
        let t = self.tick.as_mut().ok_or(SolveError::NotStarted)?;
        self.mechanism
            .tick_with_sink(t, &input, options, &mut sink)?;
        Ok(true)
    }

    // Inlined into `DynTick::walk`'s loop (one copy per mechanism), so that a run of a sweep's
    // rows has no call between the tick and the branch rule.
    #[inline(always)]
    fn tick_checked(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
        guard: &BranchGuard,
        dt: T,
        before: &mut [T],
    ) -> Result<Option<T>, SolveError> {
        let input = arrays(input)?;
        let t = self.tick.as_mut().ok_or(SolveError::NotStarted)?;
        let (q, qd, qdd) = (t.q, t.qd, t.qdd);
        self.mechanism.tick(t, &input, options)?;
        len(before, q.as_ref().len())?;
        before.copy_from_slice(q.as_ref());
        let kept = guard.keeps(q.as_ref(), qd.as_ref(), qdd.as_ref(), dt, t.q.as_ref());
        Ok(kept.then(|| t.report.condition()))
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

    fn condition(&self) -> Option<T> {
        self.tick.as_ref().map(|t| t.report.condition())
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
    ) -> Result<Option<T>, SolveError> {
        self.tick(input, options)?;
        let (b, s) = (&self.saved, &self.state);
        len(before, b.q.len())?;
        before.copy_from_slice(&b.q);
        let kept = guard.keeps_any([&b.q, &b.qd, &b.qdd, &s.q], dt);
        Ok(kept.then(|| s.report.condition()))
    }

    fn state(&self) -> Option<StateRef<'_, T>> {
        self.started.then(|| self.state.view())
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

impl<T: Real, M: StaticMechanism<T>> DynMechanism<T> for M {
    fn info(&self) -> MechanismInfo {
        StaticMechanism::info(self).into()
    }
    #[cfg(feature = "std")]
    fn info_ref(&self) -> alloc::borrow::Cow<'_, MechanismInfo> {
        alloc::borrow::Cow::Borrowed(crate::info::shared(StaticMechanism::info(self)))
    }
    fn residual(&self, x: &[T], q: &[T], out: &mut [T]) -> Result<(), SolveError> {
        let r = StaticMechanism::residual(self, &arr(x)?, &arr(q)?);
        put(out, r.as_ref())
    }
    fn jacobian(&self, x: &[T], q: &[T], out: &mut [T]) -> Result<(), SolveError> {
        StaticMechanism::jacobian(self, &arr(x)?, &arr(q)?).write_row_major(out)
    }
    fn input_jacobian(&self, x: &[T], q: &[T], out: &mut [T]) -> Result<(), SolveError> {
        StaticMechanism::input_jacobian(self, &arr(x)?, &arr(q)?).write_row_major(out)
    }
    fn jacobian_dot(
        &self,
        x: &[T],
        q: &[T],
        xd: &[T],
        qd: &[T],
        out: &mut [T],
    ) -> Result<(), SolveError> {
        StaticMechanism::jacobian_dot(self, &arr(x)?, &arr(q)?, &arr(xd)?, &arr(qd)?)
            .write_row_major(out)
    }
    fn acceleration_rhs(
        &self,
        x: &[T],
        q: &[T],
        xd: &[T],
        qd: &[T],
        xdd: &[T],
        out: &mut [T],
    ) -> Result<(), SolveError> {
        let (x, q, xd, qd, xdd) = (arr(x)?, arr(q)?, arr(xd)?, arr(qd)?, arr(xdd)?);
        let g = StaticMechanism::acceleration_rhs(self, &x, &q, &xd, &qd, &xdd);
        put(out, g.as_ref())
    }
    fn solve_position(
        &self,
        x: &[T],
        q: &mut [T],
        options: &SolveOptions<T>,
    ) -> Result<NewtonReport<T>, SolveError> {
        let mut qa: M::Q = arr(q)?;
        let report = StaticMechanism::solve_position(self, &arr(x)?, &mut qa, options)?;
        put(q, qa.as_ref())?;
        Ok(report)
    }
    fn solve_velocity(&self, x: &[T], q: &[T], xd: &[T], qd: &mut [T]) -> Result<(), SolveError> {
        len(qd, M::UNKNOWNS)?;
        let v = StaticMechanism::solve_velocity(self, &arr(x)?, &arr(q)?, &arr(xd)?)?;
        put(qd, v.as_ref())
    }
    fn solve_acceleration(
        &self,
        x: &[T],
        q: &[T],
        xd: &[T],
        qd: &[T],
        xdd: &[T],
        qdd: &mut [T],
    ) -> Result<(), SolveError> {
        len(qdd, M::UNKNOWNS)?;
        let (x, q, xd, qd, xdd) = (arr(x)?, arr(q)?, arr(xd)?, arr(qd)?, arr(xdd)?);
        let a = StaticMechanism::solve_acceleration(self, &x, &q, &xd, &qd, &xdd)?;
        put(qdd, a.as_ref())
    }
    fn sensitivities(
        &self,
        x: &[T],
        q: &[T],
        unknowns: &mut [T],
        points: &mut [T],
    ) -> Result<(), SolveError> {
        let s = StaticMechanism::sensitivities(self, &arr(x)?, &arr(q)?)?;
        s.unknowns.write_row_major(unknowns)?;
        s.points.write_row_major(points)
    }
    fn points(
        &self,
        input: InputMotion<&[T]>,
        q: &[T],
        qd: &[T],
        qdd: &[T],
        out: &mut [PointMotion<T>],
    ) -> Result<(), SolveError> {
        len(out, M::POINTS)?;
        let p = StaticMechanism::points(self, &arrays(input)?, &arr(q)?, &arr(qd)?, &arr(qdd)?);
        put(out, p.as_ref())
    }
    fn bodies(
        &self,
        input: InputMotion<&[T]>,
        q: &[T],
        qd: &[T],
        qdd: &[T],
        out: &mut [BodyMotion<T>],
    ) -> Result<(), SolveError> {
        let input = arrays(input)?;
        StaticMechanism::bodies(self, &input, &arr(q)?, &arr(qd)?, &arr(qdd)?, out)
    }
    fn mass_properties(&self, out: &mut [BodyMass<T>]) -> Result<[T; 2], SolveError> {
        StaticMechanism::mass_properties(self, out)
    }
    fn solve_in_place(
        &self,
        state: &mut DynState<T>,
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError> {
        len(&state.qd, M::UNKNOWNS)?;
        len(&state.qdd, M::UNKNOWNS)?;
        len(&state.points, M::POINTS)?;
        let s = StaticMechanism::solve(
            self,
            &arrays(state.input_slices())?,
            &arr(&state.q)?,
            options,
        )?;
        state.q.copy_from_slice(s.q.as_ref());
        state.qd.copy_from_slice(s.qd.as_ref());
        state.qdd.copy_from_slice(s.qdd.as_ref());
        state.points.copy_from_slice(s.points.as_ref());
        state.report = s.report;
        Ok(())
    }
    fn ticker(&self) -> Box<dyn DynTick<T> + '_> {
        Box::new(StaticTick::new(self))
    }
}
