//! Sweeps, the continuation step (`mechgen::sweep::continue_to`): follows a branch from one input
//! value to another by tangent predictor and Newton corrector in adaptive substeps, within a
//! bounded number of substeps. Part of [`crate::sweep`].

use super::Continuation;
use mechgen_runtime::error::SolveError;
use mechgen_runtime::guard::{BranchGuard, MAX_JUMP};
use mechgen_runtime::{DynMechanism, Kind, MechanismInfo};

/// Substeps one continuation may always try (halvings near a dead point included).
pub const BASE_SUBSTEPS: usize = 1000;

/// Extra substeps per largest substep of the distance to go.
pub const SUBSTEPS_PER_STEP: usize = 8;

/// Longest distance one continuation covers, in largest substeps (2000 × 2° is about 11 turns of
/// an angle input; 2000 × span/180 is about 11 spans of a length input). A row farther than this
/// from the state before it gets [`StopReason::SubstepLimit`].
pub const MAX_ROUTE: usize = 2000;

/// The most substeps any one continuation tries: [`BASE_SUBSTEPS`] + [`SUBSTEPS_PER_STEP`] ×
/// [`MAX_ROUTE`]. Each substep makes at most three solves (tangent, corrector, fallback).
pub const MAX_SUBSTEPS: usize = BASE_SUBSTEPS + SUBSTEPS_PER_STEP * MAX_ROUTE;

/// Why a continuation (or a row) stopped short of its input value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// A solve failed at the smallest substep (the row's error is that solve's).
    Solver,
    /// Every substep near the stop was refused: the predictor would have moved an unknown too far,
    /// or the corrector jumped away from the prediction (the branch turns back or is left).
    Refused,
    /// [`MAX_SUBSTEPS`] (or the distance's share of it) were used up before the value was reached.
    SubstepLimit,
    /// The start configuration's inputs are not usable (see [`super::check_start`]).
    UnusableStart,
    /// A held input (`--set`) could not be moved from its start value to its set value.
    HeldInput,
}

/// A continuation that stopped: the error for the row and why.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stop {
    pub error: SolveError,
    pub reason: StopReason,
}

/// The mechanism's length scale: the largest |length param| (or 1 when it has none), the same
/// scale the solvers' relative tolerances use.
pub fn length_scale(info: &MechanismInfo) -> f64 {
    let s = info
        .params
        .iter()
        .filter(|p| p.kind == Kind::Length && p.value.is_finite())
        .fold(0.0f64, |m, p| m.max(p.value.abs()));
    if s > 0.0 { s } else { 1.0 }
}

/// The largest substep actually used for input `kind`: `c.max_step`, but for a length input at
/// least 1/180 of the length scale (a span of zero or a tiny span would otherwise need endless
/// substeps), and 2° for an angle input whose `max_step` is not a positive number.
pub fn largest_substep(c: &Continuation, kind: Kind, scale: f64) -> f64 {
    let given = if c.max_step.is_finite() && c.max_step > 0.0 {
        c.max_step
    } else {
        0.0
    };
    match kind {
        Kind::Angle if given > 0.0 => given,
        Kind::Angle => 2f64.to_radians(),
        _ => given.max(scale / 180.0),
    }
}

/// How many substeps a continuation over `distance` may try with largest substep `h_max`.
pub fn substep_budget(distance: f64, h_max: f64) -> usize {
    let route = (distance / h_max).ceil();
    let route = if route.is_finite() {
        route.min(MAX_ROUTE as f64) as usize
    } else {
        MAX_ROUTE
    };
    BASE_SUBSTEPS + SUBSTEPS_PER_STEP * route
}

/// Follows the branch of the state `(x, q)` as the input `index` moves to `target`. On success
/// `x` and `q` hold the new state and the condition estimate there is returned; on failure they
/// keep the last state reached. At most [`substep_budget`] substeps, so it always ends.
pub fn continue_branch(
    k: &dyn DynMechanism<f64>,
    x: &mut [f64],
    q: &mut [f64],
    index: usize,
    target: f64,
    c: &Continuation,
) -> Result<f64, Stop> {
    let mut unlimited = usize::MAX;
    continue_within(k, x, q, index, target, c, &mut unlimited)
}

/// [`continue_branch`] with at most `allowance` substeps (a sweep's remaining budget), which it
/// decreases by the substeps it used.
pub fn continue_within(
    k: &dyn DynMechanism<f64>,
    x: &mut [f64],
    q: &mut [f64],
    index: usize,
    target: f64,
    c: &Continuation,
    allowance: &mut usize,
) -> Result<f64, Stop> {
    let info = k.info_ref();
    match Follower::new(&info, index, x.len()) {
        Ok(mut f) => f.continue_within(k, x, q, target, c, allowance),
        Err(error) => Err(Stop {
            error,
            reason: StopReason::Solver,
        }),
    }
}

/// The continuation of one input of one mechanism with its workspace: what it reads of the
/// mechanism's description (read once), and the vectors each substep fills (allocated once), so
/// that a sweep continues row after row without reading the description or allocating.
pub struct Follower {
    index: usize,
    kind: Kind,
    guard: BranchGuard,
    scale: f64,
    tangent: Vec<f64>,
    trial: Vec<f64>,
    predicted: Vec<f64>,
    xt: Vec<f64>,
    unit: Vec<f64>,
}

