//! The JIT, a whole motion: a [`Program`] lowered into one function, its instructions in order
//! with one SSA value per register across every stage. A closed-form block and a small block's
//! rates run inline, the runtime's lane kernels traced into the function (`inline.rs`), calling
//! the runtime's scalar step only where a kernel's mask leaves the common path; every other call
//! step is a call of `code::stage` (Newton, the refinement, a larger block's factors) with the
//! values it needs in a stack buffer; a status other than 0 returns at once.

use std::collections::HashMap;

use cranelift_codegen::ir::condcodes::FloatCC;
use cranelift_codegen::ir::{
    Block, InstBuilder, MemFlagsData, StackSlot, StackSlotData, StackSlotKind, Value, types,
};
use mechgen_runtime::twofold::REFINE_BELOW;

use super::abi::{Call, KEPT_BYTES, Reads};
use super::code::{PIVOT_AT, STATUS_AT};
use super::emit::Emit;
use super::error::JitError;
use crate::generic::program::{Program, Step};

/// A program being lowered: the emitter, the function's frame, its stack buffers, the block
/// every failure branches to.
pub(super) struct Lower<'a, 'p> {
    pub e: Emit<'a>,
    pub p: &'p Program,
    pub frame: Value,
    /// The values of a call step.
    buf: StackSlot,
    /// A small block's factors between its two rates (invariant 4 of `code.rs`: written by its
    /// velocity's call step before its acceleration's reads it, or zeroed first).
    kept: StackSlot,
    fail: Block,
    /// One past the largest unknown whose rates are stored.
    pub writes: usize,
    /// The registers of each block's velocity step (its Jacobian for the acceleration).
    pub velocity_values: HashMap<usize, Vec<u32>>,
    /// Whether a call step needs the stages' block work (a Newton block, a large block's rates).
    pub work: bool,
}

/// An `i32` byte offset.
pub(super) fn offset(bytes: usize) -> Result<i32, JitError> {
    i32::try_from(bytes).map_err(|_| JitError::Tape)
}

/// What lowering a program found: what it reads, one past the largest unknown whose rates it
/// stores, how many outputs it writes, whether a call step needs the stages' block work, the
/// inputs and unknowns a tick's prelude reads.
pub(super) struct Lowered {
    pub reads: Reads,
    pub writes: usize,
    pub outputs: usize,
    pub work: bool,
    pub prelude: (usize, usize),
}

/// Lowers `p` into the function `e` builds (parameters `frame`, the `code::Frame`, and `out`):
/// a tick's prelude when the frame asks for one (`prelude.rs`), the steps in order.
pub(super) fn lower(
    mut e: Emit<'_>,
    p: &Program,
    frame: Value,
    out: Value,
) -> Result<Lowered, JitError> {
    let width = u32::try_from(p.call_width().max(1) * 8).map_err(|_| JitError::Tape)?;
    let slot = |bytes| StackSlotData::new(StackSlotKind::ExplicitSlot, bytes, 3);
    let buf = e.b.create_sized_stack_slot(slot(width));
    let kept_bytes = KEPT_BYTES.div_ceil(8) * 8;
    let size = u32::try_from(kept_bytes).map_err(|_| JitError::Tape)?;
    let kept = e.b.create_sized_stack_slot(slot(size));
    let fail = e.b.create_block();
    e.b.append_block_param(fail, types::I32);
    let mut l = Lower {
        e,
        p,
        frame,
        buf,
        kept,
        fail,
        writes: 0,
        velocity_values: HashMap::new(),
        work: false,
    };
    l.prelude(&p.tick)?;
    let mut outputs = 0;
    for step in &p.steps {
        match step {
            Step::Ops(range) => {
                let ops = p.ops.get(range.clone()).ok_or(JitError::Tape)?;
                l.e.ops(ops)?;
            }
            Step::Output(regs) => {
                for (j, &r) in regs.iter().enumerate() {
                    l.e.store(r, out, j)?;
                }
                outputs = outputs.max(regs.len());
            }
            Step::Closed {
                block,
                kind,
                slots,
                roots,
            } => l.closed(*block, *kind, *slots, roots)?,
            Step::Newton { block } => l.call(Call::Newton, *block, &[])?,
            Step::Refine => {
                // Only when the positions' pivot ratio is below `REFINE_BELOW` (false for NaN,
                // as the driver's test).
                let pivot = l.frame_f64(PIVOT_AT)?;
                let below = l.e.b.ins().f64const(REFINE_BELOW);
                let low = l.e.b.ins().fcmp(FloatCC::LessThan, pivot, below);
                let (refine, skip) = (l.e.b.create_block(), l.e.b.create_block());
                l.e.b.ins().brif(low, refine, &[], skip, &[]);
                l.e.b.switch_to_block(refine);
                l.call(Call::Refine, 0, &[])?;
                l.e.b.ins().jump(skip, &[]);
                l.e.b.switch_to_block(skip);
            }
            Step::Velocity {
                block,
                unknowns,
                values,
            } => l.rates(true, *block, unknowns, values)?,
            Step::Acceleration {
                block,
                unknowns,
                values,
            } => l.rates(false, *block, unknowns, values)?,
        }
    }
    let inputs = p.tick.input_angle.len();
    l.epilogue(inputs)?;
    let zero = l.e.b.ins().iconst(types::I32, 0);
    l.e.b.ins().return_(&[zero]);
    l.e.b.switch_to_block(l.fail);
    let status = l.e.b.block_params(l.fail)[0];
    l.e.b.ins().return_(&[status]);
    let (writes, work) = (l.writes, l.work);
    let carried = if p.tick.carried { p.tick.unknowns } else { 0 };
    Ok(Lowered {
        reads: l.e.finish(),
        writes,
        outputs,
        work,
        prelude: (inputs, carried),
    })
}

