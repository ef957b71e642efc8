//! Double-word arithmetic: a value as the unevaluated sum `hi + lo` of two f64 (about 106 bits),
//! for a block's residual evaluated to well below one rounding of its terms. Near a dead point the
//! Jacobian's smallest singular value σ is small and a residual known only to rounding (ε times
//! the size of the loop's terms) leaves the positions off by ε/σ along the singular direction,
//! which the rates then amplify; one Newton step with this residual ([`refine_block`]) removes
//! that error. Error-free transformations (Knuth's two-sum, Dekker's product with Veltkamp's
//! split) and Taylor series for sine and cosine after reducing by π/2 held to three words.

use crate::scalar::Real;
use crate::trig::TrigState;
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OMatrix, OVector, SMatrix, SVector};

use crate::elimination::gauss_in_place;

/// `hi + lo` with `|lo| ≤ ulp(hi) / 2`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Twofold {
    pub hi: f64,
    pub lo: f64,
}

/// `a + b = s + e` exactly.
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a + b = s + e` exactly, given `|a| ≥ |b|`.
#[inline]
fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// Veltkamp's split of `a` into two halves of 26 bits each.
#[inline]
fn split(a: f64) -> (f64, f64) {
    let t = 134_217_729.0 * a; // 2^27 + 1
    let hi = t - (t - a);
    (hi, a - hi)
}

/// `a · b = p + e` exactly (Dekker), for products far from overflow.
#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let ((ah, al), (bh, bl)) = (split(a), split(b));
    (p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
}

/// π/2 in three words.
const HALF_PI: [f64; 3] = [
    core::f64::consts::FRAC_PI_2,
    6.123_233_995_736_766e-17,
    -1.497_384_904_859_169_8e-33,
];

impl Twofold {
    /// `x` exactly.
    #[inline]
    pub fn from(x: f64) -> Twofold {
        Twofold { hi: x, lo: 0.0 }
    }

    /// The nearest f64.
    #[inline]
    pub fn value(self) -> f64 {
        self.hi + self.lo
    }

    /// The square root by one Newton correction of the f64 root (0 for 0, NaN below).
    pub fn sqrt(self) -> Twofold {
        if self.hi <= 0.0 {
            return Twofold::from(self.hi.sqrt());
        }
        let s = self.hi.sqrt();
        let r = self - Twofold::from(s) * Twofold::from(s);
        let (hi, lo) = quick_two_sum(s, r.hi / (2.0 * s));
        Twofold { hi, lo }
    }

    /// (sin, cos): reduced by a multiple of π/2 to |r| ≤ π/4, then Taylor series to r²⁹ (the
    /// remainder is below 1e-32 there).
    pub fn sin_cos(self) -> (Twofold, Twofold) {
        if !self.hi.is_finite() {
            let nan = Twofold::from(f64::NAN);
            return (nan, nan);
        }
        let k = num_traits::Float::round(self.hi / HALF_PI[0]);
        let mut r = self;
        for part in HALF_PI {
            let (p, e) = two_prod(k, part);
            r = r - Twofold { hi: p, lo: e };
        }
        let r2 = r * r;
        // sin r = Σ (−1)ⁿ r^(2n+1)/(2n+1)!, cos r = Σ (−1)ⁿ r^(2n)/(2n)!.
        let (mut s, mut c) = (r, Twofold::from(1.0));
        let (mut ts, mut tc) = (r, Twofold::from(1.0));
        // Each term from the one before by a product with the step's reciprocal (no division).
        for (sk, ck) in SIN_STEP.iter().zip(&COS_STEP) {
            ts = -(ts
                * r2
                * Twofold {
                    hi: sk[0],
                    lo: sk[1],
                });
            tc = -(tc
                * r2
                * Twofold {
                    hi: ck[0],
                    lo: ck[1],
                });
            s = s + ts;
            c = c + tc;
        }
        match (k as i64).rem_euclid(4) {
            0 => (s, c),
            1 => (c, -s),
            2 => (-s, -c),
            _ => (-c, s),
        }
    }
}

/// 1/(m(m+1)) for m = 2, 4, …, 30 as double-word numbers (hi, lo), from 60-digit arithmetic: the
/// ratio of one sine term to the next is −r²/(m(m+1)).
const SIN_STEP: [[f64; 2]; 15] = [
    [0.16666666666666666, 9.25185853854297e-18],
    [0.05, -2.7755575615628915e-18],
    [0.023809523809523808, 1.32169407693471e-18],
    [0.013888888888888888, 7.709882115452476e-19],
    [0.00909090909090909, 4.415659757031872e-19],
    [0.00641025641025641, 2.2240044563805217e-19],
    [0.004761904761904762, -4.295505750037808e-19],
    [0.003676470588235294, 5.102127870520021e-20],
    [0.0029239766081871343, 1.6231330769373633e-19],
    [0.002380952380952381, -2.147752875018904e-19],
    [0.001976284584980237, 1.3370398332627564e-19],
    [0.0016666666666666668, -1.0697461435190311e-19],
    [0.0014245014245014246, -7.104458680104445e-20],
    [0.0012315270935960591, -1.3886333243656708e-20],
    [0.001075268817204301, 9.326470300950576e-22],
];

/// 1/((m−1)m) for m = 2, 4, …, 30, likewise: the ratio of one cosine term to the next is
/// −r²/((m−1)m).
const COS_STEP: [[f64; 2]; 15] = [
    [0.5, 0.0],
    [0.08333333333333333, 4.625929269271485e-18],
    [0.03333333333333333, 4.625929269271486e-19],
    [0.017857142857142856, 9.912705577010326e-19],
    [0.011111111111111112, -4.2404351634988616e-19],
    [0.007575757575757576, -2.1026951223961299e-19],
    [0.005494505494505495, -4.2891514515910067e-19],
    [0.004166666666666667, 5.782411586589357e-20],
    [0.0032679738562091504, -9.920804192677818e-20],
    [0.002631578947368421, 5.934580312552235e-20],
    [0.0021645021645021645, 1.8774063592822588e-21],
    [0.0018115942028985507, -2.199830494898125e-20],
    [0.0015384615384615385, 1.3344026738283131e-21],
    [0.0013227513227513227, 7.3427448718595e-20],
    [0.0011494252873563218, 1.595148023886719e-20],
];

impl core::ops::Add for Twofold {
    type Output = Twofold;
    fn add(self, o: Twofold) -> Twofold {
        let (s, e) = two_sum(self.hi, o.hi);
        let (t, f) = two_sum(self.lo, o.lo);
        let (s, e) = quick_two_sum(s, e + t);
        let (hi, lo) = quick_two_sum(s, e + f);
        Twofold { hi, lo }
    }
}

impl core::ops::Neg for Twofold {
    type Output = Twofold;
    fn neg(self) -> Twofold {
        Twofold {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl core::ops::Sub for Twofold {
    type Output = Twofold;
    fn sub(self, o: Twofold) -> Twofold {
        self + -o
    }
}

impl core::ops::Mul for Twofold {
    type Output = Twofold;
    fn mul(self, o: Twofold) -> Twofold {
        let (p, e) = two_prod(self.hi, o.hi);
        let (hi, lo) = quick_two_sum(p, e + (self.hi * o.lo + self.lo * o.hi));
        Twofold { hi, lo }
    }
}

impl core::ops::Div for Twofold {
    type Output = Twofold;
    /// By one correction of the f64 quotient.
    fn div(self, o: Twofold) -> Twofold {
        let q1 = self.hi / o.hi;
        let r = self - o * Twofold::from(q1);
        let q2 = r.hi / o.hi;
        let (hi, lo) = quick_two_sum(q1, q2);
        Twofold { hi, lo }
    }
}

/// What an interpreter of expressions computes in: the solvers' scalars ([`Real`]) and
/// [`Twofold`], with one name for each operation (the generic engine's tapes run on either).
pub trait Arith:
    Copy
    + core::ops::Add<Output = Self>
    + core::ops::Sub<Output = Self>
    + core::ops::Mul<Output = Self>
    + core::ops::Div<Output = Self>
    + core::ops::Neg<Output = Self>
{
    /// An f64 constant.
    fn constant(c: f64) -> Self;
    fn sin_cos_of(self) -> (Self, Self);
    fn sin_of(self) -> Self {
        self.sin_cos_of().0
    }
    fn cos_of(self) -> Self {
        self.sin_cos_of().1
    }
    fn tan_of(self) -> Self {
        let (s, c) = self.sin_cos_of();
        s / c
    }
    fn sqrt_of(self) -> Self;
    /// `asin`, `abs`, `atan2(a, b)`, … by name (`b` unused by one-argument functions).
    fn func(name: &str, a: Self, b: Self) -> Self;
}

impl<T: Real> Arith for T {
    fn constant(c: f64) -> T {
        T::lit(c)
    }
    fn sin_cos_of(self) -> (T, T) {
        self.sin_cos()
    }
    fn sin_of(self) -> T {
        self.sin()
    }
    fn cos_of(self) -> T {
        self.cos()
    }
    fn tan_of(self) -> T {
        self.tan()
    }
    fn sqrt_of(self) -> T {
        self.sqrt()
    }
    fn func(name: &str, a: T, b: T) -> T {
        match name {
            "asin" => a.asin(),
            "acos" => a.acos(),
            "atan" => a.atan(),
            "abs" => a.abs(),
            "atan2" => a.atan2(b),
            "hypot" => a.hypot(b),
            _ => T::lit(f64::NAN),
        }
    }
}

impl Arith for Twofold {
    fn constant(c: f64) -> Twofold {
        Twofold::from(c)
    }
    fn sin_cos_of(self) -> (Twofold, Twofold) {
        self.sin_cos()
    }
    fn sqrt_of(self) -> Twofold {
        self.sqrt()
    }
    /// In f64 (a params-only function: the params are given in f64).
    fn func(name: &str, a: Twofold, b: Twofold) -> Twofold {
        Twofold::from(f64::func(name, a.value(), b.value()))
    }
}

/// Positions are refined ([`refine_block`]) when the solve's pivot ratio is below this (a
/// condition estimate above 100: within about 0.01° of a typical dead point), where the rates'
/// error from a residual known only to rounding starts to exceed 1e-11.
pub const REFINE_BELOW: f64 = 1e-2;

/// The refinement step in place: `r` (a block's residual to double-word precision) becomes
/// `J⁻¹ r` (`jac` and `scale` are overwritten). Whether to take it: finite and within `1e-6`
/// (relative) of the unknowns `at(k)`, as a step from a converged state is; otherwise the state is
/// to be left as it was.
pub fn refinement_in_place<T: Real, D: Dim>(
    jac: &mut OMatrix<T, D, D>,
    r: &mut OVector<T, D>,
    scale: &mut OVector<T, D>,
    at: impl Fn(usize) -> T,
) -> bool
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    if gauss_in_place(jac, r, scale).is_err() {
        return false;
    }
    r.iter()
        .enumerate()
        .all(|(k, d)| d.is_finite() && d.abs() <= T::lit(1e-6) * (T::one() + at(k).abs()))
}

/// One Newton step on a block at the solved state `st`: `q[idx] −= J⁻¹ r` with `r` the block's
/// residual to double-word precision and `J` its Jacobian there, the angles' sines and cosines
/// computed afresh; only when [`refinement_in_place`] takes it. Returns whether it did.
pub fn refine_block<T: Real, const K: usize, const N: usize>(
    st: &mut TrigState<T, N>,
    idx: [usize; K],
    mut jac: SMatrix<T, K, K>,
    mut residual: SVector<T, K>,
) -> bool {
    let mut scale = SVector::<T, K>::zeros();
    if !refinement_in_place(&mut jac, &mut residual, &mut scale, |k| st.q[idx[k]]) {
        return false;
    }
    for k in 0..K {
        st.set(idx[k], st.q[idx[k]] - residual[k]);
    }
    true
}

#[cfg(test)]
mod tests {
    use super::Twofold;

    /// Within `tol` of the 50-digit value `(hi, lo)` (mpmath, rounded to two words).
    fn near(got: Twofold, want: (f64, f64), tol: f64) -> bool {
        let d = (Twofold::from(got.hi) - Twofold::from(want.0))
            + (Twofold::from(got.lo) - Twofold::from(want.1));
        d.value().abs() <= tol
    }

    #[test]
    fn sine_and_cosine_to_double_word_precision() {
        // (x, sin x, cos x): mpmath at 50 digits of the f64 x, each rounded to two words.
        let cases = [
            (
                0.7,
                (0.644217687237691, 2.8740567927338755e-18),
                (0.7648421872844885, -4.013780434022238e-17),
            ),
            (
                2.5,
                (0.5984721441039565, -5.521403334082375e-17),
                (-0.8011436155469337, -1.8674742705085553e-17),
            ),
            (
                -4.2,
                (0.8715757724135882, -4.298425632639332e-17),
                (-0.4902608213406994, 3.5857105369120555e-18),
            ),
            (
                100.3,
                (-0.22891692244520673, 2.6396031437971418e-18),
                (0.9734459628650248, -4.412772653826556e-17),
            ),
            (
                0.001,
                (0.0009999998333333417, 5.670638989736153e-21),
                (0.9999995000000417, -7.831485455398128e-18),
            ),
            (
                6.00618527328823,
                (-0.2734712755738673, 2.5965101569329465e-17),
                (0.9618801699983226, -1.9309291023778033e-17),
            ),
        ];
        for (x, s, c) in cases {
            let (gs, gc) = Twofold::from(x).sin_cos();
            assert!(near(gs, s, 1e-31), "sin {x}: {gs:?} vs {s:?}");
            assert!(near(gc, c, 1e-31), "cos {x}: {gc:?} vs {c:?}");
        }
    }

    #[test]
    fn products_quotients_roots() {
        let (a, b) = (Twofold::from(0.1), Twofold::from(0.3));
        // 50-digit products of the f64 0.1 and 0.3, rounded to two words (mpmath).
        assert!(near(a * b, (0.03, 1.6653345369377347e-18), 1e-33));
        assert!(near(
            a / b,
            (0.33333333333333337, -6.16790569236198e-18),
            1e-32
        ));
        let r = Twofold::from(2.0).sqrt();
        // Two words hold 106 bits: 1.2e-32 relative is one unit of the second word here.
        assert!(
            near(
                r,
                (core::f64::consts::SQRT_2, -9.667293313452913e-17),
                4e-32
            ),
            "{r:?}"
        );
        // (a + b) − b gives a back exactly, where f64 does not.
        assert_eq!((a + b - b).value(), 0.1);
        assert_ne!(0.1 + 0.3 - 0.3, 0.1);
    }
}
