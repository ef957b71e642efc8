//! What a sweep's options mean for one mechanism (the CLI's `--input`, `--set`, `--from`, `--to`,
//! `--step`, and the same for the Python package): which input, its values (both ends included,
//! the last row exactly `--to`), the held inputs' values, in sweep units (radians or file units).

use mechgen_runtime::{CoordDesc, Kind, MechanismInfo};

/// A sweep resolved against a mechanism.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// The swept input.
    pub index: usize,
    /// Its values: radians for an angle, file units for a length.
    pub values: Vec<f64>,
    /// Held inputs given by `--set`, (index, radians or file units).
    pub held: Vec<(usize, f64)>,
    /// The range's span in sweep units (for the continuation's substeps).
    pub span: f64,
    /// Said when `--step` does not divide the range: what the last row is.
    pub note: Option<String>,
}

/// The range options: `--from`, `--to`, `--step` as given (degrees or file units).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Range {
    pub from: Option<f64>,
    pub to: Option<f64>,
    pub step: Option<f64>,
}

/// The index of `info`'s input `name` (`--input`, `--set`), or [`no_input`]'s message.
pub fn input_index(info: &MechanismInfo, name: &str) -> Result<usize, String> {
    let names = |coords: &[CoordDesc]| coords.iter().map(|c| c.name.clone()).collect::<Vec<_>>();
    let params: Vec<String> = info.params.iter().map(|p| p.name.clone()).collect();
    let inputs = names(&info.inputs);
    info.inputs
        .iter()
        .position(|i| i.name == name)
        .ok_or_else(|| no_input(&info.name, name, [&inputs, &names(&info.unknowns), &params]))
}

/// Where a param given as an input changes on the command line (the Python package says its own).
pub const PARAM_HINT: &str = "change its value in the file, or sweep several with `batch --params`";

/// What a command says when mechanism `mechanism` has no input `name`: its inputs, and what
/// `name` is where it names one of its unknowns or params (`[inputs, unknowns, params]`).
pub fn no_input(mechanism: &str, name: &str, [inputs, unknowns, params]: [&[String]; 3]) -> String {
    let has = |names: &[String]| names.iter().any(|n| n == name);
    let what = if has(params) {
        format!("; `{name}` is a param: {PARAM_HINT}")
    } else if has(unknowns) {
        format!("; `{name}` is an unknown, solved for at every row")
    } else {
        String::new()
    };
    match inputs {
        [] => format!("`{mechanism}` has no input"),
        _ => format!(
            "`{mechanism}` has no input `{name}` (its inputs: {}{what})",
            inputs.join(", ")
        ),
    }
}

/// Resolves `--input`, `--set` and the range (defaults per interfaces.md).
pub fn plan(
    info: &MechanismInfo,
    input: Option<&str>,
    set: &[(String, f64)],
    range: Range,
) -> Result<Plan, String> {
    let find = |name: &str| input_index(info, name);
    if info.inputs.is_empty() {
        return Err(format!("`{}` has no input", info.name));
    }
    let index = input.map_or(Ok(0), find)?;
    let mut held = Vec::new();
    for (name, value) in set {
        let i = find(name)?;
        if i == index {
            return Err(format!(
                "--set {name}=…: `{name}` is the swept input (use --from/--to, or --input to sweep another)"
            ));
        }
        let value = if info.inputs[i].kind == Kind::Angle {
            value.to_radians()
        } else {
            *value
        };
        held.retain(|h: &(usize, f64)| h.0 != i);
        held.push((i, value));
    }
    let CoordDesc { name, kind, .. } = &info.inputs[index];
    let (from, to, step) = match kind {
        Kind::Angle => (
            range.from.unwrap_or(0.0),
            range.to.unwrap_or(360.0),
            range.step.unwrap_or(10.0),
        ),
        _ => match (range.from, range.to) {
            (Some(f), Some(t)) => (f, t, range.step.unwrap_or((t - f) / 36.0)),
            _ => {
                return Err(format!(
                    "--from and --to are required for the length input `{name}`"
                ));
            }
        },
    };
    let step = if step == 0.0 && from == to { 1.0 } else { step };
    // The range a sweep can resolve: a thousand turns of an angle (in degrees here), a million
    // times the largest length param of a length, as for the start values (`check_start`).
    let limit = match kind {
        Kind::Angle => super::MAX_START_ANGLE.to_degrees(),
        _ => super::MAX_START_LENGTH * super::length_scale(info),
    };
    for (option, v) in [("--from", from), ("--to", to)] {
        if v.is_nan() || v.abs() > limit {
            let unit = if *kind == Kind::Angle { " deg" } else { "" };
            return Err(format!(
                "{option} {v:e}{unit} is beyond what a sweep of input `{name}` resolves: at most {limit:e}{unit} in magnitude (a thousand turns for an angle input, a million times the largest length param for a length input)"
            ));
        }
    }
    let mut values = sweep_values(from, to, step)?;
    let note = match values.as_slice() {
        [.., before, last] if (last - before).abs() < step.abs() * (1.0 - 1e-9) => Some(format!(
            "--step {step} does not divide the range: the last row is --to = {to}, {} after the row before",
            (last - before).abs()
        )),
        _ => None,
    };
    let span = if *kind == Kind::Angle {
        values.iter_mut().for_each(|v| *v = v.to_radians());
        (to - from).to_radians()
    } else {
        to - from
    };
    Ok(Plan {
        index,
        values,
        held,
        span,
        note,
    })
}

/// The input values of a sweep, both ends included, in sweep units. The step's sign is ignored:
/// the values always go from `from` towards `to`.
pub fn sweep_values(from: f64, to: f64, step: f64) -> Result<Vec<f64>, String> {
    if step == 0.0 {
        return Err("--step must not be zero".into());
    }
    let n = ((to - from) / step).abs();
    if n > 10_000_000.0 {
        return Err(format!(
            "--step {step} from {from} to {to} makes {:.3e} rows; a sweep has at most 10 000 000 (a larger --step, or a shorter range)",
            n + 1.0
        ));
    }
    let count = (n + 1e-9).floor() as usize;
    let dir = if to >= from { 1.0 } else { -1.0 };
    let mut v: Vec<f64> = (0..=count)
        .map(|i| from + dir * step.abs() * i as f64)
        .collect();
    match v.last_mut() {
        Some(last) if (to - *last).abs() <= 1e-9 * step.abs() => *last = to,
        _ => v.push(to),
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_ends_included() {
        assert_eq!(
            sweep_values(0.0, 30.0, 10.0).unwrap(),
            [0.0, 10.0, 20.0, 30.0]
        );
        assert_eq!(
            sweep_values(0.0, 25.0, 10.0).unwrap(),
            [0.0, 10.0, 20.0, 25.0]
        );
        assert_eq!(
            sweep_values(30.0, 0.0, -10.0).unwrap(),
            [30.0, 20.0, 10.0, 0.0]
        );
        assert_eq!(sweep_values(5.0, 5.0, 1.0).unwrap(), [5.0]);
        assert!(sweep_values(0.0, 30.0, 0.0).is_err());
        assert_eq!(sweep_values(0.0, 20.0, -10.0).unwrap(), [0.0, 10.0, 20.0]);
        assert!(sweep_values(0.0, 1e9, 1e-3).is_err());
    }
}
