//! The JIT, lowering: each tape instruction ([`Op`]) to Cranelift IR, in the tape's order, one
//! SSA value per register. Arithmetic is Cranelift's IEEE instructions (no fused multiply-add,
//! `sqrt` correctly rounded, as `f64::sqrt`); `sin`, `cos`, `tan` and the params-only functions
//! call back into the interpreter's own functions, so every value is the interpreter's bit for bit.

use cranelift_codegen::Context;
use cranelift_codegen::ir::condcodes::IntCC;
use cranelift_codegen::ir::{
    AbiParam, Function as IrFunction, InstBuilder, MemFlagsData, StackSlotData, StackSlotKind,
    Type, UserFuncName, Value, types,
};
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{FuncId, Linkage, Module, default_libcall_names};
use mechgen_codegen::Func;
use mechgen_runtime::twofold::Arith;

use super::code::{self, Reads};
use super::error::JitError;
use crate::generic::op::{Op, slot};

/// The params-only functions, in the order of their callbacks ([`FUNC_ENTRIES`]).
const FUNCS: [Func; 6] = [
    Func::Asin,
    Func::Acos,
    Func::Atan,
    Func::Abs,
    Func::Atan2,
    Func::Hypot,
];

extern "C" fn func<const I: usize>(a: f64, b: f64) -> f64 {
    f64::func(FUNCS[I].method(), a, b)
}

type Binary = extern "C" fn(f64, f64) -> f64;
const FUNC_ENTRIES: [Binary; 6] = [
    func::<0>, func::<1>, func::<2>, func::<3>, func::<4>, func::<5>,
];

extern "C" fn sin(x: f64) -> f64 {
    x.sin_of()
}
extern "C" fn cos(x: f64) -> f64 {
    x.cos_of()
}
extern "C" fn tan(x: f64) -> f64 {
    x.tan_of()
}

/// The callbacks compiled code calls, declared in the module.
struct Imports {
    sin: FuncId,
    cos: FuncId,
    tan: FuncId,
    sin_cos: FuncId,
    funcs: [FuncId; 6],
}

/// Tapes being compiled into one module.
pub(super) struct Lowering {
    module: JITModule,
    ctx: Context,
    fctx: FunctionBuilderContext,
    imports: Imports,
    ptr: Type,
    done: Vec<(FuncId, Reads, usize)>,
}

impl Lowering {
    /// A module for the host, optimised for speed, with the callbacks declared.
    pub(super) fn new() -> Result<Lowering, JitError> {
        let mut flags = settings::builder();
        for (k, v) in [
            ("opt_level", "speed"),
            ("use_colocated_libcalls", "false"),
            ("is_pic", "false"),
        ] {
            flags.set(k, v).map_err(|e| JitError::Host(e.to_string()))?;
        }
        let isa = cranelift_native::builder()
            .map_err(|e| JitError::Host(e.to_string()))?
            .finish(settings::Flags::new(flags))
            .map_err(|e| JitError::Host(e.to_string()))?;
        let mut jb = JITBuilder::with_isa(isa, default_libcall_names());
        jb.symbol("mechgen_sin", sin as *const u8);
        jb.symbol("mechgen_cos", cos as *const u8);
        jb.symbol("mechgen_tan", tan as *const u8);
        jb.symbol("mechgen_sin_cos", code::sin_cos as *const u8);
        for (i, f) in FUNC_ENTRIES.iter().enumerate() {
            jb.symbol(format!("mechgen_func{i}"), *f as *const u8);
        }
        let mut module = JITModule::new(jb);
        let ptr = module.target_config().pointer_type();
        let f64s = |n: usize, ret: bool| {
            let mut s = module.make_signature();
            s.params.extend((0..n).map(|_| AbiParam::new(types::F64)));
            if ret {
                s.returns.push(AbiParam::new(types::F64));
            }
            s
        };
        let (unary, binary) = (f64s(1, true), f64s(2, true));
        let mut pair = f64s(1, false);
        pair.params.push(AbiParam::new(ptr));
        let mut import = |name: &str, sig| {
            module
                .declare_function(name, Linkage::Import, sig)
                .map_err(|e| JitError::Compile(e.to_string()))
        };
        let imports = Imports {
            sin: import("mechgen_sin", &unary)?,
            cos: import("mechgen_cos", &unary)?,
            tan: import("mechgen_tan", &unary)?,
            sin_cos: import("mechgen_sin_cos", &pair)?,
            funcs: [
                import("mechgen_func0", &binary)?,
                import("mechgen_func1", &binary)?,
                import("mechgen_func2", &binary)?,
                import("mechgen_func3", &binary)?,
                import("mechgen_func4", &binary)?,
                import("mechgen_func5", &binary)?,
            ],
        };
        Ok(Lowering {
            ctx: module.make_context(),
            module,
            fctx: FunctionBuilderContext::new(),
            imports,
            ptr,
            done: Vec::new(),
        })
    }

    /// Compiles one tape (its instructions and output registers); its index among the
    /// functions [`Lowering::finish`] returns is the number added before it.
    pub(super) fn add(&mut self, ops: &[Op], outputs: &[u32]) -> Result<(), JitError> {
        let ptr = self.ptr;
        let mut sig = self.module.make_signature();
        sig.params.extend([AbiParam::new(ptr), AbiParam::new(ptr)]);
        let name = format!("tape{}", self.done.len());
        let id = self
            .module
            .declare_function(&name, Linkage::Local, &sig)
            .map_err(|e| JitError::Compile(e.to_string()))?;
        self.ctx.func = IrFunction::with_name_signature(UserFuncName::user(0, id.as_u32()), sig);
        let reads = self.body(ops, outputs)?;
        self.module
            .define_function(id, &mut self.ctx)
            .map_err(|e| JitError::Compile(e.to_string()))?;
        self.module.clear_context(&mut self.ctx);
        self.done.push((id, reads, outputs.len()));
        Ok(())
    }

