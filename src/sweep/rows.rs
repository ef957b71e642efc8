//! Sweeps, the rows (`mechgen::sweep::sweep`): settle the start, move held inputs to their values,
//! reach the row nearest the start, then walk row by row each way (`walker.rs`), the rows below
//! the start kept to be handed out in input order. Part of [`crate::sweep`].

use super::store::RowStore;
use super::walker::Walker;
use super::{
    Assembles, Continuation, Row, RowRef, StopReason, Stopped, check_start, continue_within,
    nearest_turn, sweep_budget,
};
use mechgen_runtime::error::SolveError;
use mechgen_runtime::{DynMechanism, Kind, MechanismInfo};

/// Sweeps input `index` over `values` (radians or file units) from the file's start configuration,
/// with input rate `rate` and zero input acceleration; the other inputs stay at their start
/// values. See [`sweep_each`].
pub fn sweep(
    k: &dyn DynMechanism<f64>,
    index: usize,
    values: &[f64],
    rate: f64,
    c: &Continuation,
) -> Vec<Row> {
    sweep_holding(k, index, values, rate, &[], c)
}

/// Sweeps input `index` over `values` from the file's start configuration, first moving each
/// input of `held` (index, value) from its start value to that value along the branch: the rows
/// of [`sweep_each`], collected.
pub fn sweep_holding(
    k: &dyn DynMechanism<f64>,
    index: usize,
    values: &[f64],
    rate: f64,
    held: &[(usize, f64)],
    c: &Continuation,
) -> Vec<Row> {
    let mut rows = Vec::with_capacity(values.len());
    sweep_each(k, index, values, rate, held, c, &mut |r| {
        rows.push(r.to_row())
    });
    rows
}

/// Rows solved below the start row between two checkpoints of the walk: the rows below the start
/// row are solved downward but handed out upward, a segment at a time.
pub const SEGMENT: usize = 4096;

/// The sweep of [`sweep_holding`], handing each row to `emit` in the order of `values` as soon as
/// it can, so that memory does not grow with the number of rows, and allocating nothing per row
/// (the rows are borrowed from the sweep's workspace): the held inputs are moved to their values,
/// then the sweep continues from the start to the row nearest it ([`nearest_row`]; an angle
/// input's start, swept or held, is first moved by whole turns to the representative nearest that
/// value), from that row through the rows before it (down to the first value) and, again from
/// that row, through the rows after it. From row to row the engine's own tick carries the state
/// (see `walker.rs`). The rows before the start row are solved downward and kept, up to
/// [`SEGMENT`] of them; below that, the walk keeps its state every [`SEGMENT`] rows and solves
/// each segment again from there, handing it out upward.
///
/// Failed rows keep the sweep going from the last state reached and record it in
/// [`Row::stopped`]: a branch that ends at a dead point stays there (the rows past it fail, with
/// no solve) instead of jumping to another branch. Every continuation is bounded, and the whole
/// sweep uses at most [`sweep_budget`]`(values.len())` substeps (three solves each) and four more
/// solves per row: once they are used up, the remaining rows get `substep-limit`.
pub fn sweep_each(
    k: &dyn DynMechanism<f64>,
    index: usize,
    values: &[f64],
    rate: f64,
    held: &[(usize, f64)],
    c: &Continuation,
    emit: &mut dyn FnMut(RowRef<'_>),
) {
    sweep_each_with(k, index, values, rate, held, c, None, emit);
}

/// [`sweep_each`] told whether the linkage assembles at given inputs (all of them, the held
/// ones at their values; e.g. by the branch analysis, [`crate::branches::Setup::assembles`]): a
/// row past the dead point that ended the followed branch is then `other-branch` where it does
/// and `unassemblable` where it does not ([`Stopped::assembles`]). Asked only for such rows.
#[allow(clippy::too_many_arguments)]
pub fn sweep_each_with(
    k: &dyn DynMechanism<f64>,
    index: usize,
    values: &[f64],
    rate: f64,
    held: &[(usize, f64)],
    c: &Continuation,
    assembles: Option<Assembles<'_>>,
    emit: &mut dyn FnMut(RowRef<'_>),
) {
    let mut ordered = |_: usize, row: RowRef<'_>| emit(row);
    sweep_rows(
        k,
        index,
        values,
        rate,
        held,
        c,
        assembles,
        (&mut ordered, true),
    );
}

/// [`sweep_each_with`] handing each row to `emit` with its index in `values` as soon as it is
/// solved, in the order the walk solves them (the start row, the rows below it downward, then the
/// rows above it upward) rather than in the order of `values`: the same rows, bit for bit, with
/// no row kept or solved again to be handed out in order. For a consumer that puts each row in its
/// place (the Python package's columns).
#[allow(clippy::too_many_arguments)]
pub fn sweep_each_indexed(
    k: &dyn DynMechanism<f64>,
    index: usize,
    values: &[f64],
    rate: f64,
    held: &[(usize, f64)],
    c: &Continuation,
    assembles: Option<Assembles<'_>>,
    emit: &mut dyn FnMut(usize, RowRef<'_>),
) {
    let mut emit = |i: usize, row: RowRef<'_>| emit(i, row);
    sweep_rows(
        k,
        index,
        values,
        rate,
        held,
        c,
        assembles,
        (&mut emit, false),
    );
}

/// The walk of both: rows to `emit.0` with their index, in the order of `values` when `emit.1`.
/// Generic in the sink, so that a caller's wrapper is no second dynamic call per row.
#[allow(clippy::too_many_arguments)]
fn sweep_rows<F: for<'r> FnMut(usize, RowRef<'r>)>(
    k: &dyn DynMechanism<f64>,
    index: usize,
    values: &[f64],
    rate: f64,
    held: &[(usize, f64)],
    c: &Continuation,
    assembles: Option<Assembles<'_>>,
    (emit, ordered): (&mut F, bool),
) {
    let info = k.info_ref();
    let Some(mut first) = walk_to_first(
        k,
        &info,
        index,
        values,
        rate,
        held,
        c,
        assembles,
        (&mut *emit, ordered),
        true,
    ) else {
        return;
    };
    // Up from the start row, with what the rows below left of the budget.
    let w = &mut first.walker;
    w.resume(&first.at_first);
    w.allowance = first.after_down;
    // The tick started afresh every SEGMENT rows, as below the start row (see there).
    for (s, segment) in values[first.nearest + 1..].chunks(SEGMENT).enumerate() {
        if s > 0 {
            w.renew();
        }
        let at = first.nearest + 1 + s * SEGMENT;
        w.run(segment, &mut |d, row| emit(at + d, row));
    }
}

/// Where a walk hands its rows: each with its index in the sweep's values, in their order when
/// the flag is set (else as solved).
pub(super) type RowSink<'e> = (&'e mut dyn for<'r> FnMut(usize, RowRef<'r>), bool);

