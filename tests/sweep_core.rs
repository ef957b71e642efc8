//! The sweep core's work per row: a row past the end of the followed branch (a dead point met in
//! the direction of travel) costs no solve, whatever the engine, and a sweep's rows past it fail
//! with the dead point's status.
#![cfg(feature = "runtime")]

mod common;

use common::sweep::Counting;
use mechgen::Kind;
use mechgen::sweep::{Continuation, sweep};

/// The compiled-in mechanism `name` and the same loaded from the compiled-in file (the
/// interpreter).
fn both_engines(
    name: &str,
) -> (
    Box<dyn mechgen::DynMechanism<f64>>,
    mechgen::generic::Generic,
) {
    let generated = mechgen::lookup::<f64>(name).expect("compiled in");
    let loaded = mechgen::generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
        .expect("the compiled-in file loads");
    let generic = loaded
        .into_iter()
        .find(|g| g.name() == name)
        .expect("in the file");
    (generated, generic)
}

/// `rocker_four_bar` (start q1 = 0) can turn up to its dead point near 135.95°: a sweep from 0°
/// to 200° and one to 360° make exactly the same solves, the 160 rows more all past the dead
/// point, and every row past it fails with the dead point named.
#[test]
fn rows_past_the_end_of_the_branch_cost_no_solve() {
    let (generated, generic) = both_engines("rocker_four_bar");
    for (engine, k) in [
        ("generated", generated.as_ref()),
        ("generic", &generic as &dyn mechgen::DynMechanism<f64>),
    ] {
        let calls = |to: i32| {
            let values: Vec<f64> = (0..=to).map(|d| f64::from(d).to_radians()).collect();
            let c = Continuation::for_input(Kind::Angle, values[values.len() - 1]);
            let counted = Counting::new(k);
            let rows = sweep(&counted, 0, &values, 1.0, &c);
            (counted.calls.get(), rows)
        };
        let (short, rows_short) = calls(200);
        let (long, rows) = calls(360);
        let ok = rows.iter().filter(|r| r.result.is_ok()).count();
        assert_eq!(ok, 136, "{engine}: rows 0° to 135° on the branch");
        assert!(
            rows[136..].iter().all(|r| r.dead_point().is_some()),
            "{engine}: every row past the branch's end names its dead point"
        );
        assert_eq!(rows_short, rows[..=200], "{engine}");
        assert_eq!(
            long, short,
            "{engine}: solves of a sweep to 360° against one to 200°"
        );
        assert!(short > 136, "{engine}: the counter counts ({short})");
    }
}

/// A Strandbeest leg (python/bench/strandbeest.toml) with lengths 1 % off Jansen's, whose knee
/// reaches a dead point near 192°: swept from its start (0°) in rows of 1° and of 0.05° on the
/// interpreter, the rows the two sweeps share have the same statuses and the same configuration
/// (1e-9), and no angle winds off by whole turns (the interpreter's tick keeps its closed-form
/// unknowns as the guess, as a generated tick does: an extrapolated guess near the dead point
/// once crossed it onto another branch, turns away).
#[test]
fn a_coarse_sweep_keeps_to_the_branch_of_a_fine_one_near_a_dead_point() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/python/bench/strandbeest.toml");
    let mut g = mechgen::generic::load_file(std::path::Path::new(path))
        .expect("loads")
        .remove(0);
    for (p, v) in [
        ("m", 15.144749354839064),
        ("b", 41.63244073754208),
        ("lc", 38.93706334139929),
        ("d", 39.993608204747424),
        ("le", 56.186381957254135),
        ("f", 39.68136689924513),
        ("g", 36.744482104346865),
        ("h", 65.66791505880639),
        ("li", 49.180891961036835),
        ("j", 50.3620377035005),
        ("k", 62.43945899561173),
    ] {
        g.set_param(p, v).expect("a param");
    }
    let sweep_by = |step: f64| {
        let n = (359.0 / step).round() as usize;
        let values: Vec<f64> = (0..=n)
            .map(|i| (1.0 + step * i as f64).to_radians())
            .collect();
        let c = Continuation::for_input(Kind::Angle, values[n] - values[0]);
        sweep(&g, 0, &values, 1.0, &c)
    };
    let (coarse, fine) = (sweep_by(1.0), sweep_by(0.05));
    let ok = coarse.iter().filter(|r| r.result.is_ok()).count();
    assert!((150..359).contains(&ok), "{ok} rows on the branch");
    for (i, r) in coarse.iter().enumerate() {
        let f = &fine[i * 20];
        assert!((r.input - f.input).abs() < 1e-12);
        assert_eq!(r.status(), f.status(), "row {i}");
        if let (Ok(a), Ok(b)) = (&r.result, &f.result) {
            for (u, v) in a.points.iter().zip(&b.points) {
                for c in 0..2 {
                    let d = (u.position[c] - v.position[c]).abs();
                    assert!(d < 1e-9, "row {i}: {d:e}");
                }
            }
            assert!(
                a.q.iter().all(|q| q.abs() < 4.0 * std::f64::consts::PI),
                "row {i}"
            );
        }
    }
}

