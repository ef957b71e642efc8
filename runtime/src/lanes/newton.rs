//! Newton blocks in lanes: the block's elimination ([`crate::elimination::lu_in_place`] and
//! [`crate::elimination::lu_solve`]: column equilibration, partial pivoting with each lane's own
//! row swaps) and the Newton iteration of [`crate::solve::newton_in_place`], every lane
//! iterating until it has converged and then frozen. Each repeats the scalar operations in
//! order; a lane that would leave the scalar's common path (an error, a step shortened or
//! stalled, a huge angle) is cleared in the mask `ok` and left to the scalar tick.

// Index loops over rows and columns of several arrays read better than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use super::Lanes;
use super::kernels::{LaneTrig, rotate};
use super::lu::lu;
use crate::scalar::Real;
use crate::solve::NewtonOptions;

/// The position solves' report in every lane, as [`crate::NewtonReport`] for one: Newton
/// iterations (a count in the lanes' scalar), the largest relative residual, the smallest pivot
/// ratio.
#[derive(Clone, Copy, Debug)]
pub struct LaneReport<L> {
    pub iterations: L,
    pub residual: L,
    pub pivot_ratio: L,
}

impl<L: Lanes> LaneReport<L> {
    /// No iterations, no residual, pivot ratio 1 (as `NewtonReport::new`).
    pub fn new() -> Self {
        LaneReport {
            iterations: L::zero(),
            residual: L::zero(),
            pivot_ratio: L::one(),
        }
    }
}

impl<L: Lanes> Default for LaneReport<L> {
    fn default() -> Self {
        Self::new()
    }
}

/// `newton_block` for the block with unknowns `idx` (`length[i]`: a length, relative to the
/// length scale `scale`; `angle[i]`: an angle, its sine and cosine stepped with it) in every lane
/// of `ok`, `eval` giving the block's residual and Jacobian at `st`. A lane that converges is
/// frozen and its iterations, residual and pivot ratio go to `report`; a lane that leaves the
/// scalar's common path (non-finite or singular, a step shortened or stalled, no convergence, an
/// angle too large to step by its change) is cleared in `ok`. The scalar: `crate::solve`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn newton_block<L: Lanes, const K: usize, const N: usize>(
    st: &mut LaneTrig<L, N>,
    idx: [usize; K],
    length: [bool; K],
    angle: [bool; K],
    scale: L,
    options: &NewtonOptions<L::Scalar>,
    report: &mut LaneReport<L>,
    ok: &mut L::Mask,
    eval: impl Fn(&LaneTrig<L, N>) -> ([L; K], [[L; K]; K]),
) {
    let zero = L::zero();
    let none = !L::mask(L::all_bits());
    let inv_scale = L::one() / scale;
    let (max_step, tolerance) = (L::lit(1.0), L::splat(options.tolerance));
    let mut prev_step = L::lit(f64::INFINITY);
    let mut best_step = prev_step;
    let mut active = *ok;
    for it in 1..=options.max_iterations {
        if L::bits(active) == 0 {
            break;
        }
        let (r, jac) = eval(st);
        let mut residual = zero;
        let mut good = active;
        for v in r {
            good = good & v.is_finite();
            let a = v.abs() * inv_scale;
            residual = L::select(a.gt(residual), a, residual);
        }
        good = good & residual.is_finite();
        let lu = lu(jac, &mut good);
        let dz = lu.solve(r);
        let mut step = zero;
        for i in 0..K {
            let a = if length[i] {
                dz[i].abs() * inv_scale
            } else {
                dz[i].abs()
            };
            step = L::select(a.gt(step), a, step);
        }
        // The scalar shortens a longer step: leave such lanes to it.
        good = good & step.le(max_step);
        for i in 0..K {
            let k = idx[i];
            let old = st.q[k];
            let q = old - dz[i];
            good = good & dz[i].is_finite() & q.is_finite();
            st.q[k] = L::select(good, q, old);
            if angle[i] {
                // Where ε|q| > 1e-3 the scalar turns by the change q took: leave those lanes.
                good = good & (L::splat(L::Scalar::EPSILON) * old.abs()).le(L::lit(1e-3));
                let sc = rotate(st.sc[k], q, dz[i], none);
                st.sc[k] = (
                    L::select(good, sc.0, st.sc[k].0),
                    L::select(good, sc.1, st.sc[k].1),
                );
            }
        }
        *ok = *ok & !(active & !good);
        active = good;
        let theta = step / prev_step;
        let quadratic = it > 1;
        let done = step.le(L::lit(1e-3))
            & theta.le(L::lit(0.5))
            & (step * theta * theta).le(L::splat(L::Scalar::EPSILON));
        let converged = active & (step.le(tolerance) | if quadratic { done } else { none });
        if L::bits(converged) != 0 {
            let n = L::lit(f64::from(it));
            report.iterations = L::select(converged, report.iterations + n, report.iterations);
            let rr = report.residual;
            report.residual = L::select(converged & residual.gt(rr), residual, rr);
            let pr = report.pivot_ratio;
            report.pivot_ratio = L::select(converged & lu.ratio.lt(pr), lu.ratio, pr);
        }
        active = active & !converged;
        prev_step = step;
        // Steps that stop shrinking take the scalar's stall path: leave such lanes to it.
        let progress = step.lt(best_step * L::lit(0.9));
        *ok = *ok & !(active & !progress);
        active = active & progress;
        best_step = L::select(progress, step, best_step);
    }
    // Lanes out of iterations: the scalar's error.
    *ok = *ok & !active;
}
