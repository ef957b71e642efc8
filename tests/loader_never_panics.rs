//! Arbitrary text never panics the loader (`mechgen_codegen::analyze`, `mechgen::generic::load`)
//! nor the generator (`mechgen_codegen::generate_source`), and every diagnostic is rendered with a
//! `FILE:LINE:COL` header inside the file. Inputs: random strings, and (finding far more)
//! structure-aware mutations of the repository's mechanism files: characters and lines deleted,
//! duplicated, swapped or replaced, tokens inserted (`nan`, `1e308`, `*e(`, deep nesting, huge
//! numbers, TOML punctuation, keys, unicode). Files that still load are also run once through the
//! generic engine (no panic, no NaN in Ok answers).
//!
//! Bounded cases (`PROPTEST_CASES` overrides), fixed seed (`PROPTEST_RNG_SEED` overrides). The
//! unbounded version of this is the cargo-fuzz target in `fuzz/`.
#![cfg(feature = "runtime")]

use std::cell::Cell;
use std::sync::OnceLock;

use mechgen::{DynMechanism, InputMotion, PointMotion, SolveOptions, generic};
use mechgen_codegen::diagnostic::render_one;
use mechgen_codegen::{SourceFile, analyze, generate_source};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestRunner};

const NAME: &str = "fuzz.toml";

fn config(cases: u32) -> Config {
    let mut c = Config {
        failure_persistence: None,
        ..Config::default()
    };
    if std::env::var_os("PROPTEST_CASES").is_none() {
        c.cases = cases;
    }
    if c.rng_seed == RngSeed::Random {
        c.rng_seed = RngSeed::Fixed(0x6c6f_6164_6572);
    }
    c
}

/// The repository's mechanism files: the default one, the fixtures and the diagnostics
/// fixtures, in a fixed order.
fn seeds() -> &'static [String] {
    static SEEDS: OnceLock<Vec<String>> = OnceLock::new();
    SEEDS.get_or_init(|| {
        let root = env!("CARGO_MANIFEST_DIR");
        let mut paths = vec![std::path::PathBuf::from(format!("{root}/mechanism.toml"))];
        for dir in ["tests/fixtures", "tests/diagnostics"] {
            let mut found: Vec<_> = std::fs::read_dir(format!("{root}/{dir}"))
                .unwrap_or_else(|e| panic!("{dir}: {e}"))
                .map(|e| e.expect("directory entry").path())
                .filter(|p| p.extension().is_some_and(|e| e == "toml"))
                .collect();
            found.sort();
            paths.extend(found);
        }
        assert!(paths.len() > 10, "seed files found: {paths:?}");
        paths
            .iter()
            .map(|p| std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{p:?}: {e}")))
            .collect()
    })
}

/// How many of the first seeds load (the default file and the fixtures).
fn valid_seeds() -> usize {
    seeds()
        .iter()
        .take_while(|t| generic::load(NAME, t).is_ok())
        .count()
}

/// Pieces inserted or substituted by the mutations.
const TOKENS: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "+nan",
    "1e308",
    "-1e308",
    "1e309",
    "1e-320",
    "0",
    "0.0",
    "-0",
    "1/0",
    "0/0",
    "*e(",
    "e(",
    "c(",
    "deg(",
    "sqrt(",
    "sin(",
    "tan(",
    "pi",
    "q1",
    "q2",
    "l1",
    "alpha",
    "(",
    ")",
    "((((((((((((((((((((((((((((((((((((((((((((",
    "))))))))))))))))))))))))))))))))))))))))))))",
    "------------------------------------------------",
    "+",
    "-",
    "*",
    "/",
    ",",
    "=",
    "\"",
    "'",
    "\"\"\"",
    "'''",
    "\\",
    "\\u00e9",
    "\\uD800",
    "[",
    "]",
    "[[",
    "]]",
    "{",
    "}",
    "#",
    "\n",
    "\r\n",
    "\r",
    "\t",
    "\0",
    " ",
    "[mechanism.m]",
    "[[mechanism.m]]",
    "[mechanism.m.params]",
    "[scene.s]",
    "mechanism = \"m\"",
    "inputs = [\"q1\"]",
    "unknowns = []",
    "loops = []",
    "loops = [\"\"]",
    "params",
    "points",
    "start",
    "order = 99999999999999999999",
    "0x7fffffffffffffff",
    "1979-05-27T07:32:00Z",
    "true",
    "é",
    "日本",
    "👍",
    "\u{200b}",
    "\u{feff}",
    "\u{fffd}",
    "ﬀ",
];

