//! CLI, design derivatives along a sweep: `mechgen sensitivity` (every d(output)/dp per row)
//! and `mechgen tolerance` (each output's worst-case and root-sum-square deviation for param
//! tolerances), on [`mechgen::design`]; the sweep is `sweep`'s, with its options.

use std::fmt::Write as _;

use mechgen::design::{self, Deviation, outputs, row_inputs};
use mechgen::report::significant;
use mechgen::{Kind, MechanismInfo};

use super::args::{SensitivityArgs, SweepOptions, ToleranceArgs};
use super::load::{Loaded, Selected, Swept, run_plan, select};
use mechgen::sweep::plan::{Range, plan};

/// Degrees per radian for an angle, 1 for a length.
fn per_unit(kind: Kind) -> f64 {
    if kind == Kind::Angle {
        180.0 / std::f64::consts::PI
    } else {
        1.0
    }
}

/// The unit word of a kind in tables: `deg`, or `u` for the file's length unit (as the sweep's
/// tables write it).
fn unit(kind: Kind) -> &'static str {
    if kind == Kind::Angle { "deg" } else { "u" }
}

/// The sweep `options` ask for, every row kept.
fn swept(options: &SweepOptions) -> Result<(Selected, MechanismInfo, Swept), String> {
    let file = options.file.as_deref();
    let loaded = Loaded::read(file)?;
    let sel = select(&loaded, &options.name, file, options.engine)?;
    if let Some(w) = loaded.start_warning(&options.name) {
        tell_raw!("{w}");
    }
    let info = sel.solver.info();
    let range = Range {
        from: options.from,
        to: options.to,
        step: options.step,
    };
    let plan = plan(&info, options.input.as_deref(), &options.set, range)?;
    let swept = run_plan(sel.solver.as_ref(), &info, plan, options.rate)?;
    Ok((sel, info, swept))
}

/// Each row's input and its sensitivity (row-major: outputs × params), or its status.
fn rows(
    sel: &Selected,
    info: &MechanismInfo,
    swept: &Swept,
) -> Vec<(f64, Result<Vec<f64>, String>)> {
    let index = swept.plan.index;
    swept
        .rows
        .iter()
        .map(|r| {
            let s = match &r.result {
                Ok(s) => {
                    let x = row_inputs(info, index, &swept.plan.held, r.input);
                    design::sensitivity(sel.solver.as_ref(), info, &x, &s.q)
                        .map_err(|e| e.status().to_string())
                }
                Err(_) => Err(r.status().to_string()),
            };
            (r.input, s)
        })
        .collect()
}