impl Follower {
    /// For input `index` of the mechanism `info` describes, with `ni` inputs given (`BadLength`
    /// when `index` is not one of them).
    pub fn new(info: &MechanismInfo, index: usize, ni: usize) -> Result<Follower, SolveError> {
        let kind = match info.inputs.get(index) {
            Some(input) if index < ni => input.kind,
            _ => {
                return Err(SolveError::BadLength {
                    expected: info.inputs.len(),
                    got: index,
                });
            }
        };
        let n = info.unknowns.len();
        let mut unit = vec![0.0; ni];
        unit[index] = 1.0;
        Ok(Follower {
            index,
            kind,
            guard: BranchGuard::new(info, length_scale(info)),
            scale: length_scale(info),
            tangent: vec![0.0; n],
            trial: vec![0.0; n],
            predicted: vec![0.0; n],
            xt: vec![0.0; ni],
            unit,
        })
    }

    /// The mechanism's length scale ([`length_scale`]).
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// [`continue_within`] with this workspace.
    pub fn continue_within(
        &mut self,
        k: &dyn DynMechanism<f64>,
        x: &mut [f64],
        q: &mut [f64],
        target: f64,
        c: &Continuation,
        allowance: &mut usize,
    ) -> Result<f64, Stop> {
        let mut used = 0;
        let result = self.follow(k, x, q, target, c, *allowance, &mut used);
        *allowance = allowance.saturating_sub(used);
        result
    }

    /// The branch rule this continuation checks its substeps with (and a sweep its ticks).
    pub fn guard(&self) -> &BranchGuard {
        &self.guard
    }

    /// The continuation itself, at most `allowance` substeps, counted in `used`.
    #[allow(clippy::too_many_arguments)]
    fn follow(
        &mut self,
        k: &dyn DynMechanism<f64>,
        x: &mut [f64],
        q: &mut [f64],
        target: f64,
        c: &Continuation,
        allowance: usize,
        used: &mut usize,
    ) -> Result<f64, Stop> {
        let solver = |error| Stop {
            error,
            reason: StopReason::Solver,
        };
        let index = self.index;
        let n = self.trial.len();
        if x.len() != self.xt.len() || q.len() != n {
            return Err(solver(SolveError::BadLength {
                expected: n,
                got: q.len(),
            }));
        }
        if !target.is_finite() || !x[index].is_finite() {
            return Err(solver(SolveError::NonFinite {
                quantity: mechgen_runtime::error::Quantity::Input,
                index,
            }));
        }
        let h_max = largest_substep(c, self.kind, self.scale);
        let min_fraction = if c.min_fraction > 0.0 && c.min_fraction <= 1.0 {
            c.min_fraction.max(1e-15)
        } else {
            1e-9
        };
        let budget = substep_budget((target - x[index]).abs(), h_max).min(allowance);
        let mut h = h_max;
        let mut last_err = None;
        let refused = |last_err: Option<SolveError>| match last_err {
            Some(error) => solver(error),
            None => Stop {
                error: SolveError::Unassemblable {
                    block: 0,
                    residual: f64::INFINITY,
                    iterations: 0,
                },
                reason: StopReason::Refused,
            },
        };
        for _ in 0..budget {
            *used += 1;
            let remaining = target - x[index];
            // dq/dx along the branch, from J q' = −Φx e_index.
            let have_tangent = k
                .solve_velocity(x, q, &self.unit, &mut self.tangent)
                .is_ok();
            self.xt.copy_from_slice(x);
            self.xt[index] = if remaining.abs() <= h {
                target
            } else {
                x[index] + remaining.signum() * h
            };
            let dx = self.xt[index] - x[index];
            if dx == 0.0 && remaining != 0.0 {
                // The substep is below the input's resolution here: nothing smaller to try.
                return Err(refused(last_err));
            }
            for ((t, q), d) in self.trial.iter_mut().zip(&*q).zip(&self.tangent) {
                *t = q + if have_tangent { d * dx } else { 0.0 };
            }
            self.predicted.copy_from_slice(&self.trial);
            // Leaving a dead point the tangent is huge: a substep it would carry far is shortened
            // before Newton sees it (else angles land many turns away and lose their precision).
            let too_far = self.guard.too_far(q, &self.predicted);
            let corrected = if too_far {
                None
            } else {
                Some(k.solve_position(&self.xt, &mut self.trial, &c.options))
            };
            let accepted = match corrected {
                // Accept only a corrector that stayed near the prediction: no silent branch jump.
                Some(Ok(report))
                    if BranchGuard::jump(&self.predicted, &self.trial, q) <= MAX_JUMP =>
                {
                    Some(report)
                }
                // Already at the target: nothing smaller to try.
                Some(Err(e)) if dx == 0.0 => return Err(solver(e)),
                Some(Err(e)) => {
                    last_err = Some(e);
                    None
                }
                _ => None,
            };
            // Leaving a dead point the tangent overshoots (the branch bends like √δ): Newton from
            // the current state is accepted when it moved along the tangent and not beyond it.
            let accepted = accepted.or_else(|| {
                if too_far || !have_tangent || dx == 0.0 {
                    return None;
                }
                self.trial.copy_from_slice(q);
                let report = k
                    .solve_position(&self.xt, &mut self.trial, &c.options)
                    .ok()?;
                leaves_along(&self.predicted, &self.trial, q).then_some(report)
            });
            match accepted {
                Some(report) => {
                    q.copy_from_slice(&self.trial);
                    x[index] = self.xt[index];
                    if x[index] == target {
                        return Ok(report.condition());
                    }
                    h = (h * 2.0).min(h_max);
                }
                None => h *= 0.5,
            }
            if h < h_max * min_fraction {
                return Err(refused(last_err));
            }
        }
        Err(Stop {
            error: SolveError::NoConvergence {
                block: 0,
                residual: ((target - x[index]) / h_max).abs().min(f64::MAX),
                step: h,
                iterations: u32::try_from(budget).unwrap_or(u32::MAX),
            },
            reason: StopReason::SubstepLimit,
        })
    }
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
