//! Error values of the solvers: every failure is one of these, never a panic or a NaN.

use core::fmt;

/// Which solve failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Stage {
    Position,
    Velocity,
    Acceleration,
    /// The derivatives of the unknowns with respect to the params.
    Sensitivity,
}

/// Which argument held a non-finite value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Quantity {
    Param,
    Input,
    InputRate,
    InputAcceleration,
    /// The starting guess of a position solve.
    Guess,
    /// The (solved) unknowns given to a velocity or acceleration solve.
    Position,
    /// The unknowns' velocities given to an acceleration solve.
    Rate,
}

/// Why a solve failed. `block` is the index of the diagonal block (see `StaticInfo::blocks`).
/// Numbers are reported in f64 whatever the solver's precision.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum SolveError {
    /// A param, input, rate or guess is NaN or infinite (`index` in its array).
    NonFinite { quantity: Quantity, index: usize },
    /// Newton found no configuration: its steps stopped shrinking while the residual stayed above
    /// rounding level (the smallest relative residual seen is given). Past a dead point, or an
    /// input out of the mechanism's range.
    Unassemblable {
        block: usize,
        residual: f64,
        iterations: u32,
    },
    /// The Jacobian block is singular to working precision (a dead point): `pivot_ratio` is the
    /// smallest over the largest pivot of the elimination.
    Singular {
        block: usize,
        stage: Stage,
        pivot_ratio: f64,
    },
    /// Newton hit the iteration cap while its steps were still shrinking: it was converging, but
    /// the cap is too tight for this guess (raise `max_iterations` or loosen `tolerance`).
    NoConvergence {
        block: usize,
        residual: f64,
        step: f64,
        iterations: u32,
    },
    /// A slice given to the object-safe API has the wrong length.
    BadLength { expected: usize, got: usize },
    /// The computation produced a non-finite value from finite arguments (overflow).
    Overflow { block: usize, stage: Stage },
    /// A tick was asked for before a successful first tick (`DynTick::start`).
    NotStarted,
    /// An index given to the object-safe API (an input, a point) is not below `len`.
    OutOfRange { index: usize, len: usize },
    /// A body's mass or inertia, at the params given, is negative or not finite (the file's
    /// values are checked when it is read; params changed at run time can make them so).
    BadMass { body: usize },
    /// A simulation's step size shrank below what the time can resolve at `time` (seconds): the
    /// equation of motion changes abruptly there in a way its error control cannot step over.
    StepTooSmall { time: f64, step: f64 },
    /// A simulation used up its steps (`SimulationOptions::max_steps`) before the time asked for,
    /// at `time` (seconds).
    StepLimit { time: f64, steps: u32 },
}

impl SolveError {
    /// Short kebab-case status, as in the sweep CSV.
    pub fn status(&self) -> &'static str {
        match self {
            SolveError::NonFinite { .. } => "non-finite-input",
            SolveError::Unassemblable { .. } => "unassemblable",
            SolveError::Singular { .. } => "singular",
            SolveError::NoConvergence { .. } => "no-convergence",
            SolveError::BadLength { .. } => "bad-length",
            SolveError::Overflow { .. } => "overflow",
            SolveError::NotStarted => "not-started",
            SolveError::OutOfRange { .. } => "out-of-range",
            SolveError::BadMass { .. } => "bad-mass",
            SolveError::StepTooSmall { .. } => "step-too-small",
            SolveError::StepLimit { .. } => "step-limit",
        }
    }
}

impl fmt::Display for SolveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SolveError::NonFinite { quantity, index } => {
                write!(f, "non-finite {quantity:?} at index {index}")
            }
            SolveError::Unassemblable {
                block,
                residual,
                iterations,
            } => write!(
                f,
                "no assembly near the guess in block {block} (relative residual {residual:.3e} after {iterations} iterations)"
            ),
            SolveError::Singular {
                block,
                stage,
                pivot_ratio,
            } => {
                write!(
                    f,
                    "singular Jacobian in block {block} ({stage:?} solve, pivot ratio {pivot_ratio:.3e})"
                )
            }
            SolveError::NoConvergence {
                block,
                residual,
                step,
                iterations,
            } => write!(
                f,
                "no convergence in block {block} after {iterations} iterations (relative residual {residual:.3e}, last step {step:.3e})"
            ),
            SolveError::BadLength { expected, got } => {
                write!(f, "slice of length {got}, expected {expected}")
            }
            SolveError::Overflow { block, stage } => {
                write!(f, "overflow in block {block} ({stage:?} solve)")
            }
            SolveError::NotStarted => write!(f, "tick before a first successful tick"),
            SolveError::OutOfRange { index, len } => {
                write!(f, "index {index} out of range (there are {len})")
            }
            SolveError::BadMass { body } => {
                write!(
                    f,
                    "body {body} has a negative or non-finite mass or inertia"
                )
            }
            SolveError::StepTooSmall { time, step } => write!(
                f,
                "the simulation's step shrank to {step:.3e} s at t = {time} s: the motion changes abruptly there"
            ),
            SolveError::StepLimit { time, steps } => write!(
                f,
                "the simulation used up its {steps} steps at t = {time} s"
            ),
        }
    }
}

impl core::error::Error for SolveError {}

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
