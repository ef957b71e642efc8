//! Part of stage 1: one expression string → [`Expr`] via `syn`, with spans mapped back into the
//! file (byte for byte when the string has no escapes) and errors that name what is wrong.

use quote::ToTokens as _;
use syn::spanned::Spanned as _;
use toml::Spanned;
use toml::de::DeValue;

use crate::diagnostic::{Diagnostic, Span};
use crate::front::ast::{BinOp, Expr, ExprKind, Name};
use crate::front::parse::{Parser, span_of};

impl Parser<'_> {
    /// Where the content of a string value starts, when the content is the raw text (no escapes).
    pub(crate) fn inner_span(&self, value: Span, content: &str) -> Span {
        let raw = self.text.get(value.start..value.end).unwrap_or("");
        let quote = if raw.starts_with("\"\"\"") || raw.starts_with("'''") {
            3
        } else {
            1
        };
        let start = value.start + quote;
        match self.text.get(start..start + content.len()) {
            Some(s) if s == content => Span::new(start, start + content.len()),
            _ => value,
        }
    }

    pub(crate) fn string_expr(&mut self, v: &Spanned<DeValue<'_>>) -> Option<Expr> {
        let DeValue::String(s) = v.get_ref() else {
            self.error(span_of(v), "expected an expression string");
            return None;
        };
        let value = span_of(v);
        let inner = self.inner_span(value, s);
        // Byte offsets inside the string map 1:1 to the file only when there are no escapes.
        let map = |r: std::ops::Range<usize>| {
            if inner == value {
                value
            } else {
                Span::new(inner.start + r.start, inner.start + r.end)
            }
        };
        if let Some((at, msg)) = unbalanced(s) {
            let d = Diagnostic::error(map(at..at + 1), format!("expression syntax error: {msg}"))
                .with_label(msg);
            self.diags.push(d);
            return None;
        }
        if let Some((at, msg, label)) = too_complex(s) {
            let end = at + s[at..].chars().next().map_or(0, char::len_utf8);
            let d = Diagnostic::error(map(at..end), msg)
                .with_label(label)
                .with_note("params can hold parts that do not depend on inputs or unknowns");
            self.diags.push(d);
            return None;
        }
        match syn::parse_str::<syn::Expr>(s) {
            Ok(e) => self.expr(&e, &map),
            Err(err) => {
                let at_end = err.to_string().starts_with("unexpected end of input");
                let end = s.trim_end().len();
                let (span, label) = if s.trim().is_empty() {
                    (value, "empty expression")
                } else if at_end {
                    (map(end..end), "the expression ends here")
                } else {
                    (
                        map(err.span().byte_range()),
                        "cannot parse this as an expression",
                    )
                };
                let d = Diagnostic::error(span, format!("expression syntax error: {err}"))
                    .with_label(label);
                self.diags.push(d);
                None
            }
        }
    }

    fn expr(
        &mut self,
        e: &syn::Expr,
        map: &dyn Fn(std::ops::Range<usize>) -> Span,
    ) -> Option<Expr> {
        let span = map(e.span().byte_range());
        let unsupported = |p: &mut Self, what: &str| {
            let d = Diagnostic::error(span, format!("unsupported expression: {what}"))
                .with_note("expressions use numbers, names, + - * /, parentheses and e(), c(), deg(), sin(), cos(), tan(), sqrt(), pi");
            p.diags.push(d);
            None
        };
        let kind = match e {
            syn::Expr::Lit(l) => {
                let digits = match &l.lit {
                    syn::Lit::Int(i) => i.base10_digits(),
                    syn::Lit::Float(f) => f.base10_digits(),
                    _ => return unsupported(self, "a literal that is not a number"),
                };
                match digits.parse::<f64>() {
                    Ok(x) if x.is_finite() => ExprKind::Number(x),
                    _ => {
                        let d = Diagnostic::error(
                            span,
                            format!("number `{digits}` is out of range (not a finite f64)"),
                        )
                        .with_label("too large");
                        self.diags.push(d);
                        return None;
                    }
                }
            }
            syn::Expr::Path(p) => match p.path.get_ident() {
                Some(id) if p.qself.is_none() => ExprKind::Name(id.to_string()),
                _ => return unsupported(self, "a path"),
            },
            syn::Expr::Paren(p) => return self.expr(&p.expr, map),
            syn::Expr::Group(g) => return self.expr(&g.expr, map),
            syn::Expr::Unary(u) => match u.op {
                syn::UnOp::Neg(_) => ExprKind::Neg(Box::new(self.expr(&u.expr, map)?)),
                _ => return unsupported(self, "a unary operator other than `-`"),
            },
            syn::Expr::Binary(b) => {
                let op = match &b.op {
                    syn::BinOp::Add(_) => BinOp::Add,
                    syn::BinOp::Sub(_) => BinOp::Sub,
                    syn::BinOp::Mul(_) => BinOp::Mul,
                    syn::BinOp::Div(_) => BinOp::Div,
                    other => {
                        let op = other.to_token_stream().to_string();
                        let d = Diagnostic::error(
                            map(other.span().byte_range()),
                            format!("unsupported operator `{op}`"),
                        )
                        .with_label("not one of + - * /")
                        .with_note("for a power, multiply (`l1*l1`) or use `sqrt`");
                        self.diags.push(d);
                        return None;
                    }
                };
                let (l, r) = (self.expr(&b.left, map), self.expr(&b.right, map));
                ExprKind::Binary(op, Box::new(l?), Box::new(r?))
            }
            syn::Expr::Call(c) => {
                let syn::Expr::Path(p) = &*c.func else {
                    return unsupported(self, "a call of a non-name");
                };
                let Some(id) = p.path.get_ident() else {
                    return unsupported(self, "a call of a path");
                };
                let callee = Name {
                    text: id.to_string(),
                    span: map(id.span().byte_range()),
                };
                let args: Vec<Option<Expr>> = c.args.iter().map(|a| self.expr(a, map)).collect();
                ExprKind::Call(callee, args.into_iter().collect::<Option<Vec<_>>>()?)
            }
            _ => return unsupported(self, "this kind of Rust expression"),
        };
        Some(Expr { kind, span })
    }
}

