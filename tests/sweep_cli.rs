//! The command line of issue 10 (items 2, 3, 5, 6, 8, 9): clap's help, version and suggestions,
//! `--input`/`--set` on a two-input five-bar against its closed form, the main job on `--file`,
//! units and significant digits in tables, full precision in the CSV, the start warning, the last
//! row exactly `--to`, unusable starts, and the `--animate` hook.
#![cfg(feature = "cli")]

mod common;
use common::sweep as support;

use std::process::Command;

use common::Table;
use support::angle_diff;

use common::cli::{mechgen, text};

fn temp(name: &str) -> common::cli::Temp {
    common::cli::temp("sweep-cli", name)
}

#[test]
fn help_for_every_command_and_the_version() {
    let out = mechgen(&["--help"]);
    assert!(out.status.success());
    let help = text(&out.stdout);
    for word in [
        "sweep",
        "check",
        "--file",
        "--animate",
        "--version",
        "main job",
    ] {
        assert!(help.contains(word), "{word}: {help}");
    }
    let out = mechgen(&["sweep", "--help"]);
    assert!(out.status.success());
    let help = text(&out.stdout);
    for option in [
        "--file",
        "--engine",
        "--from",
        "--to",
        "--step",
        "--rate",
        "--csv",
        "--plot",
        "--input",
        "--set",
        "--animate",
    ] {
        assert!(help.contains(option), "{option}: {help}");
    }
    assert!(help.contains("rad/s for an angle input"), "{help}");
    assert!(help.contains("deg/s"), "{help}");
    let out = mechgen(&["check", "--help"]);
    assert!(out.status.success() && text(&out.stdout).contains("--file"));
    let out = mechgen(&["--version"]);
    assert!(out.status.success());
    assert_eq!(
        text(&out.stdout).trim(),
        format!("mechgen {}", env!("CARGO_PKG_VERSION"))
    );
}

#[test]
fn misspelt_options_and_commands_get_a_suggestion() {
    for (args, suggestion) in [
        (&["sweep", "sixbar", "--form", "0"][..], "'--from'"),
        (&["sweep", "sixbar", "--fiel", "x.toml"], "'--file'"),
        (&["swep", "sixbar"], "'sweep'"),
        (&["--fille", "x.toml"], "'--file'"),
    ] {
        let out = mechgen(args);
        assert!(!out.status.success(), "{args:?}");
        let err = text(&out.stderr);
        assert!(err.starts_with("mechgen: "), "{err}");
        assert!(err.contains(suggestion), "{args:?}: {err}");
    }
}

