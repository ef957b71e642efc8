//! The RPR, RRP, one-angle, one-length and two-length closed forms in lanes
//! (`closed_form::solve_rpr`, `solve_rrp`, `solve_angle1`, `solve_length1`, `solve_linear2`: the
//! shaper's slotted guide, an inclined slide, the slider-crank's rod angle and slide, a cross
//! slide), repeating the scalar operations in order; lanes that leave the scalar's common path
//! are cleared in `ok`. [`solve_kind`] runs the kernel of a `ClosedKind` from its roots in the
//! kind's order (what the JIT traces).

use super::kernels::near;
use super::{LaneTrig, Lanes};
use crate::closed_form::ClosedKind;
use crate::scalar::Real;

/// `closed_form::solve_angle1` in every lane: `K + P cos q + Q sin q = 0` for angle `q`, with
/// `w = (P, Q)` (`P` as `None` where generated code has the literal zero), on the guess's side;
/// with `value` false only the sine and cosine are solved (the angle keeps its value); `pivot`
/// gets each lane's `t / |w|` where it is smaller.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn solve_angle1<L: Lanes, const N: usize>(
    st: &mut LaneTrig<L, N>,
    q: usize,
    k: L,
    (p, qq): (Option<L>, L),
    tolerance: L::Scalar,
    pivot: &mut L,
    ok: &mut L::Mask,
    value: bool,
) {
    let zero = L::zero();
    *ok = *ok & st.q[q].is_finite() & k.is_finite() & qq.is_finite();
    let ww = match p {
        None => qq * qq,
        Some(p) => {
            // The scalar takes its `P = 0` path where P is zero at run time: leave such lanes.
            *ok = *ok & p.is_finite() & !p.eq(zero);
            p * p + qq * qq
        }
    };
    *ok = *ok & ww.gt(zero) & (ww + k * k).is_finite();
    let c = -k;
    let r = match p {
        None => qq.abs(),
        Some(_) => ww.sqrt(),
    };
    let near_dead = r - c.abs();
    let slack = L::splat(L::Scalar::EPSILON * L::Scalar::lit(128.0));
    *ok = *ok & !near_dead.lt(-slack * r);
    let t = L::select(near_dead.gt(zero), (near_dead * (r + c.abs())).sqrt(), zero);
    let (sg, cg) = st.sc[q];
    let along = p.unwrap_or(zero) * sg - qq * cg;
    let tau = L::select(along.lt(zero), -L::one(), L::one());
    let x = tau * t;
    let (e, ratio) = match p {
        None => {
            let inv = L::one() / qq;
            ((-x * inv, c * inv), t * inv.abs())
        }
        Some(p) => {
            let inv = L::one() / ww;
            (
                ((c * p - x * qq) * inv, (c * qq + x * p) * inv),
                t * r * inv,
            )
        }
    };
    *ok = *ok & e.0.is_finite() & e.1.is_finite();
    if value {
        st.q[q] = near(st.q[q], (cg, sg), e, tolerance, ok);
    }
    st.sc[q] = (e.1, e.0);
    *pivot = L::select(ratio.lt(*pivot), ratio, *pivot);
}

/// `closed_form::solve_length1` in every lane: `K + a s = 0` for the length `s`.
#[inline(always)]
pub fn solve_length1<L: Lanes, const N: usize>(
    st: &mut LaneTrig<L, N>,
    s: usize,
    k: L,
    a: L,
    ok: &mut L::Mask,
) {
    *ok = *ok & k.is_finite() & a.is_finite() & !a.eq(L::zero());
    let v = -k / a;
    *ok = *ok & v.is_finite();
    st.q[s] = v;
}

