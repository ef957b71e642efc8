//! CLI, running things: `sweep` (table, CSV, plots; a scene's through [`super::scene`]) and the
//! main job, on what [`super::load`] loads. Sits between [`super::args`] and [`mechgen::sweep`].

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

use mechgen::{CoordDesc, Kind, MechanismInfo, design, report};

use super::args::{MainArgs, SweepArgs};
use super::load::{Loaded, run_plan_with, select, stream_plan, table_preamble, write_plots};
use mechgen::sweep::plan::{Range, plan};

/// `mechgen sweep NAME [options]`.
pub fn sweep(args: &SweepArgs) -> Result<(), String> {
    let file = args.file.as_deref();
    let loaded = Loaded::read(file)?;
    if let Some(mech) = super::scene::scene_mechanism(&loaded, &args.name) {
        return super::scene::sweep(&loaded, mech, args);
    }
    let sel = select(&loaded, &args.name, file, args.engine)?;
    if let Some(w) = loaded.start_warning(&args.name) {
        tell_raw!("{w}");
    }
    let info = sel.solver.info();
    let range = Range {
        from: args.from,
        to: args.to,
        step: args.step,
    };
    let plan = plan(&info, args.input.as_deref(), &args.set, range)?;
    let loads = loads(&info, &args.load)?;
    if !loads.is_empty() && args.rate == 0.0 {
        return Err(
            "--load needs a nonzero --rate (the effort comes from the point velocities)".into(),
        );
    }
    let effort_unit = match info.inputs[plan.index].kind {
        Kind::Angle => "force*u/rad",
        _ => "force",
    };
    let (mut header, width) = report::table_header(&info, plan.index);
    if !loads.is_empty() {
        header.pop();
        let _ = writeln!(
            header,
            "{:>width$}",
            format!("input_effort [{effort_unit}]")
        );
    }
    // Every input not swept, with its value, in the CSV after the swept one.
    let held = report::held_inputs(&info, plan.index, &plan.held);
    let csv = match &args.csv {
        Some(path) => {
            let file = std::fs::File::create(path)
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
            let mut w = std::io::BufWriter::with_capacity(super::OUTPUT_BUFFER, file);
            let mut head = report::csv_header_line_held(&info, plan.index, &held);
            if !loads.is_empty() {
                with_column(&mut head, "input_effort");
            }
            let _ = w.write_all(head.as_bytes());
            Some((path, w))
        }
        None => None,
    };
    // Rows are printed and written as they are solved (the CSV opened first: a path that cannot
    // be written prints nothing); only what plots and the branch note read is kept.
    let stdout = std::io::stdout();
    let mut table = std::io::BufWriter::with_capacity(super::OUTPUT_BUFFER, stdout.lock());
    let _ = write!(
        table,
        "{} ({} rows)\n{}{header}",
        info.name,
        plan.values.len(),
        table_preamble(&info, &plan, args.rate)
    );
    let (index, rate) = (plan.index, args.rate);
    // Rows past the dead point that ends the branch: `other-branch` where the linkage assembles
    // all the same (the branch analysis at the row's inputs), else `unassemblable`.
    let setup = super::load::assembly(file, &args.name, plan.index);
    let assembles = |x: &[f64]| setup.as_ref().and_then(|s| s.assembles(x));
    let oracle: Option<mechgen::sweep::Assembles<'_>> = setup.is_some().then_some(&assembles);
    let mut row: Vec<u8> = Vec::new();
    // The CSV is formatted on a second thread from batches of rows (the table on this one), so
    // that the two outputs' formatting, most of a long sweep's time, runs on two cores.
    let (swept, csv_result) = std::thread::scope(|scope| {
        let mut csv_out = csv.map(|(path, w)| {
            let (batches, back, worker) = csv_writer(scope, w, &info, &held, !loads.is_empty());
            (path, batches, back, worker, Batch::default())
        });
        let swept = stream_plan(
            sel.solver.as_ref(),
            &info,
            plan,
            args.rate,
            oracle,
            &mut |r| {
                // A closed stdout (`mechgen sweep … | head`) ends the table, not the sweep or
                // its CSV.
                let effort = match (&r.result, loads.is_empty()) {
                    (Ok(s), false) => {
                        design::input_effort(s, &loads, rate).filter(|e| e.is_finite())
                    }
                    _ => None,
                };
                row.clear();
                report::table_row(&mut row, &info, index, width, r);
                if let Some(e) = effort {
                    row.pop();
                    report::push_significant(&mut row, e, width);
                    row.push(b'\n');
                }
                let _ = table.write_all(&row);
                if let Some((_, batches, back, _, batch)) = &mut csv_out {
                    batch.push(r, effort);
                    if batch.full() {
                        let next = back.try_recv().unwrap_or_default();
                        let _ = batches.send(std::mem::replace(batch, next));
                    }
                }
            },
        );
        let csv_result = csv_out.map(|(path, batches, _back, worker, batch)| {
            let _ = batches.send(batch);
            drop(batches);
            let e = worker.join().ok().flatten();
            (path, e)
        });
        (swept, csv_result)
    });
    let swept = swept?;
    let _ = table.flush();
    drop(table);
    if let Some((path, Some(e))) = csv_result {
        return Err(format!("cannot write {}: {e}", path.display()));
    }
    let held = !swept.plan.held.is_empty();
    if let Some(note) =
        super::branches::sweep_note(file, &args.name, swept.plan.index, held, &swept.rows)
    {
        say!("{note}");
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

/// Rows handed to the CSV thread at a time.
const BATCH_ROWS: usize = 1024;

/// Rows for the CSV thread, with each row's input effort (`--load`): the rows' vectors are
/// reused batch after batch (a batch comes back when written), so nothing is allocated per row
/// once the first batches are made.
#[derive(Default)]
struct Batch {
    rows: Vec<(mechgen::sweep::Row, Option<f64>)>,
    len: usize,
}

impl Batch {
    fn push(&mut self, r: &mechgen::sweep::RowRef<'_>, effort: Option<f64>) {
        match self.rows.get_mut(self.len) {
            Some((row, e)) => {
                row.assign(r);
                *e = effort;
            }
            None => self.rows.push((r.to_row(), effort)),
        }
        self.len += 1;
    }

    fn full(&self) -> bool {
        self.len >= BATCH_ROWS
    }
}

/// The CSV thread: writes each batch it is sent (lines as `csv_row_held`, with the effort column
/// when `effort`) to `w` and sends it back emptied; at the end, the first write error.
#[allow(clippy::type_complexity)]
fn csv_writer<'scope, 'env: 'scope, W: std::io::Write + Send + 'scope>(
    scope: &'scope std::thread::Scope<'scope, 'env>,
    mut w: W,
    info: &'env MechanismInfo,
    held: &'env [(usize, f64)],
    effort: bool,
) -> (
    std::sync::mpsc::SyncSender<Batch>,
    std::sync::mpsc::Receiver<Batch>,
    std::thread::ScopedJoinHandle<'scope, Option<std::io::Error>>,
) {
    let (batches, incoming) = std::sync::mpsc::sync_channel::<Batch>(2);
    let (back, recycled) = std::sync::mpsc::channel::<Batch>();
    let worker = scope.spawn(move || {
        let mut line = Vec::new();
        let mut error = None;
        for mut batch in incoming {
            for (r, e) in &batch.rows[..batch.len] {
                if error.is_some() {
                    break;
                }
                line.clear();
                report::csv_row_held(&mut line, info, &r.view(), held);
                if effort {
                    with_column_bytes(&mut line, *e);
                }
                error = w.write_all(&line).err();
            }
            batch.len = 0;
            let _ = back.send(batch);
        }
        error.or_else(|| w.flush().err())
    });
    (batches, recycled, worker)
}

/// `--load P=FX,FY` against the mechanism's points.
fn loads(info: &MechanismInfo, given: &[(String, [f64; 2])]) -> Result<Vec<design::Load>, String> {
    given
        .iter()
        .map(|(name, force)| {
            let point = info.points.iter().position(|p| p == name).ok_or_else(|| {
                format!(
                    "--load {name}=…: `{}` has no point `{name}` (its points: {})",
                    info.name,
                    info.points.join(", ")
                )
            })?;
            Ok(design::Load {
                point,
                force: *force,
            })
        })
        .collect()
}

/// `cell` as a column just before the last one (`status`) of a CSV line.
fn with_column(line: &mut String, cell: &str) {
    let at = line.rfind(',').unwrap_or(0);
    line.insert_str(at, &format!(",{cell}"));
}

/// A CSV row's line with one more cell before its last (`status`): `effort`, empty when `None`.
fn with_column_bytes(line: &mut Vec<u8>, effort: Option<f64>) {
    let at = line.iter().rposition(|&b| b == b',').unwrap_or(0);
    let mut cell = vec![b','];
    if let Some(e) = effort {
        report::push_float(&mut cell, e);
    }
    line.splice(at..at, cell);
}

/// The main job's range: the start's branch between its dead points where it has them
/// ([`super::branches::start_branch`], each end moved inside by 1e-6 of the span), in 36 steps;
/// else, for an angle input, a full turn from its start value rounded down to 10° (so that the
/// start's branch is swept from where it is, not from a dead point it would have to cross to
/// reach 0°; a start of 0 gives the `sweep` defaults); for a length input without that analysis,
/// the start value ± a quarter of the mechanism's length scale (or of the start value, if larger).
pub(super) fn main_job_range(info: &MechanismInfo, file: Option<&Path>) -> Range {
    let angle = info.inputs.first().map(|i| i.kind) == Some(Kind::Angle);
    if let Some(sb) = super::branches::start_branch(file, &info.name) {
        let (a, b) = (sb.from, sb.to);
        let (a, b) = if angle {
            (a.to_degrees(), b.to_degrees())
        } else {
            (a, b)
        };
        let inset = (b - a) * 1e-6;
        return Range {
            from: Some(a + inset),
            to: Some(b - inset),
            step: Some((b - a - 2.0 * inset) / 36.0),
        };
    }
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
            tell!("mechgen: {name}: {e}");
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
        if let Err(e) = super::scene::main_job_scene(&loaded, name, file, dir, |info| {
            main_job_range(info, file)
        }) {
            tell!("mechgen: {name}: {e}");
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
        tell_raw!("{w}");
    }
    let info = sel.solver.info();
    let range = main_job_range(&info, file);
    let plan = plan(&info, None, &[], range)?;
    let setup = super::load::assembly(file, name, plan.index);
    let assembles = |x: &[f64]| setup.as_ref().and_then(|s| s.assembles(x));
    let oracle: Option<mechgen::sweep::Assembles<'_>> = setup.is_some().then_some(&assembles);
    let swept = run_plan_with(sel.solver.as_ref(), &info, plan, 1.0, oracle)?;
    say!("{} — {}", info.name, info.description);
    say!("{}", swept.table(&info));
    let lengths = (range.from.unwrap_or(-1.0), range.to.unwrap_or(1.0));
    say_raw!("{}", super::branches::summary(file, name, lengths));
    // The metrics over the start's branch (an angle input: between its dead points, else a
    // full turn from its start).
    let span = match info.inputs.first().map(|i| i.kind) {
        Some(Kind::Angle) => {
            let r = super::metrics::angle_range(&info, file);
            Some((r.span, r.dead_ends))
        }
        _ => range.from.zip(range.to).map(|s| (s, Vec::new())),
    };
    if let Some((span, dead_ends)) = span {
        match super::metrics::main_job_table(sel.solver.as_ref(), &info, file, span, &dead_ends) {
            Ok(t) => say_raw!("{t}"),
            Err(e) => tell!("mechgen: {name}: metrics: {e}"),
        }
    }
    let path = dir.join(format!("{name}.csv"));
    std::fs::write(&path, report::csv(&info, swept.plan.index, &swept.rows))
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    // A mechanism with bodies: the effort its driver needs along the same rows (at the sweep's
    // rate, no loads), NAME-dynamics.csv and NAME-dynamics.svg.
    if !info.bodies.is_empty() {
        let (table, csv, plotted) =
            super::dynamics::rows(sel.solver.as_ref(), &info, &swept, 0.0, &[]);
        say_raw!("{table}");
        let path = dir.join(format!("{name}-dynamics.csv"));
        std::fs::write(&path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        let xs: Vec<f64> = swept.rows.iter().map(|r| r.input).collect();
        super::dynamics::write_plot(&info, swept.plan.index, &xs, &plotted, dir)?;
    }
    write_plots(&sel, &info, &swept, Some(dir), animate, false)
}
