//! Past a dead point: `solve_position` reports `Unassemblable` (not `NoConvergence`, not a
//! configuration of another branch), sweeps stop at the dead point and say so, and
//! `NoConvergence` still means "the iteration cap was too tight".

#![cfg(feature = "runtime")]

mod common;

use common::angle_diff;
use common::stress::{
    DEAD_POINT_MECHANISMS, Started, cell, continuation, dead_points, generic, reference, start,
    start_with,
};
use mechgen::report::table;
use mechgen::sweep::{Row, continue_to, sweep};
use mechgen::{NewtonOptions, SolveError, SolveOptions};

/// Degrees beyond the dead point at which no configuration exists.
const BEYOND_DEG: [f64; 5] = [1e-6, 1e-5, 1e-4, 1e-2, 1.0];

#[test]
fn just_past_a_dead_point_is_unassemblable() {
    for name in DEAD_POINT_MECHANISMS {
        let table = reference(name);
        for (engine, (k, x0, q0)) in ["generated", "generic"].into_iter().zip(engines(name)) {
            // Iterations and smallest relative residual over every case of this engine.
            let (mut its, mut residuals) = (Vec::new(), Vec::new());
            for (side, dead) in dead_points(name) {
                let direction = if side == "upper" { 1.0 } else { -1.0 };
                // Guesses: the states reached by continuation at 1e-2, 1e-4 and 1e-6 degrees inside.
                let (mut x, mut q) = (x0.clone(), q0.clone());
                let mut guesses = Vec::new();
                for row in table.rows.iter().filter(|r| r[0] == side) {
                    let input = cell(&table, row, &k.info().inputs[0].name);
                    continue_to(k.as_ref(), &mut x, &mut q, 0, input, &continuation())
                        .expect("inside the range");
                    if cell(&table, row, "offset_deg") < 0.1 {
                        guesses.push(q.clone());
                    }
                }
                for beyond in BEYOND_DEG {
                    let past = [dead + direction * beyond.to_radians()];
                    for guess in &guesses {
                        let mut trial = guess.clone();
                        let result = k.solve_position(&past, &mut trial, &SolveOptions::default());
                        match result {
                            Err(SolveError::Unassemblable {
                                iterations,
                                residual,
                                ..
                            }) => {
                                its.push(iterations);
                                if beyond == 1e-6 {
                                    residuals.push(residual);
                                }
                            }
                            other => panic!(
                                "{name} {engine} {side}, {beyond:e} deg past the dead point: {other:?}"
                            ),
                        }
                    }
                }
            }
            let range = |v: &[f64]| {
                v.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &r| {
                    (lo.min(r), hi.max(r))
                })
            };
            let (rlo, rhi) = range(&residuals);
            eprintln!(
                "{name:<16} {engine:<9} unassemblable after {}-{} iterations; relative residual at 1e-6 deg beyond {rlo:.1e}-{rhi:.1e}",
                its.iter().min().unwrap_or(&0),
                its.iter().max().unwrap_or(&0)
            );
        }
    }
}

/// The generated engine and the generic one (closed forms for every kind it recognises, block
/// Newton elsewhere).
fn engines(name: &str) -> Vec<Started> {
    vec![start(name), start_with(generic(name))]
}

#[test]
fn at_the_dead_point_itself_newton_converges_linearly() {
    for name in DEAD_POINT_MECHANISMS {
        for (side, dead) in dead_points(name) {
            for (k, mut x, mut q) in engines(name) {
                let direction = if side == "upper" { 1.0 } else { -1.0 };
                let inside = dead - direction * 1e-2f64.to_radians();
                continue_to(k.as_ref(), &mut x, &mut q, 0, inside, &continuation())
                    .expect("inside the range");
                // The Jacobian is singular at the solution: convergence is only linear, and Newton
                // must run until its steps stagnate at rounding level, not stop at a fixed count.
                // (A closed-form dyad block takes no iterations: 0 is allowed for the four-bar
                // loop, which both engines solve in closed form.)
                let report = k
                    .solve_position(&[dead], &mut q, &SolveOptions::default())
                    .unwrap_or_else(|e| panic!("{name} {side}: {e:?}"));
                eprintln!(
                    "{name:<16} {side:<6} at the dead point from 1e-2 deg inside: {} iterations, cond {:.1e}",
                    report.iterations,
                    report.condition()
                );
                assert!(
                    report.iterations > 10 || report.iterations == 0,
                    "{name} {side}: {report:?}"
                );
                assert!(
                    report.residual <= 64.0 * f64::EPSILON,
                    "{name} {side}: {report:?}"
                );
                assert!(report.condition() > 1e6, "{name} {side}: {report:?}");
                let mut r = vec![0.0; q.len()];
                k.residual(&[dead], &q, &mut r).expect("sizes");
                assert!(
                    r.iter().all(|v| v.abs() < 1e-12 * 100.0),
                    "{name} {side}: residual {r:?}"
                );
            }
        }
    }
    // Newton at a dead point is exercised on both mechanisms: the generic engine with its closed
    // forms off iterates on every block.
    let newton = SolveOptions {
        closed_forms: false,
        ..SolveOptions::default()
    };
    for name in DEAD_POINT_MECHANISMS {
        let (k, mut x, mut q) = start_with(generic(name));
        let (_, dead) = dead_points(name)[0];
        let inside = dead - 1e-2f64.to_radians();
        continue_to(k.as_ref(), &mut x, &mut q, 0, inside, &continuation()).expect("inside");
        let report = k
            .solve_position(&[dead], &mut q, &newton)
            .expect("converges");
        assert!(report.iterations > 10, "{name}: {report:?}");
    }
}

