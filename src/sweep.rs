//! Sweeps of one input: continuation along the `start` configuration's branch with a tangent
//! predictor and adaptive substeps, then velocities, accelerations and points at every row. Works
//! on any [`Kinematics`] (generated or generic), written once.

use mechgen_runtime::error::SolveError;
use mechgen_runtime::mechanism::{Kind, Kinematics, MechanismInfo, PointMotion};
use mechgen_runtime::solve::NewtonOptions;

/// How the branch is followed between rows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Continuation {
    /// Largest substep: radians for an angle input, file units for a length input.
    pub max_step: f64,
    /// Give up on a row when the substep falls below this fraction of `max_step`.
    pub min_fraction: f64,
    pub newton: NewtonOptions<f64>,
}

impl Continuation {
    /// Defaults for an input of this kind: 2° substeps for an angle, 1/180 of `span` for a length.
    pub fn for_input(kind: Kind, span: f64) -> Self {
        let max_step = match kind {
            Kind::Angle => 2f64.to_radians(),
            Kind::Length => (span.abs() / 180.0).max(f64::MIN_POSITIVE),
        };
        Continuation {
            max_step,
            min_fraction: 1e-9,
            newton: NewtonOptions::default(),
        }
    }
}

/// One solved row.
#[derive(Clone, Debug, PartialEq)]
pub struct Solved {
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    pub qdd: Vec<f64>,
    pub points: Vec<PointMotion<f64>>,
    /// Condition estimate of the Jacobian at this row (1 / pivot ratio).
    pub condition: f64,
}

/// One row of a sweep: the input value (radians or file units) and its result.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub input: f64,
    pub result: Result<Solved, SolveError>,
    /// On a failed row, where the branch stopped; `None` on a solved row.
    pub stopped: Option<Stopped>,
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
}

impl Stopped {
    /// The branch ends at a dead point: its Jacobian is (nearly) singular where it stopped.
    pub fn at_dead_point(&self) -> bool {
        self.condition >= DEAD_POINT_CONDITION
    }
}

/// Follows the branch of the state `(x, q)` as the input `index` moves to `target`. On success
/// `x` and `q` hold the new state; on failure they keep the last state reached.
pub fn continue_to(
    k: &dyn Kinematics<f64>,
    x: &mut [f64],
    q: &mut [f64],
    index: usize,
    target: f64,
    c: &Continuation,
) -> Result<f64, SolveError> {
    let n = q.len();
    let mut h = c.max_step;
    let mut tangent = vec![0.0; n];
    let mut trial = vec![0.0; n];
    let mut xt = x.to_vec();
    let mut unit = vec![0.0; x.len()];
    unit[index] = 1.0;
    let mut last_err = None;
    let limit = predictor_limits(k, q);
    loop {
        let remaining = target - x[index];
        let dir = remaining.signum();
        let step = remaining.abs().min(h);
        // dq/dx along the branch, from J q' = −Φx e_index.
        let have_tangent = k.solve_velocity(x, q, &unit, &mut tangent).is_ok();
        xt.copy_from_slice(x);
        xt[index] = if remaining.abs() <= h {
            target
        } else {
            x[index] + dir * step
        };
        let dx = xt[index] - x[index];
        for i in 0..n {
            trial[i] = q[i] + if have_tangent { tangent[i] * dx } else { 0.0 };
        }
        let predicted = trial.clone();
        // Leaving a dead point the tangent is huge: a substep it would carry far is shortened
        // before Newton sees it (else angles land many turns away and lose their precision).
        let too_far = (0..n).any(|i| (predicted[i] - q[i]).abs() > limit[i]);
        let corrected = if too_far {
            None
        } else {
            Some(k.solve_position(&xt, &mut trial, &c.newton))
        };
        let accepted = match corrected {
            // Accept only a corrector that stayed near the prediction: no silent branch jump.
            Some(Ok(report)) if jump(&predicted, &trial, q) <= 0.25 => Some(report),
            // Already at the target: nothing smaller to try.
            Some(Err(e)) if dx == 0.0 => return Err(e),
            Some(Err(e)) => {
                last_err = Some(e);
                None
            }
            _ => None,
        };
        // Leaving a dead point the tangent overshoots (the branch bends like √δ): Newton from the
        // current state is accepted when it moved along the tangent and not beyond it.
        let accepted = accepted.or_else(|| {
            if too_far || !have_tangent || dx == 0.0 {
                return None;
            }
            trial.copy_from_slice(q);
            let report = k.solve_position(&xt, &mut trial, &c.newton).ok()?;
            leaves_along(&predicted, &trial, q).then_some(report)
        });
        match accepted {
            Some(report) => {
                q.copy_from_slice(&trial);
                x[index] = xt[index];
                if x[index] == target {
                    return Ok(report.condition());
                }
                h = (h * 2.0).min(c.max_step);
            }
            None => h *= 0.5,
        }
        if h < c.max_step * c.min_fraction {
            return Err(last_err.unwrap_or(SolveError::Unassemblable {
                block: 0,
                residual: f64::NAN,
                iterations: 0,
            }));
        }
    }
}

