//! Sweeps, the rows (`mechgen::sweep::sweep`): settle the start, move held inputs to their values,
//! reach the row nearest the start, then one continuation and one rate solve per row each way. Part of
//! [`crate::sweep`].

use super::{
    Continuation, Row, Solved, Stop, StopReason, Stopped, check_start, continue_within,
    nearest_turn, sweep_budget,
};
use mechgen_runtime::error::SolveError;
use mechgen_runtime::{DynMechanism, InputMotion, Kind, MechanismInfo, PointMotion};

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
    sweep_each(k, index, values, rate, held, c, &mut |r| rows.push(r));
    rows
}

/// Rows solved below the start row between two checkpoints of the continuation's state: the
/// rows below the start row are solved downward but handed out upward, a segment at a time.
pub const SEGMENT: usize = 4096;

/// The sweep of [`sweep_holding`], handing each row to `emit` in the order of `values` as soon as
/// it can, so that memory does not grow with the number of rows: the held inputs are moved to
/// their values, then the sweep continues from the start to the row nearest it ([`nearest_row`];
/// an angle input's start, swept or held, is first moved by whole turns to the representative
/// nearest that value), from that row through the rows before it (down to the first value) and,
/// again from that row, through the rows after it. The rows before it are solved downward twice:
/// once keeping the continuation's state every [`SEGMENT`] rows, then segment by segment from
/// those states (the same steps, so the same numbers), each segment handed out upward.
///
/// Failed rows keep the sweep going from the last state reached and record it in
/// [`Row::stopped`]: a branch that ends at a dead point stays there (the rows past it fail)
/// instead of jumping to another branch. Every continuation is bounded, and the whole sweep uses
/// at most [`sweep_budget`]`(values.len())` substeps (three solves each) and four more solves per
/// row: once they are used up, the remaining rows get `substep-limit` without any work.
pub fn sweep_each(
    k: &dyn DynMechanism<f64>,
    index: usize,
    values: &[f64],
    rate: f64,
    held: &[(usize, f64)],
    c: &Continuation,
    emit: &mut dyn FnMut(Row),
) {
    let info: MechanismInfo = k.info();
    let mut x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
    let mut q: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
    let (ni, nu, np) = (x.len(), q.len(), info.points.len());
    let mut fail_all = |error: SolveError, stopped: Stopped| {
        for &input in values {
            emit(Row {
                input,
                result: Err(error),
                stopped: Some(stopped),
            });
        }
    };
    if index >= ni {
        let error = SolveError::BadLength {
            expected: ni,
            got: index,
        };
        return fail_all(error, stopped(0.0, f64::INFINITY, StopReason::Solver));
    }
    if check_start(&info).is_err() {
        let error = SolveError::NonFinite {
            quantity: mechgen_runtime::error::Quantity::Input,
            index,
        };
        return fail_all(
            error,
            stopped(x[index], f64::INFINITY, StopReason::UnusableStart),
        );
    }
    let mut xd = vec![0.0; ni];
    xd[index] = rate;
    let xdd = vec![0.0; ni];
    settle_start(k, &info, &x, &mut q, c);
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
            return fail_all(
                stop.error,
                stopped(x[index], condition, StopReason::HeldInput),
            );
        }
    }
    let Some(nearest) = nearest_row(info.inputs[index].kind, x[index], values) else {
        return;
    };
    if info.inputs[index].kind == Kind::Angle {
        x[index] = nearest_turn(x[index], values[nearest]);
    }
    // One row: the continuation to it, then its rates and points.
    let solve_row = |s: &mut State, target: f64| {
        let State { x, q, allowance } = s;
        let mut reason = StopReason::Solver;
        let result = continue_within(k, x, q, index, target, c, allowance)
            .map_err(|Stop { error, reason: r }| {
                reason = r;
                error
            })
            .and_then(|condition| {
                let mut qd = vec![0.0; nu];
                let mut qdd = vec![0.0; nu];
                let mut points = vec![PointMotion::default(); np];
                k.solve_velocity(x, q, &xd, &mut qd)?;
                k.solve_acceleration(x, q, &xd, &qd, &xdd, &mut qdd)?;
                let input = InputMotion::new(&x[..], &xd[..], &xdd[..]);
                k.points(input, q, &qd, &qdd, &mut points)?;
                Ok(Solved {
                    q: q.to_vec(),
                    qd,
                    qdd,
                    points,
                    condition,
                })
            });
        // The state is a converged solution: one more solve gives its condition estimate.
        let stopped = result
            .is_err()
            .then(|| stopped(x[index], condition_at(k, x, q, c), reason));
        Row {
            input: target,
            result,
            stopped,
        }
    };
    let mut state = State { x, q, allowance };
    let first = solve_row(&mut state, values[nearest]);
    let at_first = state.clone();
    // Down to the first value: the continuation alone (it is all that moves the state), keeping
    // the state at the top of every segment.
    let mut checkpoints = Vec::new();
    for i in (0..nearest).rev() {
        if (nearest - 1 - i) % SEGMENT == 0 {
            checkpoints.push((i, state.clone()));
        }
        let State { x, q, allowance } = &mut state;
        let _ = continue_within(k, x, q, index, values[i], c, allowance);
    }
    let after_down = state.allowance;
    // Then each segment again from its checkpoint, with rates and points, handed out upward.
    let mut segment = Vec::with_capacity(SEGMENT.min(nearest));
    for (top, mut s) in checkpoints.into_iter().rev() {
        let bottom = (top + 1).saturating_sub(SEGMENT);
        segment.extend((bottom..=top).rev().map(|i| solve_row(&mut s, values[i])));
        segment.drain(..).rev().for_each(&mut *emit);
    }
    emit(first);
    // Up from the start row, with what the rows below left of the budget.
    let mut state = State {
        allowance: after_down,
        ..at_first
    };
    for &target in &values[nearest + 1..] {
        emit(solve_row(&mut state, target));
    }
}

/// The continuation's state between rows: inputs, unknowns and the substeps left.
#[derive(Clone)]
struct State {
    x: Vec<f64>,
    q: Vec<f64>,
    allowance: usize,
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
    }
}

/// Condition estimate at a converged state (infinite when the solve fails there).
fn condition_at(k: &dyn DynMechanism<f64>, x: &[f64], q: &[f64], c: &Continuation) -> f64 {
    let mut settled = q.to_vec();
    k.solve_position(x, &mut settled, &c.options)
        .map_or(f64::INFINITY, |r| r.condition())
}

/// Settles the start configuration itself (the file's values may be rounded), with angles as
/// near the file's values as whole turns allow (a far-off start may have converged turns away,
/// where angles lose precision). Leaves `q` as it is when the solve fails.
fn settle_start(
    k: &dyn DynMechanism<f64>,
    info: &MechanismInfo,
    x: &[f64],
    q: &mut [f64],
    c: &Continuation,
) {
    let mut start_q = q.to_vec();
    if k.solve_position(x, &mut start_q, &c.options).is_ok() {
        for ((settled, file), u) in start_q.iter_mut().zip(q.iter()).zip(&info.unknowns) {
            if u.kind == Kind::Angle {
                *settled = nearest_turn(*settled, *file);
            }
        }
        q.copy_from_slice(&start_q);
    }
}
