//! The work and the solver variants of `examples/accuracy` (no timing here): the seed six-bar
//! stepped over a full turn like a simulator, each variant's state sampled where the 40-digit
//! reference has rows, and the errors against it. `tests/accuracy_variants.rs` includes this file
//! too. `shaper.rs` reuses [`Stepper`], [`run`], [`State`], [`parse_reference`] and
//! [`Engine::with_start`] for the seed shaper.
#![allow(dead_code)]

use std::f64::consts::PI;
use std::time::{Duration, Instant};

use mechgen::nalgebra::{DMatrix, DVector};
use mechgen::sixbar::Sixbar;
use mechgen::{
    DynMechanism, DynState, InputMotion, NewtonOptions, PointMotion, Real, SolveError,
    SolveOptions, StaticMechanism,
};

/// Unknowns of the six-bar (q2, q3, q5, q6), all angles.
pub const N: usize = 4;
/// Steps per full turn (1 degree each).
pub const STEPS: usize = 360;
/// The reference has a row every this many steps (10 degrees).
pub const SAMPLE_EVERY: usize = 10;

/// The input step, radians (1 degree). The input rate is 1 and its acceleration 0, so the input
/// derivatives of the unknowns are their time derivatives.
pub fn step_size() -> f64 {
    PI / 180.0
}

/// The crank angles of a full turn, 0..=360 degrees in 1 degree steps (radians).
pub fn inputs() -> Vec<f64> {
    (0..=STEPS).map(|i| i as f64 * step_size()).collect()
}

/// Positions, velocities and accelerations of the unknowns, in f64 whatever the solver's precision.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct State {
    pub q: [f64; N],
    pub qd: [f64; N],
    pub qdd: [f64; N],
}

/// What one tick did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tick {
    /// Newton iterations (Jacobian factorizations of the position solve), over all blocks.
    pub iterations: u32,
    /// The position solve failed; the tick kept the predicted positions.
    pub failed: bool,
}

/// A solver advancing the six-bar's full state one input step at a time.
pub trait Stepper {
    /// Assembles at input `x` from the file's start configuration (not timed, never capped).
    fn reset(&mut self, x: f64) -> Result<(), String>;
    /// One tick from the current state (at `x - dx`) to input `x`.
    fn step(&mut self, x: f64, dx: f64) -> Result<Tick, String>;
    fn state(&self) -> State;
}

/// One full turn: the sampled states (every `SAMPLE_EVERY` steps, the first included), the Newton
/// iterations and the failed ticks.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pass {
    pub samples: Vec<State>,
    pub iterations: u64,
    pub failed: usize,
}

/// Steps `s` over `xs` (from a fresh assembly at `xs[0]`), sampling every `SAMPLE_EVERY` steps;
/// also the time the steps took (the assembly is not timed).
#[inline(never)]
pub fn run<S: Stepper>(s: &mut S, xs: &[f64]) -> Result<(Pass, Duration), String> {
    let mut pass = Pass {
        samples: Vec::with_capacity(xs.len() / SAMPLE_EVERY + 1),
        ..Pass::default()
    };
    let Some(&x0) = xs.first() else {
        return Ok((pass, Duration::ZERO));
    };
    s.reset(x0)?;
    pass.samples.push(s.state());
    let start = Instant::now();
    for (i, w) in xs.windows(2).enumerate() {
        let tick = s.step(w[1], w[1] - w[0])?;
        pass.iterations += u64::from(tick.iterations);
        pass.failed += usize::from(tick.failed);
        if (i + 1) % SAMPLE_EVERY == 0 {
            pass.samples.push(s.state());
        }
    }
    Ok((pass, start.elapsed()))
}

/// The reference rows (inputs 0, 10, ..., 360 degrees) of the unknowns.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    pub x: Vec<f64>,
    pub rows: Vec<State>,
}

