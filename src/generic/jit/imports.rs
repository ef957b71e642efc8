//! The JIT, its callbacks: the runtime's functions compiled code calls (`sin`, `cos`, `tan`,
//! `sin_cos` and the params-only functions, each the interpreter's own, and `code::stage`),
//! registered by name and declared in the module with the trampolines of the rare ones.

use cranelift_codegen::Context;
use cranelift_codegen::ir::{AbiParam, types};
use cranelift_frontend::FunctionBuilderContext;
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{FuncId, Linkage, Module};
use mechgen_codegen::Func;
use mechgen_runtime::twofold::Arith;

use super::code;
use super::cold;
use super::error::JitError;

/// The params-only functions, in the order of their callbacks ([`FUNC_ENTRIES`]).
pub(super) const FUNCS: [Func; 6] = [
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
pub(super) struct Imports {
    pub sin: FuncId,
    pub cos: FuncId,
    pub tan: FuncId,
    pub sin_cos: FuncId,
    pub funcs: [FuncId; 6],
    /// `code::stage`: a fused program's calls into the runtime.
    pub stage: FuncId,
    /// `sin_cos` and `stage` through their `preserve_all` trampolines (`cold.rs`): what a call
    /// off the common path calls.
    pub sin_cos_cold: FuncId,
    pub stage_cold: FuncId,
}

impl Imports {
    /// Registers every callback's address under its name.
    pub(super) fn symbols(jb: &mut JITBuilder) {
        jb.symbol("mechgen_sin", sin as *const u8);
        jb.symbol("mechgen_cos", cos as *const u8);
        jb.symbol("mechgen_tan", tan as *const u8);
        jb.symbol("mechgen_sin_cos", code::sin_cos as *const u8);
        jb.symbol("mechgen_stage", code::stage as *const u8);
        for (i, f) in FUNC_ENTRIES.iter().enumerate() {
            jb.symbol(format!("mechgen_func{i}"), *f as *const u8);
        }
    }

    /// Declares every callback in `module`, and the `preserve_all` trampolines of `stage` and
    /// `sin_cos` (`cold.rs`, compiled here with `ctx`).
    pub(super) fn declare(
        module: &mut JITModule,
        ctx: &mut Context,
        fctx: &mut FunctionBuilderContext,
    ) -> Result<Imports, JitError> {
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
        let stage_sig = cold::stage_signature(module);
        let mut import = |name: &str, sig| {
            module
                .declare_function(name, Linkage::Import, sig)
                .map_err(|e| JitError::Compile(e.to_string()))
        };
        let (sin, cos, tan) = (
            import("mechgen_sin", &unary)?,
            import("mechgen_cos", &unary)?,
            import("mechgen_tan", &unary)?,
        );
        let sin_cos = import("mechgen_sin_cos", &pair)?;
        let stage = import("mechgen_stage", &stage_sig)?;
        let mut funcs = [sin; 6];
        for (i, f) in funcs.iter_mut().enumerate() {
            *f = import(&format!("mechgen_func{i}"), &binary)?;
        }
        Ok(Imports {
            sin,
            cos,
            tan,
            sin_cos,
            funcs,
            stage,
            sin_cos_cold: cold::trampoline(module, ctx, fctx, "cold_sin_cos", sin_cos, &pair)?,
            stage_cold: cold::trampoline(module, ctx, fctx, "cold_stage", stage, &stage_sig)?,
        })
    }
}
