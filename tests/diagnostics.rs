//! One fixture per error kind in `tests/diagnostics/`, each with the snapshot of its messages
//! (`NAME.stderr`, refresh with `UPDATE_EXPECT=1 cargo test --test diagnostics`). Each fixture is
//! run through `mechgen check --file` (the snapshot is its stderr) and through the build's entry
//! point, `mechgen_codegen::Config` as mechgen's `build.rs` sets it, which must report exactly the
//! same text.

use std::path::{Path, PathBuf};
use std::process::Command;

use expect_test::expect_file;

const DIR: &str = "tests/diagnostics";

/// What a fixture must give: an error or only a warning, and the name its first message quotes.
#[derive(Clone, Copy)]
enum Expect {
    Error(Option<&'static str>),
    Warning(&'static str),
}
use Expect::{Error, Warning};

/// `mod NAME { check, build }` per fixture, plus the list that `every_fixture_is_tested` uses.
macro_rules! fixtures {
    ($($name:ident: $expect:expr,)*) => {
        const ALL: &[&str] = &[$(stringify!($name)),*];
        $(
            mod $name {
                use super::Expect::*;

                #[test]
                fn check() {
                    super::check(stringify!($name), $expect);
                }
                #[test]
                fn build() {
                    super::build(stringify!($name), $expect);
                }
            }
        )*
    };
}

fixtures! {
    toml_syntax: Error(None),
    unknown_key: Error(Some("colour")),
    undefined_name: Error(Some("l7")),
    reserved_name: Error(Some("pi")),
    duplicate_name: Error(Some("q3")),
    expression_syntax: Error(None),
    vector_times_vector: Error(None),
    non_finite: Error(Some("l2")),
    missing_start: Error(Some("q3")),
    not_square: Error(Some("four_bar")),
    zero_equation: Error(Some("four_bar")),
    unused_unknown: Error(Some("q3")),
    unmatched: Error(Some("b")),
    input_in_no_loop: Error(Some("q1")),
    misspelt_key: Error(Some("unknwons")),
    did_you_mean: Error(Some("lenght")),
    not_square_names: Error(Some("q4")),
    undefined_and_unused: Error(Some("q3")),
    reserved_c: Error(Some("c")),
    start_degrees: Warning("q1 = 30"),
    huge_lengths: Warning("l1"),
    unused_param: Warning("l5"),
    bad_start: Error(Some("four_bar")),
    start_off: Warning("four_bar"),
    empty_file: Error(None),
    e_of_vector: Error(Some("e")),
    scalar_point: Error(Some("C")),
    param_order: Error(Some("l4")),
    missing_key: Error(Some("four_bar")),
    mechanism_name: Error(Some("FourBar")),
    unsupported_expression: Error(None),
    scene_errors: Error(Some("D")),
    scene_name_clash: Error(Some("four_bar")),
    toml_cascade: Error(None),
    params_only_function: Error(Some("atan2")),
    many_errors: Error(Some("q3")),
    param_degrees: Warning("gam"),
    missing_bracket: Error(None),
    singular_start: Warning("rocker"),
    bodies_values: Error(Some("q1")),
    bodies_keys: Error(Some("mas")),
}

fn relative(name: &str) -> String {
    format!("{DIR}/{name}.toml")
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The rendered diagnostics of a `check` stderr: everything but the final `mechgen: …` summary.
fn diagnostics_part(stderr: &str) -> &str {
    let body = stderr.strip_suffix('\n').unwrap_or(stderr);
    match body.rfind('\n') {
        Some(i) if body[i + 1..].starts_with("mechgen: ") => &stderr[..i + 1],
        None if body.starts_with("mechgen: ") => "",
        _ => stderr,
    }
}

/// `FILE:LINE:COL: SEVERITY: MESSAGE` → (line, col, severity, message).
fn header<'a>(line: &'a str, file: &str) -> Option<(usize, usize, &'a str, &'a str)> {
    let rest = line.strip_prefix(file)?.strip_prefix(':')?;
    let mut parts = rest.splitn(4, ':');
    let l = parts.next()?.parse().ok()?;
    let c = parts.next()?.parse().ok()?;
    let severity = parts.next()?.trim();
    let message = parts.next()?.strip_prefix(' ')?;
    Some((l, c, severity, message))
}

/// Every diagnostic starts with a well-formed header at a real position; the first one has the
/// expected severity and quotes the expected name; the summary counts the errors.
fn check_text(name: &str, expect: Expect, text: &str) {
    let file = relative(name);
    let source = std::fs::read_to_string(root().join(&file)).expect("fixture");
    let headers: Vec<_> = text
        .lines()
        .filter(|l| l.starts_with(&file))
        .map(|l| header(l, &file).unwrap_or_else(|| panic!("bad header {l:?}")))
        .collect();
    assert!(!headers.is_empty(), "{name}: no diagnostic:\n{text}");
    assert!(
        text.starts_with(&file),
        "{name}: does not start with a header:\n{text}"
    );
    let lines: Vec<&str> = source.lines().collect();
    for &(l, c, _, _) in &headers {
        let len = lines.get(l - 1).map_or(0, |s| s.chars().count());
        assert!(
            l >= 1 && c >= 1 && c <= len + 1,
            "{name}: {l}:{c} is outside the file"
        );
    }
    let (_, _, severity, message) = headers[0];
    let quoted = match expect {
        Error(n) => {
            assert_eq!(severity, "error", "{name}:\n{text}");
            n
        }
        Warning(n) => {
            assert!(headers.iter().all(|h| h.2 == "warning"), "{name}:\n{text}");
            Some(n)
        }
    };
    if let Some(n) = quoted {
        assert!(
            message.contains(&format!("`{n}`")),
            "{name}: `{n}` not in {message:?}"
        );
    }
}

fn check(name: &str, expect: Expect) {
    let out = Command::new(env!("CARGO_BIN_EXE_mechgen"))
        .args(["check", "--file", &relative(name)])
        .current_dir(root())
        .output()
        .expect("run mechgen");
    let stderr = String::from_utf8(out.stderr).expect("utf-8");
    expect_file![format!("diagnostics/{name}.stderr")].assert_eq(&stderr);
    let diagnostics = diagnostics_part(&stderr);
    check_text(name, expect, diagnostics);
    let errors = diagnostics
        .lines()
        .filter(|l| l.contains(": error: "))
        .count();
    match expect {
        Error(_) => {
            assert!(!out.status.success(), "{name}: check succeeded");
            let summary = format!("mechgen: {}: {errors} error(s)\n", relative(name));
            assert!(stderr.ends_with(&summary), "{name}: no {summary:?}");
        }
        Warning(_) => {
            assert!(out.status.success(), "{name}: check failed:\n{stderr}");
            assert_eq!((errors, diagnostics), (0, stderr.as_str()), "{name}");
        }
    }
}

/// A fresh directory under the system's temp dir.
fn out_dir(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("mechgen-diagnostics-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn build(name: &str, expect: Expect) {
    let snapshot = root().join(format!("{DIR}/{name}.stderr"));
    let snapshot = std::fs::read_to_string(snapshot).expect("snapshot (run the check test first)");
    let dir = out_dir(name);
    // The configuration of mechgen's own `build.rs`.
    let result = mechgen_codegen::Config::new()
        .runtime_path("::mechgen")
        .env_override("MECHGEN_MECHANISM")
        .source_file("mechanism_source.rs")
        .generate_into(&root().join(relative(name)), &relative(name), &dir);
    let _ = std::fs::remove_dir_all(&dir);
    let text = match (result, expect) {
        (Err(rendered), Error(_)) => rendered,
        (Ok(generated), Warning(_)) => generated.warnings,
        (Ok(_), Error(_)) => panic!("{name}: the build accepted the file"),
        (Err(rendered), Warning(_)) => panic!("{name}: the build failed:\n{rendered}"),
    };
    assert_eq!(
        text,
        diagnostics_part(&snapshot),
        "{name}: build and check differ"
    );
    check_text(name, expect, &text);
}

/// Every fixture file is in the list above (and so tested), has a snapshot, and starts with a
/// comment saying what it tests.
#[test]
fn every_fixture_is_tested() {
    let mut files: Vec<String> = std::fs::read_dir(root().join(DIR))
        .expect("tests/diagnostics")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .collect();
    files.sort();
    for f in &files {
        let (stem, ext) = f.rsplit_once('.').unwrap_or((f, ""));
        assert!(ext == "toml" || ext == "stderr", "stray file {f}");
        assert!(ALL.contains(&stem), "{f} is not in the list of fixtures");
        if ext == "toml" {
            let text = std::fs::read_to_string(root().join(DIR).join(f)).expect("read");
            assert!(
                text.starts_with("# Tests: "),
                "{f}: no leading `# Tests:` comment"
            );
        }
    }
    assert_eq!(
        files.len(),
        2 * ALL.len(),
        "a fixture or snapshot is missing: {files:?}"
    );
}
