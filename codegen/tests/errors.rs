//! Bad files: every error reported, each with FILE:LINE:COLUMN and the offending name.

use mechgen_codegen::diagnostic::render;
use mechgen_codegen::{SourceFile, generate_source};

fn errors(text: &str) -> String {
    let file = SourceFile::new("bad.toml", text);
    match generate_source(&file) {
        Ok(_) => panic!("file should be rejected"),
        Err(diags) => render(&file, &diags),
    }
}

const GOOD: &str = r#"[mechanism.m]
inputs = ["q1"]
unknowns = ["q2", "q3"]
loops = ["l1*e(q1) + l2*e(q2) - l4 - l3*e(q3)"]
params = { l1 = 1.0, l2 = 3.0, l3 = 3.0, l4 = 3.5 }
start = { q1 = 0.0, q2 = 1.0, q3 = 2.0 }
"#;

#[test]
fn the_good_file_compiles() {
    assert!(generate_source(&SourceFile::new("good.toml", GOOD)).is_ok());
}

#[test]
fn undefined_name_points_inside_the_expression_string() {
    let out = errors(&GOOD.replace("l3*e(q3)\"]", "l7*e(q3)\"]"));
    assert!(out.contains("bad.toml:4:"), "{out}");
    assert!(out.contains("undefined name `l7`"), "{out}");
    // column of `l7` inside the loop string: `loops = ["` is 10 chars, then the text before it.
    let col = 11 + "l1*e(q1) + l2*e(q2) - l4 - ".len();
    assert!(
        out.contains(&format!("bad.toml:4:{col}: error: undefined name `l7`")),
        "{out}"
    );
}

#[test]
fn all_errors_are_reported() {
    let text = GOOD
        .replace("l4 - l3", "l4 - l3*e(q3)*e(q2) - l3")
        .replace("l1 = 1.0", "l1 = nan")
        .replace("params = {", "colour = 1\nparams = {");
    let out = errors(&text);
    assert!(out.contains("vector × vector"), "{out}");
    assert!(
        out.contains("`l1` in `params` is not a finite number"),
        "{out}"
    );
    assert!(out.contains("unknown key `colour`"), "{out}");
    assert_eq!(out.matches(": error: ").count(), 3, "{out}");
}

#[test]
fn structural_problems_are_errors() {
    let out = errors(&GOOD.replace(
        "unknowns = [\"q2\", \"q3\"]",
        "unknowns = [\"q2\", \"q3\", \"q4\", \"q5\"]",
    ));
    assert!(out.contains("not square"), "{out}");
    let out = errors(&GOOD.replace("l3*e(q3)", "l3*e(q2)"));
    assert!(out.contains("unknown `q3` appears in no equation"), "{out}");
    let out = errors(&GOOD.replace("q2 = 1.0, ", ""));
    assert!(out.contains("missing `start` value for `q2`"), "{out}");
    let out = errors(&GOOD.replace("l1*e(q1)", "1.0"));
    assert!(out.contains("input `q1` appears in no loop"), "{out}");
}

#[test]
fn reserved_and_duplicate_names() {
    let out = errors(&GOOD.replace("unknowns = [\"q2\", \"q3\"]", "unknowns = [\"q2\", \"q1\"]"));
    assert!(out.contains("name `q1` is declared twice"), "{out}");
    let out = errors(&GOOD.replace("l4 = 3.5", "l4 = 3.5, pi = 3.0"));
    assert!(out.contains("`pi` is a reserved name"), "{out}");
}

#[test]
fn syntax_errors() {
    let out = errors(&GOOD.replace("l1*e(q1) +", "l1*e(q1) + +*"));
    assert!(out.contains("expression syntax error"), "{out}");
    let out = errors("[mechanism.m\ninputs = 3");
    assert!(out.contains("bad.toml:1:"), "{out}");
}

/// The loop of GOOD with `extra` appended to it.
fn with_loop_tail(extra: &str) -> String {
    GOOD.replace("l3*e(q3)\"]", &format!("l3*e(q3) + {extra}\"]"))
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    // Parsed on a test thread (2 MiB stack): syn and every later stage recurse on the tree.
    let n = 100_000;
    let out = errors(&with_loop_tail(&format!(
        "{}0{}",
        "(".repeat(n),
        ")".repeat(n)
    )));
    let col = 11 + "l1*e(q1) + l2*e(q2) - l4 - l3*e(q3) + ".len() + 32;
    let header = format!(
        "bad.toml:4:{col}: error: expression nested too deeply (more than 32 levels of brackets)"
    );
    assert!(out.starts_with(&header), "{}", &out[..out.len().min(500)]);
    assert_eq!(out.matches(": error: ").count(), 1);
    let out = errors(&with_loop_tail(&format!(
        "{}q2{}",
        "sin(".repeat(n),
        ")".repeat(n)
    )));
    assert!(out.contains("nested too deeply"), "{}", &out[..500]);
}

