//! Block-wise Newton, the one both engines run (generated code on `SMatrix`, the generic engine on
//! `DMatrix`), its options and report. Allocation-free for fixed sizes; every failure is a
//! [`SolveError`]. Elimination is in `elimination.rs`, the unknowns' trigonometry in `trig.rs`.

use nalgebra::allocator::Allocator;

use crate::elimination::gauss_in_place;
pub use crate::trig::{NewtonState, TrigState, rotate};
use nalgebra::{DefaultAllocator, Dim, OMatrix, OVector, SMatrix, SVector};

use crate::error::{Quantity, SolveError, Stage};
use crate::scalar::Real;

/// Newton options. `tolerance` is relative: on angles in radians, on lengths divided by the
/// mechanism's length scale (its largest length param).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonOptions<T> {
    /// Stop when the largest relative step is at most this.
    pub tolerance: T,
    /// Iteration cap per block.
    pub max_iterations: u32,
}

impl<T: Real> Default for NewtonOptions<T> {
    fn default() -> Self {
        NewtonOptions {
            tolerance: T::DEFAULT_TOLERANCE,
            max_iterations: 64,
        }
    }
}

/// How a solve runs: Newton's options for the blocks Newton solves, and whether closed-form
/// blocks are solved in closed form. `SolveOptions::default()` is the usual choice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveOptions<T> {
    /// Tolerance and iteration cap of every Newton block.
    pub newton: NewtonOptions<T>,
    /// Solve closed-form blocks in closed form (exact, no iterations; the default): dyad blocks
    /// in generated solvers, every closed-form kind in the generic engine. `false` runs Newton on
    /// them like on every other block.
    pub closed_forms: bool,
}

impl<T: Real> Default for SolveOptions<T> {
    fn default() -> Self {
        SolveOptions {
            newton: NewtonOptions::default(),
            closed_forms: true,
        }
    }
}

impl<T: Real> From<NewtonOptions<T>> for SolveOptions<T> {
    /// These Newton options, closed forms on.
    fn from(newton: NewtonOptions<T>) -> Self {
        SolveOptions {
            newton,
            closed_forms: true,
        }
    }
}

/// What a position solve did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonReport<T> {
    /// Newton iterations, summed over the blocks.
    pub iterations: u32,
    /// Largest relative residual seen at the last iteration of any block (before its final step).
    pub residual: T,
    /// Smallest pivot ratio (smallest over largest pivot of the column-equilibrated Jacobian
    /// block) at the last iteration of any block: near 0 close to a dead point.
    pub pivot_ratio: T,
}

impl<T: Real> NewtonReport<T> {
    pub fn new() -> Self {
        NewtonReport {
            iterations: 0,
            residual: T::zero(),
            pivot_ratio: T::one(),
        }
    }

    /// A condition estimate of the Jacobian: 1 / pivot ratio.
    pub fn condition(&self) -> T {
        if self.pivot_ratio > T::zero() {
            T::one() / self.pivot_ratio
        } else {
            T::lit(f64::INFINITY)
        }
    }
}

impl<T: Real> Default for NewtonReport<T> {
    fn default() -> Self {
        Self::new()
    }
}

/// Fails on the first non-finite value.
pub fn check_finite<T: Real>(quantity: Quantity, values: &[T]) -> Result<(), SolveError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(SolveError::NonFinite { quantity, index }),
        None => Ok(()),
    }
}

/// [`check_finite`] of a motion's inputs, then of their rates, then of their accelerations: the
/// first value that is not finite, named.
pub fn check_inputs<T: Real>(x: &[T], xd: &[T], xdd: &[T]) -> Result<(), SolveError> {
    check_finite(Quantity::Input, x)?;
    check_finite(Quantity::InputRate, xd)?;
    check_finite(Quantity::InputAcceleration, xdd)
}

/// [`check_finite`] over the values with `mask[i]` only (a scene checks the params it reads).
pub fn check_finite_in<T: Real, const N: usize>(
    quantity: Quantity,
    values: &[T; N],
    mask: [bool; N],
) -> Result<(), SolveError> {
    match (0..N).find(|&i| mask[i] && !values[i].is_finite()) {
        Some(index) => Err(SolveError::NonFinite { quantity, index }),
        None => Ok(()),
    }
}

/// A step counts as progress when it is below this fraction of the smallest step so far. Newton
/// converges quadratically at a regular solution and linearly (ratio 1/2) at a dead point, so a
/// converging run makes progress at every iteration.
const PROGRESS: f64 = 0.9;

/// Consecutive iterations without progress after which the block is declared unassemblable. Just
/// past a dead point no solution exists and the iterates wander (their steps never fall below the
/// square root of the distance to the dead point), so waiting longer only risks a wild step that
/// lands on another assembly branch.
const STALL_LIMIT: u32 = 6;