/// `tests/data/sixbar.csv` (40-digit values, parsed to the nearest f64).
pub fn reference() -> Result<Reference, String> {
    let text = include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/sixbar.csv"
    ));
    parse_reference(
        text,
        mechgen::sixbar::INFO.inputs[0].name,
        mechgen::sixbar::INFO.unknowns,
    )
}

/// A reference table of a mechanism with `N` unknowns: the column `input`, and per unknown its
/// position, `_vel` and `_acc` columns (40-digit values, parsed to the nearest f64).
pub fn parse_reference(
    text: &str,
    input: &str,
    names: &[mechgen::CoordInfo],
) -> Result<Reference, String> {
    if names.len() != N {
        return Err(format!("reference: {} unknowns, not {N}", names.len()));
    }
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header: Vec<&str> = lines.next().ok_or("empty reference")?.split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or_else(|| format!("reference: no column {name}"))
    };
    let input = col(input)?;
    // Per unknown: its position, velocity and acceleration columns.
    let mut cols = [[0usize; 3]; N];
    for (c, u) in cols.iter_mut().zip(names) {
        *c = [
            col(u.name)?,
            col(&format!("{}_vel", u.name))?,
            col(&format!("{}_acc", u.name))?,
        ];
    }
    let mut r = Reference {
        x: Vec::new(),
        rows: Vec::new(),
    };
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        let num = |i: usize| -> Result<f64, String> {
            let c = cells.get(i).ok_or("reference: short row")?;
            c.parse::<f64>().map_err(|e| format!("reference: {c}: {e}"))
        };
        r.x.push(num(input)?);
        let mut s = State::default();
        for (j, c) in cols.iter().enumerate() {
            s.q[j] = num(c[0])?;
            s.qd[j] = num(c[1])?;
            s.qdd[j] = num(c[2])?;
        }
        r.rows.push(s);
    }
    Ok(r)
}

/// Angle difference folded into (−π, π].
pub fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(2.0 * PI);
    if d > PI { d - 2.0 * PI } else { d }
}

/// Largest errors over the sampled rows: positions in radians (modulo 2π), velocities and
/// accelerations relative to the largest magnitude of their reference column (as
/// `tests/common` measures). Infinite when a sample is missing or not finite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Errors {
    pub position: f64,
    pub velocity: f64,
    pub acceleration: f64,
}

impl Errors {
    pub fn max(&self) -> f64 {
        self.position.max(self.velocity).max(self.acceleration)
    }
}

pub fn errors(samples: &[State], reference: &Reference) -> Errors {
    if samples.len() != reference.rows.len() {
        return Errors {
            position: f64::INFINITY,
            velocity: f64::INFINITY,
            acceleration: f64::INFINITY,
        };
    }
    let worst = |d: f64, m: f64| if d.is_nan() { f64::INFINITY } else { m.max(d) };
    let rate = |get: fn(&State) -> &[f64; N]| {
        (0..N).fold(0.0f64, |m, j| {
            let scale = reference
                .rows
                .iter()
                .fold(f64::MIN_POSITIVE, |s, r| s.max(get(r)[j].abs()));
            samples.iter().zip(&reference.rows).fold(m, |m, (s, r)| {
                worst((get(s)[j] - get(r)[j]).abs() / scale, m)
            })
        })
    };
    let position = samples
        .iter()
        .zip(&reference.rows)
        .fold(0.0f64, |m, (s, r)| {
            (0..N).fold(m, |m, j| worst(angle_diff(s.q[j], r.q[j]).abs(), m))
        });
    Errors {
        position,
        velocity: rate(|s| &s.qd),
        acceleration: rate(|s| &s.qdd),
    }
}

