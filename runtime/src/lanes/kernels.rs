//! The lane versions of the kernels a tick of dyads runs: the dyad's closed form
//! ([`crate::dyad::solve_dyad`]), a block's factorization and solves ([`crate::elimination`]'s
//! 1×1 and 2×2 paths) and the inputs' rotated sines and cosines ([`crate::trig::rotate`]). Each
//! repeats the scalar operations in the same order; where the scalar would branch off its
//! common path (or fail), the lane is cleared in the mask `ok` and its values are not used.

use super::Lanes;
use super::lu::LaneLu;
use crate::scalar::Real;
use crate::trig::{SERIES_TURN, atan_series};

/// The unknowns of W instances with their sines and cosines (`sc[k]` = (sin, cos) of `q[k]`
/// where `q[k]` is an angle), as [`crate::trig::TrigState`] holds them for one.
#[derive(Clone, Copy, Debug)]
pub struct LaneTrig<L, const N: usize> {
    pub q: [L; N],
    pub sc: [(L, L); N],
}

/// Solves the dyad block with unknowns `a` and `b` in every lane, as
/// [`crate::dyad::solve_dyad`] does in one (with `r` of `M_a`, `M_b` given as `None` where it is
/// the literal zero of generated code): `st` gets each lane's solution, `pivot` its smallest
/// pivot ratio so far; lanes past a dead point, with a large turn or a non-finite value get
/// their lane cleared in `ok`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn solve_dyad<L: Lanes, const N: usize>(
    st: &mut LaneTrig<L, N>,
    a: usize,
    b: usize,
    k: [L; 2],
    ma: (L, Option<L>),
    mb: (L, Option<L>),
    tolerance: L::Scalar,
    pivot: &mut L,
    ok: &mut L::Mask,
) {
    solve_dyad_angles(st, (a, b), k, (ma, mb), tolerance, pivot, ok, [true; 2]);
}

/// A link's squared length and length from its (along, across) lengths `(p, r)`; a lane where
/// `r` is zero at run time is cleared (the scalar takes its plain-scaling path there).
#[inline(always)]
fn link<L: Lanes>((p, r): (L, Option<L>), ok: &mut L::Mask) -> (L, L) {
    match r {
        None => (p * p, p.abs()),
        Some(r) => {
            *ok = *ok & !r.eq(L::zero());
            let l2 = p * p + r * r;
            (l2, l2.sqrt())
        }
    }
}

/// The unit direction `(cos, sin)` of a link whose (along, across) lengths `(p, r)` reach `(x, y)`.
#[inline(always)]
fn unapply<L: Lanes>((p, r): (L, Option<L>), (x, y): (L, L)) -> (L, L) {
    match r {
        None => {
            let inv = L::one() / p;
            (x * inv, y * inv)
        }
        Some(r) => {
            let inv = L::one() / (p * p + r * r);
            ((p * x + r * y) * inv, (p * y - r * x) * inv)
        }
    }
}

