//! Generic engine, the runtime's side of a compiled whole motion ([`Stages`] of the JIT's fused
//! program): each call step runs what the interpreted driver runs for it (the closed-form kernel,
//! the block Newton, the refinement, a block's factors for both rates), and [`run`] is the tick's
//! motion through it: the same bits as the driver, in one call of machine code.

use std::any::Any;

use mechgen_runtime::InputMotion;
use mechgen_runtime::error::{SolveError, Stage};
use mechgen_runtime::scalar::Real;
use mechgen_runtime::solve::{NewtonReport, SolveOptions};
use mechgen_runtime::trig::TrigSlices;

use super::closed;
use super::engine::Generic;
use super::factors::{Factors, Kept};
use super::jit::{FusedArgs, Positions, Stages};
use super::scratch::{Scratch, Sized};
use super::tape::Env;

/// The call steps of one run, on the workspace's buffers.
struct TickStages<'a> {
    g: &'a Generic,
    options: &'a SolveOptions<f64>,
    scale: f64,
    report: NewtonReport<f64>,
    regs: &'a mut Vec<f64>,
    out: &'a mut Vec<f64>,
    by_size: &'a mut Vec<Option<Sized<f64>>>,
    /// The factors of the block whose velocity was solved last.
    kept: Option<Kept<f64>>,
    error: Option<SolveError>,
}

impl TickStages<'_> {
    fn done(&mut self, r: Result<(), SolveError>) -> bool {
        r.map_err(|e| self.error = Some(e)).is_ok()
    }

    /// Block `block`'s size, or the error of a block the mechanism does not have.
    fn size(&self, block: usize) -> Result<usize, SolveError> {
        let len = self.g.blocks.len();
        let b = self.g.blocks.get(block);
        b.map(|b| b.unknowns.len())
            .ok_or(SolveError::OutOfRange { index: block, len })
    }
}

impl Stages for TickStages<'_> {
    fn closed(&mut self, block: usize, roots: &[f64], at: Positions<'_>) -> bool {
        let form = self.g.blocks.get(block).and_then(|b| b.closed.as_ref());
        let Some(c) = form else {
            let len = self.g.blocks.len();
            return self.done(Err(SolveError::OutOfRange { index: block, len }));
        };
        let mut st = TrigSlices {
            q: at.q,
            sc: at.sc,
            angle: &self.g.angle,
        };
        let tolerance = self.options.newton.tolerance;
        let r = closed::solve(
            block,
            &c.form,
            roots,
            &mut st,
            self.scale,
            tolerance,
            &mut self.report,
        );
        self.done(r)
    }

    fn newton(&mut self, block: usize, at: Positions<'_>) -> bool {
        if let Err(e) = self.size(block) {
            return self.done(Err(e));
        }
        let mut st = TrigSlices {
            q: at.q,
            sc: at.sc,
            angle: &self.g.angle,
        };
        let ws = (&mut *self.regs, &mut *self.out, &mut *self.by_size);
        let (options, scale) = (self.options, self.scale);
        let r = (self.g).newton_block(
            block,
            (at.x, at.sx),
            &mut st,
            options,
            scale,
            &mut self.report,
            ws,
        );
        self.done(r)
    }

    fn refine(&mut self, at: Positions<'_>) -> bool {
        let mut st = TrigSlices {
            q: at.q,
            sc: at.sc,
            angle: &self.g.angle,
        };
        (self.g).refine_if(&self.g.order, at.x, at.sx, &mut st, &self.report);
        true
    }

    fn velocity(&mut self, block: usize, values: &mut [f64]) -> bool {
        let r = self.size(block).and_then(|k| {
            let mut lu = Factors::of_block(block, Stage::Velocity, values, k, self.by_size)?;
            lu.solve_into(block, Stage::Velocity, &mut values[..k])?;
            self.kept = Some(lu.keep());
            Ok(())
        });
        self.done(r)
    }

    fn acceleration(&mut self, block: usize, values: &mut [f64]) -> bool {
        let r = self.size(block).and_then(|k| {
            let kept = self.kept.take().ok_or(SolveError::NotStarted)?;
            let mut lu = Factors::kept(kept, k, self.by_size);
            lu.solve_into(block, Stage::Acceleration, &mut values[..k])
        });
        self.done(r)
    }
}

/// A tick's motion by `g`'s compiled program, when it has one for `T` (f64) and `options` (closed
/// forms on), with `p` the params and the program's prelude: positions from the guess in
/// `ws.trial` (sines and cosines in `ws.trial_sc`, the inputs' `sx`), velocities into `qd`,
/// accelerations into `qdd`, the points into `ws.points`. As the driver leaves them: on success
/// `ws.trial` holds the unknowns and `ws.sc` their sines and cosines (`ws.trial_sc` is left
/// undefined). `None`: not run.
pub(super) fn run<T: Real>(
    g: &Generic,
    p: &[f64],
    input: InputMotion<&[T]>,
    sx: &[(T, T)],
    options: &SolveOptions<T>,
    ws: &mut Scratch<T>,
    [qd, qdd]: [&mut [T]; 2],
) -> Option<Result<NewtonReport<T>, SolveError>> {
    let fused = g
        .fused
        .as_ref()
        .filter(|_| options.closed_forms && !p.is_empty())?;
    let ws = (ws as &mut dyn Any).downcast_mut::<Scratch<f64>>()?;
    let options = (options as &dyn Any).downcast_ref::<SolveOptions<f64>>()?;
    let (x, xd, xdd) = (
        T::as_f64s(input.x)?,
        T::as_f64s(input.xd)?,
        T::as_f64s(input.xdd)?,
    );
    let (sx, qd, qdd) = (
        T::pairs_as_f64s(sx)?,
        T::as_f64s_mut(qd)?,
        T::as_f64s_mut(qdd)?,
    );
    let Scratch {
        regs,
        out,
        trial,
        trial_sc,
        sc,
        points,
        by_size,
        ..
    } = ws;
    points.resize(6 * g.info.points.len(), 0.0);
    let mut stages = TickStages {
        g,
        options,
        scale: g.length_scale(),
        report: NewtonReport::new(),
        regs,
        out,
        by_size,
        kept: None,
        error: None,
    };
    let args = FusedArgs {
        x,
        p,
        xd,
        xdd,
        sx,
        q: trial,
        sc: trial_sc,
        qd,
        qdd,
    };
    let status = fused.call(args, &mut stages, points)?;
    if status != 0 {
        return Some(Err(stages.error.unwrap_or(SolveError::NotStarted)));
    }
    std::mem::swap(sc, trial_sc);
    let r = stages.report;
    Some(Ok(NewtonReport {
        iterations: r.iterations,
        residual: T::lit(r.residual),
        pivot_ratio: T::lit(r.pivot_ratio),
    }))
}

/// The params followed by the values of `g`'s program prelude (what [`run`] reads as `p`);
/// empty when `g` has no program or the prelude cannot be evaluated.
pub(super) fn params_with_prelude(g: &Generic) -> Vec<f64> {
    if g.program.is_none() {
        return Vec::new();
    }
    let mut values = vec![0.0; g.prelude.outputs()];
    let env = Env::position(&[], &[], &g.params);
    if g.prelude.eval(&env, &mut Vec::new(), &mut values).is_err() {
        return Vec::new();
    }
    let mut p = g.params.clone();
    p.extend(values);
    p
}