fn write_csv(path: &std::path::Path, text: &str) -> Result<(), String> {
    std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// `mechgen sensitivity NAME [options]`.
pub fn sensitivity(args: &SensitivityArgs) -> Result<(), String> {
    let (sel, info, swept) = swept(&args.sweep)?;
    let index = swept.plan.index;
    let input = &info.inputs[index];
    let outs = outputs(&info);
    let npar = info.params.len();
    let mut head = vec![format!("{} [{}]", input.name, unit(input.kind))];
    let mut csv = input.name.clone();
    for (o, ok) in &outs {
        for p in &info.params {
            head.push(format!("{o}/{} [{}/{}]", p.name, unit(*ok), unit(p.kind)));
            let _ = write!(csv, ",{o}/{}", p.name);
        }
    }
    csv.push_str(",status\n");
    let width = head.iter().map(String::len).max().unwrap_or(0).max(13) + 1;
    let mut table = format!(
        "{}: d(output)/d(param) along {} ({} rows; angles in degrees)\n",
        info.name,
        input.name,
        swept.rows.len()
    );
    for h in &head {
        let _ = write!(table, "{h:>width$}");
    }
    table.push('\n');
    for (x, s) in rows(&sel, &info, &swept) {
        let _ = write!(table, "{:>width$}", significant(x * per_unit(input.kind)));
        let _ = write!(csv, "{x:?}");
        match s {
            Ok(s) => {
                for (o, row) in outs.iter().zip(s.chunks_exact(npar.max(1))) {
                    for (p, v) in info.params.iter().zip(row) {
                        let scaled = v * per_unit(o.1) / per_unit(p.kind);
                        let _ = write!(table, "{:>width$}", significant(scaled));
                        let _ = write!(csv, ",{v:?}");
                    }
                }
                csv.push_str(",ok\n");
            }
            Err(status) => {
                let _ = write!(table, "  {status}");
                csv.push_str(&",".repeat(outs.len() * npar));
                let _ = writeln!(csv, ",{status}");
            }
        }
        table.push('\n');
    }
    say_raw!("{table}");
    match &args.csv {
        Some(path) => write_csv(path, &csv),
        None => Ok(()),
    }
}

/// `mechgen tolerance NAME --tol p=T ... [options]`.
pub fn tolerance(args: &ToleranceArgs) -> Result<(), String> {
    let (sel, info, swept) = swept(&args.sweep)?;
    let mut tolerances = Vec::new();
    for (name, t) in &args.tol {
        let p = info
            .params
            .iter()
            .position(|p| &p.name == name)
            .ok_or_else(|| {
                let names: Vec<&str> = info.params.iter().map(|p| p.name.as_str()).collect();
                format!(
                    "--tol {name}=…: `{}` has no param `{name}` (its params: {})",
                    info.name,
                    names.join(", ")
                )
            })?;
        tolerances.push((p, t.abs() / per_unit(info.params[p].kind)));
    }
    let input = &info.inputs[swept.plan.index];
    let outs = outputs(&info);
    let npar = info.params.len();
    let mut csv = input.name.clone();
    for (o, _) in &outs {
        let _ = write!(csv, ",{o}_worst,{o}_rss");
    }
    csv.push_str(",status\n");
    // Per output: its largest worst-case deviation, the RSS there and the input of that row.
    let mut worst: Vec<Option<(Deviation, f64)>> = vec![None; outs.len()];
    for (x, s) in rows(&sel, &info, &swept) {
        let _ = write!(csv, "{x:?}");
        match s {
            Ok(s) => {
                let d = design::deviations(&s, npar, &tolerances);
                for (w, d) in worst.iter_mut().zip(&d) {
                    let _ = write!(csv, ",{:?},{:?}", d.worst, d.rss);
                    if w.is_none_or(|(b, _)| d.worst > b.worst) {
                        *w = Some((*d, x));
                    }
                }
                csv.push_str(",ok\n");
            }
            Err(status) => {
                csv.push_str(&",".repeat(2 * outs.len()));
                let _ = writeln!(csv, ",{status}");
            }
        }
    }
    let tols: Vec<String> = args.tol.iter().map(|(n, t)| format!("{n} ± {t}")).collect();
    let mut table = format!(
        "{}: deviations for {} along {} ({} rows), at each output's worst row\n{:<20}{:>16}{:>16}{:>16}\n",
        info.name,
        tols.join(", "),
        input.name,
        swept.rows.len(),
        "output",
        "worst case",
        "rss",
        format!("at {} [{}]", input.name, unit(input.kind)),
    );
    for ((o, kind), w) in outs.iter().zip(&worst) {
        let name = format!("{o} [{}]", unit(*kind));
        let _ = match w {
            Some((d, x)) => writeln!(
                table,
                "{name:<20}{:>16}{:>16}{:>16}",
                significant(d.worst * per_unit(*kind)),
                significant(d.rss * per_unit(*kind)),
                significant(x * per_unit(input.kind))
            ),
            None => writeln!(table, "{name:<20}  no row solved"),
        };
    }
    say_raw!("{table}");
    match &args.csv {
        Some(path) => write_csv(path, &csv),
        None => Ok(()),
    }
}
