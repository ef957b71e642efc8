//! The JIT, its error: why a mechanism could not be compiled.

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
