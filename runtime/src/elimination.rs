//! Gaussian elimination with column equilibration and partial pivoting, for any nalgebra
//! dimension (`SMatrix` in generated code, `DMatrix` in the generic engine): the linear kernel of
//! Newton steps and of the velocity and acceleration solves, with the pivot ratio as the
//! condition estimate every answer reports. A factorization ([`lu_in_place`], [`Factored`]) can
//! serve several right-hand sides: the velocity and the acceleration of a block share their
//! Jacobian. A 2×2 block (the dyads of planar linkages) takes a closed form with the same pivot
//! ratio and the same singularity test as the elimination.

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
/// pivot ratio is returned; `a` is overwritten by its factors and `scale` is workspace of `b`'s
/// size (the reciprocal column scales).
#[inline(always)]
pub fn gauss_in_place<T: Real, D: Dim>(
    a: &mut OMatrix<T, D, D>,
    b: &mut OVector<T, D>,
    scale: &mut OVector<T, D>,
) -> Result<T, T>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    let ratio = lu_in_place(a, scale, |c, p| b.swap_rows(c, p))?;
    lu_solve(a, scale, b);
    Ok(ratio)
}

/// Factors `a` in place: columns equilibrated (their reciprocal maxima into `scale`), then
/// partial pivoting, each row swap `(c, p)` reported to `swap` as it is made. Afterwards `a`
/// holds the unit lower factor's multipliers below the diagonal, the upper factor above it and
/// the reciprocal pivots on it, except for a 2×2 `a`, which holds the inverse of the
/// equilibrated matrix (no swaps). Returns the pivot ratio (smallest over largest pivot), or
/// `Err` with it when `a` is singular to working precision (a zero, infinite or NaN column
/// included). [`lu_solve`] uses the factors.
// `!(a > b)` is deliberate: a NaN must fail the test.
#[inline(always)]
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn lu_in_place<T: Real, D: Dim>(
    a: &mut OMatrix<T, D, D>,
    scale: &mut OVector<T, D>,
    mut swap: impl FnMut(usize, usize),
) -> Result<T, T>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    let k = a.nrows();
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
    let tiny = T::EPSILON * T::lit(k as f64);
    let ratio = |pmin: T, pmax: T| {
        if pmax > T::zero() {
            pmin / pmax
        } else {
            T::zero()
        }
    };
    if k == 2 {
        // The elimination's pivots would be p₁ = max |a₀₀|, |a₁₀| and |det| / p₁.
        let (a00, a01, a10, a11) = (a[(0, 0)], a[(0, 1)], a[(1, 0)], a[(1, 1)]);
        let det = a00 * a11 - a01 * a10;
        let p1 = a00.abs().max(a10.abs());
        let p2 = det.abs() / p1;
        let (pmin, pmax) = (p1.min(p2), p1.max(p2));
        if !(pmin > pmax * tiny) {
            return Err(ratio(pmin, pmax));
        }
        let inv = T::one() / det;
        a[(0, 0)] = a11 * inv;
        a[(0, 1)] = -a01 * inv;
        a[(1, 0)] = -a10 * inv;
        a[(1, 1)] = a00 * inv;
        return Ok(pmin / pmax);
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
            swap(c, p);
        }
        let piv = a[(c, c)];
        pmin = pmin.min(piv.abs());
        pmax = pmax.max(piv.abs());
        if !(pmin > pmax * tiny) {
            return Err(ratio(pmin, pmax));
        }
        let inv_piv = T::one() / piv;
        a[(c, c)] = inv_piv;
        for r in c + 1..k {
            let f = a[(r, c)] * inv_piv;
            a[(r, c)] = f;
            if f != T::zero() {
                for j in c + 1..k {
                    let v = a[(c, j)];
                    a[(r, j)] -= f * v;
                }
            }
        }
    }
    Ok(pmin / pmax)
}

