//! CLI, running things: loading a file (with its start warnings), choosing the engine, `sweep`
//! (table, CSV, plots) and the main job. Sits between [`super::args`] and [`mechgen::sweep`].

use std::path::{Path, PathBuf};

use mechgen::generic::Generic;
use mechgen::sweep::{Continuation, Row, check_start, sweep_holding};
use mechgen::{CoordDesc, DynMechanism, Kind, MechanismInfo, report};
use mechgen_codegen::diagnostic::{Diagnostic, Severity, SourceFile, render};

use super::args::{Engine, MainArgs, SweepArgs};
use super::options::{Plan, Range, plan};

/// A mechanism file, analysed: every mechanism for the generic engine and the file's warnings.
pub struct Loaded {
    pub mechs: Vec<Generic>,
    file: SourceFile,
    warnings: Vec<Diagnostic>,
}

impl Loaded {
    /// The file at `path`, or the compiled-in file (`mechgen::source`).
    pub fn read(path: Option<&Path>) -> Result<Loaded, String> {
        let (name, text) = match path {
            Some(p) => (
                p.display().to_string(),
                std::fs::read_to_string(p)
                    .map_err(|e| format!("cannot read {}: {e}", p.display()))?,
            ),
            None => (
                mechgen::source::SOURCE_NAME.to_string(),
                mechgen::source::SOURCE.to_string(),
            ),
        };
        let file = SourceFile::new(name, text);
        let (compiled, diagnostics) = mechgen_codegen::analyze(&file);
        if diagnostics.iter().any(Diagnostic::is_error) {
            let n = diagnostics.iter().filter(|d| d.is_error()).count();
            let rendered = render(&file, &diagnostics);
            return Err(format!(
                "{}\n{}: {n} error(s)",
                rendered.trim_end(),
                file.name
            ));
        }
        Ok(Loaded {
            mechs: compiled.iter().map(Generic::new).collect(),
            file,
            warnings: diagnostics
                .into_iter()
                .filter(|d| d.severity == Severity::Warning)
                .collect(),
        })
    }

    /// The start check's warning for mechanism `name` (as `mechgen check` prints it), if any:
    /// its start did not close the loops and Newton converged somewhere, maybe on another branch.
    pub fn start_warning(&self, name: &str) -> Option<String> {
        let prefix = format!("start configuration of `{name}`");
        let mine: Vec<Diagnostic> = self
            .warnings
            .iter()
            .filter(|d| d.message.starts_with(&prefix))
            .cloned()
            .collect();
        (!mine.is_empty()).then(|| render(&self.file, &mine))
    }
}

/// The mechanism to sweep: its solvers, and the generic engine of the same file (for drawings).
pub struct Selected {
    pub solver: Box<dyn DynMechanism<f64>>,
    pub model: Generic,
}

/// Mechanism `name` of `loaded` with the engine asked for (generated only for the compiled-in file).
pub(super) fn select(
    loaded: &Loaded,
    name: &str,
    file: Option<&Path>,
    engine: Option<Engine>,
) -> Result<Selected, String> {
    let engine = engine.unwrap_or(if file.is_some() {
        Engine::Generic
    } else {
        Engine::Generated
    });
    if file.is_some() && engine == Engine::Generated {
        return Err(
            "--engine generated exists only for compiled-in mechanisms; use --engine generic with --file"
                .into(),
        );
    }
    let model = loaded
        .mechs
        .iter()
        .find(|m| m.name() == name)
        .cloned()
        .ok_or_else(|| {
            let names: Vec<&str> = loaded.mechs.iter().map(Generic::name).collect();
            format!(
                "no mechanism `{name}` in {} (it has: {})",
                loaded.file.name,
                names.join(", ")
            )
        })?;
    let solver: Box<dyn DynMechanism<f64>> = match engine {
        Engine::Generic => Box::new(model.clone()),
        Engine::Generated => mechgen::lookup::<f64>(name)
            .ok_or_else(|| format!("no compiled-in mechanism `{name}`"))?,
    };
    Ok(Selected { solver, model })
}

