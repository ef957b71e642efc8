//! CLI, the command line as clap (derive) parses it: the main job's options, `sweep` and `check`
//! (a `branches` command slots in as one more [`Command`] variant). Help text for every option.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

/// Planar linkage kinematics from loop equations: sweeps, tables, CSVs and plots.
///
/// With no command, runs the main job: every mechanism of the compiled-in mechanism.toml (or of
/// --file) swept over a full turn, tables printed, CSVs and SVG plots written to --out DIR
/// (default ./mechgen-out/).
#[derive(Debug, Parser)]
#[command(name = "mechgen", version, args_conflicts_with_subcommands = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    #[command(flatten)]
    pub main: MainArgs,
}

/// The main job's options (no command given).
#[derive(Debug, Args)]
pub struct MainArgs {
    /// Run the main job on this mechanism file, loaded at run time into the generic engine,
    /// instead of the compiled-in mechanism.toml.
    #[arg(long, value_name = "PATH")]
    pub file: Option<PathBuf>,
    /// Also write an animated SVG of each mechanism over its sweep into DIR.
    #[arg(long, value_name = "DIR")]
    pub animate: Option<PathBuf>,
    /// Write the CSVs and plots of the main job into DIR (created if missing).
    #[arg(long, value_name = "DIR", default_value = "mechgen-out")]
    pub out: PathBuf,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Sweep one input of a mechanism along its start configuration's branch and print a table
    /// (angles in degrees).
    Sweep(Box<SweepArgs>),
    /// Validate a mechanism file and print its mechanisms, sizes and block structure, or every
    /// error as FILE:LINE:COLUMN.
    Check(CheckArgs),
    /// Every circuit, branch and dead point of a mechanism along its first input, and every
    /// assembly configuration at chosen inputs.
    Branches(BranchesArgs),
    /// What a designer reads first, on the start's branch: each output's min and max (stroke,
    /// rocker swing) with the inputs where they occur, time ratios, transmission angles.
    Metrics(MetricsArgs),
    /// Sweep a mechanism for every param set of a CSV (one row per set), across every core:
    /// every row of every set as CSV, a summary per set.
    Batch(Box<BatchArgs>),
    /// The derivatives of every unknown and point position with respect to every param (derived
    /// params differentiated through), along a sweep.
    Sensitivity(Box<SensitivityArgs>),
    /// The worst-case and root-sum-square deviation of every unknown and point coordinate for
    /// given param tolerances, along a sweep, at each output's worst row.
    Tolerance(Box<ToleranceArgs>),
    /// Inverse dynamics along a sweep (a mechanism with bodies): the effort the input's driver
    /// applies against inertia, gravity and loads, the generalized inertia, the energies, the
    /// shaking force and moment; `--flywheel` for the flywheel a turn needs.
    Dynamics(Box<DynamicsArgs>),
    /// Forward dynamics (a mechanism with bodies): the motion of an input under gravity, loads
    /// and a constant driving effort, from the start configuration, a row every --dt.
    Simulate(Box<SimulateArgs>),
}

/// `mechgen simulate NAME --time T --dt DT [options]`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// The mechanism, as named in the file ([mechanism.NAME]).
    pub name: String,
    /// Load the mechanism from this file at run time instead of the compiled-in mechanism.toml.
    #[arg(long, value_name = "PATH")]
    pub file: Option<PathBuf>,
    /// Which solvers to use [default: generated when compiled in, else jit (or generic)].
    #[arg(long, value_enum)]
    pub engine: Option<Engine>,
    /// How long to simulate (seconds).
    #[arg(long, value_name = "T", allow_negative_numbers = true, value_parser = finite)]
    pub time: f64,
    /// The time between rows (seconds); the integrator's steps are chosen by its error control.
    #[arg(long, value_name = "DT", allow_negative_numbers = true, value_parser = finite)]
    pub dt: f64,
    /// The constant driving effort on the input (torque for an angle input, force for a length).
    #[arg(long, value_name = "Q", default_value_t = 0.0, allow_negative_numbers = true, value_parser = finite)]
    pub torque: f64,
    /// The input's rate at the start (rad/s, or file units/s).
    #[arg(long, value_name = "W0", default_value_t = 0.0, allow_negative_numbers = true, value_parser = finite)]
    pub rate: f64,
    /// A constant force (FX, FY) on point P, or `P=FX,FY@A:B` acting only while the angle input
    /// lies in [A, B] degrees (modulo a turn; B < A wraps through 0); repeatable.
    #[arg(long = "load", value_name = "P=FX,FY[@A:B]", value_parser = ranged_load)]
    pub load: Vec<LoadArg>,
    /// Which input moves, for a mechanism with several [default: the first]; the others are held
    /// at rest.
    #[arg(long, value_name = "NAME")]
    pub input: Option<String>,
    /// The value of a held input (degrees for an angle, file units for a length); repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = assignment)]
    pub set: Vec<(String, f64)>,
    /// Every row as CSV: `t`, the input, `X_vel`, `X_acc`, every unknown, `kinetic_energy`,
    /// `potential_energy`, `status`.
    #[arg(long, value_name = "PATH")]
    pub csv: Option<PathBuf>,
}

