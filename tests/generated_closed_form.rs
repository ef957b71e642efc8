//! The generated solvers on closed-form blocks (issue 11), against the generic engine and
//! independent closed forms:
//!
//! * random inverted slider-cranks, as the shaper's first loop re-parametrised through its
//!   `Params` (an RPR block through the pivot, then one angle and one length): generated = generic
//!   = closed form (atan2, asin) ≤ 1e-12 on both assembly modes, no Newton iteration, velocities =
//!   central differences;
//! * ticks of the shaper and the slider-crank take no iteration (`closed_forms: false`: Newton);
//! * the slider-crank's rod perpendicular to the slide (one angle): positions within a few ε/√δ,
//!   rates within a few ε/δ, `Unassemblable` with no iteration just past, guess left alone;
//! * the shaper's slot through the crank pivot (RPR, `h = 0`): positions within a few ε/δ of the
//!   half-angle closed form, `Singular` at the pivot itself.
#![cfg(feature = "runtime")]

mod common;

use std::cell::Cell;
use std::f64::consts::{FRAC_PI_2, PI};

use common::angle_diff;
use mechgen::generic::{self, Generic};
use mechgen::{
    DynMechanism, InputMotion, SolveError, SolveOptions, StaticMechanism, shaper, slider_crank,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestRunner};

const CASES: u32 = 256;
const SAME: f64 = 1e-12;
const FD: f64 = 1e-6;
/// Errors near dead points in units of ε/√δ (positions) or ε/δ (rates, slot positions).
const BOUND: f64 = 16.0;

fn default_engine(name: &str) -> Generic {
    generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
        .expect("the default file loads")
        .into_iter()
        .find(|g| g.name() == name)
        .expect("in the default file")
}

/// The shaper as an inverted slider-crank `s3 e(q3) = l1 e(q1) + (0, lAC)` followed by a ram
/// link that stays well conditioned: `l3 sin q3 + l4 sin q4 = 0` with `l4 = 4 l3`.
#[derive(Clone, Copy, Debug)]
struct Inverted {
    l1: f64,
    lac: f64,
    l3: f64,
}

impl Inverted {
    fn params(&self) -> shaper::Params<f64> {
        shaper::Params {
            l1: self.l1,
            l3: self.l3,
            l4: 4.0 * self.l3,
            lAC: self.lac,
            yE: 0.0,
        }
    }