/// How a generated variant spends its Newton budget.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Budget {
    /// `solve` with the default options: dyad blocks (both of the six-bar's) in closed
    /// form, no Newton iterations.
    ClosedForm,
    /// `tick` from the kept `Tick` (predictor and cached sines and cosines inside), default
    /// options.
    Ticked,
    /// `solve` with Newton on every block (`closed_forms: false`) and these options; a tick whose position solve fails (e.g. `NoConvergence`
    /// at the cap) keeps the predicted positions and solves the rates there.
    Options { tolerance: f64, max_iterations: u32 },
    /// Exactly `k` Newton iterations per block, the iterate accepted without a convergence test:
    /// `k` calls with one iteration each and tolerance ∞ (`k - 1` × `solve_position`, then
    /// `solve`).
    Fixed(u32),
}

/// The generated solvers (`mechgen::sixbar::Sixbar<T>`), statically dispatched, fixed arrays.
pub struct Generated<T: Real> {
    mechanism: Sixbar<T>,
    budget: Budget,
    options: SolveOptions<T>,
    q: [T; N],
    qd: [T; N],
    qdd: [T; N],
    points: [PointMotion<T>; 1],
    tick: Option<mechgen::sixbar::Tick<T>>,
}

impl<T: Real> Generated<T> {
    pub fn new(budget: Budget) -> Self {
        let options = match budget {
            Budget::Options {
                tolerance,
                max_iterations,
            } => SolveOptions {
                newton: NewtonOptions {
                    tolerance: T::lit(tolerance),
                    max_iterations,
                },
                closed_forms: false,
            },
            Budget::Fixed(_) => SolveOptions {
                newton: NewtonOptions {
                    tolerance: T::lit(f64::INFINITY),
                    max_iterations: 1,
                },
                closed_forms: false,
            },
            Budget::ClosedForm | Budget::Ticked => SolveOptions::default(),
        };
        Generated {
            mechanism: Sixbar::default(),
            budget,
            options,
            q: [T::zero(); N],
            qd: [T::zero(); N],
            qdd: [T::zero(); N],
            points: [PointMotion::default()],
            tick: None,
        }
    }

    /// Keeps a whole solve's state.
    fn store(&mut self, s: mechgen::State<[T; 1], [T; N], [PointMotion<T>; 1], T>) {
        (self.q, self.qd, self.qdd, self.points) = (s.q, s.qd, s.qdd, s.points);
    }

    /// The rates at the positions in `self.q` (after a failed position solve).
    fn rates(&mut self, x: &[T; 1], xd: &[T; 1], xdd: &[T; 1]) -> Result<(), SolveError> {
        let m = &self.mechanism;
        self.qd = m.solve_velocity(x, &self.q, xd)?;
        self.qdd = m.solve_acceleration(x, &self.q, xd, &self.qd, xdd)?;
        let input = InputMotion::new(*x, *xd, *xdd);
        self.points = StaticMechanism::points(m, &input, &self.q, &self.qd, &self.qdd);
        Ok(())
    }
}

/// Iterations a failed position solve spent: its own, plus the cap for every block before it.
fn failed_iterations(e: &SolveError, cap: u32) -> u32 {
    match *e {
        SolveError::NoConvergence {
            block, iterations, ..
        }
        | SolveError::Unassemblable {
            block, iterations, ..
        } => cap * block as u32 + iterations,
        _ => 0,
    }
}

impl<T: Real> Stepper for Generated<T> {
    fn reset(&mut self, x: f64) -> Result<(), String> {
        let (_, start) = Sixbar::<T>::start();
        self.q = start.to_array();
        let (x, xd, xdd) = ([T::lit(x)], [T::one()], [T::zero()]);
        let m = &self.mechanism;
        if self.budget == Budget::Ticked {
            let t = StaticMechanism::tick_start(
                m,
                &InputMotion::new(x, xd, xdd),
                &self.q,
                &self.options,
            )
            .map_err(|e| format!("assembly at {x:?}: {e}", x = x[0].to_f64()))?;
            (self.q, self.qd, self.qdd) = (t.q, t.qd, t.qdd);
            self.tick = Some(t);
            return Ok(());
        }
        let input = InputMotion::new(x, xd, xdd);
        StaticMechanism::solve(m, &input, &self.q, &SolveOptions::default())
            .map(|s| self.store(s))
            .map_err(|e| format!("assembly at {x:?}: {e}", x = x[0].to_f64()))
    }

