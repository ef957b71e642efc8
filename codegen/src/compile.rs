//! The driver: the stages in order, parse (`front`) → check (`sema`) → lower and differentiate
//! (`ir`) → lints → structure and plan (`analysis`) → emit. Each stage is a function of the one
//! before; this module only chains them and collects diagnostics.

pub(crate) use crate::analysis::Compiled;
use crate::analysis::{self, plan};
use crate::diagnostic::{Diagnostic, SourceFile};
use crate::ir::{differentiate, lower};
use crate::lints::{self, start};
use crate::sema::model::Model;
use crate::{front, sema};

/// Runs every stage up to code generation. Mechanisms with errors are left out; all diagnostics of
/// the file (errors and warnings) are returned, in file order.
pub fn analyze(file: &SourceFile) -> (Vec<Compiled>, Vec<Diagnostic>) {
    let (ast, mut diags) = front::parse::parse(file);
    let models = sema::check(&ast, &mut diags);
    let out = models
        .into_iter()
        .filter_map(|model| analyze_mechanism(model, &mut diags))
        .collect();
    diags.sort_by_key(|d| d.span.start);
    (out, diags)
}

/// Stages 3 to 5 for one checked mechanism, with the lints between them; `None` after an error.
fn analyze_mechanism(model: Model, diags: &mut Vec<Diagnostic>) -> Option<Compiled> {
    let mut system = lower::lower(&model);
    let (ni, nu) = (model.inputs.len(), model.unknowns.len());
    let derivatives = differentiate::differentiate(&mut system, ni, nu, model.params.len());
    let before = diags.len();
    lints::usage(&model, &system, diags);
    lints::degrees(&model, diags);
    let blocks = match analysis::blocks(&derivatives, &system.dag, nu) {
        Ok(blocks) => blocks,
        Err(e) => {
            diags.extend(lints::structure_diagnostics(&model, &system, e));
            return None;
        }
    };
    if diags[before..].iter().any(Diagnostic::is_error) {
        return None;
    }
    // Before the start check, which would only see non-finite loops.
    if let Some(d) = lints::overflow(&model, &system) {
        diags.push(d);
        return None;
    }
    diags.extend(start::degrees(&model));
    diags.extend(lints::magnitudes(&model));
    let start = start::check(&model, &system, &derivatives);
    let failed = start.as_ref().is_some_and(Diagnostic::is_error);
    diags.extend(start);
    if failed {
        return None;
    }
    diags.extend(start::singular(&model, &system, &derivatives));
    let blocks = plan::block_forms(&mut system, &model, &derivatives, &blocks);
    // Planning folds constants too.
    if let Some(d) = lints::overflow(&model, &system) {
        diags.push(d);
        return None;
    }
    let mut c = Compiled {
        model,
        system,
        derivatives,
        blocks,
        scenes: Vec::new(),
    };
    c.scenes = c
        .model
        .scenes
        .iter()
        .map(|s| {
            let parts = analysis::scene::Parts {
                model: &c.model,
                system: &c.system,
                derivatives: &c.derivatives,
                blocks: &c.blocks,
            };
            analysis::scene::plan_scene(&parts, s)
        })
        .collect();
    Some(c)
}