/// One edit of a text; positions are fractions of its length (so they survive earlier edits).
#[derive(Clone, Debug)]
enum Mutation {
    Delete {
        at: f64,
        len: usize,
    },
    Duplicate {
        at: f64,
        len: usize,
    },
    Insert {
        at: f64,
        token: usize,
        times: usize,
    },
    Replace {
        at: f64,
        len: usize,
        token: usize,
    },
    SwapLines {
        a: f64,
        b: f64,
    },
    Char {
        at: f64,
        c: char,
    },
    /// Replaces a whole word (name, number, key) with a token: mostly keeps the TOML valid, so
    /// the checker, lowering, start check and emitter see the result.
    Word {
        at: f64,
        token: usize,
    },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let at = 0.0f64..1.0;
    let token = 0..TOKENS.len();
    prop_oneof![
        (at.clone(), 1usize..40).prop_map(|(at, len)| Mutation::Delete { at, len }),
        (at.clone(), 1usize..80).prop_map(|(at, len)| Mutation::Duplicate { at, len }),
        (
            at.clone(),
            token.clone(),
            prop_oneof![4 => Just(1usize), 1 => 2usize..5, 1 => Just(1000usize)]
        )
            .prop_map(|(at, token, times)| Mutation::Insert { at, token, times }),
        (at.clone(), 1usize..12, token).prop_map(|(at, len, token)| Mutation::Replace {
            at,
            len,
            token
        }),
        (at.clone(), at.clone()).prop_map(|(a, b)| Mutation::SwapLines { a, b }),
        (at.clone(), any::<char>()).prop_map(|(at, c)| Mutation::Char { at, c }),
        (at, 0..TOKENS.len()).prop_map(|(at, token)| Mutation::Word { at, token }),
    ]
}

