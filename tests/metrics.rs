//! Design metrics (issue 22) against the textbook formulas, computed here from the file's params:
//! the shaper's quick return (tangent limits, sin β = AB/AC, time ratio (180° + 2β)/(180° − 2β))
//! and ram stroke; the crank-rocker's rocker swing, limit positions (crank and coupler
//! collinear), time ratio and transmission-angle extremes (cos μ = (b² + c² − (d ∓ a)²) / 2bc);
//! both engines alike (1e-12); an output that does not vary, an input that cannot complete a turn
//! (extremes at the dead point, against the 80-digit reference), a mechanism with no RRR block.
#![cfg(feature = "cli")]

mod common;

use std::f64::consts::{PI, TAU};

use common::cli::{mechgen, text};
use mechgen::metrics::{OutputMetrics, metrics, rrr_links};
use mechgen::{DynMechanism, MechanismInfo};

/// The compiled file's analysis of mechanism `name`.
fn compiled(name: &str) -> mechgen_codegen::Compiled {
    let file = mechgen_codegen::SourceFile::new("mechanism.toml", mechgen::source::SOURCE);
    let (c, _) = mechgen_codegen::analyze(&file);
    c.into_iter()
        .find(|c| c.model.name.text == name)
        .expect("mechanism")
}

/// Metrics over a full turn from the start (720 rows), on the generated and the generic engine.
fn both(name: &str) -> (MechanismInfo, Vec<OutputMetrics>, Vec<OutputMetrics>) {
    let generated = mechgen::lookup::<f64>(name).expect("compiled in");
    let generic = mechgen::generic::load("mechanism.toml", mechgen::source::SOURCE)
        .expect("loads")
        .into_iter()
        .find(|m| DynMechanism::<f64>::info(m).name == name)
        .expect("generic");
    let info = generated.info();
    let x0 = info.inputs[0].start;
    let values: Vec<f64> = (0..=720).map(|i| x0 + f64::from(i) * TAU / 720.0).collect();
    let rrr = rrr_links(&compiled(name));
    let a = metrics(generated.as_ref(), 0, &values, &[], true, &rrr, &[]);
    let b = metrics(&generic, 0, &values, &[], true, &rrr, &[]);
    (info, a, b)
}

fn param(info: &MechanismInfo, name: &str) -> f64 {
    info.params
        .iter()
        .find(|p| p.name == name)
        .expect("param")
        .value
}

fn row<'a>(rows: &'a [OutputMetrics], name: &str) -> &'a OutputMetrics {
    rows.iter()
        .find(|r| r.name == name)
        .unwrap_or_else(|| panic!("no row {name}"))
}

/// Angles equal modulo a turn.
fn same_angle(a: f64, b: f64, tol: f64) -> bool {
    let d = (a - b).rem_euclid(TAU);
    d.min(TAU - d) <= tol
}

fn engines_agree(a: &[OutputMetrics], b: &[OutputMetrics]) {
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        assert_eq!(x.name, y.name);
        let close = |u: f64, v: f64| (u - v).abs() <= 1e-12 * v.abs().max(1.0);
        assert!(close(x.min, y.min) && close(x.max, y.max), "{x:?} {y:?}");
        for (u, v) in [
            (x.input_at_min, y.input_at_min),
            (x.input_at_max, y.input_at_max),
            (x.time_ratio, y.time_ratio),
        ] {
            match (u, v) {
                (Some(u), Some(v)) => assert!(close(u, v), "{x:?} {y:?}"),
                (None, None) => {}
                _ => panic!("{x:?} {y:?}"),
            }
        }
    }
}

