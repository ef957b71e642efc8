//! The static-dispatch trait generated mechanisms implement, [`StaticMechanism`] (sizes known at
//! compile time, fixed arrays, nalgebra matrices, no allocation), its [`StaticVisitor`], and the
//! bundles its solves take and give: [`InputMotion`] (inputs with their rates) and [`State`] (the
//! one solved state every solve returns and every tick keeps). The object-safe counterpart on
//! slices is [`crate::DynMechanism`].

use crate::error::SolveError;
use crate::info::{BodyMass, BodyMotion, PointMotion, StaticInfo};
use crate::scalar::Real;
use crate::sensitivity::Sensitivities;
use crate::simd::Lanes;
use crate::solve::{NewtonReport, SolveOptions};
use nalgebra::SMatrix;

/// The inputs of a tick with their first and second time derivatives: `x`, `ẋ`, `ẍ`. `X` is the
/// typed `Inputs<T>` of a generated module, `[T; N]` in [`StaticMechanism`], `&[T]` in
/// [`crate::DynMechanism`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InputMotion<X> {
    pub x: X,
    pub xd: X,
    pub xdd: X,
}

impl<X> InputMotion<X> {
    /// Inputs `x` moving at `xd` with acceleration `xdd`.
    pub fn new(x: X, xd: X, xdd: X) -> Self {
        InputMotion { x, xd, xdd }
    }

    /// Each of the three converted by `f` (e.g. `Inputs::to_array`).
    pub fn map<Y>(&self, mut f: impl FnMut(&X) -> Y) -> InputMotion<Y> {
        InputMotion {
            x: f(&self.x),
            xd: f(&self.xd),
            xdd: f(&self.xdd),
        }
    }
}

/// The solved state of a mechanism, the one shape every whole solve gives: the inputs with their
/// rates, the unknowns with theirs, every point's motion and the position solve's report.
///
/// [`StaticMechanism::solve`] returns one (`X`, `Q` arrays, `P` the points' array), a generated
/// `NAME::Motion<T>` is the same with named fields (`Inputs<T>`, `Unknowns<T>`, `Points<T>`), a
/// tick keeps one (a [`crate::Tick`] reads as its state), and [`crate::DynMechanism`] fills a
/// [`crate::DynState`] (vectors). `solve_in_place` reads the inputs and the guess from a state
/// and writes the solution into it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct State<X, Q, P, T> {
    pub x: X,
    pub xd: X,
    pub xdd: X,
    pub q: Q,
    pub qd: Q,
    pub qdd: Q,
    pub points: P,
    pub report: NewtonReport<T>,
}

impl<X: Clone, Q, P, T> State<X, Q, P, T> {
    /// The inputs with their rates.
    pub fn input(&self) -> InputMotion<X> {
        InputMotion::new(self.x.clone(), self.xd.clone(), self.xdd.clone())
    }
}

/// Gravity, the bodies' masses and their motion, as [`StaticMechanism::with_tick_bodies`] hands
/// them over.
pub type TickBodies<'a, T> = ([T; 2], &'a [BodyMass<T>], &'a [BodyMotion<T>]);

/// What a tick hands its bodies to as it computes them ([`StaticMechanism::tick_with_sink`]):
/// gravity, then every body in `info().bodies` order, so that a consumer such as the inverse
/// dynamics' sums takes them straight from the tick's registers, nothing stored in between.
pub trait BodySink<T> {
    /// The acceleration of gravity (zero without a `gravity` key).
    fn gravity(&mut self, gravity: [T; 2]);
    /// Body `index`'s mass properties and motion.
    fn body(&mut self, index: usize, mass: BodyMass<T>, motion: BodyMotion<T>);
}

/// A sink behind a reference (what a tick on slices, `DynTick::tick_with_sink`, is handed).
impl<T, S: BodySink<T> + ?Sized> BodySink<T> for &mut S {
    #[inline(always)]
    fn gravity(&mut self, gravity: [T; 2]) {
        (**self).gravity(gravity);
    }
    #[inline(always)]
    fn body(&mut self, index: usize, mass: BodyMass<T>, motion: BodyMotion<T>) {
        (**self).body(index, mass, motion);
    }
}

/// Arrays of a mechanism's own sizes as a sink: masses, motion, gravity.
impl<T, const N: usize> BodySink<T> for ([BodyMass<T>; N], [BodyMotion<T>; N], [T; 2]) {
    #[inline(always)]
    fn gravity(&mut self, gravity: [T; 2]) {
        self.2 = gravity;
    }
    #[inline(always)]
    fn body(&mut self, index: usize, mass: BodyMass<T>, motion: BodyMotion<T>) {
        if let (Some(m), Some(b)) = (self.0.get_mut(index), self.1.get_mut(index)) {
            (*m, *b) = (mass, motion);
        }
    }
}

