//! Sweeps, one row at a time (`Walker`): the engine's own tick ([`DynTick`]: a generated
//! mechanism's `Tick`, predictor and cached sines and cosines included) carries the state from row
//! to row in substeps of at most the continuation's largest step, each checked against its
//! prediction (no branch jump); a substep the tick cannot take hands the row to the adaptive
//! continuation ([`Follower`]), and a branch that ended at a dead point fails the rows beyond it
//! without solving. Runs of rows that the tick takes in one substep each go through the engine's
//! own `DynTick::walk` (`walker/run.rs`: no dynamic call between rows); a crossing is walked
//! through in `walker/cross.rs`. Nothing is read from the description or allocated per row. Part
//! of [`crate::sweep`].

mod cross;
mod run;

use super::condition::Conditioner;
use super::continuation::largest_substep;
use super::crossing::Between;
use super::route::Route;
use super::{Assembles, Continuation, Follower, Row, RowRef, SolvedRef, Stop, StopReason, Stopped};
use mechgen_runtime::error::SolveError;
use mechgen_runtime::{
    DynMechanism, DynTick, InputMotion, MechanismInfo, PointMotion, Stride, Substep,
};

/// A row's outcome: solved (the tick holds it), or its error and where the branch stopped.
pub(super) type Outcome = Result<(), (SolveError, Stopped)>;

/// Condition estimate of a ticked row's position solve from which the walker checks whether the
/// row lies on a crossing (rows that close to a dead point have it too, and keep their tick's
/// state: the branch does not go on past a dead point).
const CROSSING_CONDITION: f64 = 1e6;

/// Condition estimate of a ticked row's position solve from which the row is solved afresh at
/// its input (a whole solve from the ticked positions, caches recomputed). Regular rows of the
/// compiled-in mechanisms are below 1e2 (and keep the tick's state, so that the sweep runs at a
/// tick's cost).
pub(super) const RESOLVE_CONDITION: f64 = 30.0;

/// The state of a sweep between rows and the workspace that moves it.
pub(super) struct Walker<'k> {
    k: &'k dyn DynMechanism<f64>,
    c: &'k Continuation,
    ticker: Box<dyn DynTick<f64> + 'k>,
    follower: Follower,
    index: usize,
    /// The inputs of the last state reached on the branch, and (when `synced`, or the tick is
    /// not started) its unknowns and their rates; else those are the tick's.
    x: Vec<f64>,
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    synced: bool,
    /// Whether the tick has a state (its last start succeeded).
    started: bool,
    /// Substeps left of the sweep's budget.
    pub(super) allowance: usize,
    /// Where the branch ended at a dead point and the direction of travel there (±1): rows
    /// beyond it fail with this error without any solve.
    dead: Option<(SolveError, Stopped, f64)>,
    /// The input rates of the ticks (the sweep's rate on the swept input, or 1 for a rate of 0)
    /// and accelerations (zero).
    xd: Vec<f64>,
    xdd: Vec<f64>,
    /// The rows' rate is zero: their rates are these zeros, their points these (positions only).
    at_rest: Option<(Vec<f64>, Vec<PointMotion<f64>>)>,
    h_max: f64,
    /// The condition estimate where the walk stops.
    conditioner: Conditioner,
    /// What [`Walker::failure`] reports.
    failure: (SolveError, Stopped),
    /// Asked, for a row past a dead point, whether the linkage assembles there; with the inputs
    /// it is asked at.
    assembles: Option<Assembles<'k>>,
    probe: Vec<f64>,
    /// The swept input's value at the start of the walk.
    origin: f64,
    /// The last row lay on a crossing: its state is `between` (interpolated along the branch),
    /// the walk stands past the crossing.
    at_crossing: bool,
    between: Between,
    /// The walk's inputs and unknowns before its last continuation (or, for a ticked row that
    /// lies on a crossing, before its last substep).
    from_x: Vec<f64>,
    from_q: Vec<f64>,
    /// The swept input before the last substep a tick took.
    before_x: f64,
}

/// Where a walk stands, to walk again from there later (a checkpoint).
#[derive(Clone)]
pub(super) struct Mark {
    x: Vec<f64>,
    q: Vec<f64>,
    allowance: usize,
    dead: Option<(SolveError, Stopped, f64)>,
}

