//! Stage 2: [`ast::File`] → [`Model`]s. Resolves names, checks scalar/vector types, infers which
//! coordinates are angles, evaluates params and start values, validates scenes.

use std::collections::HashMap;

use super::builtin::Builtin;
use super::eval::{Shown, eval};
use super::model::{Coord, Kind, Model, Param, Scene, Symbol};
use super::resolved::{DerivedId, InputId, ParamId, Resolved, Scalar, UnknownId};
use super::typing::type_of;
use crate::diagnostic::{Diagnostic, Span};
use crate::front::ast::ExprKind;
use crate::front::ast::{self, Name};

/// The error for a name that is a Rust keyword.
fn keyword(name: &Name, what: &str) -> Option<Diagnostic> {
    crate::keywords::is_keyword(&name.text).then(|| {
        Diagnostic::error(
            name.span,
            format!("{what} `{}` is a Rust keyword", name.text),
        )
        .with_note("names become modules and fields of the generated Rust code")
    })
}

/// Checks every mechanism and scene; a mechanism with errors yields no model.
pub fn check(file: &ast::File, diags: &mut Vec<Diagnostic>) -> Vec<Model> {
    let mut models = Vec::new();
    if file.mechanisms.is_empty() && !file.syntax_errors && !diags.iter().any(|d| d.is_error()) {
        diags.push(
            Diagnostic::error(Span::new(0, 0), "no mechanism defined")
                .with_note("a file holds one or more `[mechanism.NAME]` tables"),
        );
    }
    let mut seen: HashMap<&str, Span> = HashMap::new();
    for m in &file.mechanisms {
        if let Some(prev) = seen.insert(&m.name.text, m.name.span) {
            diags.push(duplicate(&m.name, prev, "mechanism"));
            continue;
        }
        let before = diags.iter().filter(|d| d.is_error()).count();
        let model = check_mechanism(m, diags);
        if diags.iter().filter(|d| d.is_error()).count() == before && !m.parse_errors {
            models.push(model);
        }
    }
    let mut scene_names: HashMap<&str, Span> = HashMap::new();
    for s in &file.scenes {
        if let Some(prev) = scene_names.insert(&s.name.text, s.name.span) {
            diags.push(duplicate(&s.name, prev, "scene"));
        }
        if let Some(m) = file.mechanisms.iter().find(|m| m.name.text == s.name.text) {
            diags.push(
                Diagnostic::error(
                    s.name.span,
                    format!("scene `{}` has the name of a mechanism", s.name.text),
                )
                .with_label("scene name")
                .with_related(m.name.span, "mechanism declared here")
                .with_note("scenes and mechanisms become modules of one namespace: rename one"),
            );
        }
        if !is_snake_case(&s.name.text) {
            diags.push(
                Diagnostic::error(
                    s.name.span,
                    format!("scene name `{}` is not snake_case", s.name.text),
                )
                .with_note("it names the generated module; use lowercase letters, digits and `_`"),
            );
        }
        diags.extend(keyword(&s.name, "scene name"));
        check_scene(s, file, &mut models, diags);
    }
    models
}

fn reserved(name: &Name) -> Diagnostic {
    let all: Vec<_> = Builtin::ALL.iter().map(|b| b.name()).collect();
    let n = &name.text;
    Diagnostic::error(name.span, format!("`{n}` is a reserved name"))
        .with_label(format!(
            "the built-in `{n}`: a file cannot give it another meaning"
        ))
        .with_note(format!("built in: {}", all.join(", ")))
        .with_note(match n.as_str() {
            "c" => "name it otherwise: a link `c` as `lc` or `l3` (`c(x, y)` is the vector (x, y))"
                .to_string(),
            _ => format!("name it otherwise, e.g. `{n}1` or `l_{n}`"),
        })
}

fn duplicate(name: &Name, prev: Span, what: &str) -> Diagnostic {
    Diagnostic::error(
        name.span,
        format!("{what} `{}` is declared twice", name.text),
    )
    .with_label("second declaration")
    .with_related(prev, "first declared here")
}

