//! Sweeps of one input: continuation along the `start` configuration's branch ([`continuation`]),
//! other inputs held at set values, then velocities, accelerations and points at every row.
//! Works on any [`DynMechanism`] (generated or generic), written once; the CLI and reports sit on it.

pub mod continuation;
mod lanes;
pub mod plan;
pub mod scene;

pub use continuation::{
    Follower, MAX_ROUTE, MAX_SUBSTEPS, Stop, StopReason, continue_branch, continue_within,
    length_scale, substep_budget,
};

use mechgen_runtime::error::SolveError;
use mechgen_runtime::solve::SolveOptions;
use mechgen_runtime::{CoordDesc, DynMechanism, Kind, MechanismInfo, PointMotion};

/// How the branch is followed between rows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Continuation {
    /// Largest substep: radians for an angle input, file units for a length input (there at
    /// least 1/180 of the mechanism's length scale, see [`continuation::largest_substep`]).
    pub max_step: f64,
    /// Give up on a row when the substep falls below this fraction of `max_step`.
    pub min_fraction: f64,
    /// The position solves of every substep and row.
    pub options: SolveOptions<f64>,
}

impl Continuation {
    /// Defaults for an input of this kind: 2° substeps for an angle, 1/180 of `span` for a length.
    pub fn for_input(kind: Kind, span: f64) -> Self {
        let max_step = match kind {
            Kind::Angle => 2f64.to_radians(),
            _ => (span.abs() / 180.0).max(f64::MIN_POSITIVE),
        };
        Continuation {
            max_step,
            min_fraction: 1e-9,
            options: SolveOptions::default(),
        }
    }
}

/// One solved row: the unknowns, their rates, every point's motion and the condition estimate.
/// Owned (`Solved`, vectors) or borrowed from the sweep's workspace ([`SolvedRef`], slices: what
/// [`sweep_each`] hands out without allocating).
#[derive(Clone, Debug, PartialEq)]
pub struct Solved<V = Vec<f64>, P = Vec<PointMotion<f64>>> {
    pub q: V,
    pub qd: V,
    pub qdd: V,
    pub points: P,
    /// Condition estimate of the Jacobian at this row (1 / pivot ratio).
    pub condition: f64,
}

/// A solved row borrowed from the sweep that solved it.
pub type SolvedRef<'a> = Solved<&'a [f64], &'a [PointMotion<f64>]>;

/// One row of a sweep: the input value (radians or file units) and its result.
#[derive(Clone, Debug, PartialEq)]
pub struct Row<S = Solved> {
    pub input: f64,
    pub result: Result<S, SolveError>,
    /// On a failed row, where the branch stopped; `None` on a solved row.
    pub stopped: Option<Stopped>,
}

/// A row borrowed from the sweep that solved it ([`sweep_each`] hands these out).
pub type RowRef<'a> = Row<SolvedRef<'a>>;

impl Row {
    /// This row, borrowed.
    pub fn view(&self) -> RowRef<'_> {
        Row {
            input: self.input,
            result: self
                .result
                .as_ref()
                .map(|s| Solved {
                    q: &s.q[..],
                    qd: &s.qd[..],
                    qdd: &s.qdd[..],
                    points: &s.points[..],
                    condition: s.condition,
                })
                .map_err(|e| *e),
            stopped: self.stopped,
        }
    }
}

impl Row {
    /// `r` written into this row, reusing its vectors where it has them.
    pub fn assign(&mut self, r: &RowRef<'_>) {
        self.input = r.input;
        self.stopped = r.stopped;
        match (&mut self.result, &r.result) {
            (Ok(d), Ok(s)) => {
                let refill = |d: &mut Vec<f64>, s: &[f64]| {
                    d.clear();
                    d.extend_from_slice(s);
                };
                refill(&mut d.q, s.q);
                refill(&mut d.qd, s.qd);
                refill(&mut d.qdd, s.qdd);
                d.points.clear();
                d.points.extend_from_slice(s.points);
                d.condition = s.condition;
            }
            (_, Ok(_)) => *self = r.to_row(),
            (_, Err(e)) => self.result = Err(*e),
        }
    }
}

