//! SIMD lane types: a vector of W scalars, one per instance ([`F64x4`], [`F32x8`], …), with
//! arithmetic that rounds lane by lane as the scalar does, comparisons to masks and selection.
//! The lane solvers of [`crate::lanes`] are written over [`Lanes`].

mod array;
mod dispatch;
mod wide;

pub use array::{ArrayMask, Vf32, Vf64};
pub use dispatch::{EIGHT_LANES_UP_TO, Isa, Kernel, dispatch, dispatch_on};
pub use wide::{F32x8, F32x16, F64x2, F64x4, F64x8, Mask};

use core::fmt::Debug;
use core::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use crate::scalar::Real;

/// A SIMD vector of `W` scalars, one per instance. Arithmetic is lane by lane and rounds as the
/// scalar does; comparisons give a [`Lanes::Mask`]; the float functions the scalar trait has
/// beyond the square root are evaluated lane by lane with the scalar's own.
pub trait Lanes:
    Copy
    + Default
    + Debug
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The scalar of one lane.
    type Scalar: Real;
    /// A lane mask (the result of a comparison).
    type Mask: Copy
        + Debug
        + BitAnd<Output = Self::Mask>
        + BitOr<Output = Self::Mask>
        + Not<Output = Self::Mask>;
    /// One value per lane.
    type Array<U: Copy + Debug + Send + Sync>: Copy + Debug + Send + Sync + AsRef<[U]> + AsMut<[U]>;
    /// The number of lanes.
    const W: usize;

    fn splat(v: Self::Scalar) -> Self;
    /// Lane `i` is `f(i)`.
    fn from_fn(f: impl FnMut(usize) -> Self::Scalar) -> Self;
    /// One value per lane, lane `i` being `f(i)`.
    fn array<U: Copy + Debug + Send + Sync>(f: impl FnMut(usize) -> U) -> Self::Array<U>;
    /// Lane `i`. Like indexing an array, panics for `i ≥ W` (every caller in the runtime and in
    /// generated code loops over `0..W`; the `LaneTick` methods users call check the index).
    fn lane(self, i: usize) -> Self::Scalar;
    /// Sets lane `i` (panics for `i ≥ W`, as [`Lanes::lane`]).
    fn set_lane(&mut self, i: usize, v: Self::Scalar);

    fn sqrt(self) -> Self;
    fn abs(self) -> Self;
    fn lt(self, o: Self) -> Self::Mask;
    fn le(self, o: Self) -> Self::Mask;
    fn gt(self, o: Self) -> Self::Mask;
    fn ge(self, o: Self) -> Self::Mask;
    /// Lane by lane `==` (a NaN equals nothing).
    fn eq(self, o: Self) -> Self::Mask;
    fn is_finite(self) -> Self::Mask;
    /// `if m { a } else { b }`, lane by lane.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// Bit `i` set where lane `i` of `m` is.
    fn bits(m: Self::Mask) -> u32;

    /// The mask of the lanes whose bit is set in `bits`.
    #[inline(always)]
    fn mask(bits: u32) -> Self::Mask {
        let one = <Self::Scalar as num_traits::One>::one();
        let zero = <Self::Scalar as num_traits::Zero>::zero();
        Self::from_fn(|i| if bits >> i & 1 == 1 { one } else { zero }).gt(Self::zero())
    }

    /// An f64 constant in every lane, rounded as [`Real::lit`] rounds it.
    #[inline(always)]
    fn lit(x: f64) -> Self {
        Self::splat(Self::Scalar::lit(x))
    }
    #[inline(always)]
    fn zero() -> Self {
        Self::splat(<Self::Scalar as num_traits::Zero>::zero())
    }
    #[inline(always)]
    fn one() -> Self {
        Self::splat(<Self::Scalar as num_traits::One>::one())
    }
    /// Every lane's bit (the mask of all lanes).
    #[inline(always)]
    fn all_bits() -> u32 {
        if Self::W >= 32 {
            u32::MAX
        } else {
            (1u32 << Self::W) - 1
        }
    }
    /// [`Real::sin_cos`] lane by lane.
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        let (mut s, mut c) = (self, self);
        for i in 0..Self::W {
            let (si, ci) = self.lane(i).sin_cos();
            s.set_lane(i, si);
            c.set_lane(i, ci);
        }
        (s, c)
    }
    /// [`Real::sin`] lane by lane.
    #[inline(always)]
    fn sin(self) -> Self {
        Self::from_fn(|i| self.lane(i).sin())
    }
    /// [`Real::cos`] lane by lane.
    #[inline(always)]
    fn cos(self) -> Self {
        Self::from_fn(|i| self.lane(i).cos())
    }
    /// [`Real::tan`] lane by lane.
    #[inline(always)]
    fn tan(self) -> Self {
        Self::from_fn(|i| self.lane(i).tan())
    }
    /// [`Real::asin`] lane by lane.
    #[inline(always)]
    fn asin(self) -> Self {
        Self::from_fn(|i| self.lane(i).asin())
    }
    /// [`Real::acos`] lane by lane.
    #[inline(always)]
    fn acos(self) -> Self {
        Self::from_fn(|i| self.lane(i).acos())
    }
    /// [`Real::atan`] lane by lane.
    #[inline(always)]
    fn atan(self) -> Self {
        Self::from_fn(|i| self.lane(i).atan())
    }
    /// [`Real::atan2`] lane by lane.
    #[inline(always)]
    fn atan2(self, o: Self) -> Self {
        Self::from_fn(|i| self.lane(i).atan2(o.lane(i)))
    }
    /// [`Real::hypot`] lane by lane.
    #[inline(always)]
    fn hypot(self, o: Self) -> Self {
        Self::from_fn(|i| self.lane(i).hypot(o.lane(i)))
    }
}

/// The lanes of a scalar for code that runs with the CPU's widest vectors: eight f64 lanes
/// ([`Vf64<8>`]), sixteen f32 lanes ([`Vf32<16>`]), plain arrays that a kernel run by
/// [`dispatch()`] compiles to one AVX-512 register, two AVX2 ones or four SSE2 ones, whichever the
/// CPU has (chosen at run time; the same results on every path).
pub trait WithLanes: Real {
    type Lanes: Lanes<Scalar = Self>;
}

impl WithLanes for f64 {
    type Lanes = Vf64<8>;
}

impl WithLanes for f32 {
    type Lanes = Vf32<16>;
}