/// The char boundary at fraction `at` of the text.
fn boundary(text: &str, at: f64) -> usize {
    let mut i = ((text.len() as f64) * at) as usize;
    i = i.min(text.len());
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// `len` chars from byte `start` (fewer at the end).
fn span_chars(text: &str, start: usize, len: usize) -> usize {
    text[start..]
        .char_indices()
        .nth(len)
        .map_or(text.len(), |(i, _)| start + i)
}

fn apply(text: &mut String, m: &Mutation) {
    match *m {
        Mutation::Delete { at, len } => {
            let s = boundary(text, at);
            let e = span_chars(text, s, len);
            text.replace_range(s..e, "");
        }
        Mutation::Duplicate { at, len } => {
            let s = boundary(text, at);
            let e = span_chars(text, s, len);
            let piece = text[s..e].to_string();
            text.insert_str(e, &piece);
        }
        Mutation::Insert { at, token, times } => {
            let s = boundary(text, at);
            text.insert_str(s, &TOKENS[token].repeat(times));
        }
        Mutation::Replace { at, len, token } => {
            let s = boundary(text, at);
            let e = span_chars(text, s, len);
            text.replace_range(s..e, TOKENS[token]);
        }
        Mutation::SwapLines { a, b } => {
            let mut lines: Vec<&str> = text.split('\n').collect();
            let n = lines.len();
            let (i, j) = (((n as f64) * a) as usize, ((n as f64) * b) as usize);
            lines.swap(i.min(n - 1), j.min(n - 1));
            *text = lines.join("\n");
        }
        Mutation::Char { at, c } => {
            let s = boundary(text, at);
            text.insert(s, c);
        }
        Mutation::Word { at, token } => {
            let word = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '.';
            let mut words = Vec::new();
            let mut start = None;
            for (i, c) in text.char_indices().chain([(text.len(), ' ')]) {
                match (start, word(c)) {
                    (None, true) => start = Some(i),
                    (Some(s), false) => {
                        words.push(s..i);
                        start = None;
                    }
                    _ => {}
                }
            }
            if !words.is_empty() {
                let i = (((words.len() as f64) * at) as usize).min(words.len() - 1);
                text.replace_range(words[i].clone(), TOKENS[token]);
            }
        }
    }
}

/// A seed file (the default file and the fixtures, which load, more often than the diagnostics
/// fixtures) with a few mutations (mostly one).
fn mutated() -> impl Strategy<Value = String> {
    let n = seeds().len();
    let seed = prop_oneof![1 => 0..n, 1 => 0..valid_seeds()];
    let count = prop_oneof![3 => Just(1usize), 2 => 2usize..4, 1 => 4usize..12];
    let edits = count.prop_flat_map(|k| proptest::collection::vec(mutation(), k));
    (seed, edits).prop_map(|(seed, ms)| {
        let mut text = seeds()[seed].clone();
        for m in &ms {
            apply(&mut text, m);
        }
        text
    })
}

/// Random text: any unicode, or the characters mechanism files are made of.
fn random_text() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<String>(),
        "[\\[\\]{}()\"'=,.#a-z0-9_+*/ \n-]{0,300}",
        "(\\[mechanism\\.[a-z]\\]\n|[a-z0-9]{1,4} = (\"[a-z0-9()*+ -]{0,20}\"|[0-9.e+-]{1,8}|\\[\"[a-z0-9]{1,3}\"\\])\n){0,20}",
    ]
}

/// How far a text got.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Outcome {
    /// TOML syntax errors.
    Syntax,
    /// Other errors.
    Errors,
    Loaded,
}

/// Everything one text goes through.
fn check_text(text: &str) -> Result<Outcome, TestCaseError> {
    let file = SourceFile::new(NAME, text);
    let (compiled, diagnostics) = analyze(&file);
    let has_errors = diagnostics.iter().any(|d| d.is_error());
    prop_assert!(
        has_errors || !compiled.is_empty() || text.trim().is_empty() || !diagnostics.is_empty(),
        "no mechanism and no diagnostic"
    );
    let lines: Vec<&str> = text.split('\n').collect();
    for d in &diagnostics {
        let out = render_one(&file, d);
        let header = out.lines().next().unwrap_or("");
        let severity = if d.is_error() { "error" } else { "warning" };
        let rest = header.strip_prefix(&format!("{NAME}:"));
        let parsed = rest.and_then(|r| {
            let mut parts = r.splitn(3, ':');
            let line: usize = parts.next()?.parse().ok()?;
            let col: usize = parts.next()?.parse().ok()?;
            let tail = parts.next()?;
            Some((line, col, tail))
        });
        let Some((line, col, tail)) = parsed else {
            return Err(TestCaseError::fail(format!("bad header {header:?}")));
        };
        prop_assert!(
            tail.starts_with(&format!(" {severity}: ")),
            "bad header {header:?}"
        );
        prop_assert!(
            (1..=lines.len()).contains(&line),
            "line {line} of {} in {header:?}",
            lines.len()
        );
        let width = lines[line - 1].chars().count();
        prop_assert!(
            (1..=width + 1).contains(&col),
            "column {col} of a {width}-char line in {header:?}"
        );
    }

    let loaded = generic::load(NAME, text);
    prop_assert_eq!(
        loaded.is_err(),
        has_errors,
        "the loader and analyze disagree"
    );
    if has_errors {
        // `generate_source` is `analyze` and an early return here.
        let syntax = diagnostics
            .iter()
            .any(|d| d.message.starts_with("TOML syntax error"));
        return Ok(if syntax {
            Outcome::Syntax
        } else {
            Outcome::Errors
        });
    }
    let generated = generate_source(&file);
    prop_assert!(
        generated
            .as_ref()
            .is_ok_and(|(code, _)| code.contains("pub mod")),
        "an analysed file does not generate: {:?}",
        generated.err()
    );
    let mechanisms = loaded.map_err(|e| TestCaseError::fail(e.to_string()))?;
    for g in &mechanisms {
        run_engine(g)?;
    }
    Ok(Outcome::Loaded)
}

