//! The seed shaper's variants of `examples/accuracy` (no timing here): the same full turn in 1°
//! ticks as the six-bar's (`variants.rs`: [`Stepper`], [`run`], [`State`]), against the 40-digit
//! reference `tests/data/shaper.csv`, with errors that respect the shaper's two kinds of unknown.
//! `tests/accuracy_variants.rs` includes this file too.
//!
//! Error measure (the largest over the states at 0°, 10°, …, 360°): angles (q3, q4) in radians
//! modulo 2π; lengths (s3, sE) relative to the larger of the largest length param and the
//! largest magnitude of their reference column; velocities and accelerations relative to the
//! largest magnitude of their reference column (as for the six-bar).
#![allow(dead_code)]

use mechgen::shaper::{INFO, Shaper};
use mechgen::{InputMotion, Kind, NewtonOptions, Real, SolveOptions, StaticMechanism};

use crate::variants::{Errors, N, Reference, State, Stepper, Tick, angle_diff, parse_reference};

const _: () = assert!(INFO.unknowns.len() == N);

/// `tests/data/shaper.csv` (40-digit values, parsed to the nearest f64).
pub fn reference() -> Result<Reference, String> {
    let text = include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/shaper.csv"
    ));
    parse_reference(text, INFO.inputs[0].name, INFO.unknowns)
}

/// The start values of the shaper's unknowns (the file's `start` table).
pub fn start() -> [f64; N] {
    Shaper::<f64>::start().1.to_array()
}

/// The largest of the shaper's length params (its default values).
pub fn largest_length_param() -> f64 {
    INFO.params
        .iter()
        .filter(|p| p.kind == Kind::Length)
        .fold(0.0, |m, p| m.max(p.default.abs()))
}

/// Largest errors over the sampled rows (see the module docs); infinite when a sample is
/// missing or not finite.
pub fn errors(samples: &[State], reference: &Reference) -> Errors {
    if samples.len() != reference.rows.len() {
        return Errors {
            position: f64::INFINITY,
            velocity: f64::INFINITY,
            acceleration: f64::INFINITY,
        };
    }
    let worst = |d: f64, m: f64| if d.is_nan() { f64::INFINITY } else { m.max(d) };
    let column = |get: fn(&State) -> &[f64; N], j: usize| {
        reference
            .rows
            .iter()
            .fold(f64::MIN_POSITIVE, |s, r| s.max(get(r)[j].abs()))
    };
    let rate = |get: fn(&State) -> &[f64; N]| {
        (0..N).fold(0.0f64, |m, j| {
            let scale = column(get, j);
            samples.iter().zip(&reference.rows).fold(m, |m, (s, r)| {
                worst((get(s)[j] - get(r)[j]).abs() / scale, m)
            })
        })
    };
    let length = largest_length_param();
    let position = (0..N).fold(0.0f64, |m, j| {
        let angle = INFO.unknowns[j].kind == Kind::Angle;
        let scale = length.max(column(|s| &s.q, j));
        samples.iter().zip(&reference.rows).fold(m, |m, (s, r)| {
            let d = if angle {
                angle_diff(s.q[j], r.q[j]).abs()
            } else {
                (s.q[j] - r.q[j]).abs() / scale
            };
            worst(d, m)
        })
    });
    Errors {
        position,
        velocity: rate(|s| &s.qd),
        acceleration: rate(|s| &s.qdd),
    }
}

/// Newton on every block (`closed_forms: false`) at this tolerance, cap 64.
pub fn newton<T: Real>(tolerance: f64) -> SolveOptions<T> {
    SolveOptions {
        newton: NewtonOptions {
            tolerance: T::lit(tolerance),
            max_iterations: 64,
        },
        closed_forms: false,
    }
}

/// The generated shaper (`mechgen::shaper::Shaper<T>`) stepped with `tick` (predictor and cached
/// sines and cosines inside) under the given options: closed forms by default, or Newton on
/// every block from the tick's prediction. Assembly (`tick_start`) with the same options.
pub struct Generated<T: Real> {
    mechanism: Shaper<T>,
    options: SolveOptions<T>,
    tick: Option<mechgen::shaper::Tick<T>>,
}

impl<T: Real> Generated<T> {
    pub fn new(options: SolveOptions<T>) -> Self {
        Generated {
            mechanism: Shaper::default(),
            options,
            tick: None,
        }
    }
}

fn motion<T: Real>(x: f64) -> InputMotion<[T; 1]> {
    InputMotion::new([T::lit(x)], [T::one()], [T::zero()])
}

impl<T: Real> Stepper for Generated<T> {
    fn reset(&mut self, x: f64) -> Result<(), String> {
        let (_, start) = Shaper::<T>::start();
        let t = StaticMechanism::tick_start(
            &self.mechanism,
            &motion(x),
            &start.to_array(),
            &self.options,
        )
        .map_err(|e| format!("shaper: assembly at {x}: {e}"))?;
        self.tick = Some(t);
        Ok(())
    }

    #[inline]
    fn step(&mut self, x: f64, _dx: f64) -> Result<Tick, String> {
        let t = self
            .tick
            .as_mut()
            .ok_or("shaper: a step before the assembly")?;
        let mut tick = Tick::default();
        match StaticMechanism::tick(&self.mechanism, t, &motion(x), &self.options) {
            Ok(()) => tick.iterations = t.report.iterations,
            Err(_) => tick.failed = true,
        }
        Ok(tick)
    }

    fn state(&self) -> State {
        let f = |a: &[T; N]| a.map(Real::to_f64);
        self.tick.as_ref().map_or_else(State::default, |t| State {
            q: f(&t.q),
            qd: f(&t.qd),
            qdd: f(&t.qdd),
        })
    }
}

/// The shaper as the generic engine loads it from the compiled-in file.
pub fn generic() -> Result<mechgen::generic::Generic, String> {
    mechgen::generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
        .map_err(|e| e.to_string())?
        .into_iter()
        .find(|g| g.name() == "shaper")
        .ok_or_else(|| "the compiled-in file has no shaper".to_string())
}
