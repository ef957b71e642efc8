//! Snapshots of generated code. Update with `UPDATE_EXPECT=1 cargo test -p mechgen-codegen`.

use expect_test::expect_file;
use mechgen_codegen::{SourceFile, generate_source};

const SLIDER: &str = r#"
[mechanism.slider]
description = "Centred slider-crank: crank l1, rod l2, slider s on the x axis"
inputs = ["q1"]
unknowns = ["q2", "s"]
loops = ["l1*e(q1) + l2*e(q2) - s"]
params = { l1 = 1.0, l2 = 3.0 }
points = { B = "l1*e(q1)" }
start = { q1 = 0.0, q2 = 0.0, s = 4.0 }
"#;

#[test]
fn small_mechanism_snapshot() {
    let (code, warnings) =
        generate_source(&SourceFile::new("slider.toml", SLIDER)).expect("valid file");
    assert!(warnings.is_empty(), "{warnings:?}");
    expect_file!["snapshots/slider.rs"].assert_eq(&code);
}

/// The golden copy of the code generated from the default `mechanism.toml`, committed so it can be
/// read without building; this test keeps it fresh.
#[test]
fn golden_copy_of_default_mechanisms_is_fresh() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../mechanism.toml");
    let text = std::fs::read_to_string(path).expect("mechanism.toml");
    let (code, _) =
        generate_source(&SourceFile::new("mechanism.toml", text)).expect("valid default file");
    expect_file!["../../generated/mechanisms.rs"].assert_eq(&code);
}

#[test]
fn generation_is_deterministic() {
    let a = generate_source(&SourceFile::new("slider.toml", SLIDER))
        .expect("valid")
        .0;
    let b = generate_source(&SourceFile::new("slider.toml", SLIDER))
        .expect("valid")
        .0;
    assert_eq!(a, b);
}
