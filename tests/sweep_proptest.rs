//! Property tests of sweeps (issue 10, items 1 and 2): random in-line slider-cranks and oblique
//! trammels swept across s = 0 lose no row (closed forms of `common/sweep.rs`), and sweeps with
//! random ranges, steps, params and start inputs end within a bounded number of solves, give one
//! row per value, solve every value within reach and report no dead point below 1e3.
//! `PROPTEST_CASES=2000 cargo test --release --test sweep_proptest` runs them longer.
#![cfg(feature = "runtime")]

#[path = "common/sweep.rs"]
mod support;

use mechgen::generic::Generic;
use mechgen::sweep::{Continuation, DEAD_POINT_CONDITION, Row, sweep, sweep_budget};
use mechgen::{DynMechanism, Kind};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestRunner};
use support::{Counting, Exact, angle_diff, load};

fn config(cases: u32) -> Config {
    let mut c = Config {
        failure_persistence: None,
        ..Config::default()
    };
    if std::env::var_os("PROPTEST_CASES").is_none() {
        c.cases = cases;
    }
    if c.rng_seed == RngSeed::Random {
        c.rng_seed = RngSeed::Fixed(0x0073_7765_6570);
    }
    c
}

/// A random test mechanism: the in-line slider-crank (crank r, rod l = ratio·r) or the trammel
/// (bar l, guide at `phi`), all lengths times `scale`.
#[derive(Clone, Debug)]
struct Mech {
    trammel: bool,
    scale: f64,
    ratio: f64,
    phi: f64,
}

impl Mech {
    /// The generic engine with these params, and its start configuration set to the closed form
    /// at the start input (0) so that the start is on the branch the closed form describes.
    fn build(&self) -> (Generic, Vec<f64>) {
        let mut g = load(if self.trammel {
            "trammel.toml"
        } else {
            "slider_inline.toml"
        });
        let set = |g: &mut Generic, n: &str, v: f64| g.set_param(n, v).expect("param");
        if self.trammel {
            set(&mut g, "L", self.scale);
            set(&mut g, "phi", self.phi);
        } else {
            let (r, l) = (self.scale, self.scale * self.ratio);
            set(&mut g, "r", r);
            set(&mut g, "l", l);
            set(&mut g, "x0", (l * l - r * r).sqrt());
        }
        let start = self.exact(0.0).expect("the start is assembled").0;
        (g, start)
    }

    /// The closed form at input `x` (radians or file units), `None` out of reach.
    fn exact(&self, x: f64) -> Option<Exact> {
        if self.trammel {
            support::trammel(self.scale, self.phi, x)
        } else {
            let (r, l) = (self.scale, self.scale * self.ratio);
            Some(support::slider_inline(r, l, (l * l - r * r).sqrt(), x))
        }
    }

    /// Whether `x` is within reach with a margin from the dead points (|sx| = L / sin φ).
    fn in_reach(&self, x: f64, margin: f64) -> bool {
        !self.trammel || x.abs() <= margin * self.scale / self.phi.sin()
    }

    fn kind(&self) -> Kind {
        if self.trammel {
            Kind::Length
        } else {
            Kind::Angle
        }
    }
}

fn mech(scales: impl Strategy<Value = f64>) -> impl Strategy<Value = Mech> {
    (
        any::<bool>(),
        scales,
        1.2f64..5.0,
        (15f64..60.0).prop_map(f64::to_radians),
    )
        .prop_map(|(trammel, scale, ratio, phi)| Mech {
            trammel,
            scale,
            ratio,
            phi,
        })
}

/// Sweeps through a counting wrapper whose start is `start_q` (and `start_x` for the input).
fn run(m: &Mech, start_x: f64, values: &[f64], span: f64) -> (Vec<Row>, usize, Generic) {
    let (g, start_q) = m.build();
    let rows;
    let calls;
    {
        let mut k = Counting::new(&g);
        k.info.inputs[0].start = start_x;
        for (u, v) in k.info.unknowns.iter_mut().zip(start_q) {
            u.start = v;
        }
        rows = sweep(&k, 0, values, 1.0, &Continuation::for_input(m.kind(), span));
        calls = k.calls.get();
    }
    (rows, calls, g)
}

/// A solved row equals the closed form: angles modulo 2π and lengths relative to the scale to
/// 1e-11, rates relative to their size (or the scale) to 1e-8.
fn check_row(m: &Mech, g: &Generic, r: &Row) -> Result<(), TestCaseError> {
    let s = r
        .result
        .as_ref()
        .map_err(|e| TestCaseError::fail(format!("row {} lost: {e} ({:?})", r.input, r.stopped)))?;
    let (q, qd) = m.exact(r.input).expect("in reach");
    let info = DynMechanism::<f64>::info(g);
    for (i, u) in info.unknowns.iter().enumerate() {
        let (d, unit) = if u.kind == Kind::Angle {
            (angle_diff(s.q[i], q[i]), 1.0)
        } else {
            (s.q[i] - q[i], m.scale)
        };
        prop_assert!(
            d.abs() <= 1e-11 * unit,
            "{} at {}: {} vs {}",
            u.name,
            r.input,
            s.q[i],
            q[i]
        );
        let rate = (s.qd[i] - qd[i]).abs() / qd[i].abs().max(unit.min(1.0));
        prop_assert!(
            rate <= 1e-8,
            "{}_vel at {}: {} vs {}",
            u.name,
            r.input,
            s.qd[i],
            qd[i]
        );
    }
    Ok(())
}

