//! Lint: the `start` configuration against the loops: residual at the start values, and the
//! runtime's Newton (`mechgen_runtime::solve::newton_in_place`, the one both engines run, on the
//! whole system in f64) from them when they do not close, so that a start off its branch is caught
//! at build time.
//!
//! Rule (relative residual = largest |Φi| at `start` / the largest length param, or 1):
//! - at most [`CLOSED`]: nothing to say;
//! - above it, Newton on the unknowns (inputs fixed) from the start values:
//!   - does not converge: error;
//!   - converges, and the residual was above [`WARN`]: warning with the converged values;
//!   - converges from a residual at most [`WARN`] (start values rounded to a tenth of a degree or
//!     so, like the seed documents'): nothing — the solvers correct that on their first step.

use mechgen_runtime::nalgebra::{DMatrix, DVector, Dyn};
use mechgen_runtime::solve::{NewtonWork, newton_in_place};
use mechgen_runtime::{NewtonOptions, NewtonReport, SolveError};

use crate::diagnostic::Diagnostic;
use crate::ir::dag::Var;
use crate::ir::differentiate::Derivatives;
use crate::ir::lower::System;
use crate::sema::model::{Kind, Model};

/// Relative residual below which the start configuration counts as assembled.
pub const CLOSED: f64 = 1e-6;
/// Relative residual above which a start that Newton repairs still gets a warning.
pub const WARN: f64 = 5e-2;
/// Newton's relative tolerance and iteration cap.
const TOLERANCE: f64 = 1e-12;
const MAX_ITERATIONS: u32 = 100;

/// What Newton from the start values did.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// The start values close the loops (relative residual).
    Closed(f64),
    /// Newton converged: the start's relative residual and the converged unknowns.
    Converged(f64, Vec<f64>),
    /// Newton failed: the start's relative residual and why.
    Failed(f64, String),
}

/// Evaluates the loops at `start` and, when they do not close, runs Newton from there.
pub fn newton_from_start(model: &Model, system: &System, derivatives: &Derivatives) -> Outcome {
    let scale = model
        .params
        .iter()
        .filter(|p| p.kind == Kind::Length)
        .map(|p| p.value.abs())
        .fold(0.0, f64::max);
    let scale = if scale > 0.0 { scale } else { 1.0 };
    let mut q: Vec<f64> = model.unknowns.iter().map(|u| u.start).collect();
    let roots: Vec<_> = system
        .residuals
        .iter()
        .chain(derivatives.jacobian.iter().flatten())
        .copied()
        .collect();
    let values_at = |q: &[f64]| {
        let var = |v: Var| match v {
            Var::X(i) => model.inputs.get(i as usize).map_or(0.0, |c| c.start),
            Var::Q(k) => q.get(k as usize).copied().unwrap_or(0.0),
            Var::P(i) => model.params.get(i as usize).map_or(0.0, |p| p.value),
            _ => 0.0,
        };
        system.dag.eval(&roots, &var)
    };
    let values = values_at(&q);
    let start_norm = system
        .residuals
        .iter()
        .fold(0.0, |m: f64, r| m.max(values[r.index()].abs()))
        / scale;
    if !start_norm.is_finite() {
        return Outcome::Failed(
            start_norm,
            "the loops are not finite at the start values".into(),
        );
    }
    if start_norm <= CLOSED {
        return Outcome::Closed(start_norm);
    }
    let n = q.len();
    let all: Vec<usize> = (0..n).collect();
    let length: Vec<bool> = model
        .unknowns
        .iter()
        .map(|u| u.kind == Kind::Length)
        .collect();
    let options = NewtonOptions {
        tolerance: TOLERANCE,
        max_iterations: MAX_ITERATIONS,
    };
    let mut work: NewtonWork<f64, Dyn> = NewtonWork {
        residual: DVector::zeros(n),
        jacobian: DMatrix::zeros(n, n),
        scale: DVector::zeros(n),
    };
    let mut report = NewtonReport::new();
    let solved = newton_in_place(
        0,
        q.as_mut_slice(),
        &all,
        &length,
        scale,
        &options,
        &mut report,
        &mut work,
        |q: &[f64], r, j| {
            let values = values_at(q);
            for (i, res) in system.residuals.iter().enumerate() {
                r[i] = values[res.index()];
                for (k, d) in derivatives.jacobian[i].iter().enumerate() {
                    j[(i, k)] = values[d.index()];
                }
            }
        },
    );
    match solved {
        Ok(()) => Outcome::Converged(start_norm, q),
        Err(e) => Outcome::Failed(start_norm, why(&e)),
    }
}

/// Why Newton stopped, in the words of a diagnostic note.
fn why(e: &SolveError) -> String {
    match e {
        SolveError::Unassemblable { residual, .. } => format!(
            "it makes no more progress (relative residual {residual:.1e}): no assembled \
             configuration near the start values"
        ),
        SolveError::Singular { .. } => "the Jacobian is singular on the way".into(),
        SolveError::NoConvergence { .. } => "the iteration cap was reached".into(),
        other => format!("{other}"),
    }
}

