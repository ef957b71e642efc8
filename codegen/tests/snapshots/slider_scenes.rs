        pub(super) fn scene_rod_motion(
            &self,
            fixed: ::mechgen::__private::Fixed<'_, T, 1, 2>,
            st: &mut ::mechgen::__private::TrigState<T, 2>,
            options: &::mechgen::__private::SolveOptions<T>,
            report: &mut ::mechgen::__private::NewtonReport<T>,
        ) -> ::core::result::Result<
            ::mechgen::__private::Rates<T, 2, 0>,
            ::mechgen::__private::SolveError,
        > {
            let ::mechgen::__private::Fixed { x, tx, tp, .. } = fixed;
            let qd = [T::zero(); 2];
            let qdd = [T::zero(); 2];
            // Block 0: closed form (one angle).
            let p_l1 = self.params.l1;
            let p_l2 = self.params.l2;
            let (s_v_q1, _) = tx[0];
            let t0 = p_l1 * s_v_q1;
            if options.closed_forms {
                ::mechgen::__private::closed_form::solve_angle1(
                    0,
                    st,
                    0,
                    t0,
                    (T::zero(), p_l2),
                    || self.scene_rod_length_scale(),
                    options.newton.tolerance,
                    report,
                    true,
                )?;
            } else {
                ::mechgen::__private::newton_block(
                    0,
                    st,
                    [0],
                    [false],
                    self.scene_rod_length_scale(),
                    &options.newton,
                    report,
                    |st| self.block0_position(x, &st.q, tx, tp, &st.sc),
                )?;
            }
            // Near a dead point: one Newton step per block with its residual in double words.
            if report.pivot_ratio < T::lit(::mechgen::__private::REFINE_BELOW) {
                self.block0_refine(x, st, tx, tp);
            }
            // Points.
            Ok((qd, qdd, []))
        }
        /// Scene `rod`: its pruned solver.
        #[doc(hidden)]
        #[inline]

        pub(super) fn scene_crank_pin_motion(
            &self,
            fixed: ::mechgen::__private::Fixed<'_, T, 1, 2>,
            _st: &mut ::mechgen::__private::TrigState<T, 2>,
            _options: &::mechgen::__private::SolveOptions<T>,
            report: &mut ::mechgen::__private::NewtonReport<T>,
        ) -> ::core::result::Result<
            ::mechgen::__private::Rates<T, 2, 1>,
            ::mechgen::__private::SolveError,
        > {
            let ::mechgen::__private::Fixed { xd, tx, .. } = fixed;
            let mut qd = [T::zero(); 2];
            let qdd = [T::zero(); 2];
            // Near a dead point: one Newton step per block with its residual in double words.
            if report.pivot_ratio < T::lit(::mechgen::__private::REFINE_BELOW) {}
            // Points.
            let p_l1 = self.params.l1;
            let v_q1_d = xd[0];
            let (s_v_q1, c_v_q1) = tx[0];
            let t0 = p_l1 * c_v_q1;
            let t1 = p_l1 * s_v_q1;
            let t2 = t1 * v_q1_d;
            let t3 = -t2;
            let t4 = t0 * v_q1_d;
            Ok((
                qd,
                qdd,
                [
                    ::mechgen::__private::PointMotion {
                        position: [t0, t1],
                        velocity: [t3, t4],
                        acceleration: [T::zero(), T::zero()],
                    },
                ],
            ))
        }
        /// Scene `crank_pin`: its pruned solver.
        #[doc(hidden)]
        #[inline]

        pub(super) fn scene_rod_middle_motion(
            &self,
            fixed: ::mechgen::__private::Fixed<'_, T, 1, 2>,
            st: &mut ::mechgen::__private::TrigState<T, 2>,
            options: &::mechgen::__private::SolveOptions<T>,
            report: &mut ::mechgen::__private::NewtonReport<T>,
            every_angle: bool,
        ) -> ::core::result::Result<
            ::mechgen::__private::Rates<T, 2, 1>,
            ::mechgen::__private::SolveError,
        > {
            let ::mechgen::__private::Fixed { x, tx, tp, .. } = fixed;
            let qd = [T::zero(); 2];
            let qdd = [T::zero(); 2];
            // Block 0: closed form (one angle).
            let p_l1 = self.params.l1;
            let p_l2 = self.params.l2;
            let (s_v_q1, _) = tx[0];
            let t0 = p_l1 * s_v_q1;
            if options.closed_forms {
                ::mechgen::__private::closed_form::solve_angle1(
                    0,
                    st,
                    0,
                    t0,
                    (T::zero(), p_l2),
                    || self.scene_rod_middle_length_scale(),
                    options.newton.tolerance,
                    report,
                    every_angle,
                )?;
            } else {
                ::mechgen::__private::newton_block(
                    0,
                    st,
                    [0],
                    [false],
                    self.scene_rod_middle_length_scale(),
                    &options.newton,
                    report,
                    |st| self.block0_position(x, &st.q, tx, tp, &st.sc),
                )?;
            }
            // Near a dead point: one Newton step per block with its residual in double words.
            if report.pivot_ratio < T::lit(::mechgen::__private::REFINE_BELOW) {
                self.block0_refine(x, st, tx, tp);
            }
            // Points.
            let (_, c_v_q1) = tx[0];
            let t1 = p_l1 * c_v_q1;
            let (s_v_q2, c_v_q2) = st.sc[0];
            let t2 = T::lit(0.5) * p_l2;
            let t3 = c_v_q2 * t2;
            let t4 = s_v_q2 * t2;
            let t5 = t1 + t3;
            let t6 = t0 + t4;
            Ok((
                qd,
                qdd,
                [
                    ::mechgen::__private::PointMotion {
                        position: [t5, t6],
                        velocity: [T::zero(), T::zero()],
                        acceleration: [T::zero(), T::zero()],
                    },
                ],
            ))
        }
        /// Scene `rod_middle`: its pruned solver.
        #[doc(hidden)]
        #[inline]