/// A finished sweep: the plan it ran and its rows.
pub(super) struct Swept {
    pub(super) plan: Plan,
    pub(super) rate: f64,
    pub(super) rows: Vec<Row>,
}

impl Swept {
    /// Every input's value during the sweep (the swept one at its start value).
    pub(super) fn inputs(&self, info: &MechanismInfo) -> Vec<f64> {
        let mut x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
        for &(i, v) in &self.plan.held {
            x[i] = v;
        }
        x
    }

    /// The table with its preamble (units, rate, held inputs, a note on the last row).
    fn table(&self, info: &MechanismInfo) -> String {
        let mut out = report::preamble(info, self.plan.index, self.rate, &self.inputs(info));
        if let Some(note) = &self.plan.note {
            out.push_str(note);
            out.push('\n');
        }
        out + &report::table(info, self.plan.index, &self.rows)
    }
}

/// Runs the sweep that `plan` describes on `k`, after the start checks.
pub(super) fn run_plan(
    k: &dyn DynMechanism<f64>,
    info: &MechanismInfo,
    plan: Plan,
    rate: f64,
) -> Result<Swept, String> {
    check_start(info).map_err(|e| format!("{}: {e}", info.name))?;
    let kind = info.inputs[plan.index].kind;
    let continuation = Continuation::for_input(kind, plan.span);
    let rows = sweep_holding(k, plan.index, &plan.values, rate, &plan.held, &continuation);
    Ok(Swept { plan, rate, rows })
}

