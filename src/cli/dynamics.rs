//! CLI, `mechgen dynamics`: inverse dynamics along a sweep (`mechgen::dynamics`, the runtime's
//! one computation, on the sweep's rows): the effort the input's driver applies against inertia,
//! gravity and loads (constant, or acting over an angle range), the generalized inertia, the
//! energies and the shaking force and moment; `--flywheel` from `mechgen::kinetics`.

use std::fmt::Write as _;
use std::io::Write as _;

use mechgen::dynamics::PointLoad;
use mechgen::kinetics::{self, RowWork, column_names, row_dynamics};
use mechgen::plot::{DynamicsRow, dynamics_svg};
use mechgen::report::significant;
use mechgen::sweep::RowRef;
use mechgen::sweep::check_start;
use mechgen::sweep::plan::{Plan, Range, plan};
use mechgen::{DynMechanism, Kind, MechanismInfo};

use super::args::{DynamicsArgs, LoadArg};
use super::load::{Loaded, Swept, Thinning, select, stream_plan};
use super::out::Out;

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
    check_start(&info).map_err(|e| format!("{}: {e}", info.name))?;
    // Rows printed and written as they are solved; of the plot's values, the rows a streamed
    // sweep keeps.
    let mut each = RowDynamics::new(k, &info, &plan, options.rate, args.acc, &loads);
    let stdout = std::io::stdout();
    let mut table = std::io::BufWriter::with_capacity(super::OUTPUT_BUFFER, stdout.lock());
    let _ = table.write_all(each.table_header().as_bytes());
    let mut csv = match &args.csv {
        Some(path) => Some(Out::create(path, &each.csv_header())?),
        None => None,
    };
    let mut plotted = args.plot.is_some().then(|| Plotted::new(plan.values.len()));
    stream_plan(k, &info, plan, options.rate, None, &mut |r| {
        let value = each.row(r);
        // A closed stdout (`… | head`) ends the table, not the rows or their CSV.
        let _ = table.write_all(each.table.as_bytes());
        if let Some(out) = &mut csv {
            out.write(each.csv.as_bytes());
        }
        if let Some(p) = &mut plotted {
            p.push(r.input, value);
        }
    })?;
    let _ = table.flush();
    drop(table);
    if let (Some(dir), Some(p)) = (&args.plot, &plotted) {
        write_plot(&info, index, &p.xs, &p.values, dir)?;
    }
    csv.map_or(Ok(()), Out::finish)
}

/// The plot's values of a streamed sweep's rows: those [`Thinning`] keeps.
struct Plotted {
    thin: Thinning,
    xs: Vec<f64>,
    values: Vec<DynamicsRow>,
    /// The row before the current one, when it was not kept.
    previous: Option<(f64, DynamicsRow)>,
}

impl Plotted {
    fn new(rows: usize) -> Plotted {
        Plotted {
            thin: Thinning::new(rows),
            xs: Vec::new(),
            values: Vec::new(),
            previous: None,
        }
    }

    fn push(&mut self, x: f64, value: DynamicsRow) {
        let (before, this) = self
            .thin
            .next(if value.is_some() { "ok" } else { "failed" });
        if before && let Some((px, pv)) = self.previous {
            self.xs.push(px);
            self.values.push(pv);
        }
        if this {
            self.xs.push(x);
            self.values.push(value);
        } else {
            self.previous = Some((x, value));
        }
    }
}