/// Deepest bracket nesting an expression may have. Parsing, checking and lowering recurse on the
/// syntax tree, whose depth is bounded by the nesting and the token count: these limits keep their
/// stack use small (a few hundred levels overflow a 2 MiB thread stack in a debug build).
pub const MAX_NESTING: usize = 32;
/// Most tokens an expression may have (a name or number is one token, each other character one).
/// The longest loop of the seed files has about 40.
pub const MAX_TOKENS: usize = 256;

/// Where an expression string exceeds [`MAX_NESTING`] or [`MAX_TOKENS`]: the byte offset of the
/// bracket or token past the limit, the message and the label.
fn too_complex(s: &str) -> Option<(usize, String, &'static str)> {
    let word = |c: char| c.is_alphanumeric() || c == '_';
    let (mut depth, mut tokens, mut in_word) = (0usize, 0usize, false);
    for (i, c) in s.char_indices() {
        let starts_token = !(c.is_whitespace() || in_word && word(c));
        in_word = word(c);
        if starts_token {
            tokens += 1;
            if tokens > MAX_TOKENS {
                let msg = format!("expression too long (more than {MAX_TOKENS} tokens)");
                return Some((i, msg, "one token too many"));
            }
        }
        match c {
            '(' | '[' | '{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    let msg = format!(
                        "expression nested too deeply (more than {MAX_NESTING} levels of brackets)"
                    );
                    return Some((i, msg, "too deep here"));
                }
            }
            ')' | ']' | '}' => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    None
}

/// The first unbalanced bracket of an expression string: its byte offset and what is wrong (syn
/// only says "cannot parse string into token stream").
fn unbalanced(s: &str) -> Option<(usize, String)> {
    let mut open: Vec<(usize, char)> = Vec::new();
    for (i, c) in s.char_indices() {
        match c {
            '(' | '[' | '{' => open.push((i, c)),
            ')' | ']' | '}' => {
                let want = match c {
                    ')' => '(',
                    ']' => '[',
                    _ => '{',
                };
                match open.pop() {
                    Some((_, o)) if o == want => {}
                    Some((j, o)) => return Some((j, format!("`{o}` closed by `{c}`"))),
                    None => return Some((i, format!("unmatched `{c}`"))),
                }
            }
            _ => {}
        }
    }
    open.pop().map(|(i, c)| (i, format!("unclosed `{c}`")))
}
