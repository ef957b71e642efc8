//! Generic engine, closed forms: a block that mechgen-codegen's `closed_form` stage classified is
//! solved by the runtime kernel of its kind (`mechgen_runtime::dyad`, `mechgen_runtime::closed_form`) from its roots,
//! which a tape evaluates at the current state; the same kernels the generated code calls.

use mechgen_codegen::ClosedForm;

use super::tape::Tape;
use mechgen_runtime::closed_form::{
    solve_angle1, solve_length1, solve_linear2, solve_rpr, solve_rrp,
};
use mechgen_runtime::dyad::solve_dyad;
use mechgen_runtime::error::SolveError;
use mechgen_runtime::scalar::Real;
use mechgen_runtime::solve::{NewtonReport, TrigState};

/// A closed-form block: its kind and the tape of its roots (in the kind's order).
#[derive(Clone, Debug)]
pub(super) struct ClosedTape {
    pub form: ClosedForm,
    pub roots: Tape,
}

/// The block's unknowns in the kernel's order, and whether each is an angle.
fn slots(form: &ClosedForm) -> ([usize; 2], [bool; 2], usize) {
    match *form {
        ClosedForm::Rrr(ref d) => ([d.a, d.b], [true, true], 2),
        ClosedForm::Rrp { q, s, .. } | ClosedForm::Rpr { q, s, .. } => ([q, s], [true, false], 2),
        ClosedForm::Linear2 { s1, s2, .. } => ([s1, s2], [false, false], 2),
        ClosedForm::Angle1 { q, .. } => ([q, q], [true, false], 1),
        ClosedForm::Length1 { s, .. } => ([s, s], [false, false], 1),
    }
}

/// Solves block `block` in closed form: `v` are its roots at the current state, `q` holds the
/// guess (which picks the assembly mode) and receives the block's unknowns on success.
pub(super) fn solve<T: Real>(
    block: usize,
    form: &ClosedForm,
    v: &[T],
    q: &mut [T],
    scale: T,
    tolerance: T,
    report: &mut NewtonReport<T>,
) -> Result<(), SolveError> {
    let (idx, angle, n) = slots(form);
    let mut st = TrigState::new([q[idx[0]], q[idx[1]]], angle);
    let sc = || scale;
    match form {
        ClosedForm::Rrr(_) => solve_dyad(
            block,
            &mut st,
            0,
            1,
            [v[0], v[1]],
            (v[2], v[3]),
            (v[4], v[5]),
            sc,
            tolerance,
            report,
        ),
        ClosedForm::Rrp { .. } => solve_rrp(
            block,
            &mut st,
            0,
            1,
            [v[0], v[1]],
            (v[2], v[3]),
            [v[4], v[5]],
            sc,
            tolerance,
            report,
            true,
        ),
        ClosedForm::Rpr { .. } => solve_rpr(
            block,
            &mut st,
            0,
            1,
            [v[0], v[1]],
            (v[2], v[3]),
            (v[4], v[5]),
            sc,
            tolerance,
            report,
            true,
        ),
        ClosedForm::Linear2 { .. } => solve_linear2(
            block,
            &mut st,
            (0, 1),
            [v[0], v[1]],
            [v[2], v[3]],
            [v[4], v[5]],
            report,
        ),
        ClosedForm::Angle1 { .. } => solve_angle1(
            block,
            &mut st,
            0,
            v[0],
            (v[1], v[2]),
            sc,
            tolerance,
            report,
            true,
        ),
        ClosedForm::Length1 { .. } => solve_length1(block, &mut st, 0, v[0], v[1]),
    }
    .map_err(|e| match e {
        // The kernel's index is into the local state: report the mechanism's unknown.
        SolveError::NonFinite { quantity, index } => SolveError::NonFinite {
            quantity,
            index: idx[index.min(1)],
        },
        e => e,
    })?;
    for (slot, &k) in idx.iter().enumerate().take(n) {
        q[k] = st.q[slot];
    }
    Ok(())
}