    fn named(&self) -> [(&'static str, f64); 5] {
        let p = self.params();
        [
            ("l1", p.l1),
            ("l3", p.l3),
            ("l4", p.l4),
            ("lAC", p.lAC),
            ("yE", p.yE),
        ]
    }

    /// [s3, q3, q4, sE] at `x` on the slot's mode `plus` (s3 > 0) and the ram's mode with
    /// cos q4 < 0 (as the file's start), and the conditioning |B| / length scale.
    fn closed(&self, plus: bool, x: f64) -> (Vec<f64>, f64) {
        let (bx, by) = (self.l1 * x.cos(), self.lac + self.l1 * x.sin());
        let rho = bx.hypot(by);
        let (s3, q3) = if plus {
            (rho, by.atan2(bx))
        } else {
            (-rho, (-by).atan2(-bx))
        };
        let l4 = 4.0 * self.l3;
        let q4 = PI - (-self.l3 * q3.sin() / l4).asin();
        let se = self.l3 * q3.cos() + l4 * q4.cos();
        (vec![s3, q3, q4, se], rho / self.scale())
    }

    fn scale(&self) -> f64 {
        self.l1.max(self.lac).max(4.0 * self.l3)
    }
}

const ANGLE: [bool; 4] = [false, true, true, false];

fn length() -> impl Strategy<Value = f64> {
    (-1.0f64..1.0).prop_map(|e| 10f64.powf(e))
}

fn check(g: &mut Generic, case: &(Inverted, f64, bool, [f64; 4])) -> Result<f64, TestCaseError> {
    let (m, x, plus, perturb) = *case;
    for (name, value) in m.named() {
        g.set_param(name, value).expect("a param of the shaper");
    }
    let generated = shaper::Shaper { params: m.params() };
    let scale = m.scale();
    let (want, _) = m.closed(plus, x);
    let guess: Vec<f64> = (0..4)
        .map(|i| want[i] + 1e-3 * perturb[i] * if ANGLE[i] { 1.0 } else { scale })
        .collect();
    let options = SolveOptions::default();
    let mut worst: f64 = 0.0;
    let mut answers = Vec::new();
    for engine in [&generated as &dyn DynMechanism<f64>, &*g] {
        let mut q = guess.clone();
        let report = engine
            .solve_position(&[x], &mut q, &options)
            .map_err(|e| TestCaseError::fail(format!("{e}")))?;
        prop_assert_eq!(report.iterations, 0, "closed forms take no iteration");
        for i in 0..4 {
            let d = if ANGLE[i] {
                angle_diff(q[i], want[i])
            } else {
                (q[i] - want[i]) / scale
            };
            prop_assert!(d.abs() <= SAME, "{case:?}: {q:?} vs {want:?}");
            worst = worst.max(d.abs());
        }
        answers.push(q);
    }
    for i in 0..4 {
        let d = (answers[0][i] - answers[1][i]) / if ANGLE[i] { 1.0 } else { scale };
        prop_assert!(d.abs() <= SAME, "{case:?}: generated {answers:?}");
    }
    // Velocities of the generated solver against central differences of the closed form.
    let h = 1e-6;
    let (a, b) = (m.closed(plus, x + h).0, m.closed(plus, x - h).0);
    let mut qd = vec![0.0; 4];
    DynMechanism::solve_velocity(&generated, &[x], &answers[0], &[1.0], &mut qd)
        .map_err(|e| TestCaseError::fail(format!("{e}")))?;
    for i in 0..4 {
        let diff = if ANGLE[i] {
            angle_diff(a[i], b[i])
        } else {
            a[i] - b[i]
        };
        let fd = diff / (2.0 * h);
        let unit = if ANGLE[i] { 1.0 } else { scale };
        prop_assert!(
            (qd[i] - fd).abs() <= FD * (qd[i].abs() + unit),
            "{case:?}: velocity {i}: {} vs {fd}",
            qd[i]
        );
    }
    Ok(worst)
}

#[test]
fn random_inverted_slider_cranks_generated_equals_generic_and_closed_form() {
    let mut config = Config {
        failure_persistence: None,
        max_global_rejects: 100_000,
        max_local_rejects: 100_000,
        ..Config::default()
    };
    if std::env::var_os("PROPTEST_CASES").is_none() {
        config.cases = CASES;
    }
    if config.rng_seed == RngSeed::Random {
        config.rng_seed = RngSeed::Fixed(0x6765_6e63_6c6f);
    }
    let wanted = config.cases;
    let g = std::cell::RefCell::new(default_engine("shaper"));
    let (worst, count) = (Cell::new(0.0f64), Cell::new(0u32));
    let strategy = (
        length(),
        length(),
        length(),
        -PI..PI,
        any::<bool>(),
        [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0],
    )
        .prop_map(|(l1, lac, l3, x, plus, p)| (Inverted { l1, lac, l3 }, x, plus, p))
        .prop_filter("the slot stays away from the pivot", |(m, x, plus, _)| {
            m.closed(*plus, *x).1 >= 0.1
        });
    TestRunner::new(config)
        .run(&strategy, |case| {
            worst.set(worst.get().max(check(&mut g.borrow_mut(), &case)?));
            count.set(count.get() + 1);
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{e}"));
    eprintln!(
        "inverted slider-cranks: {} cases, largest difference {:e}",
        count.get(),
        worst.get()
    );
    assert_eq!(count.get(), wanted);
}

#[test]
fn ticks_of_closed_form_mechanisms_take_no_iteration() {
    let newton = SolveOptions {
        closed_forms: false,
        ..SolveOptions::default()
    };
    let (xd, xdd) = ([1.0], [0.0]);
    let step = PI / 180.0;
    macro_rules! run {
        ($m:expr, $guess:expr) => {{
            let m = $m;
            for (options, closed) in [(SolveOptions::default(), true), (newton, false)] {
                let start = InputMotion::new([0.0], xd, xdd);
                let mut t =
                    StaticMechanism::tick_start(&m, &start, &$guess, &options).expect("start");
                let mut iterations = 0;
                for k in 1..=720 {
                    let x = [k as f64 * step];
                    StaticMechanism::tick(&m, &mut t, &InputMotion::new(x, xd, xdd), &options)
                        .expect("tick");
                    iterations += t.report.iterations;
                    let mut fresh = t.q;
                    m.solve_position(&x, &mut fresh, &SolveOptions::default())
                        .expect("solve");
                    for (a, b) in t.q.iter().zip(&fresh) {
                        assert!((a - b).abs() <= 1e-12, "tick {k}: {:?} vs {fresh:?}", t.q);
                    }
                }
                assert_eq!(
                    iterations == 0,
                    closed,
                    "closed forms: {closed}: {iterations}"
                );
            }
        }};
    }
    run!(shaper::Shaper::<f64>::default(), [0.302, 1.13, 2.95, 0.1]);
    run!(slider_crank::SliderCrank::<f64>::default(), [0.1, 0.25]);
}

/// The default slider-crank at r = 0.3, l = 0.2, off = 0.05 (the generic stress case): the rod is
/// perpendicular to the slide at r sin x = off + l.
fn slider(x: f64) -> (Vec<f64>, Vec<f64>, f64) {
    let (r, l, off) = (0.3, 0.2, 0.05);
    let sin2 = (off - r * x.sin()) / l;
    let q2 = sin2.asin();
    let s = r * x.cos() + l * q2.cos();
    let q2d = -r * x.cos() / (l * q2.cos());
    let sd = -r * x.sin() - l * q2.sin() * q2d;
    (vec![q2, s], vec![q2d, sd], 1.0 - sin2.abs())
}

#[test]
fn generated_slider_crank_near_and_past_its_dead_point() {
    let typed = slider_crank::SliderCrank {
        params: slider_crank::Params {
            r: 0.3,
            l: 0.2,
            off: 0.05,
        },
    };
    let m: &dyn DynMechanism<f64> = &typed;
    let dead = (0.25f64 / 0.3).asin();
    let options = SolveOptions::default();
    let mut q = slider(dead - 0.3).0;
    let (mut worst_q, mut worst_qd): (f64, f64) = (0.0, 0.0);
    for k in 2..=10 {
        let x = dead - 10f64.powi(-k);
        let report = m.solve_position(&[x], &mut q, &options).expect("inside");
        assert_eq!(report.iterations, 0);
        let (want, rates, delta) = slider(x);
        let mut qd = vec![0.0; 2];
        m.solve_velocity(&[x], &q, &[1.0], &mut qd)
            .expect("regular inside");
        for i in 0..2 {
            let e = (q[i] - want[i]).abs() / (f64::EPSILON / delta.sqrt());
            let ed = (qd[i] - rates[i]).abs() / (rates[i].abs().max(1.0) * f64::EPSILON / delta);
            assert!(
                e <= BOUND && ed <= BOUND,
                "1e-{k}: {i}: {e:.1} ε/√δ, {ed:.1} ε/δ"
            );
            worst_q = worst_q.max(e);
            worst_qd = worst_qd.max(ed);
        }
    }
    eprintln!("generated slider-crank: positions {worst_q:.2} ε/√δ, rates {worst_qd:.2} ε/δ");
    for past in [1e-6, 1e-3] {
        let mut trial = q.clone();
        let r = m.solve_position(&[dead + past], &mut trial, &options);
        assert!(
            matches!(r, Err(SolveError::Unassemblable { iterations: 0, .. })),
            "{past} past: {r:?}"
        );
        assert_eq!(trial, q, "the guess is left alone");
    }
}

#[test]
fn generated_shaper_slot_through_the_crank_pivot() {
    // l1 = lAC: the pin passes through the guide's pivot C at q1 = −π/2. With q1 = −π/2 + t,
    // B = 2 l1 sin(t/2) e(t/2): q3 = t/2, s3 = 2 l1 sin(t/2).
    let m = Inverted {
        l1: 1.0,
        lac: 1.0,
        l3: 0.5,
    };
    let typed = shaper::Shaper { params: m.params() };
    let generated: &dyn DynMechanism<f64> = &typed;
    let options = SolveOptions::default();
    let mut q = m.closed(true, -FRAC_PI_2 + 0.3).0;
    let mut worst: f64 = 0.0;
    for k in 2..=10 {
        let x = -FRAC_PI_2 + 10f64.powi(-k);
        // x + π/2 exactly: FRAC_PI_2 is π/2 rounded down by 6.123e-17.
        let t = (x + FRAC_PI_2) + 6.123_233_995_736_766e-17;
        let report = generated
            .solve_position(&[x], &mut q, &options)
            .expect("off the pivot");
        assert_eq!(report.iterations, 0);
        let delta = 2.0 * (t / 2.0).sin();
        let unit = f64::EPSILON / delta;
        let e = [(q[0] - delta).abs() / unit, (q[1] - t / 2.0).abs() / unit];
        assert!(e[0] <= BOUND && e[1] <= BOUND, "1e-{k}: {e:?} ε/δ");
        worst = worst.max(e[0]).max(e[1]);
    }
    eprintln!("generated shaper near its slot pivot: positions {worst:.2} ε/δ");
    // At the pivot itself the guide's direction is undefined.
    let at_typed = shaper::Shaper {
        params: Inverted {
            l1: 0.0,
            lac: 0.0,
            l3: 0.5,
        }
        .params(),
    };
    let at: &dyn DynMechanism<f64> = &at_typed;
    let mut trial = q.clone();
    let r = at.solve_position(&[0.3], &mut trial, &options);
    assert!(matches!(r, Err(SolveError::Singular { .. })), "{r:?}");
    assert_eq!(trial, q, "the guess is left alone");
}
