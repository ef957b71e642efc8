//! The pipeline, stage by stage: parse → check → lower → differentiate → structure → plan → emit.

use crate::check::{self, Model};
use crate::dag::{Dag, Node, NodeId, Var};
use crate::diagnostic::{Diagnostic, SourceFile};
use crate::differentiate::{self, Derivatives};
use crate::lower::{self, System};
use crate::plan::{self, BlockForms};
use crate::structure::{self, StructureError};
use crate::{emit, parse, start};

/// One mechanism through every analysis stage.
#[derive(Clone, Debug)]
pub struct Compiled {
    pub model: Model,
    pub system: System,
    pub derivatives: Derivatives,
    pub blocks: Vec<BlockForms>,
}

/// Runs every stage up to code generation. Mechanisms with errors are left out; all diagnostics of
/// the file (errors and warnings) are returned, in file order.
pub fn analyze(file: &SourceFile) -> (Vec<Compiled>, Vec<Diagnostic>) {
    let (ast, mut diags) = parse::parse(file);
    let models = check::check(&ast, &mut diags);
    let mut out = Vec::new();
    for model in models {
        let mut system = lower::lower(&model);
        let (ni, nu) = (model.inputs.len(), model.unknowns.len());
        let derivatives = differentiate::differentiate(&mut system, ni, nu);
        let before = diags.len();
        lint(&model, &system, &mut diags);
        let incidence: Vec<Vec<usize>> = derivatives
            .jacobian
            .iter()
            .map(|row| (0..nu).filter(|&k| !system.dag.is_zero(row[k])).collect())
            .collect();
        match structure::blocks(&incidence, nu) {
            Ok(blocks) if diags[before..].iter().all(|d| !d.is_error()) => {
                // Before the start check, which would only see non-finite loops.
                if let Some(d) = overflow(&model, &system) {
                    diags.push(d);
                    continue;
                }
                let start = start::check(&model, &system, &derivatives);
                let failed = start.as_ref().is_some_and(Diagnostic::is_error);
                diags.extend(start);
                if failed {
                    continue;
                }
                let blocks = plan::block_forms(&mut system, &model, &derivatives, &blocks);
                // Planning folds constants too.
                if let Some(d) = overflow(&model, &system) {
                    diags.push(d);
                    continue;
                }
                out.push(Compiled {
                    model,
                    system,
                    derivatives,
                    blocks,
                });
            }
            Ok(_) => {}
            Err(e) => diags.extend(structure_diagnostics(&model, &system, e)),
        }
    }
    diags.sort_by_key(|d| d.span.start);
    (out, diags)
}

/// Generates the Rust source for a file, or returns its diagnostics when any is an error.
pub fn compile(file: &SourceFile) -> Result<(String, Vec<Diagnostic>), Vec<Diagnostic>> {
    let (mechs, diags) = analyze(file);
    if diags.iter().any(Diagnostic::is_error) {
        return Err(diags);
    }
    match emit::emit(&mechs, &file.name) {
        Ok(code) => Ok((code, diags)),
        Err(msg) => Err(vec![Diagnostic::error(Default::default(), msg)]),
    }
}

/// A constant of the DAG that is not finite (`1e200*1e200`, `1/0` folded, or such a constant
/// differentiated): the generated code cannot spell it. Points at the first loop or point that
/// holds one, or at the mechanism when only derivatives do.
fn overflow(model: &Model, system: &System) -> Option<Diagnostic> {
    let dag = &system.dag;
    let whole: Vec<NodeId> = (0..dag.len() as u32).map(NodeId).collect();
    if !non_finite_constant(dag, &whole) {
        return None;
    }
    let message = "a constant of this expression is not finite (it overflows f64)";
    for (i, l) in model.loops.iter().enumerate() {
        if non_finite_constant(dag, &system.residuals[2 * i..2 * i + 2]) {
            return Some(Diagnostic::error(l.span, message).with_label("overflows"));
        }
    }
    for ((_, e), xy) in model.points.iter().zip(&system.points) {
        if non_finite_constant(dag, xy) {
            return Some(Diagnostic::error(e.span, message).with_label("overflows"));
        }
    }
    Some(Diagnostic::error(
        model.name.span,
        format!(
            "mechanism `{}`: a constant of its derivatives is not finite (it overflows f64)",
            model.name.text
        ),
    ))
}