/// `mechgen dynamics NAME [options]`.
#[derive(Debug, Args)]
pub struct DynamicsArgs {
    #[command(flatten)]
    pub sweep: SweepOptions,
    /// The swept input's acceleration (rad/s² for an angle input, file units/s² for a length).
    #[arg(long, value_name = "A", default_value_t = 0.0, allow_negative_numbers = true, value_parser = finite)]
    pub acc: f64,
    /// A constant force (FX, FY) on point P, or `P=FX,FY@A:B` acting only while the angle input
    /// lies in [A, B] degrees (modulo a turn; B < A wraps through 0); repeatable.
    #[arg(long = "load", value_name = "P=FX,FY[@A:B]", value_parser = ranged_load)]
    pub load: Vec<LoadArg>,
    /// Every row as CSV: the input, every unknown, `effort_X`, `inertia_X_X`, `kinetic_energy`,
    /// `potential_energy`, `shaking_fx`, `shaking_fy`, `shaking_moment`, `status`.
    #[arg(long, value_name = "PATH")]
    pub csv: Option<PathBuf>,
    /// The flywheel for a speed within ±DELTA/2 of --rate over one turn from the start (an angle
    /// input): mean effort, largest swing of the work excess, flywheel inertia (exact integrals).
    #[arg(long, value_name = "DELTA", allow_negative_numbers = true, value_parser = finite)]
    pub flywheel: Option<f64>,
    /// Also write DIR/NAME-dynamics.svg: the effort and the energies against the input.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    /// With --flywheel: also write `mean_effort,max_energy_fluctuation,flywheel_inertia` to PATH.
    #[arg(long, value_name = "PATH", requires = "flywheel")]
    pub summary: Option<PathBuf>,
}

/// `P=FX,FY` or `P=FX,FY@A:B` (degrees), every number finite.
/// `--load P=FX,FY[@A:B]` as given: the point's name, the force, the range of degrees.
pub type LoadArg = (String, [f64; 2], Option<(f64, f64)>);

fn ranged_load(s: &str) -> Result<LoadArg, String> {
    let (head, range) = match s.split_once('@') {
        Some((h, r)) => {
            let (a, b) = r
                .split_once(':')
                .ok_or_else(|| "needs P=FX,FY@A:B".to_string())?;
            (h, Some((finite(a)?, finite(b)?)))
        }
        None => (s, None),
    };
    let (name, force) = load(head)?;
    Ok((name, force, range))
}

/// `mechgen sensitivity NAME [options]`.
#[derive(Debug, Args)]
pub struct SensitivityArgs {
    /// Every row as CSV: the input, `u/p` per unknown and param, `P_x/p`, `P_y/p` per point and
    /// param (radians per param unit), then `status`.
    #[arg(long, value_name = "PATH")]
    pub csv: Option<PathBuf>,
    #[command(flatten)]
    pub sweep: SweepOptions,
}

/// `mechgen tolerance NAME --tol p=T [--tol p=T ...] [options]`.
#[derive(Debug, Args)]
pub struct ToleranceArgs {
    /// A param's tolerance T (file units; degrees for an angle param); repeatable.
    #[arg(long = "tol", value_name = "PARAM=T", value_parser = assignment, required = true)]
    pub tol: Vec<(String, f64)>,
    /// Every row as CSV: the input, `y_worst` and `y_rss` per output `y`, then `status`.
    #[arg(long, value_name = "PATH")]
    pub csv: Option<PathBuf>,
    #[command(flatten)]
    pub sweep: SweepOptions,
}

/// `mechgen batch NAME --params SETS.csv [options]`.
#[derive(Debug, Args)]
pub struct BatchArgs {
    /// The param sets: a header of param names (any of the mechanism's), one row per set; the
    /// params it does not name keep the file's values.
    #[arg(long, value_name = "PATH")]
    pub params: PathBuf,
    /// Every row of every set as CSV: `set`, then the columns of sweep's CSV.
    #[arg(long, value_name = "PATH")]
    pub csv: Option<PathBuf>,
    /// One row per set: ok_rows, failed_rows, first_failure, each output's min and max.
    #[arg(long, value_name = "PATH")]
    pub summary: Option<PathBuf>,
    /// Worker threads [default: every core].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..))]
    pub threads: Option<u16>,
    /// The sweep of each set, with sweep's options (except its outputs).
    #[command(flatten)]
    pub sweep: SweepOptions,
}

