//! The JIT, kernels inline: a closed-form block and a 1×1 or 2×2 block's rates computed in the
//! compiled function by the runtime's lane kernels traced into it (`trace.rs`), stored where
//! their mask holds; where it does not (a dead point, a large turn, a near-singular block, a
//! value out of range) the runtime's scalar step is called instead, as a call step, so the
//! results and errors are the scalar's in every case.

use cranelift_codegen::ir::{Block, InstBuilder, MemFlagsData, Value, types};
use mechgen_runtime::closed_form::ClosedKind;
use mechgen_runtime::lanes::{LaneTrig, factor_block, solve_kind};

use super::abi::Call;
use super::code::{PIVOT_AT, TOLERANCE_AT};
use super::error::JitError;
use super::fused::{Lower, offset};
use super::trace::{self, TOLERANCE, Traced, TracedMask};
use crate::generic::op::Op;

impl Lower<'_, '_> {
    /// Whether register `r` is the literal zero.
    fn is_zero(&self, r: u32) -> bool {
        matches!(self.p.ops.get(r as usize), Some(Op::Const(c)) if *c == 0.0)
    }

    /// Closed-form block `block` of `kind`, its unknowns at `slots`, from the roots in `roots`.
    pub fn closed(
        &mut self,
        block: usize,
        kind: ClosedKind,
        slots: [usize; 2],
        roots: &[u32],
    ) -> Result<(), JitError> {
        let n = roots.len();
        let zero: Vec<bool> = roots.iter().map(|&r| self.is_zero(r)).collect();
        let t = trace::record(|| {
            let v: Vec<Traced> = (0..n as u32).map(Traced::input).collect();
            let x = |i: usize| Traced::input((n + i) as u32);
            let mut st = LaneTrig {
                q: [x(0), x(1)],
                sc: [(x(2), x(3)), (x(4), x(5))],
            };
            let (mut pivot, mut ok) = (x(6), TracedMask::all());
            solve_kind(
                kind,
                &mut st,
                [0, 1],
                &v,
                &zero,
                TOLERANCE,
                &mut pivot,
                &mut ok,
            );
            (st, pivot, ok)
        })?;
        // The inputs: the roots, the guess and its sines and cosines, the pivot ratio so far.
        let mut inputs = roots
            .iter()
            .map(|&r| self.e.reg(r))
            .collect::<Result<Vec<_>, _>>()?;
        let trusted = MemFlagsData::trusted();
        let (q, sc) = (self.e.base(1)?, self.e.base(7)?);
        for &k in &slots {
            // Unknown k's value is read as the program reads it (counted), its pair at 16 k:
            // the kept pairs are as many as the unknowns (checked by `Fused::call`).
            inputs.push(self.e.load(1, k)?);
        }
        for &k in &slots {
            let at = offset(k * 16)?;
            inputs.push(self.e.b.ins().load(types::F64, trusted, sc, at));
            inputs.push(self.e.b.ins().load(types::F64, trusted, sc, at + 8));
        }
        inputs.push(self.frame_f64(PIVOT_AT)?);
        let tolerance = self.frame_f64(TOLERANCE_AT)?;
        let v = trace::lower(&mut self.e.b, &t.nodes, &inputs, Some(tolerance))?;
        let at = |x: Traced| v.get(x.0 as usize).copied().ok_or(JitError::Tape);
        let (st, pivot, ok) = t.result;
        let ok = v.get(ok.0 as usize).copied().ok_or(JitError::Tape)?;
        let (fast, slow, join) = self.diamond(ok);
        self.e.b.switch_to_block(fast);
        for (i, &k) in slots.iter().enumerate().take(kind.unknowns()) {
            let (s, c) = (at(st.sc[i].0)?, at(st.sc[i].1)?);
            let value = at(st.q[i])?;
            self.e.b.ins().store(trusted, value, q, offset(k * 8)?);
            self.e.b.ins().store(trusted, s, sc, offset(k * 16)?);
            self.e.b.ins().store(trusted, c, sc, offset(k * 16 + 8)?);
        }
        let pivot = at(pivot)?;
        let frame = self.frame;
        self.e
            .b
            .ins()
            .store(trusted, pivot, frame, offset(PIVOT_AT)?);
        self.e.b.ins().jump(join, &[]);
        self.e.b.switch_to_block(slow);
        self.call(Call::Closed, block, roots)?;
        self.e.b.ins().jump(join, &[]);
        self.e.b.switch_to_block(join);
        Ok(())
    }

