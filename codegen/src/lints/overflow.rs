//! Lint (after lowering and after planning): a constant of the DAG that is not finite cannot be
//! spelled in generated code, so the mechanism is rejected with the loop or point that holds it.

use crate::diagnostic::Diagnostic;
use crate::ir::dag::{Dag, Node, NodeId};
use crate::ir::lower::{Equation, System};
use crate::sema::model::Model;

/// A constant of the DAG that is not finite (`1e200*1e200`, `1/0` folded, or such a constant
/// differentiated): the generated code cannot spell it. Points at the first loop or point that
/// holds one, or at the mechanism when only derivatives do.
pub fn overflow(model: &Model, system: &System) -> Option<Diagnostic> {
    let dag = &system.dag;
    let whole: Vec<NodeId> = (0..dag.len() as u32).map(NodeId).collect();
    if !non_finite_constant(dag, &whole) {
        return None;
    }
    let message = "a constant of this expression is not finite (it overflows f64)";
    for (i, l) in model.loops.iter().enumerate() {
        let [x, y] = Equation::of_loop(i);
        if non_finite_constant(dag, &[system.residuals[x.0], system.residuals[y.0]]) {
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

/// Largest length magnitude whose square (a dyad's or a Jacobian's product of two lengths) stays
/// finite in f64 with room to spare, and the smallest whose square stays normal.
pub const LARGEST_LENGTH: f64 = 1e150;
pub const SMALLEST_LENGTH: f64 = 1e-150;

/// A warning for length params so large or so small that products of two lengths overflow or
/// underflow f64: the file is valid, but the solvers cannot assemble it (every row would fail).
pub fn magnitudes(model: &Model) -> Option<Diagnostic> {
    let bad: Vec<_> = model
        .params
        .iter()
        .chain(&model.derived)
        .filter(|p| {
            let a = p.value.abs();
            p.kind == crate::sema::model::Kind::Length
                && a.is_finite()
                && (a > LARGEST_LENGTH || (a > 0.0 && a < SMALLEST_LENGTH))
        })
        .collect();
    let first = bad.first()?;
    let list: Vec<String> = bad
        .iter()
        .map(|p| format!("`{}` = {:e}", p.name.text, p.value))
        .collect();
    let mut d = Diagnostic::warning(
        first.name.span,
        format!(
            "length params of `{}` whose squares overflow or underflow f64: {}",
            model.name.text,
            list.join(", ")
        ),
    )
    .with_label("squared by the solvers")
    .with_note(format!(
        "lengths between {SMALLEST_LENGTH:e} and {LARGEST_LENGTH:e} in the file's unit solve; \
         choose a unit that brings them there"
    ));
    for p in &bad[1..] {
        d = d.with_related(p.name.span, "here too");
    }
    Some(d)
}
