//! Shared test helpers: reading reference CSVs and comparing sweeps with them.
#![allow(dead_code)]

#[cfg(feature = "cli")]
pub mod cli;
pub mod engines;
pub mod lanes;
pub mod scenes;
pub mod sensitivity;
pub mod stress;
pub mod sweep;

use mechgen::sweep::Row;
use mechgen::{Kind, MechanismInfo};

/// A CSV table: header and rows of cells.
pub struct Table {
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Table {
    pub fn read(path: &str) -> Table {
        let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
        let mut lines = text.lines().filter(|l| !l.trim().is_empty());
        let header = lines
            .next()
            .expect("header")
            .split(',')
            .map(str::to_string)
            .collect();
        let rows = lines
            .map(|l| l.split(',').map(str::to_string).collect())
            .collect();
        Table { header, rows }
    }

    pub fn column(&self, name: &str) -> Vec<f64> {
        let i = self
            .header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name}"));
        self.rows
            .iter()
            .map(|r| r[i].parse::<f64>().unwrap_or(f64::NAN))
            .collect()
    }
}

/// Angle difference folded into (−π, π].
pub fn angle_diff(a: f64, b: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let d = (a - b).rem_euclid(tau);
    if d > std::f64::consts::PI { d - tau } else { d }
}

/// The columns of a sweep, named as in the CSV format, as f64 (NaN for failed rows).
pub fn sweep_columns(info: &MechanismInfo, rows: &[Row]) -> Vec<(String, Kind, bool, Vec<f64>)> {
    let mut cols = Vec::new();
    let get = |f: &dyn Fn(&mechgen::sweep::Solved) -> f64| -> Vec<f64> {
        rows.iter()
            .map(|r| r.result.as_ref().map_or(f64::NAN, f))
            .collect()
    };
    for (i, u) in info.unknowns.iter().enumerate() {
        cols.push((u.name.clone(), u.kind, false, get(&|s| s.q[i])));
    }
    for (i, u) in info.unknowns.iter().enumerate() {
        cols.push((
            format!("{}_vel", u.name),
            Kind::Length,
            true,
            get(&|s| s.qd[i]),
        ));
    }
    for (i, u) in info.unknowns.iter().enumerate() {
        cols.push((
            format!("{}_acc", u.name),
            Kind::Length,
            true,
            get(&|s| s.qdd[i]),
        ));
    }
    for (p, name) in info.points.iter().enumerate() {
        for (suffix, deriv, f) in [
            (
                "x",
                false,
                (|m: &mechgen::PointMotion<f64>| m.position[0])
                    as fn(&mechgen::PointMotion<f64>) -> f64,
            ),
            ("y", false, |m| m.position[1]),
            ("vx", true, |m| m.velocity[0]),
            ("vy", true, |m| m.velocity[1]),
            ("ax", true, |m| m.acceleration[0]),
            ("ay", true, |m| m.acceleration[1]),
        ] {
            cols.push((
                format!("{name}_{suffix}"),
                Kind::Length,
                deriv,
                get(&|s| f(&s.points[p])),
            ));
        }
    }
    cols
}

/// Largest error of every column against the reference table: angles modulo 2π, lengths
/// absolute, derivatives relative to the column's largest magnitude.
pub fn compare(info: &MechanismInfo, rows: &[Row], reference: &Table) -> Vec<(String, f64)> {
    sweep_columns(info, rows)
        .into_iter()
        .map(|(name, kind, deriv, got)| {
            let want = reference.column(&name);
            assert_eq!(want.len(), got.len(), "{name}: row count");
            let scale = if deriv {
                want.iter()
                    .fold(0.0f64, |m, v| m.max(v.abs()))
                    .max(f64::MIN_POSITIVE)
            } else {
                1.0
            };
            let err = want.iter().zip(&got).fold(0.0f64, |m, (w, g)| {
                let d = if kind == Kind::Angle {
                    angle_diff(*g, *w)
                } else {
                    g - w
                };
                if d.is_nan() {
                    f64::INFINITY
                } else {
                    m.max(d.abs() / scale)
                }
            });
            (name, err)
        })
        .collect()
}
