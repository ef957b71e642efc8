//! Design derivatives: how the solved unknowns and points move with the params. Differentiating
//! Φ(x, q(p), p) = 0 gives J dq/dp = −Φp; block-triangular like the rates, each block's
//! right-hand side holds the earlier blocks' sensitivities: J_bb s_b = −(Φp_b + J_b,earlier
//! s_earlier), one more right-hand side per param through the factorization the rates use. The
//! points follow as dP/dp = ∂P/∂p + ∂P/∂q dq/dp. Generated code and the generic engine both run
//! these two functions, on their own matrices.

use crate::elimination::Factored;
use crate::error::{SolveError, Stage};
use crate::scalar::Real;
use nalgebra::SVector;

/// The design derivatives at a solved state: dq/dp (`unknowns`, a row per unknown) and dP/dp
/// (`points`, rows `P_x`, `P_y` per point), one column per param of the mechanism's `Params`
/// (derived params differentiated through). Generated code gives `SMatrix`es.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sensitivities<Q, P> {
    pub unknowns: Q,
    pub points: P,
}

/// A block Jacobian factored for linear solves, whatever its storage.
pub trait BlockSolve<T> {
    /// `rhs` (the block's size) becomes the solution; `Overflow` when it is not finite.
    fn solve_slice(&self, block: usize, stage: Stage, rhs: &mut [T]) -> Result<(), SolveError>;
}

impl<T: Real, const K: usize> BlockSolve<T> for Factored<T, K> {
    fn solve_slice(&self, block: usize, stage: Stage, rhs: &mut [T]) -> Result<(), SolveError> {
        crate::error::len(rhs, K)?;
        let z = self.solve(block, stage, SVector::from_fn(|i, _| rhs[i]))?;
        rhs.copy_from_slice(z.as_slice());
        Ok(())
    }
}

/// Block `block`'s rows of `s` = dq/dp (row-major, one row per unknown, `nparams` columns): for
/// each param p, the block's unknowns solve J_bb s_b,p = `−(Φp[e][p] + Σ_k J[e][k] s[k][p])` over its
/// equations `e`, k over the unknowns outside the block (rows of later blocks are still zero, and
/// block-triangular J has no entry there anyway). `jac(e, k)` and `phi_p(e, p)` read the whole
/// system's matrices; `rhs` is scratch of the block's size.
#[allow(clippy::too_many_arguments)]
pub fn block_sensitivities<T: Real>(
    block: usize,
    equations: &[usize],
    unknowns: &[usize],
    lu: &impl BlockSolve<T>,
    jac: impl Fn(usize, usize) -> T,
    phi_p: impl Fn(usize, usize) -> T,
    nparams: usize,
    s: &mut [T],
    rhs: &mut [T],
) -> Result<(), SolveError> {
    let nu = s.len().checked_div(nparams).unwrap_or(0);
    for p in 0..nparams {
        for (r, &e) in rhs.iter_mut().zip(equations) {
            let mut sum = phi_p(e, p);
            for k in (0..nu).filter(|k| !unknowns.contains(k)) {
                sum += jac(e, k) * s[k * nparams + p];
            }
            *r = -sum;
        }
        lu.solve_slice(block, Stage::Sensitivity, rhs)?;
        for (&u, &v) in unknowns.iter().zip(rhs.iter()) {
            s[u * nparams + p] = v;
        }
    }
    Ok(())
}

/// `out` = dP/dp (row-major: a row per point coordinate, `nparams` columns) from ∂P/∂q
/// (`pq(row, k)`), ∂P/∂p (`pp(row, p)`) and `s` = dq/dp (row-major, `nu` rows).
pub fn point_sensitivities<T: Real>(
    pq: impl Fn(usize, usize) -> T,
    pp: impl Fn(usize, usize) -> T,
    s: &[T],
    nu: usize,
    nparams: usize,
    out: &mut [T],
) {
    if nparams == 0 {
        return;
    }
    for (row, o) in out.chunks_exact_mut(nparams).enumerate() {
        for (p, v) in o.iter_mut().enumerate() {
            let mut sum = pp(row, p);
            for k in 0..nu {
                sum += pq(row, k) * s[k * nparams + p];
            }
            *v = sum;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elimination::factor_block;
    use nalgebra::SMatrix;

    /// Two blocks of one unknown each, q0 from Φ0 = q0 − p0² and q1 from Φ1 = q1 − q0 p1: dq0/dp
    /// = (2 p0, 0), dq1/dp = (2 p0 p1, q0) at q0 = p0²; the point P = (q1, p0) adds ∂P/∂p.
    #[test]
    fn later_blocks_carry_the_earlier_sensitivities() {
        let (p0, p1) = (1.5, -0.5);
        let q0 = p0 * p0;
        // J = [[1, 0], [−p1, 1]], Φp = [[−2 p0, 0], [0, −q0]].
        let jac = SMatrix::<f64, 2, 2>::new(1.0, 0.0, -p1, 1.0);
        let phi_p = SMatrix::<f64, 2, 2>::new(-2.0 * p0, 0.0, 0.0, -q0);
        let mut s = [0.0; 4];
        for b in 0..2 {
            let lu = factor_block(
                b,
                Stage::Sensitivity,
                SMatrix::<f64, 1, 1>::new(jac[(b, b)]),
            )
            .unwrap();
            let (j, f) = (|e, k| jac[(e, k)], |e, p| phi_p[(e, p)]);
            block_sensitivities(b, &[b], &[b], &lu, j, f, 2, &mut s, &mut [0.0]).unwrap();
        }
        assert_eq!(s, [2.0 * p0, 0.0, 2.0 * p0 * p1, q0]);
        let mut out = [0.0; 4];
        let pq = |row: usize, k: usize| if row == 0 && k == 1 { 1.0 } else { 0.0 };
        let pp = |row: usize, p: usize| if row == 1 && p == 0 { 1.0 } else { 0.0 };
        point_sensitivities(pq, pp, &s, 2, 2, &mut out);
        assert_eq!(out, [2.0 * p0 * p1, q0, 1.0, 0.0]);
    }

    #[test]
    fn a_singular_block_is_an_error_of_the_sensitivity_stage() {
        let jac = SMatrix::<f64, 1, 1>::new(0.0);
        let e = factor_block(3, Stage::Sensitivity, jac).unwrap_err();
        assert_eq!(
            e,
            SolveError::Singular {
                block: 3,
                stage: Stage::Sensitivity,
                pivot_ratio: 0.0
            }
        );
    }
}
