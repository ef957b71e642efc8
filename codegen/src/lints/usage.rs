//! Lint (after lowering): inputs that drive nothing (error) and params that nothing uses
//! (warning), read off the DAG's variables and the params' own dependencies.

use crate::diagnostic::Diagnostic;
use crate::ir::dag::Var;
use crate::ir::lower::System;
use crate::sema::model::Model;

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
    for (i, p) in model.params.iter().enumerate() {
        let by_param = model.params.iter().any(|q| q.uses.contains(&i));
        if !used.contains(&Var::P(i as u16)) && !by_param {
            diags.push(Diagnostic::warning(
                p.name.span,
                format!("param `{}` is never used", p.name.text),
            ));
        }
    }
}