/// The diagnostic for a start configuration, if any (see the module rule).
pub fn check(model: &Model, system: &System, derivatives: &Derivatives) -> Option<Diagnostic> {
    let name = &model.name.text;
    match newton_from_start(model, system, derivatives) {
        Outcome::Closed(_) => None,
        Outcome::Converged(r, _) if r <= WARN => None,
        Outcome::Converged(r, q) => {
            let moved = moved_angles(model, &q);
            let values: Vec<String> = model
                .inputs
                .iter()
                .map(|c| (c, c.start))
                .chain(model.unknowns.iter().zip(q))
                .map(|(c, v)| {
                    // Angles in (−π, π]: Newton may have wandered through whole turns.
                    let v = if c.kind == crate::sema::model::Kind::Angle {
                        let tau = std::f64::consts::TAU;
                        let w = v.rem_euclid(tau);
                        if w > std::f64::consts::PI { w - tau } else { w }
                    } else {
                        v
                    };
                    format!("{} = {v:?}", c.name.text)
                })
                .collect();
            Some(
                Diagnostic::warning(
                    model.start_span,
                    format!(
                        "start configuration of `{name}` does not satisfy the loops \
                         (relative residual {r:.1e}); Newton from it converges"
                    ),
                )
                .with_label("off the loops")
                .with_note(format!(
                    "converged start: start = {{ {} }}",
                    values.join(", ")
                ))
                .with_note(match moved.is_empty() {
                    true => "check that this is the wanted assembly branch".to_string(),
                    false => format!(
                        "Newton moved {}: check that this is the wanted assembly branch (a start \
                         value in degrees is written `deg(…)`)",
                        moved.join(", ")
                    ),
                }),
            )
        }
        Outcome::Failed(r, why) => Some(
            Diagnostic::error(
                model.start_span,
                format!(
                    "start configuration of `{name}` does not satisfy the loops (relative \
                     residual {r:.1e}) and Newton from it does not converge"
                ),
            )
            .with_label("not an assembled configuration")
            .with_note(format!("Newton stopped: {why}"))
            .with_note(
                "give values that close every loop; if none exist, the params cannot be assembled",
            ),
        ),
    }
}

/// Condition number (largest over smallest singular value of the Jacobian, length columns scaled
/// by the length scale) above which a start configuration is singular for the sweeps: a dead point
/// or a crossing, which they cannot leave in a chosen direction.
pub const SINGULAR: f64 = 1e6;

/// A warning where the start configuration (the start values, or Newton's from them) is singular.
pub fn singular(model: &Model, system: &System, derivatives: &Derivatives) -> Option<Diagnostic> {
    let q: Vec<f64> = match newton_from_start(model, system, derivatives) {
        Outcome::Closed(_) => model.unknowns.iter().map(|u| u.start).collect(),
        Outcome::Converged(_, q) => q,
        Outcome::Failed(..) => return None,
    };
    let n = q.len();
    if n == 0 {
        return None;
    }
    let scale = model
        .params
        .iter()
        .filter(|p| p.kind == Kind::Length)
        .map(|p| p.value.abs())
        .fold(0.0, f64::max);
    let scale = if scale > 0.0 { scale } else { 1.0 };
    let roots: Vec<_> = derivatives.jacobian.iter().flatten().copied().collect();
    let var = |v: Var| match v {
        Var::X(i) => model.inputs.get(i as usize).map_or(0.0, |c| c.start),
        Var::Q(k) => q.get(k as usize).copied().unwrap_or(0.0),
        Var::P(i) => model.params.get(i as usize).map_or(0.0, |p| p.value),
        _ => 0.0,
    };
    let values = system.dag.eval(&roots, &var);
    let j = DMatrix::from_fn(n, n, |i, k| {
        let d = derivatives.jacobian[i][k];
        let unit = if model.unknowns[k].kind == Kind::Length {
            scale
        } else {
            1.0
        };
        values[d.index()] * unit / scale
    });
    if j.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let sv = j.singular_values();
    let (hi, lo) = (sv.max(), sv.min());
    let condition = if lo > 0.0 { hi / lo } else { f64::INFINITY };
    (condition > SINGULAR).then(|| {
        Diagnostic::warning(
            model.start_span,
            format!(
                "start configuration of `{}` is singular (condition number {condition:.1e}): a \
                 dead point or a crossing",
                model.name.text
            ),
        )
        .with_label("the loops' Jacobian is singular here")
        .with_note(
            "a sweep cannot choose its branch from here: its rows would read `singular`; start a \
             little way along the branch instead (`mechgen branches` lists the dead points and \
             crossings)",
        )
    })
}

