//! Diagnostics: errors and warnings with byte spans into a source file, rendered as FILE:LINE:COLUMN with annotate-snippets.

use annotate_snippets::{AnnotationKind, Group, Level, Renderer, Snippet};

/// Byte range in the source text (start..end).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Span {
    pub start: usize,
    pub end: usize,
}

impl Span {
    /// A span from `start` to `end` (an `end` before `start` is raised to `start`).
    pub fn new(start: usize, end: usize) -> Span {
        Span {
            start,
            end: end.max(start),
        }
    }

    /// The smallest span covering both.
    pub fn join(self, other: Span) -> Span {
        Span::new(self.start.min(other.start), self.end.max(other.end))
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Severity {
    Error,
    Warning,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    pub severity: Severity,
    /// E.g. "undefined name `l7`".
    pub message: String,
    pub span: Span,
    /// Short text under the caret, may be empty.
    pub label: String,
    /// Extra `= note: ...` lines.
    pub notes: Vec<String>,
    /// Secondary spans drawn in the same excerpt (e.g. a first declaration), with their labels.
    pub related: Vec<(Span, String)>,
}

impl Diagnostic {
    pub fn error(span: Span, message: impl Into<String>) -> Self {
        Diagnostic {
            severity: Severity::Error,
            message: message.into(),
            span,
            label: String::new(),
            notes: Vec::new(),
            related: Vec::new(),
        }
    }

    pub fn warning(span: Span, message: impl Into<String>) -> Self {
        Diagnostic {
            severity: Severity::Warning,
            ..Self::error(span, message)
        }
    }

    pub fn with_label(mut self, label: impl Into<String>) -> Self {
        self.label = label.into();
        self
    }

    pub fn with_note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }

    /// Also draws `span` (in the same file) with `label`, as context.
    pub fn with_related(mut self, span: Span, label: impl Into<String>) -> Self {
        self.related.push((span, label.into()));
        self
    }

    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

/// A source file: display name (a path as the user gave it) and its text.
#[derive(Clone, Debug)]
pub struct SourceFile {
    pub name: String,
    pub text: String,
}

impl SourceFile {
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> Self {
        SourceFile {
            name: name.into(),
            text: text.into(),
        }
    }

    /// 1-based line and 1-based column (in characters) of a byte offset (clamped to the text;
    /// offsets inside a multi-byte char round down).
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let before = &self.text[..boundary(&self.text, offset, false)];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let line = before.bytes().filter(|&b| b == b'\n').count() + 1;
        (line, before[line_start..].chars().count() + 1)
    }

    /// `name:line:col` of a byte offset.
    pub fn location(&self, offset: usize) -> String {
        let (line, col) = self.line_col(offset);
        format!("{}:{line}:{col}", self.name)
    }
}

/// Render diagnostics, plain text (no ANSI colors), in the given order. Each diagnostic starts
/// with a one-line header `FILE:LINE:COLUMN: error: MESSAGE` (or `warning:`), followed by the
/// annotate-snippets rendering of the source excerpt (span underlined, label) and its notes.
/// Blank line between diagnostics. Never panics, whatever the spans.
pub fn render(file: &SourceFile, diagnostics: &[Diagnostic]) -> String {
    let parts: Vec<String> = diagnostics.iter().map(|d| render_one(file, d)).collect();
    parts.join("\n")
}

/// Same, one diagnostic (ends with a newline).
pub fn render_one(file: &SourceFile, diagnostic: &Diagnostic) -> String {
    let text = file.text.as_str();
    let (start, end) = snap(text, diagnostic.span);
    let related: Vec<((usize, usize), &str)> = diagnostic
        .related
        .iter()
        .map(|(s, l)| (snap(text, *s), l.as_str()))
        .collect();
    let lo = related.iter().map(|r| r.0.0).fold(start, usize::min);
    let hi = related.iter().map(|r| r.0.1).fold(end, usize::max);
    // Excerpt: the whole lines the spans touch (lines between them are folded by the renderer),
    // so rendering costs O(excerpt), not O(file).
    let first = text[..lo].rfind('\n').map_or(0, |i| i + 1);
    let last = text[hi..].find('\n').map_or(text.len(), |i| hi + i + 1);
    let line_start = file.line_col(first).0;

    let mut annotation = AnnotationKind::Primary.span(start - first..end - first);
    if !diagnostic.label.is_empty() {
        annotation = annotation.label(diagnostic.label.as_str());
    }
    let context = related.iter().map(|&((s, e), label)| {
        let a = AnnotationKind::Context.span(s - first..e - first);
        if label.is_empty() { a } else { a.label(label) }
    });
    let (level, name) = match diagnostic.severity {
        Severity::Error => (Level::ERROR, "error"),
        Severity::Warning => (Level::WARNING, "warning"),
    };
    let snippet = Snippet::source(&text[first..last])
        .line_start(line_start)
        .annotation(annotation)
        .annotations(context);
    let group = Group::with_level(level).element(snippet).elements(
        diagnostic
            .notes
            .iter()
            .map(|n| Level::NOTE.message(n.as_str())),
    );
    let body = Renderer::plain().render(&[group]);
    let header = format!("{}: {name}: {}", file.location(start), diagnostic.message);
    format!("{header}\n{body}\n")
}

/// `offset` clamped to the text and rounded down (or `up`) to a char boundary.
fn boundary(text: &str, offset: usize, up: bool) -> usize {
    let mut i = offset.min(text.len());
    while !text.is_char_boundary(i) {
        if up { i += 1 } else { i -= 1 }
    }
    i
}

/// Clamps a span to the text and to char boundaries (start rounds down, end up), and puts it
/// where it is drawn: trailing line breaks leave non-empty spans, an offset after the final line
/// break moves to the end of the last line, one between `\r` and `\n` moves before the `\r`.
fn snap(text: &str, span: Span) -> (usize, usize) {
    let mut start = boundary(text, span.start.min(span.end), false);
    let mut end = boundary(text, span.start.max(span.end), true);
    while end > start && text[..end].ends_with(['\n', '\r']) {
        end -= 1;
    }
    let empty = end == start;
    if start == text.len() && text.ends_with('\n') {
        start -= 1;
    }
    if text[..start].ends_with('\r') && text[start..].starts_with('\n') {
        start -= 1;
    }
    (start, if empty { start } else { end })
}

#[cfg(test)]
mod tests {
    use super::*;
    use expect_test::expect;

