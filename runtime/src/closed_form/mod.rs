//! Closed-form position kernels of the one-loop groups mechgen-codegen's `closed_form` stage
//! recognises (the RRR dyad is `crate::dyad`): each solves its block exactly, on the guess's side
//! (never a silent branch flip; angles keep their whole turns), and lists all its real solutions
//! (assembly modes) for branch identification. Allocation-free; failures are [`SolveError`]s.
//!
//! | kind | equation | unknowns | kernel | modes |
//! | --- | --- | --- | --- | --- |
//! | RRR | `K + M_a e(q_a) + M_b e(q_b) = 0` | angles q_a, q_b | `crate::dyad::solve_dyad`, [`rrr_modes`] | 2, 1, 0 |
//! | RRP / PRR | `K + M e(q) + s u = 0` | angle q, length s | [`solve_rrp`], [`rrp_modes`] | 2, 1, 0 |
//! | RPR | `K + (M + s N) e(q) = 0` | angle q, length s | [`solve_rpr`], [`rpr_modes`] | 2, 1, 0 |
//! | linear 2×2 | `K + s1 u1 + s2 u2 = 0` | lengths s1, s2 | [`solve_linear2`], [`linear2_modes`] | 1 |
//! | one angle | `K + P cos q + Q sin q = 0` | angle q | [`solve_angle1`], [`angle1_modes`] | 2, 1, 0 |
//! | one length | `K + a s = 0` | length s | [`solve_length1`], [`length1_modes`] | 1 |
//!
//! `M = [[p, −r], [r, p]]` and `N` are rotation-scalings given as `(p, r)`; `e(q) = (cos q, sin q)`.
//!
//! The kernels with an angle take `value` (the dyad: `crate::dyad::solve_dyad_angles`): whether
//! the caller reads the angle itself. When it does not (a generated scene whose outputs read only
//! the angle's sine and cosine), only they are solved and the angle keeps its old value, which
//! saves the turn series (or `atan2`) on the way to it.

mod angle1;
mod kind;
mod linear;
mod rpr;
mod rrp;
mod rrr;

pub use angle1::{angle1_modes, solve_angle1};
pub use kind::ClosedKind;
pub use linear::{length1_modes, linear2_modes, solve_length1, solve_linear2};
pub use rpr::{rpr_modes, solve_rpr};
pub use rrp::{rrp_modes, solve_rrp};
pub use rrr::rrr_modes;

use crate::error::{SolveError, Stage};
use crate::scalar::Real;
use crate::solve::TrigState;

/// One real solution of a block: its unknowns in the kernel's order (the angle first for RRP and
/// RPR; `s1, s2` for the linear 2×2; one value for one-unknown kinds), angles as principal values
/// in (−π, π], with the (sin, cos) of each angle ((0, 1) for a length or an unused slot).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mode<T> {
    pub values: [T; 2],
    pub sc: [(T, T); 2],
}

/// All real solutions of a block: two assembly modes, one (at a dead point, or for a linear
/// block), or none (past a dead point). Fixed size, no allocation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Modes<T> {
    len: usize,
    modes: [Mode<T>; 2],
}

impl<T: Real> Modes<T> {
    /// No solution.
    pub fn none() -> Self {
        let empty = Mode {
            values: [T::zero(); 2],
            sc: [(T::zero(), T::one()); 2],
        };
        Modes {
            len: 0,
            modes: [empty; 2],
        }
    }

    fn push(&mut self, m: Mode<T>) {
        if self.len < 2 {
            self.modes[self.len] = m;
            self.len += 1;
        }
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn as_slice(&self) -> &[Mode<T>] {
        &self.modes[..self.len]
    }
}

/// How far past a dead point (relative to the length it compares) rounding alone can put a
/// configuration: within this the block is at its dead point, beyond it unassemblable.
fn dead_point_slack<T: Real>() -> T {
    T::EPSILON * T::lit(128.0)
}

/// The overflow of finite arguments (or non-finite coefficients), as the dyad and Newton report it.
fn overflow(block: usize) -> SolveError {
    SolveError::Overflow {
        block,
        stage: Stage::Position,
    }
}

/// The block's geometry when its loop can close (`Ok` from the kernel's geometry function), else
/// `Unassemblable` with the gap relative to the length scale (`scale` is asked for only then).
#[inline(always)]
fn closes<G, T: Real>(
    block: usize,
    geometry: Result<G, T>,
    scale: impl FnOnce() -> T,
) -> Result<G, SolveError> {
    geometry.map_err(|gap| SolveError::Unassemblable {
        block,
        residual: (gap / scale()).to_f64(),
        iterations: 0,
    })
}

/// The mode on the guess's side: −1 where `along` (the guess's component that tells the two
/// modes apart) is negative, +1 otherwise.
#[inline(always)]
fn side<T: Real>(along: T) -> T {
    if along < T::zero() {
        -T::one()
    } else {
        T::one()
    }
}

/// `NonFinite` for a non-finite guess of unknown `k`.
fn check_guess<T: Real, const N: usize>(st: &TrigState<T, N>, k: usize) -> Result<(), SolveError> {
    if st.q[k].is_finite() {
        Ok(())
    } else {
        Err(SolveError::NonFinite {
            quantity: crate::error::Quantity::Guess,
            index: k,
        })
    }
}

/// Whether every value is finite.
fn all_finite<T: Real>(v: &[T]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Writes angle `k` of `st` as the direction `(c, s)`: the guess's angle plus the turn to it
/// (whole turns kept), or the principal value where the guess is too large to hold the answer to
/// `tolerance` (as `crate::dyad` does). With `value` false only the sine and cosine are written
/// and the angle keeps its old value (a caller that reads only them: see the kernels' `value`).
#[inline(always)]
fn set_angle<T: Real, const N: usize>(
    st: &mut TrigState<T, N>,
    k: usize,
    (c, s): (T, T),
    tol: T,
    value: bool,
) {
    if value {
        let (sg, cg) = st.sc[k];
        st.q[k] = crate::dyad::near(st.q[k], (cg, sg), (c, s), tol);
    }
    st.sc[k] = (s, c);
}

/// A mode of an angle and a length (RRP, RPR) from the angle's direction.
fn angle_length<T: Real>((c, s): (T, T), len: T) -> Mode<T> {
    Mode {
        values: [s.atan2(c), len],
        sc: [(s, c), (T::zero(), T::one())],
    }
}

/// `M⁻¹ v` for `M = [[p, −r], [r, p]]` (`r = 0`: a plain scaling).
fn unapply<T: Real>((p, r): (T, T), (x, y): (T, T)) -> (T, T) {
    if r == T::zero() {
        let inv = T::one() / p;
        (x * inv, y * inv)
    } else {
        let inv = T::one() / (p * p + r * r);
        ((p * x + r * y) * inv, (p * y - r * x) * inv)
    }
}

/// `M e` for `M = [[p, −r], [r, p]]` and `e = (cos, sin)`.
fn apply<T: Real>((p, r): (T, T), (c, s): (T, T)) -> (T, T) {
    (p * c - r * s, r * c + p * s)
}

#[cfg(test)]
mod test_util {
    /// Distance of two angles modulo 2π.
    pub fn angle_gap(a: f64, b: f64) -> f64 {
        let d = (a - b).rem_euclid(std::f64::consts::TAU);
        d.min(std::f64::consts::TAU - d)
    }
}
