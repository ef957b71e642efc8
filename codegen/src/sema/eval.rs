//! Part of stage 2 (semantics): params and start values evaluated in f64, and expressions printed
//! back.

use std::collections::HashMap;

use super::builtin::{Builtin, undefined_function};
use super::model::Model;
use crate::diagnostic::Diagnostic;
use crate::front::ast::{BinOp, Expr, ExprKind};

/// Evaluates a scalar expression of params (params, start values) in f64.
pub fn eval(
    e: &Expr,
    values: &HashMap<String, f64>,
    what: &str,
    diags: &mut Vec<Diagnostic>,
) -> Option<f64> {
    let v = eval_inner(e, values, what, diags)?;
    if v.is_finite() {
        Some(v)
    } else {
        diags.push(Diagnostic::error(
            e.span,
            format!("{what} evaluates to a non-finite value ({v})"),
        ));
        None
    }
}

fn eval_inner(
    e: &Expr,
    values: &HashMap<String, f64>,
    what: &str,
    diags: &mut Vec<Diagnostic>,
) -> Option<f64> {
    let mut go = |x: &Expr| eval_inner(x, values, what, diags);
    Some(match &e.kind {
        ExprKind::Number(x) => *x,
        ExprKind::Name(n) if Builtin::from_name(n) == Some(Builtin::Pi) => std::f64::consts::PI,
        ExprKind::Name(n) => match values.get(n) {
            Some(v) => *v,
            None => {
                diags.push(
                    Diagnostic::error(e.span, format!("undefined name `{n}` in {what}"))
                        .with_label("not a param defined before this one"),
                );
                return None;
            }
        },
        ExprKind::Neg(x) => -go(x)?,
        ExprKind::Binary(op, a, b) => {
            let (a, b) = (go(a), go(b));
            let (a, b) = (a?, b?);
            match op {
                BinOp::Add => a + b,
                BinOp::Sub => a - b,
                BinOp::Mul => a * b,
                BinOp::Div => a / b,
            }
        }
        ExprKind::Call(f, args) => {
            let builtin = Builtin::from_name(&f.text);
            let Some(sig) = builtin.and_then(Builtin::signature) else {
                diags.push(undefined_function(&f.text, f.span, true));
                return None;
            };
            if sig.vector_result {
                diags.push(Diagnostic::error(
                    e.span,
                    format!("{what} must be a scalar, `{}(…)` is not", f.text),
                ));
                return None;
            }
            if args.len() != sig.arity {
                diags.push(arity_error(e, &f.text, sig.arity, args.len()));
                return None;
            }
            let mut values = [0.0; 2];
            for (v, a) in values.iter_mut().zip(args) {
                *v = go(a)?;
            }
            builtin.and_then(|b| b.eval(&values[..sig.arity]))?
        }
    })
}

/// The values of `model`'s derived params for the base param values `base` (one per base param,
/// in file order), each from the values before it; the error names the first derived param
/// whose value is not finite (e.g. `acos` of a number past 1). For run-time readers of the
/// syntax (drawings); the solvers compute derived params inside their own expressions.
pub fn derived_values(model: &Model, base: &[f64]) -> Result<Vec<f64>, String> {
    let mut known: HashMap<String, f64> = model
        .params
        .iter()
        .zip(base)
        .map(|(p, v)| (p.name.text.clone(), *v))
        .collect();
    let mut out = Vec::with_capacity(model.derived.len());
    for p in &model.derived {
        let mut diags = Vec::new();
        let what = format!("param `{}`", p.name.text);
        let v = eval(&p.expr, &known, &what, &mut diags).ok_or_else(|| {
            diags.first().map_or_else(
                || format!("{what} cannot be evaluated"),
                |d| d.message.clone(),
            )
        })?;
        known.insert(p.name.text.clone(), v);
        out.push(v);
    }
    Ok(out)
}

/// The error for a call with the wrong number of arguments.
pub fn arity_error(e: &Expr, name: &str, arity: usize, got: usize) -> Diagnostic {
    Diagnostic::error(
        e.span,
        format!(
            "`{name}` takes {arity} argument{}, got {got}",
            if arity == 1 { "" } else { "s" },
        ),
    )
}

/// Prints an expression back in the file's syntax (fully parenthesised where it matters).
pub struct Shown<'a>(pub &'a Expr);

impl std::fmt::Display for Shown<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.0.kind {
            ExprKind::Number(x) => write!(f, "{x:?}"),
            ExprKind::Name(n) => write!(f, "{n}"),
            ExprKind::Neg(x) => write!(f, "-{}", Shown(x)),
            ExprKind::Binary(op, a, b) => {
                let o = match op {
                    BinOp::Add => "+",
                    BinOp::Sub => "-",
                    BinOp::Mul => "*",
                    BinOp::Div => "/",
                };
                write!(f, "({} {o} {})", Shown(a), Shown(b))
            }
            ExprKind::Call(name, args) => {
                write!(f, "{}(", name.text)?;
                for (i, a) in args.iter().enumerate() {
                    if i > 0 {
                        write!(f, ", ")?;
                    }
                    write!(f, "{}", Shown(a))?;
                }
                write!(f, ")")
            }
        }
    }
}
