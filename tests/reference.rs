//! The generated solvers against the 40-digit reference values of the seed mechanisms.

mod common;

use common::{Table, compare};
use mechgen::Kind;
use mechgen::sweep::{Continuation, sweep};

fn check_against_reference(name: &str, tolerance: f64) {
    let k = mechgen::lookup::<f64>(name).expect("compiled in");
    let reference = Table::read(&format!(
        "{}/tests/data/{name}.csv",
        env!("CARGO_MANIFEST_DIR")
    ));
    let info = k.info();
    let input = &reference.header[0];
    assert_eq!(input, &info.inputs[0].name);
    let values = reference.column(input);
    let rows = sweep(
        k.as_ref(),
        0,
        &values,
        1.0,
        &Continuation::for_input(Kind::Angle, 0.0),
    );
    assert!(
        rows.iter().all(|r| r.result.is_ok()),
        "{name}: every row solves"
    );
    let errors = compare(&info, &rows, &reference);
    for (col, err) in &errors {
        assert!(
            *err <= tolerance,
            "{name}.{col}: error {err:e} > {tolerance:e}"
        );
    }
    eprintln!(
        "{name}: largest error {:e}",
        errors.iter().fold(0.0f64, |m, e| m.max(e.1))
    );
}

#[test]
fn sixbar_matches_reference() {
    check_against_reference("sixbar", 1e-10);
}

#[test]
fn shaper_matches_reference() {
    check_against_reference("shaper", 1e-10);
}
