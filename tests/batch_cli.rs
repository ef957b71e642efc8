//! `mechgen batch NAME --params SETS.csv` (interfaces.md): every set's rows equal a `sweep` of a
//! file with that set's params (both engines), the summary equals what its rows say, the output
//! does not depend on the threads, errors name FILE:LINE, and memory does not grow with the rows.
#![cfg(feature = "cli")]

mod common;

use common::cli::{mechgen, temp, text};

/// The compiled-in file's `four_bar` section with its params replaced by `params`.
fn four_bar_file(params: &[(&str, f64)]) -> String {
    let src = mechgen::source::SOURCE;
    let start = src.find("[mechanism.four_bar]").expect("four_bar");
    // Up to the next table that is not one of four_bar's own.
    let end = src[start..]
        .match_indices("\n[")
        .map(|(i, _)| start + i)
        .find(|&i| !src[i + 1..].starts_with("[mechanism.four_bar"))
        .unwrap_or(src.len());
    let mut out = String::new();
    for line in src[start..end].lines() {
        let key = line.split('=').next().unwrap_or("").trim();
        match params.iter().find(|(n, _)| *n == key) {
            Some((n, v)) => out.push_str(&format!("{n} = {v:?}\n")),
            None => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    out
}

fn run_ok(args: &[&str]) -> String {
    let out = mechgen(args);
    assert!(out.status.success(), "{args:?}: {}", text(&out.stderr));
    text(&out.stdout)
}

/// Numbers of a CSV row after its first `skip` fields (the status and empty cells as text).
fn fields(line: &str, skip: usize) -> Vec<String> {
    line.split(',').skip(skip).map(String::from).collect()
}

fn close(a: &[String], b: &[String], tol: f64) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(u), Ok(v)) => (u - v).abs() <= tol * u.abs().max(1.0),
                _ => x == y,
            })
}

const SETS: [[f64; 2]; 3] = [[0.1, 0.35], [0.12, 0.33], [0.3, 0.1]];

/// Runs `mechgen batch NAME` over [`SETS`] in 15° rows twice: compiled in (with `--summary`) and
/// on `file` (a copy of the compiled-in file's section, one thread); its stdout, then the two CSVs'
/// text and the summary's.
fn batch_both(name: &str, file: &str, tag: &str) -> (String, String, String, String) {
    let sets = temp("batch", &format!("{tag}-sets.csv"));
    let mut body = String::from("l1, l2\n");
    for s in SETS {
        body.push_str(&format!("{},{}\n", s[0], s[1]));
    }
    std::fs::write(&sets, body).unwrap();
    let base = temp("batch", &format!("{tag}.toml"));
    std::fs::write(&base, file).unwrap();
    let (gen_csv, gen_sum, file_csv) = (
        temp("batch", &format!("{tag}-gen.csv")),
        temp("batch", &format!("{tag}-gen-summary.csv")),
        temp("batch", &format!("{tag}-file.csv")),
    );
    let p = |x: &std::path::Path| x.to_str().unwrap().to_string();
    let said = run_ok(&[
        "batch",
        name,
        "--params",
        &p(&sets),
        "--step",
        "15",
        "--csv",
        &p(&gen_csv),
        "--summary",
        &p(&gen_sum),
    ]);
    run_ok(&[
        "batch",
        name,
        "--file",
        &p(&base),
        "--params",
        &p(&sets),
        "--step",
        "15",
        "--csv",
        &p(&file_csv),
        "--threads",
        "1",
    ]);
    let read = |f: &std::path::Path| std::fs::read_to_string(f).unwrap();
    (said, read(&gen_csv), read(&file_csv), read(&gen_sum))
}