/// A sweep's walk at its start row, the rows below it and the start row handed out: the walker,
/// where it stood at the start row, the budget the rows below left, and the start row's index.
pub(super) struct First<'k> {
    pub walker: Walker<'k>,
    pub at_first: super::walker::Mark,
    pub after_down: usize,
    pub nearest: usize,
    /// Whether the start row solved.
    pub solved: bool,
}

/// The first part of [`sweep_each_with`]: the start settled, the held inputs moved, the start
/// row reached, the rows below it solved (when `down`; else the walk stops at the start row) and
/// every row up to the start row handed to `emit.0` with its index (in the order of `values` when
/// `emit.1`, else as solved: the start row, then downward). `None` when nothing is left to walk
/// (every row already handed out failed, or no rows).
#[allow(clippy::too_many_arguments)]
pub(super) fn walk_to_first<'k>(
    k: &'k dyn DynMechanism<f64>,
    info: &MechanismInfo,
    index: usize,
    values: &[f64],
    rate: f64,
    held: &[(usize, f64)],
    c: &'k Continuation,
    assembles: Option<Assembles<'k>>,
    (emit, ordered): RowSink<'_>,
    down: bool,
) -> Option<First<'k>> {
    let mut x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
    let mut q: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
    let ni = x.len();
    let mut fail_all = |error: SolveError, stopped: Stopped| {
        for (i, &input) in values.iter().enumerate() {
            emit(
                i,
                Row {
                    input,
                    result: Err(error),
                    stopped: Some(stopped),
                },
            );
        }
    };
    if index >= ni {
        let error = SolveError::BadLength {
            expected: ni,
            got: index,
        };
        {
            fail_all(error, stopped(0.0, f64::INFINITY, StopReason::Solver));
            return None;
        }
    }
    if check_start(info).is_err() {
        let error = SolveError::NonFinite {
            quantity: mechgen_runtime::error::Quantity::Input,
            index,
        };
        {
            fail_all(
                error,
                stopped(x[index], f64::INFINITY, StopReason::UnusableStart),
            );
            return None;
        }
    }
    if !rate.is_finite() {
        let error = SolveError::NonFinite {
            quantity: mechgen_runtime::error::Quantity::InputRate,
            index,
        };
        {
            fail_all(error, stopped(x[index], f64::INFINITY, StopReason::Solver));
            return None;
        }
    }
    let settled = settle_start(k, info, &x, &mut q, c);
    let mut allowance = sweep_budget(values.len());
    // Held inputs first, each along the branch from its start value to its value.
    for &(i, value) in held.iter().filter(|h| h.0 < ni && h.0 != index) {
        let kind = info.inputs[i].kind;
        if kind == Kind::Angle {
            x[i] = nearest_turn(x[i], value);
        }
        let held_c = Continuation {
            options: c.options,
            min_fraction: c.min_fraction,
            ..Continuation::for_input(kind, value - x[i])
        };
        if let Err(stop) = continue_within(k, &mut x, &mut q, i, value, &held_c, &mut allowance) {
            let condition = condition_at(k, &x, &q, c);
            {
                fail_all(
                    stop.error,
                    stopped(x[index], condition, StopReason::HeldInput),
                );
                return None;
            }
        }
    }
    let nearest = nearest_row(info.inputs[index].kind, x[index], values)?;
    if info.inputs[index].kind == Kind::Angle {
        x[index] = nearest_turn(x[index], values[nearest]);
    }
    let x_start = x[index];
    let mut w = match Walker::new(k, info, index, rate, c, (x, q, allowance), assembles) {
        Ok(w) => w,
        Err(error) => {
            fail_all(error, stopped(0.0, f64::INFINITY, StopReason::Solver));
            return None;
        }
    };
    // A start row at the settled start itself needs no continuation: the tick starts there.
    let first =
        (settled && x_start == values[nearest] && w.start_here()) || w.solve(values[nearest]);
    let at_first = w.mark();
    // In order, the start row is handed out after the rows below it; as solved, now.
    let mut first_row = RowStore::new(info, usize::from(ordered));
    if ordered {
        first_row.push(&mut w, values[nearest], first);
    } else {
        emit(nearest, w.row(values[nearest], first));
    }
    if !down {
        first_row.emit_reversed(nearest, emit);
        return Some(First {
            after_down: w.allowance,
            walker: w,
            at_first,
            nearest,
            solved: first,
        });
    }
    // Down to the first value: rows kept a segment at a time (handed out as solved when not in
    // order), the walk's state kept at the top of every segment. The tick starts afresh there
    // (and every SEGMENT rows up from the start row), so that a segment solved again from its
    // checkpoint, or the same rows in a sweep that starts at the start row, have exactly these
    // numbers.
    let mut store = RowStore::new(info, if ordered { nearest.min(SEGMENT) } else { 0 });
    let mut checkpoints = Vec::new();
    // The values below the start row in the order walked (row `nearest - 1 - d` is `down[d]`).
    let down: Vec<f64> = values[..nearest].iter().rev().copied().collect();
    for (s, segment) in down.chunks(SEGMENT).enumerate() {
        let top = nearest - 1 - s * SEGMENT;
        let mark = w.mark();
        w.resume(&mark);
        if ordered {
            checkpoints.push((top, mark));
            store.clear();
            w.run(segment, &mut |_, row| store.push_row(&row));
        } else {
            w.run(segment, &mut |d, row| emit(top - d, row));
        }
    }
    let after_down = w.allowance;
    // The lowest segment is in the store; each segment above it is solved again from its
    // checkpoint. Each is handed out upward.
    if ordered {
        store.emit_reversed(0, emit);
        checkpoints.pop();
        for (top, mark) in checkpoints.into_iter().rev() {
            let bottom = (top + 1).saturating_sub(SEGMENT);
            w.resume(&mark);
            store.clear();
            w.run(&down[nearest - 1 - top..nearest - bottom], &mut |_, row| {
                store.push_row(&row)
            });
            store.emit_reversed(bottom, emit);
        }
        first_row.emit_reversed(nearest, emit);
    }
    Some(First {
        walker: w,
        at_first,
        after_down,
        nearest,
        solved: first,
    })
}

