//! Run time against error for the seed six-bar over a full turn:
//! `cargo run --release --example accuracy -- OUT_DIR` writes `OUT_DIR/accuracy.md` (the table,
//! also printed) and `OUT_DIR/accuracy.svg` (time per step against the largest error, log-log).
//!
//! Work: like a simulator tick (and the `step` bench), from the previous full state the positions
//! are predicted as q + q'·Δx + q''·Δx²/2, then positions, velocities, accelerations and the
//! points are solved; 360 steps of 1° from 0° to 360° (input rate 1, acceleration 0), after an
//! untimed assembly at 0° from the file's start values. The error is the largest over the states
//! at 0°, 10°, …, 360° against the 40-digit reference (`tests/data/sixbar.csv`): positions in
//! radians (modulo 2π), velocities and accelerations relative to their column's largest magnitude.
//! Time per step: the median over 15 repetitions of (time of N full turns) / (360 N), N chosen
//! so a repetition takes about 40 ms, after a warm-up turn; the repetitions go round the variants
//! in turn, so a slow spell of a shared machine hits them all alike (the spread is printed to
//! stderr).
//!
//! Variants: the generated solvers at several tolerances; with an iteration cap at tolerance 1e-12
//! (a tick whose position solve fails keeps the predicted positions and solves the rates there:
//! a simulator on a fixed budget cannot retry, and the solvers return the iterate only on
//! success); with exactly k iterations accepted without a convergence test; in f32; the generic
//! engine; and a hand-written-style solver that only evaluates the residual (finite-difference
//! Jacobians, dense Newton, see `variants.rs`).
//!
//! Then the seed shaper, the same way (`shaper.rs`: its unknowns s3, sE are lengths, q3, q4
//! angles; reference `tests/data/shaper.csv`): `tick` with closed forms (the default), Newton on
//! every block (`closed_forms: false`) at tolerances 1e-6 and 1e-12, f32 with closed forms, and the
//! generic engine; written to `OUT_DIR/accuracy-shaper.md` (also printed). Errors: angles in
//! radians modulo 2π, lengths relative to the larger of the largest length param and their
//! column's largest magnitude, rates relative to their column's largest magnitude.

mod shaper;
mod variants;

use std::error::Error;
use std::fmt::Write as _;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use mechgen::SolveOptions;
use mechgen::plot::{Marker, ScatterLayout, log_log_scatter_svg};
use variants::{
    Budget, Engine, Errors, FiniteDifferences, Generated, Pass, STEPS, Scheme, Stepper, errors,
    inputs, reference, run,
};

/// Wall time one repetition aims at.
const REPETITION: Duration = Duration::from_millis(40);
const REPETITIONS: usize = 15;

/// The legend groups of the plot.
const GROUPS: [&str; 7] = [
    "generated f64 Newton, tolerance (cap 64)",
    "generated f64 Newton, cap k at tolerance 1e-12 (a failed tick keeps the prediction)",
    "generated f64 Newton, k iterations per block accepted",
    "generated f32 Newton, tolerance",
    "generic engine f64",
    "generic residual + finite-difference Jacobians",
    "generated, closed-form dyads (the default)",
];

/// One row of the table.
struct Row {
    variant: String,
    label: String,
    group: usize,
    tolerance: String,
    cap: String,
    ns_per_step: f64,
    iterations_per_step: f64,
    errors: Errors,
    failed: usize,
}

/// A variant under measurement: one full turn per call (timed steps), its warm-up result and how
/// many turns make a repetition.
struct Timed<'a> {
    row: Row,
    turn: Box<dyn FnMut() -> Result<(Pass, Duration), String> + 'a>,
    first: Pass,
    turns: u32,
    per_step: Vec<f64>,
}

