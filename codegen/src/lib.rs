//! mechgen-codegen: mechanism.toml → Rust kinematics solvers, as a library for build scripts
//! ([`compile()`], [`Config`]) and for run-time engines ([`analyze`] and the types it returns).
//!
//! Stages, one folder each, chained by the short driver in `compile.rs`:
//! `front` (TOML + syn → syntax tree with spans) → `sema` (names, types, angles, values →
//! `Model`) → `ir` (the hash-consed DAG, lowering, derivatives) → `lints` (start check, overflow,
//! unused, structural errors) → `analysis` (block structure and the per-block plan → [`Compiled`])
//! → `emit` (one emitter per kind of output, identifiers from a names table; tokens →
//! `prettyplease`). [`diagnostic`] renders errors as FILE:LINE:COLUMN.
//!
//! The build library: [`compile()`]`("mechanism.toml")` in any crate's `build.rs` (or [`Config`] for
//! options) writes the solvers to `OUT_DIR`, for `mechgen::include_mechanisms!()`;
//! [`Config::try_compile`] returns the diagnostics instead of ending the build;
//! [`generate_source`] gives the code as a string.

// Float guards read better than float patterns.
#![allow(clippy::redundant_guards, clippy::needless_range_loop)]

mod analysis;
mod compile;
mod config;
pub mod diagnostic;
mod emit;
mod front;
mod ir;
mod keywords;
mod lints;
mod sema;
mod suggest;

pub use analysis::Compiled;
pub use analysis::closed_form::{ClosedForm, closed_form as classify_closed_form};
pub use analysis::compiled::plan_scenes;
pub use analysis::dyad::Dyad;
pub use analysis::plan::BlockForms;
pub use analysis::scene::{Order, ScenePlan};
pub use analysis::structure::{Block, BlockId};
pub use compile::analyze;
pub use config::{Config, Generated, compile, generate_source, runtime_of_manifest};
pub use diagnostic::{Diagnostic, Severity, SourceFile, Span};
pub use front::ast::{BinOp, Expr, ExprKind, Name};
pub use ir::dag::{Dag, Func, Node, NodeId, Var};
pub use ir::differentiate::Derivatives;
pub use ir::lower::{Chain, Equation, System, chains};
pub use sema::builtin::Builtin;
pub use sema::eval::derived_values;
pub use sema::model::{Body, Centre};
pub use sema::model::{Coord, Kind, Model, Param, Scene, Symbol};
pub use sema::resolved::{DerivedId, InputId, ParamId, UnknownId};
pub use suggest::nearest;
