//! CLI, `mechgen dynamics`: inverse dynamics along a sweep (`mechgen::dynamics`, the runtime's
//! one computation, on the sweep's rows): the effort the input's driver applies against inertia,
//! gravity and loads (constant, or acting over an angle range), the generalized inertia, the
//! energies and the shaking force and moment; `--flywheel` from `mechgen::kinetics`.

use std::fmt::Write as _;

use mechgen::dynamics::PointLoad;
use mechgen::kinetics::{self, RowWork, column_names, row_dynamics};
use mechgen::plot::{DynamicsRow, dynamics_svg};
use mechgen::report::significant;
use mechgen::sweep::plan::{Range, plan};
use mechgen::{DynMechanism, Kind, MechanismInfo};

use super::args::{DynamicsArgs, LoadArg};
use super::load::{Loaded, Swept, run_plan, select};

/// The `--load` arguments by point index, refused where a point does not exist or a range is
/// given for a length input (`dynamics` and `simulate`).
pub(super) fn loads(
    given: &[LoadArg],
    info: &MechanismInfo,
    kind: Kind,
) -> Result<Vec<PointLoad<f64>>, String> {
    given
        .iter()
        .map(|(name, force, range)| {
            let point = info.points.iter().position(|p| p == name).ok_or_else(|| {
                format!(
                    "--load {name}=…: `{}` has no point `{name}` (its points: {})",
                    info.name,
                    info.points.join(", ")
                )
            })?;
            if range.is_some() && kind != Kind::Angle {
                return Err(format!(
                    "--load {name}=…@A:B: a range of degrees needs an angle input"
                ));
            }
            Ok(PointLoad {
                point,
                force: *force,
                range: range.map(|(a, b)| [a.to_radians(), b.to_radians()]),
            })
        })
        .collect()
}

/// `mechgen dynamics NAME [options]`.
pub fn dynamics_command(args: &DynamicsArgs) -> Result<(), String> {
    let options = &args.sweep;
    let file = options.file.as_deref();
    let loaded = Loaded::read(file)?;
    let sel = select(&loaded, &options.name, file, options.engine)?;
    if let Some(w) = loaded.start_warning(&options.name) {
        tell_raw!("{w}");
    }
    let info = sel.solver.info();
    kinetics::require_bodies(&info, "use dynamics")?;
    let range = Range {
        from: options.from,
        to: options.to,
        step: options.step,
    };
    let plan = plan(&info, options.input.as_deref(), &options.set, range)?;
    let index = plan.index;
    let input = info.inputs[index].clone();
    let loads = loads(&args.load, &info, input.kind)?;
    let k = sel.solver.as_ref();
    if let Some(delta) = args.flywheel {
        let f = kinetics::flywheel(k, &plan, options.rate, &loads, delta)
            .map_err(|e| format!("{}: --flywheel: {e}", info.name))?;
        say!(
            "{}: flywheel on {} at {} rad/s over one turn from {} deg (speed within ±{}/2)\nmean_effort              {}\nmax_energy_fluctuation   {}\nflywheel_inertia         {}",
            info.name,
            input.name,
            significant(options.rate),
            significant(f.from.to_degrees()),
            delta,
            significant(f.mean_effort),
            significant(f.max_energy_fluctuation),
            significant(f.flywheel_inertia),
        );
        if let Some(path) = &args.summary {
            let text = format!(
                "mean_effort,max_energy_fluctuation,flywheel_inertia\n{:?},{:?},{:?}\n",
                f.mean_effort, f.max_energy_fluctuation, f.flywheel_inertia
            );
            std::fs::write(path, text)
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        }
    }
    let swept = run_plan(k, &info, plan, options.rate)?;
    let (table, csv, plotted) = rows(k, &info, &swept, args.acc, &loads);
    say_raw!("{table}");
    if let Some(dir) = &args.plot {
        write_plot(&info, &swept, &plotted, dir)?;
    }
    match &args.csv {
        Some(path) => {
            std::fs::write(path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))
        }
        None => Ok(()),
    }
}