/// Solves with the factors of [`lu_in_place`]: `b`, already permuted by its swaps, becomes the
/// solution.
#[inline(always)]
pub fn lu_solve<T: Real, D: Dim>(a: &OMatrix<T, D, D>, scale: &OVector<T, D>, b: &mut OVector<T, D>)
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    let k = b.len();
    if k == 2 {
        let (b0, b1) = (b[0], b[1]);
        b[0] = a[(0, 0)] * b0 + a[(0, 1)] * b1;
        b[1] = a[(1, 0)] * b0 + a[(1, 1)] * b1;
    } else {
        for c in 0..k {
            let v = b[c];
            if v != T::zero() {
                for r in c + 1..k {
                    b[r] -= a[(r, c)] * v;
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
    }
    for j in 0..k {
        b[j] *= scale[j];
    }
}

/// A block Jacobian factored once for several right-hand sides (the velocity and the
/// acceleration of a block).
#[derive(Clone, Copy, Debug)]
pub struct Factored<T, const K: usize> {
    lu: SMatrix<T, K, K>,
    scale: SVector<T, K>,
    swaps: [usize; K],
    /// The pivot ratio (condition estimate).
    pub pivot_ratio: T,
}

/// Factors block `block`'s Jacobian for a linear solve of `stage`: `Singular` when it is
/// singular to working precision.
// `!(a > b)` is deliberate: a NaN must fail the test.
#[inline(always)]
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn factor_block<T: Real, const K: usize>(
    block: usize,
    stage: Stage,
    mut jac: SMatrix<T, K, K>,
) -> Result<Factored<T, K>, SolveError> {
    let mut scale = SVector::<T, K>::from_element(T::one());
    let mut swaps: [usize; K] = core::array::from_fn(|c| c);
    if K == 1 {
        // One division, which the solves then multiply by (a constant entry folds at compile
        // time); zero or non-finite is singular, as elimination's column test says.
        let a = jac[(0, 0)];
        if !(a.abs() > T::zero()) || !a.is_finite() {
            return Err(SolveError::Singular {
                block,
                stage,
                pivot_ratio: 0.0,
            });
        }
        jac[(0, 0)] = T::one() / a;
        return Ok(Factored {
            lu: jac,
            scale,
            swaps,
            pivot_ratio: T::one(),
        });
    }
    if K == 2 {
        // Cramer, which column scaling does not change; the pivot ratio and the test are the
        // elimination's (its first pivot is 1 after equilibration, its second |det| / (m₀ m₁)).
        let (a00, a01, a10, a11) = (jac[(0, 0)], jac[(0, 1)], jac[(1, 0)], jac[(1, 1)]);
        let det = a00 * a11 - a01 * a10;
        // Plain comparisons (a NaN entry makes `det` NaN, which the test below rejects).
        let larger = |x: T, y: T| if x > y { x } else { y };
        let mm = larger(a00.abs(), a10.abs()) * larger(a01.abs(), a11.abs());
        if mm >= T::MIN_POSITIVE && mm <= T::MAX {
            // `!(… > …)`: a NaN fails. (No division on the way: the ratio itself is only
            // computed where it is read.)
            if !(det.abs() > T::EPSILON * T::lit(2.0) * mm) {
                return Err(SolveError::Singular {
                    block,
                    stage,
                    pivot_ratio: (det.abs() / mm).to_f64(),
                });
            }
            let r = det.abs() / mm;
            let inv = T::one() / det;
            jac[(0, 0)] = a11 * inv;
            jac[(0, 1)] = -a01 * inv;
            jac[(1, 0)] = -a10 * inv;
            jac[(1, 1)] = a00 * inv;
            let pivot_ratio = if r <= T::one() { r } else { T::one() / r };
            return Ok(Factored {
                lu: jac,
                scale,
                swaps,
                pivot_ratio,
            });
        }
        // Entries too large or too small for m₀ m₁: the equilibrated path below.
    }
    let pivot_ratio = factor_in_place(block, stage, &mut jac, &mut scale, &mut swaps)?;
    if K == 2 {
        // The inverse of A S is S⁻¹ A⁻¹: fold the column scales into the rows.
        for i in 0..K {
            for j in 0..K {
                jac[(i, j)] *= scale[i];
            }
        }
    }
    Ok(Factored {
        lu: jac,
        scale,
        swaps,
        pivot_ratio,
    })
}

/// [`factor_block`]'s elimination for a Jacobian of any dimension (the generic engine's
/// `DMatrix`): `a` is factored in place by [`lu_in_place`], its column scales into `scale` and its
/// row swaps into `swaps` (one per column); the pivot ratio, or `Singular` for `stage`.
#[inline(always)]
pub fn factor_in_place<T: Real, D: Dim>(
    block: usize,
    stage: Stage,
    a: &mut OMatrix<T, D, D>,
    scale: &mut OVector<T, D>,
    swaps: &mut [usize],
) -> Result<T, SolveError>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    for (c, s) in swaps.iter_mut().enumerate() {
        *s = c;
    }
    lu_in_place(a, scale, |c, p| swaps[c] = p).map_err(|ratio| SolveError::Singular {
        block,
        stage,
        pivot_ratio: ratio.to_f64(),
    })
}

/// Solves with the factors of [`factor_in_place`] (a 2×2 one's scales not folded): `rhs`
/// becomes the solution, or `Overflow` when it is not finite.
#[inline(always)]
pub fn solve_factored<T: Real, D: Dim>(
    block: usize,
    stage: Stage,
    a: &OMatrix<T, D, D>,
    scale: &OVector<T, D>,
    swaps: &[usize],
    rhs: &mut OVector<T, D>,
) -> Result<(), SolveError>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    for (c, &p) in swaps.iter().enumerate() {
        rhs.swap_rows(c, p);
    }
    lu_solve(a, scale, rhs);
    finite(block, stage, rhs.as_slice())
}

