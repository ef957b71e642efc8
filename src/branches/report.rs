//! Branch identification, output: the summary the CLI prints (circuits, branches with their input
//! ranges, dead points and crossings with their configurations, the configurations at each `--at`
//! input; angles in degrees) and the four CSV files of the interface spec (radians, shortest
//! round-trip).

use std::fmt::Write as _;

use super::{Analysis, Setup};

impl Setup {
    /// An input value as printed: degrees for an angle input.
    pub(super) fn show_input(&self, x: f64) -> String {
        if self.input_is_angle {
            format!("{:.10} deg", x.to_degrees())
        } else {
            format!("{x:.10}")
        }
    }

    /// A configuration as printed: `q1 = 12.5 deg, s = 0.3`.
    fn show_q(&self, q: &[f64]) -> String {
        q.iter()
            .zip(&self.unknown_names)
            .zip(&self.angle)
            .map(|((v, n), &a)| {
                if a {
                    format!("{n} = {:.10} deg", v.to_degrees())
                } else {
                    format!("{n} = {v:.10}")
                }
            })
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The summary of an analysis.
    pub fn summary(&self, a: &Analysis) -> String {
        let mut s = String::new();
        let range = if a.full_turn {
            "a full turn".to_string()
        } else {
            format!("{} to {}", self.show_input(a.from), self.show_input(a.to))
        };
        let _ = writeln!(
            s,
            "{}: branches along {} over {range}: {} circuit(s), {} branch(es), {} dead point(s), \
             {} crossing(s)",
            self.name,
            self.input_name,
            a.circuits,
            a.branches.len(),
            a.dead_points.len(),
            a.crossings.len()
        );
        for (block, modes) in &a.degenerate {
            let modes: Vec<String> = modes
                .iter()
                .enumerate()
                .map(|(b, m)| format!("block {b} mode {m}"))
                .collect();
            let _ = writeln!(
                s,
                "  degenerate: {} makes block {block} degenerate (two of its points coincide): \
                 those configurations are left out",
                modes.join(", ")
            );
        }
        for (i, b) in a.branches.iter().enumerate() {
            let what = if b.full_turn {
                "full turn (no dead point)".to_string()
            } else {
                let end =
                    |d: Option<usize>| d.map_or("range end".into(), |d| format!("dead point {d}"));
                format!(
                    "{} from {} to {} ({} to {})",
                    self.input_name,
                    self.show_input(b.from),
                    self.show_input(b.to),
                    end(b.dead[0]),
                    end(b.dead[1])
                )
            };
            let _ = writeln!(s, "  branch {i} (circuit {}): {what}", b.circuit);
        }
        for (i, d) in a.dead_points.iter().enumerate() {
            let _ = writeln!(
                s,
                "  dead point {i} (circuit {}): {} = {}: {}",
                d.circuit,
                self.input_name,
                self.show_input(d.input),
                self.show_q(&d.q)
            );
        }
        for (i, c) in a.crossings.iter().enumerate() {
            let _ = writeln!(
                s,
                "  crossing {i} (circuit {}): {} = {}: {} (branches {} meet)",
                c.circuit,
                self.input_name,
                self.show_input(c.input),
                self.show_q(&c.q),
                c.branches
                    .iter()
                    .map(usize::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        for &x in &a.at_inputs {
            let here: Vec<_> =
                a.at.iter()
                    .filter(|c| c.input.to_bits() == x.to_bits())
                    .collect();
            let _ = writeln!(
                s,
                "  at {} = {}: {} configuration(s)",
                self.input_name,
                self.show_input(x),
                here.len()
            );
            for c in here {
                let _ = writeln!(
                    s,
                    "    circuit {}, branch {}: {}",
                    c.circuit,
                    c.branch,
                    self.show_q(&c.q)
                );
            }
        }
        s
    }

    /// `NAME-dead-points.csv`: `input`, each unknown, `circuit`.
    pub fn dead_points_csv(&self, a: &Analysis) -> String {
        let mut s = format!("input,{},circuit\n", self.unknown_names.join(","));
        for d in &a.dead_points {
            let _ = writeln!(s, "{},{},{}", num(d.input), join(&d.q), d.circuit);
        }
        s
    }

    /// `NAME-crossings.csv`: `input`, each unknown, `branches` (labels joined by `;`).
    pub fn crossings_csv(&self, a: &Analysis) -> String {
        let mut s = format!("input,{},branches\n", self.unknown_names.join(","));
        for c in &a.crossings {
            let labels: Vec<String> = c.branches.iter().map(usize::to_string).collect();
            let _ = writeln!(s, "{},{},{}", num(c.input), join(&c.q), labels.join(";"));
        }
        s
    }

    /// `NAME-branches.csv`: `branch`, `circuit`, `input_from`, `input_to`, `full_turn`.
    pub fn branches_csv(&self, a: &Analysis) -> String {
        let mut s = String::from("branch,circuit,input_from,input_to,full_turn\n");
        for (i, b) in a.branches.iter().enumerate() {
            if b.full_turn {
                let _ = writeln!(s, "{i},{},,,true", b.circuit);
            } else {
                let _ = writeln!(s, "{i},{},{},{},false", b.circuit, num(b.from), num(b.to));
            }
        }
        s
    }

    /// `NAME-at.csv`: `input`, each unknown, `circuit`, `branch`.
    pub fn at_csv(&self, a: &Analysis) -> String {
        let mut s = format!("input,{},circuit,branch\n", self.unknown_names.join(","));
        for c in &a.at {
            let _ = writeln!(
                s,
                "{},{},{},{}",
                num(c.input),
                join(&c.q),
                c.circuit,
                c.branch
            );
        }
        s
    }
}

fn join(q: &[f64]) -> String {
    q.iter().map(|&v| num(v)).collect::<Vec<_>>().join(",")
}

/// A CSV number as the sweep's CSV writes it: shortest round-trip, with an exponent where that is
/// shorter (`1.8216e-16`, not `0.00000000000000018216`).
fn num(v: f64) -> String {
    let mut out = Vec::new();
    crate::report::push_float(&mut out, v);
    String::from_utf8(out).unwrap_or_default()
}