impl<'a> Timed<'a> {
    /// The warm-up turn (whose states give the errors) and the number of turns per repetition.
    fn new<S: Stepper + 'a>(mut s: S, xs: &'a [f64], row: Row) -> Result<Self, String> {
        let (first, t) = run(&mut s, xs)?;
        let turns = (REPETITION.as_secs_f64() / t.as_secs_f64().max(1e-9))
            .ceil()
            .max(1.0) as u32;
        let turn = Box::new(move || run(black_box(&mut s), black_box(xs)));
        Ok(Timed {
            row,
            turn,
            first,
            turns,
            per_step: Vec::new(),
        })
    }

    /// One repetition: `turns` full turns; every turn must repeat the warm-up's results.
    fn repeat(&mut self) -> Result<(), String> {
        let mut total = Duration::ZERO;
        for _ in 0..self.turns {
            let (pass, t) = (self.turn)()?;
            if black_box(&pass) != &self.first {
                return Err(format!(
                    "{}: a turn differs from the first",
                    self.row.variant
                ));
            }
            total += t;
        }
        self.per_step
            .push(total.as_secs_f64() * 1e9 / (f64::from(self.turns) * STEPS as f64));
        Ok(())
    }
}

fn sci(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.1e}")
    } else {
        "—".into()
    }
}

fn table(rows: &[Row]) -> String {
    table_with(rows, "max error positions [rad]")
}

fn table_with(rows: &[Row], positions: &str) -> String {
    let mut t = format!(
        "| variant | tolerance | iteration cap | time per step [ns] | Newton iterations per step \
         | {positions} | velocities (rel.) | accelerations (rel.) | failed steps |\n\
         | --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |\n",
    );
    for r in rows {
        let _ = writeln!(
            t,
            "| {} | {} | {} | {:.0} | {:.2} | {} | {} | {} | {} |",
            r.variant,
            r.tolerance,
            r.cap,
            r.ns_per_step,
            r.iterations_per_step,
            sci(r.errors.position),
            sci(r.errors.velocity),
            sci(r.errors.acceleration),
            r.failed
        );
    }
    t
}