/// Writes `dir/NAME-dynamics.svg` (effort and energies against the input `index`, at `xs`).
pub(super) fn write_plot(
    info: &MechanismInfo,
    index: usize,
    xs: &[f64],
    rows: &[DynamicsRow],
    dir: &std::path::Path,
) -> Result<(), String> {
    match dynamics_svg(info, index, xs, rows) {
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
/// at `acc`), whole.
pub(super) fn rows(
    k: &dyn DynMechanism<f64>,
    info: &MechanismInfo,
    swept: &Swept,
    acc: f64,
    loads: &[PointLoad<f64>],
) -> (String, String, Vec<DynamicsRow>) {
    let mut each = RowDynamics::new(k, info, &swept.plan, swept.rate, acc, loads);
    let (mut table, mut csv) = (each.table_header(), each.csv_header());
    let mut plotted = Vec::with_capacity(swept.rows.len());
    for r in &swept.rows {
        plotted.push(each.row(&r.view()));
        table.push_str(&each.table);
        csv.push_str(&each.csv);
    }
    (table, csv, plotted)
}

/// The inverse dynamics of a sweep's rows, one row at a time: its table line and CSV line
/// (reused row after row) and its plot values.
pub(super) struct RowDynamics<'a> {
    k: &'a dyn DynMechanism<f64>,
    info: &'a MechanismInfo,
    index: usize,
    /// Every input's value, the swept one the row's.
    x: Vec<f64>,
    /// The swept input's rate and acceleration.
    motion: (f64, f64),
    loads: &'a [PointLoad<f64>],
    ws: RowWork,
    /// The swept input's table unit per file unit (degrees per radian for an angle).
    per: f64,
    /// A failed row's empty cells.
    blank: String,
    /// The last row's table line and CSV line, each ending in a newline.
    pub(super) table: String,
    pub(super) csv: String,
}

/// Width of a table column.
const WIDTH: usize = 17;

impl<'a> RowDynamics<'a> {
    pub(super) fn new(
        k: &'a dyn DynMechanism<f64>,
        info: &'a MechanismInfo,
        plan: &Plan,
        rate: f64,
        acc: f64,
        loads: &'a [PointLoad<f64>],
    ) -> RowDynamics<'a> {
        let index = plan.index;
        let mut x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
        for &(i, v) in &plan.held {
            x[i] = v;
        }
        let per = if info.inputs[index].kind == Kind::Angle {
            180.0 / std::f64::consts::PI
        } else {
            1.0
        };
        RowDynamics {
            k,
            info,
            index,
            x,
            motion: (rate, acc),
            loads,
            ws: RowWork::new(info),
            per,
            blank: ",".repeat(info.unknowns.len() + column_names(&info.inputs[index].name).len()),
            table: String::new(),
            csv: String::new(),
        }
    }

    /// The table's title line and column names.
    pub(super) fn table_header(&self) -> String {
        let input = &self.info.inputs[self.index];
        let angle = input.kind == Kind::Angle;
        let mut table = format!(
            "{}: inverse dynamics along {} at {} {}/s, acceleration {} (file units: {})\n",
            self.info.name,
            input.name,
            significant(self.motion.0),
            if angle { "rad" } else { "u" },
            significant(self.motion.1),
            if angle {
                "the effort a torque, force × length"
            } else {
                "the effort a force"
            },
        );
        let unit = if angle { "deg" } else { "u" };
        let _ = write!(table, "{:>WIDTH$}", format!("{} [{unit}]", input.name));
        for n in &column_names(&input.name) {
            let _ = write!(table, "{n:>WIDTH$}");
        }
        table.push('\n');
        table
    }

    /// The CSV's header line.
    pub(super) fn csv_header(&self) -> String {
        let input = &self.info.inputs[self.index];
        let mut csv = input.name.clone();
        for u in &self.info.unknowns {
            let _ = write!(csv, ",{}", u.name);
        }
        for n in &column_names(&input.name) {
            let _ = write!(csv, ",{n}");
        }
        csv.push_str(",status\n");
        csv
    }

    /// Row `r`'s dynamics into [`RowDynamics::table`] and [`RowDynamics::csv`]; its plot values.
    pub(super) fn row(&mut self, r: &RowRef<'_>) -> DynamicsRow {
        let (table, csv) = (&mut self.table, &mut self.csv);
        table.clear();
        csv.clear();
        self.x[self.index] = r.input;
        let _ = write!(table, "{:>WIDTH$}", significant(r.input * self.per));
        let _ = write!(csv, "{:?}", r.input);
        let d = match &r.result {
            Ok(s) => row_dynamics(
                self.k,
                &self.x,
                self.index,
                s,
                self.motion,
                self.loads,
                &mut self.ws,
            )
            .map(|d| (s.q, d))
            .map_err(|e| e.status()),
            Err(_) => Err(r.status()),
        };
        let plotted = match d {
            Ok((q, d)) => {
                for q in q {
                    let _ = write!(csv, ",{q:?}");
                }
                for v in kinetics::values(&d) {
                    let _ = write!(table, "{:>WIDTH$}", significant(v));
                    let _ = write!(csv, ",{v:?}");
                }
                csv.push_str(",ok\n");
                Some([d.effort, d.kinetic, d.potential])
            }
            Err(status) => {
                let _ = write!(table, "  {status}");
                csv.push_str(&self.blank);
                let _ = writeln!(csv, ",{status}");
                None
            }
        };
        table.push('\n');
        plotted
    }
}