/// `closed_form::solve_rpr` in every lane: `K + (M + s N) e(q) = 0` for the angle `q` and the
/// length `s` (`m`, `n` the `(p, r)` of `M`, `N`), on the guess's side; `pivot` gets each lane's
/// condition estimate; with `value` false the angle keeps its value (its sine and cosine are
/// solved).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn solve_rpr<L: Lanes, const N: usize>(
    st: &mut LaneTrig<L, N>,
    (q, s): (usize, usize),
    k: [L; 2],
    m: (L, L),
    n: (L, L),
    tolerance: L::Scalar,
    pivot: &mut L,
    ok: &mut L::Mask,
    value: bool,
) {
    let zero = L::zero();
    for v in [st.q[q], k[0], k[1], m.0, m.1, n.0, n.1] {
        *ok = *ok & v.is_finite();
    }
    let nn = n.0 * n.0 + n.1 * n.1;
    *ok = *ok & nn.gt(zero);
    let inv = L::one() / nn;
    let d = (-k[0], -k[1]);
    let over_n = |(x, y): (L, L)| ((x * n.0 + y * n.1) * inv, (y * n.0 - x * n.1) * inv);
    let (g, (a, b)) = (over_n(d), over_n(m));
    let g2 = g.0 * g.0 + g.1 * g.1;
    *ok = *ok & (g2 + a * a + b * b).is_finite();
    let r = g2.sqrt();
    let bb = b.abs();
    let near_dead = r - bb;
    let slack = L::splat(L::Scalar::EPSILON * L::Scalar::lit(128.0));
    *ok = *ok & !near_dead.lt(-slack * bb) & g2.gt(zero);
    let t = L::select(near_dead.gt(zero), (near_dead * (r + bb)).sqrt(), zero);
    let (sg, cg) = st.sc[q];
    let tau = L::select((g.0 * cg + g.1 * sg).lt(zero), -L::one(), L::one());
    let x = tau * t;
    let inv_g2 = L::one() / g2;
    let e = ((g.0 * x + g.1 * b) * inv_g2, (g.1 * x - g.0 * b) * inv_g2);
    let len = x - a;
    *ok = *ok & e.0.is_finite() & e.1.is_finite() & len.is_finite();
    if value {
        st.q[q] = near(st.q[q], (cg, sg), e, tolerance, ok);
    }
    st.sc[q] = (e.1, e.0);
    st.q[s] = len;
    let ratio = t / r;
    *pivot = L::select(ratio.lt(*pivot), ratio, *pivot);
}

/// `closed_form::solve_rrp` in every lane: `K + M e(q) + s u = 0` for the angle `q` and the
/// length `s` along the fixed direction `u` (`(p, r)` of `M`, `r` as `None` where generated code
/// has the literal zero), on the guess's side (the sign of `u · M e(q)`); `pivot` gets each lane's
/// half chord over `|M|`; with `value` false the angle keeps its value.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn solve_rrp<L: Lanes, const N: usize>(
    st: &mut LaneTrig<L, N>,
    (q, s): (usize, usize),
    k: [L; 2],
    (p, r): (L, Option<L>),
    u: [L; 2],
    tolerance: L::Scalar,
    pivot: &mut L,
    ok: &mut L::Mask,
    value: bool,
) {
    let (zero, one) = (L::zero(), L::one());
    let rr = r.unwrap_or(zero);
    for v in [st.q[q], k[0], k[1], p, rr, u[0], u[1]] {
        *ok = *ok & v.is_finite();
    }
    // The scalar takes its `r = 0` path (|p| and 1/p) where r is zero at run time: leave such lanes.
    if r.is_some() {
        *ok = *ok & !rr.eq(zero);
    }
    let d = (-k[0], -k[1]);
    let uu = u[0] * u[0] + u[1] * u[1];
    let l2 = p * p + rr * rr;
    *ok = *ok & uu.gt(zero) & l2.gt(zero) & (uu + l2 + d.0 * d.0 + d.1 * d.1).is_finite();
    let l = match r {
        None => p.abs(),
        Some(_) => l2.sqrt(),
    };
    let inv_ul = one / uu.sqrt();
    let unit = (u[0] * inv_ul, u[1] * inv_ul);
    let h = unit.0 * d.1 - unit.1 * d.0;
    let dist = h.abs();
    let near_dead = l - dist;
    let slack = L::splat(L::Scalar::EPSILON * L::Scalar::lit(128.0));
    *ok = *ok & !near_dead.lt(-slack * l);
    let half = L::select(near_dead.gt(zero), (near_dead * (l + dist)).sqrt(), zero);
    let foot = (-unit.1 * h, unit.0 * h);
    let s0 = (d.0 * unit.0 + d.1 * unit.1) * inv_ul;
    let (sg, cg) = st.sc[q];
    let a = (p * cg - rr * sg, rr * cg + p * sg);
    let tau = L::select((a.0 * u[0] + a.1 * u[1]).lt(zero), -one, one);
    let w = tau * half;
    let (x, y) = (foot.0 + w * unit.0, foot.1 + w * unit.1);
    let e = match r {
        None => {
            let inv = one / p;
            (x * inv, y * inv)
        }
        Some(r) => {
            let inv = one / (p * p + r * r);
            ((p * x + r * y) * inv, (p * y - r * x) * inv)
        }
    };
    let len = s0 - w * inv_ul;
    *ok = *ok & e.0.is_finite() & e.1.is_finite() & len.is_finite();
    if value {
        st.q[q] = near(st.q[q], (cg, sg), e, tolerance, ok);
    }
    st.sc[q] = (e.1, e.0);
    st.q[s] = len;
    let ratio = half / l;
    *pivot = L::select(ratio.lt(*pivot), ratio, *pivot);
}

