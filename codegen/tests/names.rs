//! Every name the file accepts becomes Rust the generator can emit: each Rust keyword (strict,
//! reserved and weak, as the Rust Reference lists them for the 2024 edition, written here and not
//! read from the crate) as a mechanism, param, unknown and point name is either refused by
//! `check` at FILE:LINE:COLUMN of the name, quoting it, or generates code that parses; and any
//! identifier (property test) that is accepted generates code that parses. The odd-files crate
//! compiles files with weak keywords and prelude names for names.

use mechgen_codegen::diagnostic::render;
use mechgen_codegen::{SourceFile, generate_source};
use proptest::prelude::*;

/// The Rust Reference, "Keywords" (2024 edition): strict, reserved, then weak.
const STRICT: &[&str] = &[
    "as", "break", "const", "continue", "crate", "else", "enum", "extern", "false", "fn", "for",
    "if", "impl", "in", "let", "loop", "match", "mod", "move", "mut", "pub", "ref", "return",
    "self", "Self", "static", "struct", "super", "trait", "true", "type", "unsafe", "use", "where",
    "while", "async", "await", "dyn",
];
const RESERVED: &[&str] = &[
    "abstract", "become", "box", "do", "final", "macro", "override", "priv", "typeof", "unsized",
    "virtual", "yield", "try", "gen",
];
const WEAK: &[&str] = &["macro_rules", "union", "raw", "safe"];

/// A four-bar whose mechanism, param `l4`, unknown `q3` and point `P` are named `m`, `p`, `u`
/// and `pt`, with each name's byte offset in the text (mechanism, param, unknown, point).
fn file(m: &str, p: &str, u: &str, pt: &str) -> (String, [usize; 4]) {
    let head = format!("[mechanism.{m}]\ninputs = [\"q1\"]\nunknowns = [\"q2\", \"");
    let mut text = head.clone();
    let at_u = text.len();
    text += &format!("{u}\"]\nloops = [\"l1*e(q1) + l2*e(q2) - ");
    text += &format!("{p} - l3*e({u})\"]\nparams = {{ l1 = 1.0, l2 = 3.0, l3 = 3.0, ");
    let at_p = text.len();
    text += &format!("{p} = 3.5 }}\nstart = {{ q1 = 0.0, q2 = 1.0, {u} = 2.0 }}\npoints = {{ ");
    let at_pt = text.len();
    text += &format!("{pt} = \"l1*e(q1)\" }}\n");
    (text, [11, at_p, at_u, at_pt])
}

/// Line and column (1-based) of a byte offset.
fn line_col(text: &str, at: usize) -> (usize, usize) {
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let col = at - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, col)
}

/// Generates `text`: Ok when the code parses as Rust, Err with the rendered diagnostics.
fn outcome(text: &str) -> Result<(), String> {
    let f = SourceFile::new("names.toml", text);
    match generate_source(&f) {
        Ok((code, _)) => {
            syn::parse_file(&code).map_err(|e| format!("generated code does not parse: {e}"))?;
            Ok(())
        }
        Err(diags) => Err(render(&f, &diags)),
    }
}

#[test]
fn every_keyword_is_refused_where_it_stands_or_generates() {
    let base = ["m", "l4", "q3", "P"];
    for word in STRICT.iter().chain(RESERVED).chain(WEAK) {
        for role in 0..4 {
            let mut names = base;
            names[role] = word;
            let (text, at) = file(names[0], names[1], names[2], names[3]);
            match outcome(&text) {
                Ok(()) => assert!(
                    WEAK.contains(word),
                    "`{word}` (role {role}) is a strict or reserved keyword, yet accepted"
                ),
                Err(e) => {
                    assert!(!e.contains("generated code does not parse"), "{word}: {e}");
                    assert!(
                        !WEAK.contains(word),
                        "weak keyword `{word}` (role {role}) refused:\n{e}"
                    );
                    let (line, col) = line_col(&text, at[role]);
                    assert!(
                        e.contains(&format!("names.toml:{line}:{col}: error"))
                            && e.contains(&format!("`{word}`")),
                        "`{word}` (role {role}) not refused at {line}:{col}:\n{e}\n{text}"
                    );
                }
            }
        }
    }
}

/// A file with `name` as its param (role 1), unknown (2) or point (3) generates code that parses
/// (names the generated code uses itself are renamed by the names table).
fn check_name(name: &str, role: usize) -> Result<(), TestCaseError> {
    let mut names = ["m", "l4", "q3", "P"];
    names[role] = name;
    let (text, _) = file(names[0], names[1], names[2], names[3]);
    if let Err(e) = outcome(&text) {
        prop_assert!(!e.contains("generated code does not parse"), "{name}: {e}");
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]
    /// Any identifier the file accepts as a param name generates code that parses. (Two tests of
    /// 32 cases, so that a test run's two threads share them.)
    #[test]
    fn every_accepted_param_name_generates(name in "[a-zA-Z_][a-zA-Z0-9_]{0,8}") {
        check_name(&name, 1)?;
    }

    /// Any identifier the file accepts as an unknown or point name generates code that parses.
    #[test]
    fn every_accepted_unknown_or_point_name_generates(
        name in "[a-zA-Z_][a-zA-Z0-9_]{0,8}",
        role in 2usize..4,
    ) {
        check_name(&name, role)?;
    }
}
