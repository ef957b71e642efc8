//! Generic engine, a tick's program interpreted: the steps of `program.rs` in order, each run of
//! instructions into one register file shared by every stage, each call step through the same
//! [`TickStages`] the JIT's compiled program calls back into. The interpreter's tick and the
//! JIT's walk the one plan; neither sequences blocks of its own.

use mechgen_runtime::InputMotion;
use mechgen_runtime::error::{Quantity, SolveError};
use mechgen_runtime::scalar::Real;
use mechgen_runtime::solve::{NewtonReport, SolveOptions, check_finite};
use mechgen_runtime::trig::TrigSlices;

use super::engine::{Generic, ProgramParams};
use super::op::eval_range;
use super::program::{Program, Step};
use super::scratch::Scratch;
use super::stages::TickStages;
use super::tape::Env;

/// A whole motion by `g`'s program (with closed forms on; `None` otherwise or without one):
/// compiled where the JIT compiled it for `T`, else walked. From the guess in `ws.trial` (its
/// sines and cosines in `ws.trial_sc`, the inputs' in `sx`, or computed where empty); on success
/// as [`run`] leaves them.
pub(super) fn motion<T: Real>(
    g: &Generic,
    input: InputMotion<&[T]>,
    sx: &[(T, T)],
    options: &SolveOptions<T>,
    ws: &mut Scratch<T>,
    [qd, qdd]: [&mut [T]; 2],
) -> Option<Result<NewtonReport<T>, SolveError>> {
    let program = g.program.as_ref().filter(|_| options.closed_forms)?;
    let p = g.program_params.as_ref()?;
    #[cfg(feature = "jit")]
    if let Some(done) = compiled(g, input, sx, options, ws, [&mut *qd, &mut *qdd]) {
        return Some(done);
    }
    Some(run(g, program, p, input, sx, options, ws, [qd, qdd]))
}

/// [`motion`] by the compiled program, in the workspace (`None`: not compiled for `T`).
#[cfg(feature = "jit")]
fn compiled<T: Real>(
    g: &Generic,
    input: InputMotion<&[T]>,
    sx: &[(T, T)],
    options: &SolveOptions<T>,
    ws: &mut Scratch<T>,
    [qd, qdd]: [&mut [T]; 2],
) -> Option<Result<NewtonReport<T>, SolveError>> {
    let ws = (ws as &mut dyn std::any::Any).downcast_mut::<Scratch<f64>>()?;
    ws.points.resize(6 * g.info.points.len(), 0.0);
    let (input, options) = super::stages::in_f64(input, options)?;
    let sx = T::pairs_as_f64s(sx)?;
    let at = super::stages::Solving {
        q: &mut ws.trial,
        sc: &mut ws.trial_sc,
        qd: T::as_f64s_mut(qd)?,
        qdd: T::as_f64s_mut(qdd)?,
        points: &mut ws.points,
    };
    let work = (&mut ws.regs, &mut ws.out, &mut ws.by_size);
    let sx = super::jit::InputTrig::Given(sx);
    let done = super::stages::run(g, input, sx, options, work, at)?;
    if done.is_ok() {
        std::mem::swap(&mut ws.sc, &mut ws.trial_sc);
    }
    Some(done.map(super::stages::report_in))
}