#[test]
fn the_shaper_returns_quickly_as_the_tangent_limits_say() {
    let (info, rows, generic) = both("shaper");
    engines_agree(&rows, &generic);
    let (l1, lac, l3, l4, ye) = (
        param(&info, "l1"),
        param(&info, "lAC"),
        param(&info, "l3"),
        param(&info, "l4"),
        param(&info, "yE"),
    );
    // The slotted guide is tangent to the crank circle at its limits: cos q3 = ±AB/AC.
    let beta = (l1 / lac).asin();
    let ratio = (PI + 2.0 * beta) / (PI - 2.0 * beta);
    let ram = |q3: f64| {
        let s4 = (ye - l3 * q3.sin()) / l4;
        l3 * q3.cos() - l4 * (1.0 - s4 * s4).sqrt()
    };
    let (lo, hi) = ((l1 / lac).acos(), (-l1 / lac).acos());
    let stroke = (ram(lo) - ram(hi)).abs();
    let se = row(&rows, "sE");
    assert!(
        (se.max - se.min - stroke).abs() < 1e-9,
        "{se:?} stroke {stroke}"
    );
    assert!(
        (se.time_ratio.expect("two extremes") - ratio).abs() < 1e-9,
        "{se:?} {ratio}"
    );
    let q3 = row(&rows, "q3");
    assert!(
        (q3.min - lo).abs() < 1e-9 && (q3.max - hi).abs() < 1e-9,
        "{q3:?}"
    );
    // At the limits the crank is perpendicular to the guide: B = (l1 cos q1, lAC + l1 sin q1) on
    // the line through C at q3.
    for (q1, q3) in [
        (q3.input_at_min.unwrap(), lo),
        (q3.input_at_max.unwrap(), hi),
    ] {
        let (bx, by) = (l1 * q1.cos(), lac + l1 * q1.sin());
        assert!((bx * q3.sin() - by * q3.cos()).abs() < 1e-9, "q1 = {q1}");
    }
    // No RRR block: no transmission row. The ram's height does not vary.
    assert!(!rows.iter().any(|r| r.name.starts_with("transmission")));
    let ey = row(&rows, "E_y");
    assert_eq!(
        (ey.min, ey.max, ey.input_at_min, ey.time_ratio),
        (ye, ye, None, None)
    );
}

#[test]
fn the_crank_rocker_swings_between_its_limit_positions() {
    let (info, rows, generic) = both("four_bar");
    engines_agree(&rows, &generic);
    let (a, b, c, d) = (
        param(&info, "l1"),
        param(&info, "l2"),
        param(&info, "l3"),
        param(&info, "l4"),
    );
    // Limit positions: crank and coupler collinear, |AC| = b ± a, C = D + c e(q3), D = (d, 0),
    // on the start's branch (q3 in (0, π)).
    let limit = |r: f64| {
        let q3 = ((r * r - d * d - c * c) / (2.0 * d * c)).acos();
        let (cx, cy) = (d + c * q3.cos(), c * q3.sin());
        (q3, cy.atan2(cx))
    };
    let (q3_ext, q1_ext) = limit(b + a);
    let (q3_fold, at_fold) = limit(b - a);
    let q1_fold = at_fold + PI;
    let q3 = row(&rows, "q3");
    let (lo, hi) = (q3_ext.min(q3_fold), q3_ext.max(q3_fold));
    assert!(
        (q3.min - lo).abs() < 1e-9 && (q3.max - hi).abs() < 1e-9,
        "{q3:?} {lo} {hi}"
    );
    let (at_lo, at_hi) = if q3_ext < q3_fold {
        (q1_ext, q1_fold)
    } else {
        (q1_fold, q1_ext)
    };
    assert!(
        same_angle(q3.input_at_min.unwrap(), at_lo, 1e-9),
        "{q3:?} {at_lo}"
    );
    assert!(
        same_angle(q3.input_at_max.unwrap(), at_hi, 1e-9),
        "{q3:?} {at_hi}"
    );
    let travel = (q1_fold - q1_ext).rem_euclid(TAU);
    let ratio = travel.max(TAU - travel) / travel.min(TAU - travel);
    assert!(
        (q3.time_ratio.unwrap() - ratio).abs() < 1e-9,
        "{q3:?} {ratio}"
    );
    // Transmission angle: extremes at the crank along the ground line, folded to acute.
    let mu = |r: f64| ((b * b + c * c - r * r) / (2.0 * b * c)).acos();
    let (mu_in, mu_out) = (mu(d - a), mu(d + a));
    let acute = |m: f64| m.min(PI - m);
    let t = row(&rows, "transmission(q2,q3)");
    let crosses = (mu_in - PI / 2.0) * (mu_out - PI / 2.0) < 0.0;
    let want_max = if crosses {
        PI / 2.0
    } else {
        acute(mu_in).max(acute(mu_out))
    };
    assert!(
        (t.min - acute(mu_in).min(acute(mu_out))).abs() < 1e-9,
        "{t:?}"
    );
    assert!((t.max - want_max).abs() < 1e-9, "{t:?}");
    assert!(same_angle(t.input_at_min.unwrap(), 0.0, 1e-9), "{t:?}");
}