/// Each set's rows of a batch of `name` over [`SETS`] (the CSV lines compiled in and on a file)
/// held to `mechgen sweep NAME` of the set's own file (`file_of`): bit for bit on the file's
/// engine, to 1e-12 compiled in; a set whose file is refused (its start does not assemble) has
/// `unassemblable` on every row. The rows compared, and the rows not `ok`.
fn compare_sets(
    name: &str,
    (gen_lines, file_lines): (&[&str], &[&str]),
    file_of: impl Fn([f64; 2]) -> String,
) -> (usize, usize) {
    let p = |x: &std::path::Path| x.to_str().unwrap().to_string();
    let (mut compared, mut failed) = (0, 0);
    for (k, s) in SETS.iter().enumerate() {
        let f = temp("batch", &format!("{name}-set{k}.toml"));
        std::fs::write(&f, file_of(*s)).unwrap();
        let csv = temp("batch", &format!("{name}-set{k}.csv"));
        let out = mechgen(&[
            "sweep",
            name,
            "--file",
            &p(&f),
            "--step",
            "15",
            "--csv",
            &p(&csv),
        ]);
        if !out.status.success() {
            // Its start does not assemble (the file is refused): in the batch, that status on
            // every row of the set.
            assert_eq!(k, 2, "{}", text(&out.stderr));
            assert!(
                gen_lines[1 + 25 * k..1 + 25 * (k + 1)]
                    .iter()
                    .all(|l| l.ends_with(",unassemblable")),
                "set {k}"
            );
            failed += 25;
            continue;
        }
        let sweep = std::fs::read_to_string(&csv).unwrap();
        for (i, row) in sweep.lines().skip(1).enumerate() {
            let line = 1 + 25 * k + i;
            assert!(gen_lines[line].starts_with(&format!("{k},")));
            // The file's engine's batch row is the sweep's row, bit for bit.
            assert_eq!(
                fields(file_lines[line], 1),
                fields(row, 0),
                "set {k} row {i}"
            );
            // The generated engine's to 1e-12.
            assert!(
                close(&fields(gen_lines[line], 1), &fields(row, 0), 1e-12),
                "set {k} row {i}:\n{}\n{row}",
                gen_lines[line]
            );
            compared += 1;
            failed += usize::from(!row.ends_with(",ok"));
        }
    }
    (compared, failed)
}

#[test]
fn every_set_equals_a_sweep_with_its_params_on_both_engines() {
    let (said, generated, file, summary) = batch_both("four_bar", &four_bar_file(&[]), "mech");
    assert!(said.contains("3 param set(s) over 25 rows each"), "{said}");
    let (gen_lines, file_lines): (Vec<&str>, Vec<&str>) =
        (generated.lines().collect(), file.lines().collect());
    assert!(
        gen_lines[0].starts_with("set,q1,q2,q3,"),
        "{}",
        gen_lines[0]
    );
    assert_eq!(gen_lines.len(), 1 + 3 * 25);
    assert_eq!(file_lines.len(), gen_lines.len());
    let (_, failed) = compare_sets("four_bar", (&gen_lines, &file_lines), |s| {
        four_bar_file(&[("l1", s[0]), ("l2", s[1])])
    });
    // The third set (l1 = 0.3, l2 = 0.1) does not close on every row.
    assert!(failed > 0);
    // The summary: counts and extremes as the rows say.
    let head: Vec<&str> = summary.lines().next().unwrap().split(',').collect();
    assert_eq!(
        head[..6],
        [
            "set",
            "ok_rows",
            "failed_rows",
            "first_failure",
            "q2_min",
            "q2_max"
        ]
    );
    for (k, line) in summary.lines().skip(1).enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        let rows: Vec<&&str> = gen_lines[1 + 25 * k..1 + 25 * (k + 1)].iter().collect();
        let ok: Vec<Vec<&str>> = rows
            .iter()
            .filter(|r| r.ends_with(",ok"))
            .map(|r| r.split(',').collect())
            .collect();
        assert_eq!(f[0], k.to_string());
        assert_eq!(f[1], ok.len().to_string());
        assert_eq!(f[2], (25 - ok.len()).to_string());
        if !ok.is_empty() {
            // q2 is CSV column 2 (after `set` and `q1`).
            let q2: Vec<f64> = ok.iter().map(|r| r[2].parse().unwrap()).collect();
            let min = q2.iter().copied().fold(f64::INFINITY, f64::min);
            assert_eq!(f[4].parse::<f64>().unwrap(), min, "set {k}");
        }
    }
}

#[test]
fn threads_do_not_change_the_output() {
    let sets = temp("batch-threads", "sets.csv");
    let mut body = String::from("l1,l3\n");
    for i in 0..600 {
        body.push_str(&format!("{},{}\n", 0.08 + 1e-4 * f64::from(i), 0.3));
    }
    std::fs::write(&sets, body).unwrap();
    let (a, b) = (
        temp("batch-threads", "a.csv"),
        temp("batch-threads", "b.csv"),
    );
    let p = |x: &std::path::Path| x.to_str().unwrap().to_string();
    for (csv, threads) in [(&a, "1"), (&b, "2")] {
        run_ok(&[
            "batch",
            "four_bar",
            "--params",
            &p(&sets),
            "--step",
            "30",
            "--csv",
            &p(csv),
            "--threads",
            threads,
        ]);
    }
    let (a, b) = (
        std::fs::read_to_string(&a).unwrap(),
        std::fs::read_to_string(&b).unwrap(),
    );
    assert_eq!(a.lines().count(), 1 + 600 * 13);
    assert!(a == b, "the CSV depends on the threads");
}

