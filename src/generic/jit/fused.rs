//! The JIT, a whole motion: a [`Program`] lowered into one function, its instructions in order
//! with one SSA value per register across every stage, each call step a call of `code::stage`
//! (the runtime's kernel, Newton, the refinement, a block's factorization) with the values it
//! needs in a stack buffer; a status other than 0 returns at once.

use cranelift_codegen::ir::condcodes::FloatCC;
use cranelift_codegen::ir::{
    InstBuilder, MemFlagsData, StackSlotData, StackSlotKind, Value, types,
};
use mechgen_runtime::twofold::REFINE_BELOW;

use super::code::{Call, KEPT_BYTES, PIVOT_AT, Reads};
use super::emit::Emit;
use super::error::JitError;
use crate::generic::program::{Program, Step};

/// Lowers `p` into the function `e` builds (parameters `frame`, the `code::Frame`, and `out`);
/// what it reads, one past the largest unknown whose rates it stores, how many outputs it writes.
pub(super) fn lower(
    mut e: Emit<'_>,
    p: &Program,
    frame: Value,
    out: Value,
) -> Result<(Reads, usize, usize), JitError> {
    let width = u32::try_from(p.call_width().max(1) * 8).map_err(|_| JitError::Tape)?;
    let buf =
        e.b.create_sized_stack_slot(StackSlotData::new(StackSlotKind::ExplicitSlot, width, 3));
    // A small block's factors between its two rates, zeroed (invariant 4 of `code.rs`).
    let ptr = e.ptr;
    let kept_bytes = KEPT_BYTES.div_ceil(8) * 8;
    let size = u32::try_from(kept_bytes).map_err(|_| JitError::Tape)?;
    let kept =
        e.b.create_sized_stack_slot(StackSlotData::new(StackSlotKind::ExplicitSlot, size, 3));
    let zero = e.b.ins().iconst(types::I64, 0);
    for k in 0..kept_bytes / 8 {
        let at = i32::try_from(k * 8).map_err(|_| JitError::Tape)?;
        e.b.ins().stack_store(ptr, zero, kept, at);
    }
    let fail = e.b.create_block();
    e.b.append_block_param(fail, types::I32);
    let trusted = MemFlagsData::trusted();
    let (mut writes, mut outputs) = (0, 0);
    for step in &p.steps {
        let (call, block, values): (Call, usize, &[u32]) = match step {
            Step::Ops(range) => {
                let ops = p.ops.get(range.clone()).ok_or(JitError::Tape)?;
                e.ops(ops)?;
                continue;
            }
            Step::Output(regs) => {
                for (j, &r) in regs.iter().enumerate() {
                    e.store(r, out, j)?;
                }
                outputs = outputs.max(regs.len());
                continue;
            }
            Step::Closed { block, roots } => (Call::Closed, *block, roots),
            Step::Newton { block } => (Call::Newton, *block, &[]),
            Step::Refine => (Call::Refine, 0, &[]),
            Step::Velocity {
                block,
                values,
                unknowns,
            } if unknowns.len() <= 2 => (Call::SmallVelocity, *block, values),
            Step::Acceleration {
                block,
                values,
                unknowns,
            } if unknowns.len() <= 2 => (Call::SmallAcceleration, *block, values),
            Step::Velocity { block, values, .. } => (Call::Velocity, *block, values),
            Step::Acceleration { block, values, .. } => (Call::Acceleration, *block, values),
        };
        // The refinement only when the positions' pivot ratio is below `REFINE_BELOW` (false
        // for NaN, as the driver's test).
        let skip = if call == Call::Refine {
            let at = i32::try_from(PIVOT_AT).map_err(|_| JitError::Tape)?;
            let pivot = e.b.ins().load(types::F64, trusted, frame, at);
            let below = e.b.ins().f64const(REFINE_BELOW);
            let low = e.b.ins().fcmp(FloatCC::LessThan, pivot, below);
            let (refine, skip) = (e.b.create_block(), e.b.create_block());
            e.b.ins().brif(low, refine, &[], skip, &[]);
            e.b.switch_to_block(refine);
            Some(skip)
        } else {
            None
        };
        let ptr = e.ptr;
        let at = e.b.ins().stack_addr(ptr, buf, 0);
        for (j, &r) in values.iter().enumerate() {
            e.store(r, at, j)?;
        }
        let f = e.stage_callee();
        let what = e.b.ins().iconst(types::I32, call as i64);
        let block = i64::try_from(block).map_err(|_| JitError::Tape)?;
        let block = e.b.ins().iconst(types::I32, block);
        let count = i64::try_from(values.len()).map_err(|_| JitError::Tape)?;
        let count = e.b.ins().iconst(ptr, count);
        let aux = e.b.ins().stack_addr(ptr, kept, 0);
        let inst = e.b.ins().call(f, &[frame, what, block, at, count, aux]);
        let status = e.b.inst_results(inst)[0];
        let ok = skip.unwrap_or_else(|| e.b.create_block());
        e.b.ins().brif(status, fail, &[status.into()], ok, &[]);
        e.b.switch_to_block(ok);
        // A block's solved rates, from the buffer the call solved in place.
        let (slot, unknowns) = match step {
            Step::Velocity { unknowns, .. } => (4, unknowns),
            Step::Acceleration { unknowns, .. } => (6, unknowns),
            _ => continue,
        };
        let to = e.base(slot)?;
        for (i, &u) in unknowns.iter().enumerate() {
            let from = i32::try_from(i * 8).map_err(|_| JitError::Tape)?;
            let v = e.b.ins().stack_load(ptr, types::F64, buf, from);
            let at = i32::try_from(u * 8).map_err(|_| JitError::Tape)?;
            e.b.ins().store(trusted, v, to, at);
            writes = writes.max(u + 1);
        }
    }
    let zero = e.b.ins().iconst(types::I32, 0);
    e.b.ins().return_(&[zero]);
    e.b.switch_to_block(fail);
    let status = e.b.block_params(fail)[0];
    e.b.ins().return_(&[status]);
    Ok((e.finish(), writes, outputs))
}
