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
