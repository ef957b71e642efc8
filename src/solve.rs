//! Numerical kernels the generated solvers call: Gaussian elimination on fixed-size blocks and
//! block-wise Newton. Allocation-free; every failure is a [`SolveError`].

use nalgebra::allocator::Allocator;
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
#[inline]
pub fn gauss<T: Real, const K: usize>(
    mut a: SMatrix<T, K, K>,
    mut b: SVector<T, K>,
) -> Result<(SVector<T, K>, T), T> {
    let mut scale = SVector::<T, K>::zeros();
    let ratio = gauss_in_place(&mut a, &mut b, &mut scale)?;
    Ok((b, ratio))
}

/// [`gauss`] for any dimension (fixed or dynamic): on success `b` holds the solution and the
/// pivot ratio is returned; `a` is overwritten and `scale` is workspace of `b`'s size.
// `!(a > b)` is deliberate: a NaN must fail the test.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn gauss_in_place<T: Real, D: Dim>(
    a: &mut OMatrix<T, D, D>,
    b: &mut OVector<T, D>,
    scale: &mut OVector<T, D>,
) -> Result<T, T>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    let k = b.len();
    for j in 0..k {
        let mut m = T::zero();
        for i in 0..k {
            m = m.max(a[(i, j)].abs());
        }
        if !(m > T::zero()) || !m.is_finite() {
            return Err(T::zero());
        }
        scale[j] = m;
        for i in 0..k {
            a[(i, j)] = a[(i, j)] / m;
        }
    }
    let (mut pmin, mut pmax) = (T::lit(f64::INFINITY), T::zero());
    for c in 0..k {
        let mut p = c;
        for r in c + 1..k {
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
        if !(pmin > pmax * T::EPSILON * T::lit(k as f64)) {
            return Err(if pmax > T::zero() {
                pmin / pmax
            } else {
                T::zero()
            });
        }
        for r in c + 1..k {
            let f = a[(r, c)] / piv;
            if f != T::zero() {
                for j in c + 1..k {
                    let v = a[(c, j)];
                    a[(r, j)] -= f * v;
                }
                let v = b[c];
                b[r] -= f * v;
            }
        }
    }
    for c in (0..k).rev() {
        let mut s = b[c];
        for j in c + 1..k {
            s -= a[(c, j)] * b[j];
        }
        b[c] = s / a[(c, c)];
    }
    for j in 0..k {
        b[j] = b[j] / scale[j];
    }
    Ok(pmin / pmax)
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
/// (rounding noise; convergence is only linear at a dead point, so no fixed count is assumed). On
/// failure: `Unassemblable` when the residual stayed large, `NoConvergence` when it is small but
/// the steps are not.
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
pub fn newton_in_place<T: Real, D: Dim, Q: AsRef<[T]> + AsMut<[T]> + ?Sized>(
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
    let rounding = T::EPSILON * T::lit(64.0);
    let mut prev_step = T::lit(f64::INFINITY);
    let mut residual = T::zero();
    let mut step = T::zero();
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
            return Err(SolveError::Unassemblable {
                block,
                residual: f64::INFINITY,
                iterations: it,
            });
        }
        let ratio = match gauss_in_place(&mut work.jacobian, &mut work.residual, &mut work.scale) {
            Ok(ratio) => ratio,
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
        let qs = q.as_mut();
        for (i, (&k, &is_length)) in idx.iter().zip(length).enumerate() {
            let dz = work.residual[i];
            let s = if is_length {
                dz.abs() * inv_scale
            } else {
                dz.abs()
            };
            step = step.max(s);
            qs[k] -= dz;
            finite &= s.is_finite() && qs[k].is_finite();
        }
        if !finite || !step.is_finite() {
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