/// [`solve_dyad`] computing only the angles with `values[i]` (`a`, then `b`), as
/// [`crate::dyad::solve_dyad_angles`] does for a scene's tick: an angle nobody reads keeps its
/// value, only its sine and cosine are solved (generated code passes constants).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn solve_dyad_angles<L: Lanes, const N: usize>(
    st: &mut LaneTrig<L, N>,
    (a, b): (usize, usize),
    k: [L; 2],
    (ma, mb): ((L, Option<L>), (L, Option<L>)),
    tolerance: L::Scalar,
    pivot: &mut L,
    ok: &mut L::Mask,
    values: [bool; 2],
) {
    let (ga, gb) = (st.sc[a], st.sc[b]);
    let (ea, eb) = ((ga.1, ga.0), (gb.1, gb.0));
    // The scalar takes its plain-scaling path where r is zero at run time: leave such lanes to it.
    let ((la2, la), (lb2, lb)) = (link(ma, ok), link(mb, ok));
    let d = (-k[0], -k[1]);
    let l2 = d.0 * d.0 + d.1 * d.1;
    let guess_a = match ma.1 {
        None => (ma.0 * ea.0, ma.0 * ea.1),
        Some(r) => (ma.0 * ea.0 - r * ea.1, r * ea.0 + ma.0 * ea.1),
    };
    let zero = L::zero();
    *ok = *ok & (l2 + la2 + lb2).is_finite();
    *ok = *ok & (l2.gt(zero) & la2.gt(zero) & lb2.gt(zero));
    let (far, folded) = ((la + lb) * (la + lb) - l2, l2 - (la - lb) * (la - lb));
    let heron = far * folded;
    let rounding = L::splat(L::Scalar::EPSILON * L::Scalar::lit(256.0));
    *ok = *ok
        & !(far.lt(-rounding * (la + lb) * (la + lb)) | folded.lt(-rounding * (la2 - lb2).abs()));
    let inv_2l2 = L::lit(0.5) / l2;
    let along = (la2 + l2 - lb2) * inv_2l2;
    let across = L::select(heron.gt(zero), heron.sqrt() * inv_2l2, zero);
    let n = (-d.1, d.0);
    let s = L::select(
        (n.0 * guess_a.0 + n.1 * guess_a.1).lt(zero),
        -across,
        across,
    );
    let big_a = (along * d.0 + s * n.0, along * d.1 + s * n.1);
    let big_b = (d.0 - big_a.0, d.1 - big_a.1);
    let (ca, sa) = unapply(ma, big_a);
    let (cb, sb) = unapply(mb, big_b);
    // The turns from the guess by the series of `near_pair` (both small) or `near` (one
    // angle), else the scalar's; an angle not computed stays as it was.
    let (qa, qb) = match values {
        [true, true] => near_pair(
            st.q[a],
            st.q[b],
            (ea, eb),
            ((ca, sa), (cb, sb)),
            tolerance,
            ok,
        ),
        [true, false] => (near(st.q[a], ea, (ca, sa), tolerance, ok), st.q[b]),
        [false, true] => (st.q[a], near(st.q[b], eb, (cb, sb), tolerance, ok)),
        [false, false] => (st.q[a], st.q[b]),
    };
    *ok = *ok & (qa + qb + ca + sb).is_finite();
    st.q[a] = qa;
    st.q[b] = qb;
    st.sc[a] = (sa, ca);
    st.sc[b] = (sb, cb);
    let ratio = (big_a.0 * big_b.1 - big_a.1 * big_b.0).abs() / (la * lb);
    *pivot = L::select(ratio.lt(*pivot), ratio, *pivot);
}

/// Both angles of a dyad turned from their guesses (directions `ea`, `eb`) to `na`, `nb` by
/// the series of the scalar's `near_pair`; lanes where it would take another path are cleared.
#[inline(always)]
fn near_pair<L: Lanes>(
    qa: L,
    qb: L,
    (ea, eb): ((L, L), (L, L)),
    ((ca, sa), (cb, sb)): ((L, L), (L, L)),
    tolerance: L::Scalar,
    ok: &mut L::Mask,
) -> (L, L) {
    let (sin_a, sin_b) = (ea.0 * sa - ea.1 * ca, eb.0 * sb - eb.1 * cb);
    let (cos_a, cos_b) = (ea.0 * ca + ea.1 * sa, eb.0 * cb + eb.1 * sb);
    let (ta, tb) = (sin_a / (L::one() + cos_a), sin_b / (L::one() + cos_b));
    let (near, lim) = (L::lit(0.99), L::lit(0.06));
    let small = cos_a.gt(near) & cos_b.gt(near) & ta.abs().lt(lim) & tb.abs().lt(lim);
    let (acc_a, acc_b) = (atan_series(ta * ta, L::lit), atan_series(tb * tb, L::lit));
    let two = L::lit(2.0);
    let (qa, qb) = (qa + two * ta * acc_a, qb + two * tb * acc_b);
    let held = (L::splat(L::Scalar::EPSILON) * (qa.abs() + qb.abs())).le(L::splat(tolerance));
    *ok = *ok & (small & held);
    (qa, qb)
}

/// The angle `q` (direction `(cg, sg)`) turned to `(c, s)` by the scalar's series
/// (`dyad::near` through `dyad::turn`); lanes whose turn is too large for the series, or whose
/// angle cannot hold the answer to `tolerance`, are cleared in `ok`.
#[inline(always)]
pub(super) fn near<L: Lanes>(
    q: L,
    (cg, sg): (L, L),
    (c, s): (L, L),
    tolerance: L::Scalar,
    ok: &mut L::Mask,
) -> L {
    let sin = cg * s - sg * c;
    let cos = cg * c + sg * s;
    let t = sin / (L::one() + cos);
    *ok = *ok & cos.gt(L::lit(0.99)) & t.abs().lt(L::lit(0.06));
    let q_new = q + L::lit(2.0) * t * atan_series(t * t, L::lit);
    *ok = *ok & (L::splat(L::Scalar::EPSILON) * q_new.abs()).le(L::splat(tolerance));
    q_new
}

/// A block Jacobian of every lane factored for its velocity and acceleration solves (1×1: its
/// reciprocal; 2×2: its inverse; larger: its equilibrated LU factors with each lane's row
/// swaps), as [`crate::elimination::Factored`] holds one.
#[derive(Clone, Copy, Debug)]
pub struct LaneFactored<L: Lanes, const K: usize> {
    inv: [[L; K]; K],
    lu: Option<LaneLu<L, K>>,
}

