//! The `mechgen` command: `sweep`, `check`, and with no command the main job (every mechanism of
//! the compiled-in file, or of `--file`, swept over a full turn; tables printed, CSVs and plots
//! written to `mechgen-out/`). Parsing is clap's ([`cli::args`]); the work is in [`cli::run`].

#[macro_use]
mod cli;

use std::process::ExitCode;

use clap::Parser as _;
use clap::error::ErrorKind;

use cli::args::{Cli, Command};

fn main() -> ExitCode {
    let parsed = match Cli::try_parse() {
        Ok(parsed) => parsed,
        Err(e) => return clap_exit(&e),
    };
    let result = match parsed.command {
        None => cli::run::main_job(&parsed.main),
        Some(Command::Sweep(args)) => cli::run::sweep(&args),
        Some(Command::Check(args)) => cli::check::run(args.file.as_deref(), args.verbose),
        Some(Command::Branches(args)) => cli::branches::run(&args),
        Some(Command::Metrics(args)) => cli::metrics::run(&args),
        Some(Command::Batch(args)) => cli::batch::run(&args),
        Some(Command::Sensitivity(args)) => cli::design::sensitivity(&args),
        Some(Command::Dynamics(args)) => cli::dynamics::dynamics_command(&args),
        Some(Command::Simulate(args)) => cli::simulate::run(&args),
        Some(Command::Tolerance(args)) => cli::design::tolerance(&args),
    };
    report_peak_memory();
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            tell!("mechgen: {msg}");
            ExitCode::FAILURE
        }
    }
}

/// With `MECHGEN_PEAK_MEMORY` set, prints the process's peak resident memory as the kernel counts
/// it (`VmHWM` of `/proc/self/status`, Linux) on stderr: how the tests hold a long sweep's memory
/// flat. Prints nothing where the file does not exist.
fn report_peak_memory() {
    if std::env::var_os("MECHGEN_PEAK_MEMORY").is_none() {
        return;
    }
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    if let Some(line) = status.lines().find(|l| l.starts_with("VmHWM:")) {
        tell!("mechgen: peak memory {}", line["VmHWM:".len()..].trim());
    }
}

/// `--help` and `--version` go to stdout with status 0; usage errors to stderr as
/// `mechgen: …` (with clap's suggestion and usage lines) and status 2.
fn clap_exit(e: &clap::Error) -> ExitCode {
    let text = e.render().to_string();
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            say_raw!("{text}");
            ExitCode::SUCCESS
        }
        _ => {
            let text = text.strip_prefix("error: ").unwrap_or(&text);
            tell_raw!("mechgen: {text}");
            ExitCode::from(2)
        }
    }
}