fn check_mechanism(m: &ast::Mechanism, diags: &mut Vec<Diagnostic>) -> Model {
    let before = diags.len();
    if !is_snake_case(&m.name.text) {
        diags.push(
            Diagnostic::error(
                m.name.span,
                format!("mechanism name `{}` is not snake_case", m.name.text),
            )
            .with_note("it names the generated module; use lowercase letters, digits and `_`"),
        );
    }
    diags.extend(keyword(&m.name, "mechanism name"));
    let mut symbols: HashMap<String, Symbol> = HashMap::new();
    let mut first: HashMap<String, Span> = HashMap::new();
    let mut declare = |name: &Name, sym: Symbol, diags: &mut Vec<Diagnostic>| {
        // Still declared: its uses are not undefined.
        diags.extend(keyword(name, "name"));
        if Builtin::is_reserved(&name.text) {
            // Declared all the same, so that its uses are not also undefined names.
            diags.push(reserved(name));
            symbols.entry(name.text.clone()).or_insert(sym);
        } else if let Some(prev) = first.get(&name.text) {
            diags.push(duplicate(name, *prev, "name"));
        } else {
            first.insert(name.text.clone(), name.span);
            symbols.insert(name.text.clone(), sym);
        }
    };
    m.inputs
        .iter()
        .enumerate()
        .for_each(|(i, n)| declare(n, Symbol::Input(InputId::new(i)), diags));
    m.unknowns
        .iter()
        .enumerate()
        .for_each(|(i, n)| declare(n, Symbol::Unknown(UnknownId::new(i)), diags));

    // Params, in file order, each evaluated with the ones before it. A param whose expression
    // uses other params is derived; the others are the base params.
    let mut params: Vec<Param> = Vec::new();
    let mut derived: Vec<Param> = Vec::new();
    let mut declared: Vec<(String, Symbol)> = Vec::new();
    let mut values: HashMap<String, f64> = HashMap::new();
    for (name, expr) in &m.params {
        let mut uses = Vec::new();
        params_used(expr, &declared, &mut uses);
        let sym = if uses.is_empty() {
            Symbol::Param(ParamId::new(params.len()))
        } else {
            Symbol::Derived(DerivedId::new(derived.len()))
        };
        declare(name, sym, diags);
        declared.push((name.text.clone(), sym));
        let what = format!("param `{}`", name.text);
        let value = eval(expr, &values, &what, diags).unwrap_or(0.0);
        values.insert(name.text.clone(), value);
        let source = match expr.kind {
            ExprKind::Number(_) => None,
            _ => Some(format!("{}", Shown(expr))),
        };
        let param = Param {
            name: name.clone(),
            kind: Kind::Length,
            value,
            source,
            uses,
            expr: expr.clone(),
            // A plain number is its own tree; a param expression's is set with the loops'.
            resolved: Scalar::Number(value),
        };
        match sym {
            Symbol::Derived(_) => derived.push(param),
            _ => params.push(param),
        }
    }

    // Loops and points: types, names, angle inference.
    // Each expression is resolved where it is typed; one that does not resolve was reported
    // (`unresolved` counts them, so that a model is never built with a missing tree).
    let mut angles: Vec<Symbol> = Vec::new();
    let mut unresolved = 0;
    let mut loop_vectors = Vec::new();
    for l in &m.loops {
        match type_of(l, &symbols, false, &mut angles, diags) {
            Some(r) => loop_vectors.push(r.into_vector()),
            None => unresolved += 1,
        }
    }
    let mut point_vectors = Vec::new();
    for (name, p) in &m.points {
        if Builtin::is_reserved(&name.text) {
            diags.push(reserved(name));
        }
        diags.extend(keyword(name, "point name"));
        match type_of(p, &symbols, false, &mut angles, diags) {
            Some(Resolved::Vector(v)) => point_vectors.push(v),
            Some(Resolved::Scalar(_)) => diags.push(
                Diagnostic::error(
                    p.span,
                    format!("point `{}` is a scalar, not a vector", name.text),
                )
                .with_note("write it as a vector, e.g. `c(x, 0)` or `sE + c(0, yE)`"),
            ),
            None => unresolved += 1,
        }
    }
    let (mut next_param, mut next_derived) = (0, 0);
    for (name, e) in &m.params {
        let resolved =
            type_of(e, &symbols, true, &mut angles, diags).and_then(Resolved::into_scalar);
        let slot = match symbols.get(&name.text) {
            Some(Symbol::Derived(_)) if next_derived < derived.len() => {
                next_derived += 1;
                derived.get_mut(next_derived - 1)
            }
            _ if next_param < params.len() => {
                next_param += 1;
                params.get_mut(next_param - 1)
            }
            _ => None,
        };
        match (slot, resolved) {
            (Some(p), Some(r)) if p.name.text == name.text => p.resolved = r,
            _ => unresolved += 1,
        }
    }
    if unresolved > 0 && !diags[before..].iter().any(Diagnostic::is_error) {
        diags.push(Diagnostic::error(
            m.name.span,
            format!(
                "internal error: {unresolved} expression(s) of `{}` did not resolve",
                m.name.text
            ),
        ));
    }
    // Bodies and gravity (their expressions typed with the rest, so a param only they put in an
    // `e()` is an angle too).
    let masses = super::bodies::check_bodies(m, &symbols, &values, &mut angles, diags);
    let kind_of = |s: Symbol| {
        if angles.contains(&s) {
            Kind::Angle
        } else {
            Kind::Length
        }
    };
    for (i, p) in params.iter_mut().enumerate() {
        p.kind = kind_of(Symbol::Param(ParamId::new(i)));
    }
    for (j, p) in derived.iter_mut().enumerate() {
        p.kind = kind_of(Symbol::Derived(DerivedId::new(j)));
    }

    // The unknowns no loop names, by name (whatever else is wrong with the loops).
    let mut named = Vec::new();
    for e in &m.loops {
        super::typing::collect_names(e, &symbols, &mut named);
    }
    // Only when every loop parsed: a loop that did not may name the others.
    let in_no_loop: Vec<&Name> = m
        .unknowns
        .iter()
        .enumerate()
        .filter(|(i, _)| !m.parse_errors && !named.contains(&Symbol::Unknown(UnknownId::new(*i))))
        .map(|(_, n)| n)
        .collect();
    // Equations vs unknowns (a missing `loops` key is reported by the parser).
    let square = m
        .loop_count
        .is_none_or(|loops| 2 * loops == m.unknowns.len());
    if let Some(loops) = m.loop_count
        && !square
    {
        let span = m.loops.first().map_or(m.name.span, |l| l.span);
        let (s, es) = if loops == 1 { ("", "s") } else { ("s", "") };
        let unknowns = match m.unknowns.len() {
            1 => "1 unknown".to_string(),
            n => format!("{n} unknowns"),
        };
        let unused: Vec<String> = in_no_loop.iter().map(|n| format!("`{}`", n.text)).collect();
        let unused = match unused.len() {
            0 => String::new(),
            1 => format!(" ({} appears in no loop)", unused[0]),
            _ => format!(" ({} appear in no loop)", unused.join(", ")),
        };
        let mut d = Diagnostic::error(
            span,
            format!(
                "mechanism `{}` is not square: {loops} loop{s} give{es} {} equations for \
                 {unknowns}{unused}",
                m.name.text,
                2 * loops,
            ),
        )
        .with_note("each loop gives two scalar equations; list two unknowns per loop");
        for n in &in_no_loop {
            d = d.with_related(n.span, format!("`{}` appears in no loop", n.text));
        }
        diags.push(d);
    }
    if m.inputs.is_empty() {
        diags.push(Diagnostic::error(
            m.name.span,
            format!("mechanism `{}` has no inputs", m.name.text),
        ));
    }

    // Start configuration.
    let mut start: HashMap<&str, f64> = HashMap::new();
    for (name, e) in &m.start {
        match symbols.get(&name.text) {
            Some(Symbol::Input(_) | Symbol::Unknown(_)) => {
                let v = eval(e, &values, "a start value", diags).unwrap_or(0.0);
                if start.insert(&name.text, v).is_some() {
                    diags.push(duplicate(name, name.span, "start value"));
                }
            }
            Some(Symbol::Param(_) | Symbol::Derived(_)) => diags.push(Diagnostic::error(
                name.span,
                format!(
                    "`{}` is a param; `start` gives inputs and unknowns",
                    name.text
                ),
            )),
            None => {
                let coords = m.inputs.iter().chain(&m.unknowns).map(|c| c.text.as_str());
                let label = match crate::suggest::nearest(&name.text, coords) {
                    Some(g) => format!("undefined name: did you mean `{g}`?"),
                    None => "undefined name".to_string(),
                };
                diags.push(
                    Diagnostic::error(
                        name.span,
                        format!("`{}` in `start` is not an input or unknown", name.text),
                    )
                    .with_label(label),
                )
            }
        }
    }
    let coords = |names: &[Name], make: fn(usize) -> Symbol, diags: &mut Vec<Diagnostic>| {
        names
            .iter()
            .enumerate()
            .map(|(i, n)| {
                let value = start.get(n.text.as_str()).copied();
                if value.is_none() {
                    let mut d = Diagnostic::error(
                        n.span,
                        format!("missing `start` value for `{}`", n.text),
                    )
                    .with_note("`start` needs a value for every input and unknown");
                    if !m.start.is_empty() {
                        d = d.with_related(start_span(m), format!("no `{}` here", n.text));
                    }
                    diags.push(d);
                }
                Coord {
                    name: n.clone(),
                    kind: kind_of(make(i)),
                    start: value.unwrap_or(0.0),
                }
            })
            .collect::<Vec<_>>()
    };
    let inputs = coords(&m.inputs, |i| Symbol::Input(InputId::new(i)), diags);
    let unknowns = coords(&m.unknowns, |i| Symbol::Unknown(UnknownId::new(i)), diags);
    // A square file without other errors has its unknowns in no equation told by the structural
    // lint (on the DAG); after an error (an undefined name, say) it never runs, so say it here.
    if square && diags[before..].iter().any(Diagnostic::is_error) {
        for n in &in_no_loop {
            diags.push(
                Diagnostic::error(n.span, format!("unknown `{}` appears in no loop", n.text))
                    .with_label("no loop names it"),
            );
        }
    }
    Model {
        name: m.name.clone(),
        description: m.description.clone().unwrap_or_default(),
        inputs,
        unknowns,
        params,
        derived,
        loops: m.loops.clone(),
        points: m.points.clone(),
        loop_vectors,
        point_vectors,
        scenes: Vec::new(),
        symbols,
        start_span: start_span(m),
        bodies: masses.bodies,
        gravity: masses.gravity,
        dynamics_written: masses.written,
    }
}

