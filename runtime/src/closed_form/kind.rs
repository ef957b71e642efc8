//! The closed-form kinds as one value ([`ClosedKind`]): each kind's unknowns (which of them are
//! angles), the layout of its roots, its kernel, all its modes and its margin to the dead point,
//! in one place. Run-time engines and the branch analysis call these; generated code calls the
//! kernels themselves (the emitter knows the kind when it writes the call).

use super::{
    Modes, angle1_modes, length1_modes, linear2_modes, rpr_modes, rrp_modes, rrr_modes,
    solve_angle1, solve_length1, solve_linear2, solve_rpr, solve_rrp,
};
use crate::dyad::solve_dyad;
use crate::error::SolveError;
use crate::scalar::Real;
use crate::solve::{NewtonReport, TrigState};

/// A closed-form kind (see the table of [`crate::closed_form`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ClosedKind {
    /// `K + M_a e(q_a) + M_b e(q_b) = 0`, roots `[Kx, Ky, pa, ra, pb, rb]`.
    Rrr,
    /// `K + M e(q) + s u = 0`, roots `[Kx, Ky, p, r, ux, uy]`.
    Rrp,
    /// `K + (M + s N) e(q) = 0`, roots `[Kx, Ky, mp, mr, np, nr]`.
    Rpr,
    /// `K + s1 u1 + s2 u2 = 0`, roots `[Kx, Ky, u1x, u1y, u2x, u2y]`.
    Linear2,
    /// `K + P cos q + Q sin q = 0`, roots `[K, P, Q]`.
    Angle1,
    /// `K + a s = 0`, roots `[K, a]`.
    Length1,
}

impl ClosedKind {
    /// How many roots the kernel takes.
    pub fn roots(self) -> usize {
        match self {
            ClosedKind::Angle1 => 3,
            ClosedKind::Length1 => 2,
            _ => 6,
        }
    }

    /// How many unknowns it solves (1 or 2).
    pub fn unknowns(self) -> usize {
        match self {
            ClosedKind::Angle1 | ClosedKind::Length1 => 1,
            _ => 2,
        }
    }

    /// Per unknown slot (the kernel's order: the angle first for RRP and RPR), whether it is an
    /// angle; an unused second slot is `false`.
    pub fn angles(self) -> [bool; 2] {
        match self {
            ClosedKind::Rrr => [true, true],
            ClosedKind::Rrp | ClosedKind::Rpr | ClosedKind::Angle1 => [true, false],
            ClosedKind::Linear2 | ClosedKind::Length1 => [false, false],
        }
    }

    /// Solves the block in place: `slots` index its unknowns in `st` (in the kernel's order; the
    /// second is ignored for a one-unknown kind), `v` are its roots at the current state, the
    /// guess in `st` picks the mode. Every angle's value is computed.
    #[allow(clippy::too_many_arguments)]
    pub fn solve<T: Real, const N: usize>(
        self,
        block: usize,
        st: &mut TrigState<T, N>,
        [a, b]: [usize; 2],
        v: &[T],
        scale: T,
        tolerance: T,
        report: &mut NewtonReport<T>,
    ) -> Result<(), SolveError> {
        let sc = || scale;
        match self {
            ClosedKind::Rrr => solve_dyad(
                block,
                st,
                a,
                b,
                [v[0], v[1]],
                (v[2], v[3]),
                (v[4], v[5]),
                sc,
                tolerance,
                report,
            ),
            ClosedKind::Rrp => solve_rrp(
                block,
                st,
                a,
                b,
                [v[0], v[1]],
                (v[2], v[3]),
                [v[4], v[5]],
                sc,
                tolerance,
                report,
                true,
            ),
            ClosedKind::Rpr => solve_rpr(
                block,
                st,
                a,
                b,
                [v[0], v[1]],
                (v[2], v[3]),
                (v[4], v[5]),
                sc,
                tolerance,
                report,
                true,
            ),
            ClosedKind::Linear2 => solve_linear2(
                block,
                st,
                (a, b),
                [v[0], v[1]],
                [v[2], v[3]],
                [v[4], v[5]],
                report,
            ),
            ClosedKind::Angle1 => solve_angle1(
                block,
                st,
                a,
                v[0],
                (v[1], v[2]),
                sc,
                tolerance,
                report,
                true,
            ),
            ClosedKind::Length1 => solve_length1(block, st, a, v[0], v[1]),
        }
    }

    /// All real solutions of the block whose roots are `v`.
    pub fn modes<T: Real>(self, block: usize, v: &[T]) -> Result<Modes<T>, SolveError> {
        match self {
            ClosedKind::Rrr => rrr_modes(block, [v[0], v[1]], (v[2], v[3]), (v[4], v[5])),
            ClosedKind::Rrp => rrp_modes(block, [v[0], v[1]], (v[2], v[3]), [v[4], v[5]]),
            ClosedKind::Rpr => rpr_modes(block, [v[0], v[1]], (v[2], v[3]), (v[4], v[5])),
            ClosedKind::Linear2 => linear2_modes(block, [v[0], v[1]], [v[2], v[3]], [v[4], v[5]]),
            ClosedKind::Angle1 => angle1_modes(block, v[0], (v[1], v[2])),
            ClosedKind::Length1 => length1_modes(block, v[0], v[1]),
        }
    }

    /// How far the block with roots `v` is from losing (positive) or gaining (negative) its pair
    /// of modes, in length: the distance by which its circles and lines meet or miss. `None` for
    /// the kinds with one mode (linear) and non-finite roots.
    pub fn margin(self, v: &[f64]) -> Option<f64> {
        let m = match self {
            ClosedKind::Rrr => {
                let (l, la, lb) = (v[0].hypot(v[1]), v[2].hypot(v[3]), v[4].hypot(v[5]));
                (la + lb - l).min(l - la + lb).min(l + la - lb)
            }
            ClosedKind::Rrp => {
                // The circle of radius |M| about −K against the line along u through the origin.
                let ul = v[4].hypot(v[5]);
                let h = (v[4] * -v[1] - v[5] * -v[0]) / ul;
                v[2].hypot(v[3]) - h.abs()
            }
            ClosedKind::Rpr => {
                // In the frame of N: |g| against |b|, scaled back by |N|.
                let nn = v[4] * v[4] + v[5] * v[5];
                let g = (-v[0] * v[4] - v[1] * v[5]) / nn;
                let g1 = (-v[1] * v[4] + v[0] * v[5]) / nn;
                let b = (v[3] * v[4] - v[2] * v[5]) / nn;
                (g.hypot(g1) - b.abs()) * nn.sqrt()
            }
            ClosedKind::Angle1 => v[1].hypot(v[2]) - v[0].abs(),
            ClosedKind::Linear2 | ClosedKind::Length1 => return None,
        };
        m.is_finite().then_some(m)
    }
}
