//! mechgen-codegen: mechanism.toml → Rust kinematics solvers.
//!
//! Pipeline (one module per stage, chained in [`mod@compile`]):
//! [`parse`] (TOML + syn, with spans) → [`check`] (names; [`typing`]: types, angles; [`eval`]: values) → [`lower`] (loops to
//! scalar residuals in the hash-consed [`dag`]) → [`differentiate`] (J, Φx, J̇, γ, points) →
//! [`structure`] (matching, block-triangular order) → [`plan`] (per-block forms, [`dyad`]: closed-form dyad blocks), [`start`] (the start configuration against the loops) → [`emit`]
//! (quote → prettyplease; [`emit_solve`]: the block solvers; every identifier it introduces comes
//! from a names table). [`diagnostic`] renders errors as FILE:LINE:COLUMN.
//!
//! The build library: [`compile`]`("mechanism.toml")` in any crate's `build.rs` (or [`Config`] for
//! options) writes the solvers to `OUT_DIR`, for `mechgen::include_mechanisms!()`;
//! [`generate_source`] gives the code as a string. [`build_script`] is mechgen's own build.

// Float guards read better than float patterns; `% 2` is the loop component parity.
#![allow(
    clippy::redundant_guards,
    clippy::manual_is_multiple_of,
    clippy::needless_range_loop
)]

pub mod ast;
pub mod build_script;
pub mod check;
pub mod compile;
mod config;
pub mod dag;
pub mod diagnostic;
pub mod differentiate;
pub mod dyad;
pub mod emit;
pub mod emit_body;
mod emit_module;
pub mod emit_motion;
pub mod emit_solve;
pub mod emit_system;
pub mod eval;
pub mod lower;
mod names;
pub mod parse;
mod parse_expr;
pub mod plan;
pub mod start;
pub mod structure;
pub mod typing;

pub use compile::{Compiled, analyze};
pub use config::{Config, Generated, compile, generate_source};
pub use diagnostic::{Diagnostic, Severity, SourceFile, Span};
