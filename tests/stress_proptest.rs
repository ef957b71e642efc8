//! Property tests on random valid mechanisms: random four-bars (Grashof crank-rockers, and any
//! four-bar at an input inside its range), offset slider-cranks (r + |off| < l) and six-bars (the
//! seed's lengths perturbed by a few percent, random crank angle). Each case gets a configuration
//! computed independently in closed form (circle intersections), the same base params on the
//! generated solver and on the generic engine, and then:
//!
//! * (a) both position solves from the closed form perturbed by 1e-3 converge, to the closed form
//!   and to each other;
//! * (b) velocities and accelerations (unknowns and points) of both engines agree, and agree with
//!   central finite differences of the closed-form positions (and of the solved velocities) along
//!   the motion;
//! * (c) nothing is NaN, and every Ok position has a relative residual below the tolerance;
//! * (d) random arguments, non-finite and huge ones included, never panic, never give a non-finite
//!   Ok answer, and non-finite params, inputs, guesses and rates give `SolveError::NonFinite`.
//!
//! Cases are bounded (`CASES`, or `PROPTEST_CASES`) and the seed is fixed (or `PROPTEST_RNG_SEED`)
//! so CI runs are reproducible; a failure prints the shrunk case. The largest differences seen are
//! printed (`cargo test --test stress_proptest -- --nocapture`).
#![cfg(feature = "runtime")]
// `!(a > b)` is deliberate: a NaN must fail the test.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod common;

use std::cell::Cell;
use std::f64::consts::PI;
use std::sync::OnceLock;

use common::angle_diff;
use mechgen::generic::Generic;
use mechgen::{
    DynMechanism, InputMotion, Kind, PointMotion, Quantity, SolveError, SolveOptions, four_bar,
    generic, sixbar, slider_crank,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestRunner};

/// Cases per property (unless `PROPTEST_CASES` is set).
const CASES: u32 = 256;
/// Position solves against the closed form and each other (relative, angles in radians).
const SAME: f64 = 1e-12;
/// Finite differences against derivatives (relative).
const FD: f64 = 1e-6;

fn config(cases: u32) -> Config {
    let mut c = Config {
        failure_persistence: None,
        max_global_rejects: 100_000,
        max_local_rejects: 100_000,
        ..Config::default()
    };
    if std::env::var_os("PROPTEST_CASES").is_none() {
        c.cases = cases;
    }
    if c.rng_seed == RngSeed::Random {
        c.rng_seed = RngSeed::Fixed(0x006d_6563_6867_656e);
    }
    c
}

// ---------------------------------------------------------------------------------------------
// Random mechanisms and their closed forms

#[derive(Clone, Copy, Debug)]
enum Mech {
    FourBar {
        l: [f64; 4],
        lp: f64,
    },
    SliderCrank {
        r: f64,
        l: f64,
        off: f64,
    },
    /// l1, l2, l3, l4, l5, l6, l2e, xg, yg
    Sixbar {
        p: [f64; 9],
    },
}

/// A valid case: the mechanism, its input, which assembly branch, the perturbation of the start
/// (per unknown, in [−1, 1] × 1e-3 rad or 1e-3 length scales), input rate and acceleration.
#[derive(Clone, Copy, Debug)]
struct Spec {
    mech: Mech,
    x: f64,
    left: bool,
    perturb: [f64; 4],
    xd: f64,
    xdd: f64,
}

const SIXBAR_NAMES: [&str; 9] = ["l1", "l2", "l3", "l4", "l5", "l6", "l2e", "xg", "yg"];

