//! SIMD lanes: W independent instances of one mechanism (each with its own params, inputs and
//! state) solved together, one instance per lane of a [`Lanes`] vector ([`F64x4`], [`F32x8`], …).
//!
//! The lane solvers run the scalar solvers' own operations lane by lane (IEEE arithmetic and
//! square roots are the same in a lane as in a scalar), so a lane that takes the common path of a
//! tick gives the scalar tick's result to the last bit. Every test a scalar tick branches on
//! (a dead point, a large turn, a condition below the refinement threshold, a cache due to be
//! recomputed, changed params, a non-finite value) is a mask here: the lanes it selects are
//! ticked again by the scalar tick from their unchanged state, which gives each its own result or
//! its own [`SolveError`](crate::SolveError). No lane ever changes another.

mod closed;
mod kernels;
mod lu;
mod newton;
mod start;
mod state;
mod tick;

pub use crate::simd::{
    F32x8, F32x16, F64x2, F64x4, F64x8, Isa, Kernel, Lanes, Vf32, Vf64, WithLanes, dispatch,
    dispatch_on,
};
pub use closed::{solve_angle1, solve_kind, solve_length1, solve_linear2, solve_rpr, solve_rrp};
pub use kernels::{
    LaneFactored, LaneTrig, factor_block, rotate, rotate_inputs, solve_dyad, solve_dyad_angles,
};
pub use lu::{LaneLu, lu};
pub use newton::{LaneReport, newton_block};
pub use start::tick_start;
pub use state::{LaneFixed, LaneRates, LaneState, LaneTick, LaneView, Memo, fresh_params_id};
pub use tick::{LanePath, LaneShape, ScalarLane, tick};
