//! Part of stage 2: scalar/vector types of expressions, names resolved, and which coordinates are
//! angles (those under `e()` or a trigonometric function).

use std::collections::HashMap;

use super::builtin::{Builtin, undefined_function};
use super::eval::arity_error;
use super::model::Symbol;
use crate::diagnostic::{Diagnostic, Span};
use crate::front::ast::{BinOp, Expr, ExprKind};

/// Scalar or planar vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    Scalar,
    Vector,
}

fn undefined(name: &str, span: Span, symbols: &HashMap<String, Symbol>) -> Diagnostic {
    // The nearest defined name, first in sorted order among equally near ones (deterministic).
    let mut known: Vec<&str> = symbols.keys().map(String::as_str).collect();
    known.sort_unstable();
    let label = match crate::suggest::nearest(name, known) {
        Some(g) => format!("not an input, unknown or param: did you mean `{g}`?"),
        None => "not an input, unknown or param".to_string(),
    };
    Diagnostic::error(span, format!("undefined name `{name}`")).with_label(label)
}

/// Type of an expression; `None` after an error was reported. `params_only`: param expressions may
/// use only params. Coordinates under `e()` or a trig function are recorded in `angles`.
pub fn type_of(
    e: &Expr,
    symbols: &HashMap<String, Symbol>,
    params_only: bool,
    angles: &mut Vec<Symbol>,
    diags: &mut Vec<Diagnostic>,
) -> Option<Ty> {
    macro_rules! go {
        ($x:expr, $angles:expr) => {
            type_of($x, symbols, params_only, $angles, diags)
        };
    }
    match &e.kind {
        ExprKind::Number(_) => Some(Ty::Scalar),
        ExprKind::Name(n) if Builtin::from_name(n) == Some(Builtin::Pi) => Some(Ty::Scalar),
        ExprKind::Name(n) => match symbols.get(n) {
            Some(Symbol::Param(_) | Symbol::Derived(_)) => Some(Ty::Scalar),
            Some(_) if !params_only => Some(Ty::Scalar),
            Some(_) => {
                diags.push(Diagnostic::error(
                    e.span,
                    format!("param expression uses coordinate `{n}`"),
                ));
                None
            }
            None => {
                // Param expressions report their own undefined names during evaluation.
                if !params_only {
                    diags.push(undefined(n, e.span, symbols));
                }
                None
            }
        },
        ExprKind::Neg(x) => go!(x, angles),
        ExprKind::Binary(op, a, b) => {
            let (ta, tb) = (go!(a, angles), go!(b, angles));
            let (ta, tb) = (ta?, tb?);
            match (op, ta, tb) {
                (BinOp::Add | BinOp::Sub, Ty::Scalar, Ty::Scalar) => Some(Ty::Scalar),
                (BinOp::Add | BinOp::Sub, _, _) => Some(Ty::Vector),
                (BinOp::Mul | BinOp::Div, Ty::Scalar, Ty::Scalar) => Some(Ty::Scalar),
                (BinOp::Mul, Ty::Scalar, Ty::Vector)
                | (BinOp::Mul | BinOp::Div, Ty::Vector, Ty::Scalar) => Some(Ty::Vector),
                (BinOp::Mul, Ty::Vector, Ty::Vector) => {
                    diags.push(
                        Diagnostic::error(a.span, "vector × vector is not defined")
                            .with_label("a vector")
                            .with_related(b.span, "times a vector")
                            .with_note("multiply a vector by a scalar, e.g. `l1*e(q1)`"),
                    );
                    None
                }
                (BinOp::Div, _, Ty::Vector) => {
                    diags.push(Diagnostic::error(
                        b.span,
                        "division by a vector is not defined",
                    ));
                    None
                }
            }
        }
        ExprKind::Call(f, args) => {
            let builtin = Builtin::from_name(&f.text);
            let sig = match builtin.and_then(Builtin::signature) {
                Some(sig) if params_only || !builtin.is_some_and(Builtin::params_only) => sig,
                Some(_) => {
                    diags.push(
                        Diagnostic::error(
                            f.span,
                            format!("`{}` is allowed in params only", f.text),
                        )
                        .with_note(
                            "define a param with it and use the param here: loops and points \
                             are differentiated, params are fixed for a solve",
                        ),
                    );
                    return None;
                }
                // Param expressions report unknown functions during evaluation.
                None if params_only => return None,
                None => {
                    let other = f.text.as_str();
                    diags.push(if symbols.contains_key(other) || builtin.is_some() {
                        Diagnostic::error(f.span, format!("`{other}` is not a function"))
                            .with_note(format!("functions: {}", Builtin::function_list(false)))
                    } else {
                        undefined_function(other, f.span, false)
                    });
                    return None;
                }
            };
            let (arity, angle_arg) = (sig.arity, sig.angle_arguments);
            let result = if sig.vector_result {
                Ty::Vector
            } else {
                Ty::Scalar
            };
            if args.len() != arity {
                diags.push(arity_error(e, &f.text, arity, args.len()));
                return None;
            }
            let mut ok = true;
            for a in args {
                match go!(a, angles) {
                    Some(Ty::Scalar) => {}
                    Some(Ty::Vector) => {
                        diags.push(Diagnostic::error(
                            a.span,
                            format!("`{}` of a vector is not defined", f.text),
                        ));
                        ok = false;
                    }
                    None => ok = false,
                }
                if angle_arg {
                    collect_names(a, symbols, angles);
                }
            }
            ok.then_some(result)
        }
    }
}

/// The symbols `e` names, each once, in order of first use.
pub(crate) fn collect_names(e: &Expr, symbols: &HashMap<String, Symbol>, out: &mut Vec<Symbol>) {
    match &e.kind {
        ExprKind::Name(n) => {
            if let Some(s) = symbols.get(n)
                && !out.contains(s)
            {
                out.push(*s);
            }
        }
        ExprKind::Number(_) => {}
        ExprKind::Neg(x) => collect_names(x, symbols, out),
        ExprKind::Binary(_, a, b) => {
            collect_names(a, symbols, out);
            collect_names(b, symbols, out);
        }
        ExprKind::Call(_, args) => args.iter().for_each(|a| collect_names(a, symbols, out)),
    }
}
