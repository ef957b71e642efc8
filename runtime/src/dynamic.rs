//! The object-safe trait on slices, [`DynMechanism`]: what sweeps, the CLI, `lookup` and the
//! generic engine share, for generated mechanisms (a blanket impl over
//! [`crate::StaticMechanism`]) and mechanisms loaded at run time alike. Every slice is checked:
//! a wrong length is [`SolveError::BadLength`], never a truncated copy.

use crate::error::SolveError;
use crate::info::{MechanismInfo, PointMotion};
use crate::mechanism::{Array, InputMotion, RowMajor, StaticMechanism};
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
    fn solve_velocity(&self, x: &[T], q: &[T], xd: &[T], qd: &mut [T]) -> Result<(), SolveError>;
    fn solve_acceleration(
        &self,
        input: InputMotion<&[T]>,
        q: &[T],
        qd: &[T],
        qdd: &mut [T],
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
    /// One whole tick: positions from the guess in `q`, then velocities, accelerations and
    /// points. The default calls the four stages in turn; generated mechanisms share work
    /// between them.
    fn solve(
        &self,
        input: InputMotion<&[T]>,
        q: &mut [T],
        qd: &mut [T],
        qdd: &mut [T],
        points: &mut [PointMotion<T>],
        options: &SolveOptions<T>,
    ) -> Result<NewtonReport<T>, SolveError> {
        let report = self.solve_position(input.x, q, options)?;
        self.solve_velocity(input.x, q, input.xd, qd)?;
        self.solve_acceleration(input, q, qd, qdd)?;
        self.points(input, q, qd, qdd, points)?;
        Ok(report)
    }
}

pub use crate::error::len;

fn arr<T: Real, A: Array<T>>(s: &[T]) -> Result<A, SolveError> {
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

fn arrays<T: Real, A: Array<T>>(m: InputMotion<&[T]>) -> Result<InputMotion<A>, SolveError> {
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
        input: InputMotion<&[T]>,
        q: &[T],
        qd: &[T],
        qdd: &mut [T],
    ) -> Result<(), SolveError> {
        len(qdd, M::UNKNOWNS)?;
        let i: InputMotion<M::X> = arrays(input)?;
        let a =
            StaticMechanism::solve_acceleration(self, &i.x, &arr(q)?, &i.xd, &arr(qd)?, &i.xdd)?;
        put(qdd, a.as_ref())
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
    fn solve(
        &self,
        input: InputMotion<&[T]>,
        q: &mut [T],
        qd: &mut [T],
        qdd: &mut [T],
        points: &mut [PointMotion<T>],
        options: &SolveOptions<T>,
    ) -> Result<NewtonReport<T>, SolveError> {
        len(qd, M::UNKNOWNS)?;
        len(qdd, M::UNKNOWNS)?;
        len(points, M::POINTS)?;
        let s = StaticMechanism::solve(self, &arrays(input)?, &arr(q)?, options)?;
        put(q, s.q.as_ref())?;
        put(qd, s.qd.as_ref())?;
        put(qdd, s.qdd.as_ref())?;
        put(points, s.points.as_ref())?;
        Ok(s.report)
    }
}
