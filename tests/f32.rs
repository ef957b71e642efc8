//! The f32 instantiation of the generated solvers against the 40-digit reference values of the
//! seed mechanisms: continuation in f32 from the start configuration with 1° substeps and a tangent
//! predictor, then velocities (input rate 1), accelerations (input acceleration 0) and points.

mod common;

use common::{Table, angle_diff};
use mechgen::{Kind, SolveError, SolveOptions, StaticInfo};

const TOLERANCE: f64 = 1e-4;
/// Largest continuation substep: 1°.
const SUBSTEP: f64 = std::f64::consts::PI / 180.0;

/// The computed columns of a sweep, named as in the reference CSV, with the kind of comparison.
struct Columns {
    names: Vec<String>,
    /// True for an angle (compared modulo 2π, absolute).
    angle: Vec<bool>,
    values: Vec<Vec<f64>>,
}

impl Columns {
    fn new(info: &StaticInfo) -> Columns {
        let mut names = Vec::new();
        let mut angle = Vec::new();
        for u in info.unknowns {
            names.push(u.name.to_string());
            angle.push(u.kind == Kind::Angle);
        }
        for suffix in ["vel", "acc"] {
            for u in info.unknowns {
                names.push(format!("{}_{suffix}", u.name));
                angle.push(false);
            }
        }
        for p in info.points {
            for suffix in ["x", "y", "vx", "vy", "ax", "ay"] {
                names.push(format!("{p}_{suffix}"));
                angle.push(false);
            }
        }
        let values = vec![Vec::new(); names.len()];
        Columns {
            names,
            angle,
            values,
        }
    }

    /// One row: q, q̇, q̈, then every point's position, velocity and acceleration.
    fn push(&mut self, q: &[f32], qd: &[f32], qdd: &[f32], points: &[mechgen::PointMotion<f32>]) {
        let row = q
            .iter()
            .chain(qd)
            .chain(qdd)
            .copied()
            .chain(points.iter().flat_map(|p| {
                [
                    p.position[0],
                    p.position[1],
                    p.velocity[0],
                    p.velocity[1],
                    p.acceleration[0],
                    p.acceleration[1],
                ]
            }));
        let mut count = 0;
        for (column, v) in self.values.iter_mut().zip(row) {
            column.push(f64::from(v));
            count += 1;
        }
        assert_eq!(count, self.names.len(), "one value per column");
    }
}

/// Every column of the reference but the input, `detJ` and `status` against the computed ones:
/// angles modulo 2π absolute, everything else relative to the reference column's largest magnitude.
/// Returns (column, error, row) of every column, and fails on any above the tolerance.
fn compare(name: &str, reference: &Table, computed: &Columns) -> Vec<(String, f64, usize)> {
    let mut errors = Vec::new();
    for header in &reference.header[1..] {
        if header == "detJ" || header == "status" {
            continue;
        }
        let c = computed
            .names
            .iter()
            .position(|n| n == header)
            .unwrap_or_else(|| panic!("{name}: reference column {header} not computed"));
        let want = reference.column(header);
        let got = &computed.values[c];
        assert_eq!(want.len(), got.len(), "{name}.{header}: row count");
        let scale = want
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        let (mut worst, mut at) = (0.0f64, 0);
        for (row, (w, g)) in want.iter().zip(got).enumerate() {
            let e = if computed.angle[c] {
                angle_diff(*g, *w).abs()
            } else {
                (g - w).abs() / scale
            };
            let e = if e.is_nan() { f64::INFINITY } else { e };
            if e > worst {
                (worst, at) = (e, row);
            }
        }
        errors.push((header.clone(), worst, at));
    }
    assert_eq!(
        errors.len(),
        computed.names.len(),
        "{name}: every computed column is in the reference"
    );
    errors
}

/// Sweeps the reference's input column in f32 with the typed API of `$ty`, and compares.
macro_rules! sweep_f32 {
    ($fn:ident, $module:ident :: $ty:ident) => {
        fn $fn(reference: &Table) -> Result<Columns, (usize, SolveError)> {
            use mechgen::$module::{INFO, $ty};
            let m = $ty::<f32>::default();
            let options = SolveOptions::<f32>::default();
            let (x, q) = $ty::<f32>::start();
            let (mut x, mut q) = (x.to_array(), q.to_array());
            // Settle the start configuration (its values are rounded).
            m.solve_position(&x, &mut q, &options).map_err(|e| (0, e))?;
            let unit = [1.0f32];
            let zero = [0.0f32];
            let mut columns = Columns::new(&INFO);
            let mut from = f64::from(x[0]);
            for (row, target) in reference
                .column(&reference.header[0])
                .into_iter()
                .enumerate()
            {
                let substeps = ((target - from).abs() / SUBSTEP).ceil() as usize;
                for k in 1..=substeps {
                    let next = [(from + (target - from) * k as f64 / substeps as f64) as f32];
                    // Tangent predictor: dq/dx times the input step.
                    let tangent = m.solve_velocity(&x, &q, &unit).map_err(|e| (row, e))?;
                    let dx = next[0] - x[0];
                    let mut guess = q;
                    for (g, t) in guess.iter_mut().zip(tangent) {
                        *g += t * dx;
                    }
                    m.solve_position(&next, &mut guess, &options)
                        .map_err(|e| (row, e))?;
                    (x, q) = (next, guess);
                }
                from = target;
                let qd = m.solve_velocity(&x, &q, &unit).map_err(|e| (row, e))?;
                let qdd = m
                    .solve_acceleration(&x, &q, &unit, &qd, &zero)
                    .map_err(|e| (row, e))?;
                let points = m.point_motion(&x, &q, &unit, &qd, &zero, &qdd);
                columns.push(&q, &qd, &qdd, &points);
            }
            Ok(columns)
        }
    };
}

sweep_f32!(sweep_sixbar, sixbar::Sixbar);
sweep_f32!(sweep_shaper, shaper::Shaper);

fn check(name: &str, sweep: fn(&Table) -> Result<Columns, (usize, SolveError)>) {
    let reference = Table::read(&format!(
        "{}/tests/data/{name}.csv",
        env!("CARGO_MANIFEST_DIR")
    ));
    assert_eq!(reference.header[0], "q1", "{name}: the input column");
    let computed = sweep(&reference)
        .unwrap_or_else(|(row, e)| panic!("{name}: f32 sweep failed at row {row}: {e:?}"));
    let errors = compare(name, &reference, &computed);
    let (column, worst, row) = errors
        .iter()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .expect("columns");
    eprintln!("{name} (f32): largest error {worst:.3e} ({column}, row {row})");
    let failing: Vec<String> = errors
        .iter()
        .filter(|e| e.1 > TOLERANCE)
        .map(|(c, e, r)| format!("{name}.{c}: error {e:e} at row {r}"))
        .collect();
    assert!(
        failing.is_empty(),
        "f32 errors above {TOLERANCE:e}:\n{}",
        failing.join("\n")
    );
}

#[test]
fn sixbar_f32_matches_reference() {
    check("sixbar", sweep_sixbar);
}

#[test]
fn shaper_f32_matches_reference() {
    check("shaper", sweep_shaper);
}
