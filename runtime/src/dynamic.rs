//! The object-safe trait on slices, [`DynMechanism`]: what sweeps, the CLI, `lookup` and the
//! generic engine share, for generated mechanisms (a blanket impl over
//! [`crate::StaticMechanism`]) and mechanisms loaded at run time alike. It mirrors
//! `StaticMechanism` argument for argument, on slices, with [`DynState`] (vectors) for the
//! solved [`State`]. Every slice is checked: a wrong length is [`SolveError::BadLength`], never a
//! truncated copy.

use alloc::borrow::Cow;
use alloc::boxed::Box;
use alloc::vec;
use alloc::vec::Vec;

use crate::dyn_tick::{DynTick, StateRef};
use crate::error::SolveError;
use crate::info::{BodyMass, BodyMotion, MechanismInfo, PointMotion};
use crate::mechanism::{Array, InputMotion, State};
use crate::scalar::Real;
use crate::solve::{NewtonReport, SolveOptions};

/// Object-safe kinematics on slices, with dynamic dispatch. Slices of the wrong length give
/// [`SolveError::BadLength`]. Matrices are row-major.
pub trait DynMechanism<T: Real> {
    fn info(&self) -> MechanismInfo;
    /// [`DynMechanism::info`] without building it where the engine keeps one (the generic engine's
    /// own; a generated mechanism's, made once per process with `std`): what a sweep reads at its
    /// start. The same description either way.
    fn info_ref(&self) -> Cow<'_, MechanismInfo> {
        Cow::Owned(self.info())
    }
    /// Φ(x, q) into `out` (UNKNOWNS).
    fn residual(&self, x: &[T], q: &[T], out: &mut [T]) -> Result<(), SolveError>;
    /// J into `out` (UNKNOWNS × UNKNOWNS).
    fn jacobian(&self, x: &[T], q: &[T], out: &mut [T]) -> Result<(), SolveError>;
    /// Φx into `out` (UNKNOWNS × INPUTS).
    fn input_jacobian(&self, x: &[T], q: &[T], out: &mut [T]) -> Result<(), SolveError>;
    /// J̇ into `out` (UNKNOWNS × UNKNOWNS).
    fn jacobian_dot(
        &self,
        x: &[T],
        q: &[T],
        xd: &[T],
        qd: &[T],
        out: &mut [T],
    ) -> Result<(), SolveError>;
    /// γ into `out` (UNKNOWNS).
    fn acceleration_rhs(
        &self,
        x: &[T],
        q: &[T],
        xd: &[T],
        qd: &[T],
        xdd: &[T],
        out: &mut [T],
    ) -> Result<(), SolveError>;
    /// Positions from the guess in `q`; `q` is written only on success.
    fn solve_position(
        &self,
        x: &[T],
        q: &mut [T],
        options: &SolveOptions<T>,
    ) -> Result<NewtonReport<T>, SolveError>;
    /// q̇ at a solved position into `qd` (UNKNOWNS).
    fn solve_velocity(&self, x: &[T], q: &[T], xd: &[T], qd: &mut [T]) -> Result<(), SolveError>;
    /// q̈ at a solved position and velocity into `qdd` (UNKNOWNS).
    fn solve_acceleration(
        &self,
        x: &[T],
        q: &[T],
        xd: &[T],
        qd: &[T],
        xdd: &[T],
        qdd: &mut [T],
    ) -> Result<(), SolveError>;
    /// The design derivatives at a solved position (`StaticMechanism::sensitivities`), row-major:
    /// dq/dp into `unknowns` (UNKNOWNS × PARAMS), dP/dp into `points` (2·POINTS × PARAMS).
    fn sensitivities(
        &self,
        x: &[T],
        q: &[T],
        unknowns: &mut [T],
        points: &mut [T],
    ) -> Result<(), SolveError>;
    /// Every point's motion into `out` (POINTS).
    fn points(
        &self,
        input: InputMotion<&[T]>,
        q: &[T],
        qd: &[T],
        qdd: &[T],
        out: &mut [PointMotion<T>],
    ) -> Result<(), SolveError>;
    /// Every body's motion at a solved state into `out` (one per `info().bodies`; the default,
    /// for a mechanism without bodies: `out` must be empty).
    fn bodies(
        &self,
        input: InputMotion<&[T]>,
        q: &[T],
        qd: &[T],
        qdd: &[T],
        out: &mut [BodyMotion<T>],
    ) -> Result<(), SolveError> {
        let _ = (input, q, qd, qdd);
        len(out, 0)
    }
    /// Every body's mass and inertia at the current params into `out` (one per
    /// `info().bodies`); returns the acceleration of gravity (zero without a `gravity` key).
    fn mass_properties(&self, out: &mut [BodyMass<T>]) -> Result<[T; 2], SolveError> {
        len(out, 0)?;
        Ok([T::zero(); 2])
    }
    /// One whole tick from `guess`: positions, velocities, accelerations and points, as a new
    /// [`DynState`] (the allocating form of [`DynMechanism::solve_in_place`]).
    fn solve(
        &self,
        input: InputMotion<&[T]>,
        guess: &[T],
        options: &SolveOptions<T>,
    ) -> Result<DynState<T>, SolveError> {
        let mut state = DynState::new(input, guess, self.info().points.len());
        self.solve_in_place(&mut state, options)?;
        Ok(state)
    }
    /// [`DynMechanism::solve`] into `state`: its inputs and rates are the input, its unknowns
    /// the guess; on success it holds the solution, on error it is unchanged. Every vector must
    /// have its length (`SolveError::BadLength`); a state reused from solve to solve allocates
    /// nothing.
    fn solve_in_place(
        &self,
        state: &mut DynState<T>,
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError>;
    /// A tick of this mechanism on slices, not yet started (see [`DynTick`]): a generated
    /// mechanism's own tick (`crate::ticks::StaticTick`), or for any other engine
    /// `crate::ticks::SolveTick::new(self)` (the runtime's predictor with
    /// [`DynMechanism::solve_in_place`]). Made once per run (it allocates); its ticks do not.
    fn ticker(&self) -> Box<dyn DynTick<T> + '_>;
}

