//! Generic engine, the call steps of a tick's program ([`TickStages`]): each runs what the block
//! driver runs for it (the closed-form kernel, the block Newton, the refinement, a block's
//! factors for both rates). The interpreter's walk of the program calls them directly
//! (`walk.rs`); the JIT's compiled program through its callbacks ([`Stages`]), and [`run`] is the
//! tick's motion in one call of machine code. Both give the driver's bits.

#[cfg(feature = "jit")]
use std::any::Any;

#[cfg(feature = "jit")]
use mechgen_runtime::InputMotion;
#[cfg(feature = "jit")]
use mechgen_runtime::error::Quantity;
use mechgen_runtime::error::{SolveError, Stage};
use mechgen_runtime::scalar::Real;
#[cfg(feature = "jit")]
use mechgen_runtime::solve::check_inputs;
use mechgen_runtime::solve::{NewtonReport, SolveOptions};
use mechgen_runtime::trig::TrigSlices;

use super::closed;
use super::driver::BlockWork;
use super::engine::Generic;
use super::factors::{Factors, Kept};
#[cfg(feature = "jit")]
use super::jit::{FusedArgs, InputTrig, NOT_FINITE, Positions, Stages};
use super::scratch::Sized;

/// The call steps of one run of a tick's program, on the workspace's buffers (in any
/// precision: the interpreter's walk, `walk.rs`; in f64 the JIT's callbacks too).
pub(super) struct TickStages<'a, T: Real> {
    pub g: &'a Generic,
    pub options: &'a SolveOptions<T>,
    pub scale: T,
    pub report: NewtonReport<T>,
    pub regs: &'a mut Vec<T>,
    pub out: &'a mut Vec<T>,
    pub by_size: &'a mut Vec<Option<Sized<T>>>,
    /// The factors of the block whose velocity was solved last.
    pub kept: Option<Kept<T>>,
    /// The error of a failed callback (the JIT's, which can only return a status).
    #[cfg(feature = "jit")]
    pub error: Option<SolveError>,
}

impl<'a, T: Real> TickStages<'a, T> {
    /// The stages of one run, on the workspace's buffers (`regs`, `out`, `by_size`).
    pub fn new(
        g: &'a Generic,
        options: &'a SolveOptions<T>,
        scale: T,
        (regs, out, by_size): BlockWork<'a, T>,
    ) -> Self {
        TickStages {
            g,
            options,
            scale,
            report: NewtonReport::new(),
            regs,
            out,
            by_size,
            kept: None,
            #[cfg(feature = "jit")]
            error: None,
        }
    }

    /// Block `block`'s size, or the error of a block the mechanism does not have.
    fn size(&self, block: usize) -> Result<usize, SolveError> {
        let len = self.g.blocks.len();
        let b = self.g.blocks.get(block);
        b.map(|b| b.unknowns.len())
            .ok_or(SolveError::OutOfRange { index: block, len })
    }

    /// Block `block` by its closed-form kernel from its `roots`.
    pub fn closed(
        &mut self,
        block: usize,
        roots: &[T],
        st: &mut TrigSlices<'_, T>,
    ) -> Result<(), SolveError> {
        let form = self.g.blocks.get(block).and_then(|b| b.closed.as_ref());
        let Some(c) = form else {
            let len = self.g.blocks.len();
            return Err(SolveError::OutOfRange { index: block, len });
        };
        let tolerance = self.options.newton.tolerance;
        let report = &mut self.report;
        closed::solve(block, &c.form, roots, st, self.scale, tolerance, report)
    }

    /// Block `block` by Newton on its position tape.
    pub fn newton(
        &mut self,
        block: usize,
        (x, sx): (&[T], &[(T, T)]),
        st: &mut TrigSlices<'_, T>,
    ) -> Result<(), SolveError> {
        self.size(block)?;
        let ws = (&mut *self.regs, &mut *self.out, &mut *self.by_size);
        let (options, scale, report) = (self.options, self.scale, &mut self.report);
        (self.g).newton_block(block, (x, sx), st, options, scale, report, ws)
    }

    /// The refinement of every block, if the positions' pivot ratio asks for it.
    pub fn refine(&mut self, x: &[T], sx: &[(T, T)], st: &mut TrigSlices<'_, T>) {
        (self.g).refine_if(&self.g.order, x, sx, st, &self.report);
    }

    /// `values` (right-hand side k, Jacobian k×k): the factors kept, the velocities in
    /// `values[..k]`.
    pub fn velocity(&mut self, block: usize, values: &mut [T]) -> Result<(), SolveError> {
        let k = self.size(block)?;
        let mut lu = Factors::of_block(block, Stage::Velocity, values, k, self.by_size)?;
        lu.solve_into(block, Stage::Velocity, &mut values[..k])?;
        self.kept = Some(lu.keep());
        Ok(())
    }

    /// `values[..k]` becomes the accelerations, by the kept factors.
    pub fn acceleration(&mut self, block: usize, values: &mut [T]) -> Result<(), SolveError> {
        let k = self.size(block)?;
        let kept = self.kept.take().ok_or(SolveError::NotStarted)?;
        let mut lu = Factors::kept(kept, k, self.by_size);
        lu.solve_into(block, Stage::Acceleration, &mut values[..k])
    }
}