impl Mech {
    fn name(&self) -> &'static str {
        match self {
            Mech::FourBar { .. } => "four_bar",
            Mech::SliderCrank { .. } => "slider_crank",
            Mech::Sixbar { .. } => "sixbar",
        }
    }

    /// The base params this case sets, by name.
    fn params(&self) -> Vec<(&'static str, f64)> {
        match *self {
            Mech::FourBar { l, lp } => vec![
                ("l1", l[0]),
                ("l2", l[1]),
                ("l3", l[2]),
                ("l4", l[3]),
                ("lp", lp),
            ],
            Mech::SliderCrank { r, l, off } => vec![("r", r), ("l", l), ("off", off)],
            Mech::Sixbar { p } => SIXBAR_NAMES.iter().copied().zip(p).collect(),
        }
    }

    /// Generated solver and generic engine with this case's params, and the generated solver's
    /// params in file order.
    fn engines(&self) -> (Box<dyn DynMechanism<f64>>, Generic, Vec<f64>) {
        fn boxed<M: DynMechanism<f64> + 'static>(
            m: M,
            p: &[f64],
        ) -> (Box<dyn DynMechanism<f64>>, Vec<f64>) {
            (Box::new(m), p.to_vec())
        }
        let (generated, params) = match *self {
            Mech::FourBar { l, lp } => {
                let params = four_bar::Params {
                    l1: l[0],
                    l2: l[1],
                    l3: l[2],
                    l4: l[3],
                    lp,
                    ..Default::default()
                };
                boxed(four_bar::FourBar { params }, &params.to_array())
            }
            Mech::SliderCrank { r, l, off } => {
                let params = slider_crank::Params { r, l, off };
                boxed(slider_crank::SliderCrank { params }, &params.to_array())
            }
            Mech::Sixbar { p } => {
                let params = sixbar::Params {
                    l1: p[0],
                    l2: p[1],
                    l3: p[2],
                    l4: p[3],
                    l5: p[4],
                    l6: p[5],
                    l2e: p[6],
                    xg: p[7],
                    yg: p[8],
                    ..Default::default()
                };
                boxed(sixbar::Sixbar { params }, &params.to_array())
            }
        };
        let mut g = loaded(self.name());
        for (name, value) in self.params() {
            g.set_param(name, value).expect("a base param of the file");
        }
        (generated, g, params)
    }

    /// Unknowns in closed form at input `x` on the `left` branch, with the smallest |sine| of the
    /// angle between the two links of a dyad (1 = well conditioned, 0 = dead point).
    fn closed(&self, left: bool, x: f64) -> Option<(Vec<f64>, f64)> {
        match *self {
            Mech::FourBar { l, .. } => {
                let (q2, q3, s) = four_bar_loop(l, left, x)?;
                Some((vec![q2, q3], s))
            }
            Mech::SliderCrank { r, l, off } => {
                // r sin q1 + l sin q2 = off; sC = r cos q1 + l cos q2.
                let s = (off - r * x.sin()) / l;
                if !(s.abs() < 1.0) {
                    return None;
                }
                let q2 = if left { PI - s.asin() } else { s.asin() };
                let sc = r * x.cos() + l * q2.cos();
                Some((vec![q2, sc], q2.cos().abs()))
            }
            Mech::Sixbar { p } => {
                // Always the seed's branches.
                let (left4, left_dyad) = sixbar_branches();
                let (q2, q3, s1) = four_bar_loop([p[0], p[1], p[2], p[3]], left4, x)?;
                let alpha = sixbar::Params::<f64>::default().alpha;
                // E = C + l2e e(q2 − α), C = D + l3 e(q3); then the dyad G-F-E.
                let e = [
                    p[3] + p[2] * q3.cos() + p[6] * (q2 - alpha).cos(),
                    p[2] * q3.sin() + p[6] * (q2 - alpha).sin(),
                ];
                let g = [p[7], p[8]];
                let f = circles(g, p[5], e, p[4], left_dyad)?;
                let q6 = (f[1] - g[1]).atan2(f[0] - g[0]);
                let q5 = (e[1] - f[1]).atan2(e[0] - f[0]);
                Some((vec![q2, q3, q5, q6], s1.min((q5 - q6).sin().abs())))
            }
        }
    }
}

/// The four-bar loop l1 e(q1) + l2 e(q2) = l4 + l3 e(q3): C is where the circle about B (radius
/// l2) meets the one about D (radius l3), left or right of B→D.
fn four_bar_loop(l: [f64; 4], left: bool, q1: f64) -> Option<(f64, f64, f64)> {
    let b = [l[0] * q1.cos(), l[0] * q1.sin()];
    let d = [l[3], 0.0];
    let c = circles(b, l[1], d, l[2], left)?;
    let q2 = (c[1] - b[1]).atan2(c[0] - b[0]);
    let q3 = (c[1] - d[1]).atan2(c[0] - d[0]);
    Some((q2, q3, (q3 - q2).sin().abs()))
}