pub mod rod {
    #![allow(non_snake_case)]
    // Allowed above, and why:
    // non_snake_case: output fields keep the file's names (`P_x`, `u_vel`).
    pub use super::slider::{Params as Params, Inputs as Inputs, Unknowns as Unknowns};
    /// What the scene keeps of its mechanism, and its output columns.
    pub const INFO: ::mechgen::__private::SceneInfo = ::mechgen::__private::SceneInfo {
        name: "rod",
        mechanism: "slider",
        order: 0,
        blocks: &[0],
        solved: &[0],
        angles_skipped: &[],
        unknowns: &["q2"],
        points: &[],
        columns: &["q2"],
    };
    /// The scene's outputs, one field per column of `INFO.columns` (a point's
    /// coordinates as `P_x`, `P_y`, rates as `u_vel`, `P_vx`, …).
    #[derive(Clone, Copy, Debug, Default, PartialEq)]
    pub struct Outputs<T> {
        pub q2: T,
    }
    /// What `solve` returns (`mechgen::SceneState`): the inputs with their rates, the
    /// unknowns (the kept blocks' solved), the outputs and the Newton report.
    pub type Solved<T> = ::mechgen::__private::SceneState<
        Inputs<T>,
        Unknowns<T>,
        Outputs<T>,
        T,
    >;
    impl<T: ::core::marker::Copy> Outputs<T> {
        pub fn from_array(a: [T; 1]) -> Self {
            Outputs { q2: a[0] }
        }
        pub fn to_array(&self) -> [T; 1] {
            [self.q2]
        }
    }
    /// The output columns read from a solved state, of one instance or of W in lanes.
    #[inline]
    fn columns_of<V: ::core::marker::Copy>(
        q: &[V; 2],
        _qd: &[V; 2],
        _qdd: &[V; 2],
        _points: &[::mechgen::__private::PointMotion<V>; 0],
    ) -> Outputs<V> {
        Outputs::from_array([q[0]])
    }
    /// The state of W instances between lane ticks (see `Lanes::tick_start`).
    pub type LaneTick<L> = ::mechgen::__private::LaneTick<
        L,
        1,
        2,
        0,
        2,
        ::mechgen::__private::SceneMemo<<L as ::mechgen::__private::Lanes>::Scalar>,
    >;
    /// W instances of the scene in SIMD lanes (`L` = `mechgen::lanes::F64x4` for four f64 instances, `F32x8` for eight f32 ones), each with its own params, inputs and state: lane `i` of every value is instance `i`, and every lane's result (or error) is the scalar tick's, to the last bit.
    ///
    /// Its blocks all have lane kernels: the common path of a tick runs in lanes.
    #[derive(Clone, Copy, Debug)]
    pub struct Lanes<L: ::mechgen::__private::Lanes> {
        scenes: L::Array<Rod<L::Scalar>>,
        params: [L; 2],
        /// Changes with the params (`mechgen::lanes::fresh_params_id`).
        params_id: usize,
    }
    impl<L: ::mechgen::__private::Lanes> Lanes<L> {
        /// What the lane driver knows of the instances besides their values: the params a tick
        /// compares, the angles among the inputs, unknowns and params, the unknowns it predicts.
        const SHAPE: ::mechgen::__private::lanes::LaneShape<1, 2, 2> = ::mechgen::__private::lanes::LaneShape {
            read: [true, true],
            angle_x: [true],
            angle_q: [true, false],
            angle_p: [false, false],
            predict: [false, false],
        };
        /// Instance `i` is `f(i)`.
        pub fn from_fn(f: impl FnMut(usize) -> Rod<L::Scalar>) -> Self {
            let scenes = L::array(f);
            let params = ::core::array::from_fn(|k| L::from_fn(|i| {
                scenes.as_ref()[i].params.to_array()[k]
            }));
            Lanes {
                scenes,
                params,
                params_id: ::mechgen::__private::lanes::fresh_params_id(),
            }
        }
        /// Instance `i` (`None` for `i ≥ W`).
        pub fn scene(&self, i: usize) -> ::core::option::Option<&Rod<L::Scalar>> {
            self.scenes.as_ref().get(i)
        }
        /// Sets instance `i` (`BadLength` for `i ≥ W`); its next tick starts its caches afresh.
        pub fn set(
            &mut self,
            i: usize,
            m: Rod<L::Scalar>,
        ) -> ::core::result::Result<(), ::mechgen::__private::SolveError> {
            let ::core::option::Option::Some(slot) = self.scenes.as_mut().get_mut(i)
            else {
                return ::core::result::Result::Err(::mechgen::__private::SolveError::BadLength {
                    expected: L::W,
                    got: i,
                });
            };
            *slot = m;
            for (k, v) in m.params.to_array().into_iter().enumerate() {
                self.params[k].set_lane(i, v);
            }
            self.params_id = ::mechgen::__private::lanes::fresh_params_id();
            ::core::result::Result::Ok(())
        }
        /// The first tick of every instance, each solved from its lane of `guess` in lanes (each lane that leaves the common path by the scalar `tick_start`; the same results). A lane that fails reports its error in `status` and starts again at the next tick.
        pub fn tick_start(
            &self,
            input: &::mechgen::__private::InputMotion<[L; 1]>,
            guess: &[L; 2],
            options: &::mechgen::__private::SolveOptions<L::Scalar>,
        ) -> LaneTick<L> {
            ::mechgen::__private::lanes::tick_start(
                (&self.params, self.params_id),
                [&input.x, &input.xd, &input.xdd],
                guess,
                &Self::SHAPE,
                options
                    .closed_forms
                    .then_some(
                        #[inline(always)]
                        |
                            fixed: ::mechgen::__private::lanes::LaneFixed<'_, L, 1, 2>,
                            st: &mut ::mechgen::__private::lanes::LaneTrig<L, 2>,
                            report: &mut ::mechgen::__private::lanes::LaneReport<L>,
                            ok: &mut L::Mask|
                        { self.motion_lanes(fixed, st, &options.newton, report, ok) },
                    ),
                |
                    i: usize,
                    t: &mut ::mechgen::__private::Tick<L::Scalar, 1, 2, 0, 2>,
                    memo: &mut ::mechgen::__private::SceneMemo<L::Scalar>,
                    started: bool,
                    xs: [&[L::Scalar; 1]; 3]|
                { self.scalar_lane(i, t, memo, started, xs, options) },
            )
        }
        /// One tick of every instance to its lane of `input` (see the scalar `tick`). A lane
        /// that fails reports its error in `status` and keeps its last state; no lane changes
        /// another. No allocation.
        #[inline(always)]
        pub fn tick(
            &self,
            t: &mut LaneTick<L>,
            input: &::mechgen::__private::InputMotion<[L; 1]>,
            options: &::mechgen::__private::SolveOptions<L::Scalar>,
        ) {
            ::mechgen::__private::lanes::tick(
                t,
                (&self.params, self.params_id),
                [&input.x, &input.xd, &input.xdd],
                &Self::SHAPE,
                options
                    .closed_forms
                    .then_some(
                        #[inline(always)]
                        |
                            fixed: ::mechgen::__private::lanes::LaneFixed<'_, L, 1, 2>,
                            st: &mut ::mechgen::__private::lanes::LaneTrig<L, 2>,
                            report: &mut ::mechgen::__private::lanes::LaneReport<L>,
                            ok: &mut L::Mask|
                        { self.motion_lanes(fixed, st, &options.newton, report, ok) },
                    ),
                |
                    i: usize,
                    t: &mut ::mechgen::__private::Tick<L::Scalar, 1, 2, 0, 2>,
                    memo: &mut ::mechgen::__private::SceneMemo<L::Scalar>,
                    started: bool,
                    xs: [&[L::Scalar; 1]; 3]|
                { self.scalar_lane(i, t, memo, started, xs, options) },
            )
        }
        /// Lane `i` ticked by its scalar tick from `t` (`started`), or started from its guess
        /// `t.q`: what the lane driver runs for a lane off the common path.
        fn scalar_lane(
            &self,
            i: usize,
            t: &mut ::mechgen::__private::Tick<L::Scalar, 1, 2, 0, 2>,
            memo: &mut ::mechgen::__private::SceneMemo<L::Scalar>,
            started: bool,
            [x,
            xd,
            xdd,
            ]: [&[L::Scalar; 1]; 3],
            options: &::mechgen::__private::SolveOptions<L::Scalar>,
        ) -> ::core::result::Result<(), ::mechgen::__private::SolveError> {
            let m = self.scenes.as_ref()[i].mechanism();
            let (s, r) = if started {
                let mut s = ::mechgen::__private::scene_tick_join(*t, *memo);
                let r = m.scene_rod_tick(&mut s, x, xd, xdd, options);
                (s, r)
            } else {
                (
                    m.scene_rod_tick_start(x, xd, xdd, &t.q, options)?,
                    ::core::result::Result::Ok(()),
                )
            };
            (*t, *memo) = ::mechgen::__private::scene_tick_parts(s);
            r
        }
        /// The common path of a tick in lanes: every closed form from the last tick's branch,
        /// every Newton block from the predicted guess (a start: both from the guess), then
        /// velocities, accelerations and points, as the scalar tick computes them; lanes that
        /// leave it (a dead point, a large turn, a Newton step off the common path, a condition
        /// below the refinement threshold, a non-finite value) are cleared in `ok`.
        #[inline(always)]
        fn motion_lanes(
            &self,
            fixed: ::mechgen::__private::lanes::LaneFixed<'_, L, 1, 2>,
            st: &mut ::mechgen::__private::lanes::LaneTrig<L, 2>,
            newton: &::mechgen::__private::NewtonOptions<L::Scalar>,
            report: &mut ::mechgen::__private::lanes::LaneReport<L>,
            ok: &mut L::Mask,
        ) -> ::mechgen::__private::lanes::LaneRates<L, 2, 0> {
            let ::mechgen::__private::lanes::LaneFixed { tx, .. } = fixed;
            let qd = [L::zero(); 2];
            let qdd = [L::zero(); 2];
            let p_l1 = self.params[0];
            let p_l2 = self.params[1];
            let (s_v_q1, _) = tx[0];
            let t0 = p_l1 * s_v_q1;
            ::mechgen::__private::lanes::solve_angle1(
                st,
                0,
                t0,
                (::core::option::Option::None, p_l2),
                newton.tolerance,
                &mut report.pivot_ratio,
                ok,
                true,
            );
            *ok = *ok
                & !report.pivot_ratio.lt(L::lit(::mechgen::__private::REFINE_BELOW));
            (qd, qdd, [])
        }
    }
    impl<L: ::mechgen::__private::Lanes> Lanes<L> {
        /// The outputs of every lane (lane `i` of each field is instance `i`'s; a lane that
        /// never started holds zeros).
        pub fn outputs(t: &LaneTick<L>) -> Outputs<L> {
            columns_of(&t.q, &t.qd, &t.qdd, &t.points)
        }
    }
    impl<L: ::mechgen::__private::Lanes> ::mechgen::__private::LaneScene<L>
    for Lanes<L> {
        type Scene = Rod<L::Scalar>;
        type X = [L; 1];
        type Q = [L; 2];
        type Out = [L; 1];
        type Tick = LaneTick<L>;
        fn from_fn(f: impl FnMut(usize) -> Self::Scene) -> Self {
            Lanes::from_fn(f)
        }
        fn set(
            &mut self,
            i: usize,
            s: Self::Scene,
        ) -> ::core::result::Result<(), ::mechgen::__private::SolveError> {
            Lanes::set(self, i, s)
        }
        fn tick_start(
            &self,
            input: &::mechgen::__private::InputMotion<Self::X>,
            guess: &Self::Q,
            options: &::mechgen::__private::SolveOptions<L::Scalar>,
        ) -> Self::Tick {
            Lanes::tick_start(self, input, guess, options)
        }
        #[inline(always)]
        fn tick(
            &self,
            t: &mut Self::Tick,
            input: &::mechgen::__private::InputMotion<Self::X>,
            options: &::mechgen::__private::SolveOptions<L::Scalar>,
        ) {
            Lanes::tick(self, t, input, options)
        }
        fn outputs(t: &Self::Tick) -> Self::Out {
            Lanes::outputs(t).to_array()
        }
        fn lane(
            t: &Self::Tick,
            i: usize,
        ) -> ::core::option::Option<
            (
                ::core::result::Result<(), ::mechgen::__private::SolveError>,
                ::mechgen::__private::SceneTick<L::Scalar, 1, 2, 0, 2>,
            ),
        > {
            ::core::option::Option::Some((
                t.status(i),
                ::mechgen::__private::scene_tick_join(t.lane(i)?, t.memo(i)?),
            ))
        }
    }
    /// The state between ticks (read it with `outputs`): the kept blocks' unknowns with
    /// their rates up to the scene's order, the scene's points, and the caches.
    pub type Tick<T> = ::mechgen::__private::SceneTick<T, 1, 2, 0, 2>;
    /// Scene `rod` of mechanism `slider`: q2 to order 0; solves blocks `[0]` only.
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct Rod<T = f64> {
        pub params: Params<T>,
    }
    impl<T: ::mechgen::__private::Real> ::core::default::Default for Rod<T> {
        fn default() -> Self {
            Rod {
                params: <Params<T> as ::core::default::Default>::default(),
            }
        }
    }
    impl<T: ::mechgen::__private::Real> Rod<T> {
        pub fn new(params: Params<T>) -> Self {
            Rod { params }
        }
        #[inline(always)]
        fn mechanism(&self) -> super::slider::Slider<T> {
            super::slider::Slider::new(self.params)
        }
        /// The mechanism's `start` configuration.
        pub fn start() -> (Inputs<T>, Unknowns<T>) {
            super::slider::Slider::<T>::start()
        }
        #[inline]
        fn outputs_of(
            q: &[T; 2],
            qd: &[T; 2],
            qdd: &[T; 2],
            points: &[::mechgen::__private::PointMotion<T>; 0],
        ) -> Outputs<T> {
            columns_of(q, qd, qdd, points)
        }
        /// Positions of the kept blocks from `guess`, their rates up to the order, the
        /// outputs; the returned unknowns hold the kept blocks' solution.
        pub fn solve(
            &self,
            input: &::mechgen::__private::InputMotion<Inputs<T>>,
            guess: &Unknowns<T>,
            options: &::mechgen::__private::SolveOptions<T>,
        ) -> ::core::result::Result<Solved<T>, ::mechgen::__private::SolveError> {
            let mut q = guess.to_array();
            let (qd, qdd, points, report) = self
                .mechanism()
                .scene_rod_solve(
                    &input.x.to_array(),
                    &input.xd.to_array(),
                    &input.xdd.to_array(),
                    &mut q,
                    options,
                )?;
            Ok(Solved {
                x: input.x,
                xd: input.xd,
                xdd: input.xdd,
                q: Unknowns::from_array(q),
                out: Self::outputs_of(&q, &qd, &qdd, &points),
                report,
            })
        }
        /// [`Self::solve`] into `state`: its inputs and rates are the input, its unknowns
        /// the guess; on success it holds the solution, on error it is unchanged.
        pub fn solve_in_place(
            &self,
            state: &mut Solved<T>,
            options: &::mechgen::__private::SolveOptions<T>,
        ) -> ::core::result::Result<(), ::mechgen::__private::SolveError> {
            *state = self.solve(&state.input(), &state.q, options)?;
            Ok(())
        }
        /// The first tick of a simulation, solved from `guess` (see `tick`).
        pub fn tick_start(
            &self,
            input: &::mechgen::__private::InputMotion<Inputs<T>>,
            guess: &Unknowns<T>,
            options: &::mechgen::__private::SolveOptions<T>,
        ) -> ::core::result::Result<Tick<T>, ::mechgen::__private::SolveError> {
            self.mechanism()
                .scene_rod_tick_start(
                    &input.x.to_array(),
                    &input.xd.to_array(),
                    &input.xdd.to_array(),
                    &guess.to_array(),
                    options,
                )
        }
        /// One simulator tick to `input`: the mechanism's tick (predictor, cached sines
        /// and cosines, closed forms on the last branch) on the kept blocks only. On
        /// error `t` reads as before (its outputs, inputs and report are unchanged).
        #[inline]
        pub fn tick(
            &self,
            t: &mut Tick<T>,
            input: &::mechgen::__private::InputMotion<Inputs<T>>,
            options: &::mechgen::__private::SolveOptions<T>,
        ) -> ::core::result::Result<(), ::mechgen::__private::SolveError> {
            self.mechanism()
                .scene_rod_tick(
                    t,
                    &input.x.to_array(),
                    &input.xd.to_array(),
                    &input.xdd.to_array(),
                    options,
                )
        }
        /// The outputs of a tick state.
        pub fn outputs(t: &Tick<T>) -> Outputs<T> {
            let s = ::mechgen::__private::scene_tick_state(t);
            Self::outputs_of(&s.q, &s.qd, &s.qdd, &s.points)
        }
    }
    impl<T: ::mechgen::__private::Real> ::mechgen::__private::Scene<T> for Rod<T> {
        const NAME: &'static str = "rod";
        type X = [T; 1];
        type Q = [T; 2];
        type Out = [T; 1];
        type Tick = Tick<T>;
        type Lanes<L: ::mechgen::__private::Lanes<Scalar = T>> = Lanes<L>;
        fn info(&self) -> &'static ::mechgen::__private::SceneInfo {
            &INFO
        }
        fn with_params(params: &[T]) -> ::core::option::Option<Self> {
            <[T; 2]>::try_from(params).ok().map(|a| Rod::new(Params::from_array(a)))
        }
        fn solve(
            &self,
            input: &::mechgen::__private::InputMotion<Self::X>,
            guess: &Self::Q,
            options: &::mechgen::__private::SolveOptions<T>,
        ) -> ::core::result::Result<
            ::mechgen::__private::SceneStateOf<Self, T>,
            ::mechgen::__private::SolveError,
        > {
            let mut q = *guess;
            let (qd, qdd, points, report) = self
                .mechanism()
                .scene_rod_solve(&input.x, &input.xd, &input.xdd, &mut q, options)?;
            let out = Self::outputs_of(&q, &qd, &qdd, &points).to_array();
            Ok(::mechgen::__private::SceneState {
                x: input.x,
                xd: input.xd,
                xdd: input.xdd,
                q,
                out,
                report,
            })
        }
        fn tick_start(
            &self,
            input: &::mechgen::__private::InputMotion<Self::X>,
            guess: &Self::Q,
            options: &::mechgen::__private::SolveOptions<T>,
        ) -> ::core::result::Result<Self::Tick, ::mechgen::__private::SolveError> {
            self.mechanism()
                .scene_rod_tick_start(&input.x, &input.xd, &input.xdd, guess, options)
        }
        fn tick(
            &self,
            t: &mut Self::Tick,
            input: &::mechgen::__private::InputMotion<Self::X>,
            options: &::mechgen::__private::SolveOptions<T>,
        ) -> ::core::result::Result<(), ::mechgen::__private::SolveError> {
            self.mechanism().scene_rod_tick(t, &input.x, &input.xd, &input.xdd, options)
        }
        fn outputs(&self, t: &Self::Tick) -> Self::Out {
            Rod::outputs(t).to_array()
        }
        fn report(&self, t: &Self::Tick) -> ::mechgen::__private::NewtonReport<T> {
            *t.report()
        }
    }
}
/// Scene `crank_pin` of mechanism `slider`: B_x, B_y, B_vx, B_vy to order 1; solves blocks `[]` only.
