//! The `mechgen` command: `sweep`, `check`, and with no arguments the main job (every compiled-in
//! mechanism swept over a full turn, tables printed, CSVs written).

use std::process::ExitCode;

use mechgen::sweep::{Continuation, sweep};
use mechgen::{Kind, Kinematics, MechanismInfo, report};

const USAGE: &str = "usage:
  mechgen                         sweep every compiled-in mechanism, print tables, write CSVs to ./mechgen-out
  mechgen sweep NAME [--file PATH] [--engine generated|generic] [--from X --to X --step X] [--rate V] [--csv PATH]
  mechgen check [--file PATH]     validate a mechanism file and print its structure";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        None => main_job(),
        Some("sweep") => run_sweep(&args[1..]),
        Some("check") => run_check(&args[1..]),
        Some("-h" | "--help" | "help") => {
            println!("{USAGE}");
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

/// `--name value` options.
struct Options {
    pairs: Vec<(String, String)>,
    positional: Vec<String>,
}

impl Options {
    fn parse(args: &[String], known: &[&str]) -> Result<Options, String> {
        let (mut pairs, mut positional) = (Vec::new(), Vec::new());
        let mut it = args.iter();
        while let Some(a) = it.next() {
            if let Some(name) = a.strip_prefix("--") {
                if !known.contains(&name) {
                    return Err(format!("unknown option `{a}`\n{USAGE}"));
                }
                let v = it
                    .next()
                    .ok_or_else(|| format!("option `{a}` needs a value"))?;
                pairs.push((name.to_string(), v.clone()));
            } else {
                positional.push(a.clone());
            }
        }
        Ok(Options { pairs, positional })
    }

    fn get(&self, name: &str) -> Option<&str> {
        self.pairs
            .iter()
            .rev()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    fn number(&self, name: &str) -> Result<Option<f64>, String> {
        match self.get(name) {
            None => Ok(None),
            Some(v) => match v.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(Some(x)),
                _ => Err(format!("--{name} needs a finite number, got `{v}`")),
            },
        }
    }
}

/// The input values of a sweep, both ends included, in sweep units.
fn sweep_values(from: f64, to: f64, step: f64) -> Result<Vec<f64>, String> {
    if step == 0.0 {
        return Err("--step must not be zero".into());
    }
    let n = ((to - from) / step.abs().copysign(to - from)).abs();
    if n > 10_000_000.0 {
        return Err("too many sweep rows (more than 10 000 000)".into());
    }
    let count = (n + 1e-9).floor() as usize;
    let dir = if to >= from { 1.0 } else { -1.0 };
    let mut v: Vec<f64> = (0..=count)
        .map(|i| from + dir * step.abs() * i as f64)
        .collect();
    if (to - v[v.len() - 1]).abs() > 1e-9 * step.abs() {
        v.push(to);
    } else if let Some(last) = v.last_mut() {
        *last = to;
    }
    Ok(v)
}

fn engine_for(name: &str, opts: &Options) -> Result<Box<dyn Kinematics<f64>>, String> {
    let engine = opts.get("engine");
    if opts.get("file").is_some() || engine == Some("generic") {
        return Err("the generic engine (--file, --engine generic) is not built yet".into());
    }
    if let Some(e) = engine
        && e != "generated"
    {
        return Err(format!("unknown engine `{e}` (generated or generic)"));
    }
    mechgen::lookup::<f64>(name).ok_or_else(|| {
        format!(
            "no compiled-in mechanism `{name}` (compiled in: {})",
            mechgen::MECHANISMS.join(", ")
        )
    })
}

fn run_sweep(args: &[String]) -> Result<(), String> {
    let opts = Options::parse(
        args,
        &["file", "engine", "from", "to", "step", "rate", "csv"],
    )?;
    let [name] = opts.positional.as_slice() else {
        return Err(format!("sweep takes one mechanism name\n{USAGE}"));
    };
    let k = engine_for(name, &opts)?;
    let info = k.info();
    let (rows_text, csv_text) = sweep_mechanism(k.as_ref(), &info, &opts)?;
    print!("{rows_text}");
    if let Some(path) = opts.get("csv") {
        std::fs::write(path, csv_text).map_err(|e| format!("cannot write {path}: {e}"))?;
    }
    Ok(())
}

fn sweep_mechanism(
    k: &dyn Kinematics<f64>,
    info: &MechanismInfo,
    opts: &Options,
) -> Result<(String, String), String> {
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
    let mut values = sweep_values(from, to, step)?;
    if *kind == Kind::Angle {
        values.iter_mut().for_each(|v| *v = v.to_radians());
    }
    let continuation = Continuation::for_input(*kind, to - from);
    let rows = sweep(k, 0, &values, rate, &continuation);
    let mut text = format!("{} ({} rows)\n", info.name, rows.len());
    text.push_str(&report::table(info, 0, &rows));
    Ok((text, report::csv(info, 0, &rows)))
}

fn run_check(args: &[String]) -> Result<(), String> {
    let opts = Options::parse(args, &["file"])?;
    if !opts.positional.is_empty() {
        return Err(format!("check takes no positional arguments\n{USAGE}"));
    }
    let (name, text) = match opts.get("file") {
        Some(path) => (
            path.to_string(),
            std::fs::read_to_string(path).map_err(|e| format!("cannot read {path}: {e}"))?,
        ),
        None => ("mechanism.toml (compiled in)".to_string(), String::new()),
    };
    if opts.get("file").is_none() {
        for n in mechgen::MECHANISMS {
            if let Some(k) = mechgen::lookup::<f64>(n) {
                print_structure(&k.info());
            }
        }
        return Ok(());
    }
    let file = mechgen_codegen::SourceFile::new(name, text);
    let (mechs, diags) = mechgen_codegen::analyze(&file);
    let rendered = mechgen_codegen::diagnostic::render(&file, &diags);
    if diags.iter().any(|d| d.is_error()) {
        eprint!("{rendered}");
        return Err(format!(
            "{}: {} error(s)",
            file.name,
            diags.iter().filter(|d| d.is_error()).count()
        ));
    }
    eprint!("{rendered}");
    for m in &mechs {
        let info = MechanismInfo {
            name: m.model.name.text.clone(),
            description: m.model.description.clone(),
            inputs: m
                .model
                .inputs
                .iter()
                .map(|c| (c.name.text.clone(), kind(c.kind), c.start))
                .collect(),
            unknowns: m
                .model
                .unknowns
                .iter()
                .map(|c| (c.name.text.clone(), kind(c.kind), c.start))
                .collect(),
            params: m
                .model
                .params
                .iter()
                .map(|p| (p.name.text.clone(), kind(p.kind), p.value))
                .collect(),
            points: m.model.points.iter().map(|p| p.0.text.clone()).collect(),
            blocks: m.blocks.iter().map(|b| b.block.unknowns.clone()).collect(),
        };
        print_structure(&info);
    }
    Ok(())
}

fn kind(k: mechgen_codegen::check::Kind) -> Kind {
    match k {
        mechgen_codegen::check::Kind::Angle => Kind::Angle,
        mechgen_codegen::check::Kind::Length => Kind::Length,
    }
}

fn print_structure(info: &MechanismInfo) {
    let names = |v: &[(String, Kind, f64)]| {
        v.iter()
            .map(|(n, k, _)| {
                format!(
                    "{n} ({})",
                    if *k == Kind::Angle { "angle" } else { "length" }
                )
            })
            .collect::<Vec<_>>()
    };
    println!("mechanism {}: {}", info.name, info.description);
    println!("  inputs:   {}", names(&info.inputs).join(", "));
    println!("  unknowns: {}", names(&info.unknowns).join(", "));
    println!("  params:   {}", info.params.len());
    println!("  points:   {}", info.points.join(", "));
    let blocks: Vec<String> = info
        .blocks
        .iter()
        .map(|b| {
            let us: Vec<&str> = b.iter().map(|&u| info.unknowns[u].0.as_str()).collect();
            format!("{}x{} [{}]", b.len(), b.len(), us.join(", "))
        })
        .collect();
    println!("  blocks:   {}", blocks.join(" -> "));
}

fn main_job() -> Result<(), String> {
    let dir = std::path::Path::new("mechgen-out");
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let no_opts = Options {
        pairs: vec![],
        positional: vec![],
    };
    for name in mechgen::MECHANISMS {
        let k = engine_for(name, &no_opts)?;
        let info = k.info();
        let (text, csv) = sweep_mechanism(k.as_ref(), &info, &no_opts)?;
        println!("{text}");
        let path = dir.join(format!("{name}.csv"));
        std::fs::write(&path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    println!("CSV files written to {}/", dir.display());
    Ok(())
}
