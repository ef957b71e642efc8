//! CLI, `mechgen branches NAME`: loads the file (compiled-in or `--file`), analyses the named
//! mechanism along its first input (`mechgen::branches`; the analysis is made from the file's
//! analysis, so both `--engine` values give the same result), prints the summary and writes the
//! CSV files and the plot asked for. Also the summary line block of the main job.

use std::path::Path;

use mechgen::branches::{Analysis, Setup};
use mechgen::sweep::plan::no_input;
use mechgen_codegen::diagnostic::{Diagnostic, render};
use mechgen_codegen::{Compiled, Coord, Kind};

use super::args::{BranchesArgs, Engine};

/// The analysed file's mechanisms (the process's one analysis of the file), or its errors.
pub(super) fn compile(path: Option<&Path>) -> Result<FileMechanisms, String> {
    let a = super::analysed::analysis(path)?;
    if a.diagnostics.iter().any(Diagnostic::is_error) {
        return Err(render(&a.file, &a.diagnostics).trim_end().to_string());
    }
    Ok(FileMechanisms(a))
}

/// A file's mechanisms, as [`compile`] gives them.
pub(super) struct FileMechanisms(std::rc::Rc<super::analysed::FileAnalysis>);

impl std::ops::Deref for FileMechanisms {
    type Target = [Compiled];
    fn deref(&self) -> &[Compiled] {
        &self.0.compiled
    }
}

/// The input range of the start's branch of mechanism `name` (radians or file units): between
/// the dead points that bound it. For a length input, the branch analysis over the start ± four
/// length scales (at least ± 1), or that window's end where no dead point bounds it; for an angle
/// input, the analysis over a full turn, the range shifted by whole turns to hold the start, and
/// `None` for a branch that turns fully (no dead point on it). `None` also when the analysis has
/// no answer.
pub(super) fn start_branch(path: Option<&Path>, name: &str) -> Option<StartBranch> {
    let compiled = compile(path).ok()?;
    let c = compiled.iter().find(|c| c.model.name.text == name)?;
    let setup = Setup::new(c, 0).ok()?;
    let x0 = c.model.inputs.first()?.start;
    let q0: Vec<f64> = c.model.unknowns.iter().map(|u| u.start).collect();
    let (from, to, at) = if setup.input_is_angle {
        let tau = std::f64::consts::TAU;
        (0.0, tau, x0.rem_euclid(tau))
    } else {
        let w = 4.0 * setup.scale.max(x0.abs()).max(1.0);
        (x0 - w, x0 + w, x0)
    };
    let a = setup.analyze(from, to, &[at]).ok()?;
    let mine =
        a.at.iter()
            .min_by(|x, y| setup.dist(&x.q, &q0).total_cmp(&setup.dist(&y.q, &q0)))?;
    let b = a.branches.get(mine.branch)?;
    if !(b.from.is_finite() && b.to.is_finite() && b.from < b.to) || b.full_turn {
        return None;
    }
    // The dead points' states at the range's ends (`dead[0]` at `from`, `dead[1]` at `to`).
    let ends = |from: f64, to: f64| -> Vec<(f64, Vec<f64>)> {
        b.dead
            .iter()
            .zip([from, to])
            .filter_map(|(d, x)| Some((x, a.dead_points.get((*d)?)?.q.clone())))
            .collect()
    };
    if !setup.input_is_angle {
        return Some(StartBranch {
            from: b.from,
            to: b.to,
            ends: ends(b.from, b.to),
        });
    }
    // Both ends must be dead points (a branch of a full turn's analysis may end at the range's
    // seam only when it turns fully, handled above).
    if b.dead.iter().any(Option::is_none) {
        return None;
    }
    // The turn that holds the start: the range moved by whole turns so that from ≤ x0 ≤ to.
    let tau = std::f64::consts::TAU;
    let shift = ((x0 - b.from) / tau).floor() * tau;
    let (lo, hi) = (b.from + shift, b.to + shift);
    (lo <= x0 && x0 <= hi).then(|| StartBranch {
        from: lo,
        to: hi,
        ends: ends(lo, hi),
    })
}

/// The start's branch: its input range (radians for an angle, file units) and the states
/// (input, unknowns) of the dead points that end it.
pub(super) struct StartBranch {
    pub from: f64,
    pub to: f64,
    pub ends: Vec<(f64, Vec<f64>)>,
}

