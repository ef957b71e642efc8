//! [`Lanes`] on plain arrays ([`Vf64`], [`Vf32`]): every operation a loop over the lanes that the
//! compiler turns into the vector instructions of the function it is inlined into. Compiled in a
//! function that [`dispatch`](super::dispatch()) runs with AVX-512 enabled, an eight-lane `Vf64` is
//! one 512-bit register; with AVX2 two 256-bit ones; on baseline x86-64 four SSE2 ones. The same
//! source and the same IEEE operations in every case, so the results are equal bit for bit.

use core::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use super::Lanes;
use crate::scalar::Real;

/// A mask of `W` lanes (a comparison's result of [`Vf64`] or [`Vf32`]): all bits set in a lane
/// where it holds (as the vector instructions give it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ArrayMask<const W: usize>([i64; W]);

impl<const W: usize> ArrayMask<W> {
    #[inline(always)]
    fn from_bools(f: impl Fn(usize) -> bool) -> Self {
        let mut m = [0; W];
        for (i, m) in m.iter_mut().enumerate() {
            *m = -i64::from(f(i));
        }
        ArrayMask(m)
    }
}

impl<const W: usize> BitAnd for ArrayMask<W> {
    type Output = Self;
    #[inline(always)]
    fn bitand(mut self, o: Self) -> Self {
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a &= b;
        }
        self
    }
}

impl<const W: usize> BitOr for ArrayMask<W> {
    type Output = Self;
    #[inline(always)]
    fn bitor(mut self, o: Self) -> Self {
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a |= b;
        }
        self
    }
}

impl<const W: usize> Not for ArrayMask<W> {
    type Output = Self;
    #[inline(always)]
    fn not(mut self) -> Self {
        for a in self.0.iter_mut() {
            *a = !*a;
        }
        self
    }
}

macro_rules! array_lanes {
    ($(#[$doc:meta])* $name:ident, $t:ty) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub struct $name<const W: usize>(pub [$t; W]);

        impl<const W: usize> Default for $name<W> {
            #[inline(always)]
            fn default() -> Self {
                $name([0.0; W])
            }
        }

        impl<const W: usize> $name<W> {
            /// The lanes `v`.
            pub const fn new(v: [$t; W]) -> Self {
                $name(v)
            }
            /// The lanes as an array.
            pub const fn to_array(self) -> [$t; W] {
                self.0
            }
            #[inline(always)]
            fn zip(mut self, o: Self, f: impl Fn($t, $t) -> $t) -> Self {
                for (a, b) in self.0.iter_mut().zip(o.0) {
                    *a = f(*a, b);
                }
                self
            }
            #[inline(always)]
            fn each(mut self, f: impl Fn($t) -> $t) -> Self {
                for a in self.0.iter_mut() {
                    *a = f(*a);
                }
                self
            }
            #[inline(always)]
            fn test(self, o: Self, f: impl Fn($t, $t) -> bool) -> ArrayMask<W> {
                ArrayMask::from_bools(|i| f(self.0[i], o.0[i]))
            }
        }

        impl<const W: usize> Add for $name<W> {
            type Output = Self;
            #[inline(always)]
            fn add(self, o: Self) -> Self {
                self.zip(o, |a, b| a + b)
            }
        }
        impl<const W: usize> Sub for $name<W> {
            type Output = Self;
            #[inline(always)]
            fn sub(self, o: Self) -> Self {
                self.zip(o, |a, b| a - b)
            }
        }
        impl<const W: usize> Mul for $name<W> {
            type Output = Self;
            #[inline(always)]
            fn mul(self, o: Self) -> Self {
                self.zip(o, |a, b| a * b)
            }
        }
        impl<const W: usize> Div for $name<W> {
            type Output = Self;
            #[inline(always)]
            fn div(self, o: Self) -> Self {
                self.zip(o, |a, b| a / b)
            }
        }
        impl<const W: usize> Neg for $name<W> {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                self.each(|a| -a)
            }
        }

        impl<const W: usize> Lanes for $name<W> {
            type Scalar = $t;
            type Mask = ArrayMask<W>;
            type Array<U: Copy + core::fmt::Debug + Send + Sync> = [U; W];
            const W: usize = W;

            #[inline(always)]
            fn splat(v: $t) -> Self {
                $name([v; W])
            }
            #[inline(always)]
            fn from_fn(f: impl FnMut(usize) -> $t) -> Self {
                $name(core::array::from_fn(f))
            }
            #[inline(always)]
            fn array<U: Copy + core::fmt::Debug + Send + Sync>(f: impl FnMut(usize) -> U) -> [U; W] {
                core::array::from_fn(f)
            }
            #[inline(always)]
            fn lane(self, i: usize) -> $t {
                self.0[i]
            }
            #[inline(always)]
            fn set_lane(&mut self, i: usize, v: $t) {
                self.0[i] = v;
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                // The scalar's correctly rounded square root, which vectorizes to the
                // instruction (`sqrtpd`): equal in every lane.
                self.each(Real::sqrt)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                self.each(Real::abs)
            }
            #[inline(always)]
            fn lt(self, o: Self) -> ArrayMask<W> {
                self.test(o, |a, b| a < b)
            }
            #[inline(always)]
            fn le(self, o: Self) -> ArrayMask<W> {
                self.test(o, |a, b| a <= b)
            }
            #[inline(always)]
            fn gt(self, o: Self) -> ArrayMask<W> {
                self.test(o, |a, b| a > b)
            }
            #[inline(always)]
            fn ge(self, o: Self) -> ArrayMask<W> {
                self.test(o, |a, b| a >= b)
            }
            #[inline(always)]
            fn eq(self, o: Self) -> ArrayMask<W> {
                self.test(o, |a, b| a == b)
            }
            #[inline(always)]
            fn is_finite(self) -> ArrayMask<W> {
                ArrayMask::from_bools(|i| self.0[i].is_finite())
            }
            #[inline(always)]
            fn select(m: ArrayMask<W>, mut a: Self, b: Self) -> Self {
                for ((a, b), m) in a.0.iter_mut().zip(b.0).zip(m.0) {
                    if m == 0 {
                        *a = b;
                    }
                }
                a
            }
            #[inline(always)]
            fn mask(bits: u32) -> ArrayMask<W> {
                ArrayMask::from_bools(|i| bits >> i & 1 == 1)
            }
            #[inline(always)]
            fn bits(m: ArrayMask<W>) -> u32 {
                // A lane of a mask is 0 or -1 (every mask is made by `from_bools` and kept so by
                // `&`, `|` and `!`): its sign bit, which the CPU gathers in one instruction.
                let mut bits = 0;
                for (i, &b) in m.0.iter().enumerate() {
                    bits |= u32::from(b < 0) << i;
                }
                bits
            }
        }
    };
}