fn main() -> Result<(), Box<dyn Error>> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .ok_or("usage: cargo run --release --example accuracy -- OUT_DIR")?,
    );
    std::fs::create_dir_all(&out)?;
    if cfg!(debug_assertions) {
        eprintln!("warning: a debug build; run with --release for meaningful times");
    }
    let reference = reference()?;
    let xs = inputs();
    let loaded = mechgen::generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)?;
    let generic = loaded
        .iter()
        .find(|g| g.name() == "sixbar")
        .ok_or("the compiled-in file has no sixbar")?;

    let mut timed: Vec<Timed> = Vec::new();
    macro_rules! variant {
        ($stepper:expr, $variant:expr, $label:expr, $group:expr, $tol:expr, $cap:expr) => {{
            let row = Row {
                variant: $variant.to_string(),
                label: $label.to_string(),
                group: $group,
                tolerance: $tol.to_string(),
                cap: $cap.to_string(),
                ns_per_step: f64::NAN,
                iterations_per_step: f64::NAN,
                errors: errors(&[], &reference),
                failed: 0,
            };
            timed.push(Timed::new($stepper, &xs, row)?);
        }};
    }

    variant!(
        Generated::<f64>::new(Budget::ClosedForm),
        "generated f64, closed-form dyads (default)",
        "closed form f64",
        6,
        "—",
        "—"
    );
    variant!(
        Generated::<f64>::new(Budget::Ticked),
        "generated f64, `tick` (predictor stepping, cached sines and cosines)",
        "tick f64",
        6,
        "—",
        "—"
    );
    variant!(
        Generated::<f32>::new(Budget::ClosedForm),
        "generated f32, closed-form dyads (default)",
        "closed form f32",
        6,
        "—",
        "—"
    );
    for (tolerance, name) in [
        (1e-4, "1e-4"),
        (1e-6, "1e-6"),
        (1e-8, "1e-8"),
        (1e-10, "1e-10"),
        (1e-12, "1e-12"),
        (1e-14, "1e-14"),
    ] {
        let default = if tolerance == 1e-12 {
            " (default tolerance)"
        } else {
            ""
        };
        variant!(
            Generated::<f64>::new(Budget::Options {
                tolerance,
                max_iterations: 64
            }),
            format!("generated f64 Newton, tolerance {name}{default}"),
            name,
            0,
            name,
            64
        );
    }
    for cap in 1..=3 {
        variant!(
            Generated::<f64>::new(Budget::Options {
                tolerance: 1e-12,
                max_iterations: cap
            }),
            format!("generated f64 Newton, cap {cap}, failed tick keeps the prediction"),
            format!("cap {cap}"),
            1,
            "1e-12",
            cap
        );
    }
    for k in 1..=3 {
        variant!(
            Generated::<f64>::new(Budget::Fixed(k)),
            format!("generated f64 Newton, {k} iteration(s) per block accepted"),
            format!("{k} it"),
            2,
            "none",
            k
        );
    }
    for (tolerance, name) in [(1e-5, "1e-5 (default)"), (1e-3, "1e-3")] {
        variant!(
            Generated::<f32>::new(Budget::Options {
                tolerance,
                max_iterations: 64
            }),
            format!("generated f32 Newton, tolerance {name}"),
            format!("f32 {}", &name[..4]),
            3,
            &name[..4],
            64
        );
    }
    variant!(
        Engine::new(generic, SolveOptions::default()),
        "generic engine f64 (default)",
        "generic",
        4,
        "1e-12",
        64
    );
    for (scheme, name) in [(Scheme::Forward, "forward"), (Scheme::Central, "central")] {
        let fd = FiniteDifferences::new(generic, scheme);
        let (tol, cap) = (fd.tolerance, fd.max_iterations);
        variant!(
            fd,
            format!("generic residual + {name} differences, dense Newton"),
            format!("FD {name}"),
            5,
            format!("{tol:e}"),
            cap
        );
    }

    let rows = measure(timed, |s| errors(s, &reference))?;

    let md = format!(
        "Seed six-bar, full turn in 1° steps (360 ticks: predict q + q'·Δx + q''·Δx²/2, then \
         positions, velocities, accelerations, points); largest error over 0°, 10°, …, 360° against \
         the 40-digit reference (positions in rad modulo 2π, rates relative to the column's largest \
         value). Time per step: median of {REPETITIONS} repetitions of about {} ms, interleaved \
         over the variants.\n\n{}\n\
         Newton iterations are block iterations summed over the six-bar's two 2×2 blocks (generated, \
         generic) or iterations on the full 4×4 system (finite differences). A capped tick whose \
         position solve fails (`NoConvergence`) keeps the predicted positions and solves the rates \
         there; it is counted at the cap. \"k iterations\": k solves with `max_iterations: 1` and \
         tolerance ∞, the iterate accepted untested. Finite differences: forward h = √ε·max(1, |z|), \
         central h = ∛ε·max(1, |z|), accelerations through a central second difference along \
         (ẋ, q̇); Newton stops at a step of 1e-12, cap 50.\n",
        REPETITION.as_millis(),
        table(&rows)
    );
    print!("{md}");
    std::fs::write(out.join("accuracy.md"), &md)?;

    let markers: Vec<Marker> = rows
        .iter()
        .map(|r| Marker {
            label: r.label.clone(),
            x: r.ns_per_step,
            y: r.errors.max(),
            group: r.group,
        })
        .collect();
    let layout = ScatterLayout {
        title: "Seed six-bar: time per step against error".into(),
        subtitle: "full turn in 1° steps (predict, solve positions, velocities, accelerations, \
                   points); largest error against the 40-digit reference"
            .into(),
        x_desc: "time per step [ns]".into(),
        y_desc: "largest error (positions [rad], rates relative)".into(),
        groups: GROUPS.iter().map(|g| g.to_string()).collect(),
    };
    std::fs::write(
        out.join("accuracy.svg"),
        log_log_scatter_svg(&layout, &markers)?,
    )?;
    eprintln!("wrote {}/accuracy.md and accuracy.svg", out.display());

    let md = shaper_study(&xs)?;
    print!("{md}");
    std::fs::write(out.join("accuracy-shaper.md"), &md)?;
    eprintln!("wrote {}/accuracy-shaper.md", out.display());
    Ok(())
}

