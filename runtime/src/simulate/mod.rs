//! Forward dynamics of one input: the motion the applied effort, gravity and loads make, the
//! other inputs held at rest. The equation of motion is the inverse dynamics solved for the
//! input's acceleration: the effort the motion needs is linear in `ẍ` with the generalized inertia
//! as its slope ([`crate::dynamics()`]), so `ẍ = (Q(t, x, ẋ) − effort(x, ẋ, ẍ = 0)) / M(x)`. Every
//! evaluation solves the positions on the loop (the engine's tick from its last state: the one
//! predictor), so the loop closes at every stage to solver precision.
//!
//! The integrator is the explicit Runge–Kutta pair of Dormand and Prince, 5(4) (the coefficients
//! of Hairer, Nørsett and Wanner, *Solving ODEs I*, II.5), with the first-same-as-last stage and
//! the usual step size control (error in the weighted RMS norm with `atol + rtol·|y|`, factor
//! `0.9·err^(−1/5)` kept within [0.2, 5]); [`Simulation::advance_to`] lands exactly on the time
//! asked for. Nothing is allocated per step.
//!
//! A load that acts over a range of the input switches only between steps: a step that would
//! cross one of its edges is shortened to land on it (`edges.rs`), and the load is switched there
//! for the way the motion leaves the edge. Where the forces on both sides push into the edge, the
//! input rests on it ([`Simulation::held`]) until they no longer do.

mod edges;

use alloc::boxed::Box;
use alloc::vec;
use alloc::vec::Vec;

use crate::dyn_tick::DynTick;
use crate::dynamic::DynMechanism;
use crate::dynamics::{Dynamics, DynamicsWork, PointLoad, dyn_tick_dynamics};
use crate::error::{SolveError, Stage};
use crate::mechanism::InputMotion;
use crate::scalar::Real;
use crate::solve::SolveOptions;

/// The user's effort on the input, a function of (t, x, ẋ).
pub type Effort<'a, T> = dyn FnMut(T, T, T) -> T + 'a;

/// The Dormand–Prince 5(4) tableau: nodes, stage weights, 5th-order weights and the difference of
/// the 5th- and 4th-order weights (the error estimate).
const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Tolerances and limits of a [`Simulation`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulationOptions<T> {
    /// Relative and absolute error per step (radians or file units, and per second).
    pub rtol: T,
    pub atol: T,
    /// The largest step (seconds); also the first one tried.
    pub max_step: T,
    /// Steps allowed for one [`Simulation::advance_to`] before it gives up (`NoConvergence`).
    pub max_steps: u32,
    /// The position solves' options.
    pub solve: SolveOptions<T>,
}

impl<T: Real> Default for SimulationOptions<T> {
    fn default() -> Self {
        SimulationOptions {
            rtol: T::lit(1e-12),
            atol: T::lit(1e-12),
            max_step: T::lit(1e-2),
            max_steps: 1_000_000,
            solve: SolveOptions::default(),
        }
    }
}

/// One input's motion under forces, stepped by the Dormand–Prince pair (see the module).
pub struct Simulation<'a, T: Real> {
    m: &'a dyn DynMechanism<T>,
    tick: Box<dyn DynTick<T> + 'a>,
    input: usize,
    /// The user's loads; whether each acts through the current step; those that do, as loads
    /// that always act (what the equation of motion reads).
    loads: Vec<PointLoad<T>>,
    on: Vec<bool>,
    active: Vec<PointLoad<T>>,
    /// Resting on a load's edge.
    held: bool,
    options: SimulationOptions<T>,
    x: Vec<T>,
    xd: Vec<T>,
    xdd: Vec<T>,
    ws: DynamicsWork<T>,
    /// Time, input, input rate; the acceleration there (the first stage of the next step).
    t: T,
    y: [T; 2],
    acc: T,
    h: T,
}