/// The index of the row a sweep reaches first: the value nearest the start input `x0` (for an
/// angle input, nearest modulo a turn); the first of equally near values. `None` for no values.
pub fn nearest_row(kind: Kind, x0: f64, values: &[f64]) -> Option<usize> {
    let distance = |v: f64| match kind {
        Kind::Angle => (nearest_turn(x0, v) - v).abs(),
        _ => (x0 - v).abs(),
    };
    let mut best: Option<(usize, f64)> = None;
    for (i, &v) in values.iter().enumerate() {
        let d = distance(v);
        // A row at the start itself: none after it is nearer (the first of equally near wins).
        if d == 0.0 {
            return Some(i);
        }
        // A NaN distance (non-finite value) is never nearer than a finite one.
        if best.is_none_or(|(_, b)| d < b || (b.is_nan() && !d.is_nan())) {
            best = Some((i, d));
        }
    }
    best.map(|(i, _)| i)
}

fn stopped(input: f64, condition: f64, reason: StopReason) -> Stopped {
    Stopped {
        input,
        condition,
        reason,
        assembles: None,
    }
}

/// Condition estimate at a converged state (infinite when the solve fails there).
fn condition_at(k: &dyn DynMechanism<f64>, x: &[f64], q: &[f64], c: &Continuation) -> f64 {
    super::condition::Conditioner::new(q.len()).at(k, x, q, c)
}

/// Settles the start configuration itself (the file's values may be rounded), with angles as
/// near the file's values as whole turns allow (a far-off start may have converged turns away,
/// where angles lose precision). Leaves `q` as it is when the solve fails; whether it solved.
fn settle_start(
    k: &dyn DynMechanism<f64>,
    info: &MechanismInfo,
    x: &[f64],
    q: &mut [f64],
    c: &Continuation,
) -> bool {
    let mut start_q = q.to_vec();
    let solved = k.solve_position(x, &mut start_q, &c.options).is_ok();
    if solved {
        for ((settled, file), u) in start_q.iter_mut().zip(q.iter()).zip(&info.unknowns) {
            if u.kind == Kind::Angle {
                *settled = nearest_turn(*settled, *file);
            }
        }
        q.copy_from_slice(&start_q);
    }
    solved
}