/// `MECHGEN_LANES` chooses how many sets go side by side in SIMD lanes (1: none, every set by
/// the scalar sweep; 4; 8): the CSV is the same bytes whatever it says (a six-bar's sets, some
/// meeting a dead point inside the range, so that sets leave the lanes too).
#[test]
fn the_lane_width_does_not_change_the_output() {
    let sets = temp("batch-lanes-var", "sets.csv");
    let mut body = String::from("l2,l3\n");
    for i in 0..37 {
        let f = 1.0 + 0.02 * (f64::from(i) / 18.0 - 1.0);
        body.push_str(&format!("{},{}\n", 75.0 * f, 59.0 / f));
    }
    std::fs::write(&sets, body).unwrap();
    let p = |x: &std::path::Path| x.to_str().unwrap().to_string();
    let mut outputs = Vec::new();
    for lanes in ["1", "4", "8", "default"] {
        let csv = temp("batch-lanes-var", &format!("{lanes}.csv"));
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_mechgen"));
        cmd.args([
            "batch",
            "sixbar",
            "--params",
            &p(&sets),
            "--step",
            "10",
            "--csv",
            &p(&csv),
        ]);
        cmd.env_remove(mechgen::batch::lanes::LANES_VAR);
        if lanes != "default" {
            cmd.env(mechgen::batch::lanes::LANES_VAR, lanes);
        }
        let out = cmd.output().unwrap();
        assert!(out.status.success(), "{lanes}: {}", text(&out.stderr));
        outputs.push((lanes, std::fs::read_to_string(&csv).unwrap()));
    }
    let (_, first) = &outputs[0];
    assert!(
        first.lines().count() > 37 * 30,
        "{} lines",
        first.lines().count()
    );
    for (lanes, csv) in &outputs[1..] {
        assert!(csv == first, "MECHGEN_LANES={lanes} changes the CSV");
    }
}

/// A range that ends at the start (1°…360° from a start at 0°: every row below the start row):
/// the lanes walk down from the start row and hand each row out as solved; the CSV still has
/// each set's rows in input order, each the generic engine's (scalar sweep) to 1e-12.
#[test]
fn rows_below_the_start_row_come_in_input_order() {
    let sets = temp("batch-down", "sets.csv");
    let mut body = String::from("l1,l3\n");
    for i in 0..9 {
        body.push_str(&format!("{},{}\n", 0.1 + 2e-3 * f64::from(i), 0.35));
    }
    std::fs::write(&sets, body).unwrap();
    let base = temp("batch-down", "four_bar.toml");
    std::fs::write(&base, four_bar_file(&[])).unwrap();
    let (lanes, file) = (
        temp("batch-down", "lanes.csv"),
        temp("batch-down", "file.csv"),
    );
    let p = |x: &std::path::Path| x.to_str().unwrap().to_string();
    for (csv, engine) in [(&lanes, None), (&file, Some(&base))] {
        let mut args = vec!["batch".to_string(), "four_bar".to_string()];
        if let Some(f) = engine {
            args.extend(["--file".to_string(), p(f)]);
        }
        for a in [
            "--params",
            &p(&sets),
            "--from",
            "1",
            "--to",
            "360",
            "--step",
            "1",
        ] {
            args.push(a.to_string());
        }
        args.extend(["--csv".to_string(), p(csv)]);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        run_ok(&args);
    }
    let (lanes, file) = (
        std::fs::read_to_string(&lanes).unwrap(),
        std::fs::read_to_string(&file).unwrap(),
    );
    let (a, b): (Vec<&str>, Vec<&str>) = (lanes.lines().collect(), file.lines().collect());
    assert_eq!(a.len(), 1 + 9 * 360);
    assert_eq!(a.len(), b.len());
    let input = |line: &str| fields(line, 1)[0].parse::<f64>().unwrap();
    for (k, (x, y)) in a.iter().zip(&b).enumerate().skip(1) {
        let (set, row) = ((k - 1) / 360, (k - 1) % 360);
        assert!(x.starts_with(&format!("{set},")), "line {k}: {x}");
        assert!(x.ends_with(",ok"), "line {k}: {x}");
        // Row `row` is at 1° + `row`° (radians in the CSV).
        let want = (1.0 + row as f64).to_radians();
        assert!((input(x) - want).abs() < 1e-12, "line {k}: {x}");
        assert!(
            close(&fields(x, 0), &fields(y, 0), 1e-12),
            "line {k}:\n{x}\n{y}"
        );
    }
}