/// The analysis of one mechanism over a range given in the CLI's units (degrees for an angle),
/// along its first input, the others at their start values.
fn analyse(
    c: &Compiled,
    from: Option<f64>,
    to: Option<f64>,
    at: &[f64],
) -> Result<(Setup, Analysis), String> {
    analyse_along(c, None, &[], (from, to), at)
}

/// [`analyse`] along input `input` (default the first), the inputs of `set` held at their values
/// (degrees for an angle), the others at their start values.
fn analyse_along(
    c: &Compiled,
    input: Option<&str>,
    set: &[(String, f64)],
    (from, to): (Option<f64>, Option<f64>),
    at: &[f64],
) -> Result<(Setup, Analysis), String> {
    let m = &c.model;
    let find = |name: &str| {
        m.inputs
            .iter()
            .position(|i| i.name.text == name)
            .ok_or_else(|| {
                let coords = |c: &[Coord]| c.iter().map(|c| c.name.text.clone()).collect();
                let inputs: Vec<String> = coords(&m.inputs);
                let unknowns: Vec<String> = coords(&m.unknowns);
                let params: Vec<String> = m.params.iter().map(|p| p.name.text.clone()).collect();
                no_input(&m.name.text, name, [&inputs, &unknowns, &params])
            })
    };
    let index = input.map_or(Ok(0), find)?;
    let mut setup = Setup::new(c, index)?;
    for (name, value) in set {
        let i = find(name)?;
        let v = if m.inputs[i].kind == Kind::Angle {
            value.to_radians()
        } else {
            *value
        };
        if !setup.hold(i, v) {
            return Err(format!(
                "--set {name}=…: `{name}` is the input analysed along (use --from/--to, or --input to analyse along another)"
            ));
        }
    }
    let angle = m.inputs[index].kind == Kind::Angle;
    let (from, to) = match (angle, from, to) {
        (true, from, to) => {
            let from = from.unwrap_or(0.0);
            (from.to_radians(), to.unwrap_or(from + 360.0).to_radians())
        }
        (false, Some(f), Some(t)) => (f, t),
        (false, _, _) => {
            return Err(format!(
                "`{}` has a length input ({}): --from and --to are required",
                setup.name, setup.input_name
            ));
        }
    };
    if to <= from {
        return Err("--to must be greater than --from".into());
    }
    let at: Vec<f64> = at
        .iter()
        .map(|&x| if angle { x.to_radians() } else { x })
        .collect();
    let analysis = setup.analyze(from, to, &at)?;
    Ok((setup, analysis))
}

