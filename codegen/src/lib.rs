//! mechgen-codegen: mechanism.toml → Rust kinematics solvers.
//!
//! Pipeline (one module per stage, chained in [`mod@compile`]):
//! [`parse`] (TOML + syn, with spans) → [`check`] (names; [`typing`]: types, angles; [`eval`]: values) → [`lower`] (loops to
//! scalar residuals in the hash-consed [`dag`]) → [`differentiate`] (J, Φx, J̇, γ, points) →
//! [`structure`] (matching, block-triangular order) → [`plan`] (per-block forms, [`dyad`]: closed-form dyad blocks), [`start`] (the start configuration against the loops) → [`emit`]
//! (quote → prettyplease; [`emit_solve`]: the block solvers). [`diagnostic`] renders errors as FILE:LINE:COLUMN; [`build_script`] is
//! the entry point for a `build.rs`.

// Float guards read better than float patterns; `% 2` is the loop component parity.
#![allow(
    clippy::redundant_guards,
    clippy::manual_is_multiple_of,
    clippy::needless_range_loop
)]

pub mod ast;
pub mod build_script;
pub mod check;
pub mod closed_form;
pub mod compile;
pub mod dag;
pub mod diagnostic;
pub mod differentiate;
pub mod dyad;
pub mod emit;
pub mod emit_body;
pub mod emit_motion;
pub mod emit_solve;
pub mod emit_system;
pub mod eval;
pub mod lower;
pub mod parse;
mod parse_expr;
pub mod plan;
pub mod start;
pub mod structure;
pub mod typing;

pub use compile::{Compiled, analyze, compile};
pub use diagnostic::{Diagnostic, Severity, SourceFile, Span};