/// Where the circle about `p` (radius `rp`) meets the circle about `q` (radius `rq`): the
/// intersection left of p→q, or right of it.
fn circles(p: [f64; 2], rp: f64, q: [f64; 2], rq: f64, left: bool) -> Option<[f64; 2]> {
    let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
    let d = dx.hypot(dy);
    if !(d > 0.0) {
        return None;
    }
    let a = (rp * rp - rq * rq + d * d) / (2.0 * d);
    let h2 = rp * rp - a * a;
    if !(h2 > 0.0) {
        return None;
    }
    let h = if left { h2.sqrt() } else { -h2.sqrt() };
    let (ux, uy) = (dx / d, dy / d);
    Some([p[0] + a * ux - h * uy, p[1] + a * uy + h * ux])
}

/// The seed six-bar's branches (four-bar loop, dyad): the closed forms nearest the file's
/// `start` at the default params.
fn sixbar_branches() -> (bool, bool) {
    static BRANCHES: OnceLock<(bool, bool)> = OnceLock::new();
    *BRANCHES.get_or_init(|| {
        let d = sixbar::Params::<f64>::default();
        let l = [d.l1, d.l2, d.l3, d.l4];
        let x = sixbar::INFO.inputs[0].start;
        let start: Vec<f64> = sixbar::INFO.unknowns.iter().map(|u| u.start).collect();
        let mut best = (f64::INFINITY, (true, true));
        for left4 in [true, false] {
            let Some((q2, q3, _)) = four_bar_loop(l, left4, x) else {
                continue;
            };
            for left_dyad in [true, false] {
                let e = [
                    d.l4 + d.l3 * q3.cos() + d.l2e * (q2 - d.alpha).cos(),
                    d.l3 * q3.sin() + d.l2e * (q2 - d.alpha).sin(),
                ];
                let Some(f) = circles([d.xg, d.yg], d.l6, e, d.l5, left_dyad) else {
                    continue;
                };
                let q6 = (f[1] - d.yg).atan2(f[0] - d.xg);
                let q5 = (e[1] - f[1]).atan2(e[0] - f[0]);
                let off = [q2, q3, q5, q6]
                    .iter()
                    .zip(&start)
                    .map(|(a, b)| angle_diff(*a, *b).abs())
                    .fold(0.0, f64::max);
                if off < best.0 {
                    best = (off, (left4, left_dyad));
                }
            }
        }
        assert!(best.0 < 0.01, "the six-bar start is {} rad off", best.0);
        best.1
    })
}

/// The compiled-in file, loaded once by the generic engine; a fresh copy of one mechanism.
fn loaded(name: &str) -> Generic {
    static ALL: OnceLock<Vec<Generic>> = OnceLock::new();
    ALL.get_or_init(|| {
        generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
            .expect("the compiled-in file loads")
    })
    .iter()
    .find(|g| g.name() == name)
    .unwrap_or_else(|| panic!("`{name}` is in the compiled-in file"))
    .clone()
}

/// Log-uniform in [0.1, 10].
fn length() -> impl Strategy<Value = f64> {
    (-1.0f64..1.0).prop_map(|e| 10f64.powf(e))
}

fn rest() -> impl Strategy<Value = (bool, [f64; 4], f64, f64)> {
    let rate = (0.1f64..10.0, any::<bool>()).prop_map(|(v, neg)| if neg { -v } else { v });
    (
        any::<bool>(),
        [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0],
        rate,
        -10.0f64..10.0,
    )
}

/// Conditioning every valid case keeps (smallest |sine| between the links of a dyad).
const CONDITIONING: f64 = 0.1;

fn spec(mech: Mech, x: f64, rest: (bool, [f64; 4], f64, f64)) -> Spec {
    let (left, perturb, xd, xdd) = rest;
    Spec {
        mech,
        x,
        left,
        perturb,
        xd,
        xdd,
    }
}

fn assembles(s: &Spec) -> bool {
    s.mech
        .closed(s.left, s.x)
        .is_some_and(|(_, c)| c >= CONDITIONING)
}