#[test]
fn two_inputs_one_swept_one_held() {
    let csv = temp("fivebar.csv");
    let file = support::data("fivebar.toml");
    let out = mechgen(&[
        "sweep",
        "fivebar",
        "--file",
        file.to_str().expect("utf-8"),
        "--input",
        "q4",
        "--set",
        "q1=60",
        "--from",
        "60",
        "--to",
        "120",
        "--step",
        "5",
        "--csv",
        csv.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("held: q1 = 60.00000 deg"), "{stdout}");
    assert!(stdout.contains("q4[deg]"), "{stdout}");
    let t = Table::read(csv.to_str().expect("utf-8"));
    assert_eq!(t.header[0], "q4");
    let (q4, q2, q3) = (t.column("q4"), t.column("q2"), t.column("q3"));
    let (q2v, q3v) = (t.column("q2_vel"), t.column("q3_vel"));
    assert_eq!(q4.len(), 13);
    let q1 = 60f64.to_radians();
    // The held input is recorded, after the swept one, on every row.
    assert_eq!(t.header[1], "q1");
    assert!(
        t.column("q1").iter().all(|&v| v == q1),
        "{:?}",
        t.column("q1")
    );
    for i in 0..q4.len() {
        let want = support::fivebar(q1, q4[i]);
        assert!(
            angle_diff(q2[i], want[0]).abs() < 1e-12,
            "{i}: {} vs {}",
            q2[i],
            want[0]
        );
        assert!(
            angle_diff(q3[i], want[1]).abs() < 1e-12,
            "{i}: {} vs {}",
            q3[i],
            want[1]
        );
        // Rates of the closed form by central differences (error about 1e-10).
        let h = 1e-6;
        let (p, m) = (
            support::fivebar(q1, q4[i] + h),
            support::fivebar(q1, q4[i] - h),
        );
        let d = [
            angle_diff(p[0], m[0]) / (2.0 * h),
            angle_diff(p[1], m[1]) / (2.0 * h),
        ];
        assert!(
            (q2v[i] - d[0]).abs() < 1e-7 && (q3v[i] - d[1]).abs() < 1e-7,
            "{i}"
        );
    }
    // The default: the first input swept, the other at its start value.
    let out = mechgen(&["sweep", "fivebar", "--file", file.to_str().expect("utf-8")]);
    assert!(text(&out.stdout).contains("held: q4 = 90.00000 deg"));
    // Names that are not inputs, and --set on the swept input, are errors.
    for args in [
        &["--input", "q9"][..],
        &["--set", "q9=1"],
        &["--set", "q1=1"],
        &["--set", "q4"],
    ] {
        let mut all = vec!["sweep", "fivebar", "--file", file.to_str().expect("utf-8")];
        all.extend_from_slice(args);
        let out = mechgen(&all);
        assert!(!out.status.success(), "{args:?}");
        assert!(text(&out.stderr).starts_with("mechgen: "), "{args:?}");
    }
}

/// The main job on a file (`--file`), writing into `--out DIR` (interfaces.md: default
/// `./mechgen-out/`): every mechanism of the file swept, its CSV and drawing there, the directory
/// created with its parents, and nothing written into `./mechgen-out/`. (One run: the main job on
/// a file costs seconds in a debug build.)
#[test]
fn the_main_job_takes_a_file_and_writes_into_out() {
    let dir = temp("main-out");
    std::fs::create_dir_all(&dir).expect("dir");
    let file = support::data("stephenson.toml");
    let out = Command::new(env!("CARGO_BIN_EXE_mechgen"))
        .args(["--file", file.to_str().expect("utf-8"), "--out", "a/b"])
        .current_dir(&dir)
        .output()
        .expect("runs");
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("written to a/b/"),
        "{}",
        text(&out.stdout)
    );
    for name in ["stephenson_a", "stephenson_b"] {
        let csv = dir.join("a/b").join(format!("{name}.csv"));
        let t = Table::read(csv.to_str().expect("utf-8"));
        let ok = t
            .rows
            .iter()
            .filter(|r| r.last().is_some_and(|s| s == "ok"))
            .count();
        assert!(ok >= 7, "{name}: {ok} rows solved");
        assert!(dir.join("a/b").join(format!("{name}-drawing.svg")).exists());
    }
    assert!(!dir.join("mechgen-out").exists());
}

