//! Lint (after lowering): inputs that drive nothing (error) and params that nothing uses
//! (warning), read off the DAG's variables and the params' own dependencies.

use crate::diagnostic::Diagnostic;
use crate::front::ast::{Expr, ExprKind};
use crate::ir::dag::Var;
use crate::ir::lower::System;
use crate::sema::model::{Model, Param, Symbol};
use crate::sema::resolved::{DerivedId, ParamId};

/// Inputs that drive nothing (error) and params that are never used (warning).
pub fn usage(model: &Model, system: &System, diags: &mut Vec<Diagnostic>) {
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
    // A param is used when the solvers read it (base params: in the DAG, where lowering put
    // the derived params' expressions too) or another param's expression names it.
    let mut named: Vec<Symbol> = model.derived.iter().flat_map(|d| d.uses.clone()).collect();
    for e in model
        .loops
        .iter()
        .chain(model.points.iter().map(|(_, e)| e))
        .chain(&model.dynamics_written)
    {
        names_in(e, model, &mut named);
    }
    for (i, p) in model.params.iter().enumerate() {
        if !used.contains(&Var::P(i as u16)) && !named.contains(&Symbol::Param(ParamId::new(i))) {
            diags.push(never_used(p));
        }
    }
    for (j, p) in model.derived.iter().enumerate() {
        if !named.contains(&Symbol::Derived(DerivedId::new(j))) {
            diags.push(never_used(p));
        }
    }
}

fn never_used(p: &Param) -> Diagnostic {
    Diagnostic::warning(
        p.name.span,
        format!("param `{}` is never used", p.name.text),
    )
}

/// The symbols an expression names.
fn names_in(e: &Expr, model: &Model, out: &mut Vec<Symbol>) {
    match &e.kind {
        ExprKind::Number(_) => {}
        ExprKind::Name(n) => out.extend(model.symbols.get(n).copied()),
        ExprKind::Neg(x) => names_in(x, model, out),
        ExprKind::Binary(_, a, b) => {
            names_in(a, model, out);
            names_in(b, model, out);
        }
        ExprKind::Call(_, args) => args.iter().for_each(|a| names_in(a, model, out)),
    }
}
