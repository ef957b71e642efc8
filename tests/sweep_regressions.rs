//! Sweeps that lose no rows and always end (issue 10, items 1–3), on both engines, against closed
//! forms computed in `common/sweep.rs`: healthy configurations whose length unknowns are all zero,
//! spans of zero, unreachable values, huge params and start inputs, rows many turns apart, and an
//! angle input's start taken modulo 2π.
#![cfg(feature = "runtime")]

#[path = "common/sweep.rs"]
mod support;

use mechgen::sweep::{Continuation, Row, StopReason, check_start, sweep, sweep_budget};
use mechgen::{DynMechanism, Kind, report};
use support::{Counting, Exact, angle_diff, load};

/// Every row solved and equal to `exact` (angles modulo 2π and lengths to `tol`, rates to
/// `tol_rate` relative to `scale`); the unknowns' kinds say which are angles.
fn assert_rows(
    k: &dyn DynMechanism<f64>,
    rows: &[Row],
    exact: impl Fn(f64) -> Exact,
    tol: f64,
    tol_rate: f64,
) -> f64 {
    let info = k.info();
    let mut worst: f64 = 0.0;
    for r in rows {
        let s = r.result.as_ref().unwrap_or_else(|e| {
            panic!("{}: row {} lost: {e} ({:?})", info.name, r.input, r.stopped)
        });
        let (q, qd) = exact(r.input);
        for (i, u) in info.unknowns.iter().enumerate() {
            let d = if u.kind == Kind::Angle {
                angle_diff(s.q[i], q[i])
            } else {
                s.q[i] - q[i]
            };
            assert!(
                d.abs() <= tol,
                "{} at {}: {} {} vs {}",
                info.name,
                r.input,
                u.name,
                s.q[i],
                q[i]
            );
            let dr = (s.qd[i] - qd[i]).abs() / qd[i].abs().max(1.0);
            assert!(
                dr <= tol_rate,
                "{} at {}: {}_vel {} vs {}",
                info.name,
                r.input,
                u.name,
                s.qd[i],
                qd[i]
            );
            worst = worst.max(d.abs()).max(dr);
        }
    }
    worst
}

fn range(from: f64, to: f64, step: f64) -> Vec<f64> {
    let n = ((to - from) / step).round() as usize;
    (0..=n).map(|i| from + step * i as f64).collect()
}

#[test]
fn the_trammel_sweeps_through_zero_lengths() {
    let g = load("trammel.toml");
    let values = range(-0.34, 0.40, 0.02);
    let rows = sweep(
        &g,
        0,
        &values,
        1.0,
        &Continuation::for_input(Kind::Length, 0.74),
    );
    assert_eq!(rows.len(), 38);
    let phi = 30f64.to_radians();
    let worst = assert_rows(
        &g,
        &rows,
        |sx| support::trammel(0.26, phi, sx).expect("in reach"),
        1e-13,
        1e-11,
    );
    eprintln!("trammel: largest difference {worst:e}");
    // The row at sx = -0.26 = -L lands on sy = 0 (to rounding).
    let sy: Vec<f64> = rows
        .iter()
        .map(|r| r.result.as_ref().map_or(f64::NAN, |s| s.q[1]))
        .collect();
    assert!(sy[4].abs() < 1e-15 && sy[3] < 0.0 && sy[5] > 0.0, "{sy:?}");
}

#[test]
fn the_in_line_slider_crank_sweeps_from_450_to_540_degrees() {
    let g = load("slider_inline.toml");
    let values: Vec<f64> = range(450.0, 540.0, 5.0)
        .iter()
        .map(|d| d.to_radians())
        .collect();
    let rows = sweep(
        &g,
        0,
        &values,
        1.0,
        &Continuation::for_input(Kind::Angle, 0.0),
    );
    let x0 = 0.282842712474619;
    let worst = assert_rows(
        &g,
        &rows,
        |q1| support::slider_inline(0.1, 0.3, x0, q1),
        1e-13,
        1e-11,
    );
    eprintln!("slider_inline: largest difference {worst:e}");
    let s0 = rows[0].result.as_ref().expect("450").q[1];
    assert!(s0.abs() < 1e-15, "s at 450 deg is {s0:e}");
}