fn write(dir: &Path, file: String, text: &str) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let path = dir.join(file);
    std::fs::write(&path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// `mechgen branches NAME [options]`.
pub fn run(args: &BranchesArgs) -> Result<(), String> {
    if args.file.is_some() && args.engine == Some(Engine::Generated) {
        return Err(
            "--engine generated exists only for compiled-in mechanisms; use --engine jit or generic with --file"
                .into(),
        );
    }
    let compiled = compile(args.file.as_deref())?;
    let c = compiled
        .iter()
        .find(|c| c.model.name.text == args.name)
        .ok_or_else(|| {
            // A scene's configuration space is its mechanism's: say so and name the command.
            let scene_of = compiled.iter().find(|c| {
                c.model
                    .scenes
                    .iter()
                    .any(|s| s.name.text == args.name)
            });
            if let Some(m) = scene_of {
                let m = &m.model.name.text;
                return format!(
                    "`{}` is a scene of mechanism `{m}`: a scene has its mechanism's branches and dead points; run `mechgen branches {m}`",
                    args.name
                );
            }
            let names: Vec<&str> = compiled
                .iter()
                .map(|c| c.model.name.text.as_str())
                .collect();
            format!(
                "no mechanism `{}` (the file has: {})",
                args.name,
                names.join(", ")
            )
        })?;
    if args.file.is_none()
        && args.engine == Some(Engine::Generated)
        && mechgen::lookup::<f64>(&args.name).is_none()
    {
        return Err(format!("no compiled-in mechanism `{}`", args.name));
    }
    let started = std::time::Instant::now();
    let (setup, analysis) = analyse_along(
        c,
        args.input.as_deref(),
        &args.set,
        (args.from, args.to),
        &args.at,
    )?;
    let elapsed = started.elapsed();
    say_raw!("{}", setup.summary(&analysis));
    say!("(analysis: {:.1} ms)", elapsed.as_secs_f64() * 1e3);
    if let Some(dir) = &args.csv {
        let n = &setup.name;
        write(
            dir,
            format!("{n}-dead-points.csv"),
            &setup.dead_points_csv(&analysis),
        )?;
        write(
            dir,
            format!("{n}-branches.csv"),
            &setup.branches_csv(&analysis),
        )?;
        write(dir, format!("{n}-at.csv"), &setup.at_csv(&analysis))?;
        write(
            dir,
            format!("{n}-crossings.csv"),
            &setup.crossings_csv(&analysis),
        )?;
    }
    if let Some(dir) = &args.plot {
        let svg = mechgen::plot::branches_svg(&setup, &analysis).map_err(|e| e.to_string())?;
        write(dir, format!("{}-branches.svg", setup.name), &svg)?;
    }
    Ok(())
}

/// The branch summary of every mechanism of a file (the main job), over a full turn of an angle
/// input or a length input's default range `(from, to)`; a mechanism that cannot be analysed
/// gets its reason.
pub fn summary(path: Option<&Path>, name: &str, length_range: (f64, f64)) -> String {
    let result = compile(path).and_then(|cs| {
        let c = cs
            .iter()
            .find(|c| c.model.name.text == name)
            .ok_or_else(|| format!("no mechanism `{name}`"))?;
        let angle = c.model.inputs.first().map(|i| i.kind) == Some(Kind::Angle);
        let (from, to) = if angle {
            (Some(0.0), Some(360.0))
        } else {
            (Some(length_range.0), Some(length_range.1))
        };
        analyse(c, from, to, &[])
    });
    match result {
        Ok((setup, analysis)) => setup.summary(&analysis),
        Err(e) => format!("{name}: no branch analysis: {e}\n"),
    }
}

/// For a sweep of the first input (others at their start values) that stopped at a dead point:
/// which branch it was on and which branch of the same circuit continues there, from the branch
/// analysis. `None` when the sweep did not stop at a dead point or the analysis does not apply.
pub fn sweep_note(
    path: Option<&Path>,
    name: &str,
    index: usize,
    held: bool,
    rows: &[mechgen::sweep::Row],
) -> Option<String> {
    if index != 0 || held {
        return None;
    }
    let stop = rows.iter().find_map(mechgen::sweep::Row::dead_point)?;
    let compiled = compile(path).ok()?;
    let c = compiled.iter().find(|c| c.model.name.text == name)?;
    // The solved row nearest the stop (or, when none was solved, the start): its configuration
    // picks the sweep's branch.
    let start = (
        c.model.inputs.first()?.start,
        c.model.unknowns.iter().map(|u| u.start).collect::<Vec<_>>(),
    );
    let last = rows
        .iter()
        .filter_map(|r| r.result.as_ref().ok().map(|s| (r.input, s.q.clone())))
        .min_by(|a, b| {
            (a.0 - stop.input)
                .abs()
                .total_cmp(&(b.0 - stop.input).abs())
        })
        .unwrap_or(start);
    let setup = Setup::new(c, 0).ok()?;
    let (from, to) = if setup.input_is_angle {
        // The default range of `mechgen branches`, so that the labels are its labels.
        (0.0, std::f64::consts::TAU)
    } else {
        let w = (stop.input - last.0).abs().max(setup.scale);
        (last.0.min(stop.input) - w, last.0.max(stop.input) + w)
    };
    let a = setup.analyze(from, to, &[last.0]).ok()?;
    let mine = a.at.iter().min_by(|x, y| {
        setup
            .dist(&x.q, &last.1)
            .total_cmp(&setup.dist(&y.q, &last.1))
    })?;
    let gap = |d: f64| {
        if setup.input_is_angle {
            let g = (d - stop.input).rem_euclid(std::f64::consts::TAU);
            g.min(std::f64::consts::TAU - g)
        } else {
            (d - stop.input).abs()
        }
    };
    let (k, _) = a
        .dead_points
        .iter()
        .enumerate()
        .min_by(|x, y| gap(x.1.input).total_cmp(&gap(y.1.input)))?;
    let other = a
        .branches
        .iter()
        .enumerate()
        .find(|(b, br)| *b != mine.branch && br.dead.contains(&Some(k)))?
        .0;
    let x = a.dead_points[k].input;
    let shown = if setup.input_is_angle {
        format!("{:.6} deg", x.to_degrees())
    } else {
        format!("{x:.6}")
    };
    Some(format!(
        "branch analysis: the sweep followed branch {} (circuit {}); at the dead point {} = {shown} \
         branch {other} of the same circuit continues (mechgen branches {name})",
        mine.branch, mine.circuit, setup.input_name
    ))
}
