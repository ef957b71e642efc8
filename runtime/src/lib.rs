//! mechgen-runtime: what the generated solvers of `mechgen-codegen` run on. The user-facing types
//! sit at the root (the scalar trait [`Real`], [`SolveError`], [`NewtonOptions`], the traits
//! [`StaticMechanism`] (static dispatch, generated code) and [`DynMechanism`] (object-safe, slices),
//! [`Tick`], [`SolveOptions`]); the functions generated code calls are its ABI,
//! re-exported under the hidden [`__private`] module, which is the only path generated code uses.
//!
//! A crate that embeds generated solvers depends on this crate alone (with `mechgen-codegen` as a
//! build-dependency: `mechgen_codegen::compile("mechanism.toml")` in `build.rs`, then
//! [`include_mechanisms!`]); applications depend on `mechgen`, which re-exports it. This crate
//! depends on nalgebra, num-traits, wide (SIMD vectors for [`lanes`]) and, with `std`, pulp (the
//! run-time choice of vector instructions, [`simd::dispatch`]) only and is `no_std` (with `alloc` for the owned `MechanismInfo`): the float
//! functions (`sin`, `cos`, `sqrt`, …) come through num-traits, from std with the default `std`
//! feature, from libm without it (`--no-default-features`, checked by CI).

#![no_std]
#![forbid(unsafe_code)]

// `MechanismInfo` (the owned description run-time engines share) holds strings and vectors.
extern crate alloc;
// With `std`, num-traits takes the float functions of f64 and f32 (`sin_cos`, `sqrt`, …) from std.
#[cfg(feature = "std")]
extern crate std;

pub mod closed_form;
pub mod dyad;
pub mod dyn_tick;
pub mod dynamic;
pub mod dynamics;
pub mod elimination;
pub mod error;
pub mod guard;
pub mod info;
pub mod lanes;
pub mod mechanism;
pub mod scalar;
pub mod scene;
pub mod scene_tick;
pub mod sensitivity;
pub mod simd;
pub mod simulate;
pub mod solve;
pub mod tick;
pub mod ticks;
pub mod trig;
pub mod twofold;

pub use dyn_tick::{DynTick, StateRef, Stride, Substep};
pub use dynamic::{DynMechanism, DynState};
pub use dynamics::{
    Dynamics, DynamicsWork, PointLoad, dyn_tick_dynamics, dynamics, inverse_dynamics,
    tick_dynamics, tick_with_dynamics,
};
pub use error::{Quantity, SolveError, Stage};
pub use info::{
    BodyMass, BodyMotion, CoordDesc, CoordInfo, Kind, MechanismInfo, ParamDesc, ParamInfo,
    PointMotion, StaticInfo,
};
pub use lanes::{LaneState, LaneTick, LaneView};
pub use mechanism::{
    Array, BodySink, InputMotion, LaneMechanism, RowMajor, State, StateOf, StaticMechanism,
    StaticVisitor, TickBodies,
};
pub use nalgebra;
pub use scalar::Real;
pub use scene::{
    DynScene, DynSceneState, LaneScene, LaneSceneOf, Scene, SceneDescription, SceneInfo,
    SceneState, SceneStateOf, SceneVisitor,
};
pub use scene_tick::{SceneMemo, SceneTick};
pub use sensitivity::Sensitivities;
pub use simd::{Lanes, WithLanes};
pub use simulate::{Simulation, SimulationOptions};
pub use solve::{NewtonOptions, NewtonReport, SolveOptions};
pub use tick::{Tick, TickStateOf};

/// Includes the solvers `mechgen_codegen::compile` (or `Config::compile`) generated in this
/// crate's build: one module per mechanism and scene of the file, named as in the file. With a
/// file name, the file a `Config::out_file` named (`include_mechanisms!("other.rs")`).
#[macro_export]
macro_rules! include_mechanisms {
    () => {
        include!(concat!(env!("OUT_DIR"), "/mechanisms.rs"));
    };
    ($file:literal) => {
        include!(concat!(env!("OUT_DIR"), "/", $file));
    };
}

/// The ABI of generated code: every item the generated solvers name, reached by them as
/// `<runtime path>::__private::…` (`::mechgen::__private::…` by default). Not a public API: it
/// changes with the generator, which always emits code for the runtime it ships with.
#[doc(hidden)]
pub mod __private {
    pub use crate::closed_form;
    pub use crate::dyad::{solve_dyad, solve_dyad_angles};
    pub use crate::dynamic::{DynMechanism, put as put_slice};
    pub use crate::elimination::factor_block;
    pub use crate::error::{Quantity, SolveError, Stage};
    pub use crate::info::{
        BodyMass, BodyMotion, CoordInfo, Kind, ParamInfo, PointMotion, StaticInfo,
    };
    pub use crate::lanes::{self, LaneTick, Lanes};
    pub use crate::mechanism::{
        BodySink, InputMotion, LaneMechanism, State, StateOf, StaticMechanism, StaticVisitor,
        TickBodies,
    };
    pub use crate::scalar::Real;
    pub use crate::scene::{
        DynScene, LaneScene, Scene, SceneInfo, SceneState, SceneStateOf, SceneVisitor,
    };
    pub use crate::scene_tick::{
        SceneMemo, SceneTick, scene_rates_estimated, scene_tick, scene_tick_join, scene_tick_parts,
        scene_tick_state, scene_tick_state_mut,
    };
    pub use crate::sensitivity::{Sensitivities, block_sensitivities, point_sensitivities};
    pub use crate::solve::{
        NewtonOptions, NewtonReport, SolveOptions, check_finite, check_finite_in, newton_block,
    };
    pub use crate::tick::{Solution, Tick, TickCache};
    pub use crate::trig::TrigState;
    pub use crate::twofold::{REFINE_BELOW, Twofold, refine_block};
    pub use nalgebra;

    /// A solve's rates and points: `(q̇, q̈, points)`.
    pub type Rates<T, const NU: usize, const NP: usize> = ([T; NU], [T; NU], [PointMotion<T>; NP]);
    /// [`Rates`] with the Newton report of the positions.
    pub type RatesReport<T, const NU: usize, const NP: usize> =
        ([T; NU], [T; NU], [PointMotion<T>; NP], NewtonReport<T>);
    /// What one generated solve reads besides the unknowns: the inputs, their rates (zero where
    /// a solve has none) and the sines and cosines of the inputs and params.
    #[derive(Clone, Copy, Debug)]
    pub struct Fixed<'a, T, const NI: usize, const NP: usize> {
        pub x: &'a [T; NI],
        pub xd: &'a [T; NI],
        pub xdd: &'a [T; NI],
        pub tx: &'a [(T, T); NI],
        pub tp: &'a [(T, T); NP],
    }

    /// The sines and cosines of the inputs and of the params: `(tx, tp)`.
    pub type TrigFixed<T, const NI: usize, const NP: usize> = ([(T, T); NI], [(T, T); NP]);

    /// The sines and cosines of the inputs, unknowns and params, borrowed: `(tx, tq, tp)`.
    pub type TrigRefs<'a, T, const NI: usize, const NU: usize, const NP: usize> =
        (&'a [(T, T); NI], &'a [(T, T); NU], &'a [(T, T); NP]);
}