/// The compiled-in offset slider-crank with params whose slider passes through sC = 0 at the row
/// q1 = 195° (r = 0.1, l = 0.2, off = 0.1492; dead point near 210°): generated and generic.
#[test]
fn both_engines_sweep_a_slider_through_zero() {
    let (r, l) = (0.1, 0.2);
    let crossing = 195f64.to_radians();
    let off = r * crossing.sin() + (l * l - (r * crossing.cos()).powi(2)).sqrt();
    let generated = mechgen::slider_crank::SliderCrank::<f64> {
        params: mechgen::slider_crank::Params { r, l, off },
    };
    let source = mechgen::generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
        .expect("compiled-in file loads");
    let mut generic = source
        .into_iter()
        .find(|m| m.name() == "slider_crank")
        .expect("slider_crank");
    for (name, v) in [("r", r), ("l", l), ("off", off)] {
        generic.set_param(name, v).expect("param");
    }
    let values: Vec<f64> = range(150.0, 205.0, 1.0)
        .iter()
        .map(|d| d.to_radians())
        .collect();
    let c = Continuation::for_input(Kind::Angle, 0.0);
    let exact = |q1| support::slider_offset(r, l, off, q1).expect("in reach");
    let a = sweep(&generated, 0, &values, 1.0, &c);
    let b = sweep(&generic, 0, &values, 1.0, &c);
    for rows in [&a, &b] {
        assert_rows(&generated, rows, exact, 1e-13, 1e-11);
        let sc: Vec<f64> = rows
            .iter()
            .map(|r| r.result.as_ref().map_or(f64::NAN, |s| s.q[1]))
            .collect();
        assert!(
            sc[45].abs() < 1e-15 && sc[44] > 0.0 && sc[46] < 0.0,
            "{sc:?}"
        );
    }
}

#[test]
fn an_angle_start_is_taken_modulo_a_turn() {
    let file = mechgen::generic::load_file(&support::data("stephenson.toml")).expect("loads");
    let [a, b] = [&file[0], &file[1]];
    let values: Vec<f64> = range(-110.0, -20.0, 10.0)
        .iter()
        .map(|d| d.to_radians())
        .collect();
    let c = Continuation::for_input(Kind::Angle, 0.0);
    let (ra, rb) = (sweep(a, 0, &values, 1.0, &c), sweep(b, 0, &values, 1.0, &c));
    let generated = mechgen::lookup::<f64>("sixbar_g").expect("compiled in");
    let rg = sweep(generated.as_ref(), 0, &values, 1.0, &c);
    for ((x, y), z) in ra.iter().zip(&rb).zip(&rg) {
        let (x, y, z) = (
            x.result.as_ref().expect("337.9-style start solves"),
            y.result.as_ref().expect("-22.1-style start solves"),
            z.result.as_ref().expect("generated solves"),
        );
        assert_eq!(x.q, y.q, "the same configuration, the same rows");
        assert_eq!(x.qd, y.qd);
        for (u, v) in x.q.iter().zip(&z.q) {
            assert!(angle_diff(*u, *v).abs() < 1e-12, "{u} vs {v}");
        }
    }
}

/// Sweeps `values` through a counting wrapper; returns the rows and the number of calls, which
/// must stay within the documented bound.
fn counted(k: &Counting<'_>, values: &[f64], c: &Continuation) -> (Vec<Row>, usize) {
    let rows = sweep(k, 0, values, 1.0, c);
    let calls = k.calls.get();
    let bound = 3 * sweep_budget(values.len()) + 4 * values.len() + 1;
    assert_eq!(rows.len(), values.len());
    assert!(calls <= bound, "{calls} calls, bound {bound}");
    (rows, calls)
}