/// Angle unknowns that Newton moved by more than [`MOVED_DEGREES`] from their start values
/// (modulo whole turns), as `` `q2` by 33.1° ``.
fn moved_angles(model: &Model, converged: &[f64]) -> Vec<String> {
    let tau = std::f64::consts::TAU;
    model
        .unknowns
        .iter()
        .zip(converged)
        .filter(|(c, _)| c.kind == Kind::Angle)
        .filter_map(|(c, &v)| {
            let d = (v - c.start).rem_euclid(tau);
            let d = d.min(tau - d).to_degrees();
            (d > MOVED_DEGREES).then(|| format!("`{}` by {d:.1}°", c.name.text))
        })
        .collect()
}

/// How far (degrees) Newton may move a start angle before the warning names it.
const MOVED_DEGREES: f64 = 3.0;

/// A warning when start values of angles are more than a turn in radians (`q1 = 90`): almost
/// always degrees written where the format reads radians.
pub fn degrees(model: &Model) -> Option<Diagnostic> {
    let tau = std::f64::consts::TAU;
    let big: Vec<_> = model
        .inputs
        .iter()
        .chain(&model.unknowns)
        .filter(|c| c.kind == Kind::Angle && c.start.abs() > tau)
        .collect();
    let first = big.first()?;
    let list: Vec<String> = big
        .iter()
        .map(|c| format!("`{} = {}`", c.name.text, c.start))
        .collect();
    Some(
        Diagnostic::warning(
            model.start_span,
            format!(
                "start values of `{}` are more than a turn in radians: {}",
                model.name.text,
                list.join(", ")
            ),
        )
        .with_label("angles are in radians")
        .with_note(format!(
            "for degrees write `{} = deg({})`",
            first.name.text, first.start
        )),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SourceFile;
    use crate::compile::analyze;

    fn outcomes(text: &str) -> Vec<Outcome> {
        let (mechs, _) = analyze(&SourceFile::new("t.toml", text));
        mechs
            .iter()
            .map(|m| newton_from_start(&m.model, &m.system, &m.derivatives))
            .collect()
    }

    const FOUR_BAR: &str = r#"[mechanism.m]
inputs = ["q1"]
unknowns = ["q2", "q3"]
loops = ["l1*e(q1) + l2*e(q2) - l4 - l3*e(q3)"]
params = { l1 = 0.1, l2 = 0.35, l3 = 0.3, l4 = 0.4 }
start = { q1 = 0.0, q2 = Q2, q3 = Q3 }
"#;

    #[test]
    fn exact_rounded_and_far_starts() {
        let exact = FOUR_BAR
            .replace("Q2", "0.9479697413828936")
            .replace("Q3", "1.8959394827657874");
        assert!(matches!(outcomes(&exact)[..], [Outcome::Closed(r)] if r < 1e-14));
        let rounded = FOUR_BAR
            .replace("Q2", "\"deg(54.3)\"")
            .replace("Q3", "\"deg(108.6)\"");
        let [Outcome::Converged(r, q)] = &outcomes(&rounded)[..] else {
            panic!("{:?}", outcomes(&rounded));
        };
        assert!(*r > CLOSED && *r < WARN, "{r}");
        assert!((q[0] - 0.9479697413828936).abs() < 1e-12, "{q:?}");
        let far = rounded.replace("deg(54.3)", "deg(70)");
        assert!(matches!(outcomes(&far)[..], [Outcome::Converged(r, _)] if r > WARN));
        let (mechs, diags) = analyze(&SourceFile::new("t.toml", far));
        assert_eq!((mechs.len(), diags.len()), (1, 1), "{diags:?}");
        assert!(!diags[0].is_error() && diags[0].notes[0].contains("q2 = 0.94796974138289"));
        let unreachable = exact.replace("l4 = 0.4", "l4 = 1.0");
        let (mechs, diags) = analyze(&SourceFile::new("t.toml", unreachable));
        assert!(
            mechs.is_empty() && diags.len() == 1 && diags[0].is_error(),
            "{diags:?}"
        );
    }

    #[test]
    fn default_seed_and_fixture_files_are_quiet() {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
        let fixtures = std::fs::read_dir(format!("{root}/tests/fixtures")).expect("fixtures");
        let mut paths: Vec<String> = fixtures
            .filter_map(|e| Some(e.ok()?.path().display().to_string()))
            .filter(|p| p.ends_with(".toml"))
            .collect();
        paths.extend(["mechanism.toml", "tests/data/seeds.toml"].map(|p| format!("{root}/{p}")));
        assert!(paths.len() >= 6, "{paths:?}");
        for path in paths {
            let text = std::fs::read_to_string(&path).expect("file");
            let (mechs, diags) = analyze(&SourceFile::new(path.as_str(), text));
            assert!(diags.is_empty(), "{path}: {diags:?}");
            for m in &mechs {
                let o = newton_from_start(&m.model, &m.system, &m.derivatives);
                let r = match o {
                    Outcome::Closed(r) | Outcome::Converged(r, _) => r,
                    Outcome::Failed(..) => panic!("{}: {o:?}", m.model.name.text),
                };
                assert!(r < WARN, "{}: {r}", m.model.name.text);
            }
        }
    }
}
