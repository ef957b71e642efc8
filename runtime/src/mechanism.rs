//! The traits every mechanism implements: [`Mechanism`] (static sizes, fixed arrays; generated
//! code) and [`Kinematics`] (object-safe, slices; every `Mechanism` and the generic engine), plus
//! the descriptive types they share.

use alloc::string::{String, ToString};
use alloc::vec::Vec;

use crate::error::SolveError;
use crate::scalar::Real;
use crate::solve::{NewtonOptions, NewtonReport};

/// Angle (radians) or length (file units), as inferred from the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    Angle,
    Length,
}

/// An input or unknown: its name, kind and value in the file's `start` configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoordInfo {
    pub name: &'static str,
    pub kind: Kind,
    pub start: f64,
}

/// A param and its default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamInfo {
    pub name: &'static str,
    pub kind: Kind,
    pub default: f64,
}

/// Everything static about a generated mechanism.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StaticInfo {
    pub name: &'static str,
    pub description: &'static str,
    pub inputs: &'static [CoordInfo],
    pub unknowns: &'static [CoordInfo],
    pub params: &'static [ParamInfo],
    pub points: &'static [&'static str],
    /// Unknown indices of each diagonal block, in solve order.
    pub blocks: &'static [&'static [usize]],
}

/// An owned copy of the description, for mechanisms loaded at run time.
#[derive(Clone, Debug, PartialEq)]
pub struct MechanismInfo {
    pub name: String,
    pub description: String,
    /// (name, kind, start value)
    pub inputs: Vec<(String, Kind, f64)>,
    pub unknowns: Vec<(String, Kind, f64)>,
    pub params: Vec<(String, Kind, f64)>,
    pub points: Vec<String>,
    pub blocks: Vec<Vec<usize>>,
}

impl From<&StaticInfo> for MechanismInfo {
    fn from(s: &StaticInfo) -> Self {
        let coords = |cs: &[CoordInfo]| {
            cs.iter()
                .map(|c| (c.name.to_string(), c.kind, c.start))
                .collect()
        };
        MechanismInfo {
            name: s.name.to_string(),
            description: s.description.to_string(),
            inputs: coords(s.inputs),
            unknowns: coords(s.unknowns),
            params: s
                .params
                .iter()
                .map(|p| (p.name.to_string(), p.kind, p.default))
                .collect(),
            points: s.points.iter().map(|p| p.to_string()).collect(),
            blocks: s.blocks.iter().map(|b| b.to_vec()).collect(),
        }
    }
}

/// A point's position, velocity and acceleration.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PointMotion<T> {
    pub position: [T; 2],
    pub velocity: [T; 2],
    pub acceleration: [T; 2],
}

/// A fixed-size coordinate array (`[T; N]`).
pub trait Array<T>:
    Copy + AsRef<[T]> + AsMut<[T]> + core::fmt::Debug + Send + Sync + 'static
{
    fn zeros() -> Self;
}

impl<T: Real, const N: usize> Array<T> for [T; N] {
    fn zeros() -> Self {
        [T::zero(); N]
    }
}

/// A generated mechanism: sizes known at compile time, arrays on the stack, no allocation.
pub trait Mechanism<T: Real>: Send + Sync {
    const NAME: &'static str;
    const INPUTS: usize;
    const UNKNOWNS: usize;
    const POINTS: usize;
    /// `[T; INPUTS]`
    type X: Array<T>;
    /// `[T; UNKNOWNS]`
    type Q: Array<T>;
    /// The state between simulator ticks (`mechgen::Tick` of this mechanism's sizes).
    type Tick: Copy + core::fmt::Debug + Send + Sync + 'static;