#[test]
fn no_convergence_means_the_iteration_cap_was_too_tight() {
    for name in DEAD_POINT_MECHANISMS {
        for (k, x, q) in engines(name) {
            // An ordinary configuration 0.2 rad from the start, from the start's values.
            let moved = [x[0] + 0.2];
            let tight = SolveOptions {
                newton: NewtonOptions {
                    max_iterations: 2,
                    ..NewtonOptions::default()
                },
                ..SolveOptions::default()
            };
            let mut trial = q.clone();
            let result = k.solve_position(&moved, &mut trial, &tight);
            if let Ok(report) = result {
                // A closed-form block: no iterations to cap.
                assert_eq!(report.iterations, 0, "{name}: {report:?}");
                continue;
            }
            assert!(
                matches!(result, Err(SolveError::NoConvergence { .. })),
                "{name}: two iterations: {result:?}"
            );
            // The same solve with the default cap converges, continuing from where it stopped.
            let report = k
                .solve_position(&moved, &mut trial, &SolveOptions::default())
                .unwrap_or_else(|e| panic!("{name}: {e:?}"));
            assert!(report.residual <= 64.0 * f64::EPSILON, "{name}: {report:?}");
            // A tolerance below rounding is met as far as the precision allows: steps that stop
            // shrinking at a rounding-level residual are convergence, not failure.
            let exact = SolveOptions {
                newton: NewtonOptions {
                    tolerance: 0.0,
                    ..NewtonOptions::default()
                },
                ..SolveOptions::default()
            };
            let mut again = q.clone();
            let report = k
                .solve_position(&moved, &mut again, &exact)
                .unwrap_or_else(|e| panic!("{name}, tolerance 0: {e:?}"));
            assert!(report.iterations < 64, "{name}: {report:?}");
            for (a, b) in again.iter().zip(&trial) {
                assert!((a - b).abs() < 1e-14, "{name}: {again:?} vs {trial:?}");
            }
        }
    }
}

/// The sweep rows at `inputs` (radians) from the start configuration.
fn sweep_rows(name: &str, inputs: &[f64]) -> Vec<Row> {
    let (k, _, _) = start(name);
    sweep(k.as_ref(), 0, inputs, 1.0, &continuation())
}

/// Asserts that the rows are solved exactly where `stop_at` gives no dead point, and that the
/// others are `Unassemblable`, stopped at that dead point (radians) and named so in the table.
fn check_stops(name: &str, rows: &[Row], stop_at: impl Fn(f64) -> Option<f64>) {
    let info = mechgen::lookup::<f64>(name).expect("compiled in").info();
    let text = table(&info, 0, rows);
    for r in rows {
        let at = format!("{name} at {:.4} deg", r.input.to_degrees());
        let Some(dead) = stop_at(r.input) else {
            assert!(r.result.is_ok(), "{at}: {:?}", r.result);
            assert_eq!(r.stopped, None, "{at}");
            continue;
        };
        assert!(
            matches!(r.result, Err(SolveError::Unassemblable { .. })),
            "{at}: {:?}",
            r.result
        );
        let stopped = r
            .stopped
            .unwrap_or_else(|| panic!("{at}: no stop recorded"));
        // Continuation halves its substep down to 1e-9 of 2 degrees: it gets within ~1e-10 rad.
        assert!(
            (stopped.input - dead).abs() < 1e-9,
            "{at}: stopped at {} rad, dead point {dead}",
            stopped.input
        );
        assert!(stopped.at_dead_point(), "{at}: {stopped:?}");
        let expected = format!(
            "unassemblable: dead point near {} = {:.4} deg",
            info.inputs[0].name,
            dead.to_degrees()
        );
        assert!(
            text.contains(&expected),
            "{name}: table lacks {expected:?}:\n{text}"
        );
    }
}

