//! Scenes: generated solvers that compute only what one use of a mechanism needs (the blocks its
//! outputs depend on, derivatives up to its order, its points). Every generated scene implements
//! [`Scene`] (static sizes, its own tick state); [`DynScene`] is its object-safe face over
//! slices (blanket impl), which `lookup_scene` returns; [`SceneVisitor`] visits them statically.

use alloc::string::{String, ToString};
use alloc::vec;
use alloc::vec::Vec;

use crate::dynamic::len;
use crate::error::SolveError;
use crate::mechanism::{Array, InputMotion};
use crate::scalar::Real;
use crate::simd::Lanes;
use crate::solve::{NewtonReport, SolveOptions};

/// Static description of a scene: what it keeps of its mechanism.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SceneInfo {
    pub name: &'static str,
    /// The mechanism it solves.
    pub mechanism: &'static str,
    /// 0 positions, 1 and velocities, 2 and accelerations.
    pub order: u8,
    /// Kept blocks (indices into the mechanism's blocks), in solve order.
    pub blocks: &'static [usize],
    /// Unknowns the kept blocks solve (indices into the mechanism's unknowns).
    pub solved: &'static [usize],
    /// Angles of kept closed-form blocks that no output reads itself (only through their sines
    /// and cosines, as a point on the link does): a tick solves their sines and cosines only.
    pub angles_skipped: &'static [usize],
    /// Output unknowns and points, by name.
    pub unknowns: &'static [&'static str],
    pub points: &'static [&'static str],
    /// The output columns in order (interfaces.md): per unknown `u`, `u_vel`, `u_acc`; per point
    /// `P_x`, `P_y`, `P_vx`, `P_vy`, `P_ax`, `P_ay`, up to the order.
    pub columns: &'static [&'static str],
}

/// The owned description of a scene, what run-time engines (the generic engine) share with
/// generated scenes through [`DynScene::info`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneDescription {
    pub name: String,
    pub mechanism: String,
    pub order: u8,
    pub blocks: Vec<usize>,
    pub solved: Vec<usize>,
    pub angles_skipped: Vec<usize>,
    pub unknowns: Vec<String>,
    pub points: Vec<String>,
    pub columns: Vec<String>,
}

impl From<&SceneInfo> for SceneDescription {
    fn from(s: &SceneInfo) -> Self {
        let strings = |v: &[&str]| v.iter().map(|n| n.to_string()).collect();
        SceneDescription {
            name: s.name.to_string(),
            mechanism: s.mechanism.to_string(),
            order: s.order,
            blocks: s.blocks.to_vec(),
            solved: s.solved.to_vec(),
            angles_skipped: s.angles_skipped.to_vec(),
            unknowns: strings(s.unknowns),
            points: strings(s.points),
            columns: strings(s.columns),
        }
    }
}

