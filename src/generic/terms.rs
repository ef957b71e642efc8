//! Generic engine, drawing structure (feature `runtime`): the terms of a loop or point
//! expression of the checked model, each with its sign and how it moves (`Motion`: ground, rigid
//! on a body, slider, other), read from the names it uses and their angle or length kinds.

use std::collections::HashMap;

use mechgen_codegen::{BinOp, Expr, ExprKind};
use mechgen_codegen::{Kind, Model, Symbol};

/// How a term moves.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Motion {
    /// Params only: a fixed vector of the ground.
    Ground,
    /// A fixed length turning with these angle coordinates (sorted ids): a body.
    Rigid(Vec<usize>),
    /// A length coordinate along a direction turning with these angle coordinates (none: a guide
    /// fixed to the ground).
    Slider { length: usize, guide: Vec<usize> },
    /// Anything else (several length coordinates): not drawn.
    Other,
}

/// One term of a loop or point with its sign.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Term {
    pub expr: Expr,
    pub sign: f64,
    pub motion: Motion,
}

/// The terms of a sum (a loop or a point) with their signs and motions. Coordinates are numbered
/// inputs first, then unknowns.
pub(super) fn terms_of(e: &Expr, model: &Model) -> Vec<Term> {
    let inputs = model.inputs.len();
    let kind_of = |id: usize| match id.checked_sub(inputs) {
        None => model.inputs.get(id).map_or(Kind::Angle, |c| c.kind),
        Some(k) => model.unknowns.get(k).map_or(Kind::Angle, |c| c.kind),
    };
    let mut terms = Vec::new();
    flatten(e, 1.0, &mut terms);
    terms
        .into_iter()
        .map(|(expr, sign)| {
            let (expr, inner) = outer_sign(expr);
            let mut ids = Vec::new();
            coordinates(&expr, &model.symbols, inputs, &mut ids);
            ids.sort_unstable();
            ids.dedup();
            let (lengths, angles): (Vec<usize>, Vec<usize>) =
                ids.into_iter().partition(|&id| kind_of(id) == Kind::Length);
            let motion = match lengths.as_slice() {
                [] if angles.is_empty() => Motion::Ground,
                [] => Motion::Rigid(angles),
                [length] => Motion::Slider {
                    length: *length,
                    guide: angles,
                },
                _ => Motion::Other,
            };
            Term {
                expr,
                sign: sign * inner,
                motion,
            }
        })
        .collect()
}

/// How well a walk through the moving terms of a loop with ground terms meets the ground: +1 for
/// each end link (or slider) whose tail is on the ground, −1 for each whose head is. A link that
/// turns about a ground pivot is written from it (`l1*e(q1)` from A), so a walk should leave the
/// ground forwards along its first term and come back backwards along its last.
pub(super) fn tails(moving: &[Term]) -> i32 {
    let drawn = |t: &Term| matches!(t.motion, Motion::Rigid(_) | Motion::Slider { .. });
    let score = |t: Option<&Term>, forward: bool| match t.filter(|t| drawn(t)) {
        Some(t) if (t.sign > 0.0) == forward => 1,
        Some(_) => -1,
        None => 0,
    };
    score(moving.first(), true) + score(moving.last(), false)
}

/// A term with the signs of its factors taken out (`-l1*e(q1)`, which Rust syntax reads as
/// `(-l1)*e(q1)`, is `l1*e(q1)` subtracted), so that a bar's sign says which way it is walked.
fn outer_sign(e: &Expr) -> (Expr, f64) {
    match &e.kind {
        ExprKind::Neg(a) => {
            let (x, s) = outer_sign(a);
            (x, -s)
        }
        ExprKind::Number(v) if *v < 0.0 => (
            Expr {
                kind: ExprKind::Number(-v),
                span: e.span,
            },
            -1.0,
        ),
        ExprKind::Binary(op @ (BinOp::Mul | BinOp::Div), a, b) => {
            let ((xa, sa), (xb, sb)) = (outer_sign(a), outer_sign(b));
            let kind = ExprKind::Binary(*op, Box::new(xa), Box::new(xb));
            (Expr { kind, span: e.span }, sa * sb)
        }
        _ => (e.clone(), 1.0),
    }
}

/// The terms of a sum with their signs (+1 added, −1 subtracted).
fn flatten<'e>(e: &'e Expr, sign: f64, out: &mut Vec<(&'e Expr, f64)>) {
    match &e.kind {
        ExprKind::Binary(BinOp::Add, a, b) => {
            flatten(a, sign, out);
            flatten(b, sign, out);
        }
        ExprKind::Binary(BinOp::Sub, a, b) => {
            flatten(a, sign, out);
            flatten(b, -sign, out);
        }
        ExprKind::Neg(a) => flatten(a, -sign, out),
        _ => out.push((e, sign)),
    }
}

/// The coordinates (inputs, then unknowns, as one id range) a term depends on.
fn coordinates(e: &Expr, symbols: &HashMap<String, Symbol>, inputs: usize, out: &mut Vec<usize>) {
    match &e.kind {
        ExprKind::Number(_) => {}
        ExprKind::Name(n) => match symbols.get(n) {
            Some(Symbol::Input(i)) => out.push(i.index()),
            Some(Symbol::Unknown(i)) => out.push(inputs + i.index()),
            _ => {}
        },
        ExprKind::Neg(a) => coordinates(a, symbols, inputs, out),
        ExprKind::Binary(_, a, b) => {
            coordinates(a, symbols, inputs, out);
            coordinates(b, symbols, inputs, out);
        }
        ExprKind::Call(_, args) => {
            for a in args {
                coordinates(a, symbols, inputs, out);
            }
        }
    }
}
