//! Inverse dynamics, written once for every engine: from a solved state, the bodies' motion
//! ([`DynMechanism::bodies`]) and their velocity coefficients along one input, the effort that
//! input's driver must apply against inertia, gravity and loads at points, with the generalized
//! inertia, the kinetic and potential energy and the shaking force and moment.
//!
//! With `x` the input, `G` a body's centre of mass, `φ` its angle, `c_G = ∂G/∂x` and
//! `c_φ = ∂φ/∂x` its velocity coefficients along the loop (the other inputs held), and `c_P` a
//! loaded point's, virtual work gives
//!
//! ```text
//! effort  Q    = Σ m (a_G − g)·c_G + I φ̈ c_φ  −  Σ F·c_P
//! inertia M_xx = Σ m |c_G|² + I c_φ²
//! T = ½ Σ m |v_G|² + I φ̇²,  V = −Σ m g·G,  F_shake = −Σ m a_G,  M_shake = −Σ G × m a_G + I φ̈.
//! ```

use alloc::vec;
use alloc::vec::Vec;

use crate::dyn_tick::{DynTick, StateRef};
use crate::dynamic::DynMechanism;
use crate::error::SolveError;
use crate::info::{BodyMass, BodyMotion, MechanismInfo, PointMotion};
use crate::mechanism::{BodySink, InputMotion, State, StaticMechanism, TickBodies};
use crate::scalar::Real;
use crate::solve::SolveOptions;

/// A force at a point (index into `info().points`), in the file's units, acting everywhere or
/// only while the driven angle input lies in `range`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLoad<T> {
    pub point: usize,
    pub force: [T; 2],
    /// `[from, to]` in radians, taken modulo a turn (`to` below `from` wraps through 0); `None`:
    /// the load always acts.
    pub range: Option<[T; 2]>,
}

impl<T: Real> PointLoad<T> {
    /// A load that always acts.
    pub fn new(point: usize, force: [T; 2]) -> Self {
        PointLoad {
            point,
            force,
            range: None,
        }
    }

    /// A load that acts while the driven angle input lies in `[from, to]` radians.
    pub fn over(point: usize, force: [T; 2], range: [T; 2]) -> Self {
        PointLoad {
            point,
            force,
            range: Some(range),
        }
    }

    /// Whether the load acts at input `x` (radians).
    pub fn acts_at(&self, x: T) -> bool {
        let Some([a, b]) = self.range else {
            return true;
        };
        let tau = core::f64::consts::TAU;
        let turn = |v: T| {
            let r = v.to_f64() % tau;
            if r < 0.0 { r + tau } else { r }
        };
        if (b - a).to_f64() >= tau {
            return true;
        }
        let (t, a, b) = (turn(x), turn(a), turn(b));
        if a <= b {
            a <= t && t <= b
        } else {
            t >= a || t <= b
        }
    }
}

/// Inverse dynamics at one state, for the input it was asked about.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dynamics<T> {
    /// The generalized force the input's driver applies so that the mechanism follows the
    /// state's motion: a torque for an angle input, a force for a length input.
    pub effort: T,
    /// The generalized inertia on the input, Σ m |∂G/∂x|² + I (∂φ/∂x)².
    pub inertia: T,
    pub kinetic: T,
    /// Of gravity, zero at the origin.
    pub potential: T,
    /// −Σ m a_G: the force the moving bodies put on the frame, gravity apart.
    pub shaking_force: [T; 2],
    /// −Σ (G × m a_G + I φ̈), about the origin.
    pub shaking_moment: T,
}

