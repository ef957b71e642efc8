//! CLI, `mechgen batch NAME --params SETS.csv` (interfaces.md): one sweep per param set, exactly
//! as `sweep` sweeps it, the sets across every core ([`mechgen::batch`]); every row written in set
//! order as its chunk is solved, a summary row per set, a progress bar on stderr.

use std::io::{IsTerminal as _, Write as _};

use mechgen::batch::lanes::{Group, lane_width_for, sweep_group};
use mechgen::batch::{
    CHUNK, ParamSets, SetSummary, for_each_ordered_by, scene_with_params, solver_with_params,
};
use mechgen::sweep::scene::{SceneSolver, scene_csv_header, scene_csv_row};
use mechgen::sweep::{Continuation, check_start, sweep_each_with};
use mechgen::{DynMechanism, DynScene, report};

use super::args::{BatchArgs, Engine};
use super::load::{Loaded, select};
use super::out::Out;
use mechgen::sweep::plan::{Range, plan};

/// `mechgen batch NAME --params SETS.csv [options]`.
/// Rows (sets × rows per set) a batch writes to `--csv` at most.
const MAX_CSV_ROWS: usize = 100_000_000;
/// Rows from which a batch says its size before it starts.
const LONG_BATCH: usize = 10_000_000;

pub fn run(args: &BatchArgs) -> Result<(), String> {
    let s = &args.sweep;
    let file = s.file.as_deref();
    let loaded = Loaded::read(file)?;
    // A scene: its mechanism's sets swept as a batch sweeps them, the scene's solver at every
    // row (as `sweep SCENE`), its columns in the CSV.
    let scene = super::scene::scene_mechanism(&loaded, &s.name).map(|m| m.name().to_string());
    let mechanism = scene.as_deref().unwrap_or(&s.name);
    let sel = select(&loaded, mechanism, file, s.engine)?;
    let info = sel.solver.info();
    let sets_name = args.params.display().to_string();
    let text = std::fs::read_to_string(&args.params)
        .map_err(|e| format!("cannot read {sets_name}: {e}"))?;
    let sets = ParamSets::parse(&sets_name, &text)?;
    for note in &sets.notes {
        tell!("mechgen: {note}");
    }
    for n in &sets.names {
        // A derived param is named with what it is derived from.
        if !info.params.iter().any(|p| &p.name == n)
            && let Err(e) = sel.model.clone().set_param(n, 0.0)
        {
            return Err(format!("{sets_name}:1: {e}"));
        }
    }
    let indices = sets.indices(&sets_name, &info)?;
    let range = Range {
        from: s.from,
        to: s.to,
        step: s.step,
    };
    let plan = plan(&info, s.input.as_deref(), &s.set, range)?;
    // Sets × rows, checked before anything is solved or written: a CSV beyond MAX_CSV_ROWS would
    // fill a disk (about 200 bytes a row), and a long batch says how long it is.
    let total = sets.sets.len().saturating_mul(plan.values.len());
    if args.csv.is_some() && total > MAX_CSV_ROWS {
        return Err(format!(
            "{} set(s) × {} rows = {total} rows: a CSV of about {:.0} GB; --csv writes at most {MAX_CSV_ROWS} rows (ask for --summary only, or fewer sets, or a larger --step)",
            sets.sets.len(),
            plan.values.len(),
            total as f64 * 200e-9
        ));
    }
    if total > LONG_BATCH {
        tell!(
            "mechgen: {} set(s) × {} rows = {total} rows to solve (at some 100 ns a row per core)",
            sets.sets.len(),
            plan.values.len()
        );
    }
    check_start(&info).map_err(|e| format!("{}: {e}", info.name))?;
    let continuation = Continuation::for_input(info.inputs[plan.index].kind, plan.span);
    // Every input not swept, with its value, in the CSV after the swept one.
    let held = report::held_inputs(&info, plan.index, &plan.held);
    let generated = super::load::engine_for(file, s.engine) == Engine::Generated;
    let engine = |set: usize| -> Box<dyn DynMechanism<f64>> {
        let params = sets.params_of(set, &indices, &info);
        solver_with_params(mechanism, &sel.model, generated, &params)
    };
    let scene_of = |set: usize| -> Result<Box<dyn DynScene<f64>>, String> {
        let params = sets.params_of(set, &indices, &info);
        scene_with_params(&s.name, &sel.model, generated, &params)
            .ok_or_else(|| format!("no compiled-in scene `{}`", s.name))
    };
    // Where a scene's solver starts each set: the inputs held at their values.
    let x = mechgen::design::row_inputs(&info, plan.index, &plan.held, 0.0);
    let scene_columns = match &scene {
        Some(_) => Some(scene_of(0)?.info()),
        None => None,
    };
    let want_rows = args.csv.is_some();
    // One set: its CSV rows (when asked for) and its summary.
    // The file's analysis, for the rows past the dead point that ends a set's branch (made for a
    // set when it first has one: `other-branch` where the linkage assembles all the same).
    let compiled = super::branches::compile(file).ok();
    let analysed = compiled
        .as_ref()
        .and_then(|cs| cs.iter().find(|c| c.model.name.text == mechanism))
        .and_then(|c| mechgen::branches::Assembly::new(c, plan.index));
    let solve = |set: usize| -> (Vec<u8>, SetSummary) {
        let k = engine(set);
        // Made for set 0 above, so made for every set (the same scene, params as many).
        let scene = scene_columns.as_ref().and_then(|_| scene_of(set).ok());
        let mut scene = scene.as_deref().map(|scene| {
            let solver = SceneSolver::new(scene, &x, plan.index, s.rate, &continuation.options);
            (solver, scene.info().columns.len(), String::new())
        });
        let mut rows = Vec::new();
        let mut summary = SetSummary::new(&info);
        let setup = std::cell::OnceCell::new();
        let assembles = |x: &[f64]| {
            setup
                .get_or_init(|| {
                    let params = sets.params_of(set, &indices, &info);
                    analysed.as_ref()?.with_params(&params)
                })
                .as_ref()
                .and_then(|setup| setup.assembles(x))
        };
        let oracle: Option<mechgen::sweep::Assembles<'_>> =
            analysed.is_some().then_some(&assembles);
        sweep_each_with(
            k.as_ref(),
            plan.index,
            &plan.values,
            s.rate,
            &plan.held,
            &continuation,
            oracle,
            &mut |r| {
                let Some((solver, columns, line)) = &mut scene else {
                    summary.add(&r);
                    if want_rows {
                        let _ = write!(rows, "{set},");
                        report::csv_row_held(&mut rows, &info, &r, &held);
                    }
                    return;
                };
                let row = solver.row(&r);
                match (&r.result, &row.outputs) {
                    (Ok(_), Err(_)) => summary.fail(r.input),
                    _ => summary.add(&r),
                }
                if want_rows {
                    let _ = write!(rows, "{set},");
                    line.clear();
                    scene_csv_row(line, *columns, &row);
                    rows.extend_from_slice(line.as_bytes());
                }
            },
        );
        (rows, summary)
    };
    let header = match &scene_columns {
        Some(d) => scene_csv_header(d, &info.inputs[plan.index].name).join(",") + "\n",
        None => report::csv_header_line_held(&info, plan.index, &held),
    };
    let mut csv = match &args.csv {
        Some(p) => Some(Out::create(p, &format!("set,{header}"))?),
        None => None,
    };
    let mut summary_out = match &args.summary {
        Some(p) => Some(Out::create(p, &SetSummary::header(&info))?),
        None => None,
    };
    let count = sets.sets.len();
    // A compiled-in mechanism's sets go in lane groups (`mechgen::batch::lanes`): each group's
    // sets swept side by side, those that leave the lanes swept again by the scalar sweep.
    let lanes = if generated && scene.is_none() {
        lane_width_for(info.unknowns.len())
    } else {
        1
    };
    let solve_group = |g: usize| -> Vec<(Vec<u8>, SetSummary)> {
        let group_sets = g * lanes..((g + 1) * lanes).min(count);
        if lanes == 1 {
            return group_sets.map(solve).collect();
        }
        let params: Vec<Vec<f64>> = group_sets
            .clone()
            .map(|set| sets.params_of(set, &indices, &info))
            .collect();
        let mut out: Vec<(Vec<u8>, SetSummary)> = params
            .iter()
            .map(|_| (Vec::new(), SetSummary::new(&info)))
            .collect();
        // The rows come as solved (the start row, down, then up): each row's span in the set's
        // text, to be put in row order.
        let mut spans: Vec<Vec<(usize, usize)>> = vec![Vec::new(); params.len()];
        let group = Group {
            params: &params,
            index: plan.index,
            values: &plan.values,
            rate: s.rate,
            held: &plan.held,
            continuation: &continuation,
        };
        let left = sweep_group(mechanism, &group, &mut |i, at, r| {
            let (rows, summary) = &mut out[i];
            summary.add(&r);
            if want_rows {
                spans[i].push((at, rows.len()));
                let _ = write!(rows, "{},", group_sets.start + i);
                report::csv_row_held(rows, &info, &r, &held);
            }
        })
        .unwrap_or(u32::MAX);
        for (i, set) in group_sets.enumerate() {
            if left >> i & 1 == 1 {
                out[i] = solve(set);
            } else {
                in_row_order(&mut out[i].0, &spans[i]);
            }
        }
        out
    };
    let progress = count > mechgen::batch::CHUNK && std::io::stderr().is_terminal();
    let (mut whole, mut failed_start) = (0, 0);
    let mut set = 0;
    for_each_ordered_by(
        count.div_ceil(lanes),
        CHUNK.div_ceil(lanes),
        args.threads.map(usize::from),
        solve_group,
        |_, group| {
            for (rows, summary) in group {
                if let Some(c) = &mut csv {
                    c.write(&rows);
                }
                if let Some(o) = &mut summary_out {
                    o.write(summary.row(set).as_bytes());
                }
                whole += usize::from(summary.failed_rows == 0);
                failed_start += usize::from(summary.ok_rows == 0);
                if progress && ((set + 1) % mechgen::batch::CHUNK == 0 || set + 1 == count) {
                    let done = (set + 1) * 40 / count;
                    tell_raw!(
                        "\r[{}{}] {}/{count} sets",
                        "=".repeat(done),
                        " ".repeat(40 - done),
                        set + 1
                    );
                    if set + 1 == count {
                        tell!();
                    }
                }
                set += 1;
            }
        },
    )?;
    if let Some(c) = csv {
        c.finish()?;
    }
    if let Some(o) = summary_out {
        o.finish()?;
    }
    say!(
        "{}: {count} param set(s) over {} rows each: {whole} assembled on every row, {} with \
         failed rows, {failed_start} on none",
        s.name,
        plan.values.len(),
        count - whole
    );
    Ok(())
}

/// A set's rows, written as solved (`spans`: each row's index and where its text starts, in the
/// order written), put in row order.
fn in_row_order(text: &mut Vec<u8>, spans: &[(usize, usize)]) {
    if spans.is_sorted_by_key(|s| s.0) {
        return;
    }
    let ends: Vec<usize> = spans
        .iter()
        .skip(1)
        .map(|s| s.1)
        .chain([text.len()])
        .collect();
    let mut ranges: Vec<(usize, usize, usize)> = spans
        .iter()
        .zip(ends)
        .map(|(&(row, start), end)| (row, start, end))
        .collect();
    ranges.sort_unstable_by_key(|r| r.0);
    let mut ordered = Vec::with_capacity(text.len());
    for (_, start, end) in ranges {
        ordered.extend_from_slice(&text[start..end]);
    }
    *text = ordered;
}
