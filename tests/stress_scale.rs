//! Scale invariance: a mechanism with every length param multiplied by 1e-3 and by 1e4 must give
//! the same angles (absolute 1e-12 rad) and the same lengths, point positions, velocities and
//! accelerations divided by the factor (relative 1e-12) over a sweep. Every tolerance of the
//! solvers and of the continuation must therefore be relative. Mechanisms: the seed six-bar (two
//! 2×2 blocks, full turn), the dyad-driven six-bar (one 4×4 block, up to 4 degrees from its dead
//! point) and the shaper (length unknowns).
//!
//! `cargo test --release --test stress_scale -- --nocapture` prints the measured errors.

mod common;

use common::angle_diff;
use common::stress::{continuation, length_scale};
use mechgen::sweep::continue_to;
use mechgen::{DynMechanism, InputMotion, Kind, PointMotion, SolveOptions};

const FACTORS: [f64; 2] = [1e-3, 1e4];
/// Angles (radians) and everything else relative to the length scale or the column's largest value.
const TOLERANCE: f64 = 1e-12;

/// A compiled-in mechanism with every length param multiplied by `s` (angles unchanged), through
/// `Params::from_array` and the kinds in `INFO`.
macro_rules! scaled {
    ($module:ident :: $ty:ident) => {
        |s: f64| -> Box<dyn DynMechanism<f64>> {
            use mechgen::$module::{INFO, Params};
            let p = Params::<f64>::default().to_array();
            let v = std::array::from_fn(|i| match INFO.params[i].kind {
                Kind::Angle => p[i],
                _ => p[i] * s,
            });
            Box::new(mechgen::$module::$ty {
                params: Params::from_array(v),
            })
        }
    };
}

fn sixbar(s: f64) -> Box<dyn DynMechanism<f64>> {
    scaled!(sixbar::Sixbar)(s)
}

fn sixbar_g(s: f64) -> Box<dyn DynMechanism<f64>> {
    scaled!(sixbar_g::SixbarG)(s)
}

fn shaper(s: f64) -> Box<dyn DynMechanism<f64>> {
    scaled!(shaper::Shaper)(s)
}

/// Every value of a sweep divided by the factor where it is a length (or its rate), with the
/// kind of comparison: (angle, values). Columns: unknowns, their rates and accelerations, then
/// the point positions, velocities and accelerations.
struct Sweep {
    columns: Vec<(bool, Vec<f64>)>,
}

/// Sweeps the (one, angle) input of `make(s)` over `inputs` by continuation from the file's start
/// configuration scaled by `s`, at input rate 1 and input acceleration 0.
fn run(make: fn(f64) -> Box<dyn DynMechanism<f64>>, s: f64, inputs: &[f64]) -> Sweep {
    let k = make(s);
    let info = k.info();
    assert_eq!(info.inputs[0].kind, Kind::Angle, "an angle input");
    let length = |kind: Kind| kind == Kind::Length;
    let unscale = |kind: Kind, v: f64| if length(kind) { v / s } else { v };
    let mut x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
    let mut q: Vec<f64> = info
        .unknowns
        .iter()
        .map(|u| if length(u.kind) { u.start * s } else { u.start })
        .collect();
    k.solve_position(&x, &mut q, &SolveOptions::default())
        .expect("start assembles");
    let n = q.len();
    let mut columns: Vec<(bool, Vec<f64>)> = Vec::new();
    for u in &info.unknowns {
        columns.push((u.kind == Kind::Angle, Vec::new()));
    }
    for _ in 0..2 * n + 6 * info.points.len() {
        columns.push((false, Vec::new()));
    }
    for &input in inputs {
        continue_to(k.as_ref(), &mut x, &mut q, 0, input, &continuation())
            .unwrap_or_else(|e| panic!("{} at {input}: {e:?}", info.name));
        let (mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n]);
        let mut points = vec![PointMotion::default(); info.points.len()];
        k.solve_velocity(&x, &q, &[1.0], &mut qd).expect("velocity");
        k.solve_acceleration(&x, &q, &[1.0], &qd, &[0.0], &mut qdd)
            .expect("acceleration");
        k.points(
            InputMotion::new(&x, &[1.0], &[0.0]),
            &q,
            &qd,
            &qdd,
            &mut points,
        )
        .expect("points");
        let kinds = info.unknowns.iter().map(|u| u.kind).cycle();
        let row = q
            .iter()
            .chain(&qd)
            .chain(&qdd)
            .zip(kinds)
            .map(|(v, k)| unscale(k, *v));
        let row = row.chain(points.iter().flat_map(|p| {
            [p.position, p.velocity, p.acceleration]
                .into_iter()
                .flatten()
                .map(|v| v / s)
        }));
        for (c, v) in columns.iter_mut().zip(row) {
            c.1.push(v);
        }
    }
    Sweep { columns }
}

/// Largest error of the scaled sweep against the unscaled one: angles absolute; lengths (unknowns
/// and point positions) relative to the length scale; rates relative to the column's largest value.
fn compare(base: &Sweep, scaled: &Sweep, n: usize, length: f64) -> [f64; 3] {
    let mut worst = [0.0f64; 3];
    for (i, ((angle, want), (_, got))) in base.columns.iter().zip(&scaled.columns).enumerate() {
        // group: 0 positions, 1 velocities, 2 accelerations
        let group = if i < 3 * n {
            i / n
        } else {
            (i - 3 * n) % 6 / 2
        };
        let scale = match (group, angle) {
            (0, true) => 1.0,
            (0, false) => length,
            _ => column_max(want),
        };
        for (w, g) in want.iter().zip(got) {
            let d = if *angle { angle_diff(*g, *w) } else { g - w };
            let e = if d.is_nan() {
                f64::INFINITY
            } else {
                d.abs() / scale
            };
            worst[group] = worst[group].max(e);
        }
    }
    worst
}

fn column_max(v: &[f64]) -> f64 {
    v.iter().fold(f64::MIN_POSITIVE, |m, x| m.max(x.abs()))
}

fn check(make: fn(f64) -> Box<dyn DynMechanism<f64>>, degrees: &[f64]) {
    let inputs: Vec<f64> = degrees.iter().map(|d| d.to_radians()).collect();
    let info = make(1.0).info();
    let length = length_scale(&info);
    let base = run(make, 1.0, &inputs);
    for s in FACTORS {
        let scaled = run(make, s, &inputs);
        let [pos, vel, acc] = compare(&base, &scaled, info.unknowns.len(), length);
        eprintln!(
            "{:<8} x{s:<6e}: positions {pos:.1e}, velocities {vel:.1e}, accelerations {acc:.1e}",
            info.name
        );
        for (what, e) in [("position", pos), ("velocity", vel), ("acceleration", acc)] {
            assert!(
                e <= TOLERANCE,
                "{} scaled by {s:e}: {what} error {e:e}",
                info.name
            );
        }
    }
}

#[test]
fn sixbar_is_scale_invariant() {
    let degrees: Vec<f64> = (0..=36).map(|d| f64::from(d * 10)).collect();
    check(sixbar, &degrees);
}

#[test]
fn dyad_driven_sixbar_is_scale_invariant() {
    let degrees: Vec<f64> = (0..=18).map(|d| 250.0 + f64::from(d * 5)).collect();
    check(sixbar_g, &degrees);
}

#[test]
fn shaper_is_scale_invariant() {
    let degrees: Vec<f64> = (0..=36).map(|d| f64::from(d * 10)).collect();
    check(shaper, &degrees);
}