    fn info(&self) -> &'static StaticInfo;
    /// Φ(x, q).
    fn residual(&self, x: &Self::X, q: &Self::Q) -> Self::Q;
    /// J = ∂Φ/∂q, row-major into `out` (UNKNOWNS × UNKNOWNS).
    fn jacobian(&self, x: &Self::X, q: &Self::Q, out: &mut [T]);
    /// Φx = ∂Φ/∂x, row-major into `out` (UNKNOWNS × INPUTS).
    fn input_jacobian(&self, x: &Self::X, q: &Self::Q, out: &mut [T]);
    /// J̇, row-major into `out`.
    fn jacobian_dot(&self, x: &Self::X, q: &Self::Q, xd: &Self::X, qd: &Self::Q, out: &mut [T]);
    /// γ with J q̈ = γ.
    fn acceleration_rhs(
        &self,
        x: &Self::X,
        q: &Self::Q,
        xd: &Self::X,
        qd: &Self::Q,
        xdd: &Self::X,
    ) -> Self::Q;
    fn solve_position(
        &self,
        x: &Self::X,
        q: &mut Self::Q,
        options: &NewtonOptions<T>,
    ) -> Result<NewtonReport<T>, SolveError>;
    fn solve_velocity(&self, x: &Self::X, q: &Self::Q, xd: &Self::X)
    -> Result<Self::Q, SolveError>;
    fn solve_acceleration(
        &self,
        x: &Self::X,
        q: &Self::Q,
        xd: &Self::X,
        qd: &Self::Q,
        xdd: &Self::X,
    ) -> Result<Self::Q, SolveError>;
    /// Point motions into `out` (as many as fit).
    #[allow(clippy::too_many_arguments)]
    fn points(
        &self,
        x: &Self::X,
        q: &Self::Q,
        xd: &Self::X,
        qd: &Self::Q,
        xdd: &Self::X,
        qdd: &Self::Q,
        out: &mut [PointMotion<T>],
    );
    /// The first tick of a simulation, solved from `guess` (see [`Mechanism::tick`]).
    fn tick_start(
        &self,
        x: &Self::X,
        xd: &Self::X,
        xdd: &Self::X,
        guess: &Self::Q,
        options: &NewtonOptions<T>,
    ) -> Result<Self::Tick, SolveError>;
    /// One simulator tick from the state `t` to the inputs `x`: a second-order predictor, the
    /// cached sines and cosines rotated, then positions, velocities, accelerations and points.
    /// On error `t` is unchanged.
    fn tick(
        &self,
        t: &mut Self::Tick,
        x: &Self::X,
        xd: &Self::X,
        xdd: &Self::X,
        options: &NewtonOptions<T>,
    ) -> Result<(), SolveError>;
    /// One tick: positions from the guess in `q`, then velocities, accelerations and the points
    /// (into `points`, as many as fit), sharing the trigonometry between the stages.
    #[allow(clippy::too_many_arguments)]
    fn solve_motion(
        &self,
        x: &Self::X,
        xd: &Self::X,
        xdd: &Self::X,
        q: &mut Self::Q,
        qd: &mut Self::Q,
        qdd: &mut Self::Q,
        points: &mut [PointMotion<T>],
        options: &NewtonOptions<T>,
    ) -> Result<NewtonReport<T>, SolveError>;
}

/// Generic code run on every compiled-in mechanism by `visit_all`, with static dispatch.
pub trait Visitor<T: Real> {
    fn visit<M: Mechanism<T> + 'static>(&mut self, mechanism: &M);
}

/// Object-safe kinematics on slices: what sweeps, benches and the CLI use, for generated
/// mechanisms (through [`Mechanism`]) and the generic engine alike. Slices of the wrong length give
/// [`SolveError::BadLength`].
pub trait Kinematics<T: Real> {
    fn info(&self) -> MechanismInfo;
    fn residual(&self, x: &[T], q: &[T], out: &mut [T]) -> Result<(), SolveError>;
    fn jacobian(&self, x: &[T], q: &[T], out: &mut [T]) -> Result<(), SolveError>;
    fn input_jacobian(&self, x: &[T], q: &[T], out: &mut [T]) -> Result<(), SolveError>;
    fn jacobian_dot(
        &self,
        x: &[T],
        q: &[T],
        xd: &[T],
        qd: &[T],
        out: &mut [T],
    ) -> Result<(), SolveError>;
    fn acceleration_rhs(
        &self,
        x: &[T],
        q: &[T],
        xd: &[T],
        qd: &[T],
        xdd: &[T],
        out: &mut [T],
    ) -> Result<(), SolveError>;
    fn solve_position(
        &self,
        x: &[T],
        q: &mut [T],
        options: &NewtonOptions<T>,
    ) -> Result<NewtonReport<T>, SolveError>;
    fn solve_velocity(&self, x: &[T], q: &[T], xd: &[T], qd: &mut [T]) -> Result<(), SolveError>;
    #[allow(clippy::too_many_arguments)]
    fn solve_acceleration(
        &self,
        x: &[T],
        q: &[T],
        xd: &[T],
        qd: &[T],
        xdd: &[T],
        qdd: &mut [T],
    ) -> Result<(), SolveError>;
    #[allow(clippy::too_many_arguments)]
    fn points(
        &self,
        x: &[T],
        q: &[T],
        xd: &[T],
        qd: &[T],
        xdd: &[T],
        qdd: &[T],
        out: &mut [PointMotion<T>],
    ) -> Result<(), SolveError>;
    /// One tick: positions from the guess in `q`, then velocities, accelerations and points. The
    /// default calls the four solves in turn; generated mechanisms share work between them.
    #[allow(clippy::too_many_arguments)]
    fn solve_motion(
        &self,
        x: &[T],
        xd: &[T],
        xdd: &[T],
        q: &mut [T],
        qd: &mut [T],
        qdd: &mut [T],
        points: &mut [PointMotion<T>],
        options: &NewtonOptions<T>,
    ) -> Result<NewtonReport<T>, SolveError> {
        let report = self.solve_position(x, q, options)?;
        self.solve_velocity(x, q, xd, qd)?;
        self.solve_acceleration(x, q, xd, qd, xdd, qdd)?;
        self.points(x, q, xd, qd, xdd, qdd, points)?;
        Ok(report)
    }
}

