//! The sweep core's work per row: a row past the end of the followed branch (a dead point met in
//! the direction of travel) costs no solve, whatever the engine, and a sweep's rows past it fail
//! with the dead point's status.
#![cfg(feature = "runtime")]

mod common;

use common::sweep::Counting;
use mechgen::Kind;
use mechgen::sweep::{Continuation, sweep};

/// `rocker_four_bar` (start q1 = 0) can turn up to its dead point near 135.95°: a sweep from 0°
/// to 200° and one to 360° make exactly the same solves, the 160 rows more all past the dead
/// point, and every row past it fails with the dead point named.
#[test]
fn rows_past_the_end_of_the_branch_cost_no_solve() {
    let generated = mechgen::lookup::<f64>("rocker_four_bar").expect("compiled in");
    let loaded = mechgen::generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
        .expect("the compiled-in file loads");
    let generic = loaded
        .into_iter()
        .find(|g| g.name() == "rocker_four_bar")
        .expect("in the file");
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