/// The longest Newton step taken, relative (radians; lengths over the length scale): one radian.
const MAX_STEP: f64 = 1.0;

/// Newton's method on one diagonal block: `q[idx]` are the block's unknowns (`length[i]` when
/// unknown `i` is a length), `eval` gives the block residual and Jacobian at `q`.
///
/// Stops on what the steps do, not on a fixed count (near a dead point convergence is only
/// linear):
/// - converged when the relative step is at most the tolerance; when the convergence is quadratic
///   and the next step would be at rounding level (so it is not taken); or when the steps stop
///   shrinking while the residual is at rounding level (nothing more to gain in this precision);
/// - `Unassemblable` when the steps stop shrinking (`STALL_LIMIT` = 6 iterations without progress)
///   while the residual is not at rounding level: no configuration near the guess, as just past a
///   dead point;
/// - `NoConvergence` when the iteration cap is hit while the steps are still shrinking (the cap or
///   the tolerance is too tight for this guess);
/// - `Singular` when the Jacobian block is singular to working precision away from a solution.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn newton_block<T: Real, const K: usize, S: NewtonState<T> + ?Sized>(
    block: usize,
    q: &mut S,
    idx: [usize; K],
    length: [bool; K],
    scale: T,
    options: &NewtonOptions<T>,
    report: &mut NewtonReport<T>,
    eval: impl Fn(&S) -> (SVector<T, K>, SMatrix<T, K, K>),
) -> Result<(), SolveError> {
    let mut work = NewtonWork {
        residual: SVector::<T, K>::zeros(),
        jacobian: SMatrix::<T, K, K>::zeros(),
        scale: SVector::<T, K>::zeros(),
    };
    newton_in_place(
        block,
        q,
        &idx,
        &length,
        scale,
        options,
        report,
        &mut work,
        |q, r, j| {
            let (rr, jj) = eval(q);
            *r = rr;
            *j = jj;
        },
    )
}

/// Workspace of [`newton_in_place`]: the block's residual, Jacobian and column scales.
pub struct NewtonWork<T: Real, D: Dim>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    pub residual: OVector<T, D>,
    pub jacobian: OMatrix<T, D, D>,
    pub scale: OVector<T, D>,
}