#[test]
fn errors_name_the_file_and_line() {
    let p = |x: &std::path::Path| x.to_str().unwrap().to_string();
    for (body, want) in [
        ("l1,zz\n0.1,2\n", ":1: no param `zz` in `four_bar`"),
        ("l1\n0.1\nabc\n", ":3: `abc` for `l1` is not a number"),
        ("l1,l2\n0.1\n", ":2: 1 values for 2 params"),
        ("l1,l1\n0.1,0.1\n", ":1: param `l1` is named twice"),
    ] {
        let f = temp("batch-errors", "sets.csv");
        std::fs::write(&f, body).unwrap();
        let out = mechgen(&["batch", "four_bar", "--params", &p(&f)]);
        assert!(!out.status.success());
        let err = text(&out.stderr);
        assert!(err.contains(&format!("{}{want}", p(&f))), "{err}");
    }
}

/// A batch's memory does not grow with its rows: the six-bar's 2000 sets over 37 rows with both
/// CSVs (74 000 rows, about 29 MB of CSV) peak less than half the CSV's size above the same batch
/// of 10 sets (the process itself, its buffers and threads: 7 MB more, and 7.5 MB with 10 000
/// sets), where holding the rows would take about the CSV's size (300–400 bytes a row). (In a debug build each set costs milliseconds in lanes: 2000 sets keep
/// this test under ten seconds.)
#[test]
fn a_batch_keeps_its_memory_flat_as_rows_grow() {
    if !std::path::Path::new("/proc/self/status").exists() {
        return;
    }
    let peak_of = |sets: usize| -> (f64, usize, u64, usize) {
        let file = temp("batch-memory", &format!("sets{sets}.csv"));
        let mut body = String::from("l1\n");
        for i in 0..sets {
            body.push_str(&format!("{}\n", 25.0 + 3e-4 * i as f64));
        }
        std::fs::write(&file, body).unwrap();
        let (csv, summary) = (
            temp("batch-memory", &format!("rows{sets}.csv")),
            temp("batch-memory", &format!("sum{sets}.csv")),
        );
        let p = |x: &std::path::Path| x.to_str().unwrap().to_string();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_mechgen"))
            .args([
                "batch",
                "sixbar",
                "--params",
                &p(&file),
                "--csv",
                &p(&csv),
                "--summary",
                &p(&summary),
            ])
            .env("MECHGEN_PEAK_MEMORY", "1")
            .output()
            .expect("runs");
        assert!(out.status.success(), "{}", text(&out.stderr));
        let err = text(&out.stderr);
        let peak: f64 = err
            .lines()
            .find_map(|l| l.strip_prefix("mechgen: peak memory "))
            .expect("peak line")
            .trim_end_matches(" kB")
            .trim()
            .parse()
            .unwrap();
        let written = std::fs::read_to_string(&csv).unwrap();
        let rows = written.lines().count() - 1;
        let sums = std::fs::read_to_string(&summary).unwrap().lines().count() - 1;
        let _ = std::fs::remove_file(&csv);
        (peak, rows, written.len() as u64, sums)
    };
    let (small, small_rows, _, small_sums) = peak_of(10);
    let (large, rows, bytes, sums) = peak_of(2000);
    assert_eq!((small_rows, small_sums), (370, 10));
    assert_eq!((rows, sums), (74_000, 2000));
    let csv_kb = bytes as f64 / 1024.0;
    assert!(csv_kb > 20_000.0, "{csv_kb} kB of CSV");
    assert!(
        large - small < 0.5 * csv_kb,
        "peak {large} kB for 2000 sets against {small} kB for 10, with {csv_kb} kB of CSV"
    );
    assert!(large < 100_000.0, "peak {large} kB");
}

