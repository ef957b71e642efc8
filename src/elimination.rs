//! Gaussian elimination with column equilibration and partial pivoting, for any nalgebra
//! dimension (`SMatrix` in generated code, `DMatrix` in the generic engine): the linear kernel of
//! Newton steps and of the velocity and acceleration solves, with the pivot ratio as the
//! condition estimate every answer reports.

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OMatrix, OVector, SMatrix, SVector};

use crate::error::{SolveError, Stage};
use crate::scalar::Real;

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
/// pivot ratio is returned; `a` is overwritten (its diagonal with the reciprocal pivots) and
/// `scale` is workspace of `b`'s size (the reciprocal column scales).
// `!(a > b)` is deliberate: a NaN must fail the test.
#[inline(always)]
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
        // Reciprocals: one division per column and per pivot, the rest multiplications.
        let inv = T::one() / m;
        scale[j] = inv;
        for i in 0..k {
            a[(i, j)] *= inv;
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
        let inv_piv = T::one() / piv;
        a[(c, c)] = inv_piv;
        for r in c + 1..k {
            let f = a[(r, c)] * inv_piv;
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
        b[c] = s * a[(c, c)];
    }
    for j in 0..k {
        b[j] *= scale[j];
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
