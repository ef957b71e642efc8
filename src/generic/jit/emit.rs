//! The JIT, emission: each tape instruction ([`Op`]) to Cranelift IR, in order, one SSA value per
//! register. Arithmetic is Cranelift's IEEE instructions (no fused multiply-add, `sqrt` correctly
//! rounded, as `f64::sqrt`); `sin`, `cos`, `tan` and the params-only functions call back into the
//! interpreter's own functions, so every value is the interpreter's bit for bit.

use cranelift_codegen::ir::condcodes::IntCC;
use cranelift_codegen::ir::immediates::Ieee64;
use cranelift_codegen::ir::{
    InstBuilder, InstructionData, MemFlagsData, Opcode, StackSlot, StackSlotData, StackSlotKind,
    Type, Value, types,
};
use cranelift_frontend::FunctionBuilder;
use cranelift_jit::JITModule;
use cranelift_module::{FuncId, Module};

use super::abi::Reads;
use super::error::JitError;
use super::imports::{FUNCS, Imports};
use crate::generic::op::{Op, slot};

/// Instructions being lowered into one function: the `Args` slots it reads loaded once at its
/// entry, one SSA value per register.
pub(super) struct Emit<'a> {
    pub b: FunctionBuilder<'a>,
    module: &'a mut JITModule,
    imports: &'a Imports,
    pub ptr: Type,
    base: [Option<Value>; 11],
    pair_slot: StackSlot,
    regs: Vec<Value>,
    pending_cos: Option<Value>,
    reads: Reads,
    /// Every unknown has its kept pair (a fused program's frame): read without a test.
    pub pairs_complete: bool,
}

impl<'a> Emit<'a> {
    /// At the entry block of `b`: loads the slots of `args` that `ops` read, and those `extra`
    /// names (slot indices of `Args`).
    pub(super) fn new<const N: usize>(
        mut b: FunctionBuilder<'a>,
        module: &'a mut JITModule,
        imports: &'a Imports,
        args: Value,
        ops: &[Op],
        extra: [usize; N],
    ) -> Self {
        let ptr = module.target_config().pointer_type();
        let slot_bytes = i32::try_from(ptr.bytes()).unwrap_or(8);
        // Which slots are read: the seven variable slices, then the kept sines and cosines of
        // the unknowns (slots 7 and 8: pointer, length) and of the inputs (9 and 10).
        let mut used = [false; 11];
        for op in ops {
            match *op {
                Op::Var(v) => used[slot(v).0] = true,
                Op::SinCosQ(..) => (used[7], used[8]) = (true, true),
                Op::SinCosX(..) => (used[9], used[10]) = (true, true),
                _ => {}
            }
        }
        for i in extra {
            used[i] = true;
        }
        let mut base = [None; 11];
        for (i, _) in used.iter().enumerate().filter(|(_, u)| **u) {
            let at = slot_bytes * i as i32;
            base[i] = Some(b.ins().load(ptr, fixed(), args, at));
        }
        let pair_slot =
            b.create_sized_stack_slot(StackSlotData::new(StackSlotKind::ExplicitSlot, 16, 3));
        Emit {
            b,
            module,
            imports,
            ptr,
            base,
            pair_slot,
            regs: Vec::with_capacity(ops.len()),
            pending_cos: None,
            reads: Reads::default(),
            pairs_complete: false,
        }
    }

    /// The value of register `r`.
    pub(super) fn reg(&self, r: u32) -> Result<Value, JitError> {
        self.regs.get(r as usize).copied().ok_or(JitError::Tape)
    }

    /// The base pointer of `Args` slot `i` (loaded at entry).
    pub(super) fn base(&self, i: usize) -> Result<Value, JitError> {
        self.base[i].ok_or(JitError::Tape)
    }

    /// Element `i` of the slice in `Args` slot `s` (one of the seven), counted in what the
    /// function reads.
    pub(super) fn load(&mut self, s: usize, i: usize) -> Result<Value, JitError> {
        let n = self.reads.0.get_mut(s).ok_or(JitError::Tape)?;
        *n = (*n).max(i + 1);
        let at = i32::try_from(i * 8).map_err(|_| JitError::Tape)?;
        let from = self.base[s].ok_or(JitError::Tape)?;
        // The inputs, params and input rates do not change while the function runs: their
        // loads may move to their first use (fewer values live across the function).
        let flags = if matches!(s, 0 | 2 | 3 | 5) {
            fixed()
        } else {
            MemFlagsData::trusted()
        };
        Ok(self.b.ins().load(types::F64, flags, from, at))
    }

    /// Stores register `r` at `to[j]` (f64 elements).
    pub(super) fn store(&mut self, r: u32, to: Value, j: usize) -> Result<(), JitError> {
        let v = self.reg(r)?;
        let at = i32::try_from(j * 8).map_err(|_| JitError::Tape)?;
        self.b.ins().store(MemFlagsData::trusted(), v, to, at);
        Ok(())
    }