impl RowRef<'_> {
    /// This row, owned.
    pub fn to_row(&self) -> Row {
        Row {
            input: self.input,
            result: self
                .result
                .as_ref()
                .map(|s| Solved {
                    q: s.q.to_vec(),
                    qd: s.qd.to_vec(),
                    qdd: s.qdd.to_vec(),
                    points: s.points.to_vec(),
                    condition: s.condition,
                })
                .map_err(|e| *e),
            stopped: self.stopped,
        }
    }
}

impl<S> Row<S> {
    /// Where the branch stopped at a dead point, for a failed row whose branch ends at one (not
    /// for an overflow, whose condition estimate is infinite too).
    pub fn dead_point(&self) -> Option<Stopped> {
        match self.result {
            Err(SolveError::Overflow { .. }) => None,
            _ => self.stopped.filter(Stopped::at_dead_point),
        }
    }

    /// The CSV status: `ok`, the solver error's status, or `substep-limit` (the continuation used
    /// up its substeps before reaching the row) or `unusable-start`; past the dead point that
    /// ended the branch, where the sweep could tell, `other-branch` (the linkage assembles at the
    /// row's input, on another branch) or `unassemblable` (it does not).
    pub fn status(&self) -> &'static str {
        if self.result.is_err()
            && let Some(s) = self.dead_point()
            && let Some(assembles) = s.assembles
        {
            return if assembles {
                "other-branch"
            } else {
                "unassemblable"
            };
        }
        match (&self.result, self.stopped.map(|s| s.reason)) {
            (Ok(_), _) => "ok",
            (Err(_), Some(StopReason::SubstepLimit)) => "substep-limit",
            (Err(_), Some(StopReason::UnusableStart)) => "unusable-start",
            (Err(e), _) => e.status(),
        }
    }
}

/// Condition estimate above which a branch that cannot be continued is reported as ending at a
/// dead point. Regular configurations of the compiled-in mechanisms are below 1e2; continuation
/// stops within about 1e-10 of a dead point, where the estimate is above 1e4.
pub const DEAD_POINT_CONDITION: f64 = 1e3;

/// Where a continuation that could not reach a row stopped: the last state on the branch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stopped {
    /// The last input value reached (radians or file units).
    pub input: f64,
    /// Condition estimate of the Jacobian there (infinite when it could not be evaluated).
    pub condition: f64,
    /// Why it stopped there.
    pub reason: StopReason,
    /// For a row past the dead point that ended its branch: whether the linkage assembles at the
    /// row's input all the same (on another branch), where the sweep was given a way to tell
    /// ([`sweep_each_with`]); `None` where it was not.
    pub assembles: Option<bool>,
}

impl Stopped {
    /// The branch ends at a dead point: its Jacobian is (nearly) singular where it stopped, and
    /// the continuation did not merely run out of substeps.
    pub fn at_dead_point(&self) -> bool {
        self.condition >= DEAD_POINT_CONDITION
            && matches!(self.reason, StopReason::Solver | StopReason::Refused)
    }
}

/// Follows the branch of the state `(x, q)` as the input `index` moves to `target`. On success
/// `x` and `q` hold the new state; on failure they keep the last state reached. Always ends
/// ([`continue_branch`] says why it stopped).
pub fn continue_to(
    k: &dyn DynMechanism<f64>,
    x: &mut [f64],
    q: &mut [f64],
    index: usize,
    target: f64,
    c: &Continuation,
) -> Result<f64, SolveError> {
    continue_branch(k, x, q, index, target, c).map_err(|s| s.error)
}

/// Largest |start value| of an angle input: a thousand turns (f64 still resolves 1e-12 rad there).
pub const MAX_START_ANGLE: f64 = 1000.0 * std::f64::consts::TAU;

/// Largest |start value| of a length input, relative to the mechanism's length scale.
pub const MAX_START_LENGTH: f64 = 1e6;

/// A start configuration that cannot start a sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct StartError {
    /// The input's name and its start value (radians or file units).
    pub input: String,
    pub value: f64,
    /// The largest usable magnitude.
    pub limit: f64,
}

impl std::fmt::Display for StartError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the start value of input `{}` ({:e}) is not usable to start a sweep: its magnitude must be at most {:e} (a thousand turns for an angle, a million times the largest length param for a length)",
            self.input, self.value, self.limit
        )
    }
}

impl std::error::Error for StartError {}