    /// Block `block`'s velocity (`velocity`: from `values`, right-hand side then the Jacobian row
    /// by row) or acceleration (from its right-hand side `values`, by the factors of its velocity
    /// step, factored again inline: the same operations on the same values).
    pub fn rates(
        &mut self,
        velocity: bool,
        block: usize,
        unknowns: &[usize],
        values: &[u32],
    ) -> Result<(), JitError> {
        let k = unknowns.len();
        let slot = if velocity { 4 } else { 6 };
        if k > 2 {
            let call = if velocity {
                Call::Velocity
            } else {
                Call::Acceleration
            };
            return self.called_rates(slot, unknowns, &[(call, block, values)]);
        }
        if velocity {
            let inline = self.small(k, values, &values[..k])?;
            let calls = [(Call::SmallVelocity, block, values)];
            self.rates_or(slot, unknowns, inline, &calls)?;
            self.velocity_values.insert(block, values.to_vec());
            return Ok(());
        }
        let Some(jac) = self.velocity_values.get(&block).cloned() else {
            // No factors of this block's velocity to read: the scalar's factors of zeros.
            self.zero_kept()?;
            let calls = [(Call::SmallAcceleration, block, values)];
            return self.called_rates(slot, unknowns, &calls);
        };
        let inline = self.small(k, &jac, values)?;
        // The scalar's factors in the caller's slot (the velocity may have been solved inline),
        // then its acceleration by them.
        let calls = [
            (Call::SmallVelocity, block, &jac[..]),
            (Call::SmallAcceleration, block, values),
        ];
        self.rates_or(slot, unknowns, inline, &calls)
    }

    /// Stores a block's rates solved inline (`z`, in `Args` slot `slot`) where the mask `ok`
    /// holds, else those the scalar's call steps `calls` solve.
    fn rates_or(
        &mut self,
        slot: usize,
        unknowns: &[usize],
        (z, ok): (Vec<Value>, Value),
        calls: &[(Call, usize, &[u32])],
    ) -> Result<(), JitError> {
        let (fast, slow, join) = self.diamond(ok);
        self.e.b.switch_to_block(fast);
        self.store_rates(slot, unknowns, &z)?;
        self.e.b.ins().jump(join, &[]);
        self.e.b.switch_to_block(slow);
        self.called_rates(slot, unknowns, calls)?;
        self.e.b.ins().jump(join, &[]);
        self.e.b.switch_to_block(join);
        Ok(())
    }

    /// The call steps `calls` in order, then the rates the last solved in the buffer stored in
    /// `Args` slot `slot`.
    fn called_rates(
        &mut self,
        slot: usize,
        unknowns: &[usize],
        calls: &[(Call, usize, &[u32])],
    ) -> Result<(), JitError> {
        for &(call, block, values) in calls {
            self.call(call, block, values)?;
        }
        let v = self.solved_values(unknowns.len())?;
        self.store_rates(slot, unknowns, &v)
    }

    /// A k×k block (k ≤ 2) with its Jacobian in `values[k..]` factored and solved for `rhs`
    /// inline: the solution and the mask of the common path.
    fn small(
        &mut self,
        k: usize,
        values: &[u32],
        rhs: &[u32],
    ) -> Result<(Vec<Value>, Value), JitError> {
        let jac = values.get(k..k + k * k).ok_or(JitError::Tape)?;
        let t = trace::record(|| {
            let x = |i: usize| Traced::input(i as u32);
            let mut ok = TracedMask::all();
            let z: Vec<Traced> = if k == 1 {
                let f = factor_block::<Traced, 1>([[x(0)]], &mut ok);
                f.solve([x(1)], &mut ok).to_vec()
            } else {
                let f = factor_block::<Traced, 2>([[x(0), x(1)], [x(2), x(3)]], &mut ok);
                f.solve([x(4), x(5)], &mut ok).to_vec()
            };
            (z, ok)
        })?;
        let inputs = (jac.iter().chain(rhs))
            .map(|&r| self.e.reg(r))
            .collect::<Result<Vec<_>, _>>()?;
        let v = trace::lower(&mut self.e.b, &t.nodes, &inputs, None)?;
        let at = |i: u32| v.get(i as usize).copied().ok_or(JitError::Tape);
        let (z, ok) = t.result;
        let z = z.iter().map(|x| at(x.0)).collect::<Result<Vec<_>, _>>()?;
        Ok((z, at(ok.0)?))
    }

    /// Branches on the mask `ok`: the blocks of the common path, of the scalar's, and where
    /// they join.
    fn diamond(&mut self, ok: Value) -> (Block, Block, Block) {
        let b = &mut self.e.b;
        let (fast, slow, join) = (b.create_block(), b.create_block(), b.create_block());
        b.ins().brif(ok, fast, &[], slow, &[]);
        (fast, slow, join)
    }
}