/// A generated scene: fixed sizes, arrays on the stack, no allocation. `X` and `Q` are its
/// mechanism's input and unknown arrays (unknowns outside the kept blocks are carried, never
/// solved); `Out` holds the output columns of [`SceneInfo::columns`].
pub trait Scene<T: Real>: Send + Sync {
    const NAME: &'static str;
    type X: Array<T>;
    type Q: Array<T>;
    type Out: Array<T>;
    /// The state between ticks (`tick_start`, `tick`).
    type Tick: Copy + PartialEq + core::fmt::Debug;
    /// W instances in the SIMD lanes `L` (the generated `NAME::Lanes<L>`).
    type Lanes<L: Lanes<Scalar = T>>: LaneScene<L, Scene = Self>;
    fn info(&self) -> &'static SceneInfo;
    /// The scene with the params `params`, in the order of its mechanism's params (`None`
    /// unless there are exactly that many).
    fn with_params(params: &[T]) -> Option<Self>
    where
        Self: Sized;
    /// Positions of the kept blocks from `guess`, then their rates up to the scene's order and
    /// the outputs.
    fn solve(
        &self,
        input: &InputMotion<Self::X>,
        guess: &Self::Q,
        options: &SolveOptions<T>,
    ) -> Result<SceneStateOf<Self, T>, SolveError>;
    /// [`Scene::solve`] into `state`: its inputs and rates are the input, its unknowns the
    /// guess; on success it holds the solution, on error it is unchanged.
    fn solve_in_place(
        &self,
        state: &mut SceneStateOf<Self, T>,
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError> {
        *state = self.solve(&state.input(), &state.q, options)?;
        Ok(())
    }
    /// The first tick of a simulation.
    fn tick_start(
        &self,
        input: &InputMotion<Self::X>,
        guess: &Self::Q,
        options: &SolveOptions<T>,
    ) -> Result<Self::Tick, SolveError>;
    /// One tick to `input` (same predictor and trig caching as the mechanism's tick).
    fn tick(
        &self,
        t: &mut Self::Tick,
        input: &InputMotion<Self::X>,
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError>;
    /// The outputs a tick state holds.
    fn outputs(&self, t: &Self::Tick) -> Self::Out;
    /// The report of a tick state's last position solve (Newton iterations, residual, pivot).
    fn report(&self, t: &Self::Tick) -> NewtonReport<T>;
}

/// W instances of a generated scene in SIMD lanes (`NAME::Lanes<L>`, see `crate::lanes`), for
/// code generic over scenes. Lane `i` of every value is instance `i`; each lane's outputs, state
/// and status are its scalar tick's, bit for bit.
pub trait LaneScene<L: Lanes>: Sized + Send + Sync {
    /// One instance.
    type Scene: Scene<L::Scalar>;
    /// `[L; INPUTS]`
    type X: Copy + Default + AsRef<[L]> + AsMut<[L]> + Send + Sync;
    /// `[L; UNKNOWNS]`
    type Q: Copy + Default + AsRef<[L]> + AsMut<[L]> + Send + Sync;
    /// `[L; COLUMNS]`: the output columns in lanes.
    type Out: Copy + AsRef<[L]>;
    /// The state between lane ticks (`NAME::LaneTick<L>`).
    type Tick: Clone + Send + Sync;
    /// Instance `i` is `f(i)`.
    fn from_fn(f: impl FnMut(usize) -> Self::Scene) -> Self;
    /// Sets instance `i` (`BadLength` for `i ≥ W`).
    fn set(&mut self, i: usize, s: Self::Scene) -> Result<(), SolveError>;
    /// The first tick of every instance from its lane of `guess`.
    fn tick_start(
        &self,
        input: &InputMotion<Self::X>,
        guess: &Self::Q,
        options: &SolveOptions<L::Scalar>,
    ) -> Self::Tick;
    /// One tick of every instance to its lane of `input`.
    fn tick(
        &self,
        t: &mut Self::Tick,
        input: &InputMotion<Self::X>,
        options: &SolveOptions<L::Scalar>,
    );
    /// The output columns of every lane (a lane that never started holds zeros).
    fn outputs(t: &Self::Tick) -> Self::Out;
    /// Instance `i`: the status of its last tick and its state as the scalar tick (`None` for
    /// `i ≥ W`).
    fn lane(t: &Self::Tick, i: usize) -> Option<LaneSceneOf<L, Self>>;
    /// [`tick`](Self::tick) with the widest vector instructions of the CPU, chosen at run time
    /// (as [`LaneMechanism::tick_widest`](crate::LaneMechanism::tick_widest)).
    #[inline]
    fn tick_widest(
        &self,
        t: &mut Self::Tick,
        input: &InputMotion<Self::X>,
        options: &SolveOptions<L::Scalar>,
    ) {
        crate::simd::dispatch(LaneTickKernel {
            lanes: self,
            t,
            input,
            options,
        });
    }
    /// [`tick`](Self::tick) compiled with the instruction set `isa`
    /// ([`dispatch_on`](crate::simd::dispatch_on)); false (and `t` unchanged) where this CPU
    /// does not have it. The same results on every instruction set.
    #[inline]
    fn tick_on(
        &self,
        isa: crate::simd::Isa,
        t: &mut Self::Tick,
        input: &InputMotion<Self::X>,
        options: &SolveOptions<L::Scalar>,
    ) -> bool {
        let kernel = LaneTickKernel {
            lanes: self,
            t,
            input,
            options,
        };
        crate::simd::dispatch_on(isa, kernel).is_ok()
    }
}

/// [`LaneScene::tick`] as a [`Kernel`](crate::simd::Kernel).
struct LaneTickKernel<'a, L: Lanes, S: LaneScene<L>> {
    lanes: &'a S,
    t: &'a mut S::Tick,
    input: &'a InputMotion<S::X>,
    options: &'a SolveOptions<L::Scalar>,
}

impl<L: Lanes, S: LaneScene<L>> crate::simd::Kernel for LaneTickKernel<'_, L, S> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        self.lanes.tick(self.t, self.input, self.options);
    }
}