#[test]
fn a_span_of_zero_and_unreachable_values_end() {
    let g = load("trammel.toml");
    let k = Counting::new(&g);
    // --from 0.3 --to 0.3: a length input at one value away from the start (it used to hang).
    let (rows, calls) = counted(&k, &[0.3], &Continuation::for_input(Kind::Length, 0.0));
    let phi = 30f64.to_radians();
    assert_rows(
        &g,
        &rows,
        |sx| support::trammel(0.26, phi, sx).expect("in reach"),
        1e-13,
        1e-11,
    );
    eprintln!("one value 0.3 from the start: {calls} calls");
    // One value out of reach (the dead point is at sx = 0.52): a failed row at the dead point.
    let k = Counting::new(&g);
    let (rows, calls) = counted(&k, &[0.6], &Continuation::for_input(Kind::Length, 0.0));
    let stop = rows[0].stopped.expect("stopped");
    eprintln!("one value out of reach: {calls} calls, stopped at {stop:?}");
    assert!(rows[0].result.is_err());
    assert!(
        (stop.input - 0.52).abs() < 1e-6 && stop.at_dead_point(),
        "{stop:?}"
    );
}

#[test]
fn huge_params_and_start_inputs_end() {
    // A bar of 1e9 swept at one value.
    let mut g = load("trammel.toml");
    g.set_param("L", 1e9).expect("param");
    let k = Counting::new(&g);
    let (rows, calls) = counted(&k, &[1.0], &Continuation::for_input(Kind::Length, 0.0));
    eprintln!("bar of 1e9: {calls} calls");
    let s = rows[0].result.as_ref().expect("solves");
    let (q, _) = support::trammel(1e9, 30f64.to_radians(), 1.0).expect("in reach");
    assert!(angle_diff(s.q[0], q[0]).abs() < 1e-12 && ((s.q[1] - q[1]) / 1e9).abs() < 1e-12);
    // Start inputs of 2e154 and 1e300 are not usable: every row says so, nothing is solved.
    for start in [2e154, 1e300, -1e300] {
        for file in ["trammel.toml", "slider_inline.toml"] {
            let g = load(file);
            let mut k = Counting::new(&g);
            k.info.inputs[0].start = start;
            assert!(check_start(&k.info).is_err());
            let (rows, calls) =
                counted(&k, &[0.1, 0.2], &Continuation::for_input(Kind::Angle, 0.0));
            assert_eq!(calls, 0);
            assert!(
                rows.iter().all(|r| r.status() == "unusable-start"),
                "{rows:?}"
            );
        }
    }
}

#[test]
fn rows_many_turns_apart_get_a_substep_limit() {
    let g = load("slider_inline.toml");
    let k = Counting::new(&g);
    let values: Vec<f64> = [0.0, 5e5, 1e6]
        .iter()
        .map(|d: &f64| d.to_radians())
        .collect();
    let (rows, calls) = counted(&k, &values, &Continuation::for_input(Kind::Angle, 0.0));
    eprintln!("rows 1389 turns apart: {calls} calls");
    assert_eq!(rows[0].status(), "ok");
    for r in &rows[1..] {
        assert_eq!(r.status(), "substep-limit", "{r:?}");
        assert_eq!(r.stopped.map(|s| s.reason), Some(StopReason::SubstepLimit));
        assert!(!r.stopped.expect("stopped").at_dead_point());
    }
    let info = DynMechanism::<f64>::info(&g);
    let table = report::table(&info, 0, &rows);
    assert!(
        table.contains("substep-limit: the continuation used up its substeps"),
        "{table}"
    );
    assert!(!table.contains("dead point"), "{table}");
    assert!(report::csv(&info, 0, &rows).contains(",substep-limit\n"));
}

#[test]
fn a_sweep_of_many_far_apart_rows_stops_trying() {
    // 40 rows each 139 turns from the one before: past the sweep's budget the remaining rows get
    // `substep-limit` without any work.
    let g = load("slider_inline.toml");
    let k = Counting::new(&g);
    let values: Vec<f64> = (0..40).map(|i| (f64::from(i) * 5e4).to_radians()).collect();
    let (rows, calls) = counted(&k, &values, &Continuation::for_input(Kind::Angle, 0.0));
    eprintln!("40 rows 139 turns apart: {calls} calls");
    assert_eq!(rows[0].status(), "ok");
    assert!(rows[1..].iter().all(|r| r.status() == "substep-limit"));
}
