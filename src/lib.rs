//! mechgen: planar linkage kinematics. Loop-closure equations in `mechanism.toml` become, at build
//! time, allocation-free position, velocity and acceleration solvers (see `ARCHITECTURE.md`).
//!
//! ```
//! use mechgen::sixbar::{Inputs, Sixbar};
//! use mechgen::NewtonOptions;
//!
//! let sixbar = Sixbar::<f64>::default();
//! let (_, start) = Sixbar::<f64>::start();
//! let m = sixbar
//!     .solve(Inputs { q1: 0.0 }, Inputs { q1: 1.0 }, Inputs { q1: 0.0 }, start, &NewtonOptions::default())
//!     .unwrap();
//! assert!((m.q.q2 - 0.875_017_264_833_039).abs() < 1e-12);
//! ```

// Generated code names this crate `::mechgen`, also inside it.
extern crate self as mechgen;

pub mod closed_form;
pub mod dyad;
pub mod elimination;
pub mod error;
#[cfg(feature = "runtime")]
pub mod generic;
pub mod mechanism;
#[cfg(feature = "plot")]
pub mod plot;
pub mod report;
pub mod scalar;
pub mod solve;
pub mod sweep;
pub mod tick;
pub mod trig;

pub use dyad::solve_dyad;
pub use elimination::{
    Factored, copy_row_major, factor_block, gauss, gauss_in_place, lu_in_place, lu_solve,
    solve_block,
};
pub use error::{Quantity, SolveError, Stage};
pub use mechanism::{
    Array, CoordInfo, Kind, Kinematics, Mechanism, MechanismInfo, ParamInfo, PointMotion,
    StaticInfo, Visitor,
};
pub use nalgebra;
pub use scalar::Real;
pub use solve::{NewtonOptions, NewtonReport, check_finite, newton_block, newton_in_place};
pub use tick::{Solution, Tick};
pub use trig::{NewtonState, TrigState};

/// The solvers generated from the build's mechanism file (`mechanism.toml`, or `MECHGEN_MECHANISM`).
pub mod generated {
    include!(concat!(env!("OUT_DIR"), "/mechanisms.rs"));
}
pub use generated::*;

/// The mechanism file the solvers were generated from: `SOURCE_NAME` and `SOURCE` (its text), for
/// the generic engine ([`generic::load`]), drawings and `mechgen check`.
pub mod source {
    include!(concat!(env!("OUT_DIR"), "/mechanism_source.rs"));
}