    #[inline]
    fn step(&mut self, x: f64, dx: f64) -> Result<Tick, String> {
        let (x, xd, xdd) = ([T::lit(x)], [T::one()], [T::zero()]);
        if let Some(t) = self.tick.as_mut() {
            let mut tick = Tick::default();
            match StaticMechanism::tick(
                &self.mechanism,
                t,
                &InputMotion::new(x, xd, xdd),
                &self.options,
            ) {
                Ok(()) => tick.iterations += t.report.iterations,
                Err(_) => tick.failed = true,
            }
            (self.q, self.qd, self.qdd) = (t.q, t.qd, t.qdd);
            return Ok(tick);
        }
        let dx = T::lit(dx);
        let half = T::lit(0.5);
        for j in 0..N {
            self.q[j] += dx * (self.qd[j] + half * dx * self.qdd[j]);
        }
        let m = &self.mechanism;
        let mut tick = Tick::default();
        if let Budget::Fixed(k) = self.budget {
            for _ in 1..k {
                match m.solve_position(&x, &mut self.q, &self.options) {
                    Ok(r) => tick.iterations += r.iterations,
                    Err(e) => {
                        tick.iterations += failed_iterations(&e, 1);
                        tick.failed = true;
                    }
                }
            }
        }
        let result =
            StaticMechanism::solve(m, &InputMotion::new(x, xd, xdd), &self.q, &self.options);
        match result {
            Ok(s) => {
                tick.iterations += s.report.iterations;
                self.store(s);
            }
            Err(e) => {
                tick.iterations += failed_iterations(&e, self.options.newton.max_iterations);
                tick.failed = true;
                // `q` still holds the prediction: the solvers write it back only on success.
                self.rates(&x, &xd, &xdd)
                    .map_err(|e| format!("rates at {:?}: {e}", x[0].to_f64()))?;
            }
        }
        Ok(tick)
    }

    fn state(&self) -> State {
        let f = |a: &[T; N]| a.map(Real::to_f64);
        State {
            q: f(&self.q),
            qd: f(&self.qd),
            qdd: f(&self.qdd),
        }
    }
}

/// Any [`DynMechanism`] through its object-safe `solve` (the generic engine: interpreted
/// tapes, slices, `DMatrix`).
pub struct Engine<'k, K: ?Sized> {
    k: &'k K,
    options: SolveOptions<f64>,
    /// The assembly's start values (the six-bar's unless [`Engine::with_start`]).
    start: [f64; N],
    st: DynState<f64>,
}

impl<'k, K: DynMechanism<f64> + ?Sized> Engine<'k, K> {
    pub fn new(k: &'k K, options: SolveOptions<f64>) -> Self {
        let input = InputMotion::new(&[0.0][..], &[1.0], &[0.0]);
        Engine {
            k,
            options,
            start: Sixbar::<f64>::start().1.to_array(),
            st: DynState::new(input, &[0.0; N], k.info().points.len()),
        }
    }

    /// Assembles from these start values instead (another mechanism with `N` unknowns).
    pub fn with_start(mut self, start: [f64; N]) -> Self {
        self.start = start;
        self
    }
}

impl<K: DynMechanism<f64> + ?Sized> Stepper for Engine<'_, K> {
    fn reset(&mut self, x: f64) -> Result<(), String> {
        self.st.x[0] = x;
        self.st.q.copy_from_slice(&self.start);
        self.k
            .solve_in_place(&mut self.st, &SolveOptions::default())
            .map_err(|e| format!("assembly at {x}: {e}"))
    }

    #[inline]
    fn step(&mut self, x: f64, dx: f64) -> Result<Tick, String> {
        let st = &mut self.st;
        st.x[0] = x;
        for j in 0..N {
            st.q[j] += dx * (st.qd[j] + 0.5 * dx * st.qdd[j]);
        }
        self.k
            .solve_in_place(st, &self.options)
            .map_err(|e| format!("tick at {x}: {e}"))?;
        Ok(Tick {
            iterations: st.report.iterations,
            failed: false,
        })
    }

    fn state(&self) -> State {
        let mut s = State::default();
        s.q.copy_from_slice(&self.st.q);
        s.qd.copy_from_slice(&self.st.qd);
        s.qdd.copy_from_slice(&self.st.qdd);
        s
    }
}

