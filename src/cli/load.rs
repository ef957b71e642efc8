//! CLI, what running a command needs first: loading a file (with its start warnings), choosing
//! the engine for a mechanism, running a sweep plan, and the plots a sweep asked for. `run` (sweeps
//! and the main job) and `scene` (scene sweeps) both sit on it.

use std::path::{Path, PathBuf};

use mechgen::generic::Generic;
use mechgen::sweep::{Assembles, Continuation, Row, RowRef, check_start, sweep_each_with};
use mechgen::{DynMechanism, MechanismInfo, report};
use mechgen_codegen::diagnostic::{Diagnostic, Severity, SourceFile, render};

use super::args::Engine;
use mechgen::sweep::plan::Plan;

/// A mechanism file, analysed: every mechanism for the generic engine and the file's warnings.
pub struct Loaded {
    pub mechs: Vec<Generic>,
    file: SourceFile,
    warnings: Vec<Diagnostic>,
}

impl Loaded {
    /// The file at `path`, or the compiled-in file (`mechgen::source`).
    pub fn read(path: Option<&Path>) -> Result<Loaded, String> {
        let a = super::analysed::analysis(path)?;
        let (file, diagnostics) = (&a.file, &a.diagnostics);
        if diagnostics.iter().any(Diagnostic::is_error) {
            let n = diagnostics.iter().filter(|d| d.is_error()).count();
            let rendered = render(file, diagnostics);
            return Err(format!(
                "{}\n{}: {n} error(s)",
                rendered.trim_end(),
                file.name
            ));
        }
        Ok(Loaded {
            mechs: a.compiled.iter().map(Generic::new).collect(),
            file: file.clone(),
            warnings: diagnostics
                .iter()
                .filter(|d| d.severity == Severity::Warning)
                .cloned()
                .collect(),
        })
    }

    /// The start check's warning for mechanism `name` (as `mechgen check` prints it), if any:
    /// its start did not close the loops and Newton converged somewhere, maybe on another branch.
    pub fn start_warning(&self, name: &str) -> Option<String> {
        mechgen::generic::start_warning(&self.file, &self.warnings, name)
    }
}

/// The mechanism to sweep: its solvers, and the generic engine of the same file (for drawings).
pub struct Selected {
    pub solver: Box<dyn DynMechanism<f64>>,
    pub model: Generic,
}

/// The engine a command runs: the one asked for, else `generated` for the compiled-in file and
/// `jit` (where the host has a Cranelift back end, else `generic`) for `--file`.
pub(super) fn engine_for(file: Option<&Path>, engine: Option<Engine>) -> Engine {
    engine.unwrap_or(if file.is_none() {
        Engine::Generated
    } else if mechgen::generic::jit::available() {
        Engine::Jit
    } else {
        Engine::Generic
    })
}

/// `model` ready to run as `engine`: compiled by the JIT for `Engine::Jit` (a failure is an
/// error when `--engine jit` was asked for, else the interpreter runs).
pub(super) fn prepare(model: &mut Generic, engine: Engine, asked: bool) -> Result<(), String> {
    if engine != Engine::Jit {
        return Ok(());
    }
    match model.compile() {
        Ok(_) => Ok(()),
        Err(e) if asked => Err(format!("{}: {e} (use --engine generic)", model.name())),
        Err(_) => Ok(()),
    }
}

/// What a command that runs mechanisms says when `loaded` has no mechanism `name`: that it is a
/// scene (which `sweep` and `batch` run), or the file's mechanisms and the nearest name.
fn no_mechanism(loaded: &Loaded, name: &str) -> String {
    if let Some(m) = loaded
        .mechs
        .iter()
        .find(|m| m.scene_names().contains(&name))
    {
        return format!(
            "`{name}` is a scene of mechanism `{m}`: `sweep` and `batch` run scenes; this command runs on the whole mechanism (give `{m}`)",
            m = m.name()
        );
    }
    let names: Vec<&str> = loaded.mechs.iter().map(Generic::name).collect();
    let guess = mechgen_codegen::nearest(name, names.iter().copied())
        .map(|g| format!("; did you mean `{g}`?"))
        .unwrap_or_default();
    format!(
        "no mechanism `{name}` in {} (it has: {}){guess}",
        loaded.file.name,
        names.join(", ")
    )
}