/// `mechgen metrics NAME [options]`.
#[derive(Debug, Args)]
pub struct MetricsArgs {
    /// The mechanism, as named in the file ([mechanism.NAME]).
    pub name: String,
    /// Load the mechanism from this file at run time (generic engine).
    #[arg(long, value_name = "PATH")]
    pub file: Option<PathBuf>,
    /// Which solvers to use [default: generated when compiled in, else generic].
    #[arg(long, value_enum)]
    pub engine: Option<Engine>,
    /// Start of the input range: degrees for an angle input, file units for a length input
    /// [default: a full turn of an angle input from its start; required for a length].
    #[arg(long, value_name = "X", allow_negative_numbers = true, value_parser = finite)]
    pub from: Option<f64>,
    /// End of the input range [default: a full turn after --from].
    #[arg(long, value_name = "X", allow_negative_numbers = true, value_parser = finite)]
    pub to: Option<f64>,
    /// Also write the metrics as CSV (radians; interfaces.md).
    #[arg(long, value_name = "PATH")]
    pub csv: Option<PathBuf>,
    /// Which input to move, for a mechanism with several [default: the first].
    #[arg(long, value_name = "NAME")]
    pub input: Option<String>,
    /// The value of an input that is not moved (degrees for an angle); repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = assignment)]
    pub set: Vec<(String, f64)>,
}

/// `mechgen branches NAME [options]`.
#[derive(Debug, Args)]
pub struct BranchesArgs {
    /// The mechanism, as named in the file ([mechanism.NAME]).
    pub name: String,
    /// Load the mechanism from this file at run time instead of the compiled-in mechanism.toml.
    #[arg(long, value_name = "PATH")]
    pub file: Option<PathBuf>,
    /// As for sweep; both engines give the same analysis (it is made from the file's analysis).
    #[arg(long, value_enum)]
    pub engine: Option<Engine>,
    /// Start of the input range: degrees for an angle input, file units for a length input
    /// [default: a full turn for an angle; required for a length].
    #[arg(long, value_name = "X", allow_negative_numbers = true, value_parser = finite)]
    pub from: Option<f64>,
    /// End of the input range [default: --from + 360 for an angle; required for a length].
    #[arg(long, value_name = "X", allow_negative_numbers = true, value_parser = finite)]
    pub to: Option<f64>,
    /// An input at which to list every assembly configuration (repeatable).
    #[arg(long, value_name = "X", allow_negative_numbers = true, value_parser = finite)]
    pub at: Vec<f64>,
    /// Which input to analyse along, for a mechanism with several [default: the first].
    #[arg(long, value_name = "NAME")]
    pub input: Option<String>,
    /// The value of an input held during the analysis (degrees for an angle, file units for a
    /// length); repeatable; inputs not set stay at their start values.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = assignment)]
    pub set: Vec<(String, f64)>,
    /// Write NAME-dead-points.csv, NAME-branches.csv, NAME-at.csv and NAME-crossings.csv into DIR.
    #[arg(long, value_name = "DIR")]
    pub csv: Option<PathBuf>,
    /// Write DIR/NAME-branches.svg: every unknown against the input, one colour per branch.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
}

/// Which solvers a sweep uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Engine {
    /// The solvers generated at build time (compiled-in mechanisms only).
    Generated,
    /// The mechanism file compiled to machine code at run time (Cranelift); the default for
    /// `--file` where the host has a back end.
    Jit,
    /// The run-time engine that interprets the mechanism file.
    Generic,
}

/// `mechgen sweep NAME [options]`: the sweep, and what it writes.
#[derive(Debug, Args)]
pub struct SweepArgs {
    #[command(flatten)]
    pub sweep: SweepOptions,
    /// Also write the rows as CSV (radians, full precision) to PATH.
    #[arg(long, value_name = "PATH")]
    pub csv: Option<PathBuf>,
    /// Also write DIR/NAME-motion.svg and DIR/NAME-drawing.svg.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    /// Also write an animated SVG of the mechanism over the sweep into DIR.
    #[arg(long, value_name = "DIR")]
    pub animate: Option<PathBuf>,
    /// A force (FX, FY, file force units) on point P; repeatable. Adds the column
    /// `input_effort`: the input torque (angle input) or force (length input) that balances the
    /// loads, by virtual work.
    #[arg(long = "load", value_name = "P=FX,FY", value_parser = load)]
    pub load: Vec<(String, [f64; 2])>,
}

