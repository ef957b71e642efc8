//! Generic engine, the JIT back end (feature `jit`): every tape of a loaded mechanism compiled
//! by Cranelift into one module of machine code, once per load; the block driver then calls the
//! compiled tapes where it interprets them otherwise (in f64; f32 and the double-word refinement
//! stay interpreted). Same instructions in the same order as the interpreter, no fused
//! multiply-add, the same `sin`/`cos`/`tan`/`atan2` functions: the same bits.

mod code;
mod error;
mod lower;

pub use code::Function;
pub use error::JitError;

use super::op::Op;

/// Compiles tapes, each given as its instructions and output registers, into one module; the
/// functions in the same order.
pub(super) fn compile(tapes: &[(&[Op], &[u32])]) -> Result<Vec<Function>, JitError> {
    let mut lowering = lower::Lowering::new()?;
    for (ops, outputs) in tapes {
        lowering.add(ops, outputs)?;
    }
    lowering.finish()
}

/// Whether Cranelift has a back end for this host.
pub fn available() -> bool {
    cranelift_native::builder().is_ok()
}