    /// Links the module; the functions in the order they were added.
    pub(super) fn finish(mut self) -> Result<Vec<code::Function>, JitError> {
        self.module
            .finalize_definitions()
            .map_err(|e| JitError::Compile(e.to_string()))?;
        let addresses: Vec<_> = (self.done.iter())
            .map(|&(id, reads, n)| (self.module.get_finalized_function(id), reads, n))
            .collect();
        let code = code::Code::new(self.module);
        Ok(addresses
            .into_iter()
            .map(|(a, reads, n)| code::Function::new(&code, a, reads, n))
            .collect())
    }

    /// The body of `self.ctx.func`: the `Args` slots it reads loaded once at entry, then every
    /// instruction in order, then the outputs stored.
    fn body(&mut self, ops: &[Op], outputs: &[u32]) -> Result<Reads, JitError> {
        let (ptr, trusted) = (self.ptr, MemFlagsData::trusted());
        let slot_bytes = i32::try_from(ptr.bytes()).unwrap_or(8);
        let mut b = FunctionBuilder::new(&mut self.ctx.func, &mut self.fctx);
        let entry = b.create_block();
        b.append_block_params_for_function_params(entry);
        b.switch_to_block(entry);
        let (args, out) = (b.block_params(entry)[0], b.block_params(entry)[1]);
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
        let mut base = [None; 11];
        for (i, _) in used.iter().enumerate().filter(|(_, u)| **u) {
            base[i] = Some(b.ins().load(ptr, trusted, args, slot_bytes * i as i32));
        }
        let module = &mut self.module;
        let mut callee =
            |b: &mut FunctionBuilder, id: FuncId| module.declare_func_in_func(id, b.func);
        let pair_slot =
            b.create_sized_stack_slot(StackSlotData::new(StackSlotKind::ExplicitSlot, 16, 3));
        let mut reads = Reads::default();
        let mut regs: Vec<Value> = Vec::with_capacity(ops.len());
        let mut pending_cos = None;
        for op in ops {
            let g = |r: u32| regs.get(r as usize).copied().ok_or(JitError::Tape);
            let v = match *op {
                Op::Const(c) => b.ins().f64const(c),
                Op::Var(v) => {
                    let (s, i) = slot(v);
                    reads.0[s] = reads.0[s].max(i + 1);
                    let at = i32::try_from(i * 8).map_err(|_| JitError::Tape)?;
                    let from = base[s].ok_or(JitError::Tape)?;
                    b.ins().load(types::F64, trusted, from, at)
                }
                Op::Add(x, y) => b.ins().fadd(g(x)?, g(y)?),
                Op::Sub(x, y) => b.ins().fsub(g(x)?, g(y)?),
                Op::Mul(x, y) => b.ins().fmul(g(x)?, g(y)?),
                Op::Div(x, y) => b.ins().fdiv(g(x)?, g(y)?),
                Op::Neg(x) => b.ins().fneg(g(x)?),
                Op::Sqrt(x) => b.ins().sqrt(g(x)?),
                Op::Sin(x) | Op::Cos(x) | Op::Tan(x) => {
                    let id = match op {
                        Op::Sin(_) => self.imports.sin,
                        Op::Cos(_) => self.imports.cos,
                        _ => self.imports.tan,
                    };
                    let f = callee(&mut b, id);
                    let call = b.ins().call(f, &[g(x)?]);
                    b.inst_results(call)[0]
                }
                Op::Func(f, x, y) => {
                    let i = FUNCS.iter().position(|h| *h == f).ok_or(JitError::Tape)?;
                    let f = callee(&mut b, self.imports.funcs[i]);
                    let call = b.ins().call(f, &[g(x)?, g(y)?]);
                    b.inst_results(call)[0]
                }
                Op::SinCos(x) | Op::SinCosQ(x, _) | Op::SinCosX(x, _) => {
                    let x = g(x)?;
                    let f = callee(&mut b, self.imports.sin_cos);
                    let computed = |b: &mut FunctionBuilder| {
                        let at = b.ins().stack_addr(ptr, pair_slot, 0);
                        b.ins().call(f, &[x, at]);
                        let s = b.ins().stack_load(ptr, types::F64, pair_slot, 0);
                        let c = b.ins().stack_load(ptr, types::F64, pair_slot, 8);
                        (s, c)
                    };
                    let (s, c) = match *op {
                        Op::SinCosQ(_, k) | Op::SinCosX(_, k) => {
                            let at = if matches!(op, Op::SinCosQ(..)) { 7 } else { 9 };
                            let (pairs, len) = base[at].zip(base[at + 1]).ok_or(JitError::Tape)?;
                            kept_or(&mut b, pairs, len, k, computed)?
                        }
                        _ => computed(&mut b),
                    };
                    pending_cos = Some(c);
                    s
                }
                Op::Cos2 => pending_cos.take().ok_or(JitError::Tape)?,
            };
            regs.push(v);
        }
        for (j, &r) in outputs.iter().enumerate() {
            let v = regs.get(r as usize).copied().ok_or(JitError::Tape)?;
            let at = i32::try_from(j * 8).map_err(|_| JitError::Tape)?;
            b.ins().store(trusted, v, out, at);
        }
        b.ins().return_(&[]);
        b.seal_all_blocks();
        b.finalize(module.target_config());
        Ok(reads)
    }
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