/// The reference rows of one dead point at `offset_deg`, as (input, unknowns).
fn reference_row(name: &str, side: &str, offset_deg: &str) -> (f64, Vec<f64>) {
    let table = reference(name);
    let row = table
        .rows
        .iter()
        .find(|r| r[0] == side && r[1] == offset_deg)
        .expect("reference row");
    let info = mechgen::lookup::<f64>(name).expect("compiled in").info();
    let q = info
        .unknowns
        .iter()
        .map(|u| cell(&table, row, &u.name))
        .collect();
    (cell(&table, row, &info.inputs[0].name), q)
}

/// The row at `input` is on the start branch: its unknowns match the reference (modulo 2π).
fn check_branch(rows: &[Row], input: f64, want: &[f64]) {
    let row = rows.iter().find(|r| r.input == input).expect("row");
    let got = &row.result.as_ref().expect("solved").q;
    for (g, w) in got.iter().zip(want) {
        assert!(angle_diff(*g, *w).abs() < 1e-12, "{got:?} vs {want:?}");
    }
}

/// Rows at the same inputs hold the same values: not only modulo 2π (angles that drifted by whole
/// turns lose digits).
fn check_same(a: &[Row], b: &[Row]) {
    for (ra, rb) in a.iter().zip(b) {
        assert_eq!(ra.input, rb.input);
        let (qa, qb) = (
            &ra.result.as_ref().expect("a").q,
            &rb.result.as_ref().expect("b").q,
        );
        for (x, y) in qa.iter().zip(qb) {
            assert!((x - y).abs() < 1e-10, "at {}: {qa:?} vs {qb:?}", ra.input);
        }
    }
}

#[test]
fn a_sweep_stops_at_the_dead_point_and_says_so() {
    // rocker_four_bar over a full turn: past 135.95 deg nothing is reachable on this branch
    // (the mirror range from 224 deg on belongs to the other side of the dead point).
    let name = "rocker_four_bar";
    let dead = dead_points(name)[0].1;
    let (near, near_q) = reference_row(name, "upper", "1e-2");
    let mut inputs: Vec<f64> = (0..=36).map(|d| f64::from(d * 10).to_radians()).collect();
    inputs.insert(14, near);
    // Back inside after the stop: the branch continues from the dead point, on the same side.
    inputs.push(100f64.to_radians());
    let rows = sweep_rows(name, &inputs);
    check_stops(name, &rows[..rows.len() - 1], |x| {
        (x > dead).then_some(dead)
    });
    check_branch(&rows, near, &near_q);
    check_same(&rows[10..11], &rows[rows.len() - 1..]);

    // sixbar_g from 250 deg up, and from the start down: each side stops at its dead point.
    let name = "sixbar_g";
    let deads = dead_points(name);
    assert_eq!(
        (deads[0].0.as_str(), deads[1].0.as_str()),
        ("upper", "lower")
    );
    for (side, dead) in deads.clone() {
        let (near, near_q) = reference_row(name, &side, "1e-2");
        let mut inputs: Vec<f64> = if side == "upper" {
            (50..=72).map(|d| f64::from(d * 5).to_radians()).collect()
        } else {
            (40..=56)
                .rev()
                .map(|d| f64::from(d * 5).to_radians())
                .collect()
        };
        let at = inputs
            .iter()
            .position(|x| (x - dead).abs() < 5f64.to_radians())
            .expect("near");
        inputs.insert(at + 1, near);
        let rows = sweep_rows(name, &inputs);
        let beyond = |x: f64| if side == "upper" { x > dead } else { x < dead };
        check_stops(name, &rows, |x| beyond(x).then_some(dead));
        check_branch(&rows, near, &near_q);
    }

    // sixbar_g over a full turn around its start (110 to 470 deg): from the start (280.7 deg)
    // down to 110 deg it stops at the lower dead point, comes back from it for 250 to 340 deg (the
    // same values as a sweep that never left the range) and stops at the upper one.
    let full: Vec<f64> = (11..=47).map(|d| f64::from(d * 10).to_radians()).collect();
    let rows = sweep_rows(name, &full);
    let (upper, lower) = (deads[0].1, deads[1].1);
    check_stops(name, &rows, |x| {
        if x < lower {
            Some(lower)
        } else {
            (x > upper).then_some(upper)
        }
    });
    let direct = sweep_rows(name, &full[14..24]);
    check_same(&rows[14..24], &direct);

    // From 0 deg (the default range): the sweep first reaches the row nearest the start (280 deg,
    // the start needs no whole turn), then goes up to 360 deg and down to 0 deg from there: 250 to
    // 340 deg are solved, with the same values as above, and each side stops at its dead point.
    let from_zero: Vec<f64> = (0..=36).map(|d| f64::from(d * 10).to_radians()).collect();
    let rows = sweep_rows(name, &from_zero);
    check_stops(name, &rows, |x| {
        if x < lower {
            Some(lower)
        } else {
            (x > upper).then_some(upper)
        }
    });
    check_same(&rows[25..35], &direct);
}
