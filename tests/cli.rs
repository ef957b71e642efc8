//! The `mechgen` command as interfaces.md specifies it: sweep (both engines, `--file`), check,
//! the CSV format (no NaN or inf, kebab-case status, empty cells on failed rows), exit codes.
#![cfg(feature = "cli")]

mod common;

use std::path::Path;
use std::process::Command;

use common::{Table, angle_diff};

use common::cli::{mechgen, text};

fn temp(name: &str) -> common::cli::Temp {
    common::cli::temp("cli", name)
}

/// Every cell is a finite number or empty, the status is `ok` or kebab-case, failed rows are empty.
fn check_csv_format(path: &Path) -> Table {
    let t = Table::read(path.to_str().expect("utf-8 path"));
    assert_eq!(t.header.last().map(String::as_str), Some("status"));
    for row in &t.rows {
        assert_eq!(row.len(), t.header.len(), "{row:?}");
        let status = &row[row.len() - 1];
        assert!(
            !status.is_empty() && status.chars().all(|c| c.is_ascii_lowercase() || c == '-'),
            "status `{status}`"
        );
        for cell in &row[1..row.len() - 1] {
            if status == "ok" {
                if cell.is_empty() {
                    continue; // cond may be empty exactly at a singular point
                }
                let v: f64 = cell.parse().unwrap_or_else(|_| panic!("cell `{cell}`"));
                assert!(v.is_finite(), "cell `{cell}`");
            } else {
                assert!(cell.is_empty(), "failed row has a value: {row:?}");
            }
        }
        assert!(row[0].parse::<f64>().is_ok_and(f64::is_finite), "{row:?}");
    }
    t
}

/// Angles of the compiled-in mechanism `mech` compared modulo 2π, derivatives relative to their
/// column's largest magnitude, lengths absolute (as the reference README describes).
fn compare_with_reference(csv: &Path, reference: &str, tolerance: f64) {
    let mech = reference.trim_end_matches(".csv");
    let info = mechgen::lookup::<f64>(mech).expect("compiled in").info();
    let angles: Vec<&str> = info
        .inputs
        .iter()
        .chain(&info.unknowns)
        .filter(|c| c.kind == mechgen::Kind::Angle)
        .map(|c| c.name.as_str())
        .collect();
    let got = check_csv_format(csv);
    let want = Table::read(&format!(
        "{}/tests/data/{reference}",
        env!("CARGO_MANIFEST_DIR")
    ));
    assert_eq!(got.rows.len(), want.rows.len());
    assert!(got.rows.iter().all(|r| r.last().is_some_and(|s| s == "ok")));
    let mut worst: f64 = 0.0;
    for name in want
        .header
        .iter()
        .filter(|h| *h != "status" && *h != "detJ")
    {
        let (g, w) = (got.column(name), want.column(name));
        let deriv = name.ends_with("_vel")
            || name.ends_with("_acc")
            || name.contains("_v")
            || name.contains("_a");
        let scale = if deriv {
            w.iter().fold(1e-300f64, |m, v| m.max(v.abs()))
        } else {
            1.0
        };
        let angle = angles.contains(&name.as_str());
        for (a, b) in g.iter().zip(&w) {
            let d = if angle { angle_diff(*a, *b) } else { a - b };
            worst = worst.max(d.abs() / scale);
        }
    }
    eprintln!("{reference}: largest error {worst:e}");
    assert!(worst <= tolerance, "{reference}: error {worst:e}");
}

