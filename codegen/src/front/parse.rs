//! Stage 1: mechanism file text → [`crate::front::ast::File`]. TOML with spans (toml's `DeTable`), each expression
//! string with `syn` (in `parse_expr.rs`), spans mapped back into the file so diagnostics point
//! inside the strings. After a TOML syntax error only the syntax errors are reported.

use std::borrow::Cow;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use crate::diagnostic::{Diagnostic, SourceFile, Span};
use crate::front::ast::{Body, Expr, ExprKind, File, Mechanism, Name, Scene};

/// TOML syntax errors reported: the first only (in the file's order). After it the parser's
/// recovery guesses, and what it reports next mostly follows from the first (one missing `]`
/// gave 59 errors); each rendering also costs the length of its lines.
pub const MAX_SYNTAX_ERRORS: usize = 1;

/// Most inputs, unknowns, loops, params or points a mechanism may have (variables are numbered
/// in 16 bits, and no linkage comes near).
pub const MAX_ITEMS: usize = 1000;

type Item<'a> = (&'a Spanned<Cow<'a, str>>, &'a Spanned<DeValue<'a>>);

/// Parses a whole file, collecting every error; what could be read is returned either way.
pub fn parse(file: &SourceFile) -> (File, Vec<Diagnostic>) {
    let mut p = Parser {
        text: &file.text,
        diags: Vec::new(),
    };
    let (root, errors) = DeTable::parse_recoverable(&file.text);
    // After a TOML syntax error the recovered tables are guesses: report every syntax error and
    // nothing built on the guesses.
    let syntax_errors = !errors.is_empty();
    let more = errors.len().saturating_sub(MAX_SYNTAX_ERRORS);
    // The parser's recovery reports follow-on errors out of order (an unterminated string is
    // reported after the errors it causes below it): the first in the file is the real one, so
    // sort by position before keeping the first few.
    let mut located: Vec<(Span, String)> = errors
        .into_iter()
        .map(|e| {
            let span = e
                .span()
                .map_or(Span::new(0, 0), |r| Span::new(r.start, r.end));
            (span, e.message().trim().to_string())
        })
        .collect();
    located.sort_by_key(|(span, _)| (span.start, span.end));
    for (span, message) in located.into_iter().take(MAX_SYNTAX_ERRORS) {
        let mut d = Diagnostic::error(span, format!("TOML syntax error: {message}"));
        if let Some(line) = unclosed_array_before(&file.text, span.start) {
            d = d.with_note(format!(
                "line {line} opens an array with `[` that it does not close: a missing `]` there?"
            ));
        }
        p.diags.push(d);
    }
    if let Some(last) = p.diags.last_mut().filter(|_| more > 0) {
        last.notes.push(format!(
            "{more} more TOML syntax errors follow (not shown): after a syntax error the parser \
             guesses, and most of what it reports next follows from the first; fix it and check \
             again"
        ));
    }
    let mut out = File {
        syntax_errors,
        ..File::default()
    };
    if syntax_errors {
        return (out, p.diags);
    }
    for (key, value) in sorted(root.get_ref()) {
        match key.get_ref().as_ref() {
            "mechanism" => {
                for (name, body) in p.table_entries(value, "mechanism") {
                    if let Some(m) = p.mechanism(name, body) {
                        out.mechanisms.push(m);
                    }
                }
            }
            "scene" => {
                for (name, body) in p.table_entries(value, "scene") {
                    if let Some(s) = p.scene(name, body) {
                        out.scenes.push(s);
                    }
                }
            }
            other => {
                p.unknown_key(key, other, "top level", &["mechanism", "scene"]);
            }
        }
    }
    (out, p.diags)
}

/// Table entries in file order (toml's map is sorted by key).
fn sorted<'a>(t: &'a DeTable<'a>) -> Vec<Item<'a>> {
    let mut v: Vec<Item<'a>> = t.iter().collect();
    v.sort_by_key(|(k, _)| k.span().start);
    v
}

pub(crate) fn span_of<T>(s: &Spanned<T>) -> Span {
    let r = s.span();
    Span::new(r.start, r.end)
}

fn name_of(key: &Spanned<Cow<'_, str>>) -> Name {
    Name {
        text: key.get_ref().to_string(),
        span: span_of(key),
    }
}

pub(crate) struct Parser<'t> {
    pub(crate) text: &'t str,
    pub(crate) diags: Vec<Diagnostic>,
}