impl Mark {
    /// The inputs and unknowns of the walk at the mark; `None` when the walk had met a dead point
    /// there (it goes on only back the way it came).
    pub(super) fn state(&self) -> Option<(&[f64], &[f64])> {
        self.dead.is_none().then_some((&self.x[..], &self.q[..]))
    }
}

/// What a walk that goes on in SIMD lanes reads of its scalar walk (`lanes.rs`).
#[derive(Clone, Copy)]
pub(super) struct LaneWalk<'w> {
    pub xd: &'w [f64],
    pub xdd: &'w [f64],
    pub h_max: f64,
    pub guard: &'w mechgen_runtime::guard::BranchGuard,
}

impl<'k> Walker<'k> {
    /// The input rates, the largest substep and the branch rule of this walk, for a walk on in
    /// lanes; `None` for a walk at rest (rate 0), whose rows the lanes do not produce.
    pub(super) fn lane_walk(&self) -> Option<LaneWalk<'_>> {
        self.at_rest.is_none().then(|| LaneWalk {
            xd: &self.xd,
            xdd: &self.xdd,
            h_max: self.h_max,
            guard: self.follower.guard(),
        })
    }

    /// A walk of input `index` from `(x, q)` at input rate `rate` (finite).
    pub(super) fn new(
        k: &'k dyn DynMechanism<f64>,
        info: &MechanismInfo,
        index: usize,
        rate: f64,
        c: &'k Continuation,
        (x, q, allowance): (Vec<f64>, Vec<f64>, usize),
        assembles: Option<Assembles<'k>>,
    ) -> Result<Walker<'k>, SolveError> {
        let follower = Follower::new(info, index, x.len())?;
        let origin = x.get(index).copied().unwrap_or(f64::NAN);
        let (ni, nu) = (x.len(), q.len());
        let mut xd = vec![0.0; ni];
        xd[index] = if rate == 0.0 { 1.0 } else { rate };
        let at_rest = (rate == 0.0).then(|| {
            (
                vec![0.0; nu],
                vec![PointMotion::default(); info.points.len()],
            )
        });
        let h_max = largest_substep(c, info.inputs[index].kind, follower.scale());
        Ok(Walker {
            k,
            c,
            ticker: k.ticker(),
            follower,
            index,
            x,
            q,
            qd: vec![0.0; nu],
            qdd: vec![0.0; nu],
            synced: true,
            started: false,
            allowance,
            dead: None,
            xd,
            xdd: vec![0.0; ni],
            at_rest,
            h_max,
            conditioner: Conditioner::new(nu),
            failure: (
                SolveError::NotStarted,
                Stopped {
                    input: 0.0,
                    condition: f64::INFINITY,
                    reason: StopReason::Solver,
                    assembles: None,
                },
            ),
            probe: vec![0.0; ni],
            assembles,
            origin,
            at_crossing: false,
            between: Between::default(),
            from_x: vec![0.0; ni],
            from_q: vec![0.0; nu],
            before_x: f64::NAN,
        })
    }

    /// Where the walk stands now.
    pub(super) fn mark(&mut self) -> Mark {
        self.sync();
        Mark {
            x: self.x.clone(),
            q: self.q.clone(),
            allowance: self.allowance,
            dead: self.dead,
        }
    }

    /// Walks on from `mark`, the tick started afresh there: what the walk does from a mark is
    /// the same whenever it is done.
    pub(super) fn resume(&mut self, mark: &Mark) {
        self.x.copy_from_slice(&mark.x);
        self.q.copy_from_slice(&mark.q);
        self.synced = true;
        self.allowance = mark.allowance;
        self.dead = mark.dead;
        let _ = self.restart();
    }

    /// The tick started afresh where the walk stands (as [`Walker::resume`] from a mark made
    /// now).
    pub(super) fn renew(&mut self) {
        let _ = self.restart();
    }

    /// The walk's unknowns and rates made the tick's (after ticks that did not copy them).
    fn sync(&mut self) {
        if self.started
            && !self.synced
            && let Some(s) = self.ticker.state()
        {
            self.q.copy_from_slice(s.q);
            self.qd.copy_from_slice(s.qd);
            self.qdd.copy_from_slice(s.qdd);
        }
        self.synced = true;
    }

    /// The tick started afresh at the walk's state (not started when that fails to solve).
    fn restart(&mut self) -> Result<(), SolveError> {
        self.sync();
        let input = InputMotion::new(&self.x[..], &self.xd[..], &self.xdd[..]);
        self.started = false;
        self.ticker.start(input, &self.q, &self.c.options)?;
        self.started = self.ticker.state().is_some();
        self.synced = false;
        self.sync();
        Ok(())
    }

    /// The row at input `target`: the branch followed to it, then its rates and points. False
    /// when it fails ([`Walker::failure`] says how).
    pub(super) fn solve(&mut self, target: f64) -> bool {
        self.at_crossing = false;
        let outcome = self.solve_row(target);
        self.conclude(target, outcome)
    }

    /// The row at `input` (`solved`: what [`Walker::solve`] returned for it), borrowed from the
    /// walk.
    pub(super) fn row(&mut self, input: f64, solved: bool) -> RowRef<'_> {
        if !solved {
            let (error, at) = self.failure();
            return Row {
                input,
                result: Err(error),
                stopped: Some(at),
            };
        }
        match self.solved() {
            Some(s) => Row {
                input,
                result: Ok(s),
                stopped: None,
            },
            None => Row {
                input,
                result: Err(SolveError::NotStarted),
                stopped: Some(Stopped {
                    input,
                    condition: f64::INFINITY,
                    reason: StopReason::Solver,
                    assembles: None,
                }),
            },
        }
    }

    /// The last failed row's error and where the branch stopped.
    pub(super) fn failure(&self) -> (SolveError, Stopped) {
        self.failure
    }

    fn solve_row(&mut self, target: f64) -> Outcome {
        if let Some((error, stopped, direction)) = self.dead {
            if (target - stopped.input) * direction > 0.0 {
                return Err((error, stopped));
            }
            self.dead = None;
        }
        if self.started
            && let Some(condition) = self.tick_to(target)
        {
            return self.ticked(target, condition);
        }
        self.continue_to(target)
    }

    /// The row at `target` ticked to, its last substep's position solve of condition estimate
    /// `condition`: solved afresh near a singular point, along the branch on a crossing (a
    /// ticked row always stands: at a dead point, the ticked one).
    fn ticked(&mut self, target: f64, condition: f64) -> Outcome {
        if condition >= RESOLVE_CONDITION {
            // The walk's state before the row's last substep (the tick left its unknowns in
            // `q`), should the row lie on a crossing.
            self.from_x.copy_from_slice(&self.x);
            self.from_x[self.index] = self.before_x;
            self.from_q.copy_from_slice(&self.q);
            // Near a singular point the tick's rotated sines and cosines and its predictor cost
            // digits of the rates (1e-9 relative at 1° from a crossing): the row solved afresh
            // there, from the ticked positions.
            self.sync();
            let _ = self.restart();
        }
        // A tick that landed on a crossing solves its positions only to about √ε (the two
        // assembly modes meet there): the row along the branch instead.
        let singular = condition >= CROSSING_CONDITION;
        if singular && self.before_x != target {
            self.sync();
            let (x, q) = (self.x.clone(), self.q.clone());
            if !self.cross(target) {
                // A dead point (no branch past it): the ticked row stands.
                (self.x, self.q) = (x, q);
                self.synced = true;
                let _ = self.restart();
            }
        }
        Ok(())
    }

    /// The row where the walk stands, its state solved already (the settled start): the tick
    /// started there, with no continuation. False (nothing changed but the tick, not started)
    /// when the tick does not start; [`Walker::solve`] then solves the row.
    pub(super) fn start_here(&mut self) -> bool {
        self.at_crossing = false;
        self.restart().is_ok() && self.started
    }

    /// The solved row's numbers (the tick's state; rates and point rates zero for a walk at
    /// rest) and the condition estimate of its position solve.
    #[inline]
    pub(super) fn solved(&mut self) -> Option<SolvedRef<'_>> {
        if self.at_crossing {
            let b = &self.between;
            return Some(match &mut self.at_rest {
                None => SolvedRef {
                    q: &b.q,
                    qd: &b.qd,
                    qdd: &b.qdd,
                    points: &b.points,
                    condition: f64::INFINITY,
                },
                Some((zeros, points)) => {
                    for (p, t) in points.iter_mut().zip(&b.points) {
                        p.position = t.position;
                    }
                    SolvedRef {
                        q: &b.q,
                        qd: zeros,
                        qdd: zeros,
                        points,
                        condition: f64::INFINITY,
                    }
                }
            });
        }
        let s = self.ticker.state()?;
        let condition = s.report.condition();
        Some(match &mut self.at_rest {
            None => SolvedRef {
                q: s.q,
                qd: s.qd,
                qdd: s.qdd,
                points: s.points,
                condition,
            },
            Some((zeros, points)) => {
                for (p, t) in points.iter_mut().zip(s.points) {
                    p.position = t.position;
                }
                SolvedRef {
                    q: s.q,
                    qd: zeros,
                    qdd: zeros,
                    points,
                    condition,
                }
            }
        })
    }

    /// The tick to `target` in equal substeps of at most the largest substep, each accepted when
    /// its solution moved no unknown too far and stayed near its prediction: the condition
    /// estimate of the last one's position solve. `None` when one is
    /// not taken (the walk then stands at the last substep taken, the tick started there).
    fn tick_to(&mut self, target: f64) -> Option<f64> {
        let i = self.index;
        let route = Route::new(self.x[i], target, self.h_max)?;
        let mut condition = 0.0;
        for j in 1..=route.len() {
            let xt = route.end(j);
            let mut stride = Stride {
                x: &mut self.x,
                xd: &self.xd,
                xdd: &self.xdd,
                index: i,
                before: &mut self.q,
                guard: self.follower.guard(),
                allowance: &mut self.allowance,
            };
            let step = stride.substep(&mut *self.ticker, xt, &self.c.options);
            condition = self.take(step)?;
        }
        Some(condition)
    }

    /// What a substep came to, taken into the walk: the condition estimate of a kept one; `None`
    /// when it was not taken (refused by the branch rule: the tick started again where the walk
    /// stood; failed, or no budget left).
    fn take(&mut self, step: Substep<f64>) -> Option<f64> {
        match step {
            Substep::Kept { condition, from } => {
                self.before_x = from;
                self.synced = false;
                Some(condition)
            }
            Substep::Refused => {
                // The tick left the branch (or moved too far): start again where it stood.
                self.synced = true;
                let _ = self.restart();
                None
            }
            Substep::Failed | Substep::Spent => None,
        }
    }

    /// The adaptive continuation to `target` from the walk's state, then the tick started there;
    /// on failure the walk stands where the branch stopped.
    fn continue_to(&mut self, target: f64) -> Outcome {
        self.sync();
        let i = self.index;
        // Where the walk stood (on the branch), should it meet a crossing on the way.
        self.from_x.copy_from_slice(&self.x);
        self.from_q.copy_from_slice(&self.q);
        let result = self.follower.continue_within(
            self.k,
            &mut self.x,
            &mut self.q,
            target,
            self.c,
            &mut self.allowance,
        );
        let stop = match result {
            Ok(_) => match self.restart() {
                Ok(()) => return Ok(()),
                Err(error) => Stop {
                    error,
                    reason: StopReason::Solver,
                },
            },
            Err(stop) => {
                let _ = self.restart();
                stop
            }
        };
        let stopped = Stopped {
            input: self.x[i],
            condition: self.condition_here(),
            reason: stop.reason,
            assembles: None,
        };
        // A singular point on the way (the position solve's condition, or a singular rate
        // solve where the positions solved): the branch may go on past it.
        let singular = stopped.at_dead_point() || matches!(stop.error, SolveError::Singular { .. });
        if singular && self.cross(target) {
            return Ok(());
        }
        if stopped.at_dead_point() {
            self.dead = Some((stop.error, stopped, (target - stopped.input).signum()));
        }
        Err((stop.error, stopped))
    }

    /// Condition estimate at the walk's (converged) state; infinite when the solve fails there.
    fn condition_here(&mut self) -> f64 {
        self.sync();
        self.conditioner.at(self.k, &self.x, &self.q, self.c)
    }
}
