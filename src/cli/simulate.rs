//! CLI, `mechgen simulate`: forward dynamics of one input (`mechgen::simulation` on the runtime's
//! `Simulation`), a row every `--dt`: the table (thinned to at most [`TABLE_ROWS`] rows, with the
//! energy balance) and the CSV of every row, written as it is made.

use std::fmt::Write as _;

use mechgen::report::significant;
use mechgen::simulation::{Setup, row_count, simulate};
use mechgen::sweep::plan::{Range, input_index, plan};
use mechgen::{Kind, SolveError};

use super::args::SimulateArgs;
use super::load::{Loaded, select};
use super::out::Out;

/// Rows the table shows at most (the CSV has every row).
pub const TABLE_ROWS: usize = 41;

/// Rows a simulation may write at most.
const MAX_ROWS: usize = 10_000_000;

/// `mechgen simulate NAME --time T --dt DT [options]`.
pub fn run(args: &SimulateArgs) -> Result<(), String> {
    let file = args.file.as_deref();
    let loaded = Loaded::read(file)?;
    let sel = select(&loaded, &args.name, file, args.engine)?;
    if let Some(w) = loaded.start_warning(&args.name) {
        tell_raw!("{w}");
    }
    let info = sel.solver.info();
    mechgen::kinetics::require_bodies(&info, "simulate it")?;
    let rows = row_count(args.time, args.dt, MAX_ROWS)?;
    // The input and the held values, as a sweep resolves them (a range of the start alone).
    let index = match &args.input {
        Some(n) => input_index(&info, n)?,
        None => 0,
    };
    let start = info.inputs.get(index).map_or(0.0, |c| match c.kind {
        Kind::Angle => c.start.to_degrees(),
        _ => c.start,
    });
    let range = Range {
        from: Some(start),
        to: Some(start),
        step: None,
    };
    let p = plan(&info, args.input.as_deref(), &args.set, range)?;
    let mut x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
    for &(i, v) in &p.held {
        x[i] = v;
    }
    let loads = super::dynamics::loads(&args.load, &info, info.inputs[p.index].kind)?;
    let setup = Setup {
        index: p.index,
        x: &x,
        rate: args.rate,
        effort: args.torque,
        loads: &loads,
        time: args.time,
        dt: args.dt,
    };
    let guess: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
    let input = &info.inputs[p.index];
    let per = if input.kind == Kind::Angle {
        180.0 / std::f64::consts::PI
    } else {
        1.0
    };
    let name = &input.name;
    let mut header = format!("t,{name},{name}_vel,{name}_acc");
    for u in &info.unknowns {
        let _ = write!(header, ",{}", u.name);
    }
    header.push_str(",kinetic_energy,potential_energy,status\n");
    // The CSV is written row by row (created before the first: a path that cannot be written is
    // said at once), not held: up to MAX_ROWS rows would take gigabytes.
    let mut out = match &args.csv {
        Some(path) => Some(Out::create(path, &header)?),
        None => None,
    };
    let mut csv = String::new();
    let width = 16;
    let unit = if input.kind == Kind::Angle {
        "deg"
    } else {
        "u"
    };
    let mut table = format!(
        "{}: {name} from the start{} under gravity{}, driving effort {}, {} s in rows of {} s ({rows} rows; {})\n",
        info.name,
        if args.rate == 0.0 {
            String::new()
        } else {
            format!(" (rate {} /s)", significant(args.rate))
        },
        if loads.is_empty() { "" } else { " and loads" },
        significant(args.torque),
        significant(args.time),
        significant(args.dt),
        match rows.div_ceil(TABLE_ROWS - 1).max(1) {
            1 => "every row shown".to_string(),
            n => format!("one row in {n} shown"),
        },
    );
    for h in [
        "t [s]".to_string(),
        format!("{name} [{unit}]"),
        format!("{name}_vel [{unit}/s]"),
        format!("{name}_acc [{unit}/s²]"),
        "kinetic".into(),
        "potential".into(),
        "total".into(),
    ] {
        let _ = write!(table, "{h:>width$}");
    }
    table.push('\n');
    let every = rows.div_ceil(TABLE_ROWS - 1).max(1);
    let (mut first, mut drift, mut count) = (None::<f64>, 0.0f64, 0usize);
    // The energy the drift is measured against: the start's total, or the largest kinetic
    // energy where that is larger (a potential whose zero is the start makes the total 0).
    let mut moved = 0.0f64;
    let mut stopped: Option<SolveError> = None;
    let mut held_from: Option<(f64, f64)> = None;
    simulate(sel.solver.as_ref(), &setup, &guess, &mut |r| {
        let status = r.status();
        if let Err(e) = r.status {
            stopped = Some(e);
        }
        if r.status.is_ok() {
            let total = r.kinetic + r.potential;
            let e0 = *first.get_or_insert(total);
            drift = drift.max((total - e0).abs());
            moved = moved.max(r.kinetic.abs());
        }
        if let Some(out) = out.as_mut() {
            csv.clear();
            let _ = write!(csv, "{:?}", r.t);
            if r.status.is_ok() {
                for v in r.input {
                    let _ = write!(csv, ",{v:?}");
                }
                for q in &r.q {
                    let _ = write!(csv, ",{q:?}");
                }
                let _ = writeln!(csv, ",{:?},{:?},{status}", r.kinetic, r.potential);
            } else {
                for _ in 0..3 + r.q.len() + 2 {
                    csv.push(',');
                }
                let _ = writeln!(csv, ",{status}");
            }
            out.write(csv.as_bytes());
        }
        let last = count + 1 == rows || r.status.is_err();
        if count.is_multiple_of(every) || last {
            let _ = write!(table, "{:>width$}", significant(r.t));
            if r.status.is_ok() {
                let [x, v, a] = r.input;
                for value in [x * per, v * per, a * per, r.kinetic, r.potential] {
                    let _ = write!(table, "{:>width$}", significant(value));
                }
                let _ = write!(table, "{:>width$}", significant(r.kinetic + r.potential));
                if r.held {
                    let _ = write!(table, "  {status}");
                }
            } else {
                let _ = write!(
                    table,
                    "  {status}: {}",
                    r.status.err().map_or(String::new(), |e| e.to_string())
                );
            }
            table.push('\n');
        }
        if r.held && held_from.is_none() {
            held_from = Some((r.t, r.input[0] * per));
        }
        count += 1;
    })?;
    if let Some((t, x)) = held_from {
        let _ = writeln!(
            table,
            "from t = {} the input rests at {} on the edge of a load's range: the forces on both sides push into it (rows `at-load-edge`)",
            significant(t),
            significant(x)
        );
    }
    if let Some(e0) = first {
        let _ = writeln!(
            table,
            "largest change of kinetic + potential energy: {}{}{}",
            significant(drift),
            relative(drift, e0.abs().max(moved)),
            if args.torque != 0.0 || !loads.is_empty() {
                " (the driving effort and the loads do work)"
            } else {
                ""
            }
        );
    }
    say_raw!("{table}");
    if let Some(out) = out {
        out.finish()?;
    }
    match stopped {
        Some(e) => {
            tell!("mechgen: {}: the simulation stopped: {e}", info.name);
            Ok(())
        }
        None => Ok(()),
    }
}

/// ` (R of …)`: the energy drift against its scale, the larger of the start's total and the
/// largest kinetic energy (nothing where both are 0: the mechanism stayed at rest at zero energy).
fn relative(drift: f64, scale: f64) -> String {
    if scale > 0.0 {
        format!(
            " ({} of the larger of the start's total and the largest kinetic energy)",
            significant(drift / scale)
        )
    } else {
        String::new()
    }
}
