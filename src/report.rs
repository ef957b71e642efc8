//! Sweep output: the seed-style text table (angles in degrees) and the CSV of the interface spec
//! (radians, no NaN or inf in any cell, kebab-case status on failed rows).

use std::fmt::Write as _;

use crate::sweep::{Row, Solved};
use mechgen_runtime::mechanism::{Kind, MechanismInfo};

/// Column headers of the CSV, in order.
pub fn csv_header(info: &MechanismInfo, index: usize) -> Vec<String> {
    let mut h = vec![info.inputs[index].0.clone()];
    h.extend(info.unknowns.iter().map(|u| u.0.clone()));
    h.extend(info.unknowns.iter().map(|u| format!("{}_vel", u.0)));
    h.extend(info.unknowns.iter().map(|u| format!("{}_acc", u.0)));
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
    let header = csv_header(info, index);
    let mut out = header.join(",");
    out.push('\n');
    let blanks = header.len() - 2;
    for r in rows {
        let _ = write!(out, "{}", r.input);
        match &r.result {
            Ok(s) => {
                let nums = numbers(s);
                if nums.iter().all(|v| v.is_finite()) {
                    for v in nums {
                        let _ = write!(out, ",{v}");
                    }
                    // A condition number can be infinite exactly at a dead point: leave it empty then.
                    if s.condition.is_finite() {
                        let _ = write!(out, ",{}", s.condition);
                    } else {
                        out.push(',');
                    }
                    out.push_str(",ok\n");
                } else {
                    out.push_str(&",".repeat(blanks));
                    out.push_str(",non-finite\n");
                }
            }
            Err(e) => {
                out.push_str(&",".repeat(blanks));
                out.push(',');
                out.push_str(e.status());
                out.push('\n');
            }
        }
    }
    out
}

/// The seed-style table: angles in degrees (and degrees per second, per second squared).
pub fn table(info: &MechanismInfo, index: usize, rows: &[Row]) -> String {
    let deg = |k: Kind| {
        if k == Kind::Angle {
            180.0 / std::f64::consts::PI
        } else {
            1.0
        }
    };
    let input_kind = info.inputs[index].1;
    let mut head = vec![format!("{}{}", info.inputs[index].0, unit(input_kind))];
    for (suffix, per) in [("", ""), ("_vel", "/s"), ("_acc", "/s2")] {
        head.extend(info.unknowns.iter().map(|u| match u.1 {
            Kind::Angle => format!("{}{suffix}[deg{per}]", u.0),
            Kind::Length => u.0.to_string() + suffix,
        }));
    }
    for p in &info.points {
        head.extend(
            ["x", "y", "vx", "vy", "ax", "ay"]
                .iter()
                .map(|s| format!("{p}_{s}")),
        );
    }
    let width = head.iter().map(String::len).max().unwrap_or(0).max(12) + 1;
    let mut out = String::new();
    for h in &head {
        let _ = write!(out, "{h:>width$}");
    }
    out.push('\n');
    for r in rows {
        let _ = write!(out, "{:>width$.4}", r.input * deg(input_kind));
        match &r.result {
            Ok(s) => {
                let kinds = info.unknowns.iter().map(|u| u.1);
                let scaled = s.q.iter().zip(kinds.clone()).map(|(v, k)| {
                    if k == Kind::Angle {
                        wrap_deg(v * deg(k))
                    } else {
                        *v
                    }
                });
                let scaled: Vec<f64> = scaled
                    .chain(s.qd.iter().zip(kinds.clone()).map(|(v, k)| v * deg(k)))
                    .chain(s.qdd.iter().zip(kinds).map(|(v, k)| v * deg(k)))
                    .collect();
                for v in scaled {
                    let _ = write!(out, "{v:>width$.6}");
                }
                for p in &s.points {
                    for v in p.position.iter().chain(&p.velocity).chain(&p.acceleration) {
                        let _ = write!(out, "{v:>width$.6}");
                    }
                }
            }
            Err(e) => {
                let name = &info.inputs[index].0;
                let at = |input: f64| {
                    format!(
                        "{name} = {:.4}{}",
                        input * deg(input_kind),
                        unit_word(input_kind)
                    )
                };
                let _ = match r.stopped {
                    Some(s) if s.at_dead_point() => write!(
                        out,
                        "  {}: dead point near {} (cond {:.1e}), the branch cannot be continued past it",
                        e.status(),
                        at(s.input),
                        s.condition
                    ),
                    Some(s) => write!(
                        out,
                        "  {}: {e}; branch stopped at {} (cond {:.1e})",
                        e.status(),
                        at(s.input),
                        s.condition
                    ),
                    None => write!(out, "  {}: {e}", e.status()),
                };
            }
        }
        out.push('\n');
    }
    out
}

fn unit_word(k: Kind) -> &'static str {
    if k == Kind::Angle { " deg" } else { "" }
}

fn unit(k: Kind) -> &'static str {
    if k == Kind::Angle { "[deg]" } else { "" }
}

/// Degrees folded into [0, 360).
fn wrap_deg(d: f64) -> f64 {
    let w = d.rem_euclid(360.0);
    if w >= 360.0 { 0.0 } else { w }
}