#[test]
fn an_input_that_cannot_complete_a_turn_has_its_extremes_at_the_dead_point() {
    let (_, rows, generic) = both("sixbar_g");
    // Positions near a dead point are known to ε/√δ: the engines agree less closely there.
    for (x, y) in rows.iter().zip(&generic) {
        assert!(
            (x.max - y.max).abs() < 1e-6 && (x.min - y.min).abs() < 1e-6,
            "{x:?} {y:?}"
        );
    }
    // From the start (280.67°) up to the dead point at 344.129067…° (80-digit reference).
    let reference = include_str!("data/stress/dead_points.csv");
    let dead: f64 = reference
        .lines()
        .find(|l| l.starts_with("sixbar_g,upper,"))
        .and_then(|l| l.split(',').nth(2))
        .and_then(|v| v.parse().ok())
        .expect("reference dead point");
    let q1 = row(&rows, "q1");
    let at = q1.input_at_max.expect("varies");
    assert!((at - dead).abs() < 1e-9, "{q1:?}");
    assert!(
        rows.iter()
            .all(|r| r.min.is_finite() && r.max.is_finite() && r.time_ratio.is_none())
    );
    // No RRR block (one 4×4 Newton block): no transmission row.
    assert!(!rows.iter().any(|r| r.name.starts_with("transmission")));
}

