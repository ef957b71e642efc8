//! Generic engine, the JIT back end (feature `jit`): every tape of a loaded mechanism compiled
//! by Cranelift into one module of machine code, once per load; the block driver then calls the
//! compiled tapes where it interprets them otherwise (in f64; f32 and the double-word refinement
//! stay interpreted). Same instructions in the same order as the interpreter, no fused
//! multiply-add, the same `sin`/`cos`/`tan`/`atan2` functions: the same bits.

mod code;
mod lower;

pub use code::Function;

use super::op::Op;

/// Why a mechanism could not be compiled (the interpreter then runs it).
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum JitError {
    /// Cranelift has no back end for this host, or refused its settings.
    Host(String),
    /// Cranelift refused a function (a verifier or code-emission error).
    Compile(String),
    /// A tape that reads a register before writing it (an internal error).
    Tape,
}

impl std::fmt::Display for JitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            JitError::Host(e) => write!(f, "no JIT for this host: {e}"),
            JitError::Compile(e) => write!(f, "JIT compilation failed: {e}"),
            JitError::Tape => f.write_str("JIT compilation failed: a malformed tape"),
        }
    }
}

impl std::error::Error for JitError {}

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
