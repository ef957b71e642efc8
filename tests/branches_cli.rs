//! `mechgen branches NAME` (interfaces.md): the summary, the four CSV files with their exact
//! columns and consistent labels, crossings, the plot, `--file` with a length input, and the errors.
#![cfg(feature = "cli")]

mod common;

use std::process::Output;

use common::cli::{TempDir, mechgen, text};

/// A fresh directory for `name`, removed after the test.
fn dir(name: &str) -> TempDir {
    TempDir::new(&format!("branches-{name}"))
}

#[test]
fn sixbar_g_summary_csv_and_plot() {
    let d = dir("g");
    let ds = d.to_str().unwrap();
    let out = mechgen(&[
        "branches", "sixbar_g", "--at", "280.67", "--at", "-100", "--at", "0", "--csv", ds,
        "--plot", ds,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("2 circuit(s), 6 branch(es), 6 dead point(s)"),
        "{text}"
    );
    assert!(
        text.contains("at q6 = 0.0000000000 deg: 0 configuration(s)"),
        "{text}"
    );
    let read = |f: &str| std::fs::read_to_string(d.join(f)).unwrap();
    let dead = read("sixbar_g-dead-points.csv");
    assert!(dead.starts_with("input,q1,q2,q3,q5,circuit\n"));
    assert_eq!(dead.lines().count(), 7);
    let branches = read("sixbar_g-branches.csv");
    assert!(branches.starts_with("branch,circuit,input_from,input_to,full_turn\n"));
    assert_eq!(branches.lines().count(), 7);
    // No crossing: the header alone.
    assert_eq!(
        read("sixbar_g-crossings.csv"),
        "input,q1,q2,q3,q5,branches\n"
    );
    let at = read("sixbar_g-at.csv");
    assert!(at.starts_with("input,q1,q2,q3,q5,circuit,branch\n"));
    // 2 configurations at 280.67°, 4 at −100°, none at 0°.
    assert_eq!(at.lines().count(), 7);
    // Each `at` row's circuit is its branch's circuit in branches.csv.
    let circuit_of: Vec<String> = branches
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().to_string())
        .collect();
    for l in at.lines().skip(1) {
        let f: Vec<&str> = l.split(',').collect();
        let b: usize = f[6].parse().unwrap();
        assert_eq!(circuit_of[b], f[5]);
    }
    for text in [&dead, &branches, &at] {
        assert!(!text.contains("NaN") && !text.contains("inf"));
    }
    let svg = read("sixbar_g-branches.svg");
    assert!(svg.starts_with("<svg") && svg.contains("branch 5 (circuit 1)"));
}

