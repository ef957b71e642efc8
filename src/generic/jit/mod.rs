//! Generic engine, the JIT back end (feature `jit`): every tape of a loaded mechanism compiled
//! by Cranelift into one module of machine code, once per load; the block driver then calls the
//! compiled tapes where it interprets them otherwise (in f64; f32 and the double-word refinement
//! stay interpreted). Same instructions in the same order as the interpreter, no fused
//! multiply-add, the same `sin`/`cos`/`tan`/`atan2` functions: the same bits.

mod abi;
mod code;
mod cold;
mod emit;
mod error;
mod fused;
mod imports;
mod inline;
mod lower;
mod prelude;
mod trace;

pub use abi::{FusedArgs, InputTrig, NOT_FINITE, Positions, Stages, TickPrelude};
pub use code::{Function, Fused, flat_points};
pub use error::JitError;

use super::op::Op;
use super::program::Program;

/// Compiles tapes, each given as its instructions and output registers, and a whole motion's
/// program into one module; the functions in the same order, and the program's.
pub(super) fn compile(
    tapes: &[(&[Op], &[u32])],
    program: Option<&Program>,
) -> Result<(Vec<Function>, Option<Fused>), JitError> {
    let mut lowering = lower::Lowering::new()?;
    for (ops, outputs) in tapes {
        lowering.add(ops, outputs)?;
    }
    if let Some(p) = program {
        lowering.add_program(p)?;
    }
    lowering.finish()
}

/// Whether Cranelift has a back end for this host.
pub fn available() -> bool {
    cranelift_native::builder().is_ok()
}