impl Lower<'_, '_> {
    /// The f64 of the frame at byte `at`.
    pub fn frame_f64(&mut self, at: usize) -> Result<Value, JitError> {
        let trusted = MemFlagsData::trusted();
        Ok(self
            .e
            .b
            .ins()
            .load(types::F64, trusted, self.frame, offset(at)?))
    }

    /// A call of `code::stage` with `values` in the buffer; on failure a return of its status,
    /// else on at a new block, the solved values (if any) in the buffer. A call every run makes
    /// (a Newton block, a large block's rates) is direct; one off the common path (a closed
    /// form's or small block's scalar step, the refinement) goes through the `preserve_all`
    /// trampoline (`cold.rs`), which leaves the status in the frame.
    pub fn call(&mut self, call: Call, block: usize, values: &[u32]) -> Result<(), JitError> {
        let always = matches!(call, Call::Newton | Call::Velocity | Call::Acceleration);
        self.work |= always;
        let ptr = self.e.ptr;
        let at = self.e.b.ins().stack_addr(ptr, self.buf, 0);
        for (j, &r) in values.iter().enumerate() {
            self.e.store(r, at, j)?;
        }
        let f = self.e.stage_callee(!always);
        let what = self.e.b.ins().iconst(types::I32, call as i64);
        let block = i64::try_from(block).map_err(|_| JitError::Tape)?;
        let block = self.e.b.ins().iconst(types::I32, block);
        let count = i64::try_from(values.len()).map_err(|_| JitError::Tape)?;
        let count = self.e.b.ins().iconst(ptr, count);
        let aux = self.e.b.ins().stack_addr(ptr, self.kept, 0);
        let args = [self.frame, what, block, at, count, aux];
        let inst = self.e.b.ins().call(f, &args);
        let status = match self.e.b.inst_results(inst).first() {
            Some(&status) => status,
            None => {
                let (trusted, at) = (MemFlagsData::trusted(), offset(STATUS_AT)?);
                (self.e.b.ins()).load(types::I32, trusted, self.frame, at)
            }
        };
        let ok = self.e.b.create_block();
        self.e
            .b
            .ins()
            .brif(status, self.fail, &[status.into()], ok, &[]);
        self.e.b.switch_to_block(ok);
        Ok(())
    }

    /// Zeroes the slot of a small block's factors (all-zero bytes are a `Factored`), before an
    /// acceleration's call step that no velocity's call step of the same block precedes.
    pub fn zero_kept(&mut self) -> Result<(), JitError> {
        let zero = self.e.b.ins().iconst(types::I64, 0);
        for k in 0..KEPT_BYTES.div_ceil(8) {
            let ptr = self.e.ptr;
            self.e
                .b
                .ins()
                .stack_store(ptr, zero, self.kept, offset(k * 8)?);
        }
        Ok(())
    }

    /// Stores `v[i]` as the rate of `unknowns[i]` in `Args` slot `slot` (4: velocities, 6:
    /// accelerations).
    pub fn store_rates(
        &mut self,
        slot: usize,
        unknowns: &[usize],
        v: &[Value],
    ) -> Result<(), JitError> {
        let to = self.e.base(slot)?;
        for (&u, &v) in unknowns.iter().zip(v) {
            self.e
                .b
                .ins()
                .store(MemFlagsData::trusted(), v, to, offset(u * 8)?);
            self.writes = self.writes.max(u + 1);
        }
        Ok(())
    }

    /// The first `n` values of the buffer (what a call step solved in place).
    pub fn solved_values(&mut self, n: usize) -> Result<Vec<Value>, JitError> {
        let (ptr, buf) = (self.e.ptr, self.buf);
        (0..n)
            .map(|i| {
                Ok(self
                    .e
                    .b
                    .ins()
                    .stack_load(ptr, types::F64, buf, offset(i * 8)?))
            })
            .collect()
    }
}
