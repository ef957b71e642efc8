//! Generic engine, closed forms: a block that mechgen-codegen's `closed_form` stage classified is
//! solved by the runtime's `ClosedKind::solve` from its roots, which a tape evaluates at the
//! current state; the same kernels the generated code calls.

use mechgen_codegen::ClosedForm;

use super::tape::Tape;
use mechgen_runtime::error::SolveError;
use mechgen_runtime::scalar::Real;
use mechgen_runtime::solve::{NewtonReport, TrigState};

/// A closed-form block: its kind and the tape of its roots (in the kind's order).
#[derive(Clone, Debug)]
pub(super) struct ClosedTape {
    pub form: ClosedForm,
    pub roots: Tape,
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
    let (kind, idx) = (form.kind(), form.slots());
    let mut st = TrigState::new([q[idx[0]], q[idx[1]]], kind.angles());
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
        q[k] = st.q[slot];
    }
    Ok(())
}
