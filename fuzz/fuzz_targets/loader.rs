//! Arbitrary UTF-8 through the loader (`analyze`, with every diagnostic rendered) and the
//! generator (`generate_source`): neither may panic, and every rendered diagnostic starts with a
//! `fuzz.toml:LINE:COL:` header inside the file. Run from the repository root:
//! `cargo +nightly fuzz run loader fuzz/seeds` (see the README).
#![no_main]

use libfuzzer_sys::fuzz_target;
use mechgen_codegen::diagnostic::render_one;
use mechgen_codegen::{SourceFile, analyze, generate_source};

fuzz_target!(|text: &str| {
    let file = SourceFile::new("fuzz.toml", text);
    let (_, diagnostics) = analyze(&file);
    let lines: Vec<&str> = text.split('\n').collect();
    for d in &diagnostics {
        let out = render_one(&file, d);
        let header = out.lines().next().unwrap_or("");
        let mut parts = header.splitn(4, ':');
        assert_eq!(parts.next(), Some("fuzz.toml"), "{header}");
        let line: usize = parts.next().and_then(|l| l.parse().ok()).expect(header);
        let col: usize = parts.next().and_then(|c| c.parse().ok()).expect(header);
        assert!((1..=lines.len()).contains(&line), "{header}");
        assert!(
            (1..=lines[line - 1].chars().count() + 1).contains(&col),
            "{header}"
        );
    }
    let errors = diagnostics.iter().any(|d| d.is_error());
    match generate_source(&file) {
        Ok((code, _)) => assert!(!errors && code.contains("@generated")),
        // Emission never fails on a file that analyses without errors.
        Err(diags) => assert!(errors && !diags.is_empty(), "{diags:?}"),
    }
});