#[test]
fn the_command_prints_the_table_and_writes_the_csv() {
    let csv = common::cli::temp("metrics", "four_bar.csv");
    let out = mechgen(&["metrics", "four_bar", "--csv", csv.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table = text(&out.stdout);
    assert!(
        table.contains("transmission(q2,q3) [deg]") && table.contains("q3 [deg]"),
        "{table}"
    );
    let body = std::fs::read_to_string(&csv).expect("csv");
    let mut lines = body.lines();
    assert_eq!(
        lines.next(),
        Some("output,min,max,input_at_min,input_at_max,time_ratio")
    );
    let rows: Vec<&str> = lines.collect();
    let names: Vec<&str> = rows[..8]
        .iter()
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(
        names,
        ["q2", "q3", "B_x", "B_y", "C_x", "C_y", "P_x", "P_y"]
    );
    // The name with a comma is a quoted field; then the five numbers (an empty time ratio).
    let t = rows[8]
        .strip_prefix("\"transmission(q2,q3)\",")
        .expect("quoted name");
    assert_eq!(t.split(',').count(), 5, "{t}");
    assert!(t.ends_with(','), "{t}");
    assert!(!body.contains("NaN") && !body.contains("inf"));
    // A length input needs its range.
    let out = mechgen(&[
        "metrics",
        "trammel",
        "--file",
        "tests/data/sweep/trammel.toml",
    ]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("--from and --to are required"),
        "{}",
        text(&out.stderr)
    );
}

/// The triple-rocker's input rocks between its dead points at ±acos((a² + d² − (b + c)²) / 2ad):
/// `metrics` without a range covers that whole branch on both sides of the start (the input
/// below 0 included), so the extremes are those of the geometry: B_y down to −a, and q2's maximum
/// where the analytic solution of the dyad (computed here from the params, by a golden-section
/// search over the branch) has it.
#[test]
fn a_rocking_input_is_analysed_over_its_whole_branch() {
    let info = mechgen::lookup::<f64>("rocker_four_bar")
        .expect("compiled in")
        .info();
    let (a, b, c, d) = (
        param(&info, "l1"),
        param(&info, "l2"),
        param(&info, "l3"),
        param(&info, "l4"),
    );
    let dead = ((a * a + d * d - (b + c) * (b + c)) / (2.0 * a * d)).acos();
    // q2 on the start's assembly mode (the coupler's angle: C = B + b·e(q2) on the circle of
    // radius c about D).
    let sign = {
        let (q2, q1) = (info.unknowns[0].start, info.inputs[0].start);
        let (bx, by) = (a * q1.cos(), a * q1.sin());
        let base = (-by).atan2(d - bx);
        if (q2 - base).sin() > 0.0 { 1.0 } else { -1.0 }
    };
    let q2 = |q1: f64| {
        let (bx, by) = (a * q1.cos(), a * q1.sin());
        let (dx, dy) = (d - bx, -by);
        let l = dx.hypot(dy);
        let cos = ((b * b + l * l - c * c) / (2.0 * b * l)).clamp(-1.0, 1.0);
        dy.atan2(dx) + sign * cos.acos()
    };
    // The maximum of q2 over (−dead, dead): a grid, then golden sections around its best.
    let n = 20_000;
    let best = (0..=n)
        .map(|i| -dead + 2.0 * dead * i as f64 / n as f64)
        .max_by(|x, y| q2(*x).total_cmp(&q2(*y)))
        .expect("grid");
    let (mut lo, mut hi) = (best - 2.0 * dead / n as f64, best + 2.0 * dead / n as f64);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..200 {
        let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if q2(m1) < q2(m2) {
            lo = m1;
        } else {
            hi = m2;
        }
    }
    let q2_max = q2((lo + hi) / 2.0);
    let csv = common::cli::temp("metrics", "rocker_four_bar.csv");
    let out = mechgen(&["metrics", "rocker_four_bar", "--csv", csv.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let body = std::fs::read_to_string(&csv).expect("csv");
    let cells = |name: &str| -> Vec<f64> {
        let line = body
            .lines()
            .find(|l| l.starts_with(&format!("{name},")))
            .expect("row");
        line.split(',')
            .skip(1)
            .take(4)
            .map(|v| v.parse().expect("number"))
            .collect()
    };
    let q2_row = cells("q2");
    assert!(
        (q2_row[1] - q2_max).abs() < 1e-9,
        "{q2_row:?} against {q2_max}"
    );
    assert!(
        q2_row[3] < 0.0,
        "the maximum lies below the start: {q2_row:?}"
    );
    let by = cells("B_y");
    assert!((by[0] + a).abs() < 1e-12, "{by:?}");
    // The range is the branch, its extremes at the dead points read there (not at the last row
    // before them): q3's maximum at the lower dead point, q2's minimum at the upper one (coupler
    // and rocker in line: q2 there from the geometry), the transmission angle down to zero.
    let q1_range = cells("q3");
    assert!(
        (q1_range[3].abs() - dead).abs() < 1e-9,
        "q3's maximum at the lower dead point: {q1_range:?}"
    );
    let q2_min = q2(dead);
    assert!(
        (q2_row[0] - q2_min).abs() < 1e-7 && (q2_row[2] - dead).abs() < 1e-9,
        "{q2_row:?} against {q2_min} at {dead}"
    );
    let mu = body
        .lines()
        .find(|l| l.starts_with("\"transmission("))
        .and_then(|l| l.split(',').nth(2))
        .and_then(|v| v.parse::<f64>().ok())
        .expect("transmission row");
    assert!(
        mu.abs() < 1e-6,
        "transmission angle at the dead point: {mu}"
    );
    assert!(
        text(&out.stdout).contains("106.068459"),
        "{}",
        text(&out.stdout)
    );
}