/// The JIT's callbacks: the same steps, their errors kept.
#[cfg(feature = "jit")]
impl TickStages<'_, f64> {
    fn done(&mut self, r: Result<(), SolveError>) -> bool {
        r.map_err(|e| self.error = Some(e)).is_ok()
    }
}

#[cfg(feature = "jit")]
impl Stages for TickStages<'_, f64> {
    fn closed(&mut self, block: usize, roots: &[f64], at: Positions<'_>) -> bool {
        let angle = &self.g.angle;
        let mut st = TrigSlices {
            q: at.q,
            sc: at.sc,
            angle,
        };
        let r = TickStages::closed(self, block, roots, &mut st);
        self.done(r)
    }

    fn newton(&mut self, block: usize, at: Positions<'_>) -> bool {
        let angle = &self.g.angle;
        let mut st = TrigSlices {
            q: at.q,
            sc: at.sc,
            angle,
        };
        let r = TickStages::newton(self, block, (at.x, at.sx), &mut st);
        self.done(r)
    }

    fn refine(&mut self, at: Positions<'_>) -> bool {
        let angle = &self.g.angle;
        let mut st = TrigSlices {
            q: at.q,
            sc: at.sc,
            angle,
        };
        TickStages::refine(self, at.x, at.sx, &mut st);
        true
    }

    fn velocity(&mut self, block: usize, values: &mut [f64]) -> bool {
        let r = TickStages::velocity(self, block, values);
        self.done(r)
    }

    fn acceleration(&mut self, block: usize, values: &mut [f64]) -> bool {
        let r = TickStages::acceleration(self, block, values);
        self.done(r)
    }

    fn pivot_ratio(&self) -> f64 {
        self.report.pivot_ratio
    }

    fn set_pivot_ratio(&mut self, ratio: f64) {
        self.report.pivot_ratio = ratio;
    }

    fn fail(&mut self, error: SolveError) {
        self.error = Some(error);
    }
}

/// The buffers a motion is solved in: the unknowns (the guess on entry) and their sines and
/// cosines, solved in place; the velocities, accelerations and the points' six values each,
/// written.
#[cfg(feature = "jit")]
pub(super) struct Solving<'s> {
    pub q: &'s mut [f64],
    pub sc: &'s mut [(f64, f64)],
    pub qd: &'s mut [f64],
    pub qdd: &'s mut [f64],
    pub points: &'s mut [f64],
}

#[cfg(feature = "jit")]
/// A motion by `g`'s compiled program, when it has one and `options` has closed forms on:
/// positions from the guess in `at` (the inputs' sines and cosines `sx`: given, or a tick's made
/// by its prelude), the rates and points into it, the callbacks' steps in `work`. On success
/// `at.q` holds the unknowns and `at.sc` their sines and cosines, as the driver leaves them (and
/// a tick's prelude has stored the inputs). `None`: not run. Inlined into its two callers, so
/// that the call's arguments are built in place, not copied from frame to frame.
#[inline(always)]
pub(super) fn run(
    g: &Generic,
    input: InputMotion<&[f64]>,
    sx: InputTrig<'_>,
    options: &SolveOptions<f64>,
    work: BlockWork<'_, f64>,
    at: Solving<'_>,
) -> Option<Result<NewtonReport<f64>, SolveError>> {
    let fused = g.fused.as_ref().filter(|_| options.closed_forms)?;
    let p = g.program_params.as_ref()?;
    let mut stages = TickStages::new(g, options, p.scale, work);
    let args = FusedArgs {
        x: input.x,
        p: &p.values,
        xd: input.xd,
        xdd: input.xdd,
        sx,
        q: at.q,
        sc: at.sc,
        qd: at.qd,
        qdd: at.qdd,
        tolerance: options.newton.tolerance,
    };
    let (status, pivot_ratio) = fused.call(args, &mut stages, at.points)?;
    if status == NOT_FINITE {
        let (x, xd, xdd) = (input.x, input.xd, input.xdd);
        let named = check_inputs(x, xd, xdd).err();
        return Some(Err(named.unwrap_or(SolveError::NonFinite {
            quantity: Quantity::Input,
            index: 0,
        })));
    }
    if status != 0 {
        return Some(Err(stages.error.unwrap_or(SolveError::NotStarted)));
    }
    let r = stages.report;
    Some(Ok(NewtonReport {
        iterations: r.iterations,
        residual: r.residual,
        pivot_ratio,
    }))
}

/// The motion's arguments in f64, when `T` is f64 (what compiled code runs in).
#[cfg(feature = "jit")]
pub(super) fn in_f64<'a, T: Real>(
    input: InputMotion<&'a [T]>,
    options: &'a SolveOptions<T>,
) -> Option<(InputMotion<&'a [f64]>, &'a SolveOptions<f64>)> {
    let options = (options as &dyn Any).downcast_ref::<SolveOptions<f64>>()?;
    let (x, xd, xdd) = (
        T::as_f64s(input.x)?,
        T::as_f64s(input.xd)?,
        T::as_f64s(input.xdd)?,
    );
    Some((InputMotion { x, xd, xdd }, options))
}

/// A report of compiled code's motion as one in `T`.
#[cfg(feature = "jit")]
pub(super) fn report_in<T: Real>(r: NewtonReport<f64>) -> NewtonReport<T> {
    NewtonReport {
        iterations: r.iterations,
        residual: T::lit(r.residual),
        pivot_ratio: T::lit(r.pivot_ratio),
    }
}