/// Random mechanisms swept across their s = 0 (the slider at q1 = 90° or 270°, in any turn; the
/// trammel at sx = −L), with a row exactly on it: every row solved and right.
#[test]
fn sweeps_across_zero_lengths_lose_no_row() {
    let strategy = (
        mech((-3.0f64..3.0).prop_map(|e| 10f64.powf(e))),
        0.05f64..0.95,
        0.05f64..0.95,
        1usize..30,
        -2i32..3,
        any::<bool>(),
    );
    let mut runner = TestRunner::new(config(64));
    let result = runner.run(&strategy, |(m, below, above, n, turns, late)| {
        // The zero and the values around it, one of them on it.
        let (zero, before, after) = if m.trammel {
            let reach = m.scale / m.phi.sin();
            (-m.scale, below * (reach - m.scale) * 0.95, above * m.scale)
        } else {
            let at = if late { 270f64 } else { 90.0 } + 360.0 * f64::from(turns);
            (at.to_radians(), below * 1.5, above * 1.5)
        };
        let step = (before + after) / n as f64;
        let first = -((before / step).floor());
        let values: Vec<f64> = (0..=n).map(|i| zero + (first + i as f64) * step).collect();
        let (rows, _, g) = run(&m, 0.0, &values, after + before);
        prop_assert_eq!(rows.len(), values.len());
        for r in &rows {
            check_row(&m, &g, r)?;
        }
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// Sweeps of random mechanisms (lengths from 1e-9 to 1e9), ranges (from = to, negative steps,
/// steps larger than the range, values out of reach) and start inputs (huge ones included) end
/// within the bound on solves, give one row per value, solve every value within reach and name
/// no dead point below [`DEAD_POINT_CONDITION`].
#[test]
fn sweeps_end_within_bounded_work() {
    let start = prop_oneof![
        4 => Just(0.0),
        1 => prop_oneof![Just(2e154), Just(1e300), Just(-1e300), Just(7e3), Just(-5e6)],
    ];
    let strategy = (
        mech((-9.0f64..9.0).prop_map(|e| 10f64.powf(e))),
        -3.0f64..3.0,
        -3.0f64..3.0,
        prop_oneof![Just(0.0), -2.0f64..2.0],
        prop_oneof![1usize..20, Just(1)],
        start,
    );
    let mut runner = TestRunner::new(config(96));
    let result = runner.run(&strategy, |(m, a, b, b_same, n, start)| {
        // Ranges in units of the scale (trammel) or in turns (slider); from = to when b_same = 0.
        let unit = if m.trammel {
            m.scale
        } else {
            2.0 * std::f64::consts::PI
        };
        let (from, to) = (a * unit, if b_same == 0.0 { a * unit } else { b * unit });
        // A random step of either sign, up to twice the range (the last row is `to`).
        let step = ((to - from).abs().max(unit * 0.01) * 2.0 / n as f64) * b.signum();
        let count = ((to - from) / step).abs().floor() as usize;
        let dir = if to >= from { 1.0 } else { -1.0 };
        let mut values: Vec<f64> = (0..=count)
            .map(|i| from + dir * step.abs() * i as f64)
            .collect();
        if values.last() != Some(&to) {
            values.push(to);
        }
        let start_x = start * if m.trammel { m.scale } else { 1.0 };
        let (rows, calls, g) = run(&m, start_x, &values, to - from);
        let bound = 3 * sweep_budget(values.len()) + 4 * values.len() + 1;
        prop_assert!(calls <= bound, "{calls} calls for {} rows", values.len());
        prop_assert_eq!(rows.len(), values.len());
        let usable = start_x.abs()
            <= if m.trammel {
                1e6 * m.scale
            } else {
                1000.0 * 2.0 * std::f64::consts::PI
            };
        for r in &rows {
            if let Some(stop) = r.stopped {
                prop_assert!(!stop.at_dead_point() || stop.condition >= DEAD_POINT_CONDITION);
            }
            if !usable {
                prop_assert_eq!(r.status(), "unusable-start");
            } else if start == 0.0 && m.in_reach(r.input, 0.98) {
                check_row(&m, &g, r)?;
            } else if !m.in_reach(r.input, 1.02) {
                prop_assert!(
                    r.result.is_err(),
                    "out of reach at {}: {:?}",
                    r.input,
                    r.result
                );
            }
        }
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}
