//! mechgen: planar linkage kinematics. Loop-closure equations in `mechanism.toml` become, at build
//! time, allocation-free position, velocity and acceleration solvers (see `ARCHITECTURE.md`).
//!
//! The crate is the application around the runtime: it re-exports `mechgen-runtime` (the scalar
//! trait, errors, traits, the kernels generated code calls) and holds the solvers generated from
//! the build's mechanism file ([`generated`], its modules also at the root), plus, behind
//! features, sweeps and reports (`sweep`), the generic engine (`runtime`), plots (`plot`) and the
//! command (`cli`).
//!
//! ```
//! use mechgen::sixbar::{Inputs, Sixbar};
//! use mechgen::{InputMotion, SolveOptions};
//!
//! let sixbar = Sixbar::<f64>::default();
//! let (_, start) = Sixbar::<f64>::start();
//! let input = InputMotion { x: Inputs { q1: 0.0 }, xd: Inputs { q1: 1.0 }, xdd: Inputs { q1: 0.0 } };
//! let m = sixbar.solve(&input, &start, &SolveOptions::default()).unwrap();
//! assert!((m.q.q2 - 0.875_017_264_833_039).abs() < 1e-12);
//! ```
//!
//! Root modules are few on purpose: [`runtime`], [`generated`], [`source`], `nalgebra`, and with
//! features `sweep`, `report`, `generic`, `plot`. A compiled-in mechanism is also re-exported at
//! the root (`mechgen::four_bar`) unless its name is one of these (or `mechgen`): then it is reached
//! as `mechgen::generated::NAME` (and by name through [`lookup`] and [`visit_all`] as always).

// Denied everywhere but in `generic::jit::code`, the one module that calls compiled code (a
// test holds every other file to it).
#![deny(unsafe_code)]
// A mechanism named `mechgen` is shadowed at the root by the private `extern crate self as mechgen`
// below, on purpose (like one named after a root module): it is `mechgen::generated::mechgen`.
#![allow(hidden_glob_reexports)]

// Generated code names this crate `::mechgen`, also inside it.
extern crate self as mechgen;

/// The runtime crate (`mechgen-runtime`): its modules (`mechgen::runtime::tick::RESYNC_TICKS`, …).
pub use mechgen_runtime as runtime;

#[doc(hidden)]
pub use mechgen_runtime::__private;
// The kernels (`dyad`, `closed_form`, `elimination`, `solve`, `trig`) are reached through
// `mechgen::runtime::…`; generated code reaches what it calls through `__private`.
/// Inverse dynamics, written once for every engine: `dynamics`, `inverse_dynamics`.
pub use mechgen_runtime::dynamics;
/// SIMD lanes: `mechgen::lanes::F64x4` and the other lane types, the [`Lanes`] trait.
pub use mechgen_runtime::lanes;
pub use mechgen_runtime::nalgebra;
/// Forward dynamics of one input (`Simulation`, error-controlled Dormand–Prince steps).
pub use mechgen_runtime::simulate;
/// The ticks on slices every engine gives (`DynMechanism::ticker`): `StaticTick`, `SolveTick`.
pub use mechgen_runtime::ticks;
pub use mechgen_runtime::{
    Array, BodyMass, BodyMotion, BodySink, CoordDesc, CoordInfo, DynMechanism, DynScene,
    DynSceneState, DynState, DynTick, InputMotion, Kind, LaneMechanism, LaneScene, LaneState,
    LaneTick, Lanes, MechanismInfo, NewtonOptions, NewtonReport, ParamDesc, ParamInfo, PointMotion,
    Quantity, Real, RowMajor, Scene, SceneDescription, SceneInfo, SceneState, SceneTick,
    SceneVisitor, SolveError, SolveOptions, Stage, State, StaticInfo, StaticMechanism,
    StaticVisitor, Tick, TickBodies,
};

#[cfg(feature = "sweep")]
pub mod batch;
#[cfg(feature = "sweep")]
pub mod design;
#[cfg(feature = "sweep")]
pub mod fleet;
#[cfg(feature = "runtime")]
pub mod generic;
#[cfg(feature = "sweep")]
pub mod kinetics;
#[cfg(feature = "runtime")]
pub mod metrics;
#[cfg(feature = "plot")]
pub mod plot;
#[cfg(feature = "sweep")]
pub mod report;
pub mod simulation;
#[cfg(feature = "sweep")]
pub mod sweep;

/// The generated solvers of a mechanism file, as a crate's own items: one module per mechanism
/// (`NAME::TypeName`, `NAME::Params`, …) and `MECHANISMS`, `lookup`, `visit_all`, from the file
/// that the crate's `build.rs` compiled with `mechgen_codegen::compile` (`OUT_DIR/mechanisms.rs`).
/// `include_mechanisms!("other.rs")` includes another output file of the build library
/// (`mechgen_codegen::Config::out_file`). The runtime's macro, re-exported.
pub use mechgen_runtime::include_mechanisms;

/// The solvers generated from the build's mechanism file (`mechanism.toml`, or `MECHGEN_MECHANISM`).
pub mod generated {
    crate::include_mechanisms!();
}
// Explicit root items (the modules above, the re-exports) shadow a mechanism of the same name:
// that one stays reachable as `mechgen::generated::NAME`.
pub use generated::*;

/// The mechanism file the solvers were generated from: `SOURCE_NAME` and `SOURCE` (its text), for
/// the generic engine ([`generic::load`]), drawings and `mechgen check`.
pub mod source {
    include!(concat!(env!("OUT_DIR"), "/mechanism_source.rs"));
}
#[cfg(feature = "runtime")]
pub mod branches;

/// The README's Rust blocks, compiled (and run, but for `no_run`) as doctests of this crate, so
/// that they cannot rot; `tests/readme.rs` holds the one `ignore` block, a downstream crate's
/// `src/main.rs`, to the file CI builds and runs.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

#[cfg(doctest)]
#[doc = include_str!("../docs/rust.md")]
pub struct RustDocDoctests;

#[cfg(doctest)]
#[doc = include_str!("../docs/cli.md")]
pub struct CliDocDoctests;
