//! The JIT, a tick's prelude in the motion's function (`program::TickShape`), run when the
//! frame asks for it: the inputs checked finite (a return of `NOT_FINITE` before anything is
//! written), their sines and cosines rotated from the last tick's by the runtime's own series
//! (`trig::turn_series`, traced) or computed afresh where the runtime's `rotate` would (a large
//! turn, a resync), the last tick's unknowns carried as the guess where every block is solved in
//! closed form; after a successful motion, the inputs stored in the tick's state. The operations
//! of `mechgen_runtime::tick::inputs_trig` in its order: the interpreter's tick's bits.

use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::{InstBuilder, MemFlagsData, Value, types};
use mechgen_runtime::lanes::Lanes;
use mechgen_runtime::trig::{SERIES_TURN, turn_series};

use super::abi::NOT_FINITE;
use super::code::{LAST_AT, RESYNC, TICK_AT, TO_AT};
use super::emit::abs;
use super::error::JitError;
use super::fused::{Lower, offset};
use super::trace::{self, Traced};
use crate::generic::program::TickShape;

/// The `Args` slots of the inputs, their rates and accelerations.
const INPUT_SLOTS: [usize; 3] = [0, 3, 5];

/// The `Args` slots of the unknowns, their kept pairs and the inputs' pairs.
const Q_SLOT: usize = 1;
const SC_SLOT: usize = 7;
const SX_SLOT: usize = 9;

impl Lower<'_, '_> {
    /// The prelude at the function's entry (see the module), then on at the motion's block.
    pub fn prelude(&mut self, shape: &TickShape) -> Result<(), JitError> {
        let trusted = MemFlagsData::trusted();
        let frame = self.frame;
        let flags = (self.e.b.ins()).load(types::I64, trusted, frame, offset(TICK_AT)?);
        let (tick, body) = (self.e.b.create_block(), self.e.b.create_block());
        self.e.b.ins().brif(flags, tick, &[], body, &[]);
        self.e.b.switch_to_block(tick);
        let x = self.finite_inputs(shape.input_angle.len())?;
        let ptr = self.e.ptr;
        let last = |l: &mut Self, k: usize| -> Result<Value, JitError> {
            Ok(l.e
                .b
                .ins()
                .load(ptr, trusted, frame, offset(LAST_AT + 8 * k)?))
        };
        let (x_last, tx_last) = (last(self, 0)?, last(self, 1)?);
        let resync = self.e.b.ins().band_imm_u(flags, RESYNC as i64);
        let rotates = self.e.b.ins().icmp_imm_u(IntCC::Equal, resync, 0);
        let series = trace::record(|| {
            let (s, c, dz) = (Traced::input(0), Traced::input(1), Traced::input(2));
            let (sd, cd) = turn_series(dz, Traced::splat);
            (s * cd - c * sd, c * cd + s * sd)
        })?;
        let sx = self.e.base(SX_SLOT)?;
        for (i, _) in shape.input_angle.iter().enumerate().filter(|(_, a)| **a) {
            let at = offset(8 * i)?;
            let xl = self.e.b.ins().load(types::F64, trusted, x_last, at);
            let dz = self.e.b.ins().fsub(xl, x[i]);
            let magnitude = abs(&mut self.e.b, dz);
            let small = self.e.b.ins().f64const(SERIES_TURN);
            let small = (self.e.b.ins()).fcmp(FloatCC::LessThanOrEqual, magnitude, small);
            let rotated = self.e.b.ins().band(small, rotates);
            let b = &mut self.e.b;
            let (rotate, afresh, join) = (b.create_block(), b.create_block(), b.create_block());
            b.append_block_param(join, types::F64);
            b.append_block_param(join, types::F64);
            b.ins().brif(rotated, rotate, &[], afresh, &[]);
            b.switch_to_block(rotate);
            let pair = offset(16 * i)?;
            let s = b.ins().load(types::F64, trusted, tx_last, pair);
            let c = b.ins().load(types::F64, trusted, tx_last, pair + 8);
            let v = trace::lower(b, &series.nodes, &[s, c, dz], None)?;
            let at = |t: Traced| v.get(t.0 as usize).copied().ok_or(JitError::Tape);
            let (s, c) = (at(series.result.0)?, at(series.result.1)?);
            b.ins().jump(join, &[s.into(), c.into()]);
            b.switch_to_block(afresh);
            let (s, c) = self.e.sin_cos_cold(x[i]);
            let b = &mut self.e.b;
            b.ins().jump(join, &[s.into(), c.into()]);
            b.switch_to_block(join);
            let (s, c) = (b.block_params(join)[0], b.block_params(join)[1]);
            b.ins().store(trusted, s, sx, pair);
            b.ins().store(trusted, c, sx, pair + 8);
        }
        if shape.carried {
            let (q_last, tq_last) = (last(self, 2)?, last(self, 3)?);
            let (q, sc) = (self.e.base(Q_SLOT)?, self.e.base(SC_SLOT)?);
            let b = &mut self.e.b;
            for k in 0..shape.unknowns {
                let (at, pair) = (offset(8 * k)?, offset(16 * k)?);
                let v = b.ins().load(types::F64, trusted, q_last, at);
                b.ins().store(trusted, v, q, at);
                for half in [0, 8] {
                    let v = b.ins().load(types::F64, trusted, tq_last, pair + half);
                    b.ins().store(trusted, v, sc, pair + half);
                }
            }
        }
        self.e.b.ins().jump(body, &[]);
        self.e.b.switch_to_block(body);
        Ok(())
    }

