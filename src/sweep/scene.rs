//! Scene sweeps (interfaces.md, "Scenes on the command line"): the mechanism's continuation
//! follows the start's branch (same options, same branch rule, same statuses), and at every
//! solved row the scene's own solver runs from that row's configuration, so the columns are the
//! scene's: the input, its outputs up to its order, `cond`, `status`. [`scene_csv`] and
//! [`scene_table`] write them as the mechanism's CSV and table are written.

use std::fmt::Write as _;

use mechgen_runtime::error::SolveError;
use mechgen_runtime::info::{Kind, MechanismInfo};
use mechgen_runtime::mechanism::InputMotion;
use mechgen_runtime::scene::{DynScene, DynSceneState, SceneDescription};
use mechgen_runtime::solve::SolveOptions;

use super::Row;
use crate::report::significant;

/// One row of a scene sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneRow {
    pub input: f64,
    /// The scene's output columns, or why the row has none.
    pub outputs: Result<Vec<f64>, SolveError>,
    /// The CSV status (`ok`, or the branch's or the scene solver's failure).
    pub status: &'static str,
    /// The Jacobian's condition estimate at the row (from the continuation), when finite.
    pub condition: Option<f64>,
}

/// The scene's outputs along `rows` (a sweep of input `index` of its mechanism at `rate`, every
/// other input at its value in `x`), each solved by `scene` from the row's configuration.
pub fn scene_rows(
    scene: &dyn DynScene<f64>,
    x: &[f64],
    index: usize,
    rows: &[Row],
    rate: f64,
    options: &SolveOptions<f64>,
) -> Vec<SceneRow> {
    let ncols = scene.info().columns.len();
    let mut xd = vec![0.0; x.len()];
    xd[index] = rate;
    let xdd = vec![0.0; x.len()];
    let mut state = DynSceneState::new(InputMotion::new(x, &xd, &xdd), &[], ncols);
    rows.iter()
        .map(|r| match &r.result {
            Ok(s) => {
                state.x[index] = r.input;
                state.q.clone_from(&s.q);
                let solved = scene.solve_in_place(&mut state, options).and_then(|_| {
                    match state.out.iter().all(|v| v.is_finite()) {
                        true => Ok(state.out.clone()),
                        false => Err(SolveError::Overflow {
                            block: 0,
                            stage: mechgen_runtime::error::Stage::Position,
                        }),
                    }
                });
                SceneRow {
                    input: r.input,
                    status: solved.as_ref().map_or_else(|e| e.status(), |_| "ok"),
                    outputs: solved,
                    condition: s.condition.is_finite().then_some(s.condition),
                }
            }
            Err(e) => SceneRow {
                input: r.input,
                outputs: Err(*e),
                status: r.status(),
                condition: None,
            },
        })
        .collect()
}

/// CSV header: the input, the scene's columns, `cond`, `status`.
pub fn scene_csv_header(scene: &SceneDescription, input: &str) -> Vec<String> {
    let mut h = vec![input.to_string()];
    h.extend(scene.columns.iter().cloned());
    h.extend(["cond".to_string(), "status".to_string()]);
    h
}

/// The scene sweep as CSV text (radians, shortest round-trip numbers, empty cells on failed rows).
pub fn scene_csv(scene: &SceneDescription, input: &str, rows: &[SceneRow]) -> String {
    let header = scene_csv_header(scene, input);
    let mut out = header.join(",") + "\n";
    for r in rows {
        let _ = write!(out, "{:?}", r.input);
        match &r.outputs {
            Ok(v) => v.iter().for_each(|v| {
                let _ = write!(out, ",{v:?}");
            }),
            Err(_) => out.push_str(&",".repeat(scene.columns.len())),
        }
        match (r.outputs.is_ok(), r.condition) {
            (true, Some(c)) => {
                let _ = write!(out, ",{c:?}");
            }
            _ => out.push(','),
        }
        let _ = writeln!(out, ",{}", r.status);
    }
    out
}

/// Each column's kind and its time derivative (0, 1, 2): angles in the table are degrees.
fn column_units(scene: &SceneDescription, info: &MechanismInfo) -> Vec<(Kind, usize)> {
    let n = usize::from(scene.order) + 1;
    let mut units = Vec::new();
    for u in &scene.unknowns {
        let kind = info
            .unknowns
            .iter()
            .find(|c| &c.name == u)
            .map_or(Kind::Length, |c| c.kind);
        units.extend((0..n).map(|o| (kind, o)));
    }
    units.extend((0..scene.points.len()).flat_map(|_| (0..n).flat_map(|o| [(Kind::Length, o); 2])));
    units
}

/// The seed-style table of a scene sweep: the input and the scene's columns with their units,
/// angles in degrees, numbers to seven significant digits; a failed row shows its status.
pub fn scene_table(
    scene: &SceneDescription,
    info: &MechanismInfo,
    index: usize,
    rows: &[SceneRow],
) -> String {
    let (input, input_kind) = (&info.inputs[index].name, &info.inputs[index].kind);
    let units = column_units(scene, info);
    let tag = |k: Kind, o: usize| {
        let per = ["", "/s", "/s2"][o];
        match k {
            Kind::Angle => format!("[deg{per}]"),
            _ => format!("[u{per}]"),
        }
    };
    let mut head = vec![format!("{input}{}", tag(*input_kind, 0))];
    head.extend(
        scene
            .columns
            .iter()
            .zip(&units)
            .map(|(c, &(k, o))| format!("{c}{}", tag(k, o))),
    );
    let width = head.iter().map(String::len).max().unwrap_or(0).max(13) + 1;
    let deg = |k: Kind| match k {
        Kind::Angle => 180.0 / std::f64::consts::PI,
        _ => 1.0,
    };
    let mut out = String::new();
    head.iter().for_each(|h| {
        let _ = write!(out, "{h:>width$}");
    });
    out.push('\n');
    for r in rows {
        let _ = write!(out, "{:>width$}", significant(r.input * deg(*input_kind)));
        match &r.outputs {
            Ok(v) => {
                for (v, &(k, o)) in v.iter().zip(&units) {
                    let mut s = v * deg(k);
                    if k == Kind::Angle && o == 0 {
                        s = s.rem_euclid(360.0) % 360.0;
                    }
                    let _ = write!(out, "{:>width$}", significant(s));
                }
            }
            Err(e) => {
                let _ = write!(out, "  {}: {e}", r.status);
            }
        }
        out.push('\n');
    }
    out
}