/// Finite differences for the Jacobians of [`FiniteDifferences`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    /// (Φ(z + h e_k) − Φ(z)) / h, h = √ε·max(1, |z_k|): one residual per column, error ~√ε.
    Forward,
    /// (Φ(z + h e_k) − Φ(z − h e_k)) / 2h, h = ∛ε·max(1, |z_k|): two per column, error ~ε^(2/3).
    Central,
}

/// What many users write by hand: only the residual function Φ(x, q) (here
/// [`DynMechanism::residual`], e.g. the generic engine's residual tape), Jacobians by finite
/// differences, dense full-system Newton with nalgebra's `DMatrix` LU (no block structure), and:
/// - velocities from J q̇ = −Φx ẋ, both Jacobians by finite differences at the solution;
/// - accelerations from J q̈ = −Φx ẍ − D²Φ[v, v] with v = (ẋ, q̇), the second directional
///   derivative by a central second difference along v (step ε^(1/4) relative; error ~√ε);
/// - points from the engine's point function.
///
/// Newton stops when the largest step is at most `tolerance` (radians), or fails at `max_iterations`.
pub struct FiniteDifferences<'k, K: ?Sized> {
    k: &'k K,
    pub scheme: Scheme,
    pub tolerance: f64,
    pub max_iterations: u32,
    x: f64,
    q: DVector<f64>,
    qd: DVector<f64>,
    qdd: DVector<f64>,
    points: Vec<PointMotion<f64>>,
}

impl<'k, K: DynMechanism<f64> + ?Sized> FiniteDifferences<'k, K> {
    pub fn new(k: &'k K, scheme: Scheme) -> Self {
        let points = vec![PointMotion::default(); k.info().points.len()];
        FiniteDifferences {
            k,
            scheme,
            tolerance: 1e-12,
            max_iterations: 50,
            x: 0.0,
            q: DVector::zeros(N),
            qd: DVector::zeros(N),
            qdd: DVector::zeros(N),
            points,
        }
    }

    fn phi(&self, x: f64, q: &DVector<f64>) -> Result<DVector<f64>, String> {
        let mut out = DVector::zeros(q.len());
        self.k
            .residual(&[x], q.as_slice(), out.as_mut_slice())
            .map_err(|e| e.to_string())?;
        Ok(out)
    }

    /// ∂Φ/∂q by finite differences; `phi0` = Φ(x, q).
    fn jacobian(
        &self,
        x: f64,
        q: &DVector<f64>,
        phi0: &DVector<f64>,
    ) -> Result<DMatrix<f64>, String> {
        let n = q.len();
        let mut j = DMatrix::zeros(n, n);
        let mut z = q.clone();
        for k in 0..n {
            let qk = q[k];
            match self.scheme {
                Scheme::Forward => {
                    let h = f64::EPSILON.sqrt() * qk.abs().max(1.0);
                    z[k] = qk + h;
                    let h = z[k] - qk; // the step actually taken
                    let col = (self.phi(x, &z)? - phi0) / h;
                    j.set_column(k, &col);
                }
                Scheme::Central => {
                    let h = f64::EPSILON.cbrt() * qk.abs().max(1.0);
                    z[k] = qk + h;
                    let plus = self.phi(x, &z)?;
                    z[k] = qk - h;
                    let minus = self.phi(x, &z)?;
                    j.set_column(k, &((plus - minus) / (2.0 * h)));
                }
            }
            z[k] = qk;
        }
        Ok(j)
    }

