//! Generic engine, closed forms: a block that mechgen-codegen's `closed_form` stage classified is
//! solved by the runtime's `ClosedKind::solve` from its roots, which a tape evaluates at the
//! current state; the same kernels the generated code calls.

use mechgen_codegen::ClosedForm;

use super::tape::Tape;
use mechgen_runtime::error::SolveError;
use mechgen_runtime::scalar::Real;
use mechgen_runtime::solve::{NewtonReport, TrigState};
use mechgen_runtime::trig::TrigSlices;

/// A closed-form block: its kind and the tape of its roots (in the kind's order).
#[derive(Clone, Debug)]
pub(super) struct ClosedTape {
    pub form: ClosedForm,
    pub roots: Tape,
}

/// Solves block `block` in closed form: `v` are its roots at the current state, `st` holds the
/// guess (which picks the assembly mode) and receives the block's unknowns (and their sines and
/// cosines, as the kernel sets them) on success.
pub(super) fn solve<T: Real>(
    block: usize,
    form: &ClosedForm,
    v: &[T],
    q: &mut TrigSlices<'_, T>,
    scale: T,
    tolerance: T,
    report: &mut NewtonReport<T>,
) -> Result<(), SolveError> {
    let (kind, idx) = (form.kind(), form.slots());
    let (a, b) = (idx[0], idx[1]);
    let mut st = TrigState::from_parts([q.q[a], q.q[b]], [q.sc[a], q.sc[b]], kind.angles());
    kind.solve(block, &mut st, [0, 1], v, scale, tolerance, report)
        .map_err(|e| match e {
            // The kernel's index is into the local state: report the mechanism's unknown.
            SolveError::NonFinite { quantity, index } => SolveError::NonFinite {
                quantity,
                index: idx[index.min(1)],
            },
            e => e,
        })?;
    for (slot, &k) in idx.iter().enumerate().take(kind.unknowns()) {
        q.q[k] = st.q[slot];
        q.sc[k] = st.sc[slot];
    }
    Ok(())
}
