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

use crate::dyn_tick::StateRef;
use crate::dynamic::DynMechanism;
use crate::error::SolveError;
use crate::info::{BodyMass, BodyMotion, MechanismInfo, PointMotion};
use crate::mechanism::{InputMotion, State, StaticMechanism, TickBodies};
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
    let scaled = motion.iter().zip(coefficients).map(|(s, c)| {
        let (cg, cphi) = (c.com.velocity, c.angle[1]);
        (s, cg, cphi)
    });
    sums(gravity, masses, scaled, loads)
}

/// [`inverse_dynamics`] over each body's motion with its coefficients `(c_G, c_φ)`. Gravity
/// enters through two sums over the bodies (Σ m c_G and Σ m G), not per body; a product that
/// both the inertia and the kinetic energy need (`(m v) · v` when the coefficients are the rates)
/// is written the same way in both, so it is computed once.
#[inline(always)]
fn sums<'a, T: Real>(
    gravity: [T; 2],
    masses: &[BodyMass<T>],
    bodies: impl Iterator<Item = (&'a BodyMotion<T>, [T; 2], T)>,
    loads: impl IntoIterator<Item = ([T; 2], [T; 2])>,
) -> Dynamics<T> {
    let zero = T::zero();
    let (mut effort, mut inertia, mut twice_kinetic, mut torque) = (zero, zero, zero, zero);
    let (mut mass_c, mut mass_g, mut force) = ([zero; 2], [zero; 2], [zero; 2]);
    for (b, (s, c, c_phi)) in masses.iter().zip(bodies) {
        let (m, i) = (b.mass, b.inertia);
        let (g, v, a) = (s.com.position, s.com.velocity, s.com.acceleration);
        let (omega, alpha) = (s.angle[1], s.angle[2]);
        let f = [m * a[0], m * a[1]];
        let mc = [m * c[0], m * c[1]];
        let mv = [m * v[0], m * v[1]];
        let i_alpha = i * alpha;
        effort += f[0] * c[0] + f[1] * c[1] + i_alpha * c_phi;
        inertia += mc[0] * c[0] + mc[1] * c[1] + i * c_phi * c_phi;
        twice_kinetic += mv[0] * v[0] + mv[1] * v[1] + i * omega * omega;
        torque += g[0] * f[1] - g[1] * f[0] + i_alpha;
        for k in 0..2 {
            mass_c[k] += mc[k];
            mass_g[k] += m * g[k];
            force[k] += f[k];
        }
    }
    effort -= gravity[0] * mass_c[0] + gravity[1] * mass_c[1];
    for (cp, f) in loads {
        effort -= f[0] * cp[0] + f[1] * cp[1];
    }
    Dynamics {
        effort,
        inertia,
        kinetic: T::lit(0.5) * twice_kinetic,
        potential: -(gravity[0] * mass_g[0] + gravity[1] * mass_g[1]),
        shaking_force: [-force[0], -force[1]],
        shaking_moment: -torque,
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
    m.tick_with_bodies(t, motion, options, |t, bodies| {
        after_tick(m, t, (input, loads), bodies, ws)
    })
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

/// The sums, given gravity, the masses and the bodies' motion at `state`: the coefficients from
/// the state's rates (or a velocity solve at unit rate), then [`inverse_dynamics`].
#[inline(always)]
fn finish<T: Real, M: DynMechanism<T> + ?Sized>(
    m: &M,
    state: &StateRef<'_, T>,
    input: usize,
    loads: &[PointLoad<T>],
    (gravity, masses, motion): ([T; 2], &[BodyMass<T>], &[BodyMotion<T>]),
    ws: &mut UnitWork<T>,
) -> Result<Dynamics<T>, SolveError> {
    let (ni, np) = (state.x.len(), state.points.len());
    if input >= ni {
        return Err(SolveError::OutOfRange {
            index: input,
            len: ni,
        });
    }
    if let Some(l) = loads.iter().find(|l| l.point >= np) {
        return Err(SolveError::OutOfRange {
            index: l.point,
            len: np,
        });
    }
    // Finite and not negative (a NaN fails both comparisons).
    let good = |v: T| v >= T::zero() && v <= T::MAX;
    if let Some(body) = masses
        .iter()
        .position(|b| !good(b.mass) || !good(b.inertia))
    {
        return Err(SolveError::BadMass { body });
    }
    if !gravity.iter().all(|g| g.is_finite()) {
        return Err(SolveError::NonFinite {
            quantity: crate::error::Quantity::Param,
            index: 0,
        });
    }
    let rate = state.xd[input];
    let alone = state
        .xd
        .iter()
        .enumerate()
        .all(|(j, &v)| j == input || v == T::zero());
    if alone && rate != T::zero() {
        // Ġ = (∂G/∂x) ẋ when x alone moves: the sums over the rates themselves are the power
        // and twice the kinetic energy, the effort and the inertia those over ẋ and ẋ².
        let bodies = motion.iter().map(|s| (s, s.com.velocity, s.angle[1]));
        let x = state.x[input];
        let loads = loads
            .iter()
            .filter(|l| l.acts_at(x))
            .map(|l| (state.points[l.point].velocity, l.force));
        // The reciprocal first: its latency overlaps the sums.
        let inv = T::one() / rate;
        let d = sums(gravity, masses, bodies, loads);
        return Ok(Dynamics {
            effort: d.effort * inv,
            inertia: d.inertia * inv * inv,
            ..d
        });
    }
    ws.xd.fill(T::zero());
    ws.xd[input] = T::one();
    m.solve_velocity(state.x, state.q, &ws.xd, &mut ws.qd)?;
    let unit = InputMotion::new(state.x, &ws.xd[..], &ws.zx[..]);
    m.bodies(unit, state.q, &ws.qd, &ws.zq, &mut ws.unit)?;
    if !loads.is_empty() {
        m.points(unit, state.q, &ws.qd, &ws.zq, &mut ws.points)?;
    }
    let (points, x) = (&ws.points, state.x[input]);
    let loads = loads
        .iter()
        .filter(|l| l.acts_at(x))
        .map(|l| (points[l.point].velocity, l.force));
    Ok(inverse_dynamics(gravity, masses, motion, &ws.unit, loads))
}