array_lanes!(
    /// `W` f64 lanes as a plain array (see the module): the lanes
    /// [`WithLanes`](super::WithLanes) gives for f64 (`Vf64<8>`), vectorized to the widest
    /// instructions of the CPU where [`dispatch`](super::dispatch()) runs them.
    Vf64,
    f64
);
array_lanes!(
    /// `W` f32 lanes as a plain array (see [`Vf64`]); [`WithLanes`](super::WithLanes) gives
    /// `Vf32<16>` for f32.
    Vf32,
    f32
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masks_compare_as_the_scalar_does() {
        let a = Vf64::new([1.0, f64::NAN, -0.0, 3.0]);
        let b = Vf64::new([2.0, 1.0, 0.0, f64::INFINITY]);
        assert_eq!(Vf64::bits(a.lt(b)), 0b1001);
        assert_eq!(Vf64::bits(!a.gt(b)), 0b1111);
        assert_eq!(Vf64::bits(a.eq(b)), 0b0100);
        assert_eq!(Vf64::bits(b.is_finite()), 0b0111);
        assert_eq!(Vf64::bits(a.is_finite()), 0b1101);
        assert_eq!(Vf64::bits(Vf64::<4>::mask(0b0110)), 0b0110);
        let s = Vf64::select(a.lt(b), a, b);
        assert_eq!((s.lane(0), s.lane(1)), (1.0, 1.0));
        assert_eq!(Vf64::<4>::all_bits(), 0b1111);
        assert_eq!(Vf32::<16>::all_bits(), 0xffff);
        let x = Vf64::new([0.3, -2.0, 5.0, 1e3]);
        let (s, c) = Lanes::sin_cos(x);
        for i in 0..4 {
            assert_eq!((s.lane(i), c.lane(i)), x.lane(i).sin_cos());
            assert_eq!(Lanes::sqrt(Lanes::abs(x)).lane(i), x.lane(i).abs().sqrt());
            assert_eq!((x / x * x - x + x).lane(i), x.lane(i));
        }
    }
}
