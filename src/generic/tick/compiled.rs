//! Generic engine, its tick's compiled paths (feature `jit`, f64): a whole tick in one call of
//! machine code with its prelude ([`GenericTick::advance_compiled`]), and a motion by the
//! compiled program from a prediction made in Rust (`Slot::compiled`).

use std::any::Any;

use mechgen_runtime::error::SolveError;
use mechgen_runtime::mechanism::InputMotion;
use mechgen_runtime::solve::{NewtonReport, SolveOptions};
use mechgen_runtime::tick::{RESYNC_TICKS, predict};

use super::super::driver::BlockWork;
use super::super::engine::Generic;
use super::super::jit::{InputTrig, TickPrelude, flat_points};
use super::super::scratch::{Scratched, Sized};
use super::super::stages::{self, Solving};
use super::{GenericTick, Slot, copy_few};

impl<T: Scratched> GenericTick<'_, T> {
    /// [`GenericTick::advance`] by the compiled program with its tick's prelude (in f64, closed
    /// forms on, a program that needs no block work; `jit/prelude.rs`): the inputs checked, their
    /// sines and cosines rotated and the unknowns carried (or predicted here first, where a block
    /// is solved by Newton) and the inputs stored, all in one call of machine code. The same
    /// steps as the other way, in the same order. `None`: not run (then the other way runs).
    pub(super) fn advance_compiled(
        &mut self,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
    ) -> Option<Result<(), SolveError>> {
        let (input, options) = stages::in_f64(input, options)?;
        let g = self.g;
        let slots = (&mut self.slots as &mut dyn Any).downcast_mut::<[Slot<f64>; 2]>()?;
        let (regs, out, by_size) = &mut self.idle;
        let work = (
            (regs as &mut dyn Any).downcast_mut::<Vec<f64>>()?,
            (out as &mut dyn Any).downcast_mut::<Vec<f64>>()?,
            (by_size as &mut dyn Any).downcast_mut::<Vec<Option<Sized<f64>>>>()?,
        );
        let resync = self.age >= RESYNC_TICKS;
        let [a, b] = slots;
        let (old, new) = if self.cur == 0 { (&*a, b) } else { (&*b, a) };
        let s = &old.state;
        let Slot { state: n, tx, tq } = new;
        if !self.all_closed {
            copy_few(tq, &old.tq);
            predict(
                old.last(),
                input.x,
                &g.angle,
                &self.keep,
                resync,
                &mut n.q,
                tq,
            );
        }
        let prelude = TickPrelude {
            x_last: &s.x,
            tx_last: &old.tx,
            q_last: &s.q,
            tq_last: &old.tq,
            sx: tx,
            to: [&mut n.x, &mut n.xd, &mut n.xdd],
            resync,
        };
        let solving = Solving {
            q: &mut n.q,
            sc: tq,
            qd: &mut n.qd,
            qdd: &mut n.qdd,
            points: flat_points(&mut n.points),
        };
        let sx = InputTrig::Tick(prelude);
        match stages::run(g, input, sx, options, work, solving)? {
            Ok(report) => n.report = report,
            Err(e) => return Some(Err(e)),
        }
        self.cur ^= 1;
        self.age = if resync { 0 } else { self.age + 1 };
        Some(Ok(()))
    }
}

impl<T: Scratched> Slot<T> {
    /// `motion` by the compiled program, in `at` itself (`None`: not compiled, or not in f64).
    #[inline(always)]
    pub(super) fn compiled(
        &mut self,
        g: &Generic,
        input: InputMotion<&[T]>,
        options: &SolveOptions<T>,
        (regs, out, by_size): BlockWork<'_, T>,
    ) -> Option<Result<NewtonReport<T>, SolveError>> {
        g.fused.as_ref()?;
        let (input, options) = stages::in_f64(input, options)?;
        let at = (self as &mut dyn Any).downcast_mut::<Slot<f64>>()?;
        let work = (
            (regs as &mut dyn Any).downcast_mut::<Vec<f64>>()?,
            (out as &mut dyn Any).downcast_mut::<Vec<f64>>()?,
            (by_size as &mut dyn Any).downcast_mut::<Vec<Option<Sized<f64>>>>()?,
        );
        let Slot { state: s, tx, tq } = at;
        let solving = Solving {
            q: &mut s.q,
            sc: tq,
            qd: &mut s.qd,
            qdd: &mut s.qdd,
            points: flat_points(&mut s.points),
        };
        let tx = InputTrig::Given(tx);
        let done = stages::run(g, input, tx, options, work, solving)?;
        Some(done.map(stages::report_in))
    }
}
