//! Numerical kernels the generated solvers call: Gaussian elimination on fixed-size blocks and
//! block-wise Newton. Allocation-free; every failure is a [`SolveError`].

use nalgebra::{SMatrix, SVector};

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

/// Solves `a z = b` by Gaussian elimination with column equilibration and partial pivoting.
/// Returns the solution and the pivot ratio, or the pivot ratio when `a` is singular to working
/// precision.
// `!(a > b)` is deliberate: a NaN must fail the test.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn gauss<T: Real, const K: usize>(
    mut a: SMatrix<T, K, K>,
    mut b: SVector<T, K>,
) -> Result<(SVector<T, K>, T), T> {
    let mut col_scale = [T::one(); K];
    for (j, s) in col_scale.iter_mut().enumerate() {
        let mut m = T::zero();
        for i in 0..K {
            m = m.max(a[(i, j)].abs());
        }
        if !(m > T::zero()) || !m.is_finite() {
            return Err(T::zero());
        }
        *s = m;
        for i in 0..K {
            a[(i, j)] = a[(i, j)] / m;
        }
    }
    let (mut pmin, mut pmax) = (T::lit(f64::INFINITY), T::zero());
    for c in 0..K {
        let mut p = c;
        for r in c + 1..K {
            if a[(r, c)].abs() > a[(p, c)].abs() {
                p = r;
            }
        }
        if p != c {
            a.swap_rows(p, c);
            b.swap_rows(p, c);
        }
        let piv = a[(c, c)];
        pmin = pmin.min(piv.abs());
        pmax = pmax.max(piv.abs());
        if !(pmin > pmax * T::EPSILON * T::lit(K as f64)) {
            return Err(if pmax > T::zero() {
                pmin / pmax
            } else {
                T::zero()
            });
        }
        for r in c + 1..K {
            let f = a[(r, c)] / piv;
            if f != T::zero() {
                for k in c + 1..K {
                    let v = a[(c, k)];
                    a[(r, k)] -= f * v;
                }
                let v = b[c];
                b[r] -= f * v;
            }
        }
    }
    for c in (0..K).rev() {
        let mut s = b[c];
        for k in c + 1..K {
            s -= a[(c, k)] * b[k];
        }
        b[c] = s / a[(c, c)];
    }
    for (j, s) in col_scale.iter().enumerate() {
        b[j] = b[j] / *s;
    }
    Ok((b, pmin / pmax))
}

/// One linear block solve of a velocity or acceleration pass.
#[inline]
pub fn solve_block<T: Real, const K: usize>(
    block: usize,
    stage: Stage,
    jac: SMatrix<T, K, K>,
    rhs: SVector<T, K>,
) -> Result<SVector<T, K>, SolveError> {
    match gauss(jac, rhs) {
        Ok((z, _)) if z.iter().all(|v| v.is_finite()) => Ok(z),
        Ok(_) => Err(SolveError::Overflow { block, stage }),
        Err(ratio) => Err(SolveError::Singular {
            block,
            stage,
            pivot_ratio: ratio.to_f64(),
        }),
    }
}

/// Newton's method on one diagonal block: `q[idx]` are the block's unknowns (`length[i]` when
/// unknown `i` is a length), `eval` gives the block residual and Jacobian at `q`.
///
/// Converges when the relative step is at most the tolerance, or when small steps stop shrinking
/// (rounding noise; convergence is only linear at a dead point, so no fixed count is assumed). On failure: `Unassemblable` when the
/// residual stayed large, `NoConvergence` when it is small but the steps are not.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn newton_block<T: Real, const K: usize, const N: usize>(
    block: usize,
    q: &mut [T; N],
    idx: [usize; K],
    length: [bool; K],
    scale: T,
    options: &NewtonOptions<T>,
    report: &mut NewtonReport<T>,
    eval: impl Fn(&[T; N]) -> (SVector<T, K>, SMatrix<T, K, K>),
) -> Result<(), SolveError> {
    let inv_scale = T::one() / scale;
    let rounding = T::EPSILON * T::lit(64.0);
    let mut prev_step = T::lit(f64::INFINITY);
    let mut residual = T::zero();
    let mut step = T::zero();
    for it in 1..=options.max_iterations {
        let (r, jac) = eval(q);
        residual = T::zero();
        for v in r.iter() {
            residual = residual.max(v.abs() * inv_scale);
        }
        if !residual.is_finite() {
            return Err(SolveError::Unassemblable {
                block,
                residual: f64::INFINITY,
                iterations: it,
            });
        }
        let (dz, ratio) = match gauss(jac, r) {
            Ok(s) => s,
            Err(ratio) => {
                // An exact solution at a singular Jacobian (a dead point hit exactly) is still a solution.
                if residual <= rounding {
                    report.iterations += it - 1;
                    report.residual = report.residual.max(residual);
                    report.pivot_ratio = report.pivot_ratio.min(ratio);
                    return Ok(());
                }
                return Err(SolveError::Singular {
                    block,
                    stage: Stage::Position,
                    pivot_ratio: ratio.to_f64(),
                });
            }
        };
        step = T::zero();
        for i in 0..K {
            let s = if length[i] {
                dz[i].abs() * inv_scale
            } else {
                dz[i].abs()
            };
            step = step.max(s);
            q[idx[i]] -= dz[i];
        }
        if !step.is_finite() {
            return Err(SolveError::Unassemblable {
                block,
                residual: residual.to_f64(),
                iterations: it,
            });
        }
        // Steps that stopped shrinking, at a level only rounding explains: nothing more to gain.
        let stagnated = step <= T::EPSILON.sqrt() && step >= prev_step;
        if step <= options.tolerance || stagnated {
            report.iterations += it;
            report.residual = report.residual.max(residual);
            report.pivot_ratio = report.pivot_ratio.min(ratio);
            return Ok(());
        }
        prev_step = step;
    }
    let iterations = options.max_iterations;
    if residual > T::EPSILON.sqrt() {
        Err(SolveError::Unassemblable {
            block,
            residual: residual.to_f64(),
            iterations,
        })
    } else {
        Err(SolveError::NoConvergence {
            block,
            residual: residual.to_f64(),
            step: step.to_f64(),
            iterations,
        })
    }
}

/// Copies a matrix into a row-major slice (as much as fits).
pub fn copy_row_major<T: Real, const R: usize, const C: usize>(
    m: &SMatrix<T, R, C>,
    out: &mut [T],
) {
    for i in 0..R {
        for j in 0..C {
            if let Some(o) = out.get_mut(i * C + j) {
                *o = m[(i, j)];
            }
        }
    }
}
