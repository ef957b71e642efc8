//! Generic engine, a block's Jacobian factored for its rates: one factorization serves the
//! velocity and the acceleration (kept between the two as [`Kept`]), a 1×1 or 2×2 block by the
//! runtime's `factor_block` straight from a tape's outputs, a larger one in place in the
//! workspace; the sensitivities solve with the same factors ([`BlockSolve`]).

use mechgen_runtime::elimination::{Factored, factor_block, factor_in_place, solve_factored};
use mechgen_runtime::error::{SolveError, Stage};
use mechgen_runtime::nalgebra::{DMatrix, DVector, SMatrix, SVector};
use mechgen_runtime::scalar::Real;
use mechgen_runtime::sensitivity::BlockSolve;

use super::scratch::{Sized, sized};

impl<T: Real> BlockSolve<T> for Factors<'_, T> {
    fn solve_slice(&self, block: usize, stage: Stage, rhs: &mut [T]) -> Result<(), SolveError> {
        match self {
            Factors::Any {
                lu, scale, swaps, ..
            } => {
                let mut v = DVector::from_column_slice(rhs);
                solve_factored(block, stage, lu, scale, swaps, &mut v)?;
                rhs.copy_from_slice(v.as_slice());
                Ok(())
            }
            small => small.solve_small(block, stage, rhs),
        }
    }
}

/// A block Jacobian factored for its rates: a 1×1 or 2×2 block by the runtime's `factor_block`
/// (the reciprocal, Cramer's inverse), exactly as generated code factors it; a larger one by
/// elimination in place on the workspace's `DMatrix` (the same `lu_in_place` generated code runs
/// on its `SMatrix`).
pub(super) enum Factors<'a, T: Real> {
    One(Factored<T, 1>),
    Two(Factored<T, 2>),
    Any {
        lu: &'a DMatrix<T>,
        scale: &'a DVector<T>,
        swaps: &'a [usize],
        /// Where a right-hand side is solved.
        rhs: &'a mut DVector<T>,
    },
}

/// [`Factors`] kept between a block's velocity and its acceleration: a larger block's stay in
/// the workspace of its size.
#[derive(Clone, Copy, Debug)]
pub(super) enum Kept<T> {
    One(Factored<T, 1>),
    Two(Factored<T, 2>),
    Any,
}

impl<'a, T: Real> Factors<'a, T> {
    /// The factors of a block's Jacobian, given after its k right-hand-side values in `values`
    /// (row-major): a 1×1 or 2×2 one straight from them, a larger one in its workspace of
    /// `by_size` (its right-hand side copied there too).
    pub(super) fn of_block(
        block: usize,
        stage: Stage,
        values: &[T],
        k: usize,
        by_size: &'a mut Vec<Option<Sized<T>>>,
    ) -> Result<Self, SolveError> {
        Ok(match k {
            1 => Factors::One(factor_small(block, stage, values)?),
            2 => Factors::Two(factor_small(block, stage, values)?),
            _ => {
                let size = sized(by_size, k);
                fill(values, k, &mut size.rhs, &mut size.jac);
                let Sized {
                    jac,
                    scale,
                    swaps,
                    rhs,
                    ..
                } = size;
                Factors::new(block, stage, jac, scale, swaps, rhs)?
            }
        })
    }

    /// What to keep of these factors ([`Factors::kept`] makes them again).
    pub(super) fn keep(&self) -> Kept<T> {
        match self {
            Factors::One(f) => Kept::One(*f),
            Factors::Two(f) => Kept::Two(*f),
            Factors::Any { .. } => Kept::Any,
        }
    }

    /// The factors `kept` describes, a larger block's (of size `k`) from its workspace in
    /// `by_size`.
    pub(super) fn kept(kept: Kept<T>, k: usize, by_size: &'a mut Vec<Option<Sized<T>>>) -> Self {
        match kept {
            Kept::One(f) => Factors::One(f),
            Kept::Two(f) => Factors::Two(f),
            Kept::Any => {
                let size = sized(by_size, k);
                Factors::Any {
                    lu: &size.jac,
                    scale: &size.scale,
                    swaps: &size.swaps,
                    rhs: &mut size.rhs,
                }
            }
        }
    }

    /// `rhs` becomes the solution (a slice of the block's size), or `Overflow` for `stage`.
    pub(super) fn solve_into(
        &mut self,
        block: usize,
        stage: Stage,
        rhs: &mut [T],
    ) -> Result<(), SolveError> {
        match self {
            Factors::Any {
                lu,
                scale,
                swaps,
                rhs: v,
            } => {
                v.as_mut_slice().copy_from_slice(rhs);
                solve_factored(block, stage, lu, scale, swaps, v)?;
                rhs.copy_from_slice(v.as_slice());
                Ok(())
            }
            small => small.solve_small(block, stage, rhs),
        }
    }

    /// [`Factors::solve_into`] of a 1×1 or 2×2 block (a larger one is left as it is).
    fn solve_small(&self, block: usize, stage: Stage, rhs: &mut [T]) -> Result<(), SolveError> {
        match self {
            Factors::One(f) => solve_small(f, block, stage, rhs),
            Factors::Two(f) => solve_small(f, block, stage, rhs),
            Factors::Any { .. } => Ok(()),
        }
    }

    /// Factors `jac` (a larger one in place, with `scale`, `swaps` and `rhs` its workspace).
    pub(super) fn new(
        block: usize,
        stage: Stage,
        jac: &'a mut DMatrix<T>,
        scale: &'a mut DVector<T>,
        swaps: &'a mut [usize],
        rhs: &'a mut DVector<T>,
    ) -> Result<Self, SolveError> {
        Ok(match jac.nrows() {
            1 => Factors::One(factor_block(
                block,
                stage,
                SMatrix::from_fn(|i, j| jac[(i, j)]),
            )?),
            2 => Factors::Two(factor_block(
                block,
                stage,
                SMatrix::from_fn(|i, j| jac[(i, j)]),
            )?),
            _ => {
                factor_in_place(block, stage, jac, scale, swaps)?;
                Factors::Any {
                    lu: jac,
                    scale,
                    swaps,
                    rhs,
                }
            }
        })
    }
}

/// A 1×1 or 2×2 block's factors (the runtime's `factor_block`, as generated code factors it)
/// straight from a tape's outputs: K right-hand-side values, then the Jacobian row-major.
#[inline(always)]
pub(crate) fn factor_small<T: Real, const K: usize>(
    block: usize,
    stage: Stage,
    values: &[T],
) -> Result<Factored<T, K>, SolveError> {
    factor_block(block, stage, SMatrix::from_fn(|i, j| values[K + i * K + j]))
}

/// The first K values of `rhs` become the solution by the factors `f`, or `Overflow`.
#[inline(always)]
pub(crate) fn solve_small<T: Real, const K: usize>(
    f: &Factored<T, K>,
    block: usize,
    stage: Stage,
    rhs: &mut [T],
) -> Result<(), SolveError> {
    let z = f.solve(block, stage, SVector::from_fn(|i, _| rhs[i]))?;
    rhs[..K].copy_from_slice(z.as_slice());
    Ok(())
}

/// Splits a block tape's outputs into its vector (first `k`) and its matrix (row-major).
pub(super) fn fill<T: Real>(out: &[T], k: usize, v: &mut DVector<T>, m: &mut DMatrix<T>) {
    for i in 0..k {
        v[i] = out[i];
        for j in 0..k {
            m[(i, j)] = out[k + i * k + j];
        }
    }
}