#[test]
fn long_operator_chains_are_an_error_not_a_stack_overflow() {
    for tail in [
        format!("{}0", "-".repeat(100_000)),
        format!("0{}", "+0".repeat(100_000)),
        format!("l1{}", "*l1".repeat(100_000)),
        format!("0{}", "?".repeat(100_000)),
        format!("0{}", " as f64".repeat(100_000)),
        format!("a{}", ".b".repeat(100_000)),
    ] {
        let out = errors(&with_loop_tail(&tail));
        assert!(
            out.contains("error: expression too long (more than 256 tokens)"),
            "{}",
            &out[..out.len().min(500)]
        );
    }
    // The same in a param (its value is evaluated recursively too).
    let out = errors(&GOOD.replace("l4 = 3.5", &format!("l4 = \"3.5{}\"", "+0".repeat(50_000))));
    assert!(out.contains("expression too long"), "{}", &out[..500]);
}

#[test]
fn nesting_and_length_within_the_limits_compile() {
    // 30 levels of brackets and a 150-operator chain: far below what overflows a 2 MiB stack.
    let tail = format!("{}0{}", "(".repeat(30), ")".repeat(30));
    assert!(generate_source(&SourceFile::new("ok.toml", with_loop_tail(&tail))).is_ok());
    let tail = format!("0{}", "-0".repeat(100));
    assert!(generate_source(&SourceFile::new("ok.toml", with_loop_tail(&tail))).is_ok());
    let tail = format!("{}0", "-".repeat(200));
    assert!(generate_source(&SourceFile::new("ok.toml", with_loop_tail(&tail))).is_ok());
}

#[test]
fn toml_syntax_errors_are_capped() {
    // Found by tests/loader_never_panics.rs: a pasted run of `mechanism = "m"` inside a string
    // gave 4005 recovery errors, each rendered with its 15000-char line (34 s in a debug build).
    let text = GOOD.replace(
        "l4 - l3",
        &format!("l4 - l3{}", "mechanism = \"m\"".repeat(1000)),
    );
    let t = std::time::Instant::now();
    let out = errors(&text);
    assert_eq!(
        out.matches(": error: TOML syntax error").count(),
        1,
        "{out}"
    );
    assert!(
        out.contains("more TOML syntax errors follow (not shown)"),
        "{out}"
    );
    assert!(t.elapsed().as_secs() < 5, "{:?}", t.elapsed());
}

#[test]
fn rust_keywords_are_not_names() {
    // Found by tests/loader_never_panics.rs: a param named `true` passed the checker and the
    // generated code did not parse ("internal error").
    let out = errors(&GOOD.replace("l4 = 3.5", "l4 = 3.5, true = 1.0"));
    assert!(
        out.contains("error: name `true` is a Rust keyword"),
        "{out}"
    );
    let out = errors(&GOOD.replace("\"q3\"", "\"type\"").replace("q3", "type"));
    assert!(
        out.contains("error: name `type` is a Rust keyword"),
        "{out}"
    );
    assert!(!out.contains("undefined"), "still declared: {out}");
    let out = errors(&format!("{GOOD}points = {{ _ = \"c(0, 0)\" }}\n"));
    assert!(
        out.contains("error: point name `_` is a Rust keyword"),
        "{out}"
    );
    let out = errors(&GOOD.replace("[mechanism.m]", "[mechanism.fn]"));
    assert!(
        out.contains("bad.toml:1:12: error: mechanism name `fn` is a Rust keyword"),
        "{out}"
    );
}

#[test]
fn non_finite_constants_are_errors_not_generator_panics() {
    // Found by tests/loader_never_panics.rs: `1e309` inside an expression string parsed as
    // infinity, passed the checker and panicked the emitter (proc-macro2's `f64_unsuffixed`).
    let out = errors(&with_loop_tail("1e309*e(q1)"));
    let col = 11 + "l1*e(q1) + l2*e(q2) - l4 - l3*e(q3) + ".len();
    let header = format!("bad.toml:4:{col}: error: number `1e309` is out of range");
    assert!(out.contains(&header), "{out}");
    // Finite literals whose product overflows once constants are folded.
    for tail in ["1e300*1e300*e(q1)", "e(1e200*1e200*q1)"] {
        let out = errors(&with_loop_tail(tail));
        assert!(
            out.contains("bad.toml:4:11: error: a constant of this expression is not finite"),
            "{out}"
        );
    }
    let out = errors(&format!("{GOOD}points = {{ P = \"1e200*1e200*e(q1)\" }}\n"));
    assert!(
        out.contains("bad.toml:7:17: error: a constant of this expression is not finite"),
        "{out}"
    );
    let out = errors(&GOOD.replace("l1 = 1.0", "l1 = \"1e400\""));
    assert!(out.contains("number `1e400` is out of range"), "{out}");
}

#[test]
fn too_many_params_is_an_error() {
    // Variables are numbered in 16 bits: param 65536 would alias param 0. Far below that, a
    // mechanism is limited to 1000 names of each kind.
    let many: Vec<String> = (0..1001).map(|i| format!("p{i} = 1.0")).collect();
    let text = GOOD.replace("l4 = 3.5", &format!("l4 = 3.5, {}", many.join(", ")));
    let out = errors(&text);
    assert!(
        out.contains("bad.toml:1:12: error: mechanism `m` has 1005 params, more than 1000"),
        "{}",
        &out[..out.len().min(500)]
    );
    assert_eq!(out.matches(": error: ").count(), 1);
}