/// Times the variants (repetitions interleaved over them, so a slow spell of the machine hits
/// them all) and measures their warm-up turns' errors.
fn measure(
    mut timed: Vec<Timed>,
    errors: impl Fn(&[variants::State]) -> Errors,
) -> Result<Vec<Row>, String> {
    for rep in 0..REPETITIONS {
        eprintln!("repetition {}/{REPETITIONS}", rep + 1);
        for t in &mut timed {
            t.repeat()?;
        }
    }
    Ok(timed
        .into_iter()
        .map(|mut t| {
            t.per_step.sort_by(f64::total_cmp);
            let row = Row {
                ns_per_step: t.per_step[t.per_step.len() / 2],
                iterations_per_step: t.first.iterations as f64 / STEPS as f64,
                errors: errors(&t.first.samples),
                failed: t.first.failed,
                ..t.row
            };
            eprintln!(
                "{:<64} {:>6.0} ns/step (spread {:.0}..{:.0})  {:>5.2} it/step  max error {}  failed {}",
                row.variant,
                row.ns_per_step,
                t.per_step[0],
                t.per_step[t.per_step.len() - 1],
                row.iterations_per_step,
                sci(row.errors.max()),
                row.failed
            );
            row
        })
        .collect())
}

/// The seed shaper's variants (`shaper.rs`), timed and measured like the six-bar's: the markdown.
fn shaper_study(xs: &[f64]) -> Result<String, Box<dyn Error>> {
    let reference = shaper::reference()?;
    let generic = shaper::generic()?;
    let mut timed: Vec<Timed> = Vec::new();
    let row = |variant: &str, tolerance: &str| Row {
        variant: variant.to_string(),
        label: String::new(),
        group: 0,
        tolerance: tolerance.to_string(),
        cap: if tolerance == "—" { "—" } else { "64" }.to_string(),
        ns_per_step: f64::NAN,
        iterations_per_step: f64::NAN,
        errors: shaper::errors(&[], &reference),
        failed: 0,
    };
    timed.push(Timed::new(
        shaper::Generated::<f64>::new(SolveOptions::default()),
        xs,
        row("generated f64, `tick`, closed forms (default)", "—"),
    )?);
    for (tolerance, name) in [(1e-6, "1e-6"), (1e-12, "1e-12")] {
        timed.push(Timed::new(
            shaper::Generated::<f64>::new(shaper::newton(tolerance)),
            xs,
            row(
                &format!("generated f64, `tick`, Newton (`closed_forms: false`), tolerance {name}"),
                name,
            ),
        )?);
    }
    timed.push(Timed::new(
        shaper::Generated::<f32>::new(SolveOptions::default()),
        xs,
        row("generated f32, `tick`, closed forms (default)", "—"),
    )?);
    timed.push(Timed::new(
        Engine::new(&generic, SolveOptions::default()).with_start(shaper::start()),
        xs,
        row("generic engine f64 (default)", "1e-12"),
    )?);
    let rows = measure(timed, |s| shaper::errors(s, &reference))?;
    Ok(format!(
        "Seed shaper, full turn in 1° steps (360 `tick`s, or predict and `solve` for the generic \
         engine); largest error over 0°, 10°, …, 360° against the 40-digit reference \
         (`tests/data/shaper.csv`): angles q3, q4 in rad modulo 2π, lengths s3, sE relative to the \
         larger of the largest length param ({}) and the column's largest value, rates relative to \
         the column's largest value. Time per step: median of {REPETITIONS} repetitions of about \
         {} ms, interleaved over the variants.\n\n{}\n\
         Newton iterations are block iterations summed over the shaper's blocks (0 for closed \
         forms).\n",
        shaper::largest_length_param(),
        REPETITION.as_millis(),
        table_with(&rows, "max error positions [rad, rel.]")
    ))
}
