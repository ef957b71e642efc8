//! `mechgen sensitivity`, `mechgen tolerance` and `sweep --load` (interfaces.md): the tolerance
//! RSS against a Monte Carlo of the position solve, the input effort of a slider-crank against
//! the textbook formula, and the sensitivity CSV against the library at every row.
#![cfg(feature = "cli")]

mod common;

use common::Table;
use common::cli::{mechgen, temp, text};
use mechgen::SolveOptions;
use mechgen::sixbar::Sixbar;

/// A small deterministic generator (xorshift64*) with Box–Muller normals.
struct Normal(u64);

impl Normal {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let r = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        ((r >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    fn sample(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// The seed six-bar with tolerances σ on four link lengths: at every row of a 30° sweep, each
/// output's RSS deviation from `mechgen tolerance` is within 5 % of the standard deviation of
/// 10 000 position solves with the lengths drawn from normal distributions of those σ.
#[test]
fn tolerance_rss_agrees_with_a_monte_carlo_of_the_position_solve() {
    let csv = temp("design", "tolerance.csv");
    let tols = [("l1", 2e-4), ("l2", 5e-4), ("l3", 3e-4), ("l4", 4e-4)];
    let mut args = vec!["tolerance", "sixbar", "--step", "30", "--csv"];
    let path = csv.to_str().unwrap().to_string();
    args.push(&path);
    let given: Vec<String> = tols.iter().map(|(n, t)| format!("{n}={t}")).collect();
    for g in &given {
        args.extend(["--tol", g.as_str()]);
    }
    let out = mechgen(&args);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("worst case"));
    let table = Table::read(&path);
    let nominal = Sixbar::<f64>::default();
    let start = Sixbar::<f64>::start().1.to_array();
    let outputs = ["q2", "q3", "q5", "q6", "E_x", "E_y"];
    let mut rng = Normal(0x9E37_79B9_7F4A_7C15);
    let mut q = start;
    let mut compared = 0;
    for (r, row) in table.rows.iter().enumerate() {
        assert_eq!(row.last().map(String::as_str), Some("ok"), "row {r}");
        let x = [row[0].parse::<f64>().unwrap()];
        nominal
            .solve_position(&x, &mut q, &SolveOptions::default())
            .expect("nominal");
        let n = 10_000;
        let mut sums = [[0.0f64; 2]; 6];
        for _ in 0..n {
            let mut p = nominal.params;
            p.l1 += tols[0].1 * rng.sample();
            p.l2 += tols[1].1 * rng.sample();
            p.l3 += tols[2].1 * rng.sample();
            p.l4 += tols[3].1 * rng.sample();
            let m = Sixbar::new(p);
            let mut qs = q;
            m.solve_position(&x, &mut qs, &SolveOptions::default())
                .expect("a perturbed solve");
            let e = m.point_positions(&x, &qs)[0];
            let values = [qs[0], qs[1], qs[2], qs[3], e[0], e[1]];
            let base = [q[0], q[1], q[2], q[3]];
            let e0 = nominal.point_positions(&x, &q)[0];
            let nominal_values = [base[0], base[1], base[2], base[3], e0[0], e0[1]];
            for ((s, v), v0) in sums.iter_mut().zip(values).zip(nominal_values) {
                s[0] += v - v0;
                s[1] += (v - v0) * (v - v0);
            }
        }
        for (o, s) in outputs.iter().zip(&sums) {
            let mean = s[0] / n as f64;
            let sd = (s[1] / n as f64 - mean * mean).sqrt();
            let rss = table.column(&format!("{o}_rss"))[r];
            assert!(
                (rss - sd).abs() <= 0.05 * sd,
                "row {r} ({} rad), {o}: rss {rss:e}, Monte Carlo {sd:e}",
                x[0]
            );
            compared += 1;
        }
    }
    assert_eq!(compared, 13 * 6);
}

const SLIDER_CRANK: &str = r#"
[mechanism.crank_slider]
description = "crank r, rod l, slider C on the x axis"
inputs = ["theta"]
unknowns = ["psi", "x"]
loops = ["r*e(theta) + l*e(psi) - c(x, 0)"]
points = { C = "c(x, 0)", B = "r*e(theta)" }
[mechanism.crank_slider.params]
r = 0.1
l = 0.35
[mechanism.crank_slider.start]
theta = 0.0
psi = 0.0
x = 0.45
"#;

/// A force F along the slider's axis on C: the input torque by virtual work equals the textbook
/// F r sin(θ + φ) / cos φ (φ the rod's angle to the axis, sin φ = r sin θ / l) over a turn.
#[test]
fn input_effort_of_a_slider_crank_is_the_textbook_torque() {
    let file = temp("design", "crank_slider.toml");
    std::fs::write(&file, SLIDER_CRANK).unwrap();
    let csv = temp("design", "effort.csv");
    let out = mechgen(&[
        "sweep",
        "crank_slider",
        "--file",
        file.to_str().unwrap(),
        "--step",
        "5",
        "--rate",
        "2.5",
        "--load",
        "C=3,0",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("input_effort [force*u/rad]"));
    let table = Table::read(csv.to_str().unwrap());
    let (r, l, f) = (0.1, 0.35, 3.0);
    let (theta, effort) = (table.column("theta"), table.column("input_effort"));
    assert_eq!(theta.len(), 73);
    for (t, e) in theta.iter().zip(&effort) {
        let phi = (r * t.sin() / l).asin();
        let want = f * r * (t + phi).sin() / phi.cos();
        assert!(
            (e - want).abs() <= 1e-10 * f * r,
            "theta {t}: {e} against {want}"
        );
    }
    // A point the mechanism lacks is an error naming it.
    let bad = mechgen(&["sweep", "four_bar", "--load", "Z=1,0"]);
    assert!(!bad.status.success());
    assert!(
        text(&bad.stderr).contains("no point `Z`"),
        "{}",
        text(&bad.stderr)
    );
}

/// The CSV of `mechgen sensitivity` holds, at every row, what the library's
/// `DynMechanism::sensitivities` gives at the row's configuration (columns `u/p`, `P_x/p`,
/// `P_y/p`, status last).
#[test]
fn sensitivity_csv_columns_are_the_library_values() {
    let csv = temp("design", "sensitivity.csv");
    let out = mechgen(&[
        "sensitivity",
        "four_bar",
        "--step",
        "45",
        "--engine",
        "generic",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table = Table::read(csv.to_str().unwrap());
    let k = mechgen::lookup::<f64>("four_bar").expect("compiled in");
    let info = k.info();
    let npar = info.params.len();
    let mut want_header = vec![info.inputs[0].name.clone()];
    let mut outs: Vec<String> = info.unknowns.iter().map(|u| u.name.clone()).collect();
    for p in &info.points {
        outs.extend([format!("{p}_x"), format!("{p}_y")]);
    }
    for o in &outs {
        want_header.extend(info.params.iter().map(|p| format!("{o}/{}", p.name)));
    }
    want_header.push("status".into());
    assert_eq!(table.header, want_header);
    let rows = mechgen::sweep::sweep(
        k.as_ref(),
        0,
        &table.column(&info.inputs[0].name),
        1.0,
        &mechgen::sweep::Continuation::for_input(info.inputs[0].kind, 1.0),
    );
    for (row, swept) in table.rows.iter().zip(&rows) {
        let s = swept.result.as_ref().expect("solved");
        let (nu, np) = (info.unknowns.len(), info.points.len());
        let (mut dq, mut dp) = (vec![0.0; nu * npar], vec![0.0; 2 * np * npar]);
        k.sensitivities(&[swept.input], &s.q, &mut dq, &mut dp)
            .expect("sensitivities");
        for (cell, want) in row[1..].iter().zip(dq.iter().chain(&dp)) {
            let got: f64 = cell.parse().unwrap();
            assert!(
                (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                "{got} vs {want}"
            );
        }
        assert_eq!(row.last().map(String::as_str), Some("ok"));
    }
}
