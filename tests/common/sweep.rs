//! Shared by the sweep tests: a [`DynMechanism`] wrapper that counts solves (and can report another
//! start), and the closed forms of the test mechanisms in `tests/data/sweep/`, computed here
//! independently of the solvers.
#![allow(dead_code)]

use std::cell::Cell;

use mechgen::{
    DynMechanism, DynState, InputMotion, MechanismInfo, NewtonReport, PointMotion, SolveError,
    SolveOptions,
};

/// Counts every call that solves or evaluates something; `info` may differ from the inner one's
/// (another start configuration).
pub struct Counting<'a> {
    pub inner: &'a dyn DynMechanism<f64>,
    pub info: MechanismInfo,
    pub calls: Cell<usize>,
}

impl<'a> Counting<'a> {
    pub fn new(inner: &'a dyn DynMechanism<f64>) -> Self {
        Counting {
            inner,
            info: inner.info(),
            calls: Cell::new(0),
        }
    }

    fn count(&self) {
        self.calls.set(self.calls.get() + 1);
    }
}

impl DynMechanism<f64> for Counting<'_> {
    /// The runtime's tick on slices: every solve it makes goes through the counted methods.
    fn ticker(&self) -> Box<dyn mechgen::DynTick<f64> + '_> {
        Box::new(mechgen::ticks::SolveTick::new(self))
    }
    fn info(&self) -> MechanismInfo {
        self.info.clone()
    }
    fn residual(&self, x: &[f64], q: &[f64], out: &mut [f64]) -> Result<(), SolveError> {
        self.count();
        self.inner.residual(x, q, out)
    }
    fn jacobian(&self, x: &[f64], q: &[f64], out: &mut [f64]) -> Result<(), SolveError> {
        self.count();
        self.inner.jacobian(x, q, out)
    }
    fn input_jacobian(&self, x: &[f64], q: &[f64], out: &mut [f64]) -> Result<(), SolveError> {
        self.count();
        self.inner.input_jacobian(x, q, out)
    }
    fn jacobian_dot(
        &self,
        x: &[f64],
        q: &[f64],
        xd: &[f64],
        qd: &[f64],
        out: &mut [f64],
    ) -> Result<(), SolveError> {
        self.count();
        self.inner.jacobian_dot(x, q, xd, qd, out)
    }
    fn acceleration_rhs(
        &self,
        x: &[f64],
        q: &[f64],
        xd: &[f64],
        qd: &[f64],
        xdd: &[f64],
        out: &mut [f64],
    ) -> Result<(), SolveError> {
        self.count();
        self.inner.acceleration_rhs(x, q, xd, qd, xdd, out)
    }
    fn solve_position(
        &self,
        x: &[f64],
        q: &mut [f64],
        options: &SolveOptions<f64>,
    ) -> Result<NewtonReport<f64>, SolveError> {
        self.count();
        self.inner.solve_position(x, q, options)
    }
    fn solve_velocity(
        &self,
        x: &[f64],
        q: &[f64],
        xd: &[f64],
        qd: &mut [f64],
    ) -> Result<(), SolveError> {
        self.count();
        self.inner.solve_velocity(x, q, xd, qd)
    }
    fn solve_acceleration(
        &self,
        x: &[f64],
        q: &[f64],
        xd: &[f64],
        qd: &[f64],
        xdd: &[f64],
        qdd: &mut [f64],
    ) -> Result<(), SolveError> {
        self.count();
        self.inner.solve_acceleration(x, q, xd, qd, xdd, qdd)
    }
    fn points(
        &self,
        input: InputMotion<&[f64]>,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut [PointMotion<f64>],
    ) -> Result<(), SolveError> {
        self.count();
        self.inner.points(input, q, qd, qdd, out)
    }
    fn sensitivities(
        &self,
        x: &[f64],
        q: &[f64],
        unknowns: &mut [f64],
        points: &mut [f64],
    ) -> Result<(), SolveError> {
        self.count();
        self.inner.sensitivities(x, q, unknowns, points)
    }
    fn solve_in_place(
        &self,
        state: &mut DynState<f64>,
        options: &SolveOptions<f64>,
    ) -> Result<(), SolveError> {
        self.count();
        self.inner.solve_in_place(state, options)
    }
}