/// What [`LaneScene::lane`] gives for one lane: its status and scalar tick state.
pub type LaneSceneOf<L, S> = (
    Result<(), SolveError>,
    <<S as LaneScene<L>>::Scene as Scene<<L as Lanes>::Scalar>>::Tick,
);

/// Generic code over every compiled-in scene, statically typed (`visit_scenes`).
pub trait SceneVisitor<T: Real> {
    fn visit<S: Scene<T> + 'static>(&mut self, scene: &S);
}

/// The object-safe face of a [`Scene`] over slices (lengths checked: `SolveError::BadLength`).
pub trait DynScene<T: Real> {
    fn info(&self) -> SceneDescription;
    /// As [`Scene::solve`], into a new [`DynSceneState`] (the allocating form of
    /// [`DynScene::solve_in_place`]).
    fn solve(
        &self,
        input: InputMotion<&[T]>,
        guess: &[T],
        options: &SolveOptions<T>,
    ) -> Result<DynSceneState<T>, SolveError> {
        let mut state = DynSceneState::new(input, guess, self.info().columns.len());
        self.solve_in_place(&mut state, options)?;
        Ok(state)
    }
    /// As [`Scene::solve_in_place`]: `q` has the mechanism's unknowns, `out` one value per
    /// column (lengths checked: `SolveError::BadLength`).
    fn solve_in_place(
        &self,
        state: &mut DynSceneState<T>,
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError>;
}

/// A solved scene, the shape of [`crate::State`] with the scene's outputs: the inputs with
/// their rates, the mechanism's unknowns (the kept blocks' solved, the others as guessed), the
/// output columns and the position solve's report. A generated scene's `NAME::Solved<T>` is one
/// with named fields.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneState<X, Q, O, T> {
    pub x: X,
    pub xd: X,
    pub xdd: X,
    pub q: Q,
    pub out: O,
    pub report: NewtonReport<T>,
}

impl<X: Clone, Q, O, T> SceneState<X, Q, O, T> {
    /// The inputs with their rates.
    pub fn input(&self) -> InputMotion<X> {
        InputMotion::new(self.x.clone(), self.xd.clone(), self.xdd.clone())
    }
}

/// The [`SceneState`] of a [`Scene`] `S`: its input, unknown and output arrays.
pub type SceneStateOf<S, T> =
    SceneState<<S as Scene<T>>::X, <S as Scene<T>>::Q, <S as Scene<T>>::Out, T>;

/// The [`SceneState`] of a [`DynScene`]: vectors.
pub type DynSceneState<T> = SceneState<Vec<T>, Vec<T>, Vec<T>, T>;

impl<T: Real> DynSceneState<T> {
    /// A state at `input` with the unknowns `guess` and `columns` zero outputs.
    pub fn new(input: InputMotion<&[T]>, guess: &[T], columns: usize) -> Self {
        SceneState {
            x: input.x.to_vec(),
            xd: input.xd.to_vec(),
            xdd: input.xdd.to_vec(),
            q: guess.to_vec(),
            out: vec![T::zero(); columns],
            report: NewtonReport::new(),
        }
    }

    /// The inputs with their rates, as slices.
    pub fn input_slices(&self) -> InputMotion<&[T]> {
        InputMotion::new(&self.x, &self.xd, &self.xdd)
    }
}

fn arr<T: Real, A: Array<T>>(s: &[T]) -> Result<A, SolveError> {
    let mut a = A::zeros();
    len(s, a.as_ref().len())?;
    a.as_mut().copy_from_slice(s);
    Ok(a)
}

impl<T: Real, S: Scene<T>> DynScene<T> for S {
    fn info(&self) -> SceneDescription {
        Scene::info(self).into()
    }
    fn solve_in_place(
        &self,
        state: &mut DynSceneState<T>,
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError> {
        let input: InputMotion<S::X> =
            InputMotion::new(arr(&state.x)?, arr(&state.xd)?, arr(&state.xdd)?);
        len(&state.out, S::Out::zeros().as_ref().len())?;
        let s = Scene::solve(self, &input, &arr(&state.q)?, options)?;
        state.q.copy_from_slice(s.q.as_ref());
        state.out.copy_from_slice(s.out.as_ref());
        state.report = s.report;
        Ok(())
    }
}