/// Whether the file's start inputs can start a continuation: finite and within
/// [`MAX_START_ANGLE`] (angles) or [`MAX_START_LENGTH`] × the length scale (lengths).
pub fn check_start(info: &MechanismInfo) -> Result<(), StartError> {
    let scale = length_scale(info);
    for CoordDesc {
        name,
        kind,
        start: value,
    } in &info.inputs
    {
        let limit = match kind {
            Kind::Angle => MAX_START_ANGLE,
            _ => MAX_START_LENGTH * scale,
        };
        if value.is_nan() || value.abs() > limit {
            return Err(StartError {
                input: name.clone(),
                value: *value,
                limit,
            });
        }
    }
    Ok(())
}

/// `x0` moved by whole turns to the representative nearest `toward` (the same configuration).
pub fn nearest_turn(x0: f64, toward: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let apart = toward - x0;
    // Under half a turn apart (whatever the rounding of the quotient below): no turn to add.
    if apart.abs() < 0.49 * tau {
        return x0;
    }
    let turns = round_turns(apart / tau);
    if turns.is_finite() && turns != 0.0 {
        x0 + turns * tau
    } else {
        x0
    }
}

/// `y` rounded half away from zero as `f64::round` (a zero's sign aside), which baseline x86-64
/// makes a library call: a sweep's nearest row asks this of every row.
fn round_turns(y: f64) -> f64 {
    // From 2^52 on (and for a NaN or an infinity) `y` is its own rounding.
    if y.is_nan() || y.abs() >= 4_503_599_627_370_496.0 {
        return y;
    }
    // Truncation toward zero, exact below 2^52, and the fraction it leaves (exact too).
    let t = (y as i64) as f64;
    let fraction = y - t;
    if fraction >= 0.5 {
        t + 1.0
    } else if fraction <= -0.5 {
        t - 1.0
    } else {
        t
    }
}

/// Substeps a sweep may use per row, on top of [`SWEEP_RESERVE`]: a whole sweep stops trying
/// (its remaining rows get `substep-limit`) past [`sweep_budget`] substeps in all.
pub const SUBSTEPS_PER_ROW: usize = 64;

/// Substeps every sweep may use whatever its number of rows: four full continuations.
pub const SWEEP_RESERVE: usize = 4 * MAX_SUBSTEPS;

/// The most substeps a sweep of `rows` rows uses in all (held inputs and every row together).
/// Each substep makes at most three solves, each row four more (rates, points, condition).
pub fn sweep_budget(rows: usize) -> usize {
    rows.saturating_mul(SUBSTEPS_PER_ROW)
        .saturating_add(SWEEP_RESERVE)
}

mod condition;
mod crossing;
mod route;
mod rows;
mod store;
mod walker;
mod width;

pub use lanes::{LANES, MIN_LANES, sweep_sets_in_lanes};
pub use rows::{
    SEGMENT, nearest_row, sweep, sweep_each, sweep_each_indexed, sweep_each_with, sweep_holding,
};
pub use width::{LANES_VAR, lane_width, lane_width_for};

/// Whether the linkage assembles at the inputs given (every input, in sweep units); `None` where
/// it cannot tell (the row then keeps its solver error's status).
pub type Assembles<'a> = &'a dyn Fn(&[f64]) -> Option<bool>;

#[cfg(test)]
mod tests {
    use super::round_turns;

    /// The quick rounding is `f64::round` (zeros equal whatever their sign): halves, their
    /// neighbours, both signs, near and past 2^52, non-finite values.
    #[test]
    fn turns_round_as_f64_round() {
        let mut ys = vec![f64::INFINITY, f64::NEG_INFINITY, 4_503_599_627_370_496.0];
        for k in -40..=40 {
            let half = f64::from(k) + 0.5;
            ys.extend([half, half.next_up(), half.next_down(), f64::from(k) * 0.37]);
        }
        for e in 40..70 {
            let big = 2f64.powi(e);
            ys.extend([
                big - 0.5,
                big + 0.5,
                big.next_down(),
                -big.next_up(),
                -(big + 1.5),
            ]);
        }
        for y in ys {
            assert_eq!(round_turns(y), y.round(), "{y:e}");
        }
        assert!(round_turns(f64::NAN).is_nan());
    }
}
