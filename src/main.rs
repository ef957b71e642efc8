//! The `mechgen` command: `sweep`, `check`, and with no arguments the main job (every compiled-in
//! mechanism swept over a full turn, tables printed, CSVs and plots written to `mechgen-out/`).

#[macro_use]
mod cli;

use std::path::Path;
use std::process::ExitCode;

use cli::options::{Options, sweep_values};
use mechgen::generic::{self, Generic};
use mechgen::sweep::{Continuation, Row, sweep};
use mechgen::{Kind, Kinematics, MechanismInfo, report};

pub const USAGE: &str = "usage:
  mechgen                         sweep every compiled-in mechanism: tables, CSVs and plots in ./mechgen-out
  mechgen sweep NAME [--file PATH] [--engine generated|generic] [--from X --to X --step X]
                     [--rate V] [--csv PATH] [--plot DIR]
  mechgen check [--file PATH]     validate a mechanism file and print its structure";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        None => main_job(),
        Some("sweep") => run_sweep(&args[1..]),
        Some("check") => run_check(&args[1..]),
        Some("-h" | "--help" | "help") => {
            say!("{USAGE}");
            Ok(())
        }
        Some(other) => Err(format!("unknown command `{other}`\n{USAGE}")),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("mechgen: {msg}");
            ExitCode::FAILURE
        }
    }
}

/// The mechanism to sweep: its solvers, and the generic engine of the same file (for drawings).
struct Selected {
    solver: Box<dyn Kinematics<f64>>,
    model: Generic,
}

/// Loads every mechanism of a file (or of the compiled-in file) for the generic engine.
fn load(path: Option<&str>) -> Result<Vec<Generic>, String> {
    match path {
        Some(p) => generic::load_file(Path::new(p)).map_err(|e| e.to_string()),
        None => generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
            .map_err(|e| e.to_string()),
    }
}