/// `Overflow` for `stage` unless every value of a block's solution is finite.
#[inline(always)]
fn finite<T: Real>(block: usize, stage: Stage, z: &[T]) -> Result<(), SolveError> {
    if z.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(SolveError::Overflow { block, stage })
    }
}

impl<T: Real, const K: usize> Factored<T, K> {
    /// The solution for `rhs`, or `Overflow` when it is not finite.
    #[inline(always)]
    pub fn solve(
        &self,
        block: usize,
        stage: Stage,
        mut rhs: SVector<T, K>,
    ) -> Result<SVector<T, K>, SolveError> {
        if K == 1 {
            // A 1×1 block holds its reciprocal.
            rhs[0] *= self.lu[(0, 0)];
        } else if K == 2 {
            // A 2×2 block holds its inverse (no scales, no swaps).
            let (b0, b1) = (rhs[0], rhs[1]);
            rhs[0] = self.lu[(0, 0)] * b0 + self.lu[(0, 1)] * b1;
            rhs[1] = self.lu[(1, 0)] * b0 + self.lu[(1, 1)] * b1;
        } else {
            for c in 0..K {
                rhs.swap_rows(c, self.swaps[c]);
            }
            lu_solve(&self.lu, &self.scale, &mut rhs);
        }
        finite(block, stage, rhs.as_slice())?;
        Ok(rhs)
    }
}

impl<T: Real, const K: usize> Factored<T, K> {
    /// The solutions for the `C` columns of `rhs` at once (a block's sensitivities to every
    /// param), or `Overflow` when one is not finite.
    #[inline(always)]
    pub fn solve_columns<const C: usize>(
        &self,
        block: usize,
        stage: Stage,
        mut rhs: SMatrix<T, K, C>,
    ) -> Result<SMatrix<T, K, C>, SolveError> {
        if K <= 2 {
            // A 1×1 or 2×2 block holds its inverse.
            rhs = self.lu * rhs;
        } else {
            for c in 0..K {
                rhs.swap_rows(c, self.swaps[c]);
            }
            for c in 0..C {
                let mut col: SVector<T, K> = rhs.column(c).into_owned();
                lu_solve(&self.lu, &self.scale, &mut col);
                rhs.set_column(c, &col);
            }
        }
        finite(block, stage, rhs.as_slice())?;
        Ok(rhs)
    }
}