/// The [`State`] of a [`StaticMechanism`] `M`: its input, unknown and point arrays.
pub type StateOf<M, T> = State<
    <M as StaticMechanism<T>>::X,
    <M as StaticMechanism<T>>::Q,
    <M as StaticMechanism<T>>::Points,
    T,
>;

/// A fixed-size coordinate array (`[T; N]`).
pub trait Array<T>:
    Copy + AsRef<[T]> + AsMut<[T]> + core::fmt::Debug + Send + Sync + 'static
{
    fn zeros() -> Self;
}

impl<T: Real, const N: usize> Array<T> for [T; N] {
    fn zeros() -> Self {
        [T::zero(); N]
    }
}

/// A fixed-size matrix that can be written row-major into a slice of exactly its size.
pub trait RowMajor<T>: Copy + core::fmt::Debug {
    /// Row-major into `out`; `SolveError::BadLength` unless `out` holds exactly rows × columns.
    fn write_row_major(&self, out: &mut [T]) -> Result<(), SolveError>;
}

impl<T: Real, const R: usize, const C: usize> RowMajor<T> for SMatrix<T, R, C> {
    fn write_row_major(&self, out: &mut [T]) -> Result<(), SolveError> {
        crate::error::len(out, R * C)?;
        for (i, row) in out.chunks_exact_mut(C.max(1)).enumerate().take(R) {
            for (j, o) in row.iter_mut().enumerate() {
                *o = self[(i, j)];
            }
        }
        Ok(())
    }
}

/// A generated mechanism, with static dispatch: sizes as associated consts, coordinates as fixed
/// arrays, matrices as nalgebra `SMatrix`, no allocation. The generated module's own methods are
/// the typed form of the same (named `Inputs`, `Unknowns`, `Points` structs); every
/// `StaticMechanism` is also a [`crate::DynMechanism`].
pub trait StaticMechanism<T: Real>: Clone + Send + Sync {
    const NAME: &'static str;
    const INPUTS: usize;
    const UNKNOWNS: usize;
    const POINTS: usize;
    /// `[T; INPUTS]`
    type X: Array<T>;
    /// `[T; UNKNOWNS]`
    type Q: Array<T>;
    /// `[PointMotion<T>; POINTS]`
    type Points: Copy + AsRef<[PointMotion<T>]> + core::fmt::Debug + Send + Sync + 'static;
    /// J and J̇: `SMatrix<T, UNKNOWNS, UNKNOWNS>`.
    type Jacobian: RowMajor<T>;
    /// Φx: `SMatrix<T, UNKNOWNS, INPUTS>`.
    type InputJacobian: RowMajor<T>;
    /// dq/dp: `SMatrix<T, UNKNOWNS, PARAMS>`.
    type ParamJacobian: RowMajor<T>;
    /// dP/dp: `SMatrix<T, 2 × POINTS, PARAMS>` (rows `P_x`, `P_y` per point).
    type PointParamJacobian: RowMajor<T>;
    /// The state between simulator ticks: a [`crate::Tick`] of this mechanism's sizes (see there
    /// for what it holds), which reads as its [`State`].
    type Tick: Copy
        + PartialEq
        + core::fmt::Debug
        + Send
        + Sync
        + 'static
        + core::ops::Deref<Target = State<Self::X, Self::Q, Self::Points, T>>;
    /// W instances in the SIMD lanes `L` (the generated `NAME::Lanes<L>`).
    type Lanes<L: Lanes<Scalar = T>>: LaneMechanism<L, Mechanism = Self>;

