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
    /// The state between ticks (read it with `outputs`): the kept blocks' unknowns with
    /// their rates up to the scene's order, the scene's points, and the caches.
    pub type Tick<T> = ::mechgen::__private::SceneTick<T, 1, 2, 0, 2>;
    /// Scene `rod` of mechanism `slider`: q2 to order 0; solves blocks [0] only.
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
            _qd: &[T; 2],
            _qdd: &[T; 2],
            _points: &[::mechgen::__private::PointMotion<T>; 0],
        ) -> Outputs<T> {
            Outputs::from_array([q[0]])
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
        fn info(&self) -> &'static ::mechgen::__private::SceneInfo {
            &INFO
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
/// Scene `crank_pin` of mechanism `slider`: B_x, B_y, B_vx, B_vy to order 1; solves blocks [] only.