/// Grashof crank-rockers: the shortest link is the crank, s + l ≤ p + q with a margin, so every
/// crank angle assembles.
fn crank_rocker() -> impl Strategy<Value = Spec> {
    (
        [length(), length(), length(), length()],
        0usize..6,
        length(),
    )
        .prop_filter_map("not a crank-rocker with margin", |(mut l, perm, lp)| {
            l.sort_by(f64::total_cmp);
            let others = [
                [1, 2, 3],
                [1, 3, 2],
                [2, 1, 3],
                [2, 3, 1],
                [3, 1, 2],
                [3, 2, 1],
            ][perm];
            let (l1, l2, l3, l4) = (l[0], l[others[0]], l[others[1]], l[others[2]]);
            let margin = 0.05 * l[3];
            // The crank turns fully: |BD| stays in [|l2 − l3|, l2 + l3] with a margin.
            let turns = l4 + l1 <= l2 + l3 - margin && (l4 - l1).abs() >= (l2 - l3).abs() + margin;
            (turns && l[3] / l[0] <= 20.0).then_some(Mech::FourBar {
                l: [l1, l2, l3, l4],
                lp,
            })
        })
        .prop_flat_map(|m| (Just(m), -PI..PI, rest()))
        .prop_map(|(m, x, r)| spec(m, x, r))
        .prop_filter("badly conditioned", assembles)
}

/// Any four-bar (Grashof or not) at an input inside its range.
fn any_four_bar() -> impl Strategy<Value = Spec> {
    (
        [length(), length(), length(), length()],
        length(),
        -PI..PI,
        rest(),
    )
        .prop_filter("link ratio above 20", |(l, ..)| {
            let max = l.iter().copied().fold(0.0, f64::max);
            let min = l.iter().copied().fold(f64::INFINITY, f64::min);
            max / min <= 20.0
        })
        .prop_map(|(l, lp, x, r)| spec(Mech::FourBar { l, lp }, x, r))
        .prop_filter("cannot be assembled there", assembles)
}

fn four_bars() -> impl Strategy<Value = Spec> {
    prop_oneof![crank_rocker(), any_four_bar()]
}

/// Offset slider-cranks with r + |off| ≤ 0.9 l: the crank turns fully.
fn slider_cranks() -> impl Strategy<Value = Spec> {
    (length(), 0.05f64..0.85, -1.0f64..1.0, -PI..PI, rest())
        .prop_map(|(l, a, b, x, r)| {
            let r_ = a * l;
            let off = b * (0.9 * l - r_);
            spec(Mech::SliderCrank { r: r_, l, off }, x, r)
        })
        .prop_filter("badly conditioned", assembles)
}

/// The seed six-bar's lengths and ground pivot, each perturbed by up to 3 %, at a random crank
/// angle, on the seed's branch (`left` is true: the branch flag is only used by four-bars and
/// slider-cranks).
fn sixbars() -> impl Strategy<Value = Spec> {
    (proptest::collection::vec(-1.0f64..1.0, 9), -PI..PI, rest())
        .prop_map(|(u, x, r)| {
            let d = sixbar::Params::<f64>::default();
            let seed = [d.l1, d.l2, d.l3, d.l4, d.l5, d.l6, d.l2e, d.xg, d.yg];
            let mut p = [0.0; 9];
            for i in 0..9 {
                p[i] = seed[i] * (1.0 + 0.03 * u[i]);
            }
            Spec {
                left: true,
                ..spec(Mech::Sixbar { p }, x, r)
            }
        })
        .prop_filter("cannot be assembled there", assembles)
}

// ---------------------------------------------------------------------------------------------
// Comparisons

/// Largest differences seen over a property's cases.
#[derive(Clone, Copy, Debug, Default)]
struct Worst {
    /// Solved positions against the closed form.
    closed: f64,
    /// Generated against generic: positions, rates, points.
    engines: f64,
    /// Relative residual of Ok answers.
    residual: f64,
    /// Velocities (unknowns and points) against finite differences of positions.
    velocity_fd: f64,
    /// Accelerations (unknowns and points) against finite differences of velocities.
    acceleration_fd: f64,
}

impl Worst {
    fn max(self, o: Worst) -> Worst {
        Worst {
            closed: self.closed.max(o.closed),
            engines: self.engines.max(o.engines),
            residual: self.residual.max(o.residual),
            velocity_fd: self.velocity_fd.max(o.velocity_fd),
            acceleration_fd: self.acceleration_fd.max(o.acceleration_fd),
        }
    }
}

/// Coordinates per unit: 1 for angles, the length scale for lengths.
fn units(kinds: &[Kind], scale: f64) -> Vec<f64> {
    kinds
        .iter()
        .map(|k| if *k == Kind::Angle { 1.0 } else { scale })
        .collect()
}