/// `sweep_each_indexed` hands out the rows of `sweep_each_with`, bit for bit, each once with its
/// index, as the walk solves them: the start row first, then the rows below it downward, then the
/// rows above it; across two checkpoints of the downward walk (`SEGMENT` rows apart), and on a
/// rocker whose rows past its dead points, both ways, fail.
#[test]
fn indexed_rows_are_the_ordered_rows_as_solved() {
    use mechgen::sweep::{SEGMENT, sweep_each_indexed, sweep_each_with};
    // 2·SEGMENT + 300 rows below the start and 500 above in steps of 0.01°; 200 each way in 1°.
    let fine = (2 * SEGMENT + 300, 500, 0.01);
    for (name, (below, above, step)) in [
        ("four_bar", fine),
        ("rocker_four_bar", fine),
        ("rocker_four_bar", (200, 200, 1.0)),
    ] {
        let k = mechgen::lookup::<f64>(name).expect("compiled in");
        let start = k.info().inputs[0].start;
        let values: Vec<f64> = (0..below + above + 1)
            .map(|i| start + (i as f64 - below as f64) * f64::to_radians(step))
            .collect();
        let c = Continuation::for_input(Kind::Angle, values[values.len() - 1] - values[0]);
        let mut ordered = Vec::new();
        sweep_each_with(k.as_ref(), 0, &values, 1.0, &[], &c, None, &mut |r| {
            ordered.push(r.to_row())
        });
        let mut order = Vec::new();
        let mut indexed = vec![None; values.len()];
        sweep_each_indexed(k.as_ref(), 0, &values, 1.0, &[], &c, None, &mut |i, r| {
            order.push(i);
            assert!(
                indexed[i].replace(r.to_row()).is_none(),
                "{name}: row {i} twice"
            );
        });
        let indexed: Vec<_> = indexed.into_iter().map(|r| r.expect("every row")).collect();
        assert_eq!(indexed, ordered, "{name}");
        let solved: Vec<usize> = std::iter::once(below)
            .chain((0..below).rev())
            .chain(below + 1..values.len())
            .collect();
        assert_eq!(order, solved, "{name}: the start row, then down, then up");
        let ok = ordered.iter().filter(|r| r.result.is_ok()).count();
        assert!(ok > 200, "{name}: {ok} rows solved");
        if step == 1.0 {
            assert!(ok < ordered.len(), "{name}: rows past the dead points fail");
        }
    }
}

/// A sweep whose first row is the start itself starts its tick there, with no continuation to
/// it: fewer solves than a sweep whose one row lies 1e-9 rad off the start (which continues to
/// it first), on both engines; the two rows agree to the step's size.
#[test]
fn a_start_row_at_the_start_needs_no_continuation() {
    let (generated, generic) = both_engines("four_bar");
    for (engine, k) in [
        ("generated", generated.as_ref()),
        ("generic", &generic as &dyn mechgen::DynMechanism<f64>),
    ] {
        let start = k.info().inputs[0].start;
        let solves = |value: f64| {
            let c = Continuation::for_input(Kind::Angle, 1.0);
            let counted = Counting::new(k);
            let rows = sweep(&counted, 0, &[value], 1.0, &c);
            (counted.calls.get(), rows)
        };
        let (at, rows_at) = solves(start);
        let (off, rows_off) = solves(start + 1e-9);
        assert!(at < off, "{engine}: {at} solves at the start, {off} off it");
        let (a, b) = (&rows_at[0].result, &rows_off[0].result);
        let (a, b) = (a.as_ref().expect("solved"), b.as_ref().expect("solved"));
        for (u, v) in a.q.iter().zip(&b.q) {
            assert!((u - v).abs() < 1e-8, "{engine}: {u} against {v}");
        }
    }
}