/// The sums of the module's formulas over bodies and loads. `coefficients` are the bodies'
/// motions at unit input rate (only their velocities are read: `∂G/∂x`, `∂φ/∂x`); each load is a
/// force with its point's coefficient `∂P/∂x`.
pub fn inverse_dynamics<T: Real>(
    gravity: [T; 2],
    masses: &[BodyMass<T>],
    motion: &[BodyMotion<T>],
    coefficients: &[BodyMotion<T>],
    loads: impl IntoIterator<Item = ([T; 2], [T; 2])>,
) -> Dynamics<T> {
    let mut sums = Sums::new(gravity);
    for (k, ((b, s), c)) in masses.iter().zip(motion).zip(coefficients).enumerate() {
        sums.add(k, *b, s, c.com.velocity, c.angle[1]);
    }
    sums.total(loads)
}

/// The module's sums, body by body ([`Sums::add`], the one place the formulas are written): each
/// body's motion with its coefficients `(c_G, c_φ)`. Gravity enters through two sums over the
/// bodies (Σ m c_G and Σ m G), not per body; a product that both the inertia and the kinetic
/// energy need (`(m v) · v` when the coefficients are the rates) is written the same way in
/// both, so it is computed once.
#[derive(Clone, Copy, Debug)]
struct Sums<T> {
    gravity: [T; 2],
    effort: T,
    inertia: T,
    twice_kinetic: T,
    torque: T,
    mass_c: [T; 2],
    mass_g: [T; 2],
    force: [T; 2],
    /// The first body whose mass or inertia is negative or not finite.
    bad: Option<usize>,
}

impl<T: Real> Sums<T> {
    fn new(gravity: [T; 2]) -> Self {
        let zero = T::zero();
        Sums {
            gravity,
            effort: zero,
            inertia: zero,
            twice_kinetic: zero,
            torque: zero,
            mass_c: [zero; 2],
            mass_g: [zero; 2],
            force: [zero; 2],
            bad: None,
        }
    }

    /// One body, `c` and `c_phi` its coefficients.
    #[inline(always)]
    fn add(&mut self, index: usize, b: BodyMass<T>, s: &BodyMotion<T>, c: [T; 2], c_phi: T) {
        let (m, i) = (b.mass, b.inertia);
        // Finite and not negative (a NaN fails both comparisons).
        let good = |v: T| v >= T::zero() && v <= T::MAX;
        if !(good(m) && good(i)) && self.bad.is_none() {
            self.bad = Some(index);
        }
        let (g, v, a) = (s.com.position, s.com.velocity, s.com.acceleration);
        let (omega, alpha) = (s.angle[1], s.angle[2]);
        let f = [m * a[0], m * a[1]];
        let mc = [m * c[0], m * c[1]];
        let mv = [m * v[0], m * v[1]];
        let i_alpha = i * alpha;
        self.effort += f[0] * c[0] + f[1] * c[1] + i_alpha * c_phi;
        self.inertia += mc[0] * c[0] + mc[1] * c[1] + i * c_phi * c_phi;
        self.twice_kinetic += mv[0] * v[0] + mv[1] * v[1] + i * omega * omega;
        self.torque += g[0] * f[1] - g[1] * f[0] + i_alpha;
        for k in 0..2 {
            self.mass_c[k] += mc[k];
            self.mass_g[k] += m * g[k];
            self.force[k] += f[k];
        }
    }

    /// A bad mass or inertia (`BadMass`), or gravity not finite.
    fn check(&self) -> Result<(), SolveError> {
        if let Some(body) = self.bad {
            return Err(SolveError::BadMass { body });
        }
        if !self.gravity.iter().all(|g| g.is_finite()) {
            return Err(SolveError::NonFinite {
                quantity: crate::error::Quantity::Param,
                index: 0,
            });
        }
        Ok(())
    }

    /// The totals, with each load's force and its point's coefficient.
    #[inline(always)]
    fn total(self, loads: impl IntoIterator<Item = ([T; 2], [T; 2])>) -> Dynamics<T> {
        let (gravity, mut effort) = (self.gravity, self.effort);
        effort -= gravity[0] * self.mass_c[0] + gravity[1] * self.mass_c[1];
        for (cp, f) in loads {
            effort -= f[0] * cp[0] + f[1] * cp[1];
        }
        Dynamics {
            effort,
            inertia: self.inertia,
            kinetic: T::lit(0.5) * self.twice_kinetic,
            potential: -(gravity[0] * self.mass_g[0] + gravity[1] * self.mass_g[1]),
            shaking_force: [-self.force[0], -self.force[1]],
            shaking_moment: -self.torque,
        }
    }