/// Largest difference of two configurations in units (angles folded).
fn position_diff(kinds: &[Kind], units: &[f64], a: &[f64], b: &[f64]) -> f64 {
    let mut worst: f64 = 0.0;
    for i in 0..a.len() {
        let d = if kinds[i] == Kind::Angle {
            angle_diff(a[i], b[i])
        } else {
            a[i] - b[i]
        };
        worst = worst.max(d.abs() / units[i]);
    }
    worst
}

/// Largest difference of two rate vectors in units, relative to the largest entry of `b` (or
/// `floor`, whichever is larger). NaN anywhere gives infinity.
fn relative(units: &[f64], a: &[f64], b: &[f64], floor: f64) -> f64 {
    let big = b
        .iter()
        .zip(units)
        .map(|(v, u)| v.abs() / u)
        .fold(floor, f64::max);
    let mut worst: f64 = 0.0;
    for i in 0..a.len() {
        let d = (a[i] - b[i]).abs() / units[i];
        if !d.is_finite() {
            return f64::INFINITY;
        }
        worst = worst.max(d / big);
    }
    worst
}

fn finite(v: &[f64]) -> bool {
    v.iter().all(|v| v.is_finite())
}

/// Positions, velocities, accelerations of all points, flattened per quantity.
fn point_parts(p: &[PointMotion<f64>]) -> [Vec<f64>; 3] {
    [
        p.iter().flat_map(|m| m.position).collect(),
        p.iter().flat_map(|m| m.velocity).collect(),
        p.iter().flat_map(|m| m.acceleration).collect(),
    ]
}

/// What one engine gives at a case.
struct Answer {
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    points: Vec<PointMotion<f64>>,
}

fn solve(
    k: &dyn DynMechanism<f64>,
    what: &str,
    s: &Spec,
    guess: &[f64],
    scale: f64,
    worst: &mut Worst,
) -> Result<Answer, TestCaseError> {
    let nu = guess.len();
    let options = SolveOptions::default();
    let x = [s.x];
    let mut q = guess.to_vec();
    let report = k.solve_position(&x, &mut q, &options);
    prop_assert!(report.is_ok(), "{what}: position solve: {report:?}");
    prop_assert!(finite(&q), "{what}: position {q:?}");
    let mut phi = vec![0.0; nu];
    k.residual(&x, &q, &mut phi).expect("lengths fit");
    let residual = phi.iter().fold(0.0f64, |m, v| m.max(v.abs())) / scale;
    worst.residual = worst.residual.max(residual);
    prop_assert!(
        residual <= options.newton.tolerance,
        "{what}: relative residual {residual:e} of an Ok answer"
    );
    let mut qd = vec![0.0; nu];
    let v = k.solve_velocity(&x, &q, &[s.xd], &mut qd);
    prop_assert!(v.is_ok() && finite(&qd), "{what}: velocity {v:?} {qd:?}");
    let mut qdd = vec![0.0; nu];
    let a = k.solve_acceleration(&x, &q, &[s.xd], &qd, &[s.xdd], &mut qdd);
    prop_assert!(
        a.is_ok() && finite(&qdd),
        "{what}: acceleration {a:?} {qdd:?}"
    );
    let mut points = vec![PointMotion::default(); k.info().points.len()];
    k.points(
        InputMotion::new(&x, &[s.xd], &[s.xdd]),
        &q,
        &qd,
        &qdd,
        &mut points,
    )
    .expect("lengths fit");
    for part in point_parts(&points) {
        prop_assert!(finite(&part), "{what}: points {points:?}");
    }
    Ok(Answer { q, qd, qdd, points })
}