impl Parser<'_> {
    pub(crate) fn error(&mut self, span: Span, msg: impl Into<String>) {
        self.diags.push(Diagnostic::error(span, msg));
    }

    /// Reports an unknown key, with the nearest of `keys` when it is a likely misspelling, which
    /// it returns.
    fn unknown_key<'k>(
        &mut self,
        key: &Spanned<Cow<'_, str>>,
        name: &str,
        place: &str,
        keys: &[&'k str],
    ) -> Option<&'k str> {
        let guess = crate::suggest::nearest(name, keys.iter().copied());
        let label = match guess {
            Some(g) => format!("not a key of the format: did you mean `{g}`?"),
            None => "not a key of the format".to_string(),
        };
        let expected = match keys {
            [] => String::new(),
            [one] => format!("`{one}`"),
            [init @ .., last] => format!("{} or {last}", init.join(", ")),
        };
        let d = Diagnostic::error(span_of(key), format!("unknown key `{name}` in {place}"))
            .with_label(label)
            .with_note(format!("expected {expected}"));
        self.diags.push(d);
        guess
    }

    fn table<'a>(&mut self, v: &'a Spanned<DeValue<'a>>, what: &str) -> Option<&'a DeTable<'a>> {
        match v.get_ref() {
            DeValue::Table(t) => Some(t),
            _ => {
                self.error(span_of(v), format!("`{what}` must be a table"));
                None
            }
        }
    }

    fn table_entries<'a>(&mut self, v: &'a Spanned<DeValue<'a>>, what: &str) -> Vec<Item<'a>> {
        self.table(v, what).map(sorted).unwrap_or_default()
    }

    fn mechanism(
        &mut self,
        key: &Spanned<Cow<'_, str>>,
        body: &Spanned<DeValue<'_>>,
    ) -> Option<Mechanism> {
        let name = name_of(key);
        let table = self.table(body, &format!("mechanism.{}", name.text))?;
        let before = self.diags.len();
        let mut m = Mechanism {
            name,
            description: None,
            inputs: vec![],
            unknowns: vec![],
            loops: vec![],
            loop_count: None,
            parse_errors: false,
            params: vec![],
            points: vec![],
            start: vec![],
            gravity: None,
            bodies: vec![],
        };
        let mut seen = [false; 3];
        const KEYS: [&str; 9] = [
            "description",
            "inputs",
            "unknowns",
            "loops",
            "params",
            "points",
            "start",
            "gravity",
            "bodies",
        ];
        for (k, v) in sorted(table) {
            let mut key = k.get_ref().as_ref();
            if !KEYS.contains(&key) {
                let place = format!("mechanism `{}`", m.name.text);
                // A misspelt key that no other entry spells right is read as the key it misspells,
                // so that one typo gives one error (not a missing key and every name undefined).
                match self.unknown_key(k, key, &place, &KEYS) {
                    Some(g) if !table.contains_key(g) => key = g,
                    _ => continue,
                }
            }
            match key {
                "description" => match v.get_ref() {
                    DeValue::String(s) => m.description = Some(s.to_string()),
                    _ => self.error(span_of(v), "`description` must be a string"),
                },
                "inputs" => (seen[0], m.inputs) = (true, self.names(v, "inputs")),
                "unknowns" => (seen[1], m.unknowns) = (true, self.names(v, "unknowns")),
                "loops" => {
                    seen[2] = true;
                    let items = self.array(v, "loops");
                    m.loop_count = Some(items.len());
                    m.loops = items.iter().filter_map(|e| self.string_expr(e)).collect();
                }
                "params" => m.params = self.assignments(v, "params", true),
                "points" => m.points = self.assignments(v, "points", false),
                "start" => m.start = self.assignments(v, "start", true),
                "gravity" => match v.get_ref() {
                    DeValue::String(_) => m.gravity = self.string_expr(v),
                    _ => self.error(
                        span_of(v),
                        "`gravity` must be a vector expression string, e.g. \"c(0, -9.81)\"",
                    ),
                },
                "bodies" => m.bodies = self.bodies(v, &m.name.text),
                _ => {}
            }
        }
        for (i, key) in ["inputs", "unknowns", "loops"].iter().enumerate() {
            if !seen[i] {
                let d = Diagnostic::error(
                    m.name.span,
                    format!("mechanism `{}` has no `{key}`", m.name.text),
                )
                .with_label(format!("`{key}` is required"));
                self.diags.push(d);
            }
        }
        let counts = [
            ("inputs", m.inputs.len()),
            ("unknowns", m.unknowns.len()),
            ("loops", m.loop_count.unwrap_or(0)),
            ("params", m.params.len()),
            ("points", m.points.len()),
        ];
        for (what, n) in counts.into_iter().filter(|c| c.1 > MAX_ITEMS) {
            self.error(
                m.name.span,
                format!(
                    "mechanism `{}` has {n} {what}, more than {MAX_ITEMS}",
                    m.name.text
                ),
            );
        }
        m.parse_errors = self.diags.len() > before;
        Some(m)
    }

    fn scene(&mut self, key: &Spanned<Cow<'_, str>>, body: &Spanned<DeValue<'_>>) -> Option<Scene> {
        let name = name_of(key);
        let table = self.table(body, &format!("scene.{}", name.text))?;
        let mut s = Scene {
            name,
            mechanism: None,
            outputs: vec![],
            order: None,
        };
        for (k, v) in sorted(table) {
            match k.get_ref().as_ref() {
                "mechanism" => match v.get_ref() {
                    DeValue::String(t) => {
                        s.mechanism = Some(Name {
                            text: t.to_string(),
                            span: span_of(v),
                        })
                    }
                    _ => self.error(
                        span_of(v),
                        "`mechanism` must be a string naming a mechanism",
                    ),
                },
                "outputs" => s.outputs = self.names(v, "outputs"),
                "order" => match v.get_ref() {
                    DeValue::Integer(i) => match int_value(i) {
                        Some(n) => s.order = Some((n, span_of(v))),
                        None => self.error(span_of(v), "`order` is out of range"),
                    },
                    _ => self.error(span_of(v), "`order` must be 0, 1 or 2"),
                },
                other => {
                    let place = format!("scene `{}`", s.name.text);
                    self.unknown_key(k, other, &place, &["mechanism", "outputs", "order"]);
                }
            }
        }
        if s.mechanism.is_none() {
            self.error(
                s.name.span,
                format!("scene `{}` has no `mechanism`", s.name.text),
            );
        }
        Some(s)
    }

    fn array<'a>(
        &mut self,
        v: &'a Spanned<DeValue<'a>>,
        what: &str,
    ) -> Vec<&'a Spanned<DeValue<'a>>> {
        match v.get_ref() {
            DeValue::Array(a) => a.iter().collect(),
            _ => {
                self.error(span_of(v), format!("`{what}` must be an array"));
                vec![]
            }
        }
    }

    fn names(&mut self, v: &Spanned<DeValue<'_>>, what: &str) -> Vec<Name> {
        let mut out = vec![];
        for item in self.array(v, what) {
            match item.get_ref() {
                DeValue::String(s) => {
                    let span = self.inner_span(span_of(item), s);
                    if is_identifier(s) {
                        out.push(Name {
                            text: s.to_string(),
                            span,
                        });
                    } else {
                        self.error(span, format!("`{s}` in `{what}` is not a valid name"));
                    }
                }
                _ => self.error(span_of(item), format!("`{what}` must hold names (strings)")),
            }
        }
        out
    }

    /// `[mechanism.NAME.bodies]`: one table per body with `angle`, `mass`, `com` (required) and
    /// `inertia`; numbers or expression strings for `mass` and `inertia`, strings for the others.
    fn bodies(&mut self, v: &Spanned<DeValue<'_>>, mechanism: &str) -> Vec<Body> {
        const BODY_KEYS: [&str; 4] = ["angle", "mass", "com", "inertia"];
        let Some(table) = self.table(v, "bodies") else {
            return vec![];
        };
        let mut out = vec![];
        for (k, v) in sorted(table) {
            let name = name_of(k);
            let Some(fields) = self.table(v, &format!("bodies.{}", name.text)) else {
                continue;
            };
            let mut body = Body {
                name,
                angle: None,
                mass: None,
                com: None,
                inertia: None,
            };
            for (fk, fv) in sorted(fields) {
                let key = fk.get_ref().as_ref();
                let place = format!("body `{}` of mechanism `{mechanism}`", body.name.text);
                let key = if BODY_KEYS.contains(&key) {
                    key
                } else {
                    match self.unknown_key(fk, key, &place, &BODY_KEYS) {
                        Some(g) if !fields.contains_key(g) => g,
                        _ => continue,
                    }
                };
                let what = format!("bodies.{}", body.name.text);
                let number_ok = matches!(key, "mass" | "inertia");
                let expr = match fv.get_ref() {
                    DeValue::String(_) => self.string_expr(fv),
                    DeValue::Integer(_) | DeValue::Float(_) if number_ok => self.number(
                        fv,
                        &Name {
                            text: key.to_string(),
                            span: span_of(fk),
                        },
                        &what,
                    ),
                    _ => {
                        let kind = if number_ok {
                            "a number or an expression string"
                        } else {
                            "an expression string"
                        };
                        self.error(span_of(fv), format!("`{key}` of {what} must be {kind}"));
                        None
                    }
                };
                match key {
                    "angle" => body.angle = expr,
                    "mass" => body.mass = expr,
                    "com" => body.com = expr,
                    _ => body.inertia = expr,
                }
            }
            for (key, given) in [
                ("angle", body.angle.is_some()),
                ("mass", body.mass.is_some()),
                ("com", body.com.is_some()),
            ] {
                if !given && !fields.contains_key(key) {
                    let d = Diagnostic::error(
                        body.name.span,
                        format!("body `{}` has no `{key}`", body.name.text),
                    )
                    .with_label(format!("`{key}` is required"));
                    self.diags.push(d);
                }
            }
            out.push(body);
        }
        out
    }

    /// `name = number | "expression"` tables (params, points, start).
    fn assignments(
        &mut self,
        v: &Spanned<DeValue<'_>>,
        what: &str,
        numbers: bool,
    ) -> Vec<(Name, Expr)> {
        let Some(table) = self.table(v, what) else {
            return vec![];
        };
        let mut out = vec![];
        for (k, v) in sorted(table) {
            let name = name_of(k);
            if !is_identifier(&name.text) {
                self.error(
                    name.span,
                    format!("`{}` in `{what}` is not a valid name", name.text),
                );
                continue;
            }
            let expr = match v.get_ref() {
                // A param or start value that does not parse stays declared (as 0, after the
                // error), so its uses do not add undefined-name errors.
                DeValue::String(_) if numbers => {
                    Some(self.string_expr(v).unwrap_or_else(|| Expr {
                        kind: ExprKind::Number(0.0),
                        span: span_of(v),
                    }))
                }
                DeValue::String(_) => self.string_expr(v),
                DeValue::Integer(_) | DeValue::Float(_) if numbers => self.number(v, &name, what),
                _ => {
                    let kind = if numbers {
                        "a number or an expression string"
                    } else {
                        "a vector expression string"
                    };
                    self.error(
                        span_of(v),
                        format!("`{}` in `{what}` must be {kind}", name.text),
                    );
                    None
                }
            };
            if let Some(e) = expr {
                out.push((name, e));
            }
        }
        out
    }

    fn number(&mut self, v: &Spanned<DeValue<'_>>, name: &Name, what: &str) -> Option<Expr> {
        let span = span_of(v);
        let value = match v.get_ref() {
            DeValue::Integer(i) => int_value(i).map(|n| n as f64),
            DeValue::Float(f) => f.as_str().replace('_', "").parse::<f64>().ok(),
            _ => None,
        };
        match value {
            Some(x) if x.is_finite() => Some(Expr {
                kind: ExprKind::Number(x),
                span,
            }),
            Some(_) => {
                // Reported here; the name stays declared so no undefined-name errors follow.
                let raw = self.text.get(span.start..span.end).unwrap_or("nan or inf");
                let d = Diagnostic::error(
                    span,
                    format!("`{}` in `{what}` is not a finite number: {raw}", name.text),
                )
                .with_label("not finite")
                .with_note("nan and inf are valid TOML but not valid values");
                self.diags.push(d);
                Some(Expr {
                    kind: ExprKind::Number(0.0),
                    span,
                })
            }
            None => {
                self.error(
                    span,
                    format!("`{}` in `{what}`: number out of range", name.text),
                );
                None
            }
        }
    }
}