    /// [`Sums::total`] of sums over the rates of one moving input (rate `rate`, not zero): the
    /// power and twice the kinetic energy, so the effort and the inertia are those over ẋ and ẋ².
    #[inline(always)]
    fn per_rate(self, rate: T, loads: impl IntoIterator<Item = ([T; 2], [T; 2])>) -> Dynamics<T> {
        // The reciprocal first: its latency overlaps the sums.
        let inv = T::one() / rate;
        let d = self.total(loads);
        Dynamics {
            effort: d.effort * inv,
            inertia: d.inertia * inv * inv,
            ..d
        }
    }
}

/// A sink for a tick's bodies ([`BodySink`]) that sums them at once, each body's own rates its
/// coefficients (one input moving).
struct AtRates<T>(Sums<T>);

impl<T: Real> BodySink<T> for AtRates<T> {
    #[inline(always)]
    fn gravity(&mut self, gravity: [T; 2]) {
        self.0.gravity = gravity;
    }
    #[inline(always)]
    fn body(&mut self, index: usize, mass: BodyMass<T>, motion: BodyMotion<T>) {
        self.0
            .add(index, mass, &motion, motion.com.velocity, motion.angle[1]);
    }
}

/// What [`dynamics`] works in: grown once for a mechanism ([`DynamicsWork::new`]), then nothing
/// is allocated.
#[derive(Clone, Debug)]
pub struct DynamicsWork<T> {
    masses: Vec<BodyMass<T>>,
    motion: Vec<BodyMotion<T>>,
    unit: UnitWork<T>,
}

/// The velocity solve at unit input rate (when other inputs move too) works in these.
#[derive(Clone, Debug)]
struct UnitWork<T> {
    unit: Vec<BodyMotion<T>>,
    points: Vec<PointMotion<T>>,
    xd: Vec<T>,
    qd: Vec<T>,
    zx: Vec<T>,
    zq: Vec<T>,
}

impl<T: Real> DynamicsWork<T> {
    /// Sized for the mechanism `info` describes.
    pub fn new(info: &MechanismInfo) -> Self {
        let (ni, nu, nb) = (info.inputs.len(), info.unknowns.len(), info.bodies.len());
        DynamicsWork {
            masses: vec![BodyMass::default(); nb],
            motion: vec![BodyMotion::default(); nb],
            unit: UnitWork {
                unit: vec![BodyMotion::default(); nb],
                points: vec![PointMotion::default(); info.points.len()],
                xd: vec![T::zero(); ni],
                qd: vec![T::zero(); nu],
                zx: vec![T::zero(); ni],
                zq: vec![T::zero(); nu],
            },
        }
    }
}

/// Inverse dynamics of `m` at its solved `state` for the input `input`, under `loads` (the other
/// inputs are taken at rest: their rates must be zero for the effort to mean the driver's).
///
/// The velocity coefficients come from the state itself when only `input` moves (`∂G/∂x` =
/// `Ġ / ẋ`), else from a velocity solve at unit rate of `input`. Errors: an index out of range,
/// slices of the wrong length, a negative or non-finite mass or inertia (`BadMass`: params
/// changed at run time), and a singular velocity solve (a dead point) on the second way.
pub fn dynamics<T: Real, M: DynMechanism<T> + ?Sized>(
    m: &M,
    state: &StateRef<'_, T>,
    input: usize,
    loads: &[PointLoad<T>],
    ws: &mut DynamicsWork<T>,
) -> Result<Dynamics<T>, SolveError> {
    let gravity = m.mass_properties(&mut ws.masses)?;
    let at = InputMotion::new(state.x, state.xd, state.xdd);
    m.bodies(at, state.q, state.qd, state.qdd, &mut ws.motion)?;
    let bodies = (gravity, &ws.masses[..], &ws.motion[..]);
    finish(m, state, input, loads, bodies, &mut ws.unit)
}