/// Checks (a) to (c) on one valid case.
fn check_valid(s: &Spec) -> Result<Worst, TestCaseError> {
    let (generated, generic, params) = s.mech.engines();
    let info = generated.info();
    prop_assert_eq!(&info.name, s.mech.name());
    prop_assert_eq!(&info.name, generic.name());
    // Bit for bit (NaN-safe): the same params on both engines.
    let bits = |p: &[f64]| p.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    prop_assert_eq!(bits(&params), bits(generic.params()), "same params set");
    let kinds: Vec<Kind> = info.unknowns.iter().map(|u| u.kind).collect();
    let scale = generic.length_scale();
    let units = units(&kinds, scale);
    let nu = kinds.len();
    let closed = |x: f64| s.mech.closed(s.left, x).map(|(q, _)| q);
    let q0 = closed(s.x).expect("the strategy keeps assembled cases");
    let guess: Vec<f64> = (0..nu)
        .map(|i| q0[i] + 1e-3 * s.perturb[i] * units[i])
        .collect();
    let mut w = Worst::default();

    // (a), (c)
    let a = solve(generated.as_ref(), "generated", s, &guess, scale, &mut w)?;
    let b = solve(&generic, "generic", s, &guess, scale, &mut w)?;
    w.closed =
        position_diff(&kinds, &units, &a.q, &q0).max(position_diff(&kinds, &units, &b.q, &q0));
    prop_assert!(w.closed <= SAME, "off the closed form by {:e}", w.closed);

    // (b) generated = generic
    let xd2 = s.xd * s.xd + s.xdd.abs();
    let pa = point_parts(&a.points);
    let pb = point_parts(&b.points);
    let point_units = vec![scale; pa[0].len()];
    w.engines = [
        position_diff(&kinds, &units, &a.q, &b.q),
        relative(&units, &a.qd, &b.qd, 0.0),
        relative(&units, &a.qdd, &b.qdd, 1e-3 * xd2),
        relative(&point_units, &pa[0], &pb[0], 0.0),
        relative(&point_units, &pa[1], &pb[1], 0.0),
        relative(&point_units, &pa[2], &pb[2], 1e-3 * xd2),
    ]
    .into_iter()
    .fold(0.0, f64::max);
    prop_assert!(
        w.engines <= SAME,
        "generated and generic differ by {:e}",
        w.engines
    );

    // (b) finite differences along the motion x(t) = x + ẋ t + ẍ t²/2, positions in closed form,
    // velocities from the generated solver at those positions: central differences at steps h
    // and h/2 (input steps of 2e-5 and 1e-5 rad), Richardson-extrapolated (error O(h⁴)).
    let h = 2e-5 / s.xd.abs();
    let motion = |t: f64| (s.x + s.xd * t + 0.5 * s.xdd * t * t, s.xd + s.xdd * t);
    // Unknowns, their velocities, point positions and velocities at time t.
    let state = |t: f64| -> Result<[Vec<f64>; 4], TestCaseError> {
        let (x, xd) = motion(t);
        let q = closed(x).ok_or_else(|| TestCaseError::fail("closed form lost"))?;
        let mut qd = vec![0.0; nu];
        generated
            .solve_velocity(&[x], &q, &[xd], &mut qd)
            .map_err(|e| TestCaseError::fail(format!("velocity at t = {t}: {e}")))?;
        let mut p = vec![PointMotion::default(); a.points.len()];
        let zero = vec![0.0; nu];
        generated
            .points(
                InputMotion::new(&[x], &[xd], &[0.0]),
                &q,
                &qd,
                &zero,
                &mut p,
            )
            .expect("lengths fit");
        let [pos, vel, _] = point_parts(&p);
        Ok([q, qd, pos, vel])
    };
    // Central differences of the four quantities at step `h`.
    let central = |h: f64| -> Result<[Vec<f64>; 4], TestCaseError> {
        let (plus, minus) = (state(h)?, state(-h)?);
        Ok(std::array::from_fn(|j| {
            (0..plus[j].len())
                .map(|i| {
                    let d = if j == 0 && kinds[i] == Kind::Angle {
                        angle_diff(plus[j][i], minus[j][i])
                    } else {
                        plus[j][i] - minus[j][i]
                    };
                    d / (2.0 * h)
                })
                .collect()
        }))
    };
    let (coarse, fine) = (central(h)?, central(h / 2.0)?);
    let fd: [Vec<f64>; 4] = std::array::from_fn(|j| {
        fine[j]
            .iter()
            .zip(&coarse[j])
            .map(|(f, c)| (4.0 * f - c) / 3.0)
            .collect()
    });
    let velocity_fd = [
        relative(&units, &fd[0], &a.qd, 0.0),
        relative(&point_units, &fd[2], &pa[1], 0.0),
    ];
    let acceleration_fd = [
        relative(&units, &fd[1], &a.qdd, 1e-3 * xd2),
        relative(&point_units, &fd[3], &pa[2], 1e-3 * xd2),
    ];
    w.velocity_fd = velocity_fd.into_iter().fold(0.0, f64::max);
    w.acceleration_fd = acceleration_fd.into_iter().fold(0.0, f64::max);
    prop_assert!(
        w.velocity_fd <= FD,
        "velocities against finite differences: {velocity_fd:?}"
    );
    prop_assert!(
        w.acceleration_fd <= FD,
        "accelerations against finite differences: {acceleration_fd:?}"
    );
    Ok(w)
}