    /// `code::stage`, referenced from this function: directly, or through its trampoline for
    /// a call off the common path (`cold`).
    pub(super) fn stage_callee(&mut self, cold: bool) -> cranelift_codegen::ir::FuncRef {
        let id = if cold {
            self.imports.stage_cold
        } else {
            self.imports.stage
        };
        self.callee(id)
    }

    /// A callee declared in the module, referenced from this function.
    pub(super) fn callee(&mut self, id: FuncId) -> cranelift_codegen::ir::FuncRef {
        self.module.declare_func_in_func(id, self.b.func)
    }

    /// Lowers the next instructions (their registers follow those lowered before).
    pub(super) fn ops(&mut self, ops: &[Op]) -> Result<(), JitError> {
        let ptr = self.ptr;
        for op in ops {
            let v = match *op {
                Op::Const(c) => self.b.ins().f64const(c),
                Op::Var(v) => {
                    let (s, i) = slot(v);
                    self.load(s, i)?
                }
                Op::Add(x, y) => {
                    let (x, y) = constant_second(&self.b, self.reg(x)?, self.reg(y)?);
                    self.b.ins().fadd(x, y)
                }
                Op::Sub(x, y) => {
                    let (x, y) = (self.reg(x)?, self.reg(y)?);
                    self.b.ins().fsub(x, y)
                }
                Op::Mul(x, y) => {
                    let (x, y) = constant_second(&self.b, self.reg(x)?, self.reg(y)?);
                    self.b.ins().fmul(x, y)
                }
                Op::Div(x, y) => {
                    let (x, y) = (self.reg(x)?, self.reg(y)?);
                    self.b.ins().fdiv(x, y)
                }
                Op::Neg(x) => {
                    let x = self.reg(x)?;
                    neg(&mut self.b, x)
                }
                Op::Sqrt(x) => {
                    let x = self.reg(x)?;
                    self.b.ins().sqrt(x)
                }
                Op::Sin(x) | Op::Cos(x) | Op::Tan(x) => {
                    let id = match op {
                        Op::Sin(_) => self.imports.sin,
                        Op::Cos(_) => self.imports.cos,
                        _ => self.imports.tan,
                    };
                    let (f, x) = (self.callee(id), self.reg(x)?);
                    let call = self.b.ins().call(f, &[x]);
                    self.b.inst_results(call)[0]
                }
                Op::Func(f, x, y) => {
                    let i = FUNCS.iter().position(|h| *h == f).ok_or(JitError::Tape)?;
                    let f = self.callee(self.imports.funcs[i]);
                    let (x, y) = (self.reg(x)?, self.reg(y)?);
                    let call = self.b.ins().call(f, &[x, y]);
                    self.b.inst_results(call)[0]
                }
                Op::SinCos(x) | Op::SinCosQ(x, _) | Op::SinCosX(x, _) => {
                    let x = self.reg(x)?;
                    // Computed where a kept pair is missing (off the common path: the
                    // trampoline) or always (a direct call).
                    let (cold, f) = (
                        self.callee(self.imports.sin_cos_cold),
                        self.callee(self.imports.sin_cos),
                    );
                    let pair_slot = self.pair_slot;
                    let computed =
                        |b: &mut FunctionBuilder| sin_cos_call(b, cold, ptr, pair_slot, x);
                    let (s, c) = match *op {
                        // A fused program's unknowns all have their pair (`Fused::call` checks
                        // `sc` as long as `q`, which is read up to k here).
                        Op::SinCosQ(_, k) if self.pairs_complete => {
                            let n = &mut self.reads.0[1];
                            *n = (*n).max(k as usize + 1);
                            let sc = self.base[7].ok_or(JitError::Tape)?;
                            let at =
                                i32::try_from(u64::from(k) * 16).map_err(|_| JitError::Tape)?;
                            let trusted = MemFlagsData::trusted();
                            let s = self.b.ins().load(types::F64, trusted, sc, at);
                            (s, self.b.ins().load(types::F64, trusted, sc, at + 8))
                        }
                        Op::SinCosQ(_, k) | Op::SinCosX(_, k) => {
                            let at = if matches!(op, Op::SinCosQ(..)) { 7 } else { 9 };
                            let pairs = self.base[at].zip(self.base[at + 1]);
                            let (pairs, len) = pairs.ok_or(JitError::Tape)?;
                            kept_or(&mut self.b, pairs, len, k, computed)?
                        }
                        _ => sin_cos_call(&mut self.b, f, ptr, pair_slot, x),
                    };
                    self.pending_cos = Some(c);
                    s
                }
                Op::Cos2 => self.pending_cos.take().ok_or(JitError::Tape)?,
            };
            self.regs.push(v);
        }
        Ok(())
    }

