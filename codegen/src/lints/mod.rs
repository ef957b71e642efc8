//! Stage 4 (lints): checks that need the lowered system rather than the syntax: the start
//! configuration against the loops, non-finite constants, unused inputs and params, angle params
//! beyond a turn (degrees meant), and the
//! structural errors of the Jacobian told in the file's terms. Each returns diagnostics; none
//! changes the system.

mod degrees;
mod overflow;
pub mod start;
mod structure;
mod usage;

pub use degrees::degrees;
pub use overflow::{magnitudes, overflow};
pub use structure::structure_diagnostics;
pub use usage::usage;
