//! Sweeps stream their rows (issue 18 item 6): rows below the start row are solved downward and
//! handed out upward from checkpoints of the continuation's state, with exactly the numbers of a
//! sweep that solves them in one downward pass; and a long sweep's memory does not grow with its
//! rows (the kernel's count of the process's peak memory).
#![cfg(feature = "cli")]

mod common;

use common::cli::text;
use mechgen::Kind;
use mechgen::sweep::{Continuation, SEGMENT, nearest_row, sweep};

/// `sixbar_g` starts at q6 = 280.67 deg; 250 to 340 deg in steps of 0.004 deg puts about 7700
/// rows below the start row, more than one segment. The same rows swept in descending order from
/// the start row (whose sweep has no row below its start row, so no checkpoint) are the rows below
/// the start row in one downward pass: bit for bit the same.
#[test]
fn checkpointed_rows_equal_one_downward_pass() {
    let k = mechgen::lookup::<f64>("sixbar_g").expect("compiled in");
    let info = k.info();
    let values: Vec<f64> = (0..=22_500)
        .map(|i| (250.0 + 0.004 * f64::from(i)).to_radians())
        .collect();
    let c = Continuation::for_input(Kind::Angle, values[values.len() - 1] - values[0]);
    let m = nearest_row(Kind::Angle, info.inputs[0].start, &values).expect("rows");
    assert!(m > SEGMENT + 10, "{m} rows below the start row");
    let rows = sweep(k.as_ref(), 0, &values, 1.0, &c);
    let down: Vec<f64> = values[..=m].iter().rev().copied().collect();
    assert_eq!(
        nearest_row(Kind::Angle, info.inputs[0].start, &down),
        Some(0)
    );
    let one_pass = sweep(k.as_ref(), 0, &down, 1.0, &c);
    for (i, r) in one_pass.iter().rev().enumerate() {
        assert_eq!(r, &rows[i], "row {i}");
    }
    assert!(rows.iter().all(|r| r.result.is_ok()));
}

fn peak_kb(out: &std::process::Output) -> f64 {
    let err = text(&out.stderr);
    let line = err
        .lines()
        .find_map(|l| l.strip_prefix("mechgen: peak memory "))
        .unwrap_or_else(|| panic!("no peak memory line:\n{err}"));
    line.trim_end_matches(" kB").trim().parse().expect("kB")
}

/// 100 000 rows with a CSV: the peak memory stays far below what holding the rows took (about
/// 1.1 kB per row: 113 MB here), and about where 10 000 rows leave it.
#[test]
fn a_long_sweep_with_a_csv_keeps_memory_flat() {
    if !std::path::Path::new("/proc/self/status").exists() {
        return;
    }
    let run = |step: &str, csv: &str| {
        let csv = common::cli::temp("sweep-stream", csv);
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_mechgen"))
            .args([
                "sweep",
                "sixbar",
                "--step",
                step,
                "--csv",
                csv.to_str().unwrap(),
            ])
            .env("MECHGEN_PEAK_MEMORY", "1")
            .output()
            .expect("runs");
        assert!(out.status.success(), "{}", text(&out.stderr));
        let rows = std::fs::read_to_string(&csv).expect("csv").lines().count() - 1;
        let _ = std::fs::remove_file(&csv);
        (rows, peak_kb(&out))
    };
    let (small_rows, small) = run("0.036", "small.csv");
    let (rows, peak) = run("0.0036", "large.csv");
    assert_eq!((small_rows, rows), (10_001, 100_001));
    assert!(peak < 60_000.0, "peak {peak} kB for {rows} rows");
    assert!(
        peak < small + 20_000.0,
        "peak {peak} kB for {rows} rows, {small} kB for {small_rows}"
    );
}