#[test]
fn length_input_through_file_and_errors() {
    let d = dir("len");
    let file = d.join("slid.toml");
    std::fs::write(
        &file,
        "[mechanism.slid]\ninputs = [\"sC\"]\nunknowns = [\"q1\", \"q2\"]\n\
         loops = [\"r*e(q1) + l*e(q2) - sC - c(0, off)\"]\n\
         params = { r = 0.05, l = 0.2, off = 0.02 }\nstart = { sC = 0.2, q1 = 1.6, q2 = -0.15 }\n",
    )
    .unwrap();
    let f = file.to_str().unwrap();
    let out = mechgen(&[
        "branches", "slid", "--file", f, "--from", "-0.3", "--to", "0.3", "--at", "0.2",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("2 circuit(s), 4 branch(es), 4 dead point(s)"),
        "{text}"
    );
    // A length input needs its range; a name that is not there; generated with --file.
    assert!(!mechgen(&["branches", "slid", "--file", f]).status.success());
    assert!(!mechgen(&["branches", "nothing"]).status.success());
    assert!(
        !mechgen(&["branches", "slid", "--file", f, "--engine", "generated"])
            .status
            .success()
    );
    assert!(
        !mechgen(&["branches", "four_bar", "--from", "10", "--to", "5"])
            .status
            .success()
    );
    // Both engines give the same analysis for a compiled-in mechanism.
    let a = mechgen(&["branches", "rocker_four_bar", "--engine", "generated"]);
    let b = mechgen(&["branches", "rocker_four_bar", "--engine", "generic"]);
    let strip = |o: &Output| {
        String::from_utf8_lossy(&o.stdout)
            .lines()
            .filter(|l| !l.starts_with("(analysis"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(strip(&a), strip(&b));
}

/// A four-bar that assembles over q1 ∈ [0.04°, 0.46°] only (inside one cell of the grid).
#[test]
fn narrow_circuit_through_the_cli() {
    let f = format!(
        "{}/tests/data/branches/narrow.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let out = mechgen(&["branches", "--file", &f, "narrow", "--at", "0.25"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("1 circuit(s), 2 branch(es), 2 dead point(s)"),
        "{text}"
    );
    assert!(
        text.contains("at q1 = 0.2500000000 deg: 2 configuration(s)"),
        "{text}"
    );
}

/// Issue 18 item 7: `branches SCENE` names the scene's mechanism and the command to run, instead
/// of "no mechanism"; an unknown name still lists the file's mechanisms.
#[test]
fn a_scene_is_named_as_a_scene_of_its_mechanism() {
    let out = mechgen(&["branches", "sixbar_e_path"]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("`sixbar_e_path` is a scene of mechanism `sixbar`")
            && err.contains("mechgen branches sixbar"),
        "{err}"
    );
    let out = mechgen(&["branches", "nosuch"]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("no mechanism `nosuch` (the file has: sixbar"));
}

/// The toggle press of `tests/data/branches/crossings.toml`: its two crossings are printed and
/// written as crossings (not dead points), with the two branches that meet at each.
#[test]
fn toggle_press_crossings_csv() {
    let d = dir("press");
    let ds = d.to_str().unwrap();
    let file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/branches/crossings.toml"
    );
    let out = mechgen(&["branches", "press", "--file", file, "--csv", ds]);
    let text = format!("{}{}", text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("3 circuit(s), 4 branch(es), 0 dead point(s), 2 crossing(s)"),
        "{text}"
    );
    assert!(
        text.contains("crossing 0 (circuit 0): q1 = 76.33508"),
        "{text}"
    );
    let read = |f: &str| std::fs::read_to_string(d.join(f)).unwrap();
    assert_eq!(read("press-dead-points.csv").lines().count(), 1);
    let crossings = read("press-crossings.csv");
    let rows: Vec<Vec<&str>> = crossings.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(rows[0], ["input", "q2", "q3", "q4", "s", "branches"]);
    assert_eq!(rows.len(), 3, "{crossings}");
    for r in &rows[1..] {
        assert_eq!(r[5], "0;1", "{crossings}");
        // The knee B = (0, l): q3 = 90°, q4 = −90°, the slider at s = 0.
        let v: Vec<f64> = r[1..5].iter().map(|x| x.parse().unwrap()).collect();
        assert!((v[1] - std::f64::consts::FRAC_PI_2).abs() < 1e-9, "{r:?}");
        assert!((v[2] + std::f64::consts::FRAC_PI_2).abs() < 1e-9, "{r:?}");
        assert!(v[3].abs() < 1e-9, "{r:?}");
    }
}

/// The Peaucellier–Lipkin linkage: two of the four mode combinations of its first two dyads put B
/// on D (the third loop then has no size): `branches` names them and analyses the rest, two
/// circuits of two branches each, every one rocking between the dead points where
/// |OC| = 2a cos(q1/2) reaches L − s (a = 1, L = 3, s = 1.5: q1 = ±2 acos(0.75)).
#[test]
fn degenerate_modes_are_named_and_the_rest_analysed() {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/peaucellier.toml");
    let out = mechgen(&[
        "branches",
        "peaucellier",
        "--file",
        file.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let s = text(&out.stdout);
    assert!(s.contains("2 circuit(s), 4 branch(es)"), "{s}");
    let degenerate: Vec<&str> = s.lines().filter(|l| l.contains("degenerate:")).collect();
    assert_eq!(degenerate.len(), 2, "{s}");
    assert!(
        degenerate
            .iter()
            .all(|l| l.contains("makes block 2 degenerate")),
        "{s}"
    );
    let dead = (2.0 * 0.75f64.acos()).to_degrees();
    let range = format!(
        "q1 from {:.10} deg to {:.10} deg",
        360.0 - dead,
        360.0 + dead
    );
    let branches: Vec<&str> = s.lines().filter(|l| l.contains("  branch ")).collect();
    assert_eq!(branches.len(), 4, "{s}");
    assert!(branches.iter().all(|l| l.contains(&range)), "{range}\n{s}");
}

/// The branch CSVs write numbers as the sweep's CSV does (shortest round-trip, an exponent where
/// shorter): every cell parses back to a finite value and none spells out a run of zeros.
#[test]
fn branch_csv_numbers_are_shortest_round_trip() {
    // The parallelogram's crossings have q2 within rounding of 0 (1.8e-16 and the like).
    let d = dir("numbers");
    let file =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/odd-files/crossings.toml");
    let (f, o) = (file.to_str().unwrap(), d.to_str().unwrap());
    let out = mechgen(&[
        "branches",
        "parallelogram",
        "--file",
        f,
        "--csv",
        o,
        "--at",
        "0",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let crossings = std::fs::read_to_string(d.join("parallelogram-crossings.csv")).unwrap();
    assert_eq!(crossings.lines().count(), 3, "{crossings}");
    for name in ["dead-points", "branches", "crossings", "at"] {
        let path = d.join(format!("parallelogram-{name}.csv"));
        let Ok(body) = std::fs::read_to_string(&path) else {
            continue;
        };
        for line in body.lines().skip(1) {
            for cell in line.split(',') {
                assert!(!cell.contains("00000000"), "{name}: {cell} in {line}");
                if let Ok(v) = cell.parse::<f64>() {
                    assert!(v.is_finite(), "{name}: {line}");
                }
            }
        }
    }
}

/// `--input` and `--set` as for `sweep`: the two-input five-bar analysed along q4 with q1 held at
/// 60° has two full-turn branches, and the sweep of the same along q4 solves every row of a turn
/// on its start's branch; `--set` of the analysed input and an unknown input are errors naming
/// them.
#[test]
fn input_and_set_choose_the_input_analysed() {
    let file =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/sweep/fivebar.toml");
    let f = file.to_str().unwrap();
    let out = mechgen(&[
        "branches", "fivebar", "--file", f, "--input", "q4", "--set", "q1=60",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let s = text(&out.stdout);
    assert!(s.contains("fivebar: branches along q4 over a full turn: 2 circuit(s), 2 branch(es), 0 dead point(s)"), "{s}");
    let sweep = mechgen(&[
        "sweep", "fivebar", "--file", f, "--input", "q4", "--set", "q1=60",
    ]);
    assert!(sweep.status.success());
    let rows = text(&sweep.stdout);
    assert!(
        !rows.contains("unassemblable") && !rows.contains("other-branch"),
        "{rows}"
    );
    let bad = mechgen(&[
        "branches", "fivebar", "--file", f, "--input", "q4", "--set", "q4=60",
    ]);
    assert!(!bad.status.success());
    assert!(
        text(&bad.stderr).contains("`q4` is the input analysed along"),
        "{}",
        text(&bad.stderr)
    );
    let bad = mechgen(&["branches", "fivebar", "--file", f, "--input", "q9"]);
    assert!(!bad.status.success());
    assert!(
        text(&bad.stderr).contains("has no input `q9` (its inputs: q1, q4)"),
        "{}",
        text(&bad.stderr)
    );
}