/// A tick's motion by walking `program` (of `g`), with `p` its params and prelude ([`ProgramParams`]):
/// positions from the guess in `ws.trial` (sines and cosines in `ws.trial_sc`, the inputs' `sx`),
/// velocities into `qd`, accelerations into `qdd`, the points into `ws.points`. On success
/// `ws.trial` holds the unknowns and `ws.sc` their sines and cosines (`ws.trial_sc` is left
/// undefined), as the block driver leaves them.
#[allow(clippy::too_many_arguments)]
fn run<T: Real>(
    g: &Generic,
    program: &Program,
    p: &ProgramParams,
    input: InputMotion<&[T]>,
    sx: &[(T, T)],
    options: &SolveOptions<T>,
    ws: &mut Scratch<T>,
    [qd, qdd]: [&mut [T]; 2],
) -> Result<NewtonReport<T>, SolveError> {
    let InputMotion { x, xd, xdd } = input;
    let Scratch {
        regs,
        out,
        trial,
        trial_sc,
        sc,
        points,
        by_size,
        program: file,
        values,
        ..
    } = ws;
    file.resize(program.ops.len(), T::zero());
    points.resize(6 * g.info.points.len(), T::zero());
    let mut stages = TickStages::new(g, options, T::lit(p.scale), (regs, out, by_size));
    const NONE: &[usize] = &[];
    let angle = &g.angle[..];
    for step in &program.steps {
        let (taken, unknowns, to) = match step {
            Step::Ops(range) => {
                let env = Env {
                    x,
                    q: trial,
                    p: &p.values,
                    xd,
                    qd,
                    xdd,
                    qdd,
                    sc: trial_sc,
                    sx,
                };
                let (kq, kx) = (
                    |k: u32| env.sc.get(k as usize).copied(),
                    |i: u32| sx.get(i as usize).copied(),
                );
                eval_range(&program.ops, range.clone(), |v| env.get(v), kq, kx, file);
                continue;
            }
            Step::Output(regs) => {
                for (o, &r) in points.iter_mut().zip(regs) {
                    *o = file[r as usize];
                }
                continue;
            }
            Step::Closed { roots: v, .. } => (&v[..], NONE, None),
            Step::Velocity {
                values: v,
                unknowns,
                ..
            } => (&v[..], &unknowns[..], Some(&mut *qd)),
            Step::Acceleration {
                values: v,
                unknowns,
                ..
            } => (&v[..], &unknowns[..], Some(&mut *qdd)),
            Step::Newton { .. } | Step::Refine => (&[][..], NONE, None),
        };
        values.clear();
        values.extend(taken.iter().map(|&r| file[r as usize]));
        let mut st = TrigSlices {
            q: trial,
            sc: trial_sc,
            angle,
        };
        match *step {
            Step::Closed { block, .. } => stages.closed(block, values, &mut st)?,
            Step::Newton { block } => stages.newton(block, (x, sx), &mut st)?,
            Step::Refine => stages.refine(x, sx, &mut st),
            Step::Velocity { block, .. } => stages.velocity(block, values)?,
            Step::Acceleration { block, .. } => stages.acceleration(block, values)?,
            Step::Ops(_) | Step::Output(_) => {}
        }
        if let Some(to) = to {
            for (&u, v) in unknowns.iter().zip(values.iter()) {
                to[u] = *v;
            }
        }
    }
    std::mem::swap(sc, trial_sc);
    Ok(stages.report)
}

impl Generic {
    /// A whole solve by the mechanism's program ([`motion`]), or `None` where it has none
    /// (or closed forms are off): every argument checked as the driver checks them, then the
    /// positions from the guess `q`, the rates into `qd` and `qdd`. On success the unknowns are
    /// in `ws.trial` and the points' values in `ws.points`.
    pub(super) fn whole_motion<T: Real>(
        &self,
        input: InputMotion<&[T]>,
        q: &[T],
        options: &SolveOptions<T>,
        ws: &mut Scratch<T>,
        rates: [&mut [T]; 2],
    ) -> Option<Result<NewtonReport<T>, SolveError>> {
        self.program.as_ref().filter(|_| options.closed_forms)?;
        let checked = check_finite(Quantity::Param, &self.params)
            .and_then(|()| check_finite(Quantity::Input, input.x))
            .and_then(|()| check_finite(Quantity::Guess, q))
            .and_then(|()| check_finite(Quantity::InputRate, input.xd))
            .and_then(|()| check_finite(Quantity::InputAcceleration, input.xdd));
        if let Err(e) = checked {
            return Some(Err(e));
        }
        ws.trial.clear();
        ws.trial.extend_from_slice(q);
        ws.trial_sc.clear();
        ws.trial_sc.resize(q.len(), (T::zero(), T::one()));
        mechgen_runtime::trig::TrigSlices {
            q: &mut ws.trial,
            sc: &mut ws.trial_sc,
            angle: &self.angle,
        }
        .init();
        motion(self, input, &[], options, ws, rates)
    }
}
