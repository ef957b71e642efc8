//! Part of stage 2: scalar/vector types of expressions, names resolved into the typed ids of the
//! resolved tree ([`super::resolved`]), and which coordinates are angles (those under `e()` or a
//! trigonometric function). One pass: what it accepts, it resolves.

use std::collections::HashMap;

use super::builtin::{Builtin, undefined_function};
use super::eval::arity_error;
use super::model::Symbol;
use super::resolved::{Fn1, Fn2, Op, Resolved, Scalar, Vector};
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

impl Resolved {
    pub fn ty(&self) -> Ty {
        match self {
            Resolved::Scalar(_) => Ty::Scalar,
            Resolved::Vector(_) => Ty::Vector,
        }
    }
}

/// The resolved tree of a symbol.
fn leaf(sym: Symbol) -> Scalar {
    match sym {
        Symbol::Input(i) => Scalar::Input(i),
        Symbol::Unknown(i) => Scalar::Unknown(i),
        Symbol::Param(i) => Scalar::Param(i),
        Symbol::Derived(j) => Scalar::Derived(j),
    }
}

/// A built-in call on resolved scalar arguments (arity checked by the caller).
fn call(builtin: Builtin, mut args: Vec<Scalar>) -> Option<Resolved> {
    let mut next = || args.pop().map(Box::new);
    let (b, a) = (next(), next());
    let one = |f: Fn1, a: Option<Box<Scalar>>| Some(Resolved::Scalar(Scalar::Call1(f, a?)));
    match builtin {
        Builtin::E => Some(Resolved::Vector(Vector::E(b?))),
        Builtin::C => Some(Resolved::Vector(Vector::C(a?, b?))),
        Builtin::Atan2 => Some(Resolved::Scalar(Scalar::Call2(Fn2::Atan2, a?, b?))),
        Builtin::Hypot => Some(Resolved::Scalar(Scalar::Call2(Fn2::Hypot, a?, b?))),
        Builtin::Sin => one(Fn1::Sin, b),
        Builtin::Cos => one(Fn1::Cos, b),
        Builtin::Tan => one(Fn1::Tan, b),
        Builtin::Sqrt => one(Fn1::Sqrt, b),
        Builtin::Deg => one(Fn1::Deg, b),
        Builtin::Asin => one(Fn1::Asin, b),
        Builtin::Acos => one(Fn1::Acos, b),
        Builtin::Atan => one(Fn1::Atan, b),
        Builtin::Abs => one(Fn1::Abs, b),
        // A constant, not a function: its call has no signature and was reported.
        Builtin::Pi => None,
    }
}

/// An expression typed and resolved; `None` after an error was reported. `params_only`: param
/// expressions may use only params. Coordinates under `e()` or a trig function are recorded in
/// `angles`.
pub fn type_of(
    e: &Expr,
    symbols: &HashMap<String, Symbol>,
    params_only: bool,
    angles: &mut Vec<Symbol>,
    diags: &mut Vec<Diagnostic>,
) -> Option<Resolved> {
    macro_rules! go {
        ($x:expr, $angles:expr) => {
            type_of($x, symbols, params_only, $angles, diags)
        };
    }
    match &e.kind {
        ExprKind::Number(x) => Some(Resolved::Scalar(Scalar::Number(*x))),
        ExprKind::Name(n) if Builtin::from_name(n) == Some(Builtin::Pi) => {
            Some(Resolved::Scalar(Scalar::Number(std::f64::consts::PI)))
        }
        ExprKind::Name(n) => match symbols.get(n) {
            Some(&sym @ (Symbol::Param(_) | Symbol::Derived(_))) => {
                Some(Resolved::Scalar(leaf(sym)))
            }
            Some(&sym) if !params_only => Some(Resolved::Scalar(leaf(sym))),
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
        ExprKind::Neg(x) => go!(x, angles).map(Resolved::neg),
        ExprKind::Binary(op, a, b) => {
            let (ra, rb) = (go!(a, angles), go!(b, angles));
            let (ra, rb) = (ra?, rb?);
            let bin = match op {
                BinOp::Add => Op::Add,
                BinOp::Sub => Op::Sub,
                BinOp::Mul => Op::Mul,
                BinOp::Div => Op::Div,
            };
            match (op, ra.ty(), rb.ty()) {
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
                _ => Resolved::binary(bin, ra, rb),
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
            if args.len() != arity {
                diags.push(arity_error(e, &f.text, arity, args.len()));
                return None;
            }
            let mut ok = true;
            let mut resolved = Vec::with_capacity(arity);
            for a in args {
                match go!(a, angles) {
                    Some(Resolved::Scalar(s)) => resolved.push(s),
                    Some(Resolved::Vector(_)) => {
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
            // A signature belongs to a function, so `builtin` is known here.
            if ok { call(builtin?, resolved) } else { None }
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
