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

/// A K×K matrix factored in every lane as `lu_in_place` leaves it: the factors (a 2×2 one's
/// equilibrated inverse), the column scales and each column's row swap (`swaps[c][r]`: the lanes
/// that swapped rows `c` and `r > c`).
#[derive(Clone, Copy, Debug)]
pub struct LaneLu<L: Lanes, const K: usize> {
    a: [[L; K]; K],
    scale: [L; K],
    swaps: [[L::Mask; K]; K],
    /// The pivot ratio (smallest over largest pivot).
    pub ratio: L,
}

/// `lu_in_place` in every lane; lanes singular to working precision are cleared in `ok`.
#[inline(always)]
pub fn lu<L: Lanes, const K: usize>(mut a: [[L; K]; K], ok: &mut L::Mask) -> LaneLu<L, K> {
    let zero = L::zero();
    let none = !L::mask(L::all_bits());
    let mut scale = [L::one(); K];
    for j in 0..K {
        let mut m = zero;
        for i in 0..K {
            let v = a[i][j].abs();
            m = L::select(v.gt(m), v, m);
        }
        *ok = *ok & m.gt(zero) & m.is_finite();
        let inv = L::one() / m;
        scale[j] = inv;
        for i in 0..K {
            a[i][j] = a[i][j] * inv;
        }
    }
    let tiny = L::splat(L::Scalar::EPSILON * L::Scalar::lit(K as f64));
    let mut swaps = [[none; K]; K];
    if K == 2 {
        let (a00, a01, a10, a11) = (a[0][0], a[0][1], a[1][0], a[1][1]);
        let det = a00 * a11 - a01 * a10;
        let (x, y) = (a00.abs(), a10.abs());
        let p1 = L::select(y.gt(x), y, x);
        let p2 = det.abs() / p1;
        let (pmin, pmax) = (L::select(p2.lt(p1), p2, p1), L::select(p2.gt(p1), p2, p1));
        *ok = *ok & pmin.gt(pmax * tiny);
        let inv = L::one() / det;
        a[0][0] = a11 * inv;
        a[0][1] = -a01 * inv;
        a[1][0] = -a10 * inv;
        a[1][1] = a00 * inv;
        return LaneLu {
            a,
            scale,
            swaps,
            ratio: pmin / pmax,
        };
    }
    let (mut pmin, mut pmax) = (L::lit(f64::INFINITY), zero);
    for c in 0..K {
        // The first row of the largest entry, per lane (`>`: the scalar's first maximum).
        let mut best = a[c][c].abs();
        let mut pick = [none; K];
        for r in c + 1..K {
            let v = a[r][c].abs();
            let better = v.gt(best);
            best = L::select(better, v, best);
            for p in pick.iter_mut().take(r).skip(c + 1) {
                *p = *p & !better;
            }
            pick[r] = better;
        }
        let old = a[c];
        for r in c + 1..K {
            for j in 0..K {
                let (rc, rr) = (a[c][j], a[r][j]);
                a[c][j] = L::select(pick[r], rr, rc);
                a[r][j] = L::select(pick[r], old[j], rr);
            }
        }
        swaps[c] = pick;
        let piv = a[c][c];
        let ap = piv.abs();
        pmin = L::select(ap.lt(pmin), ap, pmin);
        pmax = L::select(ap.gt(pmax), ap, pmax);
        *ok = *ok & pmin.gt(pmax * tiny);
        let inv_piv = L::one() / piv;
        a[c][c] = inv_piv;
        for r in c + 1..K {
            let f = a[r][c] * inv_piv;
            a[r][c] = f;
            let nonzero = !f.eq(zero);
            for j in c + 1..K {
                a[r][j] = L::select(nonzero, a[r][j] - f * a[c][j], a[r][j]);
            }
        }
    }
    LaneLu {
        a,
        scale,
        swaps,
        ratio: pmin / pmax,
    }
}

impl<L: Lanes, const K: usize> LaneLu<L, K> {
    /// The solution for `b` in every lane: its rows swapped as the factorization swapped them,
    /// then `lu_solve`.
    #[inline(always)]
    pub fn solve(&self, mut b: [L; K]) -> [L; K] {
        let (a, zero) = (&self.a, L::zero());
        if K == 2 {
            let (b0, b1) = (b[0], b[1]);
            b[0] = a[0][0] * b0 + a[0][1] * b1;
            b[1] = a[1][0] * b0 + a[1][1] * b1;
        } else {
            for c in 0..K {
                let old = b[c];
                for r in c + 1..K {
                    let rr = b[r];
                    b[c] = L::select(self.swaps[c][r], rr, b[c]);
                    b[r] = L::select(self.swaps[c][r], old, rr);
                }
            }
            for c in 0..K {
                let v = b[c];
                let nonzero = !v.eq(zero);
                for r in c + 1..K {
                    b[r] = L::select(nonzero, b[r] - a[r][c] * v, b[r]);
                }
            }
            for c in (0..K).rev() {
                let mut s = b[c];
                for j in c + 1..K {
                    s = s - a[c][j] * b[j];
                }
                b[c] = s * a[c][c];
            }
        }
        for j in 0..K {
            b[j] = b[j] * self.scale[j];
        }
        b
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