    fn info(&self) -> &'static StaticInfo;
    /// The mechanism with the params `params`, in the order of `info().params` (`None` unless
    /// there are exactly that many).
    fn with_params(params: &[T]) -> Option<Self>
    where
        Self: Sized;
    /// Φ(x, q).
    fn residual(&self, x: &Self::X, q: &Self::Q) -> Self::Q;
    /// J = ∂Φ/∂q.
    fn jacobian(&self, x: &Self::X, q: &Self::Q) -> Self::Jacobian;
    /// Φx = ∂Φ/∂x.
    fn input_jacobian(&self, x: &Self::X, q: &Self::Q) -> Self::InputJacobian;
    /// J̇.
    fn jacobian_dot(&self, x: &Self::X, q: &Self::Q, xd: &Self::X, qd: &Self::Q) -> Self::Jacobian;
    /// γ with J q̈ = γ.
    fn acceleration_rhs(
        &self,
        x: &Self::X,
        q: &Self::Q,
        xd: &Self::X,
        qd: &Self::Q,
        xdd: &Self::X,
    ) -> Self::Q;
    /// Positions block by block from the guess in `q`; on success `q` is the solution.
    fn solve_position(
        &self,
        x: &Self::X,
        q: &mut Self::Q,
        options: &SolveOptions<T>,
    ) -> Result<NewtonReport<T>, SolveError>;
    /// q̇ at a solved position.
    fn solve_velocity(&self, x: &Self::X, q: &Self::Q, xd: &Self::X)
    -> Result<Self::Q, SolveError>;
    /// q̈ at a solved position and velocity.
    fn solve_acceleration(
        &self,
        x: &Self::X,
        q: &Self::Q,
        xd: &Self::X,
        qd: &Self::Q,
        xdd: &Self::X,
    ) -> Result<Self::Q, SolveError>;
    /// The design derivatives at a solved position (see [`Sensitivities`]); a block singular
    /// there is `Singular` at stage `Sensitivity`.
    fn sensitivities(
        &self,
        x: &Self::X,
        q: &Self::Q,
    ) -> Result<Sensitivities<Self::ParamJacobian, Self::PointParamJacobian>, SolveError>;
    /// [`StaticMechanism::sensitivities`] at a tick's state, with the sines and cosines it keeps.
    fn tick_sensitivities(
        &self,
        t: &Self::Tick,
    ) -> Result<Sensitivities<Self::ParamJacobian, Self::PointParamJacobian>, SolveError>;
    /// Every point's motion at a solved state.
    fn points(
        &self,
        input: &InputMotion<Self::X>,
        q: &Self::Q,
        qd: &Self::Q,
        qdd: &Self::Q,
    ) -> Self::Points;
    /// Every body's motion at a solved state into `out` (one per `info().bodies`). A
    /// mechanism without bodies has the default: `out` must be empty.
    fn bodies(
        &self,
        input: &InputMotion<Self::X>,
        q: &Self::Q,
        qd: &Self::Q,
        qdd: &Self::Q,
        out: &mut [BodyMotion<T>],
    ) -> Result<(), SolveError> {
        let _ = (input, q, qd, qdd);
        crate::error::len(out, 0)
    }
    /// Every body's mass and inertia at the current params into `out` (one per
    /// `info().bodies`); returns the acceleration of gravity (zero without a `gravity` key).
    fn mass_properties(&self, out: &mut [BodyMass<T>]) -> Result<[T; 2], SolveError> {
        crate::error::len(out, 0)?;
        Ok([T::zero(); 2])
    }
    /// Gravity, every body's mass and inertia ([`StaticMechanism::mass_properties`]) and motion
    /// ([`StaticMechanism::bodies`]) at the tick's state, on the sines and cosines the tick
    /// keeps, handed to `f` in arrays of the mechanism's own sizes: what inverse dynamics after
    /// a tick reads ([`crate::dynamics::tick_dynamics`]). A mechanism without bodies has the
    /// default: no bodies and no gravity.
    fn with_tick_bodies<R>(&self, t: &Self::Tick, f: impl FnOnce(TickBodies<'_, T>) -> R) -> R {
        let _ = t;
        f(([T::zero(); 2], &[], &[]))
    }
    /// A tick ([`StaticMechanism::tick`]), then `f` on the ticked state with its bodies as
    /// [`StaticMechanism::with_tick_bodies`] gives them (`f`'s result is the call's); a generated
    /// mechanism with bodies computes them in the tick's own body, sharing the points'
    /// subexpressions. On a tick's error `t` is unchanged and `f` is not called.
    fn tick_with_bodies<R>(
        &self,
        t: &mut Self::Tick,
        input: &InputMotion<Self::X>,
        options: &SolveOptions<T>,
        f: impl FnOnce(&Self::Tick, TickBodies<'_, T>) -> Result<R, SolveError>,
    ) -> Result<R, SolveError> {
        self.tick(t, input, options)?;
        self.with_tick_bodies(t, |b| f(t, b))
    }
    /// A tick ([`StaticMechanism::tick`]) that hands gravity and every body to `sink` as it
    /// computes them (a generated mechanism with bodies: in the tick's own body, sharing the
    /// points' subexpressions; by default: after the tick, from
    /// [`StaticMechanism::with_tick_bodies`]). On error `t` is unchanged and `sink` may have
    /// been handed some bodies.
    fn tick_with_sink<S: BodySink<T>>(
        &self,
        t: &mut Self::Tick,
        input: &InputMotion<Self::X>,
        options: &SolveOptions<T>,
        sink: &mut S,
    ) -> Result<(), SolveError> {
        self.tick(t, input, options)?;
        self.with_tick_bodies(t, |(gravity, masses, motion)| {
            sink.gravity(gravity);
            for (k, (m, b)) in masses.iter().zip(motion).enumerate() {
                sink.body(k, *m, *b);
            }
        });
        Ok(())
    }
    /// One whole tick from `guess`: positions, velocities, accelerations and points, sharing the
    /// trigonometry between the stages (the fastest way to a full state without a [`Self::Tick`]).
    fn solve(
        &self,
        input: &InputMotion<Self::X>,
        guess: &Self::Q,
        options: &SolveOptions<T>,
    ) -> Result<StateOf<Self, T>, SolveError>;
    /// [`StaticMechanism::solve`] into `state`: its inputs and rates are the input, its unknowns
    /// the guess; on success it holds the solution, on error it is unchanged.
    fn solve_in_place(
        &self,
        state: &mut StateOf<Self, T>,
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError> {
        *state = self.solve(&state.input(), &state.q, options)?;
        Ok(())
    }
    /// The first tick of a simulation, solved from `guess` (see [`StaticMechanism::tick`]).
    fn tick_start(
        &self,
        input: &InputMotion<Self::X>,
        guess: &Self::Q,
        options: &SolveOptions<T>,
    ) -> Result<Self::Tick, SolveError>;
    /// One simulator tick from the state `t` to `input`: a second-order predictor, the cached
    /// sines and cosines rotated, then positions, velocities, accelerations and points. On error
    /// `t` is unchanged.
    fn tick(
        &self,
        t: &mut Self::Tick,
        input: &InputMotion<Self::X>,
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError>;
}

/// Generic code run on every compiled-in mechanism by `visit_all`, with static dispatch.
pub trait StaticVisitor<T: Real> {
    fn visit<M: StaticMechanism<T> + 'static>(&mut self, mechanism: &M);
}

/// One instance of a [`LaneMechanism`] `M`: the status of its last tick and its scalar tick.
pub type LaneOf<L, M> = (
    Result<(), SolveError>,
    <<M as LaneMechanism<L>>::Mechanism as StaticMechanism<<L as Lanes>::Scalar>>::Tick,
);

/// W instances of a generated mechanism in SIMD lanes (`NAME::Lanes<L>`, see `crate::lanes`),
/// for code generic over mechanisms (the batch API, benches, tests). Lane `i` of every value
/// is instance `i`; each lane's result or error is its scalar tick's.
pub trait LaneMechanism<L: Lanes>: Sized + Send + Sync {
    /// One instance.
    type Mechanism: StaticMechanism<L::Scalar>;
    /// `[L; INPUTS]`
    type X: Copy + Default + AsRef<[L]> + AsMut<[L]> + Send + Sync;
    /// `[L; UNKNOWNS]`
    type Q: Copy + Default + AsRef<[L]> + AsMut<[L]> + Send + Sync;
    /// The state between lane ticks (`NAME::LaneTick<L>`).
    type Tick: Clone + Send + Sync + crate::lanes::LaneView<L>;
    /// Instance `i` is `f(i)`.
    fn from_fn(f: impl FnMut(usize) -> Self::Mechanism) -> Self;
    /// Sets instance `i` (`BadLength` for `i ≥ W`).
    fn set(&mut self, i: usize, m: Self::Mechanism) -> Result<(), SolveError>;
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
    /// Instance `i`: the status of its last tick and its state as the scalar tick (`None` for
    /// `i ≥ W`).
    fn lane(t: &Self::Tick, i: usize) -> Option<LaneOf<L, Self>>;
    /// [`tick`](Self::tick) compiled with the widest vector instructions of the CPU, chosen at
    /// run time ([`dispatch`](crate::simd::dispatch)): with [`Vf64<8>`](crate::simd::Vf64)
    /// lanes one AVX-512 register, two AVX2 ones or four SSE2 ones. The same results as `tick`.
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

/// [`LaneMechanism::tick`] as a [`Kernel`](crate::simd::Kernel).
struct LaneTickKernel<'a, L: Lanes, M: LaneMechanism<L>> {
    lanes: &'a M,
    t: &'a mut M::Tick,
    input: &'a InputMotion<M::X>,
    options: &'a SolveOptions<L::Scalar>,
}

impl<L: Lanes, M: LaneMechanism<L>> crate::simd::Kernel for LaneTickKernel<'_, L, M> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        self.lanes.tick(self.t, self.input, self.options);
    }
}