/// Largest change of an unknown a predictor substep may make: this many radians for an angle,
/// this fraction of the largest length unknown for a length.
const MAX_PREDICTED: f64 = 0.5;

/// Per unknown, the largest change a predictor substep may make (see [`MAX_PREDICTED`]).
fn predictor_limits(k: &dyn Kinematics<f64>, q: &[f64]) -> Vec<f64> {
    let kinds: Vec<Kind> = k.info().unknowns.iter().map(|u| u.1).collect();
    let length = q
        .iter()
        .zip(&kinds)
        .filter(|(_, kind)| **kind == Kind::Length)
        .fold(0.0f64, |m, (v, _)| m.max(v.abs()));
    kinds
        .iter()
        .map(|kind| match kind {
            Kind::Angle => MAX_PREDICTED,
            Kind::Length if length > 0.0 => MAX_PREDICTED * length,
            Kind::Length => f64::INFINITY,
        })
        .collect()
}

/// Whether the move from `before` to `corrected` goes the way of the tangent prediction (cosine
/// above 0.9) and not farther: true of a move away from a dead point along the branch (√δ is
/// concave), false of a jump to the other branch there (it goes backwards).
fn leaves_along(predicted: &[f64], corrected: &[f64], before: &[f64]) -> bool {
    let (mut dot, mut pp, mut cc) = (0.0, 0.0, 0.0);
    for i in 0..before.len() {
        let (p, c) = (predicted[i] - before[i], corrected[i] - before[i]);
        dot += p * c;
        pp += p * p;
        cc += c * c;
    }
    cc > 0.0 && cc <= pp && dot >= 0.9 * (pp * cc).sqrt()
}

/// How far the corrector moved from the prediction, relative to the substep's change of the state.
fn jump(predicted: &[f64], corrected: &[f64], before: &[f64]) -> f64 {
    let mut moved: f64 = 0.0;
    let mut scale: f64 = 1e-12;
    for i in 0..predicted.len() {
        moved = moved.max((corrected[i] - predicted[i]).abs());
        scale = scale
            .max((predicted[i] - before[i]).abs())
            .max((corrected[i] - before[i]).abs());
    }
    // Absolute floor: corrections of a converged Newton are tiny compared with a branch flip.
    if moved < 1e-9 * (1.0 + before.iter().fold(0.0f64, |m, v| m.max(v.abs()))) {
        0.0
    } else {
        moved / scale
    }
}

/// Sweeps input `index` over `values` (radians or file units) from the file's start configuration,
/// with input rate `rate` and zero input acceleration. Failed rows keep the sweep going from the
/// last state reached and record it in [`Row::stopped`]: a branch that ends at a dead point stays
/// there (the rows past it fail) instead of jumping to another branch.
pub fn sweep(
    k: &dyn Kinematics<f64>,
    index: usize,
    values: &[f64],
    rate: f64,
    c: &Continuation,
) -> Vec<Row> {
    let info: MechanismInfo = k.info();
    let mut x: Vec<f64> = info.inputs.iter().map(|i| i.2).collect();
    let mut q: Vec<f64> = info.unknowns.iter().map(|u| u.2).collect();
    let (ni, nu, np) = (x.len(), q.len(), info.points.len());
    let mut xd = vec![0.0; ni];
    if let Some(v) = xd.get_mut(index) {
        *v = rate;
    }
    let xdd = vec![0.0; ni];
    // Settle the start configuration itself first (the file's values may be rounded).
    let mut start_q = q.clone();
    if k.solve_position(&x, &mut start_q, &c.newton).is_ok() {
        // Angles as near the file's values as whole turns allow (a far-off start may have
        // converged turns away, where angles lose precision).
        for ((settled, &file), u) in start_q.iter_mut().zip(&q).zip(&info.unknowns) {
            if u.1 == Kind::Angle {
                let tau = std::f64::consts::TAU;
                let turn = (*settled - file).rem_euclid(tau);
                *settled = file
                    + if turn > std::f64::consts::PI {
                        turn - tau
                    } else {
                        turn
                    };
            }
        }
        q = start_q;
    }
    values
        .iter()
        .map(|&target| {
            let result = continue_to(k, &mut x, &mut q, index, target, c).and_then(|condition| {
                let mut qd = vec![0.0; nu];
                let mut qdd = vec![0.0; nu];
                let mut points = vec![PointMotion::default(); np];
                k.solve_velocity(&x, &q, &xd, &mut qd)?;
                k.solve_acceleration(&x, &q, &xd, &qd, &xdd, &mut qdd)?;
                k.points(&x, &q, &xd, &qd, &xdd, &qdd, &mut points)?;
                Ok(Solved {
                    q: q.clone(),
                    qd,
                    qdd,
                    points,
                    condition,
                })
            });
            let stopped = result.is_err().then(|| {
                // The state is a converged solution: one more solve gives its condition estimate.
                let mut settled = q.clone();
                let condition = k
                    .solve_position(&x, &mut settled, &c.newton)
                    .map_or(f64::INFINITY, |r| r.condition());
                Stopped {
                    input: x[index],
                    condition,
                }
            });
            Row {
                input: target,
                result,
                stopped,
            }
        })
        .collect()
}
