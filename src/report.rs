//! Sweep output: the seed-style text table (angles in degrees, significant digits, units in the
//! header) and the CSV of the interface spec (radians, full round-trip precision, no NaN or inf in
//! any cell, kebab-case status on failed rows). Sits on [`crate::sweep`]; the CLI prints these.

use std::fmt::Write as _;

use crate::sweep::{Row, Solved, StopReason};
use mechgen_runtime::{CoordDesc, Kind, MechanismInfo};

/// Column headers of the CSV, in order.
pub fn csv_header(info: &MechanismInfo, index: usize) -> Vec<String> {
    let mut h = vec![info.inputs[index].name.clone()];
    h.extend(info.unknowns.iter().map(|u| u.name.clone()));
    h.extend(info.unknowns.iter().map(|u| format!("{}_vel", u.name)));
    h.extend(info.unknowns.iter().map(|u| format!("{}_acc", u.name)));
    for p in &info.points {
        h.extend(
            ["x", "y", "vx", "vy", "ax", "ay"]
                .iter()
                .map(|s| format!("{p}_{s}")),
        );
    }
    h.push("cond".into());
    h.push("status".into());
    h
}

fn numbers(s: &Solved) -> Vec<f64> {
    let mut v: Vec<f64> = s.q.iter().chain(&s.qd).chain(&s.qdd).copied().collect();
    for p in &s.points {
        v.extend(p.position.iter().chain(&p.velocity).chain(&p.acceleration));
    }
    v
}

/// The sweep as CSV text.
pub fn csv(info: &MechanismInfo, index: usize, rows: &[Row]) -> String {
    let mut out = csv_header_line(info, index);
    for r in rows {
        csv_row(&mut out, info, r);
    }
    out
}

/// The CSV's header line (with its newline).
pub fn csv_header_line(info: &MechanismInfo, index: usize) -> String {
    let mut out = csv_header(info, index).join(",");
    out.push('\n');
    out
}

/// One row's cells after the input, as the CSV writes them (the Python package reads them too):
/// for an `ok` row the numbers of [`csv_header`] up to `cond` (`cond` `None` where it is not
/// finite, as at a dead point), then the status; a failed row (or one with a non-finite number,
/// status `non-finite`) has no numbers.
pub fn row_cells(r: &Row) -> (Option<Vec<Option<f64>>>, &'static str) {
    match &r.result {
        Ok(s) => {
            let nums = numbers(s);
            if nums.iter().all(|v| v.is_finite()) {
                let mut cells: Vec<Option<f64>> = nums.into_iter().map(Some).collect();
                cells.push(s.condition.is_finite().then_some(s.condition));
                (Some(cells), "ok")
            } else {
                (None, "non-finite")
            }
        }
        Err(_) => (None, r.status()),
    }
}

/// One row of the CSV (with its newline), appended to `out`.
pub fn csv_row(out: &mut String, info: &MechanismInfo, r: &Row) {
    let blanks = 3 * info.unknowns.len() + 6 * info.points.len() + 1;
    let _ = write!(out, "{:?}", r.input);
    match row_cells(r) {
        (Some(cells), status) => {
            for c in cells {
                match c {
                    Some(v) => {
                        let _ = write!(out, ",{v:?}");
                    }
                    None => out.push(','),
                }
            }
            let _ = writeln!(out, ",{status}");
        }
        (None, status) => {
            out.push_str(&",".repeat(blanks));
            let _ = writeln!(out, ",{status}");
        }
    }
}

/// Significant digits of the table's numbers.
pub const DIGITS: usize = 7;

/// `v` with [`DIGITS`] significant digits: fixed notation from 1e-4 to 1e7, else scientific
/// (`1.234568e303`); zeros as `0`. Never NaN or inf text for finite `v`.
pub fn significant(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return "-".into();
    }
    // The exponent after rounding to DIGITS digits (9.9999999 rounds up to 10.00000).
    let rounded: f64 = format!("{v:.*e}", DIGITS - 1).parse().unwrap_or(v);
    let exp = rounded.abs().log10().floor() as i32;
    if (-4..7).contains(&exp) {
        let decimals = (DIGITS as i32 - 1 - exp).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.*e}", DIGITS - 1)
    }
}

/// The lines above a table: units (angles in degrees, the rate's units) and the values of the
/// inputs that were held (`x` holds every input's value, radians or file units).
pub fn preamble(info: &MechanismInfo, index: usize, rate: f64, x: &[f64]) -> String {
    let mut out = String::from(
        "units: angles [deg], angular rates [deg/s] and [deg/s2]; lengths in the file's unit [u], [u/s], [u/s2]\n",
    );
    let CoordDesc { name, kind, .. } = &info.inputs[index];
    let _ = match kind {
        Kind::Angle => writeln!(
            out,
            "input {name} swept at --rate {} rad/s = {} deg/s, zero input acceleration",
            significant(rate),
            significant(rate.to_degrees())
        ),
        _ => writeln!(
            out,
            "input {name} swept at --rate {} u/s, zero input acceleration",
            significant(rate)
        ),
    };
    let held: Vec<String> = info
        .inputs
        .iter()
        .zip(x)
        .enumerate()
        .filter(|(i, _)| *i != index)
        .map(
            |(
                _,
                (
                    CoordDesc {
                        name: n, kind: k, ..
                    },
                    v,
                ),
            )| match k {
                Kind::Angle => format!("{n} = {} deg", significant(v.to_degrees())),
                _ => format!("{n} = {} u", significant(*v)),
            },
        )
        .collect();
    if !held.is_empty() {
        let _ = writeln!(out, "held: {}", held.join(", "));
    }
    out
}