/// Writes `dir/NAME-dynamics.svg` (effort and energies against the input) of `swept`'s rows.
pub(super) fn write_plot(
    info: &MechanismInfo,
    swept: &Swept,
    rows: &[DynamicsRow],
    dir: &std::path::Path,
) -> Result<(), String> {
    let xs: Vec<f64> = swept.rows.iter().map(|r| r.input).collect();
    match dynamics_svg(info, swept.plan.index, &xs, rows) {
        Ok(svg) => {
            std::fs::create_dir_all(dir)
                .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
            let path = dir.join(format!("{}-dynamics.svg", info.name));
            std::fs::write(&path, svg).map_err(|e| format!("cannot write {}: {e}", path.display()))
        }
        Err(e) => {
            tell!("mechgen: {}: no dynamics plot: {e}", info.name);
            Ok(())
        }
    }
}

/// The table, the CSV and the plot's values of `swept`'s rows' dynamics (the input accelerating
/// at `acc`).
pub(super) fn rows(
    k: &dyn DynMechanism<f64>,
    info: &MechanismInfo,
    swept: &Swept,
    acc: f64,
    loads: &[PointLoad<f64>],
) -> (String, String, Vec<DynamicsRow>) {
    let mut plotted = Vec::with_capacity(swept.rows.len());
    let index = swept.plan.index;
    let input = &info.inputs[index];
    let x0 = swept.inputs(info);
    let per = if input.kind == Kind::Angle {
        180.0 / std::f64::consts::PI
    } else {
        1.0
    };
    let names = column_names(&input.name);
    let mut csv = input.name.clone();
    for u in &info.unknowns {
        let _ = write!(csv, ",{}", u.name);
    }
    for n in &names {
        let _ = write!(csv, ",{n}");
    }
    csv.push_str(",status\n");
    let unit = if input.kind == Kind::Angle {
        "deg"
    } else {
        "u"
    };
    let width = 17;
    let mut table = format!(
        "{}: inverse dynamics along {} at {} {}/s, acceleration {} (file units: {})\n",
        info.name,
        input.name,
        significant(swept.rate),
        if input.kind == Kind::Angle {
            "rad"
        } else {
            "u"
        },
        significant(acc),
        if input.kind == Kind::Angle {
            "the effort a torque, force × length"
        } else {
            "the effort a force"
        },
    );
    let _ = write!(table, "{:>width$}", format!("{} [{unit}]", input.name));
    for n in &names {
        let _ = write!(table, "{n:>width$}");
    }
    table.push('\n');
    let mut ws = RowWork::new(info);
    let mut x = x0;
    let motion = (swept.rate, acc);
    for r in &swept.rows {
        x[index] = r.input;
        let _ = write!(table, "{:>width$}", significant(r.input * per));
        let _ = write!(csv, "{:?}", r.input);
        let view = r.view();
        let d = match &view.result {
            Ok(s) => row_dynamics(k, &x, index, s, motion, loads, &mut ws)
                .map(|d| (s.q, d))
                .map_err(|e| e.status()),
            Err(_) => Err(r.status()),
        };
        match d {
            Ok((q, d)) => {
                plotted.push(Some([d.effort, d.kinetic, d.potential]));
                for q in q {
                    let _ = write!(csv, ",{q:?}");
                }
                for v in kinetics::values(&d) {
                    let _ = write!(table, "{:>width$}", significant(v));
                    let _ = write!(csv, ",{v:?}");
                }
                csv.push_str(",ok\n");
            }
            Err(status) => {
                plotted.push(None);
                let _ = write!(table, "  {status}");
                csv.push_str(&",".repeat(info.unknowns.len() + names.len()));
                let _ = writeln!(csv, ",{status}");
            }
        }
        table.push('\n');
    }
    (table, csv, plotted)
}