fn run_valid(name: &str, strategy: impl Strategy<Value = Spec>) {
    let worst = Cell::new(Worst::default());
    let cases = Cell::new(0u32);
    let mut runner = TestRunner::new(config(CASES));
    let result = runner.run(&strategy, |s| {
        let w = check_valid(&s)?;
        worst.set(worst.get().max(w));
        cases.set(cases.get() + 1);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{name}: {e}");
    }
    eprintln!("{name}: {} cases, largest: {:?}", cases.get(), worst.get());
}

#[test]
fn random_four_bars() {
    run_valid("four_bar", four_bars());
}

#[test]
fn random_slider_cranks() {
    run_valid("slider_crank", slider_cranks());
}

#[test]
fn random_sixbars() {
    run_valid("sixbar", sixbars());
}

// ---------------------------------------------------------------------------------------------
// (d) Arbitrary arguments

/// Mostly ordinary values, often NaN, ±∞, zero, huge and tiny ones, and any bit pattern.
fn weird() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -10.0f64..10.0,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(0.0),
        1 => prop::sample::select(vec![1e308, -1e308, f64::MAX, 1e-308, 5e-324, 1e154, -1e200]),
        1 => any::<f64>(),
    ]
}

/// A valid case, with some params, the input, some guesses, the rate and the acceleration
/// replaced by arbitrary values.
#[derive(Clone, Debug)]
struct Garbage {
    base: Spec,
    params: Vec<Option<f64>>,
    x: Option<f64>,
    guess: [Option<f64>; 4],
    xd: Option<f64>,
    xdd: Option<f64>,
}

fn garbage() -> impl Strategy<Value = Garbage> {
    let some = |p: f64| proptest::option::weighted(p, weird());
    (
        prop_oneof![four_bars(), slider_cranks(), sixbars()],
        proptest::collection::vec(some(0.2), 9),
        some(0.5),
        [some(0.3), some(0.3), some(0.3), some(0.3)],
        some(0.5),
        some(0.5),
    )
        .prop_map(|(base, params, x, guess, xd, xdd)| Garbage {
            base,
            params,
            x,
            guess,
            xd,
            xdd,
        })
}

fn with_params(mech: Mech, over: &[Option<f64>]) -> Mech {
    let pick = |i: usize, v: f64| over[i].unwrap_or(v);
    match mech {
        Mech::FourBar { l, lp } => Mech::FourBar {
            l: [pick(0, l[0]), pick(1, l[1]), pick(2, l[2]), pick(3, l[3])],
            lp: pick(4, lp),
        },
        Mech::SliderCrank { r, l, off } => Mech::SliderCrank {
            r: pick(0, r),
            l: pick(1, l),
            off: pick(2, off),
        },
        Mech::Sixbar { p } => Mech::Sixbar {
            p: std::array::from_fn(|i| pick(i, p[i])),
        },
    }
}

fn first_non_finite(quantity: Quantity, v: &[f64]) -> Option<SolveError> {
    v.iter()
        .position(|v| !v.is_finite())
        .map(|index| SolveError::NonFinite { quantity, index })
}