fn select(name: &str, opts: &Options) -> Result<Selected, String> {
    let file = opts.get("file");
    let engine = match opts.get("engine") {
        None if file.is_some() => "generic",
        None => "generated",
        Some(e @ ("generated" | "generic")) => e,
        Some(e) => return Err(format!("unknown engine `{e}` (generated or generic)")),
    };
    if file.is_some() && engine == "generated" {
        return Err(
            "--engine generated exists only for compiled-in mechanisms; use --engine generic with --file"
                .into(),
        );
    }
    let mechs = load(file)?;
    let available = || {
        mechs
            .iter()
            .map(Generic::name)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let model = mechs
        .iter()
        .find(|m| m.name() == name)
        .cloned()
        .ok_or_else(|| {
            format!(
                "no mechanism `{name}` in {} (it has: {})",
                file.unwrap_or(mechgen::source::SOURCE_NAME),
                available()
            )
        })?;
    let solver: Box<dyn Kinematics<f64>> = if engine == "generic" {
        Box::new(model.clone())
    } else {
        mechgen::lookup::<f64>(name).ok_or_else(|| format!("no compiled-in mechanism `{name}`"))?
    };
    Ok(Selected { solver, model })
}

fn run_sweep(args: &[String]) -> Result<(), String> {
    let opts = Options::parse(
        args,
        &[
            "file", "engine", "from", "to", "step", "rate", "csv", "plot",
        ],
    )?;
    let [name] = opts.positional.as_slice() else {
        return Err(format!("sweep takes one mechanism name\n{USAGE}"));
    };
    let sel = select(name, &opts)?;
    let info = sel.solver.info();
    let rows = sweep_mechanism(sel.solver.as_ref(), &info, &opts)?;
    say_raw!(
        "{} ({} rows)\n{}",
        info.name,
        rows.len(),
        report::table(&info, 0, &rows)
    );
    if let Some(path) = opts.get("csv") {
        std::fs::write(path, report::csv(&info, 0, &rows))
            .map_err(|e| format!("cannot write {path}: {e}"))?;
    }
    if let Some(dir) = opts.get("plot") {
        let written = cli::plots::write(Path::new(dir), &sel.model, &info, &rows)?;
        for p in written {
            eprintln!("wrote {}", p.display());
        }
    }
    Ok(())
}

/// Runs the sweep the options describe (defaults per interfaces.md).
fn sweep_mechanism(
    k: &dyn Kinematics<f64>,
    info: &MechanismInfo,
    opts: &Options,
) -> Result<Vec<Row>, String> {
    let (_, kind, _) = info.inputs.first().ok_or("mechanism has no input")?;
    let (from, to, step) = (
        opts.number("from")?,
        opts.number("to")?,
        opts.number("step")?,
    );
    let (from, to, step) = match kind {
        Kind::Angle => (
            from.unwrap_or(0.0),
            to.unwrap_or(360.0),
            step.unwrap_or(10.0),
        ),
        Kind::Length => match (from, to) {
            (Some(f), Some(t)) => (f, t, step.unwrap_or((t - f) / 36.0)),
            _ => return Err("--from and --to are required for a length input".into()),
        },
    };
    let rate = opts.number("rate")?.unwrap_or(1.0);
    let mut values = sweep_values(from, to, if step == 0.0 && from == to { 1.0 } else { step })?;
    if *kind == Kind::Angle {
        values.iter_mut().for_each(|v| *v = v.to_radians());
    }
    let span = if *kind == Kind::Angle {
        (to - from).to_radians()
    } else {
        to - from
    };
    let continuation = Continuation::for_input(*kind, span);
    Ok(sweep(k, 0, &values, rate, &continuation))
}

fn run_check(args: &[String]) -> Result<(), String> {
    let opts = Options::parse(args, &["file"])?;
    if !opts.positional.is_empty() {
        return Err(format!("check takes no positional arguments\n{USAGE}"));
    }
    match opts.get("file") {
        Some(path) => {
            let text =
                std::fs::read_to_string(path).map_err(|e| format!("cannot read {path}: {e}"))?;
            cli::check::check(path, &text)
        }
        None => cli::check::check(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE),
    }
}

/// The main job's sweep: a full turn for an angle input (the `sweep` defaults); for a length
/// input, which has no default range, its start value ± a quarter of the mechanism's length
/// scale (or of the start value, if larger), in 36 steps.
fn main_job_range(info: &MechanismInfo) -> Options {
    let Some((_, Kind::Length, start)) = info.inputs.first() else {
        return Options::none();
    };
    let scale = info
        .params
        .iter()
        .filter(|p| p.1 == Kind::Length)
        .fold(start.abs(), |m, p| m.max(p.2.abs()));
    let half = if scale > 0.0 { scale / 4.0 } else { 1.0 };
    let args: Vec<String> = [
        ("--from", start - half),
        ("--to", start + half),
        ("--step", half / 18.0),
    ]
    .iter()
    .flat_map(|(k, v)| [k.to_string(), v.to_string()])
    .collect();
    Options::parse(&args, &["from", "to", "step"]).unwrap_or_else(|_| Options::none())
}

fn main_job() -> Result<(), String> {
    let dir = Path::new("mechgen-out");
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let none = Options::none();
    for name in mechgen::MECHANISMS {
        let sel = select(name, &none)?;
        let info = sel.solver.info();
        let rows = sweep_mechanism(sel.solver.as_ref(), &info, &main_job_range(&info))?;
        say!("{} — {}", info.name, info.description);
        say!("{}", report::table(&info, 0, &rows));
        let path = dir.join(format!("{name}.csv"));
        std::fs::write(&path, report::csv(&info, 0, &rows))
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        cli::plots::write(dir, &sel.model, &info, &rows)?;
    }
    say!(
        "CSV files and plots written to {}/ (one CSV, a motion plot and a drawing per mechanism)",
        dir.display()
    );
    Ok(())
}
