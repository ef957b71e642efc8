//! Runs of a walk's rows ([`Walker::run`]): each run that the tick takes row after row in one
//! substep each by the engine's own [`mechgen_runtime::DynTick::walk`], any other row as
//! [`Walker::solve`] solves it. Part of `walker.rs`.

use mechgen_runtime::error::SolveError;
use mechgen_runtime::{StateRef, Stride};

use super::{Outcome, RESOLVE_CONDITION, Walker};
use crate::sweep::{Row, RowRef, SolvedRef};

impl Walker<'_> {
    /// Rows at each of `targets` in turn, each handed to `emit` with its index in `targets`
    /// (the rows of [`Walker::solve`] then [`Walker::row`] at each): runs of rows that the tick
    /// takes in one substep each, kept to the branch and regular, by the engine's own
    /// [`mechgen_runtime::DynTick::walk`] (no dynamic call between them); any other row as
    /// `solve` solves it, from what its substep came to.
    pub(in crate::sweep) fn run<F: FnMut(usize, RowRef<'_>)>(
        &mut self,
        targets: &[f64],
        emit: &mut F,
    ) {
        let mut j = 0;
        while j < targets.len() {
            let mut step = None;
            if self.started && self.dead.is_none() && self.at_rest.is_none() {
                self.at_crossing = false;
                let mut stride = Stride {
                    x: &mut self.x,
                    xd: &self.xd,
                    xdd: &self.xdd,
                    index: self.index,
                    before: &mut self.q,
                    guard: self.follower.guard(),
                    allowance: &mut self.allowance,
                };
                let mut rows = |k: usize, s: StateRef<'_, f64>| {
                    let solved = SolvedRef {
                        q: s.q,
                        qd: s.qd,
                        qdd: s.qdd,
                        points: s.points,
                        condition: s.report.condition(),
                    };
                    let input = targets[j + k];
                    emit(
                        j + k,
                        Row {
                            input,
                            result: Ok(solved),
                            stopped: None,
                        },
                    );
                };
                let (n, last) = self.ticker.walk(
                    &mut stride,
                    &targets[j..],
                    self.h_max,
                    RESOLVE_CONDITION,
                    &self.c.options,
                    &mut rows,
                );
                if n > 0 {
                    self.synced = false;
                }
                j += n;
                step = last;
            }
            let Some(&target) = targets.get(j) else {
                break;
            };
            let solved = match step {
                Some(step) => {
                    self.at_crossing = false;
                    let outcome = match self.take(step) {
                        Some(condition) => self.ticked(target, condition),
                        None => self.continue_to(target),
                    };
                    self.conclude(target, outcome)
                }
                None => self.solve(target),
            };
            emit(j, self.row(target, solved));
            j += 1;
        }
    }

    /// A row's outcome made [`Walker::solve`]'s answer: whether it solved; if not, the failure
    /// kept for [`Walker::failure`] (with, past a dead point, whether the linkage assembles
    /// there).
    pub(super) fn conclude(&mut self, target: f64, outcome: Outcome) -> bool {
        match outcome {
            Ok(()) => true,
            Err((error, mut stopped)) => {
                // A branch that ended at a dead point after it left the start (not a start that
                // does not assemble, not a non-finite value).
                if let Some(assembles) = self.assembles
                    && stopped.at_dead_point()
                    && stopped.input != self.origin
                    && matches!(
                        error,
                        SolveError::Unassemblable { .. } | SolveError::Singular { .. }
                    )
                {
                    self.probe.copy_from_slice(&self.x);
                    self.probe[self.index] = target;
                    stopped.assembles = assembles(&self.probe);
                }
                self.failure = (error, stopped);
                false
            }
        }
    }
}
