//! Generic engine, its back ends: the tapes interpreted (the default of [`Generic`], every
//! precision), or compiled to machine code by the JIT ([`Generic::compile`], f64). The block
//! driver is the same for both; only a tape's evaluation changes.

use std::time::{Duration, Instant};

use super::engine::Generic;
use super::jit::{self, JitError};
use super::tape::Tape;

impl Generic {
    /// Compiles every tape of the mechanism (its blocks, closed forms, rates, points, scenes,
    /// sensitivities, drawing) with Cranelift into one module of machine code, which every
    /// later f64 solve runs instead of the interpreter (clones share it); returns the time it
    /// took. On error nothing changes: the interpreter runs.
    pub fn compile(&mut self) -> Result<Duration, JitError> {
        let began = Instant::now();
        let program = self.program.clone();
        let mut tapes = self.tapes_mut();
        let programs: Vec<_> = tapes.iter().map(|t| t.program()).collect();
        let (functions, fused) = jit::compile(&programs, program.as_deref())?;
        for (t, f) in tapes.iter_mut().zip(functions) {
            t.set_compiled(Some(f));
        }
        self.fused = fused;
        Ok(began.elapsed())
    }

    /// Back to the interpreter (what the JIT is tested against).
    pub fn interpret(&mut self) {
        for t in self.tapes_mut() {
            t.set_compiled(None);
        }
        self.fused = None;
    }

    /// Whether [`Generic::compile`] is in effect.
    pub fn is_compiled(&self) -> bool {
        self.points.is_compiled()
    }

    /// How many tapes [`Generic::compile`] compiles.
    pub fn tape_count(&self) -> usize {
        self.clone().tapes_mut().len()
    }

    /// How many instructions they hold in all.
    pub fn instruction_count(&self) -> usize {
        self.clone().tapes_mut().iter().map(|t| t.len()).sum()
    }

    /// Every tape, in a fixed order.
    fn tapes_mut(&mut self) -> Vec<&mut Tape> {
        let mut all = vec![
            &mut self.residual,
            &mut self.jacobian,
            &mut self.input_jacobian,
            &mut self.sensitivity,
            &mut self.jacobian_dot,
            &mut self.acceleration_rhs,
            &mut self.points,
            &mut self.bodies,
            &mut self.masses,
            &mut self.chains,
        ];
        for b in &mut self.blocks {
            all.extend([
                &mut b.position,
                &mut b.residual,
                &mut b.velocity,
                &mut b.acceleration,
            ]);
            all.extend(b.closed.as_mut().map(|c| &mut c.roots));
        }
        all.extend(self.scenes.iter_mut().map(|s| &mut s.points));
        all
    }
}

impl Generic {
    /// Whether a tick and a whole solve walk the mechanism's program ([`Generic::compile`]d or
    /// interpreted); `false` where they fall back to the block driver.
    pub fn has_program(&self) -> bool {
        self.program.is_some() && self.program_params.is_some()
    }

    /// Whether the program is compiled into one function (after [`Generic::compile`]).
    pub fn has_compiled_program(&self) -> bool {
        self.has_program() && self.fused.is_some()
    }
}
