//! Run-time messages of the command line as snapshots (expect-test; `UPDATE_EXPECT=1` rewrites
//! them): a batch param set with a value that is not finite fails that set only; a step that would
//! make too many rows, a range no sweep resolves, a param or unknown given as an input and a
//! negative time or flywheel DELTA are refused before any row is solved. The file-level messages
//! (a param in degrees, one missing `]`, a singular start) are fixtures of `tests/diagnostics/`.
//! Each command runs in its own temporary directory with relative paths, so the text is the same
//! on every machine.
#![cfg(feature = "cli")]

mod common;

use std::path::Path;
use std::process::Command;

use common::cli::TempDir;
use expect_test::{Expect, expect};

/// A fresh directory for `case`, removed after the test.
fn dir(case: &str) -> TempDir {
    TempDir::new(&format!("messages-{case}"))
}

/// Runs `mechgen args` in `dir`: its exit code, and stdout and stderr as one snapshot.
fn run(dir: &Path, args: &[&str], code: i32, snapshot: Expect) {
    let out = Command::new(env!("CARGO_BIN_EXE_mechgen"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("mechgen runs");
    assert_eq!(out.status.code(), Some(code), "{args:?}");
    let text = format!(
        "stdout:\n{}stderr:\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    snapshot.assert_eq(&text);
}

#[test]
fn a_set_with_a_value_that_is_not_finite_fails_alone() {
    let d = dir("nan");
    std::fs::write(
        d.join("sets.csv"),
        "l1,l2\n0.1,0.35\nnan,0.35\n0.1,-inf\n0.11,0.35\n",
    )
    .expect("sets");
    run(
        &d,
        &[
            "batch", "four_bar", "--params", "sets.csv", "--from", "0", "--to", "20", "--step",
            "10",
        ],
        0,
        expect![[r#"
            stdout:
            four_bar: 4 param set(s) over 3 rows each: 2 assembled on every row, 2 with failed rows, 2 on none
            stderr:
            mechgen: sets.csv:3: set 1: `nan` for `l1` is not finite: its rows are `non-finite-input`
            mechgen: sets.csv:4: set 2: `-inf` for `l2` is not finite: its rows are `non-finite-input`
        "#]],
    );
}

#[test]
fn a_step_too_small_for_a_batch_is_refused() {
    let d = dir("step");
    std::fs::write(d.join("sets.csv"), "l1\n0.1\n0.11\n").expect("sets");
    run(
        &d,
        &[
            "batch", "four_bar", "--params", "sets.csv", "--step", "1e-7", "--csv", "rows.csv",
        ],
        1,
        expect![[r#"
            stdout:
            stderr:
            mechgen: --step 0.0000001 from 0 to 360 makes 3.600e9 rows; a sweep has at most 10 000 000 (a larger --step, or a shorter range)
        "#]],
    );
    // Under the sweep's limit per set, but more rows than a CSV should hold.
    let sets: String = std::iter::once("l1\n".to_string())
        .chain((0..30).map(|i| format!("{}\n", 0.1 + 1e-4 * f64::from(i))))
        .collect();
    std::fs::write(d.join("many.csv"), sets).expect("sets");
    run(
        &d,
        &[
            "batch", "four_bar", "--params", "many.csv", "--step", "1e-4", "--csv", "rows.csv",
        ],
        1,
        expect![[r#"
            stdout:
            stderr:
            mechgen: 30 set(s) × 3600001 rows = 108000030 rows: a CSV of about 22 GB; --csv writes at most 100000000 rows (ask for --summary only, or fewer sets, or a larger --step)
        "#]],
    );
}

#[test]
fn a_range_no_sweep_resolves_is_refused() {
    let d = dir("range");
    run(
        &d,
        &["sweep", "four_bar", "--from", "1e20", "--to", "1e20"],
        1,
        expect![[r#"
            stdout:
            stderr:
            mechgen: --from 1e20 deg is beyond what a sweep of input `q1` resolves: at most 3.6e5 deg in magnitude (a thousand turns for an angle input, a million times the largest length param for a length input)
        "#]],
    );
}

/// `--set` and `--input` name inputs: a param or an unknown named there is refused with the
/// inputs, and what the name is instead.
#[test]
fn a_param_or_unknown_given_as_an_input_is_refused_with_what_it_is() {
    let d = dir("not-an-input");
    run(
        &d,
        &["sweep", "four_bar", "--set", "l1=0.2"],
        1,
        expect![[r#"
            stdout:
            stderr:
            mechgen: `four_bar` has no input `l1` (its inputs: q1; `l1` is a param: change its value in the file, or sweep several with `batch --params`)
        "#]],
    );
    run(
        &d,
        &["branches", "four_bar", "--input", "q2"],
        1,
        expect![[r#"
            stdout:
            stderr:
            mechgen: `four_bar` has no input `q2` (its inputs: q1; `q2` is an unknown, solved for at every row)
        "#]],
    );
}

/// A negative number where a positive one is needed is the command's own refusal (the option and
/// what it needs), not a parse error about an unexpected argument `-1`.
#[test]
fn a_negative_time_or_flywheel_is_refused_by_the_command() {
    let d = dir("negative");
    run(
        &d,
        &["simulate", "four_bar", "--time", "-1", "--dt", "0.1"],
        1,
        expect![[r#"
            stdout:
            stderr:
            mechgen: --time needs a value ≥ 0 and --dt one > 0
        "#]],
    );
    run(
        &d,
        &["dynamics", "shaper", "--flywheel", "-0.05"],
        1,
        expect![[r#"
            stdout:
            stderr:
            mechgen: shaper: --flywheel: needs a non-zero --rate and DELTA > 0
        "#]],
    );
}

/// A scene given to a command that runs whole mechanisms names its mechanism; a misspelt
/// mechanism gets the nearest name.
#[test]
fn a_scene_or_a_misspelt_name_where_a_mechanism_is_needed() {
    let d = dir("scene-name");
    run(
        &d,
        &["dynamics", "sixbar_output"],
        1,
        expect![[r#"
            stdout:
            stderr:
            mechgen: `sixbar_output` is a scene of mechanism `sixbar`: `sweep` and `batch` run scenes; this command runs on the whole mechanism (give `sixbar`)
        "#]],
    );
    run(
        &d,
        &["simulate", "fourbar", "--time", "1", "--dt", "0.1"],
        1,
        expect![[r#"
            stdout:
            stderr:
            mechgen: no mechanism `fourbar` in mechanism.toml (it has: sixbar, shaper, four_bar, slider_crank, rocker_four_bar, sixbar_g); did you mean `four_bar`?
        "#]],
    );
}
