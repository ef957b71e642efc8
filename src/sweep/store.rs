//! Rows kept to be handed out later ([`RowStore`]): a sweep solves the rows below its start row
//! downward and hands them out upward, a segment at a time. Part of [`crate::sweep`].

use super::walker::Walker;
use super::{Row, RowRef, Solved, StopReason, Stopped};
use mechgen_runtime::error::SolveError;
use mechgen_runtime::{MechanismInfo, PointMotion};

/// A kept row's outcome: its condition estimate, or its error and where the branch stopped.
type Kept = Result<f64, (SolveError, Stopped)>;

/// Rows kept to be handed out later (the rows below the start row, in the order solved): their
/// numbers in one buffer, allocated once.
pub(super) struct RowStore {
    /// Each row's input, and its condition estimate or its error and stop.
    rows: Vec<(f64, Kept)>,
    numbers: Vec<f64>,
    points: Vec<PointMotion<f64>>,
    nu: usize,
    np: usize,
}

impl RowStore {
    pub(super) fn new(info: &MechanismInfo, rows: usize) -> RowStore {
        let (nu, np) = (info.unknowns.len(), info.points.len());
        RowStore {
            rows: Vec::with_capacity(rows),
            numbers: Vec::with_capacity(rows * 3 * nu),
            points: Vec::with_capacity(rows * np),
            nu,
            np,
        }
    }

    pub(super) fn clear(&mut self) {
        self.rows.clear();
        self.numbers.clear();
        self.points.clear();
    }

    /// The row at `input` with `outcome` (its numbers read from the walk).
    pub(super) fn push(&mut self, w: &mut Walker<'_>, input: f64, solved: bool) {
        self.push_row(&w.row(input, solved));
    }

    /// A row, its numbers copied.
    pub(super) fn push_row(&mut self, row: &RowRef<'_>) {
        let input = row.input;
        let outcome = match &row.result {
            Ok(s) => {
                self.numbers.extend_from_slice(s.q);
                self.numbers.extend_from_slice(s.qd);
                self.numbers.extend_from_slice(s.qdd);
                self.points.extend_from_slice(s.points);
                Ok(s.condition)
            }
            Err(e) => Err((
                *e,
                row.stopped.unwrap_or(Stopped {
                    input,
                    condition: f64::INFINITY,
                    reason: StopReason::Solver,
                    assembles: None,
                }),
            )),
        };
        self.rows.push((input, outcome));
    }

    /// The rows kept, last kept first, the first of them row `bottom` of the sweep.
    pub(super) fn emit_reversed(&self, bottom: usize, emit: &mut dyn FnMut(usize, RowRef<'_>)) {
        let (nu, np) = (self.nu, self.np);
        let (mut n_end, mut p_end) = (self.numbers.len(), self.points.len());
        for (at, &(input, outcome)) in self.rows.iter().rev().enumerate() {
            emit(
                bottom + at,
                match outcome {
                    Ok(condition) => {
                        let (n0, p0) = (n_end - 3 * nu, p_end - np);
                        let v = &self.numbers[n0..n_end];
                        let row = Row {
                            input,
                            result: Ok(Solved {
                                q: &v[..nu],
                                qd: &v[nu..2 * nu],
                                qdd: &v[2 * nu..],
                                points: &self.points[p0..p_end],
                                condition,
                            }),
                            stopped: None,
                        };
                        (n_end, p_end) = (n0, p0);
                        row
                    }
                    Err((error, at)) => Row {
                        input,
                        result: Err(error),
                        stopped: Some(at),
                    },
                },
            );
        }
    }
}
