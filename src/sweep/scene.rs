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

use super::{Row, RowRef};
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

/// One row of a scene sweep, its outputs borrowed from the [`SceneSolver`] that solved it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneRowRef<'a> {
    pub input: f64,
    /// The scene's output columns, or why the row has none.
    pub outputs: Result<&'a [f64], SolveError>,
    /// The CSV status (`ok`, or the branch's or the scene solver's failure).
    pub status: &'static str,
    /// The Jacobian's condition estimate at the row (from the continuation), when finite.
    pub condition: Option<f64>,
}

impl SceneRow {
    pub fn view(&self) -> SceneRowRef<'_> {
        SceneRowRef {
            input: self.input,
            outputs: self.outputs.as_deref().map_err(|e| *e),
            status: self.status,
            condition: self.condition,
        }
    }
}

impl SceneRowRef<'_> {
    pub fn to_row(&self) -> SceneRow {
        SceneRow {
            input: self.input,
            outputs: self.outputs.map(<[f64]>::to_vec),
            status: self.status,
            condition: self.condition,
        }
    }
}

/// A scene's solver run at its mechanism's solved rows (a sweep of input `index` at `rate`, every
/// other input at its value in `x`), row by row, each from the row's configuration: what
/// [`scene_rows`] runs, and `mechgen batch SCENE` per set. Allocates nothing per row.
pub struct SceneSolver<'s> {
    scene: &'s dyn DynScene<f64>,
    index: usize,
    state: DynSceneState<f64>,
    options: SolveOptions<f64>,
}

impl<'s> SceneSolver<'s> {
    pub fn new(
        scene: &'s dyn DynScene<f64>,
        x: &[f64],
        index: usize,
        rate: f64,
        options: &SolveOptions<f64>,
    ) -> Self {
        let ncols = scene.info().columns.len();
        let mut xd = vec![0.0; x.len()];
        if let Some(v) = xd.get_mut(index) {
            *v = rate;
        }
        let xdd = vec![0.0; x.len()];
        SceneSolver {
            scene,
            index,
            state: DynSceneState::new(InputMotion::new(x, &xd, &xdd), &[], ncols),
            options: *options,
        }
    }

    /// The scene's row at its mechanism's row `r`.
    pub fn row(&mut self, r: &RowRef<'_>) -> SceneRowRef<'_> {
        let s = match &r.result {
            Ok(s) => s,
            Err(e) => {
                return SceneRowRef {
                    input: r.input,
                    outputs: Err(*e),
                    status: r.status(),
                    condition: None,
                };
            }
        };
        let state = &mut self.state;
        if let Some(x) = state.x.get_mut(self.index) {
            *x = r.input;
        }
        state.q.clear();
        state.q.extend_from_slice(s.q);
        let solved = self
            .scene
            .solve_in_place(state, &self.options)
            .and_then(|_| match state.out.iter().all(|v| v.is_finite()) {
                true => Ok(&state.out[..]),
                false => Err(SolveError::Overflow {
                    block: 0,
                    stage: mechgen_runtime::error::Stage::Position,
                }),
            });
        SceneRowRef {
            input: r.input,
            status: solved.as_ref().map_or_else(|e| e.status(), |_| "ok"),
            outputs: solved,
            condition: s.condition.is_finite().then_some(s.condition),
        }
    }
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
    let mut solver = SceneSolver::new(scene, x, index, rate, options);
    rows.iter()
        .map(|r| solver.row(&r.view()).to_row())
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
        scene_csv_row(&mut out, scene.columns.len(), &r.view());
    }
    out
}

/// Row `r` of a scene with `columns` output columns, as a line of [`scene_csv`].
pub fn scene_csv_row(out: &mut String, columns: usize, r: &SceneRowRef<'_>) {
    let _ = write!(out, "{:?}", r.input);
    match &r.outputs {
        Ok(v) => v.iter().for_each(|v| {
            let _ = write!(out, ",{v:?}");
        }),
        Err(_) => (0..columns).for_each(|_| out.push(',')),
    }
    match (r.outputs.is_ok(), r.condition) {
        (true, Some(c)) => {
            let _ = write!(out, ",{c:?}");
        }
        _ => out.push(','),
    }
    let _ = writeln!(out, ",{}", r.status);
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

/// The table of a scene sweep (degrees, file units, seven significant digits; angles of
/// positions in [0°, 360°)), row by row: its header line, then a line per row.
pub struct SceneTable {
    head: String,
    units: Vec<(Kind, usize)>,
    input_kind: Kind,
    width: usize,
}

impl SceneTable {
    pub fn new(scene: &SceneDescription, info: &MechanismInfo, index: usize) -> SceneTable {
        let (input, input_kind) = (&info.inputs[index].name, info.inputs[index].kind);
        let units = column_units(scene, info);
        let tag = |k: Kind, o: usize| {
            let per = ["", "/s", "/s2"][o];
            match k {
                Kind::Angle => format!("[deg{per}]"),
                _ => format!("[u{per}]"),
            }
        };
        let mut names = vec![format!("{input}{}", tag(input_kind, 0))];
        names.extend(
            scene
                .columns
                .iter()
                .zip(&units)
                .map(|(c, &(k, o))| format!("{c}{}", tag(k, o))),
        );
        let width = names.iter().map(String::len).max().unwrap_or(0).max(13) + 1;
        let mut head = String::new();
        names.iter().for_each(|h| {
            let _ = write!(head, "{h:>width$}");
        });
        head.push('\n');
        SceneTable {
            head,
            units,
            input_kind,
            width,
        }
    }

    /// The column names' line.
    pub fn header(&self) -> &str {
        &self.head
    }

    /// Row `r`'s line, appended to `out`.
    pub fn row(&self, out: &mut String, r: &SceneRowRef<'_>) {
        let width = self.width;
        let deg = |k: Kind| match k {
            Kind::Angle => 180.0 / std::f64::consts::PI,
            _ => 1.0,
        };
        let _ = write!(
            out,
            "{:>width$}",
            significant(r.input * deg(self.input_kind))
        );
        match &r.outputs {
            Ok(v) => {
                for (v, &(k, o)) in v.iter().zip(&self.units) {
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
}

/// The seed-style table of a scene sweep: the input and the scene's columns with their units,
/// angles in degrees, numbers to seven significant digits; a failed row shows its status.
pub fn scene_table(
    scene: &SceneDescription,
    info: &MechanismInfo,
    index: usize,
    rows: &[SceneRow],
) -> String {
    let table = SceneTable::new(scene, info, index);
    let mut out = table.header().to_string();
    for r in rows {
        table.row(&mut out, &r.view());
    }
    out
}