    /// ∂Φ/∂x (one input) by finite differences.
    fn input_jacobian(
        &self,
        x: f64,
        q: &DVector<f64>,
        phi0: &DVector<f64>,
    ) -> Result<DVector<f64>, String> {
        Ok(match self.scheme {
            Scheme::Forward => {
                let h = f64::EPSILON.sqrt() * x.abs().max(1.0);
                let xh = x + h;
                (self.phi(xh, q)? - phi0) / (xh - x)
            }
            Scheme::Central => {
                let h = f64::EPSILON.cbrt() * x.abs().max(1.0);
                (self.phi(x + h, q)? - self.phi(x - h, q)?) / (2.0 * h)
            }
        })
    }

    /// Dense Newton on all unknowns from the guess in `self.q`; the iterations taken.
    fn newton(&mut self, x: f64) -> Result<u32, String> {
        for it in 1..=self.max_iterations {
            let r = self.phi(x, &self.q)?;
            let j = self.jacobian(x, &self.q, &r)?;
            let dq = j.lu().solve(&r).ok_or("singular Jacobian")?;
            self.q -= &dq;
            let step = dq.amax();
            if !step.is_finite() {
                return Err(format!("Newton diverged at {x}"));
            }
            if step <= self.tolerance {
                return Ok(it);
            }
        }
        Err(format!("Newton: no convergence at {x}"))
    }

    /// Velocities, accelerations and points at the solved positions (input rate 1, acceleration 0).
    fn rates(&mut self, x: f64) -> Result<(), String> {
        let (xd, xdd) = (1.0, 0.0);
        let phi0 = self.phi(x, &self.q)?;
        let lu = self.jacobian(x, &self.q, &phi0)?.lu();
        let phi_x = self.input_jacobian(x, &self.q, &phi0)?;
        self.qd = lu.solve(&(-&phi_x * xd)).ok_or("singular Jacobian")?;
        // D²Φ[v, v] along v = (ẋ, q̇): a central second difference, step ε^(1/4) relative.
        let size = self.q.amax().max(x.abs()).max(1.0);
        let speed = self.qd.amax().max(xd.abs());
        let s = f64::EPSILON.powf(0.25) * size / speed;
        let plus = self.phi(x + s * xd, &(&self.q + &self.qd * s))?;
        let minus = self.phi(x - s * xd, &(&self.q - &self.qd * s))?;
        let second = (plus - &phi0 * 2.0 + minus) / (s * s);
        self.qdd = lu
            .solve(&(-(second + phi_x * xdd)))
            .ok_or("singular Jacobian")?;
        self.k
            .points(
                InputMotion::new(&[x], &[xd], &[xdd]),
                self.q.as_slice(),
                self.qd.as_slice(),
                self.qdd.as_slice(),
                &mut self.points,
            )
            .map_err(|e| e.to_string())
    }
}

impl<K: DynMechanism<f64> + ?Sized> Stepper for FiniteDifferences<'_, K> {
    fn reset(&mut self, x: f64) -> Result<(), String> {
        self.q = DVector::from_column_slice(&Sixbar::<f64>::start().1.to_array());
        self.x = x;
        self.newton(x)?;
        self.rates(x)
    }

    #[inline]
    fn step(&mut self, x: f64, dx: f64) -> Result<Tick, String> {
        self.q += &self.qd * dx + &self.qdd * (0.5 * dx * dx);
        self.x = x;
        let iterations = self.newton(x)?;
        self.rates(x)?;
        Ok(Tick {
            iterations,
            failed: false,
        })
    }

    fn state(&self) -> State {
        let mut s = State::default();
        s.q.copy_from_slice(self.q.as_slice());
        s.qd.copy_from_slice(self.qd.as_slice());
        s.qdd.copy_from_slice(self.qdd.as_slice());
        s
    }
}