/// `closed_form::solve_linear2` in every lane: `K + s1 u1 + s2 u2 = 0` for the lengths `s1`,
/// `s2` (Cramer on the column-equilibrated 2×2); `pivot` gets each lane's `|det|` (or its
/// inverse above 1); lanes whose directions are parallel to working precision leave.
#[inline(always)]
pub fn solve_linear2<L: Lanes, const N: usize>(
    st: &mut LaneTrig<L, N>,
    (s1, s2): (usize, usize),
    k: [L; 2],
    u1: [L; 2],
    u2: [L; 2],
    pivot: &mut L,
    ok: &mut L::Mask,
) {
    let (zero, one) = (L::zero(), L::one());
    for v in [k[0], k[1], u1[0], u1[1], u2[0], u2[1]] {
        *ok = *ok & v.is_finite();
    }
    // `f64::max` of two finite non-negative values.
    let max = |x: L, y: L| L::select(x.lt(y), y, x);
    let (m1, m2) = (max(u1[0].abs(), u1[1].abs()), max(u2[0].abs(), u2[1].abs()));
    *ok = *ok & m1.gt(zero) & m2.gt(zero);
    let (i1, i2) = (one / m1, one / m2);
    let (a, b) = ((u1[0] * i1, u1[1] * i1), (u2[0] * i2, u2[1] * i2));
    let det = a.0 * b.1 - a.1 * b.0;
    let r = det.abs();
    *ok = *ok & r.gt(L::splat(L::Scalar::EPSILON * L::Scalar::lit(2.0)));
    let d = (-k[0], -k[1]);
    let inv = one / det;
    let v1 = (d.0 * b.1 - d.1 * b.0) * inv * i1;
    let v2 = (a.0 * d.1 - a.1 * d.0) * inv * i2;
    *ok = *ok & v1.is_finite() & v2.is_finite();
    st.q[s1] = v1;
    st.q[s2] = v2;
    let ratio = L::select(r.le(one), r, one / r);
    *pivot = L::select(ratio.lt(*pivot), ratio, *pivot);
}

/// A closed-form block of `kind` in every lane, as [`crate::closed_form::ClosedKind::solve`]
/// solves one: its unknowns at `st`'s slots `[a, b]` (the second unused by a kind of one
/// unknown), its roots `v` in the kind's order, `zero[i]` where root `i` is the literal zero
/// (given to the kernel as `None` where it takes one), every angle computed. Too few roots: every
/// lane cleared.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn solve_kind<L: Lanes, const N: usize>(
    kind: ClosedKind,
    st: &mut LaneTrig<L, N>,
    [a, b]: [usize; 2],
    v: &[L],
    zero: &[bool],
    tolerance: L::Scalar,
    pivot: &mut L,
    ok: &mut L::Mask,
) {
    if v.len() < kind.roots() || a >= N || b >= N {
        *ok = *ok & L::zero().lt(L::zero());
        return;
    }
    let opt = |i: usize| (!zero.get(i).copied().unwrap_or(false)).then_some(v[i]);
    let k = [v[0], v[1]];
    match kind {
        ClosedKind::Rrr => super::kernels::solve_dyad(
            st,
            a,
            b,
            k,
            (v[2], opt(3)),
            (v[4], opt(5)),
            tolerance,
            pivot,
            ok,
        ),
        ClosedKind::Rpr => {
            let (m, n) = ((v[2], v[3]), (v[4], v[5]));
            solve_rpr(st, (a, b), k, m, n, tolerance, pivot, ok, true);
        }
        ClosedKind::Rrp => {
            let (p, u) = ((v[2], opt(3)), [v[4], v[5]]);
            solve_rrp(st, (a, b), k, p, u, tolerance, pivot, ok, true);
        }
        ClosedKind::Linear2 => {
            let (u1, u2) = ([v[2], v[3]], [v[4], v[5]]);
            solve_linear2(st, (a, b), k, u1, u2, pivot, ok);
        }
        ClosedKind::Angle1 => {
            solve_angle1(st, a, v[0], (opt(1), v[2]), tolerance, pivot, ok, true);
        }
        ClosedKind::Length1 => solve_length1(st, a, v[0], v[1], ok),
    }
}
