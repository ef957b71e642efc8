//! Lint (after the block structure): a structural error of the Jacobian's incidence, told as the
//! loops and unknowns of the file.

use crate::analysis::structure::StructureError;
use crate::diagnostic::Diagnostic;
use crate::ir::lower::{Equation, System};
use crate::sema::model::Model;

/// The diagnostics of a structurally singular mechanism.
pub fn structure_diagnostics(model: &Model, system: &System, e: StructureError) -> Vec<Diagnostic> {
    let eq = |i: usize| {
        let l = &model.loops[Equation(i).loop_index()];
        let equation = Equation(i);
        let comp = equation.axis().name();
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
                equation.loop_index() + 1
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