    /// `(sin x, cos x)` by the runtime's `sin_cos` (what the interpreter computes), off the
    /// common path (through the trampoline).
    pub(super) fn sin_cos_cold(&mut self, x: Value) -> (Value, Value) {
        let f = self.callee(self.imports.sin_cos_cold);
        sin_cos_call(&mut self.b, f, self.ptr, self.pair_slot, x)
    }

    /// Seals and finalizes the function; what it reads.
    pub(super) fn finish(mut self) -> Reads {
        self.b.seal_all_blocks();
        self.b.finalize(self.module.target_config());
        self.reads
    }
}

/// The operands of a sum or product with a constant second: x86 reads a constant second operand
/// straight from the constant pool, where a first one takes two instructions to put in a
/// register. The same bits: IEEE addition and multiplication are commutative, and a constant
/// that is not NaN cannot choose which NaN the result carries.
pub(super) fn constant_second(b: &FunctionBuilder, x: Value, y: Value) -> (Value, Value) {
    let constant = |v: Value| {
        let dfg = &b.func.dfg;
        dfg.value_def(v).inst().is_some_and(|i| match dfg.insts[i] {
            InstructionData::UnaryIeee64 {
                opcode: Opcode::F64const,
                imm,
            } => !f64::from_bits(imm.bits()).is_nan(),
            _ => false,
        })
    };
    if constant(x) && !constant(y) {
        (y, x)
    } else {
        (x, y)
    }
}

/// `-x`, the bits of `fneg`. On x86-64 as an xor with −0.0: one constant of the function, built
/// once and shared by every use, where `fneg` builds its mask in two instructions at every use.
pub(super) fn neg(b: &mut FunctionBuilder, x: Value) -> Value {
    if cfg!(target_arch = "x86_64") {
        let sign = b.ins().f64const(Ieee64::with_bits(SIGN));
        b.ins().bxor(x, sign)
    } else {
        b.ins().fneg(x)
    }
}

/// `|x|`, the bits of `fabs`: on x86-64 an and with every bit but the sign's (as [`neg`]).
pub(super) fn abs(b: &mut FunctionBuilder, x: Value) -> Value {
    if cfg!(target_arch = "x86_64") {
        let magnitude = b.ins().f64const(Ieee64::with_bits(!SIGN));
        b.ins().band(x, magnitude)
    } else {
        b.ins().fabs(x)
    }
}

/// A call of the runtime's `sin_cos` `f` on `x`, through the 16-byte stack slot `pair`.
fn sin_cos_call(
    b: &mut FunctionBuilder,
    f: cranelift_codegen::ir::FuncRef,
    ptr: Type,
    pair: StackSlot,
    x: Value,
) -> (Value, Value) {
    let at = b.ins().stack_addr(ptr, pair, 0);
    b.ins().call(f, &[x, at]);
    let s = b.ins().stack_load(ptr, types::F64, pair, 0);
    let c = b.ins().stack_load(ptr, types::F64, pair, 8);
    (s, c)
}

/// An f64's sign bit.
const SIGN: u64 = 1 << 63;

/// The flags of a load from memory that compiled code never writes while it runs (`Args`
/// itself, and the inputs, params and input rates it points to): read-only and free to move.
fn fixed() -> MemFlagsData {
    MemFlagsData::trusted().with_readonly().with_can_move()
}

/// The kept (sin, cos) of unknown `k` when `k < len` (read from `sc`), else `computed`: a
/// branch joined in a block with the two values as parameters.
fn kept_or(
    b: &mut FunctionBuilder,
    sc: Value,
    len: Value,
    k: u32,
    computed: impl FnOnce(&mut FunctionBuilder) -> (Value, Value),
) -> Result<(Value, Value), JitError> {
    let trusted = MemFlagsData::trusted();
    let ty = b.func.dfg.value_type(len);
    let (kept, compute, join) = (b.create_block(), b.create_block(), b.create_block());
    b.append_block_param(join, types::F64);
    b.append_block_param(join, types::F64);
    let kc = b.ins().iconst(ty, i64::from(k));
    let has = b.ins().icmp(IntCC::UnsignedGreaterThan, len, kc);
    b.ins().brif(has, kept, &[], compute, &[]);
    b.switch_to_block(kept);
    let at = i32::try_from(u64::from(k) * 16).map_err(|_| JitError::Tape)?;
    let s = b.ins().load(types::F64, trusted, sc, at);
    let c = b.ins().load(types::F64, trusted, sc, at + 8);
    b.ins().jump(join, &[s.into(), c.into()]);
    b.switch_to_block(compute);
    let (s, c) = computed(b);
    b.ins().jump(join, &[s.into(), c.into()]);
    b.switch_to_block(join);
    let p = b.block_params(join);
    Ok((p[0], p[1]))
}