    /// The inputs (read), having returned `NOT_FINITE` unless they, their rates and
    /// accelerations are all finite.
    fn finite_inputs(&mut self, n: usize) -> Result<Vec<Value>, JitError> {
        let mut x = Vec::with_capacity(n);
        let mut all: Option<Value> = None;
        let inf = self.e.b.ins().f64const(f64::INFINITY);
        for i in 0..n {
            for s in INPUT_SLOTS {
                let v = self.e.load(s, i)?;
                if s == INPUT_SLOTS[0] {
                    x.push(v);
                }
                // |v| < ∞: false for both infinities and NaN.
                let magnitude = abs(&mut self.e.b, v);
                let finite = (self.e.b.ins()).fcmp(FloatCC::LessThan, magnitude, inf);
                all = Some(match all {
                    Some(a) => self.e.b.ins().band(a, finite),
                    None => finite,
                });
            }
        }
        if let Some(all) = all {
            let b = &mut self.e.b;
            let (go, refuse) = (b.create_block(), b.create_block());
            b.ins().brif(all, go, &[], refuse, &[]);
            b.switch_to_block(refuse);
            let status = b.ins().iconst(types::I32, i64::from(NOT_FINITE));
            b.ins().return_(&[status]);
            b.switch_to_block(go);
        }
        Ok(x)
    }

    /// Before the successful return: a tick's inputs, rates and accelerations stored where the
    /// frame's `to` points.
    pub fn epilogue(&mut self, inputs: usize) -> Result<(), JitError> {
        let (trusted, frame, ptr) = (MemFlagsData::trusted(), self.frame, self.e.ptr);
        let flags = (self.e.b.ins()).load(types::I64, trusted, frame, offset(TICK_AT)?);
        let (store, done) = (self.e.b.create_block(), self.e.b.create_block());
        self.e.b.ins().brif(flags, store, &[], done, &[]);
        self.e.b.switch_to_block(store);
        for (k, s) in INPUT_SLOTS.into_iter().enumerate() {
            let to = (self.e.b.ins()).load(ptr, trusted, frame, offset(TO_AT + 8 * k)?);
            for i in 0..inputs {
                let v = self.e.load(s, i)?;
                self.e.b.ins().store(trusted, v, to, offset(8 * i)?);
            }
        }
        self.e.b.ins().jump(done, &[]);
        self.e.b.switch_to_block(done);
        Ok(())
    }
}