/// [`crate::elimination::factor_block`] in every lane: lanes singular to working precision (or
/// with 2×2 entries outside its Cramer path's range) get their lane cleared in `ok`.
#[inline(always)]
pub fn factor_block<L: Lanes, const K: usize>(
    jac: [[L; K]; K],
    ok: &mut L::Mask,
) -> LaneFactored<L, K> {
    let mut inv = jac;
    let zero = L::zero();
    if K == 1 {
        let a = jac[0][0];
        *ok = *ok & a.abs().gt(zero) & a.is_finite();
        inv[0][0] = L::one() / a;
    } else if K == 2 {
        let (a00, a01, a10, a11) = (jac[0][0], jac[0][1], jac[1][0], jac[1][1]);
        let det = a00 * a11 - a01 * a10;
        let larger = |x: L, y: L| L::select(x.gt(y), x, y);
        let mm = larger(a00.abs(), a10.abs()) * larger(a01.abs(), a11.abs());
        let in_range = mm.ge(L::splat(L::Scalar::MIN_POSITIVE)) & mm.le(L::splat(L::Scalar::MAX));
        let eps2 = L::splat(L::Scalar::EPSILON * L::Scalar::lit(2.0));
        *ok = *ok & in_range & det.abs().gt(eps2 * mm);
        let d = L::one() / det;
        inv[0][0] = a11 * d;
        inv[0][1] = -a01 * d;
        inv[1][0] = -a10 * d;
        inv[1][1] = a00 * d;
    } else {
        return LaneFactored {
            inv,
            lu: Some(super::lu::lu(jac, ok)),
        };
    }
    LaneFactored { inv, lu: None }
}

impl<L: Lanes, const K: usize> LaneFactored<L, K> {
    /// The solution for `rhs` in every lane; lanes where it is not finite get their lane cleared in `ok`.
    #[inline(always)]
    pub fn solve(&self, rhs: [L; K], ok: &mut L::Mask) -> [L; K] {
        let mut z = rhs;
        if let Some(lu) = &self.lu {
            z = lu.solve(rhs);
        } else if K == 1 {
            z[0] = rhs[0] * self.inv[0][0];
        } else if K == 2 {
            z[0] = self.inv[0][0] * rhs[0] + self.inv[0][1] * rhs[1];
            z[1] = self.inv[1][0] * rhs[0] + self.inv[1][1] * rhs[1];
        }
        for v in z {
            *ok = *ok & v.is_finite();
        }
        z
    }
}

/// The inputs' sines and cosines at `x` as the scalar tick's `inputs_trig` makes them, for the
/// inputs with `angle[i]`: rotated from `tx` at `x0` by [`rotate`], or, in the lanes of `resync`
/// (whose caches are due), `sin_cos` of `x` itself, lane by lane.
#[inline(always)]
pub fn rotate_inputs<L: Lanes, const NI: usize>(
    tx: &[(L, L); NI],
    x0: &[L; NI],
    x: &[L; NI],
    angle: [bool; NI],
    resync: L::Mask,
) -> [(L, L); NI] {
    let mut out = *tx;
    for i in 0..NI {
        if angle[i] {
            out[i] = rotate(tx[i], x[i], x0[i] - x[i], resync);
        }
    }
    out
}

/// [`crate::trig::rotate`] in every lane: the sine and cosine `(s, c)` of an angle turned by
/// `−dz` to `q_new`, by the series; in the lanes of `fresh` and those where `|dz| > 0.1` (or
/// not finite), `sin_cos` of `q_new` itself, lane by lane (as the scalar's cold path).
#[inline(always)]
pub fn rotate<L: Lanes>((s, c): (L, L), q_new: L, dz: L, fresh: L::Mask) -> (L, L) {
    let (sd, cd) = crate::trig::turn_series(dz, L::lit);
    let out = (s * cd - c * sd, c * cd + s * sd);
    let cold = fresh | !dz.abs().le(L::lit(SERIES_TURN));
    if L::bits(cold) == 0 {
        return out;
    }
    // Rare (once in `RESYNC_TICKS` ticks, a jump, a long Newton step): the scalar's `sin_cos`.
    let (s, c) = cold_sin_cos(q_new);
    (L::select(cold, s, out.0), L::select(cold, c, out.1))
}

/// [`Lanes::sin_cos`] behind a call the optimizer does not speculate (as
/// [`crate::trig::sin_cos_cold`] for one).
#[cold]
#[inline(never)]
fn cold_sin_cos<L: Lanes>(x: L) -> (L, L) {
    x.sin_cos()
}