/// [`dynamics`] right after a tick of a generated mechanism: its bodies on the sines and cosines
/// the tick keeps, in arrays of the mechanism's own sizes (`StaticMechanism::with_tick_bodies`),
/// then the same sums.
#[inline]
pub fn tick_dynamics<T: Real, M: StaticMechanism<T>>(
    m: &M,
    t: &M::Tick,
    input: usize,
    loads: &[PointLoad<T>],
    ws: &mut DynamicsWork<T>,
) -> Result<Dynamics<T>, SolveError> {
    m.with_tick_bodies(t, |bodies| after_tick(m, t, (input, loads), bodies, ws))
}

/// One tick of a generated mechanism to `motion` ([`StaticMechanism::tick`]) and the inverse
/// dynamics of its new state for the input `input`, the bodies computed in the tick's own body
/// (`StaticMechanism::tick_with_bodies`): the fastest way to both. On error `t` is unchanged.
#[inline]
pub fn tick_with_dynamics<T: Real, M: StaticMechanism<T>>(
    m: &M,
    t: &mut M::Tick,
    motion: &InputMotion<M::X>,
    options: &SolveOptions<T>,
    (input, loads): (usize, &[PointLoad<T>]),
    ws: &mut DynamicsWork<T>,
) -> Result<Dynamics<T>, SolveError> {
    let Some(rate) = alone_rate(motion.xd.as_ref(), input) else {
        return m.tick_with_bodies(t, motion, options, |t, bodies| {
            after_tick(m, t, (input, loads), bodies, ws)
        });
    };
    // One input moving: the tick hands each body straight to the sums.
    check_indices(
        (input, motion.x.as_ref().len()),
        loads,
        t.points.as_ref().len(),
    )?;
    let mut sums = AtRates(Sums::new([T::zero(); 2]));
    m.tick_with_sink(t, motion, options, &mut sums)?;
    sums.0.check()?;
    let x = t.x.as_ref()[input];
    Ok(sums.0.per_rate(rate, acting(loads, x, t.points.as_ref())))
}

/// One tick of any engine's tick on slices ([`DynTick::tick`]) and the inverse dynamics of its new
/// state for the input `input` under `loads` ([`dynamics`] of `m`, the mechanism that made the
/// tick). When that input alone moves and the tick hands its bodies over
/// ([`DynTick::tick_with_sink`]: a generated mechanism's, in the tick's own body, and the generic
/// engine's, on the tick's sines and cosines), they go straight to the sums. On the tick's
/// error its state is unchanged (an index out of range is found after the tick).
pub fn dyn_tick_dynamics<T: Real>(
    m: &dyn DynMechanism<T>,
    tick: &mut dyn DynTick<T>,
    motion: InputMotion<&[T]>,
    options: &SolveOptions<T>,
    (input, loads): (usize, &[PointLoad<T>]),
    ws: &mut DynamicsWork<T>,
) -> Result<Dynamics<T>, SolveError> {
    if let Some(rate) = alone_rate(motion.xd, input) {
        let mut sums = AtRates(Sums::new([T::zero(); 2]));
        if tick.tick_with_sink(motion, options, &mut sums)? {
            let state = tick.state().ok_or(SolveError::NotStarted)?;
            check_indices((input, state.x.len()), loads, state.points.len())?;
            sums.0.check()?;
            let x = state.x[input];
            return Ok(sums.0.per_rate(rate, acting(loads, x, state.points)));
        }
    } else {
        tick.tick(motion, options)?;
    }
    let state = tick.state().ok_or(SolveError::NotStarted)?;
    dynamics(m, &state, input, loads, ws)
}