/// [`newton_block`] for any block dimension (fixed or dynamic) and any storage of `q`: the one
/// Newton both engines run. `eval` writes the block residual and Jacobian at `q`.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn newton_in_place<T: Real, D: Dim, Q: NewtonState<T> + ?Sized>(
    block: usize,
    q: &mut Q,
    idx: &[usize],
    length: &[bool],
    scale: T,
    options: &NewtonOptions<T>,
    report: &mut NewtonReport<T>,
    work: &mut NewtonWork<T, D>,
    mut eval: impl FnMut(&Q, &mut OVector<T, D>, &mut OMatrix<T, D, D>),
) -> Result<(), SolveError>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    let inv_scale = T::one() / scale;
    // A relative residual this small is what rounding leaves in the loop sums.
    let rounding = T::EPSILON * T::lit(64.0);
    let mut best_step = T::lit(f64::INFINITY);
    let mut prev_step = T::lit(f64::INFINITY);
    let mut best_residual = T::lit(f64::INFINITY);
    let mut stalls = 0u32;
    let mut residual = T::zero();
    let mut step = T::zero();
    let mut converged = |it: u32, residual: T, ratio: T| {
        report.iterations += it;
        report.residual = report.residual.max(residual);
        report.pivot_ratio = report.pivot_ratio.min(ratio);
        Ok(())
    };
    for it in 1..=options.max_iterations {
        eval(q, &mut work.residual, &mut work.jacobian);
        // `max` drops NaN operands, so a NaN residual (a coordinate driven to infinity, e.g. by
        // huge params) is caught entry by entry, not from the maximum.
        residual = T::zero();
        let mut finite = true;
        for v in work.residual.iter() {
            finite &= v.is_finite();
            residual = residual.max(v.abs() * inv_scale);
        }
        if !finite || !residual.is_finite() {
            return Err(SolveError::Overflow {
                block,
                stage: Stage::Position,
            });
        }
        best_residual = best_residual.min(residual);
        let ratio = match gauss_in_place(&mut work.jacobian, &mut work.residual, &mut work.scale) {
            Ok(ratio) => ratio,
            Err(ratio) => {
                // An exact solution at a singular Jacobian (a dead point hit exactly) is still a solution.
                if residual <= rounding {
                    return converged(it - 1, residual, ratio);
                }
                return Err(SolveError::Singular {
                    block,
                    stage: Stage::Position,
                    pivot_ratio: ratio.to_f64(),
                });
            }
        };
        // `work.residual` now holds the step dz: its size, relative (radians; lengths over the
        // length scale).
        step = T::zero();
        for (i, &is_length) in length.iter().enumerate() {
            let dz = work.residual[i].abs();
            step = step.max(if is_length { dz * inv_scale } else { dz });
        }
        // A step longer than MAX_STEP (far from a solution) is shortened along its direction, so
        // the iterates stay near the guess instead of landing whole turns or branches away.
        if step > T::lit(MAX_STEP) {
            let shrink = T::lit(MAX_STEP) / step;
            for i in 0..idx.len() {
                work.residual[i] *= shrink;
            }
            step = T::lit(MAX_STEP);
        }
        for (i, &k) in idx.iter().enumerate() {
            q.apply(k, work.residual[i]);
            finite &= work.residual[i].is_finite() && q.get(k).is_finite();
        }
        if !finite || !step.is_finite() {
            return Err(SolveError::Unassemblable {
                block,
                residual: best_residual.to_f64(),
                iterations: it,
            });
        }
        // Quadratic convergence: the next step would be about step³ / prev_step², so once that
        // is at rounding level the answer is already as accurate as the precision allows.
        // (Written as step·θ², θ = step / prev_step, so that nothing overflows; only small steps,
        // in the quadratic regime, qualify.)
        let theta = step / prev_step;
        let done = it > 1
            && step <= T::lit(1e-3)
            && theta <= T::lit(0.5)
            && step * theta * theta <= T::EPSILON;
        if step <= options.tolerance || done {
            return converged(it, residual, ratio);
        }
        prev_step = step;
        if step < best_step * T::lit(PROGRESS) {
            best_step = step;
            stalls = 0;
        } else {
            stalls += 1;
            // Steps that stopped shrinking at a residual only rounding explains: converged as far
            // as this precision allows (near a dead point the last digits of q are ill-determined).
            // The iterate the residual was measured at is kept, not the noise step from it.
            if residual <= rounding {
                for (i, &k) in idx.iter().enumerate() {
                    q.apply(k, -work.residual[i]);
                }
                return converged(it, residual, ratio);
            }
            if stalls >= STALL_LIMIT {
                return Err(SolveError::Unassemblable {
                    block,
                    residual: best_residual.to_f64(),
                    iterations: it,
                });
            }
        }
    }
    let iterations = options.max_iterations;
    if stalls == 0 {
        Err(SolveError::NoConvergence {
            block,
            residual: residual.to_f64(),
            step: step.to_f64(),
            iterations,
        })
    } else {
        Err(SolveError::Unassemblable {
            block,
            residual: best_residual.to_f64(),
            iterations,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Newton on the fold f(s) = s² − c from s = 1: two roots ±√c for c > 0, a double root at
    /// c = 0 (a dead point), none for c < 0 (past it).
    fn fold(c: f64, options: &NewtonOptions<f64>) -> (Result<(), SolveError>, f64, u32) {
        let mut q = [1.0];
        let mut report = NewtonReport::new();
        let result = newton_block(0, &mut q, [0], [false], 1.0, options, &mut report, |q| {
            (
                SVector::from([q[0] * q[0] - c]),
                SMatrix::from([[2.0 * q[0]]]),
            )
        });
        (result, q[0], report.iterations)
    }

    #[test]
    fn regular_root_converges() {
        let (r, s, _) = fold(0.25, &NewtonOptions::default());
        assert_eq!(r, Ok(()));
        assert!((s - 0.5).abs() < 1e-15);
    }

    #[test]
    fn double_root_converges_linearly_without_a_fixed_count() {
        let (r, s, iterations) = fold(0.0, &NewtonOptions::default());
        assert_eq!(r, Ok(()));
        // Halving from 1 to the rounding level of a double root (√ε ≈ 1.5e-8) takes ~26 steps.
        assert!(s.abs() < 1e-7 && iterations > 20, "{s} after {iterations}");
    }

    /// (Within rounding of the dead point, |c| below 64 ε, a residual of |c| is a solution.)
    #[test]
    fn no_root_is_unassemblable_early() {
        for c in [-1e-12, -1e-8, -1e-4, -0.5] {
            let (r, _, _) = fold(c, &NewtonOptions::default());
            match r {
                Err(SolveError::Unassemblable { iterations, .. }) => {
                    assert!(iterations < 64, "c = {c}: {iterations} iterations")
                }
                other => panic!("c = {c}: {other:?}"),
            }
        }
    }

    #[test]
    fn a_tight_cap_on_a_converging_run_is_no_convergence() {
        let tight = NewtonOptions {
            max_iterations: 2,
            ..NewtonOptions::default()
        };
        let (r, _, _) = fold(0.25, &tight);
        assert!(matches!(r, Err(SolveError::NoConvergence { .. })), "{r:?}");
    }
}
