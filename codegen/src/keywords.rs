//! Rust's keywords, one list: the strict and reserved keywords of the 2024 edition and `_`. Name
//! checking (`sema`) refuses them as names in the file, and the emitter's names table
//! (`emit::names`) never hands one out, since names become modules, fields and locals of the
//! generated code. Weak keywords (`union`, `raw`, `safe`, `macro_rules`) are identifiers wherever
//! generated code puts a name, so they are not in it.

/// The strict keywords, then the reserved ones, then `_`.
pub(crate) const RUST_KEYWORDS: [&str; 53] = [
    // strict
    "as", "async", "await", "break", "const", "continue", "crate", "dyn", "else", "enum", "extern",
    "false", "fn", "for", "if", "impl", "in", "let", "loop", "match", "mod", "move", "mut", "pub",
    "ref", "return", "self", "Self", "static", "struct", "super", "trait", "true", "type",
    "unsafe", "use", "where", "while", // reserved
    "abstract", "become", "box", "do", "final", "gen", "macro", "override", "priv", "try",
    "typeof", "unsized", "virtual", "yield", // not a name
    "_",
];

/// Whether `name` is one of [`RUST_KEYWORDS`].
pub(crate) fn is_keyword(name: &str) -> bool {
    RUST_KEYWORDS.contains(&name)
}