/// Mechanism `name` of `loaded` with the engine asked for (generated only for the compiled-in file).
pub(super) fn select(
    loaded: &Loaded,
    name: &str,
    file: Option<&Path>,
    engine: Option<Engine>,
) -> Result<Selected, String> {
    let asked = engine.is_some();
    let engine = engine_for(file, engine);
    if file.is_some() && engine == Engine::Generated {
        return Err(
            "--engine generated exists only for compiled-in mechanisms; use --engine jit or generic with --file"
                .into(),
        );
    }
    let mut model = loaded
        .mechs
        .iter()
        .find(|m| m.name() == name)
        .cloned()
        .ok_or_else(|| no_mechanism(loaded, name))?;
    prepare(&mut model, engine, asked)?;
    let solver: Box<dyn DynMechanism<f64>> = match engine {
        Engine::Generic | Engine::Jit => Box::new(model.clone()),
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
        held_inputs(info, &self.plan)
    }

    /// The table with its preamble (units, rate, held inputs, a note on the last row).
    pub(super) fn table(&self, info: &MechanismInfo) -> String {
        table_preamble(info, &self.plan, self.rate)
            + &report::table(info, self.plan.index, &self.rows)
    }
}

/// Every input's value during a sweep of `plan` (the swept one at its start value).
pub(super) fn held_inputs(info: &MechanismInfo, plan: &Plan) -> Vec<f64> {
    let mut x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
    for &(i, v) in &plan.held {
        x[i] = v;
    }
    x
}

/// The lines above a sweep's table: units, rate, held inputs, a note on the last row.
pub(super) fn table_preamble(info: &MechanismInfo, plan: &Plan, rate: f64) -> String {
    let mut out = report::preamble(info, plan.index, rate, &held_inputs(info, plan));
    if let Some(note) = &plan.note {
        out.push_str(note);
        out.push('\n');
    }
    out
}

/// Runs the sweep that `plan` describes on `k`, after the start checks.
pub(super) fn run_plan(
    k: &dyn DynMechanism<f64>,
    info: &MechanismInfo,
    plan: Plan,
    rate: f64,
) -> Result<Swept, String> {
    run_plan_with(k, info, plan, rate, None)
}

/// [`run_plan`] told where the linkage assembles (see [`sweep_each_with`]).
pub(super) fn run_plan_with(
    k: &dyn DynMechanism<f64>,
    info: &MechanismInfo,
    plan: Plan,
    rate: f64,
    assembles: Option<Assembles<'_>>,
) -> Result<Swept, String> {
    check_start(info).map_err(|e| format!("{}: {e}", info.name))?;
    let kind = info.inputs[plan.index].kind;
    let continuation = Continuation::for_input(kind, plan.span);
    let mut rows = Vec::with_capacity(plan.values.len());
    sweep_each_with(
        k,
        plan.index,
        &plan.values,
        rate,
        &plan.held,
        &continuation,
        assembles,
        &mut |r| rows.push(r.to_row()),
    );
    Ok(Swept { plan, rate, rows })
}

/// The branch analysis of mechanism `name` along input `index` (the file's params), to tell a
/// sweep where the linkage assembles; `None` where the file cannot be analysed.
pub(super) fn assembly(
    file: Option<&std::path::Path>,
    name: &str,
    index: usize,
) -> Option<mechgen::branches::Setup> {
    let compiled = super::branches::compile(file).ok()?;
    let c = compiled.iter().find(|c| c.model.name.text == name)?;
    mechgen::branches::Setup::new(c, index).ok()
}

/// Rows kept of a streamed sweep for what reads rows afterwards (plots, the branch note): at
/// most about [`KEPT_ROWS`] evenly spaced rows, the last row, and both rows of every change of
/// status (where a branch stops or resumes).
pub(super) const KEPT_ROWS: usize = 2000;