/// Positions and rates (input rate 1) of one row: `[q…]`, `[q̇…]`.
pub type Exact = (Vec<f64>, Vec<f64>);

/// The oblique trammel (`trammel.toml`) at slider position `sx`, on the branch
/// sy = sx cos φ + √(L² − sx² sin² φ): `([q, sy], [q', sy'])`, or `None` out of reach.
pub fn trammel(l: f64, phi: f64, sx: f64) -> Option<Exact> {
    let (s, c) = phi.sin_cos();
    let disc = l * l - sx * sx * s * s;
    if disc <= 0.0 {
        return None;
    }
    let root = disc.sqrt();
    let sy = sx * c + root;
    let dsy = c - sx * s * s / root;
    let (x, y) = (sy * c - sx, sy * s);
    let (dx, dy) = (dsy * c - 1.0, dsy * s);
    let q = y.atan2(x);
    let dq = (x * dy - y * dx) / (x * x + y * y);
    Some((vec![q, sy], vec![dq, dsy]))
}

/// The in-line slider-crank (`slider_inline.toml`) at crank angle `q1`, branch cos q2 > 0:
/// `([q2, s], [q2', s'])`.
pub fn slider_inline(r: f64, l: f64, x0: f64, q1: f64) -> Exact {
    let (s1, c1) = q1.sin_cos();
    let sin2 = r * s1 / l;
    let cos2 = (1.0 - sin2 * sin2).sqrt();
    let q2 = -sin2.asin();
    let dq2 = -(r * c1 / l) / cos2;
    let s = r * c1 + l * cos2 - x0;
    let ds = -r * s1 + l * sin2 * dq2;
    (vec![q2, s], vec![dq2, ds])
}

/// The compiled-in offset slider-crank (`r e(q1) + l e(q2) − sC − (0, off)`) on its branch with
/// cos q2 > 0: `([q2, sC], [q2', sC'])`, or `None` out of reach.
pub fn slider_offset(r: f64, l: f64, off: f64, q1: f64) -> Option<Exact> {
    let (s1, c1) = q1.sin_cos();
    let sin2 = (off - r * s1) / l;
    if sin2.abs() >= 1.0 {
        return None;
    }
    let cos2 = (1.0 - sin2 * sin2).sqrt();
    let dq2 = -r * c1 / (l * cos2);
    let sc = r * c1 + l * cos2;
    let dsc = -r * s1 - l * sin2 * dq2;
    Some((vec![sin2.atan2(cos2), sc], vec![dq2, dsc]))
}

/// The five-bar (`fivebar.toml`, params 0.1, 0.25, 0.25, 0.1, 0.15) at cranks `q1`, `q4`, with C
/// on the left of B→E: `[q2, q3]`.
pub fn fivebar(q1: f64, q4: f64) -> [f64; 2] {
    let (l1, l2, l3, l4, l5) = (0.1, 0.25, 0.25, 0.1, 0.15);
    let b = [l1 * q1.cos(), l1 * q1.sin()];
    let e = [l5 + l4 * q4.cos(), l4 * q4.sin()];
    let (dx, dy) = (e[0] - b[0], e[1] - b[1]);
    let d = dx.hypot(dy);
    let a = (l2 * l2 - l3 * l3 + d * d) / (2.0 * d);
    let h = (l2 * l2 - a * a).sqrt();
    let (ux, uy) = (dx / d, dy / d);
    let c = [b[0] + a * ux - h * uy, b[1] + a * uy + h * ux];
    [
        (c[1] - b[1]).atan2(c[0] - b[0]),
        (c[1] - e[1]).atan2(c[0] - e[0]),
    ]
}

/// Angle difference folded into (−π, π].
pub fn angle_diff(a: f64, b: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let d = (a - b).rem_euclid(tau);
    if d > std::f64::consts::PI { d - tau } else { d }
}

/// Path of a test mechanism file, from the crate root.
pub fn data(file: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/sweep")
        .join(file)
}

/// The one mechanism of a test file, for the generic engine.
pub fn load(file: &str) -> mechgen::generic::Generic {
    let mut mechs = mechgen::generic::load_file(&data(file)).expect("test file loads");
    mechs.remove(0)
}
