//! Part of stage 2: params and start values evaluated in f64, and expressions printed back.

use std::collections::HashMap;

use crate::ast::{BinOp, Expr, ExprKind};
use crate::check::RESERVED;
use crate::diagnostic::{Diagnostic, Span};

pub fn undefined_function(name: &str, span: Span) -> Diagnostic {
    Diagnostic::error(span, format!("undefined function `{name}`"))
        .with_note("functions: e, c, deg, sin, cos, tan, sqrt")
}

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
        ExprKind::Name(n) if n == "pi" => std::f64::consts::PI,
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
        ExprKind::Call(f, args) if args.len() == 1 => {
            let x = go(&args[0])?;
            match f.text.as_str() {
                "deg" => x.to_radians(),
                "sin" => x.sin(),
                "cos" => x.cos(),
                "tan" => x.tan(),
                "sqrt" => x.sqrt(),
                "e" | "c" => {
                    diags.push(Diagnostic::error(
                        e.span,
                        format!("{what} must be a scalar, `{}` is not", f.text),
                    ));
                    return None;
                }
                other => {
                    diags.push(undefined_function(other, f.span));
                    return None;
                }
            }
        }
        ExprKind::Call(f, _) if !RESERVED.contains(&f.text.as_str()) => {
            diags.push(undefined_function(&f.text, f.span));
            return None;
        }
        ExprKind::Call(f, _) => {
            diags.push(Diagnostic::error(
                e.span,
                format!("{what} must be a scalar, `{}(…)` is not", f.text),
            ));
            return None;
        }
    })
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
