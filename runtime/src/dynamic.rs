//! The object-safe trait on slices, [`DynMechanism`]: what sweeps, the CLI, `lookup` and the
//! generic engine share, for generated mechanisms (a blanket impl over
//! [`crate::StaticMechanism`]) and mechanisms loaded at run time alike. It mirrors
//! `StaticMechanism` argument for argument, on slices, with [`DynState`] (vectors) for the
//! solved [`State`]. Every slice is checked: a wrong length is [`SolveError::BadLength`], never a
//! truncated copy.

use alloc::boxed::Box;
use alloc::vec;
use alloc::vec::Vec;

use crate::dyn_tick::{DynTick, SolveTick, StaticTick};
use crate::error::SolveError;
use crate::info::{MechanismInfo, PointMotion};
use crate::mechanism::{Array, InputMotion, RowMajor, State, StaticMechanism};
use crate::scalar::Real;
use crate::solve::{NewtonReport, SolveOptions};

/// Object-safe kinematics on slices, with dynamic dispatch. Slices of the wrong length give
/// [`SolveError::BadLength`]. Matrices are row-major.
pub trait DynMechanism<T: Real> {
    fn info(&self) -> MechanismInfo;
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
    /// mechanism's own tick, or (the default) the runtime's predictor with
    /// [`DynMechanism::solve_in_place`]. Made once per run (it allocates); its ticks do not.
    fn ticker(&self) -> Box<dyn DynTick<T> + '_> {
        Box::new(SolveTick::new(self))
    }
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

fn put<T: Copy>(dst: &mut [T], src: &[T]) -> Result<(), SolveError> {
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

impl<T: Real, M: StaticMechanism<T>> DynMechanism<T> for M {
    fn info(&self) -> MechanismInfo {
        StaticMechanism::info(self).into()
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
