//! The tick state of a generated scene ([`SceneTick`]): a mechanism's [`Tick`] kept private,
//! because a scene's tick solves only what its outputs read. Generated scenes make and move it
//! through the hidden functions below (the `__private` ABI); users read it through their scene's
//! `outputs` and the accessors here.

use crate::solve::NewtonReport;
use crate::tick::Tick;

/// The state of a scene between simulator ticks (a generated scene's `NAME::Tick<T>`), made by
/// its `tick_start` and moved on by its `tick`; read the outputs with the scene's `outputs`
/// (`Scene::outputs`).
///
/// Inside is its mechanism's [`Tick`] for the kept blocks, with the same predictor and cached
/// sines and cosines. It is private because a scene's tick computes only what its outputs read:
/// the angle of a closed-form block whose sine and cosine alone are read (the link a point sits
/// on) is not computed, nor the direction of a link nothing reads, so those entries are stale.
/// `NI` inputs, `NU` unknowns, `NP` the scene's points, `NPAR` params, as in [`Tick`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneTick<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize> {
    state: Tick<T, NI, NU, NP, NPAR>,
}

impl<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>
    SceneTick<T, NI, NU, NP, NPAR>
{
    /// The inputs of the last tick.
    pub fn x(&self) -> &[T; NI] {
        &self.state.x
    }

    /// Their rates.
    pub fn xd(&self) -> &[T; NI] {
        &self.state.xd
    }

    /// The last position solve's report (iterations, residual, smallest pivot ratio).
    pub fn report(&self) -> &NewtonReport<T> {
        &self.state.report
    }
}

/// A scene's tick state around a solved mechanism tick (what a scene's `tick_start` makes).
#[doc(hidden)]
pub fn scene_tick<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>(
    state: Tick<T, NI, NU, NP, NPAR>,
) -> SceneTick<T, NI, NU, NP, NPAR> {
    SceneTick { state }
}

/// The mechanism tick inside (generated `outputs` read from it).
#[doc(hidden)]
#[inline(always)]
pub fn scene_tick_state<T, const NI: usize, const NU: usize, const NP: usize, const NPAR: usize>(
    t: &SceneTick<T, NI, NU, NP, NPAR>,
) -> &Tick<T, NI, NU, NP, NPAR> {
    &t.state
}

/// The mechanism tick inside, to move it (generated `tick`).
#[doc(hidden)]
#[inline(always)]
pub fn scene_tick_state_mut<
    T,
    const NI: usize,
    const NU: usize,
    const NP: usize,
    const NPAR: usize,
>(
    t: &mut SceneTick<T, NI, NU, NP, NPAR>,
) -> &mut Tick<T, NI, NU, NP, NPAR> {
    &mut t.state
}