/// Whether a node reachable from `roots` is a non-finite constant.
fn non_finite_constant(dag: &Dag, roots: &[NodeId]) -> bool {
    let mut seen = vec![false; dag.len()];
    let mut stack = roots.to_vec();
    while let Some(n) = stack.pop() {
        if std::mem::replace(&mut seen[n.index()], true) {
            continue;
        }
        match dag.node(n) {
            Node::Const(bits) if !f64::from_bits(bits).is_finite() => return true,
            node => stack.extend(node.children()),
        }
    }
    false
}

/// Inputs that drive nothing (error) and params that are never used (warning).
fn lint(model: &Model, system: &System, diags: &mut Vec<Diagnostic>) {
    let mut used: Vec<Var> = Vec::new();
    for &r in system
        .residuals
        .iter()
        .chain(system.points.iter().flatten())
    {
        used.extend(system.dag.vars_of(r));
    }
    let in_loops: Vec<Var> = system
        .residuals
        .iter()
        .flat_map(|&r| system.dag.vars_of(r))
        .collect();
    for (i, input) in model.inputs.iter().enumerate() {
        if !in_loops.contains(&Var::X(i as u16)) {
            diags.push(
                Diagnostic::error(
                    input.name.span,
                    format!("input `{}` appears in no loop", input.name.text),
                )
                .with_label("drives nothing"),
            );
        }
    }
    for (i, p) in model.params.iter().enumerate() {
        let by_param = model.params.iter().any(|q| {
            q.source
                .as_deref()
                .is_some_and(|s| mentions(s, &p.name.text))
        });
        if !used.contains(&Var::P(i as u16)) && !by_param {
            diags.push(Diagnostic::warning(
                p.name.span,
                format!("param `{}` is never used", p.name.text),
            ));
        }
    }
}

fn mentions(src: &str, name: &str) -> bool {
    src.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .any(|w| w == name)
}

fn structure_diagnostics(model: &Model, system: &System, e: StructureError) -> Vec<Diagnostic> {
    let eq = |i: usize| {
        let l = &model.loops[i / 2];
        let comp = if i % 2 == 0 { "x" } else { "y" };
        let what = if system
            .dag
            .as_const(system.residuals[i])
            .is_some_and(|c| c != 0.0)
        {
            "is a nonzero constant: the loop can never close"
        } else if system.dag.is_zero(system.residuals[i]) {
            "is identically zero"
        } else {
            "depends on no unknown"
        };
        Diagnostic::error(
            l.span,
            format!(
                "mechanism `{}` is structurally singular: the {comp} equation of loop {} {what}",
                model.name.text,
                i / 2 + 1
            ),
        )
        .with_label(format!("{comp} component of this loop"))
    };
    let unknown = |k: usize, msg: &str| {
        let u = &model.unknowns[k];
        Diagnostic::error(
            u.name.span,
            format!("structurally singular: unknown `{}` {msg}", u.name.text),
        )
    };
    match e {
        StructureError::EmptyEquations(eqs) => eqs.into_iter().map(eq).collect(),
        StructureError::UnusedUnknowns(ks) => ks
            .into_iter()
            .map(|k| unknown(k, "appears in no equation"))
            .collect(),
        StructureError::Unmatched(ks) if ks.is_empty() => {
            vec![Diagnostic::error(
                model.name.span,
                "structurally singular: equations and unknowns cannot be matched",
            )]
        }
        StructureError::Unmatched(ks) => ks
            .into_iter()
            .map(|k| {
                unknown(
                    k,
                    "cannot be given an equation of its own (too many unknowns in too few loops)",
                )
            })
            .collect(),
    }
}