#[test]
fn generic_sweep_of_the_seed_file_matches_the_reference() {
    let csv = temp("sixbar-generic.csv");
    let out = mechgen(&[
        "sweep",
        "sixbar",
        "--file",
        "tests/data/seeds.toml",
        "--engine",
        "generic",
        "--csv",
        csv.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    compare_with_reference(&csv, "sixbar.csv", 1e-10);
    let csv = temp("shaper-generic.csv");
    let out = mechgen(&[
        "sweep",
        "shaper",
        "--file",
        "tests/data/seeds.toml",
        "--csv",
        csv.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    compare_with_reference(&csv, "shaper.csv", 1e-10);
}

#[test]
fn generated_sweep_matches_the_reference() {
    let csv = temp("sixbar-generated.csv");
    let out = mechgen(&["sweep", "sixbar", "--csv", csv.to_str().expect("utf-8")]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    compare_with_reference(&csv, "sixbar.csv", 1e-10);
    let stdout = text(&out.stdout);
    assert!(stdout.contains("q1[deg]"), "{stdout}");
}

#[test]
fn failed_rows_have_a_status_and_empty_cells() {
    let csv = temp("rocker.csv");
    let out = mechgen(&[
        "sweep",
        "rocker_four_bar",
        "--from",
        "0",
        "--to",
        "360",
        "--step",
        "15",
        "--csv",
        csv.to_str().expect("utf-8"),
    ]);
    assert!(
        out.status.success(),
        "rows that fail do not fail the command"
    );
    let t = check_csv_format(&csv);
    let statuses: Vec<&str> = t
        .rows
        .iter()
        .filter_map(|r| r.last().map(String::as_str))
        .collect();
    assert_eq!(statuses.len(), 25);
    assert!(statuses[..10].iter().all(|s| *s == "ok"), "{statuses:?}");
    assert!(
        statuses[10..].iter().all(|s| *s != "ok"),
        "past the dead point at 135.95 deg: {statuses:?}"
    );
    assert!(t.header.contains(&"cond".to_string()));
}

#[test]
fn length_input_and_options() {
    let out = mechgen(&[
        "sweep", "sixbar", "--from", "10", "--to", "20", "--step", "5", "--rate", "2",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    // Title, units, rate, column header, then the three rows.
    assert_eq!(text(&out.stdout).lines().count(), 4 + 3);
    let actuator = "tests/fixtures/actuator.toml";
    let out = mechgen(&["sweep", "actuator", "--file", actuator]);
    assert!(
        !out.status.success(),
        "a length input needs --from and --to"
    );
    assert!(text(&out.stderr).contains("--from and --to"));
}

#[test]
fn usage_errors_exit_non_zero_with_a_message() {
    for args in [
        &["sweep", "no_such_mechanism"][..],
        &["sweep", "sixbar", "--engine", "fast"],
        &["sweep", "sixbar", "--step", "nan"],
        &["sweep", "sixbar", "--from"],
        &["sweep", "sixbar", "--colour", "red"],
        &[
            "sweep",
            "sixbar",
            "--file",
            "tests/data/seeds.toml",
            "--engine",
            "generated",
        ],
        &["sweep", "sixbar", "--file", "does/not/exist.toml"],
        &["sweep"],
        &["frobnicate"],
        &["check", "--file", "does/not/exist.toml"],
    ] {
        let out = mechgen(args);
        assert!(!out.status.success(), "{args:?} should fail");
        let err = text(&out.stderr);
        assert!(err.starts_with("mechgen: "), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

#[test]
fn check_prints_structure_or_errors() {
    let out = mechgen(&["check"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let s = text(&out.stdout);
    for name in mechgen::MECHANISMS {
        assert!(s.contains(&format!("mechanism {name}:")), "{s}");
    }
    assert!(s.contains("blocks:   4x4 [q1, q2, q3, q5]"), "{s}");
    let out = mechgen(&["check", "--file", "tests/data/seeds.toml"]);
    assert!(out.status.success());
    let bad = temp("bad.toml");
    std::fs::write(&bad, "[mechanism.m]\ninputs = [\"q1\"]\nunknowns = [\"q2\"]\nloops = [\"l*e(q1) + zz*e(q2)\"]\nparams = { l = 1.0 }\nstart = { q1 = 0.0, q2 = 1.0 }\n").expect("write");
    let out = mechgen(&["check", "--file", bad.to_str().expect("utf-8")]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(err.contains("bad.toml:4:"), "{err}");
    assert!(err.contains("`zz`"), "{err}");
}

#[test]
fn plot_option_writes_svgs() {
    let dir = temp("plots");
    let out = mechgen(&[
        "sweep",
        "shaper",
        "--step",
        "30",
        "--plot",
        dir.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    for kind in ["motion", "drawing"] {
        let svg = std::fs::read_to_string(dir.join(format!("shaper-{kind}.svg"))).expect("written");
        assert!(svg.starts_with("<svg"), "{kind}");
        assert!(!svg.contains("NaN") && !svg.contains("inf\""), "{kind}");
    }
}

#[test]
fn the_main_job_writes_a_csv_and_two_plots_per_mechanism() {
    let dir = temp("main-job");
    std::fs::create_dir_all(&dir).expect("dir");
    let out = Command::new(env!("CARGO_BIN_EXE_mechgen"))
        .current_dir(&dir)
        .output()
        .expect("mechgen runs");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    for name in mechgen::MECHANISMS {
        assert!(stdout.contains(&format!("{name} — ")), "{stdout}");
        for file in [
            format!("{name}.csv"),
            format!("{name}-motion.svg"),
            format!("{name}-drawing.svg"),
        ] {
            let path = dir.join("mechgen-out").join(&file);
            assert!(path.exists(), "{file} missing");
        }
        check_csv_format(&dir.join("mechgen-out").join(format!("{name}.csv")));
    }
    // A rocking input's start branch is swept whole, from one dead point to the other, every row
    // on it: the triple-rocker's dead points are at ±acos((a² + d² − (b + c)²) / 2ad) = ±135.95°.
    let csv = std::fs::read_to_string(dir.join("mechgen-out").join("rocker_four_bar.csv"))
        .expect("written");
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert!(rows.iter().all(|r| r.last() == Some(&"ok")), "{csv}");
    let dead = ((0.3f64 * 0.3 + 0.4 * 0.4 - 0.65 * 0.65) / (2.0 * 0.3 * 0.4)).acos();
    let input = |r: &[&str]| r[0].parse::<f64>().expect("input");
    let (first, last) = (input(&rows[0]), input(&rows[rows.len() - 1]));
    assert!(
        (first + dead).abs() < 1e-5 && (last - dead).abs() < 1e-5,
        "{first} {last}"
    );
    assert!(
        stdout.contains("q1 from 224.0486256741 deg to 495.9513743259 deg"),
        "{stdout}"
    );
}

/// A closed stderr or stdout (`mechgen check --file bad.toml 2>&1 | true`, `mechgen check | head`)
/// ends the output, not the command: it exits with its own status, never a panic's 101.
#[test]
fn closed_pipes_keep_the_commands_status() {
    let bad = temp("closed-pipe-bad.toml");
    std::fs::write(
        &bad,
        "[mechanism.m]\ninputs = [\"q1\"]\nunknowns = [\"q2\"]\nloops = [\"zz\"]\n",
    )
    .expect("temp file");
    let closed = || {
        let (reader, writer) = std::io::pipe().expect("a pipe");
        drop(reader);
        writer
    };
    let run = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_mechgen"))
            .args(args)
            .stdout(closed())
            .stderr(closed())
            .status()
            .expect("runs")
            .code()
    };
    assert_eq!(
        run(&["check", "--file", bad.to_str().expect("utf-8")]),
        Some(1)
    );
    assert_eq!(run(&["check"]), Some(0));
    assert_eq!(run(&["sweep", "nope"]), Some(1));
    assert_eq!(run(&["--bogus"]), Some(2));
}

/// A range a sweep cannot resolve (beyond a thousand turns of an angle input: f64 no longer tells
/// a degree there) is refused with a message naming the option and the limit, not swept into rows
/// that all read `unassemblable`.
#[test]
fn a_range_beyond_a_thousand_turns_is_refused() {
    for args in [
        &["sweep", "four_bar", "--from", "1e20", "--to", "1e20"][..],
        &["sweep", "four_bar", "--from", "0", "--to", "-4e5"][..],
    ] {
        let out = mechgen(args);
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let err = text(&out.stderr);
        assert!(
            err.contains("is beyond what a sweep of input `q1` resolves: at most 3.6e5 deg"),
            "{err}"
        );
    }
    let out = mechgen(&[
        "sweep", "four_bar", "--from", "-360000", "--to", "-359990", "--step", "5",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table = text(&out.stdout);
    assert!(
        table.contains("-359995.0") && !table.contains("unassemblable"),
        "{table}"
    );
}