/// The seed-style table: angles in degrees (and degrees per second, per second squared), lengths
/// in file units `[u]`, numbers to [`DIGITS`] significant digits.
pub fn table(info: &MechanismInfo, index: usize, rows: &[Row]) -> String {
    let (mut out, width) = table_header(info, index);
    for r in rows {
        out.push_str(&table_row(info, index, width, r));
    }
    out
}

/// The table's header line (with its newline) and its column width.
pub fn table_header(info: &MechanismInfo, index: usize) -> (String, usize) {
    let input_kind = info.inputs[index].kind;
    let mut head = vec![format!(
        "{}{}",
        info.inputs[index].name,
        unit(input_kind, "")
    )];
    for (suffix, per) in [("", ""), ("_vel", "/s"), ("_acc", "/s2")] {
        head.extend(
            info.unknowns
                .iter()
                .map(|u| format!("{}{suffix}{}", u.name, unit(u.kind, per))),
        );
    }
    for p in &info.points {
        for (c, per) in [
            ("x", ""),
            ("y", ""),
            ("vx", "/s"),
            ("vy", "/s"),
            ("ax", "/s2"),
            ("ay", "/s2"),
        ] {
            head.push(format!("{p}_{c}{}", unit(Kind::Length, per)));
        }
    }
    let width = head.iter().map(String::len).max().unwrap_or(0).max(13) + 1;
    let mut out = String::new();
    for h in &head {
        let _ = write!(out, "{h:>width$}");
    }
    out.push('\n');
    (out, width)
}

/// One line of the table (with its newline), for columns of `width`.
pub fn table_row(info: &MechanismInfo, index: usize, width: usize, r: &Row) -> String {
    let input_kind = info.inputs[index].kind;
    let mut out = String::new();
    let _ = write!(out, "{:>width$}", significant(r.input * deg(input_kind)));
    match &r.result {
        Ok(s) => {
            for v in scaled(info, s) {
                let _ = write!(out, "{:>width$}", significant(v));
            }
        }
        Err(e) => {
            let name = &info.inputs[index].name;
            let at = |input: f64| {
                format!(
                    "{name} = {}{}",
                    significant(input * deg(input_kind)),
                    unit_word(input_kind)
                )
            };
            let status = r.status();
            let _ = match r.stopped {
                Some(s) if r.dead_point().is_some() => write!(
                    out,
                    "  {status}: dead point near {} (cond {:.1e}), the branch cannot be continued past it",
                    at(s.input),
                    s.condition
                ),
                Some(s) => match s.reason {
                    StopReason::SubstepLimit => write!(
                        out,
                        "  {status}: the continuation used up its substeps; branch stopped at {} (cond {:.1e})",
                        at(s.input),
                        s.condition
                    ),
                    StopReason::UnusableStart => {
                        write!(out, "  {status}: the start configuration is not usable")
                    }
                    StopReason::HeldInput => write!(
                        out,
                        "  {status}: a held input could not be moved to its value: {e}"
                    ),
                    StopReason::Refused => write!(
                        out,
                        "  {status}: the branch could not be followed past {} (cond {:.1e})",
                        at(s.input),
                        s.condition
                    ),
                    StopReason::Solver => write!(
                        out,
                        "  {status}: {e}; branch stopped at {} (cond {:.1e})",
                        at(s.input),
                        s.condition
                    ),
                },
                None => write!(out, "  {status}: {e}"),
            };
        }
    }
    out.push('\n');
    out
}

/// A solved row's numbers in table units: angles in degrees (the same continuous angle as the
/// CSV, not folded into a turn), angular rates in degrees.
fn scaled(info: &MechanismInfo, s: &Solved) -> Vec<f64> {
    let kinds = info.unknowns.iter().map(|u| u.kind);
    let mut v: Vec<f64> =
        s.q.iter()
            .zip(kinds.clone())
            .map(|(v, k)| v * deg(k))
            .chain(s.qd.iter().zip(kinds.clone()).map(|(v, k)| v * deg(k)))
            .chain(s.qdd.iter().zip(kinds).map(|(v, k)| v * deg(k)))
            .collect();
    for p in &s.points {
        v.extend(p.position.iter().chain(&p.velocity).chain(&p.acceleration));
    }
    v
}

fn deg(k: Kind) -> f64 {
    if k == Kind::Angle {
        180.0 / std::f64::consts::PI
    } else {
        1.0
    }
}

fn unit_word(k: Kind) -> &'static str {
    if k == Kind::Angle { " deg" } else { " u" }
}

/// A column's unit tag: `[deg]`, `[deg/s]`, `[u/s2]`, …
fn unit(k: Kind, per: &str) -> String {
    match k {
        Kind::Angle => format!("[deg{per}]"),
        _ => format!("[u{per}]"),
    }
}

#[cfg(test)]
mod tests {
    use super::significant;

    #[test]
    fn significant_digits() {
        assert_eq!(significant(0.0), "0");
        assert_eq!(significant(1.0), "1.000000");
        assert_eq!(significant(123.456789), "123.4568");
        assert_eq!(significant(-0.000001234567), "-1.234567e-6");
        assert_eq!(significant(0.0001234567), "0.0001234567");
        assert_eq!(significant(1e303), "1.000000e303");
        assert_eq!(significant(9.99999999), "10.00000");
        assert_eq!(significant(12345678.0), "1.234568e7");
        assert_eq!(significant(f64::NAN), "-");
    }
}
