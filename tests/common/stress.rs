//! Helpers of the stress suite (`tests/stress_*.rs`): the dead-point references of
//! `tests/data/stress/`, settled start configurations and full motions through `DynMechanism`.
#![allow(dead_code)]

use super::Table;
use mechgen::sweep::Continuation;
use mechgen::{DynMechanism, InputMotion, Kind, MechanismInfo, PointMotion, SolveOptions};

/// The dead-point mechanisms of `mechanism.toml` with references in `tests/data/stress/`.
pub const DEAD_POINT_MECHANISMS: [&str; 2] = ["rocker_four_bar", "sixbar_g"];

/// The length scale of a mechanism: its largest length param (tolerances are relative to it).
pub fn length_scale(info: &MechanismInfo) -> f64 {
    info.params
        .iter()
        .filter(|p| p.kind == Kind::Length)
        .fold(0.0f64, |m, p| m.max(p.value.abs()))
}

fn data(file: &str) -> Table {
    Table::read(&format!(
        "{}/tests/data/stress/{file}",
        env!("CARGO_MANIFEST_DIR")
    ))
}

/// The reference rows near the dead points of `name` (side, offset_deg, input, unknowns, …).
pub fn reference(name: &str) -> Table {
    data(&format!("{name}.csv"))
}

/// A number of a reference row, by column name.
pub fn cell(table: &Table, row: &[String], column: &str) -> f64 {
    let i = table
        .header
        .iter()
        .position(|h| h == column)
        .unwrap_or_else(|| panic!("no column {column}"));
    row[i].parse().expect("number")
}

/// (side, input) of the dead points of `name`: "upper" is reached by increasing the input.
pub fn dead_points(name: &str) -> Vec<(String, f64)> {
    data("dead_points.csv")
        .rows
        .iter()
        .filter(|r| r[0] == name)
        .map(|r| (r[1].clone(), r[2].parse().expect("input")))
        .collect()
}

/// The generated mechanism and its settled start configuration (x, q).
pub fn start(name: &str) -> Started {
    start_with(mechgen::lookup::<f64>(name).expect("compiled in"))
}

/// The generic engine's copy of a compiled-in mechanism (always block Newton, no closed forms).
#[cfg(feature = "runtime")]
pub fn generic(name: &str) -> Box<dyn DynMechanism<f64>> {
    let all = mechgen::generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
        .expect("compiled-in file loads");
    Box::new(
        all.into_iter()
            .find(|m| m.name() == name)
            .expect("in the file"),
    )
}

/// An engine with its start state (x, q).
pub type Started = (Box<dyn DynMechanism<f64>>, Vec<f64>, Vec<f64>);

/// [`start`] for a given engine.
pub fn start_with(k: Box<dyn DynMechanism<f64>>) -> Started {
    let info = k.info();
    let x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
    let mut q: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
    k.solve_position(&x, &mut q, &SolveOptions::default())
        .expect("start assembles");
    (k, x, q)
}

/// The default continuation of an angle input.
pub fn continuation() -> Continuation {
    Continuation::for_input(Kind::Angle, 0.0)
}

/// q̇, q̈ and the points at a solved state of a one-input mechanism, for input rate 1 and input
/// acceleration 0.
pub fn motion(
    k: &dyn DynMechanism<f64>,
    x: &[f64],
    q: &[f64],
) -> (Vec<f64>, Vec<f64>, Vec<PointMotion<f64>>) {
    let n = q.len();
    let (mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n]);
    let mut points = vec![PointMotion::default(); k.info().points.len()];
    k.solve_velocity(x, q, &[1.0], &mut qd).expect("velocity");
    k.solve_acceleration(x, q, &[1.0], &qd, &[0.0], &mut qdd)
        .expect("acceleration");
    k.points(
        InputMotion::new(x, &[1.0], &[0.0]),
        q,
        &qd,
        &qdd,
        &mut points,
    )
    .expect("points");
    (qd, qdd, points)
}

/// Largest |got − want| over the largest |want|.
pub fn relative(got: &[f64], want: &[f64]) -> f64 {
    let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    got.iter()
        .zip(want)
        .fold(0.0f64, |m, (g, w)| m.max((g - w).abs() / scale))
}

/// `error <= bound`, false for a NaN error.
pub fn within(error: f64, bound: f64) -> bool {
    error <= bound
}