impl<'a, T: Real> Simulation<'a, T> {
    /// At time 0 with the inputs `x` (the simulated one, `input`, at its start value), that input
    /// moving at `rate` (the others at rest), positions solved from `guess`, under `loads` and
    /// gravity, the user's effort asked for at (0, x, ẋ).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        m: &'a dyn DynMechanism<T>,
        input: usize,
        x: &[T],
        rate: T,
        guess: &[T],
        loads: &[PointLoad<T>],
        options: SimulationOptions<T>,
        effort: &mut Effort<'_, T>,
    ) -> Result<Self, SolveError> {
        let info = m.info();
        if input >= info.inputs.len() {
            return Err(SolveError::OutOfRange {
                index: input,
                len: info.inputs.len(),
            });
        }
        crate::error::len(x, info.inputs.len())?;
        let n = x.len();
        let mut s = Simulation {
            m,
            tick: m.ticker(),
            input,
            loads: loads.to_vec(),
            on: vec![false; loads.len()],
            active: Vec::with_capacity(loads.len()),
            held: false,
            options,
            x: x.to_vec(),
            xd: vec![T::zero(); n],
            xdd: vec![T::zero(); n],
            ws: DynamicsWork::new(&info),
            t: T::zero(),
            y: [x[input], rate],
            acc: T::zero(),
            h: options.max_step,
        };
        s.xd[input] = rate;
        let start = InputMotion::new(&s.x[..], &s.xd[..], &s.xdd[..]);
        s.tick.start(start, guess, &options.solve)?;
        s.set_modes(effort)?;
        Ok(s)
    }

    /// Time, input and input rate now.
    pub fn time(&self) -> T {
        self.t
    }
    pub fn position(&self) -> T {
        self.y[0]
    }
    pub fn rate(&self) -> T {
        self.y[1]
    }
    /// The input's acceleration now (from the equation of motion at the current state).
    pub fn acceleration_now(&self) -> T {
        self.acc
    }
    /// Whether the input rests on the edge of a load's range, the forces on both sides pushing
    /// into it (the load there takes the value between off and on that holds it, so the state
    /// satisfies neither side's equation of motion; its acceleration is 0).
    pub fn held(&self) -> bool {
        self.held
    }

    /// The solved state of the last evaluation (after [`Simulation::advance_to`] or
    /// [`Simulation::acceleration`]: the current one), with its accelerations at `ẍ = 0`.
    pub fn tick(&self) -> &dyn DynTick<T> {
        self.tick.as_ref()
    }

    /// The equation of motion at (t, x, ẋ), under the loads that act at x: positions and rates
    /// solved there (the tick), the inverse dynamics at `ẍ = 0`, and `ẍ = (Q − effort) / M`;
    /// with that inverse dynamics (its `effort` is the one at `ẍ = 0`).
    pub fn acceleration(
        &mut self,
        t: T,
        y: [T; 2],
        effort: &mut Effort<'_, T>,
    ) -> Result<(T, Dynamics<T>), SolveError> {
        self.active.clear();
        for l in &self.loads {
            if l.acts_at(y[0]) {
                self.active.push(PointLoad::new(l.point, l.force));
            }
        }
        let r = self.eval(t, y, effort);
        self.switch();
        r
    }

    /// The equation of motion at (t, x, ẋ) under the loads that act through this step.
    pub(super) fn eval(
        &mut self,
        t: T,
        y: [T; 2],
        effort: &mut Effort<'_, T>,
    ) -> Result<(T, Dynamics<T>), SolveError> {
        self.x[self.input] = y[0];
        self.xd[self.input] = y[1];
        let motion = InputMotion::new(&self.x[..], &self.xd[..], &self.xdd[..]);
        let (tick, loads) = (self.tick.as_mut(), (self.input, &self.active[..]));
        let d = dyn_tick_dynamics(
            self.m,
            tick,
            motion,
            &self.options.solve,
            loads,
            &mut self.ws,
        )?;
        if d.inertia.partial_cmp(&T::zero()) != Some(core::cmp::Ordering::Greater)
            || !d.inertia.is_finite()
        {
            // No inertia on the input (no mass moves with it): no motion follows from a force.
            return Err(SolveError::Singular {
                block: 0,
                stage: Stage::Acceleration,
                pivot_ratio: 0.0,
            });
        }
        let q = effort(t, y[0], y[1]);
        let acc = (q - d.effort) / d.inertia;
        if !acc.is_finite() {
            return Err(SolveError::Overflow {
                block: 0,
                stage: Stage::Acceleration,
            });
        }
        Ok((acc, d))
    }

    /// Integrates to time `t_end` (at or after the current time) in error-controlled steps, the
    /// last one shortened to land on `t_end` (and any that would cross a load's edge, to land on
    /// the edge); the state is then the one at `t_end` and the tick's state solved there. Resting
    /// on a load's edge ([`Self::held`]), the input stays there if the forces at `t_end` still
    /// hold it. On error (a dead point, a failed solve, the step size collapsing: `StepTooSmall`,
    /// `max_steps` used up: `StepLimit`) the state is the last accepted one before it.
    pub fn advance_to(&mut self, t_end: T, effort: &mut Effort<'_, T>) -> Result<(), SolveError> {
        let o = self.options;
        let mut steps = 0u32;
        while self.t < t_end {
            if self.held {
                self.t = t_end;
                self.set_modes(effort)?;
                break;
            }
            steps += 1;
            if steps > o.max_steps {
                return Err(SolveError::StepLimit {
                    time: self.t.to_f64(),
                    steps: o.max_steps,
                });
            }
            let left = t_end - self.t;
            if left <= resolution(self.t) {
                // Within what the time resolves of `t_end` (an edge landed on just before it).
                self.t = t_end;
                break;
            }
            let last = self.h >= left;
            let h = if last { left } else { self.h };
            let (err, taken) = self.advance(h, effort)?;
            if taken == h && last {
                self.t = t_end;
            }
            // The next step from the error of this one (refused: a smaller try at once).
            let factor = control(err);
            if err <= T::one() && last {
                // `h` was cut to land on `t_end`: keep the step the control had chosen.
                self.h = self.h.max(h * factor).min(o.max_step);
            } else {
                self.h = (h * factor).min(o.max_step);
            }
        }
        // The tick's state is the last stage of the last step taken: the state at `t_end` (the
        // pair is first-same-as-last).
        Ok(())
    }

    /// One step of the error control's own size (refused tries repeated smaller, up to
    /// `max_steps` of them; shortened to land on a load's edge; resting on one, `max_step`): the
    /// time it advanced.
    pub fn step(&mut self, effort: &mut Effort<'_, T>) -> Result<T, SolveError> {
        if self.held {
            let h = self.options.max_step;
            self.t += h;
            self.set_modes(effort)?;
            return Ok(h);
        }
        for _ in 0..self.options.max_steps {
            let h = self.h;
            let (err, taken) = self.advance(h, effort)?;
            self.h = (h * control(err)).min(self.options.max_step);
            if err <= T::one() {
                return Ok(taken);
            }
        }
        Err(SolveError::StepLimit {
            time: self.t.to_f64(),
            steps: self.options.max_steps,
        })
    }

    /// One Dormand–Prince step of size `h` from the current state: the new (x, ẋ), the
    /// acceleration there (the last stage) and the weighted error estimate.
    pub(super) fn try_step(
        &mut self,
        h: T,
        effort: &mut Effort<'_, T>,
    ) -> Result<([T; 2], T, T), SolveError> {
        let (t0, y0) = (self.t, self.y);
        let mut k = [[T::zero(); 2]; 7];
        k[0] = [y0[1], self.acc];
        for i in 1..7 {
            let mut y = y0;
            for (j, kj) in k.iter().enumerate().take(i) {
                let a = T::lit(A[i][j]) * h;
                y[0] += a * kj[0];
                y[1] += a * kj[1];
            }
            let (acc, _) = self.acceleration(t0 + T::lit(C[i]) * h, y, effort)?;
            k[i] = [y[1], acc];
        }
        // The 5th-order solution is the last stage's point (A's last row is the weights).
        let mut y = y0;
        for (j, kj) in k.iter().enumerate().take(6) {
            let a = T::lit(A[6][j]) * h;
            y[0] += a * kj[0];
            y[1] += a * kj[1];
        }
        let mut sum = T::zero();
        for c in 0..2 {
            let mut e = T::zero();
            for (j, kj) in k.iter().enumerate() {
                e += T::lit(E[j]) * h * kj[c];
            }
            let scale = self.options.atol + self.options.rtol * y0[c].abs().max(y[c].abs());
            let r = e / scale;
            sum += r * r;
        }
        let err = (sum * T::lit(0.5)).sqrt();
        Ok((y, k[6][1], err))
    }
}

/// The smallest step that still moves the time `t` by a meaningful amount.
pub(super) fn resolution<T: Real>(t: T) -> T {
    T::lit(64.0) * T::EPSILON * t.abs().max(T::one())
}

/// The step size factor after a step with weighted error `err`: `0.9·err^(−1/5)` within [0.2, 5].
fn control<T: Real>(err: T) -> T {
    let factor = if err > T::zero() {
        T::lit(0.9) * T::lit(num_traits::Float::powf(err.to_f64(), -0.2))
    } else {
        T::lit(5.0)
    };
    factor.max(T::lit(0.2)).min(T::lit(5.0))
}