/// From the first `start` key to the end of the last value.
fn start_span(m: &ast::Mechanism) -> Span {
    match (m.start.first(), m.start.last()) {
        (Some((first, _)), Some((_, last))) => first.span.join(last.span),
        _ => m.name.span,
    }
}

fn check_scene(
    s: &ast::Scene,
    file: &ast::File,
    models: &mut [Model],
    diags: &mut Vec<Diagnostic>,
) {
    let Some(mech) = &s.mechanism else { return };
    let Some(model) = models.iter_mut().find(|m| m.name.text == mech.text) else {
        if !file.mechanisms.iter().any(|m| m.name.text == mech.text) {
            diags.push(
                Diagnostic::error(
                    mech.span,
                    format!(
                        "scene `{}` uses undefined mechanism `{}`",
                        s.name.text, mech.text
                    ),
                )
                .with_label("no such mechanism"),
            );
        }
        return;
    };
    let order = match s.order {
        None => 2,
        Some((o @ 0..=2, _)) => o as u8,
        Some((o, span)) => {
            diags.push(
                Diagnostic::error(
                    span,
                    format!("scene `{}`: order {o} is not 0, 1 or 2", s.name.text),
                )
                .with_note("0: positions, 1: and velocities, 2: and accelerations"),
            );
            2
        }
    };
    let mut scene = Scene {
        name: s.name.clone(),
        unknowns: vec![],
        points: vec![],
        order,
    };
    for out in &s.outputs {
        if let Some(Symbol::Unknown(i)) = model.symbols.get(&out.text) {
            scene.unknowns.push(i.index());
        } else if let Some(i) = model.points.iter().position(|(n, _)| n.text == out.text) {
            scene.points.push(i);
        } else {
            diags.push(
                Diagnostic::error(
                    out.span,
                    format!(
                        "`{}` is not an unknown or point of `{}`",
                        out.text, mech.text
                    ),
                )
                .with_label("undefined output"),
            );
        }
    }
    model.scenes.push(scene);
}

/// The earlier params `e` names (each once, in order of first use).
fn params_used(e: &ast::Expr, earlier: &[(String, Symbol)], out: &mut Vec<Symbol>) {
    match &e.kind {
        ExprKind::Number(_) => {}
        ExprKind::Name(n) => {
            if let Some((_, sym)) = earlier.iter().find(|(name, _)| name == n)
                && !out.contains(sym)
            {
                out.push(*sym);
            }
        }
        ExprKind::Neg(x) => params_used(x, earlier, out),
        ExprKind::Binary(_, a, b) => {
            params_used(a, earlier, out);
            params_used(b, earlier, out);
        }
        ExprKind::Call(_, args) => args.iter().for_each(|a| params_used(a, earlier, out)),
    }
}

fn is_snake_case(s: &str) -> bool {
    s.chars().next().is_some_and(|c| c.is_ascii_lowercase())
        && s.chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
}
