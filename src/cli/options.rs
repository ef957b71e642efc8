//! CLI, argument handling: `--name value` options and the sweep's input values.

use crate::USAGE;

/// `--name value` options and positional arguments.
pub struct Options {
    pairs: Vec<(String, String)>,
    pub positional: Vec<String>,
}

impl Options {
    /// No options at all.
    pub fn none() -> Options {
        Options {
            pairs: Vec::new(),
            positional: Vec::new(),
        }
    }

    /// Parses `args`; an option not in `known` or without a value is an error.
    pub fn parse(args: &[String], known: &[&str]) -> Result<Options, String> {
        let (mut pairs, mut positional) = (Vec::new(), Vec::new());
        let mut it = args.iter();
        while let Some(a) = it.next() {
            if let Some(name) = a.strip_prefix("--") {
                if !known.contains(&name) {
                    return Err(format!("unknown option `{a}`\n{USAGE}"));
                }
                let v = it
                    .next()
                    .ok_or_else(|| format!("option `{a}` needs a value"))?;
                pairs.push((name.to_string(), v.clone()));
            } else {
                positional.push(a.clone());
            }
        }
        Ok(Options { pairs, positional })
    }

    /// The last value given for `--name`.
    pub fn get(&self, name: &str) -> Option<&str> {
        self.pairs
            .iter()
            .rev()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    /// A finite number, if given.
    pub fn number(&self, name: &str) -> Result<Option<f64>, String> {
        match self.get(name) {
            None => Ok(None),
            Some(v) => match v.trim().parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(Some(x)),
                _ => Err(format!("--{name} needs a finite number, got `{v}`")),
            },
        }
    }
}

/// The input values of a sweep, both ends included, in sweep units. The step's sign is ignored:
/// the values always go from `from` towards `to`.
pub fn sweep_values(from: f64, to: f64, step: f64) -> Result<Vec<f64>, String> {
    if step == 0.0 {
        return Err("--step must not be zero".into());
    }
    let n = ((to - from) / step).abs();
    if n > 10_000_000.0 {
        return Err("too many sweep rows (more than 10 000 000)".into());
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