/// A value that is a number but not finite (`nan`, `inf`) fails its own set, not the batch: every
/// row of that set is `non-finite-input`, the others are swept as usual, and stderr names the
/// file, the line and the set.
#[test]
fn a_non_finite_value_fails_its_set_only() {
    let p = |x: &std::path::Path| x.to_str().unwrap().to_string();
    let sets = temp("batch-nan", "sets.csv");
    std::fs::write(&sets, "l1,l2\n0.1,0.35\nnan,0.35\n0.1,-inf\n0.11,0.35\n").unwrap();
    for engine in ["generated", "generic"] {
        let csv = temp("batch-nan", &format!("rows-{engine}.csv"));
        let out = mechgen(&[
            "batch",
            "four_bar",
            "--params",
            &p(&sets),
            "--step",
            "60",
            "--csv",
            &p(&csv),
            "--engine",
            engine,
        ]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let err = text(&out.stderr);
        for want in [
            ":3: set 1: `nan` for `l1` is not finite",
            ":4: set 2: `-inf` for `l2` is not finite",
        ] {
            assert!(err.contains(&format!("{}{want}", p(&sets))), "{err}");
        }
        let rows = std::fs::read_to_string(&csv).unwrap();
        for line in rows.lines().skip(1) {
            let set = line.split(',').next().unwrap();
            let status = line.rsplit(',').next().unwrap();
            let want = if set == "1" || set == "2" {
                "non-finite-input"
            } else {
                "ok"
            };
            assert_eq!(status, want, "{engine}: {line}");
        }
        assert_eq!(rows.lines().count(), 1 + 4 * 7);
    }
}

/// A batch too large to write is refused before anything is solved or written, naming its size;
/// the same batch without `--csv` starts, saying its size first.
#[test]
fn a_batch_too_large_for_its_csv_is_refused_naming_its_size() {
    let sets = temp("batch", "thirty.csv");
    let body: String = std::iter::once("l1\n".to_string())
        .chain((0..30).map(|_| "0.1\n".to_string()))
        .collect();
    std::fs::write(&sets, body).unwrap();
    let csv = temp("batch", "too-large.csv");
    let _ = std::fs::remove_file(&csv);
    let out = mechgen(&[
        "batch",
        "four_bar",
        "--params",
        sets.to_str().unwrap(),
        "--step",
        "1e-4",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("30 set(s) × 3600001 rows = 108000030 rows") && err.contains("--summary"),
        "{err}"
    );
    assert!(!csv.exists(), "nothing written");
}

/// The compiled-in file's `coupler_curve` scene (of `four_bar`), as a section of a file.
fn coupler_curve_scene() -> String {
    let src = mechgen::source::SOURCE;
    let start = src.find("[scene.coupler_curve]").expect("coupler_curve");
    let end = src[start + 1..]
        .find("\n[")
        .map_or(src.len(), |i| start + 1 + i);
    format!("\n{}\n", &src[start..end])
}

#[test]
fn a_scenes_sets_equal_a_scene_sweep_with_their_params() {
    let file = four_bar_file(&[]) + &coupler_curve_scene();
    let (said, generated, file, summary) = batch_both("coupler_curve", &file, "scene");
    assert!(
        said.starts_with("coupler_curve: 3 param set(s) over 25 rows each"),
        "{said}"
    );
    let (gen_lines, file_lines): (Vec<&str>, Vec<&str>) =
        (generated.lines().collect(), file.lines().collect());
    // The scene's columns (interfaces.md, "Scenes on the command line"), not its mechanism's.
    assert_eq!(
        gen_lines[0], "set,q1,P_x,P_y,P_vx,P_vy,cond,status",
        "the header"
    );
    assert_eq!(
        (gen_lines.len(), file_lines.len()),
        (1 + 3 * 25, 1 + 3 * 25)
    );
    let (compared, _) = compare_sets("coupler_curve", (&gen_lines, &file_lines), |s| {
        four_bar_file(&[("l1", s[0]), ("l2", s[1])]) + &coupler_curve_scene()
    });
    assert_eq!(compared, 50);
    // The summary counts the scene's rows.
    for (k, line) in summary.lines().skip(1).enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        let ok = gen_lines[1 + 25 * k..1 + 25 * (k + 1)]
            .iter()
            .filter(|r| r.ends_with(",ok"))
            .count();
        assert_eq!(
            (f[1], f[2]),
            (ok.to_string().as_str(), (25 - ok).to_string().as_str())
        );
    }
}