    const TOML: &str = "[links]\nl1 = 3.0\nl2 = foo + bar\n";

    /// Renders an error at `span` in `text`, checks the header is `m.toml:LINE:COL: error: bad`
    /// and (for single-line spans) the first `^` under source line LINE sits at column COL.
    fn check(text: &str, span: (usize, usize), line: usize, col: usize) -> String {
        let file = SourceFile::new("m.toml", text);
        let d = Diagnostic::error(Span::new(span.0, span.1), "bad").with_label("here");
        let out = render_one(&file, &d);
        let header = format!("m.toml:{line}:{col}: error: bad\n");
        assert!(out.starts_with(&header), "{text:?} {span:?}:\n{out}");
        let lines: Vec<&str> = out.lines().collect();
        let gutter = format!("{line} |");
        let i = lines
            .iter()
            .position(|l| l.trim_start().starts_with(&gutter));
        let i = i.unwrap_or_else(|| panic!("no line {line} in\n{out}"));
        let caret = lines[i + 1].find('^').unwrap() - lines[i].find('|').unwrap() - 1;
        let multi_line = out.contains("_^");
        assert!(multi_line || caret == col, "{text:?} {span:?}:\n{out}");
        out
    }

    #[test]
    fn spans_and_line_col() {
        assert_eq!(Span::new(3, 5).join(Span::new(1, 4)), Span::new(1, 5));
        let f = SourceFile::new("m.toml", "ab\ncé d");
        let cols: Vec<_> = [0, 3, 5, 7, 99].map(|o| f.line_col(o)).into();
        assert_eq!(cols, [(1, 1), (2, 1), (2, 2), (2, 4), (2, 5)]); // 5 is inside 'é'
        assert_eq!(f.location(6), "m.toml:2:3");
    }

    #[test]
    fn header_and_caret() {
        let file = SourceFile::new("mech/m.toml", TOML);
        let d = Diagnostic::error(Span::new(22, 25), "undefined name `foo`");
        let out = render_one(&file, &d.with_label("not defined").with_note("names: l1"));
        let header = "mech/m.toml:3:6: error: undefined name `foo`";
        assert_eq!(out.lines().next(), Some(header));
        assert!(out.contains("\n  |      ^^^ not defined\n"), "{out}");
        assert!(out.ends_with("\n  = note: names: l1\n"), "{out}");
        let w = render_one(&file, &Diagnostic::warning(Span::new(8, 10), "unused"));
        assert!(w.starts_with("mech/m.toml:2:1: warning: unused\n"), "{w}");
        assert!(w.ends_with("| ^^\n"), "{w}");
        check(TOML, (13, 16), 2, 6);
    }