fn is_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

fn int_value(i: &toml::de::DeInteger<'_>) -> Option<i64> {
    i64::from_str_radix(&i.as_str().replace('_', ""), i.radix()).ok()
}

/// The 1-based number of the last non-blank line before `offset` when it opens more arrays
/// (`[` outside strings, after a `=`) than it closes: the usual cause of a syntax error reported
/// at the start of the line after it.
fn unclosed_array_before(text: &str, offset: usize) -> Option<usize> {
    let before = text.get(..offset)?;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    // The error is at the start of its line (only blanks before it): look at the line above.
    if !before[line_start..].trim().is_empty() {
        return None;
    }
    let lines: Vec<&str> = before[..line_start].lines().collect();
    let (k, line) = lines
        .iter()
        .enumerate()
        .rev()
        .find(|(_, l)| !l.trim().is_empty())?;
    let value = line.split_once('=')?.1;
    // A line that ends open (`key = [`, an element and a comma) goes on below: not a missing `]`.
    if value.trim_end().ends_with(['[', ',']) {
        return None;
    }
    let (mut depth, mut quoted) = (0i32, None::<char>);
    for c in value.chars() {
        match (quoted, c) {
            (Some(q), c) if c == q => quoted = None,
            (Some(_), _) => {}
            (None, '"' | '\'') => quoted = Some(c),
            (None, '#') => break,
            (None, '[') => depth += 1,
            (None, ']') => depth -= 1,
            _ => {}
        }
    }
    (depth > 0).then_some(k + 1)
}
