//! Bad files: every error reported, each with FILE:LINE:COLUMN and the offending name.

use mechgen_codegen::diagnostic::render;
use mechgen_codegen::{SourceFile, compile};

fn errors(text: &str) -> String {
    let file = SourceFile::new("bad.toml", text);
    match compile(&file) {
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
    assert!(compile(&SourceFile::new("good.toml", GOOD)).is_ok());
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