    #[test]
    fn multi_line_span() {
        let out = check(TOML, (3, 25), 1, 4);
        assert!(out.contains("1 |   [links]\n  |  ____^\n2 | | l1"), "{out}");
        assert!(
            out.contains("3 | | l2 = foo + bar\n  | |________^ here"),
            "{out}"
        );
    }

    #[test]
    fn end_of_file_and_empty_file() {
        for span in [(32, 32), (40, 50), (31, 32), (31, 99)] {
            check(TOML, span, 3, 15);
        }
        check("abc", (3, 3), 1, 4);
        check("", (0, 0), 1, 1);
        check("", (5, 10), 1, 1);
    }

    #[test]
    fn crlf() {
        let text = "a = 1\r\nb = xx\r\n";
        for (span, col) in [((11, 13), 5), ((11, 15), 5), ((13, 15), 7), ((14, 14), 7)] {
            assert!(!check(text, span, 2, col).contains('\r'));
        }
        check(text, (15, 15), 2, 7);
        check(text, (4, 14), 1, 5);
    }

    #[test]
    fn non_ascii() {
        let text = "name = \"hébé\"\nl1 = ü + x\n";
        let (x, u) = (text.find('x').unwrap(), text.find('ü').unwrap());
        check(text, (x, x + 1), 2, 10);
        check(text, (u + 1, u + 1), 2, 6); // inside 'ü': rounds down
        check(text, (u + 1, u + 2), 2, 6);
        check(text, (9, 10), 1, 10); // 'é'
    }

    #[test]
    fn never_panics() {
        let texts = [
            "",
            "\n",
            "\r\n",
            "a",
            "é\r\nü\n\nx",
            "ab\n\n",
            "\t日本\r\n",
            TOML,
        ];
        for text in texts {
            let file = SourceFile::new("f", text);
            for s in 0..text.len() + 3 {
                for e in 0..text.len() + 3 {
                    let out =
                        render_one(&file, &Diagnostic::warning(Span { start: s, end: e }, "w"));
                    let header = out.lines().next().unwrap_or("");
                    let line = header.split(':').nth(1).unwrap_or("?");
                    let ok = header.ends_with(": warning: w") && out.contains(&format!("{line} |"));
                    assert!(ok, "{text:?} {s}..{e}:\n{out}");
                }
            }
        }
    }

    #[test]
    fn related_span_on_an_earlier_line() {
        let file = SourceFile::new("m.toml", "a = 1\nb = 2\nc = 3\nd = 4\na = 5\n");
        let d = Diagnostic::error(Span::new(24, 25), "`a` twice")
            .with_related(Span::new(0, 1), "first");
        let out = render_one(&file, &d);
        assert!(out.starts_with("m.toml:5:1: error: `a` twice\n"), "{out}");
        assert!(out.contains("1 | a = 1\n  | - first\n"), "{out}");
        assert!(out.contains("5 | a = 5\n  | ^\n"), "{out}");
        assert!(!out.contains("c = 3"), "lines between are folded:\n{out}");
        let far = Diagnostic::error(Span::new(2, 3), "x").with_related(Span::new(99, 120), "");
        assert!(render_one(&file, &far).starts_with("m.toml:1:3: error: x\n"));
    }

    #[test]
    fn snapshot_two_diagnostics() {
        let file = SourceFile::new("examples/fourbar.toml", TOML);
        let diags = [
            Diagnostic::error(Span::new(22, 25), "undefined name `foo`")
                .with_label("not a link, input or parameter")
                .with_note("known names: l1"),
            Diagnostic::warning(Span::new(8, 16), "link `l1` is never used").with_label("unused"),
        ];
        expect![[r#"
            examples/fourbar.toml:3:6: error: undefined name `foo`
              |
            3 | l2 = foo + bar
              |      ^^^ not a link, input or parameter
              |
              = note: known names: l1

            examples/fourbar.toml:2:1: warning: link `l1` is never used
              |
            2 | l1 = 3.0
              | ^^^^^^^^ unused
        "#]]
        .assert_eq(&render(&file, &diags));
    }
}