fn arr<T: Real, A: Array<T>>(s: &[T]) -> Result<A, SolveError> {
    let mut a = A::zeros();
    let dst = a.as_mut();
    if dst.len() != s.len() {
        return Err(SolveError::BadLength {
            expected: dst.len(),
            got: s.len(),
        });
    }
    dst.copy_from_slice(s);
    Ok(a)
}

fn put<T: Real>(dst: &mut [T], src: &[T]) -> Result<(), SolveError> {
    if dst.len() != src.len() {
        return Err(SolveError::BadLength {
            expected: src.len(),
            got: dst.len(),
        });
    }
    dst.copy_from_slice(src);
    Ok(())
}

/// `Ok` when the slice has `expected` elements, else `SolveError::BadLength` (the object-safe
/// trait's length check, shared with run-time engines).
pub fn len<T>(s: &[T], expected: usize) -> Result<(), SolveError> {
    if s.len() == expected {
        Ok(())
    } else {
        Err(SolveError::BadLength {
            expected,
            got: s.len(),
        })
    }
}

impl<T: Real, M: Mechanism<T>> Kinematics<T> for M {
    fn info(&self) -> MechanismInfo {
        Mechanism::info(self).into()
    }
    fn residual(&self, x: &[T], q: &[T], out: &mut [T]) -> Result<(), SolveError> {
        let r = Mechanism::residual(self, &arr(x)?, &arr(q)?);
        put(out, r.as_ref())
    }
    fn jacobian(&self, x: &[T], q: &[T], out: &mut [T]) -> Result<(), SolveError> {
        len(out, M::UNKNOWNS * M::UNKNOWNS)?;
        Mechanism::jacobian(self, &arr(x)?, &arr(q)?, out);
        Ok(())
    }
    fn input_jacobian(&self, x: &[T], q: &[T], out: &mut [T]) -> Result<(), SolveError> {
        len(out, M::UNKNOWNS * M::INPUTS)?;
        Mechanism::input_jacobian(self, &arr(x)?, &arr(q)?, out);
        Ok(())
    }
    fn jacobian_dot(
        &self,
        x: &[T],
        q: &[T],
        xd: &[T],
        qd: &[T],
        out: &mut [T],
    ) -> Result<(), SolveError> {
        len(out, M::UNKNOWNS * M::UNKNOWNS)?;
        Mechanism::jacobian_dot(self, &arr(x)?, &arr(q)?, &arr(xd)?, &arr(qd)?, out);
        Ok(())
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
        let g =
            Mechanism::acceleration_rhs(self, &arr(x)?, &arr(q)?, &arr(xd)?, &arr(qd)?, &arr(xdd)?);
        put(out, g.as_ref())
    }
    fn solve_position(
        &self,
        x: &[T],
        q: &mut [T],
        options: &NewtonOptions<T>,
    ) -> Result<NewtonReport<T>, SolveError> {
        let mut qa: M::Q = arr(q)?;
        let report = Mechanism::solve_position(self, &arr(x)?, &mut qa, options)?;
        put(q, qa.as_ref())?;
        Ok(report)
    }
    fn solve_velocity(&self, x: &[T], q: &[T], xd: &[T], qd: &mut [T]) -> Result<(), SolveError> {
        let v = Mechanism::solve_velocity(self, &arr(x)?, &arr(q)?, &arr(xd)?)?;
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
        let a = Mechanism::solve_acceleration(
            self,
            &arr(x)?,
            &arr(q)?,
            &arr(xd)?,
            &arr(qd)?,
            &arr(xdd)?,
        )?;
        put(qdd, a.as_ref())
    }
    fn points(
        &self,
        x: &[T],
        q: &[T],
        xd: &[T],
        qd: &[T],
        xdd: &[T],
        qdd: &[T],
        out: &mut [PointMotion<T>],
    ) -> Result<(), SolveError> {
        len(out, M::POINTS)?;
        Mechanism::points(
            self,
            &arr(x)?,
            &arr(q)?,
            &arr(xd)?,
            &arr(qd)?,
            &arr(xdd)?,
            &arr(qdd)?,
            out,
        );
        Ok(())
    }
    fn solve_motion(
        &self,
        x: &[T],
        xd: &[T],
        xdd: &[T],
        q: &mut [T],
        qd: &mut [T],
        qdd: &mut [T],
        points: &mut [PointMotion<T>],
        options: &NewtonOptions<T>,
    ) -> Result<NewtonReport<T>, SolveError> {
        len(points, M::POINTS)?;
        let (mut qa, mut qda, mut qdda): (M::Q, M::Q, M::Q) = (arr(q)?, arr(qd)?, arr(qdd)?);
        let report = Mechanism::solve_motion(
            self,
            &arr(x)?,
            &arr(xd)?,
            &arr(xdd)?,
            &mut qa,
            &mut qda,
            &mut qdda,
            points,
            options,
        )?;
        put(q, qa.as_ref())?;
        put(qd, qda.as_ref())?;
        put(qdd, qdda.as_ref())?;
        Ok(report)
    }
}