/// One linear block solve of a velocity or acceleration pass.
#[inline]
pub fn solve_block<T: Real, const K: usize>(
    block: usize,
    stage: Stage,
    jac: SMatrix<T, K, K>,
    rhs: SVector<T, K>,
) -> Result<SVector<T, K>, SolveError> {
    factor_block(block, stage, jac)?.solve(block, stage, rhs)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A well-conditioned K×K matrix with entries of mixed scales, and a right-hand side.
    fn system<const K: usize>(seed: u64, col_scale: f64) -> (SMatrix<f64, K, K>, SVector<f64, K>) {
        let mut s = seed;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut a = SMatrix::<f64, K, K>::zeros();
        for i in 0..K {
            for j in 0..K {
                a[(i, j)] = next() + if i == j { 2.0 } else { 0.0 };
            }
        }
        for j in 0..K {
            let s = col_scale.powi(j as i32);
            for i in 0..K {
                a[(i, j)] *= s;
            }
        }
        (a, SVector::from_fn(|_, _| next()))
    }

    fn check<const K: usize>(seed: u64, col_scale: f64) {
        let (a, b) = system::<K>(seed, col_scale);
        let lu = factor_block(0, Stage::Velocity, a).expect("regular");
        // Two right-hand sides from one factorization.
        for rhs in [b, b * 3.0 - SVector::repeat(1.0)] {
            let z = lu.solve(0, Stage::Velocity, rhs).expect("finite");
            let r = a * z - rhs;
            assert!(r.amax() < 1e-14, "K={K} seed={seed} residual {r}");
            let (g, _) = gauss(a, rhs).expect("regular");
            for i in 0..K {
                let tol = 1e-13 * g[i].abs().max(1e-300);
                assert!((z[i] - g[i]).abs() <= tol, "{z} vs {g}");
            }
        }
    }

    #[test]
    fn factored_solves_match_elimination() {
        for seed in 0..50 {
            check::<1>(seed, 1.0);
            check::<2>(seed, 1.0);
            check::<3>(seed, 1.0);
            check::<4>(seed, 1.0);
            // Columns of very different scales (lengths next to angles).
            check::<2>(seed, 1e3);
            check::<3>(seed, 1e-3);
        }
    }

    #[test]
    fn two_by_two_outside_the_normal_range_takes_the_equilibrated_path() {
        for scale in [1e-160, 1e160] {
            let a = SMatrix::<f64, 2, 2>::new(1.0, 2.0, 3.0, -1.0) * scale;
            let b = SVector::<f64, 2>::new(1.0, 1.0) * scale;
            let z = solve_block(0, Stage::Velocity, a, b).expect("regular");
            // [1 2; 3 -1] z = [1; 1]: z = (3/7, 2/7).
            assert!((z[0] - 3.0 / 7.0).abs() < 1e-15 && (z[1] - 2.0 / 7.0).abs() < 1e-15);
        }
    }

    #[test]
    fn singular_and_non_finite_blocks_are_errors() {
        let singular = SMatrix::<f64, 2, 2>::new(1.0, 2.0, 2.0, 4.0);
        let b = SVector::<f64, 2>::new(1.0, 1.0);
        assert!(matches!(
            solve_block(3, Stage::Acceleration, singular, b),
            Err(SolveError::Singular {
                block: 3,
                stage: Stage::Acceleration,
                ..
            })
        ));
        let nan = SMatrix::<f64, 2, 2>::new(f64::NAN, 2.0, 3.0, 4.0);
        assert!(solve_block(0, Stage::Velocity, nan, b).is_err());
        let nan3 = SMatrix::<f64, 3, 3>::new(1.0, 0.0, 0.0, 0.0, f64::NAN, 0.0, 0.0, 0.0, 1.0);
        assert!(solve_block(0, Stage::Velocity, nan3, SVector::repeat(1.0)).is_err());
        // A pivot ratio of |det| / (m₀ m₁) for 2×2: here 1e-20 / 1.
        let near = SMatrix::<f64, 2, 2>::new(1.0, 1.0, 1.0, 1.0 + 1e-20);
        match solve_block(0, Stage::Velocity, near, b) {
            Err(SolveError::Singular { pivot_ratio, .. }) => assert!(pivot_ratio < 1e-15),
            other => panic!("{other:?}"),
        }
        let ok = factor_block(
            0,
            Stage::Velocity,
            SMatrix::<f64, 2, 2>::new(1.0, 1.0, 0.0, 0.5),
        )
        .expect("regular");
        assert!((ok.pivot_ratio - 0.5).abs() < 1e-15);
    }

    #[test]
    fn one_by_one_is_a_division() {
        for (a, b) in [
            (3.0, 1.0),
            (-0.1, 7.0),
            (1e-300, 1e-300),
            (1e300, 1e300),
            (-1.0, 2.5),
        ] {
            let lu =
                factor_block(0, Stage::Velocity, SMatrix::<f64, 1, 1>::new(a)).expect("regular");
            assert_eq!(lu.pivot_ratio, 1.0);
            let z = lu
                .solve(0, Stage::Velocity, SVector::<f64, 1>::new(b))
                .expect("finite");
            assert!(
                (z[0] - b / a).abs() <= 2.0 * f64::EPSILON * (b / a).abs(),
                "{a} {b}"
            );
        }
        for a in [0.0, -0.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                factor_block(2, Stage::Acceleration, SMatrix::<f64, 1, 1>::new(a)),
                Err(SolveError::Singular {
                    block: 2,
                    stage: Stage::Acceleration,
                    ..
                })
            ));
        }
        let lu =
            factor_block(0, Stage::Velocity, SMatrix::<f64, 1, 1>::new(1e-300)).expect("regular");
        assert!(matches!(
            lu.solve(0, Stage::Velocity, SVector::<f64, 1>::new(1e300)),
            Err(SolveError::Overflow { .. })
        ));
    }
}