/// `mechgen sweep NAME [options]`.
pub fn sweep(args: &SweepArgs) -> Result<(), String> {
    let file = args.file.as_deref();
    let loaded = Loaded::read(file)?;
    if let Some(mech) = super::scene::scene_mechanism(&loaded, &args.name) {
        return super::scene::sweep(&loaded, mech, args);
    }
    let sel = select(&loaded, &args.name, file, args.engine)?;
    if let Some(w) = loaded.start_warning(&args.name) {
        eprint!("{w}");
    }
    let info = sel.solver.info();
    let range = Range {
        from: args.from,
        to: args.to,
        step: args.step,
    };
    let plan = plan(&info, args.input.as_deref(), &args.set, range)?;
    let swept = run_plan(sel.solver.as_ref(), &info, plan, args.rate)?;
    say_raw!(
        "{} ({} rows)\n{}",
        info.name,
        swept.rows.len(),
        swept.table(&info)
    );
    let held = !swept.plan.held.is_empty();
    if let Some(note) =
        super::branches::sweep_note(file, &args.name, swept.plan.index, held, &swept.rows)
    {
        say!("{note}");
    }
    if let Some(path) = &args.csv {
        std::fs::write(path, report::csv(&info, swept.plan.index, &swept.rows))
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    write_plots(
        &sel,
        &info,
        &swept,
        args.plot.as_deref(),
        args.animate.as_deref(),
        true,
    )?;
    Ok(())
}

/// The plots and animation a sweep asked for; `report` says what was written on stderr.
pub(super) fn write_plots(
    sel: &Selected,
    info: &MechanismInfo,
    swept: &Swept,
    plot: Option<&Path>,
    animate: Option<&Path>,
    report: bool,
) -> Result<(), String> {
    let x = swept.inputs(info);
    let mut written: Vec<PathBuf> = Vec::new();
    if let Some(dir) = plot {
        written.extend(super::plots::write(
            dir,
            &sel.model,
            info,
            swept.plan.index,
            &x,
            &swept.rows,
        )?);
    }
    if let Some(dir) = animate {
        written.extend(super::plots::write_animation(
            dir,
            &sel.model,
            swept.plan.index,
            &x,
            &swept.rows,
        )?);
    }
    if report {
        for p in written {
            eprintln!("wrote {}", p.display());
        }
    }
    Ok(())
}

/// The main job's range: a full turn for an angle input, from its start value rounded down to
/// 10° (so that the start's branch is swept from where it is, not from a dead point it would have
/// to cross to reach 0°; a start of 0 gives the `sweep` defaults); for a length input, which has no
/// default range, its start value ± a quarter of the mechanism's length scale (or of the start
/// value, if larger), in 36 steps.
pub(super) fn main_job_range(info: &MechanismInfo) -> Range {
    match info.inputs.first() {
        Some(CoordDesc {
            kind: Kind::Angle,
            start,
            ..
        }) => {
            let from = (start.to_degrees() / 10.0).floor() * 10.0;
            let from = if from.is_finite() { from } else { 0.0 };
            Range {
                from: Some(from),
                to: Some(from + 360.0),
                step: Some(10.0),
            }
        }
        // A length input.
        Some(CoordDesc { start, .. }) => {
            let scale = info
                .params
                .iter()
                .filter(|p| p.kind == Kind::Length)
                .fold(start.abs(), |m, p| m.max(p.value.abs()));
            let half = if scale > 0.0 && scale.is_finite() {
                scale / 4.0
            } else {
                1.0
            };
            Range {
                from: Some(start - half),
                to: Some(start + half),
                step: Some(half / 18.0),
            }
        }
        None => Range::default(),
    }
}

/// The main job: every mechanism of the compiled-in file (generated engine) or of `--file`
/// (generic engine) over its default range; tables, CSVs and plots into `--out` (default
/// `mechgen-out/`).
pub fn main_job(args: &MainArgs) -> Result<(), String> {
    let dir = args.out.as_path();
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let file = args.file.as_deref();
    let loaded = Loaded::read(file)?;
    let names: Vec<String> = loaded.mechs.iter().map(|m| m.name().to_string()).collect();
    let mut failed = Vec::new();
    for name in &names {
        if let Err(e) = main_job_one(&loaded, name, file, dir, args.animate.as_deref()) {
            eprintln!("mechgen: {name}: {e}");
            failed.push(name.as_str());
        }
    }
    let scenes: Vec<String> = loaded
        .mechs
        .iter()
        .flat_map(|m| m.scene_names())
        .map(str::to_string)
        .collect();
    for name in &scenes {
        if let Err(e) = super::scene::main_job_scene(&loaded, name, file, dir, main_job_range) {
            eprintln!("mechgen: {name}: {e}");
            failed.push(name.as_str());
        }
    }
    say!(
        "CSV files and plots written to {}/ (one CSV, a motion plot and a drawing per mechanism; one CSV per scene)",
        dir.display()
    );
    if failed.is_empty() {
        Ok(())
    } else {
        Err(format!("no sweep of {}", failed.join(", ")))
    }
}

/// One mechanism of the main job: table, CSV, plots (and the animation if asked).
fn main_job_one(
    loaded: &Loaded,
    name: &str,
    file: Option<&Path>,
    dir: &Path,
    animate: Option<&Path>,
) -> Result<(), String> {
    let sel = select(loaded, name, file, None)?;
    if let Some(w) = loaded.start_warning(name) {
        eprint!("{w}");
    }
    let info = sel.solver.info();
    let plan = plan(&info, None, &[], main_job_range(&info))?;
    let swept = run_plan(sel.solver.as_ref(), &info, plan, 1.0)?;
    say!("{} — {}", info.name, info.description);
    say!("{}", swept.table(&info));
    let range = main_job_range(&info);
    let lengths = (range.from.unwrap_or(-1.0), range.to.unwrap_or(1.0));
    say_raw!("{}", super::branches::summary(file, name, lengths));
    let path = dir.join(format!("{name}.csv"));
    std::fs::write(&path, report::csv(&info, swept.plan.index, &swept.rows))
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    write_plots(&sel, &info, &swept, Some(dir), animate, false)
}
