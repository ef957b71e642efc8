//! Part of stage 2 (semantics): a mechanism's bodies and gravity, its mass properties for
//! dynamics (the kinematics never read them). Each body's `angle` is a scalar and its `com` a
//! vector expression of the mechanism's variables (or the name of one of its points), under the
//! rules of points; `mass` and `inertia` are params-only values, finite and at least zero;
//! `gravity` is a vector expression of params.

use std::collections::HashMap;

use super::eval::eval;
use super::model::{Body, Centre, Symbol};
use super::resolved::{Resolved, Scalar, Vector};
use super::typing::{collect_names, type_of};
use crate::diagnostic::Diagnostic;
use crate::front::ast::{self, Expr, ExprKind};

/// What checking makes of a mechanism's bodies and gravity.
pub(super) struct Checked {
    pub bodies: Vec<Body>,
    pub gravity: Option<Vector>,
    /// Every body's and gravity's expression as written (which params they name).
    pub written: Vec<Expr>,
}

/// The bodies and gravity of `m`, checked against its names (`symbols`), its params' values and
/// its points; what is wrong goes to `diags` (that body or gravity is then left out).
pub(super) fn check_bodies(
    m: &ast::Mechanism,
    symbols: &HashMap<String, Symbol>,
    values: &HashMap<String, f64>,
    angles: &mut Vec<Symbol>,
    diags: &mut Vec<Diagnostic>,
) -> Checked {
    let mut bodies = Vec::new();
    let mut written = Vec::new();
    for b in &m.bodies {
        let name = &b.name.text;
        let angle =
            b.angle
                .as_ref()
                .and_then(|e| match type_of(e, symbols, false, angles, diags)? {
                    Resolved::Scalar(s) => Some(s),
                    Resolved::Vector(_) => {
                        diags.push(Diagnostic::error(
                            e.span,
                            format!("the `angle` of body `{name}` is a vector, not a scalar"),
                        ));
                        None
                    }
                });
        let com = b
            .com
            .as_ref()
            .and_then(|e| centre(e, m, name, symbols, angles, diags));
        let mass = b
            .mass
            .as_ref()
            .and_then(|e| amount(e, "mass", name, symbols, values, angles, diags));
        let inertia = match &b.inertia {
            Some(e) => amount(e, "inertia", name, symbols, values, angles, diags),
            None => Some((0.0, Scalar::Number(0.0))),
        };
        let exprs = [&b.angle, &b.mass, &b.com, &b.inertia];
        written.extend(exprs.into_iter().flatten().cloned());
        if let (Some(angle), Some(com), Some(mass), Some(inertia)) = (angle, com, mass, inertia) {
            bodies.push(Body {
                name: b.name.clone(),
                angle,
                com,
                mass: mass.0,
                inertia: inertia.0,
                mass_expr: mass.1,
                inertia_expr: inertia.1,
            });
        }
    }
    written.extend(m.gravity.iter().cloned());
    let gravity = m
        .gravity
        .as_ref()
        .and_then(|e| gravity(e, symbols, angles, diags));
    Checked {
        bodies,
        gravity,
        written,
    }
}

/// A body's centre of mass: one of the mechanism's points by name, or a vector expression.
fn centre(
    e: &Expr,
    m: &ast::Mechanism,
    body: &str,
    symbols: &HashMap<String, Symbol>,
    angles: &mut Vec<Symbol>,
    diags: &mut Vec<Diagnostic>,
) -> Option<Centre> {
    if let ExprKind::Name(n) = &e.kind {
        if let Some(i) = m.points.iter().position(|(p, _)| &p.text == n) {
            return Some(Centre::Point(i));
        }
        if !symbols.contains_key(n) {
            // A bare name may be a point's: say so, and suggest among points and symbols.
            let mut known: Vec<&str> = m.points.iter().map(|(p, _)| p.text.as_str()).collect();
            known.extend(symbols.keys().map(String::as_str));
            known.sort_unstable();
            let label = match crate::suggest::nearest(n, known) {
                Some(g) => format!("not a point, input, unknown or param: did you mean `{g}`?"),
                None => "not a point, input, unknown or param".to_string(),
            };
            diags.push(
                Diagnostic::error(
                    e.span,
                    format!("undefined name `{n}` in the `com` of body `{body}`"),
                )
                .with_label(label),
            );
            return None;
        }
    }
    match type_of(e, symbols, false, angles, diags)? {
        Resolved::Vector(v) => Some(Centre::Vector(v)),
        Resolved::Scalar(_) => {
            diags.push(
                Diagnostic::error(
                    e.span,
                    format!("the `com` of body `{body}` is a scalar, not a vector"),
                )
                .with_note("give a vector expression, e.g. `0.5*l1*e(q1)`, or a point's name"),
            );
            None
        }
    }
}

/// A body's mass or inertia: a params-only value, finite and at least zero at the file's params;
/// its value there and its expression (which follows the params at run time).
fn amount(
    e: &Expr,
    what: &str,
    body: &str,
    symbols: &HashMap<String, Symbol>,
    values: &HashMap<String, f64>,
    angles: &mut Vec<Symbol>,
    diags: &mut Vec<Diagnostic>,
) -> Option<(f64, Scalar)> {
    if let Some(n) = moving_name(e, symbols) {
        diags.push(
            Diagnostic::error(
                e.span,
                format!("the {what} of body `{body}` names `{n}`, which is not a param"),
            )
            .with_note(
                "a mass or inertia is a value of the params: it does not change with the motion",
            ),
        );
        return None;
    }
    let v = eval(e, values, &format!("the {what} of body `{body}`"), diags)?;
    if v < 0.0 {
        diags.push(
            Diagnostic::error(
                e.span,
                format!("the {what} of body `{body}` is negative ({v})"),
            )
            .with_note("masses and inertias are finite and at least zero"),
        );
        return None;
    }
    match type_of(e, symbols, true, angles, diags)? {
        Resolved::Scalar(s) => Some((v, s)),
        Resolved::Vector(_) => {
            diags.push(Diagnostic::error(
                e.span,
                format!("the {what} of body `{body}` is a vector, not a scalar"),
            ));
            None
        }
    }
}

/// Gravity: a vector expression of params only.
fn gravity(
    e: &Expr,
    symbols: &HashMap<String, Symbol>,
    angles: &mut Vec<Symbol>,
    diags: &mut Vec<Diagnostic>,
) -> Option<Vector> {
    if let Some(n) = moving_name(e, symbols) {
        diags.push(
            Diagnostic::error(
                e.span,
                format!("`gravity` names `{n}`, which is not a param"),
            )
            .with_note("gravity is a vector expression of params, e.g. `c(0, -g)`"),
        );
        return None;
    }
    match type_of(e, symbols, true, angles, diags)? {
        Resolved::Vector(v) => Some(v),
        Resolved::Scalar(_) => {
            diags.push(
                Diagnostic::error(e.span, "`gravity` is a scalar, not a vector")
                    .with_note("write it as a vector, e.g. `c(0, -9.81)`"),
            );
            None
        }
    }
}

/// The first input or unknown `e` names (what a params-only value may not name).
fn moving_name<'s>(e: &Expr, symbols: &'s HashMap<String, Symbol>) -> Option<&'s str> {
    let mut named = Vec::new();
    collect_names(e, symbols, &mut named);
    let s = named
        .iter()
        .find(|s| matches!(s, Symbol::Input(_) | Symbol::Unknown(_)))?;
    symbols
        .iter()
        .find(|(_, v)| *v == s)
        .map(|(k, _)| k.as_str())
}