/// The [`State`] of a [`DynMechanism`]: vectors of the mechanism's sizes.
pub type DynState<T> = State<Vec<T>, Vec<T>, Vec<PointMotion<T>>, T>;

impl<T: Real> DynState<T> {
    /// A state at `input` with the unknowns `guess`, zero rates and `points` zero points: what
    /// [`DynMechanism::solve_in_place`] solves from.
    pub fn new(input: InputMotion<&[T]>, guess: &[T], points: usize) -> Self {
        State {
            x: input.x.to_vec(),
            xd: input.xd.to_vec(),
            xdd: input.xdd.to_vec(),
            q: guess.to_vec(),
            qd: vec![T::zero(); guess.len()],
            qdd: vec![T::zero(); guess.len()],
            points: vec![PointMotion::default(); points],
            report: NewtonReport::new(),
        }
    }

    /// The whole state seen through slices (what a tick's `DynTick::state` shows).
    pub fn view(&self) -> StateRef<'_, T> {
        State {
            x: &self.x[..],
            xd: &self.xd[..],
            xdd: &self.xdd[..],
            q: &self.q[..],
            qd: &self.qd[..],
            qdd: &self.qdd[..],
            points: &self.points[..],
            report: self.report,
        }
    }

    /// The inputs with their rates, as slices.
    pub fn input_slices(&self) -> InputMotion<&[T]> {
        InputMotion::new(&self.x, &self.xd, &self.xdd)
    }
}

pub use crate::error::len;

pub(crate) fn arr<T: Real, A: Array<T>>(s: &[T]) -> Result<A, SolveError> {
    let mut a = A::zeros();
    let dst = a.as_mut();
    len(s, dst.len())?;
    dst.copy_from_slice(s);
    Ok(a)
}

/// `src` copied into `dst`, which must have its length (else `SolveError::BadLength`).
pub fn put<T: Copy>(dst: &mut [T], src: &[T]) -> Result<(), SolveError> {
    len(dst, src.len())?;
    dst.copy_from_slice(src);
    Ok(())
}

pub(crate) fn arrays<T: Real, A: Array<T>>(
    m: InputMotion<&[T]>,
) -> Result<InputMotion<A>, SolveError> {
    Ok(InputMotion {
        x: arr(m.x)?,
        xd: arr(m.xd)?,
        xdd: arr(m.xdd)?,
    })
}
