//! The LU factorization in lanes ([`lu`], [`LaneLu`]): `crate::elimination::lu_in_place` and
//! `lu_solve` in every lane (column equilibration, partial pivoting with each lane's own row
//! swaps), shared by the lane kernels' rate solves and Newton blocks in lanes.

// Index loops over rows and columns of several arrays read better than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use super::Lanes;
use crate::scalar::Real;

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
