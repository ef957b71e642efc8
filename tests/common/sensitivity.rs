//! Shared by `tests/sensitivity.rs` and `tests/fixtures.rs` (which CI runs on every fixture file):
//! every compiled-in mechanism's design derivatives on both engines, against each other and
//! against Richardson-extrapolated central differences of the position solve.

use super::engines::engines;
use mechgen::sweep::{Continuation, sweep};
use mechgen::{DynMechanism, InputMotion, Kind, PointMotion, SolveOptions, generic::Generic};

/// The positions and point positions of `g` with param `j` set to `value`, solved from `q`.
fn positions(g: &Generic, j: usize, value: f64, x: &[f64], q: &[f64]) -> Option<Vec<f64>> {
    let info = DynMechanism::<f64>::info(g);
    let mut g = g.clone();
    g.set_param(&info.params[j].name, value).ok()?;
    let mut q = q.to_vec();
    g.solve_position(x, &mut q, &SolveOptions::default()).ok()?;
    let zero = vec![0.0; q.len()];
    let xz = vec![0.0; x.len()];
    let mut points = vec![PointMotion::default(); info.points.len()];
    let input = InputMotion::new(x, &xz[..], &xz[..]);
    g.points(input, &q, &zero, &zero, &mut points).ok()?;
    q.extend(points.iter().flat_map(|p| p.position));
    Some(q)
}

/// d(q, P)/dp_j by central differences at steps h and h/2, Richardson-extrapolated (error h⁴).
fn richardson(g: &Generic, j: usize, x: &[f64], q: &[f64], h: f64) -> Option<Vec<f64>> {
    let p = g.params()[j];
    let central = |h: f64| -> Option<Vec<f64>> {
        let (a, b) = (positions(g, j, p + h, x, q)?, positions(g, j, p - h, x, q)?);
        Some(a.iter().zip(&b).map(|(u, v)| (u - v) / (2.0 * h)).collect())
    };
    let (d1, d2) = (central(h)?, central(h / 2.0)?);
    Some(
        d1.iter()
            .zip(&d2)
            .map(|(a, b)| (4.0 * b - a) / 3.0)
            .collect(),
    )
}

/// Every compiled-in mechanism at every sixth solved row of a sweep of its first input: the
/// generated sensitivities equal the generic engine's to 1e-12 and Richardson differences of the
/// position solve to 1e-7, relative to each output's largest derivative (at least 1e-3).
/// Returns the failures and the number of rows compared.
pub fn check_sensitivities() -> (Vec<String>, usize) {
    let (mut fails, mut compared) = (Vec::new(), 0);
    for (k, g) in engines() {
        let (mut worst_engines, mut worst_differences) = (0.0f64, 0.0f64);
        let info = k.info();
        let (nu, np, npar) = (info.unknowns.len(), info.points.len(), info.params.len());
        let first = info.inputs[0].start;
        let values: Vec<f64> = match info.inputs[0].kind {
            Kind::Angle => (0..=36).map(|i| first + f64::from(i - 18) * 0.1).collect(),
            _ => (0..=20)
                .map(|i| first * (1.0 + 0.01 * f64::from(i)))
                .collect(),
        };
        let c = Continuation::for_input(info.inputs[0].kind, 0.2 * first.abs().max(1.0));
        let rows = sweep(&g, 0, &values, 1.0, &c);
        let scale = info
            .params
            .iter()
            .filter(|p| p.kind == Kind::Length)
            .fold(1e-3f64, |m, p| m.max(p.value.abs()));
        for row in rows.iter().filter(|r| r.result.is_ok()).step_by(6) {
            let Ok(r) = &row.result else { continue };
            let mut x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
            x[0] = row.input;
            let (mut sq, mut sp) = (vec![0.0; nu * npar], vec![0.0; 2 * np * npar]);
            let (mut gq, mut gp) = (sq.clone(), sp.clone());
            let at = format!("{} at {:.4}", info.name, x[0]);
            if let Err(e) = k.sensitivities(&x, &r.q, &mut sq, &mut sp) {
                fails.push(format!("{at}: generated {e}"));
                continue;
            }
            if let Err(e) = g.sensitivities(&x, &r.q, &mut gq, &mut gp) {
                fails.push(format!("{at}: generic {e}"));
                continue;
            }
            compared += 1;
            // Row-major (output × param) of both matrices, outputs: unknowns, then P_x, P_y.
            let got: Vec<f64> = sq.iter().chain(&sp).copied().collect();
            let generic: Vec<f64> = gq.iter().chain(&gp).copied().collect();
            let mut columns = vec![Vec::new(); npar];
            for (j, col) in columns.iter_mut().enumerate() {
                // A step relative to the param, or to the mechanism's length scale for a length
                // near zero (an angle's step is never a length's: h⁴ of a 0.1 rad step shows).
                let floor = match info.params[j].kind {
                    Kind::Length => 1e-2 * scale,
                    _ => 1e-2,
                };
                let h = 1e-4 * info.params[j].value.abs().max(floor);
                match richardson(&g, j, &x, &r.q, h) {
                    Some(d) => *col = d,
                    None => fails.push(format!("{at}: no differences for {}", info.params[j].name)),
                }
            }
            for out in 0..nu + 2 * np {
                let row =
                    |v: &[f64]| -> Vec<f64> { (0..npar).map(|j| v[out * npar + j]).collect() };
                let (a, b) = (row(&got), row(&generic));
                let d: Vec<f64> = columns
                    .iter()
                    .map(|c| c.get(out).copied().unwrap_or(0.0))
                    .collect();
                let big = d.iter().fold(1e-3f64, |m, v| m.max(v.abs()));
                for j in 0..npar {
                    worst_engines = worst_engines.max((a[j] - b[j]).abs() / big.max(a[j].abs()));
                    if !columns[j].is_empty() {
                        worst_differences = worst_differences.max((a[j] - d[j]).abs() / big);
                    }
                    if (a[j] - b[j]).abs() > 1e-12 * big.max(a[j].abs()) {
                        fails.push(format!(
                            "{at}: output {out} / {}: generated {} generic {}",
                            info.params[j].name, a[j], b[j]
                        ));
                    }
                    if !columns[j].is_empty() && (a[j] - d[j]).abs() > 1e-7 * big {
                        fails.push(format!(
                            "{at}: output {out} / {}: {} against differences {}",
                            info.params[j].name, a[j], d[j]
                        ));
                    }
                }
            }
        }
        eprintln!(
            "{}: generated vs generic {worst_engines:.1e}, vs differences {worst_differences:.1e}",
            info.name
        );
    }
    (fails, compared)
}