/// One solve of a mechanism loaded from arbitrary text, from its `start`: no panic, no NaN in an
/// Ok answer.
fn run_engine(g: &generic::Generic) -> Result<(), TestCaseError> {
    let info = DynMechanism::<f64>::info(g);
    let x: Vec<f64> = info.inputs.iter().map(|c| c.start).collect();
    let mut q: Vec<f64> = info.unknowns.iter().map(|c| c.start).collect();
    let finite = |v: &[f64]| v.iter().all(|v| v.is_finite());
    if g.solve_position(&x, &mut q, &SolveOptions::default())
        .is_ok()
    {
        prop_assert!(finite(&q), "{}: position {q:?}", info.name);
    }
    let xd = vec![1.0; x.len()];
    let mut qd = vec![0.0; q.len()];
    if g.solve_velocity(&x, &q, &xd, &mut qd).is_ok() {
        prop_assert!(finite(&qd), "{}: velocity {qd:?}", info.name);
    }
    let mut qdd = vec![0.0; q.len()];
    if g.solve_acceleration(&x, &q, &xd, &qd, &xd, &mut qdd)
        .is_ok()
    {
        prop_assert!(finite(&qdd), "{}: acceleration {qdd:?}", info.name);
    }
    let mut points = vec![PointMotion::default(); info.points.len()];
    g.points(InputMotion::new(&x, &xd, &xd), &q, &qd, &qdd, &mut points)
        .map_err(|e| TestCaseError::fail(e.to_string()))?;
    g.chains(&x, &q)
        .map_err(|e| TestCaseError::fail(e.to_string()))?;
    g.sketch(&x, &q)
        .map_err(|e| TestCaseError::fail(e.to_string()))?;
    Ok(())
}

fn run(name: &str, cases: u32, strategy: impl Strategy<Value = String>) {
    let counts = Cell::new([0u32; 3]);
    let mut runner = TestRunner::new(config(cases));
    let result = runner.run(&strategy, |text| {
        let outcome = check_text(&text)?;
        let mut c = counts.get();
        c[outcome as usize] += 1;
        counts.set(c);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{name}: {e}");
    }
    let [syntax, errors, loaded] = counts.get();
    eprintln!(
        "{name}: {} texts: {syntax} TOML syntax errors, {errors} other errors, {loaded} loaded and generated",
        syntax + errors + loaded
    );
}

#[test]
fn seed_files_go_through() {
    // Every seed itself: loads iff it has no error; the default file loads.
    for text in seeds() {
        check_text(text).unwrap_or_else(|e| panic!("{e}"));
    }
    assert!(check_text(&seeds()[0]).is_ok_and(|o| o == Outcome::Loaded));
    assert!(valid_seeds() > 1, "the default file and the fixtures load");
}

// Two tests of 128 mutated files (each runner draws its own), so that a test run's two threads
// share them.
#[test]
fn mutated_mechanism_files_never_panic() {
    run("mutated files", 128, mutated());
}

#[test]
fn more_mutated_mechanism_files_never_panic() {
    run("mutated files", 128, mutated());
}

#[test]
fn random_text_never_panics() {
    run("random text", 256, random_text());
}
