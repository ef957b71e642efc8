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

/// The slider-crank's blocks are [q2] (loop y) then [s] (loop x); scene `rod` reads q2 only, at
/// order 0: its solver is block 0 alone (a closed form), no factorization, no rate, no point.
const SLIDER_SCENES: &str = r#"
[mechanism.slider]
description = "Centred slider-crank: crank l1, rod l2, slider s on the x axis"
inputs = ["q1"]
unknowns = ["q2", "s"]
loops = ["l1*e(q1) + l2*e(q2) - s"]
params = { l1 = 1.0, l2 = 3.0 }
points = { B = "l1*e(q1)", C = "s + c(0, 0)", M = "l1*e(q1) + 0.5*l2*e(q2)" }
start = { q1 = 0.0, q2 = 0.0, s = 4.0 }

[scene.rod_middle]
mechanism = "slider"
outputs = ["M"]
order = 0

[scene.rod]
mechanism = "slider"
outputs = ["q2"]
order = 0

[scene.crank_pin]
mechanism = "slider"
outputs = ["B"]
order = 1
"#;

/// The lines from the first one containing `from` up to (not including) the next one containing `to`.
fn between<'a>(code: &'a str, from: &str, to: &str) -> Vec<&'a str> {
    code.lines()
        .skip_while(|l| !l.contains(from))
        .take_while(|l| !l.contains(to))
        .collect()
}

#[test]
fn pruned_scene_snapshot() {
    let (code, warnings) =
        generate_source(&SourceFile::new("slider.toml", SLIDER_SCENES)).expect("valid file");
    assert!(warnings.is_empty(), "{warnings:?}");
    let rod = between(&code, "fn scene_rod_motion(", "fn scene_rod_solve(").join("\n");
    let pin = between(
        &code,
        "fn scene_crank_pin_motion(",
        "fn scene_crank_pin_solve(",
    )
    .join("\n");
    let full = between(&code, "fn motion_cached(", "fn scene_rod_motion(").join("\n");
    // The full body solves both blocks, factors, and computes both points; the full module shows
    // what the scenes leave out.
    for (body, needle) in [
        (&full, "newton_block(\n"),
        (&full, "factor_block"),
        (&full, "p_l2"),
    ] {
        assert!(body.contains(needle), "full body lacks {needle}");
    }
    // `rod`: block 0 only (its closed form), no block 1, no factorization, no points' expressions.
    assert!(rod.contains("Block 0: closed form"), "{rod}");
    assert!(!rod.contains("Block 1"), "{rod}");
    assert!(
        !rod.contains("factor_block") && !rod.contains("lu.solve"),
        "{rod}"
    );
    assert!(!rod.contains("v_q1_d") && !rod.contains("xd[0]"), "{rod}");
    assert!(rod.contains("Rates<T, 2, 0>"), "no point: {rod}");
    assert!(!rod.contains("PointMotion {"), "no point: {rod}");
    // `crank_pin`: B reads only the input, so no block at all; velocities but no accelerations.
    assert!(!pin.contains("Block "), "{pin}");
    assert!(pin.contains("xd[0]") && !pin.contains("xdd[0]"), "{pin}");
    assert!(pin.contains("Rates<T, 2, 1>"), "one point: {pin}");
    // `rod` reads q2 itself: its kernel computes the angle. `rod_middle` reads only q2's sine
    // and cosine (M is on the rod): its tick skips the angle, its `solve` computes it.
    assert!(!rod.contains("every_angle"), "{rod}");
    let middle = between(
        &code,
        "fn scene_rod_middle_motion(",
        "fn scene_rod_middle_solve(",
    )
    .join("\n");
    let squeezed = |s: &str| s.split_whitespace().collect::<String>();
    assert!(middle.contains("every_angle: bool"), "{middle}");
    assert!(
        squeezed(&middle).contains("report,every_angle,)?;"),
        "{middle}"
    );
    let calls = between(
        &code,
        "fn scene_rod_middle_solve(",
        "pub fn solve_position(",
    )
    .join("\n");
    assert!(squeezed(&calls).contains("&mutreport,true)?"), "{calls}");
    assert!(squeezed(&calls).contains("&mutreport,false)?"), "{calls}");
    let module = between(&code, "pub mod rod {", "pub mod crank_pin {").join("\n");
    let snapshot = format!("{rod}\n\n{pin}\n\n{middle}\n\n{module}\n");
    expect_file!["snapshots/slider_scenes.rs"].assert_eq(&snapshot);
}

/// Names too long for a comment line (a scene's comment names it): every `__comment!` marker
/// still becomes a `//` line, and the code parses.
#[test]
fn long_names_leave_no_comment_marker() {
    let long = format!("a_{}", "very_long_scene_name_".repeat(6));
    let file =
        format!("{SLIDER}\n[scene.{long}]\nmechanism = \"slider\"\noutputs = [\"B\"]\norder = 1\n");
    let (code, _) = generate_source(&SourceFile::new("long.toml", file)).expect("valid file");
    assert!(!code.contains("__comment"), "a marker is left");
    assert!(code.contains(&format!("// {long}:")), "the scene's comment");
    syn::parse_file(&code).expect("the generated code parses");
}