/// `P=FX,FY` with finite FX and FY.
fn load(s: &str) -> Result<(String, [f64; 2]), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| "needs P=FX,FY".to_string())?;
    let (fx, fy) = value
        .split_once(',')
        .ok_or_else(|| "needs P=FX,FY".to_string())?;
    let name = name.trim();
    if name.is_empty() {
        return Err("needs P=FX,FY".into());
    }
    Ok((name.to_string(), [finite(fx)?, finite(fy)?]))
}

impl std::ops::Deref for SweepArgs {
    type Target = SweepOptions;
    fn deref(&self) -> &SweepOptions {
        &self.sweep
    }
}

/// What a sweep is: the mechanism, the engine, the range, the rate and the held inputs (`sweep`'s
/// options, and each set's sweep in `batch`).
#[derive(Debug, Args)]
pub struct SweepOptions {
    /// The mechanism to sweep, as named in the file ([mechanism.NAME]).
    pub name: String,
    /// Load the mechanism from this file at run time (generic engine) instead of the
    /// compiled-in mechanism.toml.
    #[arg(long, value_name = "PATH")]
    pub file: Option<PathBuf>,
    /// Which solvers to use [default: generated when compiled in, else generic].
    #[arg(long, value_enum)]
    pub engine: Option<Engine>,
    /// First input value: degrees for an angle input, file units for a length input
    /// [default: 0 for an angle; required for a length].
    #[arg(long, value_name = "X", allow_negative_numbers = true, value_parser = finite)]
    pub from: Option<f64>,
    /// Last input value, always the last row (both ends included): degrees for an angle input,
    /// file units for a length input [default: 360 for an angle; required for a length].
    #[arg(long, value_name = "X", allow_negative_numbers = true, value_parser = finite)]
    pub to: Option<f64>,
    /// Distance between rows (its sign is ignored: rows go from --from to --to); when it does not
    /// divide the range the last step is shorter [default: 10 for an angle, a 36th of the range
    /// for a length].
    #[arg(long, value_name = "X", allow_negative_numbers = true, value_parser = finite)]
    pub step: Option<f64>,
    /// Input velocity: rad/s for an angle input (the table prints deg/s), file units per second
    /// for a length input; the input acceleration is zero.
    #[arg(long, value_name = "V", default_value_t = 1.0, allow_negative_numbers = true, value_parser = finite)]
    pub rate: f64,
    /// Which input to sweep, for a mechanism with several [default: the first].
    #[arg(long, value_name = "NAME")]
    pub input: Option<String>,
    /// The value of an input that is not swept (degrees for an angle, file units for a length);
    /// repeatable; inputs not set stay at their start values.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = assignment)]
    pub set: Vec<(String, f64)>,
}

/// `mechgen check [--file PATH]`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// The mechanism file to check [default: the compiled-in mechanism.toml].
    #[arg(long, value_name = "PATH")]
    pub file: Option<PathBuf>,
    /// Also compile each mechanism with the JIT and print how long it took.
    #[arg(short, long)]
    pub verbose: bool,
}

/// A finite number.
fn finite(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err("needs a finite number".into()),
    }
}

/// `NAME=VALUE` with a finite VALUE.
fn assignment(s: &str) -> Result<(String, f64), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| "needs NAME=VALUE".to_string())?;
    let name = name.trim();
    if name.is_empty() {
        return Err("needs NAME=VALUE".into());
    }
    Ok((name.to_string(), finite(value)?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn loads() {
        assert_eq!(load("E=1,-2.5").unwrap(), ("E".into(), [1.0, -2.5]));
        assert!(load("E=1").is_err());
        assert!(load("=1,2").is_err());
        assert!(load("E=1,nan").is_err());
        assert_eq!(
            ranged_load("E=-7000,0@120:300").unwrap(),
            ("E".into(), [-7000.0, 0.0], Some((120.0, 300.0)))
        );
        assert_eq!(
            ranged_load("E=1,2").unwrap(),
            ("E".into(), [1.0, 2.0], None)
        );
        assert!(ranged_load("E=1,2@120").is_err());
        assert!(ranged_load("E=1,2@a:3").is_err());
    }

    #[test]
    fn assignments() {
        assert_eq!(assignment("q4=-30").unwrap(), ("q4".into(), -30.0));
        assert!(assignment("q4").is_err());
        assert!(assignment("=1").is_err());
        assert!(assignment("q4=inf").is_err());
    }
}