#[test]
fn tables_have_units_and_significant_digits_and_the_csv_full_precision() {
    let csv = temp("shaper.csv");
    let out = mechgen(&[
        "sweep",
        "shaper",
        "--from",
        "0",
        "--to",
        "25",
        "--step",
        "10",
        "--rate",
        "2",
        "--csv",
        csv.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("--rate 2.000000 rad/s = 114.5916 deg/s"),
        "{stdout}"
    );
    for column in [
        "q3[deg]",
        "q3_vel[deg/s]",
        "q3_acc[deg/s2]",
        "sE[u]",
        "sE_vel[u/s]",
        "E_ax[u/s2]",
    ] {
        assert!(stdout.contains(column), "{column}: {stdout}");
    }
    // The last row is exactly --to, and the table says why it is closer to the one before.
    assert!(stdout.contains("the last row is --to = 25"), "{stdout}");
    let t = Table::read(csv.to_str().expect("utf-8"));
    let inputs = t.column("q1");
    assert_eq!(inputs.last().copied(), Some(25f64.to_radians()));
    // Every number of the table has seven significant digits (or is 0).
    let rows: Vec<&str> = stdout
        .lines()
        .filter(|l| {
            l.split_whitespace()
                .next()
                .is_some_and(|c| c.parse::<f64>().is_ok())
        })
        .collect();
    assert_eq!(rows.len(), 4);
    for cell in rows.iter().flat_map(|l| l.split_whitespace()) {
        let digits: String = cell
            .split('e')
            .next()
            .expect("mantissa")
            .chars()
            .filter(char::is_ascii_digit)
            .collect();
        let significant = digits.trim_start_matches('0');
        assert!(cell == "0" || significant.len() == 7, "{cell}");
    }
    // CSV cells round-trip: each parses to an f64 whose shortest text is the cell itself.
    for row in &t.rows {
        for cell in &row[..row.len() - 1] {
            let v: f64 = cell.parse().expect("number");
            assert_eq!(&format!("{v:?}"), cell);
        }
    }
}

#[test]
fn sweep_repeats_the_start_warning() {
    let out = mechgen(&[
        "sweep",
        "four_bar",
        "--file",
        "tests/diagnostics/start_off.toml",
        "--step",
        "90",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    assert!(
        err.contains(
            "tests/diagnostics/start_off.toml:7:11: warning: start configuration of `four_bar`"
        ),
        "{err}"
    );
    assert!(
        err.contains("check that this is the wanted assembly branch"),
        "{err}"
    );
    // A start that closes the loops: no warning.
    let out = mechgen(&["sweep", "four_bar", "--step", "90"]);
    assert!(!text(&out.stderr).contains("warning"));
}

#[test]
fn hopeless_starts_and_spans_end_with_an_answer() {
    let huge = support::data("huge_start.toml");
    let out = mechgen(&[
        "sweep",
        "huge_start",
        "--file",
        huge.to_str().expect("utf-8"),
    ]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("`q1` (2e154) is not usable to start a sweep"),
        "{err}"
    );
    // A length input at one value away from its start, and at one value out of reach.
    let trammel = support::data("trammel.toml");
    for (value, status) in [("0.3", "ok"), ("0.6", "unassemblable")] {
        let csv = temp(&format!("trammel-{value}.csv"));
        let out = mechgen(&[
            "sweep",
            "trammel",
            "--file",
            trammel.to_str().expect("utf-8"),
            "--from",
            value,
            "--to",
            value,
            "--csv",
            csv.to_str().expect("utf-8"),
        ]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let t = Table::read(csv.to_str().expect("utf-8"));
        assert_eq!(t.rows.len(), 1);
        assert_eq!(t.rows[0].last().map(String::as_str), Some(status));
    }
}

#[test]
fn animate_is_an_option_of_sweep_and_the_main_job() {
    let dir = temp("animation");
    let out = mechgen(&[
        "sweep",
        "four_bar",
        "--step",
        "90",
        "--animate",
        dir.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    // One frame per solved row: 0, 90, 180, 270 and 360 degrees.
    let svg = std::fs::read_to_string(dir.join("four_bar-animation.svg")).expect("written");
    assert!(
        svg.starts_with("<svg") || svg.starts_with("<?xml"),
        "{}",
        &svg[..40]
    );
    assert!(svg.contains("keyTimes"), "an animated SVG");
    let out = mechgen(&["--animate", dir.to_str().expect("utf-8"), "--help"]);
    assert!(out.status.success());
}

/// Issue 18 item 1 (interfaces.md `sweep`, "Branch"): the sweep reaches the row nearest the start
/// first, then goes towards each end. `sixbar_g` starts at q6 = 280.67 deg on a branch between its
/// dead points at 244.53 and 344.13 deg: the default range (0 to 360 deg) has every row from 250
/// to 340 deg solved (the old rule moved the start to -79.33 deg and lost every row), the rows
/// outside stop at the dead point on their side, and tables print the same continuous angles as
/// the CSV (q1 goes from -21.09 to 19.55 deg, never folded to 338.9 deg).
#[test]
fn the_sweep_starts_at_the_row_nearest_the_start_and_goes_both_ways() {
    let csv = temp("sixbar_g.csv");
    let out = mechgen(&["sweep", "sixbar_g", "--csv", csv.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table = text(&out.stdout);
    let rows = std::fs::read_to_string(&csv).expect("csv");
    let mut lines = rows.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let q1 = header.iter().position(|h| *h == "q1").expect("q1 column");
    let mut previous: Option<f64> = None;
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        let input = cells[0].parse::<f64>().unwrap().to_degrees();
        let status = *cells.last().unwrap();
        let on_branch = (249.0..341.0).contains(&input);
        assert_eq!(status == "ok", on_branch, "q6 = {input} deg: {line}");
        if on_branch {
            let q1_deg = cells[q1].parse::<f64>().unwrap().to_degrees();
            // Continuous along the branch (rows 10 deg apart move q1 by less than 15 deg) ...
            if let Some(p) = previous {
                assert!((q1_deg - p).abs() < 15.0, "{p} -> {q1_deg}");
            }
            previous = Some(q1_deg);
            // ... and the table prints the CSV's angle, not one folded into [0, 360).
            let row = table
                .lines()
                .find(|l| l.split_whitespace().next() == Some(&format!("{input:.4}")[..]))
                .unwrap_or_else(|| panic!("table row {input:.4}:\n{table}"));
            let printed: f64 = row.split_whitespace().nth(1).unwrap().parse().unwrap();
            assert!(
                (printed - q1_deg).abs() < 1e-4 * q1_deg.abs().max(1.0),
                "{row}"
            );
        } else {
            // Past the branch's dead points: the other circuit of `mechgen branches sixbar_g`
            // (q6 from 40.93° to 176.19°) assembles; nothing else does.
            let other = (40.94..176.19).contains(&input);
            let want = if other {
                "other-branch"
            } else {
                "unassemblable"
            };
            assert_eq!(status, want, "q6 = {input} deg: {line}");
        }
    }
    assert!(table.contains("-21.09482"), "{table}");

    // A start between two rows: 280.67 deg lies between 275 and 285; both sides are reached, and
    // so are rows on both sides further away, whichever order the range is given in.
    for (from, to) in [("255", "335"), ("335", "255")] {
        let csv = temp(&format!("between-{from}.csv"));
        let args = [
            "sweep", "sixbar_g", "--from", from, "--to", to, "--step", "10",
        ];
        let out = mechgen(&[&args[..], &["--csv", csv.to_str().unwrap()]].concat());
        assert!(out.status.success(), "{}", text(&out.stderr));
        let rows = std::fs::read_to_string(&csv).expect("csv");
        let statuses: Vec<&str> = rows
            .lines()
            .skip(1)
            .map(|l| l.rsplit(',').next().unwrap())
            .collect();
        assert_eq!(statuses, vec!["ok"; 9], "{rows}");
    }
}

/// Issue 18 item 7: the main job sweeps a length input over the start's branch between its dead
/// points (from the branch analysis), not start ± a quarter of the length scale. The trammel's
/// dead points are at sx = ±L/sin(30°) = ±0.52 (law of sines, independent of the code): its rows
/// run from just above -0.52 to just below 0.52, every one solved.
#[test]
fn the_main_job_sweeps_a_length_input_between_its_dead_points() {
    let dir = temp("main-length");
    std::fs::create_dir_all(&dir).expect("dir");
    let file = support::data("trammel.toml");
    let out = Command::new(env!("CARGO_BIN_EXE_mechgen"))
        .args(["--file", file.to_str().expect("utf-8")])
        .current_dir(&dir)
        .output()
        .expect("runs");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let t = Table::read(dir.join("mechgen-out/trammel.csv").to_str().unwrap());
    let dead = 0.26 / 30f64.to_radians().sin();
    let inputs: Vec<f64> = t.rows.iter().map(|r| r[0].parse().unwrap()).collect();
    assert_eq!(inputs.len(), 37);
    assert!(
        (inputs[0] + dead).abs() < 1e-5 && inputs[0] > -dead,
        "{}",
        inputs[0]
    );
    assert!(
        (inputs[36] - dead).abs() < 1e-5 && inputs[36] < dead,
        "{}",
        inputs[36]
    );
    assert!(t.rows.iter().all(|r| r.last().is_some_and(|s| s == "ok")));
}

/// Issue 18 item 7: lengths whose squares overflow (1e299; `check` warns about them) give rows
/// with the status `overflow`, not a dead point with an infinite condition estimate.
#[test]
fn rows_of_lengths_whose_squares_overflow_say_overflow() {
    let csv = temp("huge.csv");
    let out = mechgen(&[
        "sweep",
        "four_bar",
        "--file",
        "tests/diagnostics/huge_lengths.toml",
        "--to",
        "30",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table = text(&out.stdout);
    assert!(!table.contains("dead point"), "{table}");
    let rows = std::fs::read_to_string(&csv).expect("csv");
    let statuses: Vec<&str> = rows
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap())
        .collect();
    assert_eq!(statuses, ["overflow"; 4], "{rows}");
}

/// The dead-point refinement on the command line's path: `sweep` of one row 1e-6° inside each of
/// `sixbar_g`'s dead points (its 4×4 Newton block at condition ~6e3), and `batch` of the same row,
/// on both engines, against the 30-digit reference at exactly the input the command line reaches
/// from that degree value (`tests/data/stress/sixbar_g_cli.csv`, mpmath, closed form in the crank
/// angle). Positions to 1e-15, velocities to 5e-9, accelerations to 1e-8 of their largest value
/// (without the refinement: ~1e-7).
#[test]
fn the_refinement_holds_on_the_command_lines_path_near_a_dead_point() {
    let reference = Table::read(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/stress/sixbar_g_cli.csv")
            .to_str()
            .expect("utf-8"),
    );
    let sets = temp("refine-sets.csv");
    std::fs::write(&sets, "l1\n26.5\n").expect("sets");
    let groups = [
        ["q1", "q2", "q3", "q5"],
        ["q1_vel", "q2_vel", "q3_vel", "q5_vel"],
        ["q1_acc", "q2_acc", "q3_acc", "q5_acc"],
    ];
    let bounds = [1e-15, 5e-9, 1e-8];
    for row in &reference.rows {
        let deg = row[1].as_str();
        for engine in ["generated", "generic"] {
            for command in ["sweep", "batch"] {
                let csv = temp(&format!("refine-{engine}-{command}-{}.csv", row[0]));
                let path = csv.to_str().expect("utf-8");
                let mut args = vec![command, "sixbar_g", "--from", deg, "--to", deg];
                args.extend(["--engine", engine, "--csv", path]);
                if command == "batch" {
                    args.extend(["--params", sets.to_str().expect("utf-8")]);
                }
                let out = mechgen(&args);
                assert!(out.status.success(), "{args:?}: {}", text(&out.stderr));
                let got = Table::read(path);
                assert_eq!(got.rows.len(), 1, "{args:?}");
                let cell = |t: &Table, r: &[String], name: &str| -> f64 {
                    let i = t.header.iter().position(|h| h == name).expect(name);
                    r[i].parse()
                        .unwrap_or_else(|_| panic!("{name} = {:?}", r[i]))
                };
                let status = got.rows[0].last().expect("status");
                assert_eq!(status, "ok", "{args:?}");
                let input = cell(&got, &got.rows[0], "q6");
                assert_eq!(
                    input,
                    cell(&reference, row, "q6"),
                    "{args:?}: the same input"
                );
                for (names, bound) in groups.iter().zip(bounds) {
                    let scale = names
                        .iter()
                        .map(|n| cell(&reference, row, n).abs())
                        .fold(0.0, f64::max);
                    for n in names {
                        let e = (cell(&got, &got.rows[0], n) - cell(&reference, row, n)).abs();
                        assert!(e <= bound * scale, "{args:?}: {n} off by {:e}", e / scale);
                    }
                }
            }
        }
    }
}

/// Each row's status (input in column `col`) against the geometry: `ok` or `other-branch` where
/// the linkage assembles (`assembles` of the input), `unassemblable` where it does not; and each
/// of the three seen at least once.
fn check_statuses(rows: &[Vec<String>], col: usize, assembles: &dyn Fn(f64) -> bool, what: &str) {
    let mut seen = [0; 3];
    for r in rows {
        let x: f64 = r[col].parse().expect("input");
        let status = r.last().expect("status").as_str();
        let want = match (status, assembles(x)) {
            ("ok", true) => 0,
            ("other-branch", true) => 1,
            ("unassemblable", false) => 2,
            (s, a) => panic!("{what}: {s} at {} deg (assembles: {a})", x.to_degrees()),
        };
        seen[want] += 1;
    }
    assert!(seen.iter().all(|&n| n > 0), "{what}: {seen:?}");
}

/// Statuses past the dead point that ends the followed branch tell the truth: `other-branch` where
/// the linkage assembles all the same, `unassemblable` where it does not, against the geometry
/// (the Peaucellier assembles where |OC| = 2a|cos(q1/2)| ≥ L − s; the triple-rocker where
/// |BD| ≤ b + c), in `sweep` (the default full turn) and `batch` (each set with its own a).
#[test]
fn rows_past_the_branch_end_are_other_branch_where_the_linkage_assembles() {
    let peaucellier =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/peaucellier.toml");
    let pf = peaucellier.to_str().expect("utf-8");
    // The Peaucellier (a = 1, L = 3, s = 1.5), a full turn from its start at 0.
    let csv = temp("other-branch-peaucellier.csv");
    let out = mechgen(&[
        "sweep",
        "peaucellier",
        "--file",
        pf,
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("other-branch: the linkage assembles here, on another branch"),
        "{}",
        text(&out.stdout)
    );
    let t = Table::read(csv.to_str().unwrap());
    let reach = |a: f64| move |x: f64| 2.0 * a * (x / 2.0).cos().abs() >= 1.5 - 1e-12;
    check_statuses(&t.rows, 0, &reach(1.0), "peaucellier");
    // The triple-rocker (a, b, c, d = 0.3, 0.35, 0.3, 0.4), compiled in.
    let csv = temp("other-branch-rocker.csv");
    let out = mechgen(&["sweep", "rocker_four_bar", "--csv", csv.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let t = Table::read(csv.to_str().unwrap());
    let rocker = |x: f64| (0.3f64 * x.cos() - 0.4).hypot(0.3 * x.sin()) <= 0.65 + 1e-12;
    check_statuses(&t.rows, 0, &rocker, "rocker_four_bar");
    // A batch: each set's own linkage (a = 0.9 reaches |q1| ≤ 2 acos(1.5/1.8)).
    let sets = temp("other-branch-sets.csv");
    std::fs::write(&sets, "a\n1.0\n0.9\n").expect("sets");
    let csv = temp("other-branch-batch.csv");
    let args = [
        "batch",
        "peaucellier",
        "--file",
        pf,
        "--params",
        sets.to_str().unwrap(),
    ];
    let out = mechgen(&[&args[..], &["--csv", csv.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let t = Table::read(csv.to_str().unwrap());
    for (set, a) in [("0", 1.0), ("1", 0.9)] {
        let rows: Vec<Vec<String>> = t.rows.iter().filter(|r| r[0] == set).cloned().collect();
        check_statuses(&rows, 1, &reach(a), &format!("batch set {set}"));
    }
}

/// A one-angle block's dead point ends the branch as an RRR's does (its pivot ratio is the sine
/// of the link's angle from its dead position, not the 1 of a 1×1 elimination, which hid the
/// dead point: every row past it read `unassemblable`, found 2026-11-30): the quick return
/// (`tests/data/quick_return.toml`) assembles where |yr − L sin φ| ≤ l5, φ the lever's angle
/// atan2(h + r sin θ, r cos θ); past its dead point at 224.2° the rows at 270° and from 320° on
/// are `other-branch`, the rest `unassemblable`, in both run-time engines and in a batch.
#[test]
fn a_one_angle_blocks_dead_point_ends_the_branch() {
    let file =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/quick_return.toml");
    let f = file.to_str().expect("utf-8");
    let assembles = |h: f64, r: f64, yr: f64| {
        move |th: f64| {
            let phi = (h + r * th.sin()).atan2(r * th.cos());
            (yr - 2.0 * phi.sin()).abs() <= 1.2 + 1e-12
        }
    };
    for engine in ["jit", "generic"] {
        let csv = temp(&format!("quick-return-{engine}.csv"));
        let args = ["sweep", "quick_return", "--file", f, "--engine", engine];
        let out = mechgen(&[&args[..], &["--csv", csv.to_str().unwrap()]].concat());
        assert!(out.status.success(), "{}", text(&out.stderr));
        assert!(
            text(&out.stdout).contains("dead point near th = 224.2070 deg"),
            "{}",
            text(&out.stdout)
        );
        let t = Table::read(csv.to_str().unwrap());
        check_statuses(&t.rows, 0, &assembles(1.0, 0.99, 2.0), engine);
    }
    // Each set its own linkage (r = 0.9, yr = 2.1: no assembly at 240°, 250°, 290°, 300° only).
    let sets = temp("quick-return-sets.csv");
    std::fs::write(&sets, "r,yr\n0.99,2.0\n0.9,2.1\n").expect("sets");
    let csv = temp("quick-return-batch.csv");
    let args = ["batch", "quick_return", "--file", f, "--params"];
    let out = mechgen(
        &[
            &args[..],
            &[sets.to_str().unwrap(), "--csv", csv.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let t = Table::read(csv.to_str().unwrap());
    for (set, r, yr) in [("0", 0.99, 2.0), ("1", 0.9, 2.1)] {
        let rows: Vec<Vec<String>> = t.rows.iter().filter(|row| row[0] == set).cloned().collect();
        check_statuses(
            &rows,
            1,
            &assembles(1.0, r, yr),
            &format!("batch set {set}"),
        );
    }
}

/// A dead point of a 1×1 block solved by Newton ends the branch too (the whole Jacobian's
/// condition estimate where the walk stops, since the block's own pivot ratio is 1 everywhere):
/// `tests/data/geared.toml` assembles where |a sin θ| ≤ b, and past its dead point at 36.87° the
/// rows are `other-branch` there and `unassemblable` elsewhere, in both run-time engines.
#[test]
fn a_newton_1x1_blocks_dead_point_ends_the_branch() {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/geared.toml");
    let f = file.to_str().expect("utf-8");
    for engine in ["jit", "generic"] {
        let csv = temp(&format!("geared-{engine}.csv"));
        let args = ["sweep", "geared", "--file", f, "--engine", engine];
        let out = mechgen(&[&args[..], &["--csv", csv.to_str().unwrap()]].concat());
        assert!(out.status.success(), "{}", text(&out.stderr));
        assert!(
            text(&out.stdout).contains("dead point near th = 36.86990 deg"),
            "{}",
            text(&out.stdout)
        );
        let t = Table::read(csv.to_str().unwrap());
        check_statuses(&t.rows, 0, &|th: f64| th.sin().abs() <= 0.6 + 1e-12, engine);
    }
}
