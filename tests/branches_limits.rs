//! The branch analysis on a chain of four-bars in series, each driven by the one before (2ⁿ
//! configurations at an input for n of them): listing them stops past
//! `MAX_CONFIGURATIONS` with an error that names the limit, in the library and on the command
//! line, at once instead of filling the memory (a chain of sixteen took 24 GB and was killed,
//! found 2026-11-30); whether the linkage assembles is still answered (depth first), against the
//! first four-bar's geometry.

mod common;

use std::f64::consts::TAU;

use mechgen::branches::{MAX_CONFIGURATIONS, Setup};
use mechgen_codegen::SourceFile;

/// The first four-bar's crank, coupler, rocker and ground: its coupler and rocker close only
/// where `|b − c| ≤ |BD| ≤ b + c`, `|BD|` the distance from the crank pin to the rocker's pivot.
const FIRST: [f64; 4] = [1.0, 1.5, 1.5, 3.2];

fn assembles_first(t: f64) -> bool {
    let [a, b, c, d] = FIRST;
    let bd = (d - a * t.cos()).hypot(a * t.sin());
    (b - c).abs() <= bd && bd <= b + c
}

/// `n` four-bars in series (the rocker angle of each the crank angle of the next; the first's
/// crank the input `t`), started at `t0` on one of their assemblies (solved here by the cosine
/// rule).
fn chain(n: usize, t0: f64) -> String {
    let (mut unknowns, mut loops, mut params, mut start) = (vec![], vec![], vec![], vec![]);
    let (mut prev, mut angle) = ("t".to_string(), t0);
    start.push(format!("t = {t0:?}"));
    for i in 0..n {
        let [a, b, c, d] = if i == 0 {
            FIRST
        } else {
            [1.0, 3.0 + 0.1 * i as f64, 2.5 + 0.05 * i as f64, 3.2]
        };
        params.push(format!(
            "a{i} = {a:?}\nb{i} = {b:?}\nc{i} = {c:?}\nd{i} = {d:?}"
        ));
        loops.push(format!(
            "\"a{i}*e({prev}) + b{i}*e(u{i}) - d{i} - c{i}*e(v{i})\""
        ));
        unknowns.push(format!("\"u{i}\", \"v{i}\""));
        let (bx, by) = (a * angle.cos(), a * angle.sin());
        let (ex, ey) = (d - bx, -by);
        let l = ex.hypot(ey);
        let u = ey.atan2(ex) + ((b * b + l * l - c * c) / (2.0 * b * l)).acos();
        let v = (by + b * u.sin()).atan2(bx + b * u.cos() - d);
        start.push(format!("u{i} = {u:?}\nv{i} = {v:?}"));
        (prev, angle) = (format!("v{i}"), v);
    }
    format!(
        "[mechanism.chain]\ninputs = [\"t\"]\nunknowns = [{}]\nloops = [{}]\n\
         [mechanism.chain.params]\n{}\n[mechanism.chain.start]\n{}\n",
        unknowns.join(", "),
        loops.join(", "),
        params.join("\n"),
        start.join("\n")
    )
}

fn setup(text: &str) -> Setup {
    let (compiled, diags) = mechgen_codegen::analyze(&SourceFile::new("chain.toml", text));
    assert!(!diags.iter().any(|d| d.is_error()), "{diags:?}");
    Setup::new(&compiled[0], 0).expect("setup")
}

#[test]
fn a_long_chain_is_refused_and_still_answers_whether_it_assembles() {
    // Twelve four-bars: 4096 configurations where every one closes.
    let s = setup(&chain(12, 0.3));
    let listed = s.configurations(0.3).expect_err("more than the limit");
    assert!(
        listed.contains(&format!(
            "over {MAX_CONFIGURATIONS} assembly configurations"
        )),
        "{listed}"
    );
    let analysed = s.analyze(0.0, TAU, &[]).expect_err("more than the limit");
    assert!(
        analysed.contains("more than the branch analysis follows"),
        "{analysed}"
    );
    let (mut yes, mut no) = (0, 0);
    for k in 0..72 {
        let t = k as f64 * 5f64.to_radians();
        let first = assembles_first(t);
        // Past the first four-bar's reach nothing closes; within it, every later four-bar
        // (Grashof, its crank turning fully) closes in both of its modes.
        assert_eq!(s.assembles(&[t]), Some(first), "t = {k}·5°");
        if first { yes += 1 } else { no += 1 }
    }
    assert!(yes > 0 && no > 0, "{yes} {no}");
    // Four four-bars (16 configurations) are listed: two per block where it closes.
    let s = setup(&chain(4, 0.3));
    for k in 0..72 {
        let t = k as f64 * 5f64.to_radians();
        let n = s.configurations(t).expect("listed").len();
        assert_eq!(n, if assembles_first(t) { 16 } else { 0 }, "t = {k}·5°");
    }
}

#[cfg(feature = "cli")]
#[test]
fn branches_says_so_on_the_command_line() {
    use common::cli::{TempDir, mechgen, text};
    let d = TempDir::new("branches-limit");
    let file = d.join("chain.toml");
    std::fs::write(&file, chain(16, 0.3)).expect("file");
    let f = file.to_str().expect("utf-8");
    let out = mechgen(&["branches", "chain", "--file", f]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("over 256 assembly configurations by block 8"),
        "{err}"
    );
    // The sweep follows its branch all the same.
    let csv = d.join("chain.csv");
    let out = mechgen(&[
        "sweep",
        "chain",
        "--file",
        f,
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
}
