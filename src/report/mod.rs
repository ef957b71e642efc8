//! Sweep output: the seed-style text table (angles in degrees, significant digits, units in the
//! header) and the CSV of the interface spec (radians, full round-trip precision, no NaN or inf in
//! any cell, kebab-case status on failed rows). Sits on [`crate::sweep`]; the CLI prints these.

use std::fmt::Write as _;

mod number;

pub use number::{DIGITS, push_float, push_significant, significant};

use crate::sweep::{Row, RowRef, SolvedRef, StopReason};
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

/// The sweep as CSV text.
pub fn csv(info: &MechanismInfo, index: usize, rows: &[Row]) -> String {
    let mut out = csv_header_line(info, index).into_bytes();
    for r in rows {
        csv_row(&mut out, info, &r.view());
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// The CSV's header line (with its newline).
pub fn csv_header_line(info: &MechanismInfo, index: usize) -> String {
    let mut out = csv_header(info, index).join(",");
    out.push('\n');
    out
}

/// The inputs a sweep of input `index` holds (every other input) with their values: the `--set`
/// value where one was given, else the start value; what [`csv_header_line_held`] and
/// [`csv_row_held`] record.
pub fn held_inputs(info: &MechanismInfo, index: usize, held: &[(usize, f64)]) -> Vec<(usize, f64)> {
    (0..info.inputs.len())
        .filter(|&i| i != index)
        .map(|i| {
            let v = held
                .iter()
                .rev()
                .find(|h| h.0 == i)
                .map_or(info.inputs[i].start, |h| h.1);
            (i, v)
        })
        .collect()
}

/// [`csv_header_line`] with a column for each held input (its name) after the swept input's.
pub fn csv_header_line_held(info: &MechanismInfo, index: usize, held: &[(usize, f64)]) -> String {
    let mut h = csv_header(info, index);
    for (k, &(i, _)) in held.iter().enumerate() {
        h.insert(1 + k, info.inputs[i].name.clone());
    }
    let mut out = h.join(",");
    out.push('\n');
    out
}

/// [`csv_row`] with the held inputs' values (radians or file units) after the swept input's.
pub fn csv_row_held(
    out: &mut Vec<u8>,
    info: &MechanismInfo,
    r: &RowRef<'_>,
    held: &[(usize, f64)],
) {
    let start = out.len();
    csv_row(out, info, r);
    if held.is_empty() {
        return;
    }
    // After the first cell (the swept input).
    let at = out[start..]
        .iter()
        .position(|&b| b == b',')
        .map_or(out.len(), |p| start + p);
    let mut cells = Vec::new();
    for &(_, v) in held {
        cells.push(b',');
        push_float(&mut cells, v);
    }
    out.splice(at..at, cells);
}

/// Whether every number of a solved row is finite (a row with one that is not is written as
/// failed, status `non-finite`: no cell is ever NaN or inf).
pub fn all_finite(s: &SolvedRef<'_>) -> bool {
    // x · 0 is ±0 for a finite x and NaN (every exponent bit set) for an infinite or NaN one.
    // The products' bits OR-ed together have an exponent bit set exactly when one was not
    // finite: no branch and no float compare per number, and integer ORs may be regrouped, so
    // the compiler runs them in vector lanes (a row almost never has a number that is not
    // finite, and every row is asked).
    let bits = |x: f64| (x * 0.0).to_bits();
    let run = |v: &[f64]| v.iter().fold(0, |acc, &x| acc | bits(x));
    let points = s.points.iter().fold(0, |acc, p| {
        let ([a, b], [c, d], [e, f]) = (p.position, p.velocity, p.acceleration);
        acc | bits(a) | bits(b) | bits(c) | bits(d) | bits(e) | bits(f)
    });
    let all = run(s.q) | run(s.qd) | run(s.qdd) | points;
    all & 0x7ff0_0000_0000_0000 == 0
}

/// A row's CSV status: `ok`, `non-finite` for a solved row with a non-finite number, or the
/// failed row's status.
pub fn status(r: &RowRef<'_>) -> &'static str {
    match &r.result {
        Ok(s) if !all_finite(s) => "non-finite",
        _ => r.status(),
    }
}

/// Every status a sweep row can have, in a fixed order (what [`status_code`] numbers): `ok`,
/// the solver errors' statuses, the continuation's, `non-finite`.
pub const STATUSES: &[&str] = &[
    "ok",
    "unassemblable",
    "other-branch",
    "singular",
    "no-convergence",
    "non-finite-input",
    "bad-length",
    "overflow",
    "not-started",
    "substep-limit",
    "unusable-start",
    "non-finite",
    "out-of-range",
    "bad-mass",
    "step-too-small",
    "step-limit",
    "at-load-edge",
];

/// `status`'s index in [`STATUSES`] (`STATUSES.len()` for a status it does not list).
pub fn status_code(status: &str) -> u8 {
    let i = STATUSES.iter().position(|s| *s == status);
    i.unwrap_or(STATUSES.len()) as u8
}

/// A row's numbers after the input, in the order of [`csv_header`] up to `cond`, handed to `put`
/// a run at a time (the unknowns, their rates, their accelerations, each point's six numbers, the
/// condition estimate): the CSV's cells, NaN where the CSV leaves a cell empty (a failed row's, a
/// non-finite condition estimate's). Returns the row's status. What the CSV writer and the Python
/// package's columns both read a row through.
pub fn row_numbers(
    r: &RowRef<'_>,
    info: &MechanismInfo,
    mut put: impl FnMut(&[f64]),
) -> &'static str {
    match &r.result {
        Ok(s) if all_finite(s) => {
            put(s.q);
            put(s.qd);
            put(s.qdd);
            for p in s.points {
                let [x, y] = p.position;
                let [vx, vy] = p.velocity;
                let [ax, ay] = p.acceleration;
                put(&[x, y, vx, vy, ax, ay]);
            }
            put(&[if s.condition.is_finite() {
                s.condition
            } else {
                f64::NAN
            }]);
            "ok"
        }
        _ => {
            let cells = 3 * info.unknowns.len() + 6 * info.points.len() + 1;
            (0..cells).for_each(|_| put(&[f64::NAN]));
            status(r)
        }
    }
}

/// One row of the CSV (with its newline), appended to `out`: the cells of [`row_numbers`] in
/// shortest round-trip form (empty where NaN), then the status. Allocates nothing but `out`'s
/// growth.
pub fn csv_row(out: &mut Vec<u8>, info: &MechanismInfo, r: &RowRef<'_>) {
    push_float(out, r.input);
    let status = row_numbers(r, info, |run| {
        for &v in run {
            out.push(b',');
            if !v.is_nan() {
                push_float(out, v);
            }
        }
    });
    out.push(b',');
    out.extend_from_slice(status.as_bytes());
    out.push(b'\n');
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
    let (head, width) = table_header(info, index);
    let mut out = head.into_bytes();
    for r in rows {
        table_row(&mut out, info, index, width, &r.view());
    }
    String::from_utf8_lossy(&out).into_owned()
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

/// One line of the table (with its newline), for columns of `width`, appended to `out`.
pub fn table_row(
    out: &mut Vec<u8>,
    info: &MechanismInfo,
    index: usize,
    width: usize,
    r: &RowRef<'_>,
) {
    use std::io::Write as _;
    let input_kind = info.inputs[index].kind;
    push_significant(out, r.input * deg(input_kind), width);
    match &r.result {
        Ok(s) => {
            for rates in [s.q, s.qd, s.qdd] {
                for (v, u) in rates.iter().zip(&info.unknowns) {
                    push_significant(out, v * deg(u.kind), width);
                }
            }
            for p in s.points {
                for v in p.position.iter().chain(&p.velocity).chain(&p.acceleration) {
                    push_significant(out, *v, width);
                }
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
                Some(s) if r.dead_point().is_some() && s.assembles == Some(true) => write!(
                    out,
                    "  {status}: the linkage assembles here, on another branch; the branch followed ends at the dead point near {} (cond {:.1e})",
                    at(s.input),
                    s.condition
                ),
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
    out.push(b'\n');
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
