//! The JIT, the rare calls: each callback a fused program makes off its common path (`stage`,
//! the runtime's `sin_cos` where the inline series does not hold) reached through a small
//! compiled trampoline of Cranelift's `preserve_all` convention, which saves every register the
//! callback may change. A call site then clobbers nothing, so the values that live across it
//! stay in registers on the common path instead of being spilled around a call it rarely makes.

use cranelift_codegen::Context;
use cranelift_codegen::ir::{
    AbiParam, Function as IrFunction, InstBuilder, MemFlagsData, Signature, UserFuncName, types,
};
use cranelift_codegen::isa::CallConv;
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::JITModule;
use cranelift_module::{FuncId, Linkage, Module};

use super::code::STATUS_AT;
use super::error::JitError;

/// Defines a trampoline of `callee` (an import of signature `sig`, of the host's convention)
/// named `name`: the same parameters in the `preserve_all` convention, no result; a result of
/// `callee` (the `stage` status, an `i32`) is stored at the frame's `STATUS_AT` (the first
/// parameter is the frame).
pub(super) fn trampoline(
    module: &mut JITModule,
    ctx: &mut Context,
    fctx: &mut FunctionBuilderContext,
    name: &str,
    callee: FuncId,
    sig: &Signature,
) -> Result<FuncId, JitError> {
    let mut cold = Signature::new(CallConv::PreserveAll);
    cold.params.clone_from(&sig.params);
    let id = module
        .declare_function(name, Linkage::Local, &cold)
        .map_err(|e| JitError::Compile(e.to_string()))?;
    ctx.func = IrFunction::with_name_signature(UserFuncName::user(1, id.as_u32()), cold);
    {
        let mut b = FunctionBuilder::new(&mut ctx.func, fctx);
        let entry = b.create_block();
        b.append_block_params_for_function_params(entry);
        b.switch_to_block(entry);
        let args = b.block_params(entry).to_vec();
        let f = module.declare_func_in_func(callee, b.func);
        let call = b.ins().call(f, &args);
        if let (Some(&status), Some(&frame)) = (b.inst_results(call).first(), args.first()) {
            if b.func.dfg.value_type(status) != types::I32 {
                return Err(JitError::Tape);
            }
            let at = i32::try_from(STATUS_AT).map_err(|_| JitError::Tape)?;
            b.ins().store(MemFlagsData::trusted(), status, frame, at);
        }
        b.ins().return_(&[]);
        b.seal_all_blocks();
        b.finalize(module.target_config());
    }
    module
        .define_function(id, ctx)
        .map_err(|e| JitError::Compile(e.to_string()))?;
    module.clear_context(ctx);
    Ok(id)
}

/// The signature of `stage` (`frame, what, block, values, count, aux -> status`).
pub(super) fn stage_signature(module: &JITModule) -> Signature {
    let ptr = module.target_config().pointer_type();
    let mut stage = module.make_signature();
    stage.params.extend([
        AbiParam::new(ptr),
        AbiParam::new(types::I32),
        AbiParam::new(types::I32),
        AbiParam::new(ptr),
        AbiParam::new(ptr),
        AbiParam::new(ptr),
    ]);
    stage.returns.push(AbiParam::new(types::I32));
    stage
}
