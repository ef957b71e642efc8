//! The scalar type generated solvers are generic over (f64 and f32).

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

/// A real floating-point scalar. Implemented for `f64` and `f32`.
pub trait Real:
    nalgebra::Scalar
    + Copy
    + Default
    + Debug
    + PartialOrd
    + Send
    + Sync
    + 'static
    + num_traits::Zero
    + num_traits::One
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
{
    /// Machine epsilon.
    const EPSILON: Self;
    /// The smallest positive normal value.
    const MIN_POSITIVE: Self;
    /// The largest finite value.
    const MAX: Self;
    /// Default relative Newton step tolerance for this precision.
    const DEFAULT_TOLERANCE: Self;
    /// An f64 constant in this precision (rounded to nearest).
    fn lit(x: f64) -> Self;
    fn to_f64(self) -> f64;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    fn sin_cos(self) -> (Self, Self);
    fn tan(self) -> Self;
    fn sqrt(self) -> Self;
    /// The params-only functions of mechanism files (derived params): `asin`, `acos`, `atan`,
    /// `hypot`.
    fn asin(self) -> Self;
    fn acos(self) -> Self;
    fn atan(self) -> Self;
    fn hypot(self, other: Self) -> Self;
    /// Angle of the point `(other, self)`, in (−π, π].
    fn atan2(self, other: Self) -> Self;
    fn abs(self) -> Self;
    fn max(self, other: Self) -> Self;
    fn min(self, other: Self) -> Self;
    fn is_finite(self) -> bool;
    /// Finite, non-zero and not subnormal.
    fn is_normal(self) -> bool;
    /// The slice itself when `Self` is `f64`, else `None` (for a back end that runs in f64
    /// only: the run-time compiled code of `mechgen`).
    fn as_f64s(s: &[Self]) -> Option<&[f64]>;
    /// [`Real::as_f64s`] of a mutable slice.
    fn as_f64s_mut(s: &mut [Self]) -> Option<&mut [f64]>;
    /// [`Real::as_f64s`] of a slice of pairs.
    fn pairs_as_f64s(s: &[(Self, Self)]) -> Option<&[(f64, f64)]>;
}

macro_rules! impl_real {
    ($t:ty, $tol:expr, $f64:ident) => {
        impl Real for $t {
            const EPSILON: Self = <$t>::EPSILON;
            const MIN_POSITIVE: Self = <$t>::MIN_POSITIVE;
            const MAX: Self = <$t>::MAX;
            const DEFAULT_TOLERANCE: Self = $tol;
            #[inline(always)]
            fn lit(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn sin(self) -> Self {
                num_traits::Float::sin(self)
            }
            #[inline(always)]
            fn cos(self) -> Self {
                num_traits::Float::cos(self)
            }
            #[inline(always)]
            fn sin_cos(self) -> (Self, Self) {
                num_traits::Float::sin_cos(self)
            }
            #[inline(always)]
            fn tan(self) -> Self {
                num_traits::Float::tan(self)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                num_traits::Float::sqrt(self)
            }
            #[inline(always)]
            fn asin(self) -> Self {
                num_traits::Float::asin(self)
            }
            #[inline(always)]
            fn acos(self) -> Self {
                num_traits::Float::acos(self)
            }
            #[inline(always)]
            fn atan(self) -> Self {
                num_traits::Float::atan(self)
            }
            #[inline(always)]
            fn hypot(self, other: Self) -> Self {
                num_traits::Float::hypot(self, other)
            }
            #[inline(always)]
            fn atan2(self, other: Self) -> Self {
                num_traits::Float::atan2(self, other)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                num_traits::Float::abs(self)
            }
            #[inline(always)]
            fn max(self, other: Self) -> Self {
                num_traits::Float::max(self, other)
            }
            #[inline(always)]
            fn min(self, other: Self) -> Self {
                num_traits::Float::min(self, other)
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                num_traits::Float::is_finite(self)
            }
            #[inline(always)]
            fn is_normal(self) -> bool {
                num_traits::Float::is_normal(self)
            }
            fn as_f64s(s: &[Self]) -> Option<&[f64]> {
                $f64!(s)
            }
            fn as_f64s_mut(s: &mut [Self]) -> Option<&mut [f64]> {
                $f64!(s)
            }
            fn pairs_as_f64s(s: &[(Self, Self)]) -> Option<&[(f64, f64)]> {
                $f64!(s)
            }
        }
    };
}

/// `Some` of the slice (`Self` is f64).
macro_rules! is_f64 {
    ($s:expr) => {
        Some($s)
    };
}

/// `None` (`Self` is not f64).
macro_rules! not_f64 {
    ($s:expr) => {{
        let _ = $s;
        None
    }};
}

impl_real!(f64, 1e-12, is_f64);
impl_real!(f32, 1e-5, not_f64);