/// (d) on one case; returns how many engine calls gave Ok.
fn check_garbage(c: &Garbage) -> Result<u32, TestCaseError> {
    let mech = with_params(c.base.mech, &c.params);
    let (generated, generic, params) = mech.engines();
    let bits = |p: &[f64]| p.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    prop_assert_eq!(bits(&params), bits(generic.params()), "same params set");
    let scale = generic.length_scale();
    let q0 = c
        .base
        .mech
        .closed(c.base.left, c.base.x)
        .expect("the strategy keeps assembled cases")
        .0;
    let nu = q0.len();
    let x = [c.x.unwrap_or(c.base.x)];
    let guess: Vec<f64> = (0..nu).map(|i| c.guess[i].unwrap_or(q0[i])).collect();
    let xd = [c.xd.unwrap_or(c.base.xd)];
    let xdd = [c.xdd.unwrap_or(c.base.xdd)];
    let expected = first_non_finite(Quantity::Param, &params)
        .or_else(|| first_non_finite(Quantity::Input, &x))
        .or_else(|| first_non_finite(Quantity::Guess, &guess));
    let mut oks = 0;
    for (what, k) in [
        ("generated", generated.as_ref()),
        ("generic", &generic as &dyn DynMechanism<f64>),
    ] {
        let options = SolveOptions::default();
        let mut q = guess.clone();
        let r = k.solve_position(&x, &mut q, &options);
        if let Some(e) = expected {
            prop_assert_eq!(r, Err(e), "{}: position solve", what);
        }
        if r.is_ok() {
            oks += 1;
            prop_assert!(finite(&q), "{what}: Ok position {q:?}");
            let mut phi = vec![0.0; nu];
            k.residual(&x, &q, &mut phi).expect("lengths fit");
            let residual = phi.iter().fold(0.0f64, |m, v| m.max(v.abs())) / scale;
            prop_assert!(
                residual <= options.newton.tolerance,
                "{what}: relative residual {residual:e} of an Ok answer {q:?}"
            );
        }
        // Rates at the solved position, or at the guess when it did not solve.
        let mut qd = vec![0.0; nu];
        let v = k.solve_velocity(&x, &q, &xd, &mut qd);
        let bad_position = first_non_finite(Quantity::Param, &params)
            .or_else(|| first_non_finite(Quantity::Input, &x))
            .or_else(|| first_non_finite(Quantity::Position, &q));
        if let Some(e) = bad_position.or_else(|| first_non_finite(Quantity::InputRate, &xd)) {
            prop_assert_eq!(v, Err(e), "{}: velocity solve", what);
        }
        if v.is_ok() {
            oks += 1;
            prop_assert!(finite(&qd), "{what}: Ok velocity {qd:?}");
        }
        let mut qdd = vec![0.0; nu];
        let a = k.solve_acceleration(&x, &q, &xd, &qd, &xdd, &mut qdd);
        let expected = bad_position
            .or_else(|| first_non_finite(Quantity::InputRate, &xd))
            .or_else(|| first_non_finite(Quantity::Rate, &qd))
            .or_else(|| first_non_finite(Quantity::InputAcceleration, &xdd));
        if let Some(e) = expected {
            prop_assert_eq!(a, Err(e), "{}: acceleration solve", what);
        }
        if a.is_ok() {
            oks += 1;
            prop_assert!(finite(&qdd), "{what}: Ok acceleration {qdd:?}");
        }
    }
    Ok(oks)
}

#[test]
fn arbitrary_arguments_never_panic_nor_give_nan() {
    let cases = Cell::new(0u32);
    let oks = Cell::new(0u32);
    let mut runner = TestRunner::new(config(4 * CASES));
    let result = runner.run(&garbage(), |c| {
        oks.set(oks.get() + check_garbage(&c)?);
        cases.set(cases.get() + 1);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    eprintln!(
        "arbitrary arguments: {} cases, {} of {} solves Ok",
        cases.get(),
        oks.get(),
        6 * cases.get()
    );
}

/// Found by `arbitrary_arguments_never_panic_nor_give_nan`: a huge param drove q2 to infinity,
/// then `max` dropped the NaN residual and the NaN step, and the position solve returned Ok with
/// [inf, NaN]. The residual overflows: both engines say `Overflow` (issue 18: rows say
/// `overflow`, not a dead point).
#[test]
fn huge_param_is_an_error_not_a_nan_answer() {
    let (r, l) = (3.9895132866117264, 7.942689481113269);
    let (x, off) = (2.3840871071930807, 1e308);
    let guess = Mech::SliderCrank {
        r,
        l,
        off: 0.5344127012728701,
    }
    .closed(false, x)
    .expect("assembles with a small offset")
    .0;
    let (generated, generic, _) = Mech::SliderCrank { r, l, off }.engines();
    for k in [generated.as_ref(), &generic as &dyn DynMechanism<f64>] {
        let mut q = guess.clone();
        let result = k.solve_position(&[x], &mut q, &SolveOptions::default());
        assert!(
            matches!(result, Err(SolveError::Overflow { .. })),
            "{result:?} {q:?}"
        );
    }
}
