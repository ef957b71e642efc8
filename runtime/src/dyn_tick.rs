//! The tick on slices, [`DynTick`]: what `DynMechanism::ticker` gives every engine, so that a
//! sweep (or any driver that steps a mechanism along its input) runs each engine's own tick
//! through one object-safe interface. The two kinds of tick are in [`crate::ticks`]: a generated
//! mechanism's own [`crate::Tick`] (`StaticTick`: the cached sines and cosines, the closed forms
//! on the guess's side, the dead-point refinement), and `SolveTick` for any other engine (the
//! runtime's second-order predictor and one whole `DynMechanism::solve_in_place`).

use crate::error::SolveError;
use crate::guard::BranchGuard;
use crate::info::PointMotion;
use crate::mechanism::{BodySink, InputMotion, State};
use crate::scalar::Real;
use crate::solve::SolveOptions;

/// A solved state seen through slices (what [`DynTick::state`] shows).
pub type StateRef<'a, T> = State<&'a [T], &'a [T], &'a [PointMotion<T>], T>;

/// A walk along one input that ticks take substep by substep ([`Stride::substep`],
/// [`DynTick::walk`]): the inputs (input `index` moved to each substep's value), their rates
/// and accelerations, the unknowns before the last tick (the branch rule's) and the substeps
/// left of the walk's budget.
pub struct Stride<'a, T> {
    pub x: &'a mut [T],
    pub xd: &'a [T],
    pub xdd: &'a [T],
    pub index: usize,
    pub before: &'a mut [T],
    pub guard: &'a BranchGuard,
    pub allowance: &'a mut usize,
}

/// What one substep of a walk came to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Substep<T> {
    /// Ticked and kept to the branch: the condition estimate of its position solve, and the
    /// swept input before the substep.
    Kept { condition: T, from: T },
    /// Ticked and refused by the branch rule (the tick's state is the refused one); the swept
    /// input is back where it was.
    Refused,
    /// The tick failed (its state unchanged); the swept input is back where it was.
    Failed,
    /// The walk's budget was used up: nothing done.
    Spent,
}

impl<T: Real> Stride<'_, T> {
    /// One substep of `tick` to `xt` along the swept input, checked by the branch rule
    /// ([`DynTick::tick_checked`] over the time the input takes at its rate): the step every
    /// walk takes, one substep at a time, and [`DynTick::walk`] row after row.
    #[inline(always)]
    pub fn substep<K: DynTick<T> + ?Sized>(
        &mut self,
        tick: &mut K,
        xt: T,
        options: &SolveOptions<T>,
    ) -> Substep<T> {
        if *self.allowance == 0 {
            return Substep::Spent;
        }
        *self.allowance -= 1;
        let i = self.index;
        let from = self.x[i];
        self.x[i] = xt;
        // The tick's predictor over this substep (the swept input alone moves); every tick is
        // checked against it: even a closed form, which keeps its guess's side, could step over
        // a narrow window where the linkage does not assemble onto another branch.
        let dt = (xt - from) / self.xd[i];
        let input = InputMotion::new(&self.x[..], self.xd, self.xdd);
        match tick.tick_checked(input, options, self.guard, dt, self.before) {
            Ok(Some(condition)) => Substep::Kept { condition, from },
            Ok(None) => {
                self.x[i] = from;
                Substep::Refused
            }
            Err(_) => {
                self.x[i] = from;
                Substep::Failed
            }
        }
    }
}

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
    /// The condition estimate of the last successful start's or tick's position solve.
    fn condition(&self) -> Option<T> {
        self.state().map(|s| s.report.condition())
    }
    /// [`DynTick::tick`], checked by `guard` against the prediction over the time `dt`
    /// ([`BranchGuard::keeps`]): `Ok(Some(condition))` when it keeps to the branch, with the
    /// condition estimate of its position solve ([`DynTick::condition`], without a second call).
    /// When not, `Ok(None)`, and the tick's state is the refused one (start again from `before`
    /// to go on). Either way `before` holds the unknowns before the tick. On error the state is
    /// unchanged.
    fn tick_checked(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
        guard: &BranchGuard,
        dt: T,
        before: &mut [T],
    ) -> Result<Option<T>, SolveError>;
    /// Rows of a walk, one tick each: the stride taken to each of `targets` in turn in one
    /// substep ([`Stride::substep`]), each row kept to the branch with a condition estimate
    /// below `settle` handed to `emit` with its index in `targets` and the tick's state. Stops
    /// at the first target that is not such a row: `(n, None)` when target `n` lies farther
    /// than `h_max` (or is not finite) and was not tried, `(n, Some(what))` when its substep
    /// came to `what` (a kept one with a condition from `settle` up included); `(len, None)`
    /// when every target was. One call for a run of rows, so that an engine's tick and the
    /// branch rule run without a dynamic call between rows.
    #[allow(clippy::too_many_arguments)]
    fn walk(
        &mut self,
        stride: &mut Stride<'_, T>,
        targets: &[T],
        h_max: T,
        settle: T,
        options: &SolveOptions<T>,
        emit: &mut dyn FnMut(usize, StateRef<'_, T>),
    ) -> (usize, Option<Substep<T>>) {
        for (j, &xt) in targets.iter().enumerate() {
            // One substep (false for a target that is not finite).
            let near = (xt - stride.x[stride.index]).abs() <= h_max;
            if !near {
                return (j, None);
            }
            let step = stride.substep(self, xt, options);
            match (step, self.state()) {
                (Substep::Kept { condition, .. }, Some(s)) if condition < settle => emit(j, s),
                _ => return (j, Some(step)),
            }
        }
        (targets.len(), None)
    }
    /// [`DynTick::tick`] handing gravity and every body to `sink`, computed on the tick's own
    /// sines and cosines (`Ok(true)`: a generated mechanism's tick,
    /// `StaticMechanism::tick_with_sink`, or the generic engine's), or a plain tick that hands
    /// nothing (`Ok(false)`, the default). On error the state is unchanged.
    fn tick_with_sink(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
        sink: &mut dyn BodySink<T>,
    ) -> Result<bool, SolveError> {
        let _ = sink;
        self.tick(input, options)?;
        Ok(false)
    }
}