/// The rate of `input` when it alone moves (every other input's rate zero) and does move.
fn alone_rate<T: Real>(xd: &[T], input: usize) -> Option<T> {
    let rate = *xd.get(input)?;
    let alone = xd
        .iter()
        .enumerate()
        .all(|(j, &v)| j == input || v == T::zero());
    (alone && rate != T::zero()).then_some(rate)
}

/// `input` among `ni` inputs, every load's point among `np` points.
fn check_indices<T>(
    (input, ni): (usize, usize),
    loads: &[PointLoad<T>],
    np: usize,
) -> Result<(), SolveError> {
    if input >= ni {
        return Err(SolveError::OutOfRange {
            index: input,
            len: ni,
        });
    }
    match loads.iter().find(|l| l.point >= np) {
        Some(l) => Err(SolveError::OutOfRange {
            index: l.point,
            len: np,
        }),
        None => Ok(()),
    }
}

/// The loads acting at input `x`, each with its point's velocity (or coefficient) in `points`.
fn acting<'a, T: Real>(
    loads: &'a [PointLoad<T>],
    x: T,
    points: &'a [PointMotion<T>],
) -> impl Iterator<Item = ([T; 2], [T; 2])> + 'a {
    loads
        .iter()
        .filter(move |l| l.acts_at(x))
        .map(|l| (points[l.point].velocity, l.force))
}

/// The sums at a tick's state, given its bodies.
#[inline(always)]
fn after_tick<T: Real, M: StaticMechanism<T>>(
    m: &M,
    t: &M::Tick,
    (input, loads): (usize, &[PointLoad<T>]),
    bodies: TickBodies<'_, T>,
    ws: &mut DynamicsWork<T>,
) -> Result<Dynamics<T>, SolveError> {
    let state = State {
        x: t.x.as_ref(),
        xd: t.xd.as_ref(),
        xdd: t.xdd.as_ref(),
        q: t.q.as_ref(),
        qd: t.qd.as_ref(),
        qdd: t.qdd.as_ref(),
        points: t.points.as_ref(),
        report: t.report,
    };
    finish(m, &state, input, loads, bodies, &mut ws.unit)
}

/// The sums, given gravity, the masses and the bodies' motion at `state`: over the state's own
/// rates when one input moves, else over coefficients from a velocity solve at unit rate.
#[inline(always)]
fn finish<T: Real, M: DynMechanism<T> + ?Sized>(
    m: &M,
    state: &StateRef<'_, T>,
    input: usize,
    loads: &[PointLoad<T>],
    (gravity, masses, motion): ([T; 2], &[BodyMass<T>], &[BodyMotion<T>]),
    ws: &mut UnitWork<T>,
) -> Result<Dynamics<T>, SolveError> {
    check_indices((input, state.x.len()), loads, state.points.len())?;
    let x = state.x[input];
    if let Some(rate) = alone_rate(state.xd, input) {
        // Ġ = (∂G/∂x) ẋ when x alone moves.
        let mut sums = AtRates(Sums::new(gravity));
        for (k, (b, s)) in masses.iter().zip(motion).enumerate() {
            sums.body(k, *b, *s);
        }
        sums.0.check()?;
        return Ok(sums.0.per_rate(rate, acting(loads, x, state.points)));
    }
    ws.xd.fill(T::zero());
    ws.xd[input] = T::one();
    m.solve_velocity(state.x, state.q, &ws.xd, &mut ws.qd)?;
    let unit = InputMotion::new(state.x, &ws.xd[..], &ws.zx[..]);
    m.bodies(unit, state.q, &ws.qd, &ws.zq, &mut ws.unit)?;
    if !loads.is_empty() {
        m.points(unit, state.q, &ws.qd, &ws.zq, &mut ws.points)?;
    }
    let mut sums = Sums::new(gravity);
    for (k, ((b, s), c)) in masses.iter().zip(motion).zip(&ws.unit).enumerate() {
        sums.add(k, *b, s, c.com.velocity, c.angle[1]);
    }
    sums.check()?;
    Ok(sums.total(acting(loads, x, &ws.points)))
}