/// Which rows of a streamed sweep of `n` rows are kept ([`KEPT_ROWS`]), row by row: every
/// `stride`-th, the last, and both rows of every change of status.
pub(super) struct Thinning {
    stride: usize,
    n: usize,
    i: usize,
    last: Option<&'static str>,
    /// Whether the row before the current one was not kept.
    pending: bool,
}

impl Thinning {
    pub(super) fn new(n: usize) -> Thinning {
        Thinning {
            stride: n.div_ceil(KEPT_ROWS).max(1),
            n,
            i: 0,
            last: None,
            pending: false,
        }
    }

    /// For the next row, of status `status`: whether the row before it (not kept when it came)
    /// is kept now, and whether this one is.
    pub(super) fn next(&mut self, status: &'static str) -> (bool, bool) {
        let changed = self.last.is_some_and(|p| p != status);
        let before = changed && self.pending;
        let this = changed || self.i.is_multiple_of(self.stride) || self.i + 1 == self.n;
        self.pending = !this;
        self.last = Some(status);
        self.i += 1;
        (before, this)
    }
}

/// Runs the sweep that `plan` describes on `k` like [`run_plan`], handing every row to `each` as
/// it is solved (in input order) and keeping only the rows [`KEPT_ROWS`] describes, so that
/// memory does not grow with the number of rows.
pub(super) fn stream_plan(
    k: &dyn DynMechanism<f64>,
    info: &MechanismInfo,
    plan: Plan,
    rate: f64,
    assembles: Option<Assembles<'_>>,
    each: &mut dyn FnMut(&RowRef<'_>),
) -> Result<Swept, String> {
    check_start(info).map_err(|e| format!("{}: {e}", info.name))?;
    let kind = info.inputs[plan.index].kind;
    let continuation = Continuation::for_input(kind, plan.span);
    let mut thin = Thinning::new(plan.values.len());
    let mut kept: Vec<Row> = Vec::new();
    // The row before the current one when it was not kept (its vectors reused row after row).
    let mut previous: Option<Row> = None;
    sweep_each_with(
        k,
        plan.index,
        &plan.values,
        rate,
        &plan.held,
        &continuation,
        assembles,
        &mut |r| {
            each(&r);
            let (before, this) = thin.next(r.status());
            if before && let Some(p) = &previous {
                kept.push(p.clone());
            }
            if this {
                kept.push(r.to_row());
            } else {
                match &mut previous {
                    Some(p) => p.assign(&r),
                    None => previous = Some(r.to_row()),
                }
            }
        },
    );
    Ok(Swept {
        plan,
        rate,
        rows: kept,
    })
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
            tell!("wrote {}", p.display());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{KEPT_ROWS, Thinning};

    /// The rows kept of `statuses`, by index.
    fn kept(statuses: &[&'static str]) -> Vec<usize> {
        let mut thin = Thinning::new(statuses.len());
        let mut out = Vec::new();
        for (i, s) in statuses.iter().enumerate() {
            let (before, this) = thin.next(s);
            if before {
                out.push(i - 1);
            }
            if this {
                out.push(i);
            }
        }
        out
    }

    #[test]
    fn a_long_sweep_keeps_evenly_spaced_rows_the_last_and_both_sides_of_a_change() {
        let n = 360_001;
        let mut statuses = vec!["ok"; n];
        statuses[200_001..250_000].fill("other-branch");
        let k = kept(&statuses);
        assert!(k.windows(2).all(|w| w[0] < w[1]), "in order, each once");
        assert!(k.len() <= KEPT_ROWS + 4, "{} rows kept", k.len());
        assert_eq!((k[0], k[k.len() - 1]), (0, n - 1));
        for i in [200_000, 200_001, 249_999, 250_000] {
            assert!(k.contains(&i), "row {i} not kept");
        }
        // Evenly spaced elsewhere: no gap wider than the stride.
        let stride = n.div_ceil(KEPT_ROWS);
        assert!(k.windows(2).all(|w| w[1] - w[0] <= stride));
    }

    #[test]
    fn a_short_sweep_keeps_every_row() {
        let statuses = ["ok", "ok", "singular", "ok"];
        assert_eq!(kept(&statuses), [0, 1, 2, 3]);
    }
}
