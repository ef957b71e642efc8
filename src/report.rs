//! Sweep output: the seed-style text table (angles in degrees, significant digits, units in the
//! header) and the CSV of the interface spec (radians, full round-trip precision, no NaN or inf in
//! any cell, kebab-case status on failed rows). Sits on [`crate::sweep`]; the CLI prints these.

use std::fmt::Write as _;

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
    let mut out = csv_header_line(info, index);
    for r in rows {
        csv_row(&mut out, info, &r.view());
    }
    out
}

/// The CSV's header line (with its newline).
pub fn csv_header_line(info: &MechanismInfo, index: usize) -> String {
    let mut out = csv_header(info, index).join(",");
    out.push('\n');
    out
}

/// Whether every number of a solved row is finite (a row with one that is not is written as
/// failed, status `non-finite`: no cell is ever NaN or inf).
pub fn all_finite(s: &SolvedRef<'_>) -> bool {
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    finite(s.q)
        && finite(s.qd)
        && finite(s.qdd)
        && s.points
            .iter()
            .all(|p| finite(&p.position) && finite(&p.velocity) && finite(&p.acceleration))
}

/// A row's CSV status: `ok`, `non-finite` for a solved row with a non-finite number, or the
/// failed row's status.
pub fn status(r: &RowRef<'_>) -> &'static str {
    match &r.result {
        Ok(s) if !all_finite(s) => "non-finite",
        _ => r.status(),
    }
}

/// `v` in shortest round-trip form (`ryu`), appended to `out`.
pub fn push_float(out: &mut String, v: f64) {
    let mut b = ryu::Buffer::new();
    out.push_str(b.format(v));
}

/// Every status a sweep row can have, in a fixed order (what [`status_code`] numbers): `ok`,
/// the solver errors' statuses, the continuation's, `non-finite`.
pub const STATUSES: &[&str] = &[
    "ok",
    "unassemblable",
    "singular",
    "no-convergence",
    "non-finite-input",
    "bad-length",
    "overflow",
    "not-started",
    "substep-limit",
    "unusable-start",
    "non-finite",
];

/// `status`'s index in [`STATUSES`] (`STATUSES.len()` for a status it does not list).
pub fn status_code(status: &str) -> u8 {
    let i = STATUSES.iter().position(|s| *s == status);
    i.unwrap_or(STATUSES.len()) as u8
}

/// A row's numbers after the input, in the order of [`csv_header`] up to `cond`, each handed to
/// `put`: the CSV's cells, NaN where the CSV leaves a cell empty (a failed row's, a non-finite
/// condition estimate's). Returns the row's status. What the CSV writer and the Python package's
/// columns both read a row through.
pub fn row_numbers(r: &RowRef<'_>, info: &MechanismInfo, mut put: impl FnMut(f64)) -> &'static str {
    match &r.result {
        Ok(s) if all_finite(s) => {
            s.q.iter().chain(s.qd).chain(s.qdd).for_each(|&v| put(v));
            for p in s.points {
                p.position
                    .iter()
                    .chain(&p.velocity)
                    .chain(&p.acceleration)
                    .for_each(|&v| put(v));
            }
            put(if s.condition.is_finite() {
                s.condition
            } else {
                f64::NAN
            });
            "ok"
        }
        _ => {
            let cells = 3 * info.unknowns.len() + 6 * info.points.len() + 1;
            (0..cells).for_each(|_| put(f64::NAN));
            status(r)
        }
    }
}

/// One row of the CSV (with its newline), appended to `out`: the cells of [`row_numbers`] in
/// shortest round-trip form (empty where NaN), then the status. Allocates nothing but `out`'s
/// growth.
pub fn csv_row(out: &mut String, info: &MechanismInfo, r: &RowRef<'_>) {
    push_float(out, r.input);
    let status = row_numbers(r, info, |v| {
        out.push(',');
        if !v.is_nan() {
            push_float(out, v);
        }
    });
    out.push(',');
    out.push_str(status);
    out.push('\n');
}

/// Significant digits of the table's numbers.
pub const DIGITS: usize = 7;

/// `v` with [`DIGITS`] significant digits: fixed notation from 1e-4 to 1e7, else scientific
/// (`1.234568e303`); zeros as `0`. Never NaN or inf text for finite `v`.
pub fn significant(v: f64) -> String {
    let mut out = String::new();
    push_significant(&mut out, v, 0);
    out
}

/// [`significant`] appended to `out`, right-aligned in `width` characters: formatted once (the
/// digits and exponent of `{:.6e}`, which fixed notation then places), nothing allocated.
pub fn push_significant(out: &mut String, v: f64, width: usize) {
    let mut text = Stack::default();
    if v == 0.0 {
        text.push(b"0");
    } else if !v.is_finite() {
        text.push(b"-");
    } else {
        let mut sci = Stack::default();
        let _ = write!(sci, "{v:.*e}", DIGITS - 1);
        let s = sci.bytes();
        let e_at = s.iter().position(|&b| b == b'e').unwrap_or(s.len());
        let exp: i32 = std::str::from_utf8(&s[(e_at + 1).min(s.len())..])
            .ok()
            .and_then(|e| e.parse().ok())
            .unwrap_or(0);
        if (-4..7).contains(&exp) {
            // The mantissa's digits, the point placed by the exponent.
            let negative = s[0] == b'-';
            let digits: Stack = s[..e_at]
                .iter()
                .filter(|b| b.is_ascii_digit())
                .copied()
                .collect();
            let d = digits.bytes();
            if negative {
                text.push(b"-");
            }
            if exp >= 0 {
                let whole = exp as usize + 1;
                text.push(&d[..whole]);
                if whole < d.len() {
                    text.push(b".");
                    text.push(&d[whole..]);
                }
            } else {
                text.push(b"0.");
                for _ in 0..(-exp - 1) {
                    text.push(b"0");
                }
                text.push(d);
            }
        } else {
            text.push(s);
        }
    }
    let t = text.bytes();
    out.extend(std::iter::repeat_n(' ', width.saturating_sub(t.len())));
    out.push_str(std::str::from_utf8(t).unwrap_or("-"));
}

/// A short text on the stack (a formatted number).
struct Stack {
    buf: [u8; 64],
    len: usize,
}

impl Default for Stack {
    fn default() -> Self {
        Stack {
            buf: [0; 64],
            len: 0,
        }
    }
}

impl Stack {
    fn push(&mut self, b: &[u8]) {
        let n = b.len().min(self.buf.len() - self.len);
        self.buf[self.len..self.len + n].copy_from_slice(&b[..n]);
        self.len += n;
    }

    fn bytes(&self) -> &[u8] {
        &self.buf[..self.len]
    }
}

impl FromIterator<u8> for Stack {
    fn from_iter<I: IntoIterator<Item = u8>>(iter: I) -> Self {
        let mut s = Stack::default();
        for b in iter {
            s.push(&[b]);
        }
        s
    }
}

impl std::fmt::Write for Stack {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.push(s.as_bytes());
        Ok(())
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
        table_row(&mut out, info, index, width, &r.view());
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

/// One line of the table (with its newline), for columns of `width`, appended to `out`.
pub fn table_row(
    out: &mut String,
    info: &MechanismInfo,
    index: usize,
    width: usize,
    r: &RowRef<'_>,
) {
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
