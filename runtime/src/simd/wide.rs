//! [`Lanes`] for the SIMD vectors of the `wide` crate (explicit SSE2/AVX code, a 256-bit vector
//! as two 128-bit halves where AVX is not enabled).

use super::Lanes;

/// A mask of lanes (a comparison's result): all bits set in a lane where it holds.
#[derive(Clone, Copy, Debug)]
pub struct Mask<V>(V);

macro_rules! impl_lanes {
    ($(#[$doc:meta])* $name:ident, $v:ty, $t:ty, $w:expr) => {
        $(#[$doc])*
        ///
        /// A newtype over `wide`'s vector that has only [`Lanes`]' methods: its float functions
        /// are the scalar's, lane by lane (the vector's own polynomial `sin_cos` would differ from
        /// the scalar's in the last bit).
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        pub struct $name($v);

        impl $name {
            /// The lanes `v`.
            pub const fn new(v: [$t; $w]) -> Self {
                $name(<$v>::new(v))
            }
            /// The lanes as an array.
            pub const fn to_array(self) -> [$t; $w] {
                self.0.to_array()
            }
        }

        impl core::ops::Add for $name {
            type Output = Self;
            #[inline(always)]
            fn add(self, o: Self) -> Self {
                $name(self.0 + o.0)
            }
        }
        impl core::ops::Sub for $name {
            type Output = Self;
            #[inline(always)]
            fn sub(self, o: Self) -> Self {
                $name(self.0 - o.0)
            }
        }
        impl core::ops::Mul for $name {
            type Output = Self;
            #[inline(always)]
            fn mul(self, o: Self) -> Self {
                $name(self.0 * o.0)
            }
        }
        impl core::ops::Div for $name {
            type Output = Self;
            #[inline(always)]
            fn div(self, o: Self) -> Self {
                $name(self.0 / o.0)
            }
        }
        impl core::ops::Neg for $name {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                $name(-self.0)
            }
        }
        impl core::ops::BitAnd for Mask<$v> {
            type Output = Self;
            #[inline(always)]
            fn bitand(self, o: Self) -> Self {
                Mask(self.0 & o.0)
            }
        }
        impl core::ops::BitOr for Mask<$v> {
            type Output = Self;
            #[inline(always)]
            fn bitor(self, o: Self) -> Self {
                Mask(self.0 | o.0)
            }
        }
        impl core::ops::Not for Mask<$v> {
            type Output = Self;
            #[inline(always)]
            fn not(self) -> Self {
                Mask(!self.0)
            }
        }

        impl Lanes for $name {
            type Scalar = $t;
            type Mask = Mask<$v>;
            type Array<U: Copy + core::fmt::Debug + Send + Sync> = [U; $w];
            const W: usize = $w;

            #[inline(always)]
            fn splat(v: $t) -> Self {
                $name(<$v>::splat(v))
            }
            #[inline(always)]
            fn from_fn(f: impl FnMut(usize) -> $t) -> Self {
                $name(<$v>::new(core::array::from_fn(f)))
            }
            #[inline(always)]
            fn array<U: Copy + core::fmt::Debug + Send + Sync>(f: impl FnMut(usize) -> U) -> [U; $w] {
                core::array::from_fn(f)
            }
            #[inline(always)]
            fn lane(self, i: usize) -> $t {
                self.0.as_array()[i]
            }
            #[inline(always)]
            fn set_lane(&mut self, i: usize, v: $t) {
                self.0.as_mut_array()[i] = v;
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                // IEEE square root, correctly rounded like the scalar's.
                $name(self.0.sqrt())
            }
            #[inline(always)]
            fn abs(self) -> Self {
                $name(self.0.abs())
            }
            #[inline(always)]
            fn lt(self, o: Self) -> Mask<$v> {
                Mask(self.0.simd_lt(o.0))
            }
            #[inline(always)]
            fn le(self, o: Self) -> Mask<$v> {
                Mask(self.0.simd_le(o.0))
            }
            #[inline(always)]
            fn gt(self, o: Self) -> Mask<$v> {
                Mask(self.0.simd_gt(o.0))
            }
            #[inline(always)]
            fn ge(self, o: Self) -> Mask<$v> {
                Mask(self.0.simd_ge(o.0))
            }
            #[inline(always)]
            fn eq(self, o: Self) -> Mask<$v> {
                Mask(self.0.simd_eq(o.0))
            }
            #[inline(always)]
            fn is_finite(self) -> Mask<$v> {
                Mask(self.0.is_finite())
            }
            #[inline(always)]
            fn select(m: Mask<$v>, a: Self, b: Self) -> Self {
                $name(m.0.select(a.0, b.0))
            }
            #[inline(always)]
            fn bits(m: Mask<$v>) -> u32 {
                m.0.to_bitmask()
            }
        }
    };
}

impl_lanes!(
    /// Four f64 lanes (one AVX register, or two SSE2 ones).
    F64x4, wide::f64x4, f64, 4
);
impl_lanes!(
    /// Two f64 lanes (one SSE2 register).
    F64x2, wide::f64x2, f64, 2
);
impl_lanes!(
    /// Eight f32 lanes (one AVX register, or two SSE2 ones).
    F32x8, wide::f32x8, f32, 8
);
impl_lanes!(
    /// Eight f64 lanes (one AVX-512 register, or two AVX ones, or four SSE2 ones).
    F64x8, wide::f64x8, f64, 8
);
impl_lanes!(
    /// Sixteen f32 lanes (one AVX-512 register, or two AVX ones, or four SSE2 ones).
    F32x16, wide::f32x16, f32, 16
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masks_compare_as_the_scalar_does() {
        let a = F64x4::new([1.0, f64::NAN, -0.0, 3.0]);
        let b = F64x4::new([2.0, 1.0, 0.0, f64::INFINITY]);
        assert_eq!(F64x4::bits(a.lt(b)), 0b1001);
        assert_eq!(F64x4::bits(!a.gt(b)), 0b1111);
        assert_eq!(F64x4::bits(a.eq(b)), 0b0100);
        assert_eq!(F64x4::bits(b.is_finite()), 0b0111);
        assert_eq!(F64x4::bits(a.is_finite()), 0b1101);
        let s = F64x4::select(a.lt(b), a, b);
        assert_eq!(s.lane(0), 1.0);
        assert_eq!(s.lane(1), 1.0);
        assert_eq!(F64x4::all_bits(), 0b1111);
        assert_eq!(F32x8::all_bits(), 0xff);
        let x = F64x4::new([0.3, -2.0, 5.0, 1e3]);
        let (s, c) = Lanes::sin_cos(x);
        for i in 0..4 {
            assert_eq!((s.lane(i), c.lane(i)), x.lane(i).sin_cos());
            assert_eq!(Lanes::sqrt(Lanes::abs(x)).lane(i), x.lane(i).abs().sqrt());
        }
    }
}
