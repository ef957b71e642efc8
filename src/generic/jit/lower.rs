//! The JIT, lowering: a module for the host, each tape compiled into one function of it (its
//! instructions by `emit.rs`), a whole motion's program into one more (`fused.rs`), then linked.

use cranelift_codegen::Context;
use cranelift_codegen::ir::{
    AbiParam, Function as IrFunction, InstBuilder, Type, UserFuncName, types,
};
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{FuncId, Linkage, Module, default_libcall_names};

use super::abi::Reads;
use super::code;
use super::emit::Emit;
use super::error::JitError;
use super::imports::Imports;
use crate::generic::op::Op;
use crate::generic::program::Program;

/// Tapes being compiled into one module.
pub(super) struct Lowering {
    module: JITModule,
    ctx: Context,
    fctx: FunctionBuilderContext,
    imports: Imports,
    ptr: Type,
    done: Vec<(FuncId, Reads, usize)>,
    /// The fused program's function, when one was added.
    fused: Option<(FuncId, super::fused::Lowered)>,
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
        Imports::symbols(&mut jb);
        let mut module = JITModule::new(jb);
        let ptr = module.target_config().pointer_type();
        let (mut ctx, mut fctx) = (module.make_context(), FunctionBuilderContext::new());
        let imports = Imports::declare(&mut module, &mut ctx, &mut fctx)?;
        Ok(Lowering {
            ctx,
            module,
            fctx,
            imports,
            ptr,
            done: Vec::new(),
            fused: None,
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

    /// Compiles a whole motion's program into one function (`fused.rs`).
    pub(super) fn add_program(&mut self, p: &Program) -> Result<(), JitError> {
        let ptr = self.ptr;
        let mut sig = self.module.make_signature();
        sig.params.extend([AbiParam::new(ptr), AbiParam::new(ptr)]);
        sig.returns.push(AbiParam::new(types::I32));
        let id = self
            .module
            .declare_function("motion", Linkage::Local, &sig)
            .map_err(|e| JitError::Compile(e.to_string()))?;
        self.ctx.func = IrFunction::with_name_signature(UserFuncName::user(0, id.as_u32()), sig);
        let mut b = FunctionBuilder::new(&mut self.ctx.func, &mut self.fctx);
        let entry = b.create_block();
        b.append_block_params_for_function_params(entry);
        b.switch_to_block(entry);
        let (frame, out) = (b.block_params(entry)[0], b.block_params(entry)[1]);
        let mut e = Emit::new(
            b,
            &mut self.module,
            &self.imports,
            frame,
            &p.ops,
            [0, 1, 3, 4, 5, 6, 7, 8, 9, 10],
        );
        e.pairs_complete = true;
        let lowered = super::fused::lower(e, p, frame, out)?;
        // A developer's view of the machine code (spills, constants): `MECHGEN_JIT_DUMP=1`
        // prints each fused program's disassembly to stderr as it is compiled.
        let dump = std::env::var_os("MECHGEN_JIT_DUMP").is_some();
        self.ctx.set_disasm(dump);
        self.module
            .define_function(id, &mut self.ctx)
            .map_err(|e| JitError::Compile(e.to_string()))?;
        if let Some(c) = self.ctx.compiled_code().filter(|_| dump) {
            eprintln!("{}", c.vcode.as_deref().unwrap_or(""));
        }
        self.module.clear_context(&mut self.ctx);
        self.fused = Some((id, lowered));
        Ok(())
    }

    /// Links the module; the functions in the order they were added, and the fused program's.
    pub(super) fn finish(mut self) -> Result<(Vec<code::Function>, Option<code::Fused>), JitError> {
        self.module
            .finalize_definitions()
            .map_err(|e| JitError::Compile(e.to_string()))?;
        let addresses: Vec<_> = (self.done.iter())
            .map(|&(id, reads, n)| (self.module.get_finalized_function(id), reads, n))
            .collect();
        let fused = (self.fused).map(|(id, l)| (self.module.get_finalized_function(id), l));
        let code = code::Code::new(self.module);
        let functions = addresses
            .into_iter()
            .map(|(a, reads, n)| code::Function::new(&code, a, reads, n))
            .collect();
        let fused = fused.map(|(a, l)| {
            let (r, w, n, k) = (l.reads, l.writes, l.outputs, l.work);
            code::Fused::new(&code, a, r, w, n, k, Some(l.prelude))
        });
        Ok((functions, fused))
    }

    /// The body of `self.ctx.func`: the `Args` slots it reads loaded once at entry, then every
    /// instruction in order, then the outputs stored.
    fn body(&mut self, ops: &[Op], outputs: &[u32]) -> Result<Reads, JitError> {
        let mut b = FunctionBuilder::new(&mut self.ctx.func, &mut self.fctx);
        let entry = b.create_block();
        b.append_block_params_for_function_params(entry);
        b.switch_to_block(entry);
        let (args, out) = (b.block_params(entry)[0], b.block_params(entry)[1]);
        let mut e = Emit::new(b, &mut self.module, &self.imports, args, ops, []);
        e.ops(ops)?;
        for (j, &r) in outputs.iter().enumerate() {
            e.store(r, out, j)?;
        }
        e.b.ins().return_(&[]);
        Ok(e.finish())
    }
}
