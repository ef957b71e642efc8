//! CLI, `mechgen metrics NAME`: loads the file (compiled-in or `--file`), picks the engine, sweeps
//! the start's branch over a full turn of an angle input (or `--from/--to`) in 0.5° steps (720
//! rows of a length input's range) and prints [`mechgen::metrics`]: a table with units and the
//! CSV of interfaces.md.

use std::fmt::Write as _;

use mechgen::metrics::{OutputMetrics, metrics, rrr_links};
use mechgen::{Kind, MechanismInfo};

use super::args::MetricsArgs;
use super::load::{Loaded, select};
use mechgen::sweep::plan::{Range, input_index, plan};

/// Rows of the sweep the extremes are refined between.
const ROWS: f64 = 720.0;

pub fn run(args: &MetricsArgs) -> Result<(), String> {
    let file = args.file.as_deref();
    let loaded = Loaded::read(file)?;
    let sel = select(&loaded, &args.name, file, args.engine)?;
    if let Some(w) = loaded.start_warning(&args.name) {
        tell_raw!("{w}");
    }
    let info = sel.solver.info();
    let index = match &args.input {
        Some(n) => input_index(&info, n)?,
        None => 0,
    };
    let angle = info.inputs.get(index).map(|i| i.kind) == Some(Kind::Angle);
    let mut dead_ends = Vec::new();
    let (from, to) = match (angle, args.from, args.to) {
        (true, None, None) if index == 0 && args.set.is_empty() => {
            let r = angle_range(&info, file);
            dead_ends = r.dead_ends;
            r.span
        }
        (true, from, to) => {
            let from = from.unwrap_or_else(|| info.inputs[index].start.to_degrees());
            (from, to.unwrap_or(from + 360.0))
        }
        (false, Some(f), Some(t)) => (f, t),
        (false, _, _) => {
            return Err(format!(
                "`{}` has a length input ({}): --from and --to are required",
                info.name, info.inputs[index].name
            ));
        }
    };
    let plan = plan(&info, args.input.as_deref(), &args.set, range_of(from, to))?;
    let full_turn = angle && ((to - from).abs() - 360.0).abs() < 1e-9;
    let rows = compute(
        sel.solver.as_ref(),
        file,
        &args.name,
        &plan,
        full_turn,
        &dead_ends,
    )?;
    say_raw!("{}", table(&info, plan.index, &rows));
    if let Some(path) = &args.csv {
        std::fs::write(path, csv(&rows))
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    Ok(())
}

/// The default range of the first input, an angle (degrees): the start's branch between its
/// dead points where it has them (each end moved inside by 1e-6 of the span), else a full turn
/// from the start.
pub(super) fn angle_range(info: &MechanismInfo, file: Option<&std::path::Path>) -> AngleRange {
    match super::branches::start_branch(file, &info.name) {
        Some(b) => {
            let (a, c) = (b.from.to_degrees(), b.to.to_degrees());
            let inset = (c - a) * 1e-6;
            AngleRange {
                span: (a + inset, c - inset),
                dead_ends: b.ends,
            }
        }
        None => {
            let from = info.inputs[0].start.to_degrees();
            AngleRange {
                span: (from, from + 360.0),
                dead_ends: Vec::new(),
            }
        }
    }
}

/// An angle input's default metrics range: `span` in degrees, and the dead points' states
/// (radians) that end it, if any.
pub(super) struct AngleRange {
    pub span: (f64, f64),
    pub dead_ends: Vec<(f64, Vec<f64>)>,
}

/// The range in [`ROWS`] steps (degrees or file units).
fn range_of(from: f64, to: f64) -> Range {
    Range {
        from: Some(from),
        to: Some(to),
        step: Some(((to - from) / ROWS).abs()),
    }
}

/// The metrics of `plan`'s sweep, with the RRR blocks of the file's analysis.
fn compute(
    k: &dyn mechgen::DynMechanism<f64>,
    file: Option<&std::path::Path>,
    name: &str,
    plan: &mechgen::sweep::plan::Plan,
    full_turn: bool,
    dead_ends: &[(f64, Vec<f64>)],
) -> Result<Vec<OutputMetrics>, String> {
    let compiled = super::branches::compile(file)?;
    let rrr = compiled
        .iter()
        .find(|c| c.model.name.text == name)
        .map(rrr_links)
        .unwrap_or_default();
    Ok(metrics(
        k,
        plan.index,
        &plan.values,
        &plan.held,
        full_turn,
        &rrr,
        dead_ends,
    ))
}

/// The main job's metrics of one mechanism, over its range (`from`, `to` in CLI units: an angle
/// input's [`angle_range`], a length input's start branch).
pub(super) fn main_job_table(
    k: &dyn mechgen::DynMechanism<f64>,
    info: &MechanismInfo,
    file: Option<&std::path::Path>,
    (from, to): (f64, f64),
    dead_ends: &[(f64, Vec<f64>)],
) -> Result<String, String> {
    let plan = plan(info, None, &[], range_of(from, to))?;
    let angle = info.inputs.first().map(|i| i.kind) == Some(Kind::Angle);
    let full_turn = angle && ((to - from).abs() - 360.0).abs() < 1e-9;
    let rows = compute(k, file, &info.name, &plan, full_turn, dead_ends)?;
    Ok(table(info, plan.index, &rows))
}

/// The metrics table: degrees for angles, file units for lengths.
pub fn table(info: &MechanismInfo, index: usize, rows: &[OutputMetrics]) -> String {
    let input = &info.inputs[index];
    let (iu, ik) = unit(input.kind);
    let mut out = format!(
        "{}: metrics on the start's branch along {} [{iu}]\n{:<24}{:>16}{:>16}{:>16}{:>16}{:>12}\n",
        info.name, input.name, "output", "min", "max", "at min", "at max", "time ratio"
    );
    for r in rows {
        let (u, k) = unit(r.kind);
        let at = |x: Option<f64>| x.map_or("-".to_string(), |x| fixed(x * ik, 6));
        let _ = writeln!(
            out,
            "{:<24}{:>16}{:>16}{:>16}{:>16}{:>12}",
            format!("{} [{u}]", r.name),
            fixed(r.min * k, 8),
            fixed(r.max * k, 8),
            at(r.input_at_min),
            at(r.input_at_max),
            r.time_ratio.map_or("-".to_string(), |t| format!("{t:.6}")),
        );
    }
    out
}

/// `v` with `digits` decimals, without the sign of a value that prints as zero (`-0.000000`).
fn fixed(v: f64, digits: usize) -> String {
    let s = format!("{v:.digits$}");
    match s.strip_prefix('-') {
        Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_string(),
        _ => s,
    }
}

fn unit(k: Kind) -> (&'static str, f64) {
    match k {
        Kind::Angle => ("deg", 180.0 / std::f64::consts::PI),
        _ => ("u", 1.0),
    }
}

/// `output,min,max,input_at_min,input_at_max,time_ratio` (radians; empty where undefined; a
/// name with a comma quoted).
pub fn csv(rows: &[OutputMetrics]) -> String {
    let mut out = String::from("output,min,max,input_at_min,input_at_max,time_ratio\n");
    let opt = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x:?}"));
    for r in rows {
        // `transmission(qa,qb)` holds a comma: quoted, as CSV quotes such a field.
        let name = if r.name.contains(',') {
            format!("\"{}\"", r.name)
        } else {
            r.name.clone()
        };
        let _ = writeln!(
            out,
            "{},{:?},{:?},{},{},{}",
            name,
            r.min,
            r.max,
            opt(r.input_at_min),
            opt(r.input_at_max),
            opt(r.time_ratio)
        );
    }
    out
}
