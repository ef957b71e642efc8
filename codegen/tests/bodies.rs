//! Bodies and gravity (the format's "Bodies and gravity"): accepted and checked, and ignored by
//! the kinematics: a file with them generates the code of the same file without them with only
//! their own items added (`body_motion`, `mass_properties`, the trait's `bodies` and
//! `mass_properties`, the names in `INFO.bodies`), and
//! the analysis keeps each body's mass, inertia (0 when not given) and centre (a point by name or
//! a vector expression). Their errors are diagnostics fixtures (`tests/diagnostics/bodies_*`).

use mechgen_codegen::Centre;
use mechgen_codegen::{SourceFile, analyze, generate_source};

const FOUR_BAR: &str = r#"[mechanism.m]
inputs = ["q1"]
unknowns = ["q2", "q3"]
loops = ["l1*e(q1) + l2*e(q2) - l4 - l3*e(q3)"]
params = { l1 = 1.0, l2 = 3.0, l3 = 3.0, l4 = 3.5, rho = 7.85 }
start = { q1 = 0.0, q2 = 1.0, q3 = 2.0 }
points = { B = "l1*e(q1)" }
"#;

const BODIES: &str = r#"gravity = "c(0, -9.81)"

[mechanism.m.bodies.crank]
angle = "q1"
mass = "rho*l1/10"
com = "B"

[mechanism.m.bodies.rocker]
angle = "q3"
mass = 2.5
com = "c(l4, 0) + l3/2*e(q3)"
inertia = "2.5*l3*l3/12"
"#;

#[test]
fn bodies_are_checked_and_the_kinematics_ignore_them() {
    let with = format!("{FOUR_BAR}{BODIES}");
    // `gravity` belongs to the mechanism's table: put it before the bodies' tables.
    let with = with
        .replacen("gravity = \"c(0, -9.81)\"\n", "", 1)
        .replacen("points = {", "gravity = \"c(0, -9.81)\"\npoints = {", 1);
    // The bodies use `rho`, so it is not an unused param there (it is in the file without them).
    let (a, warnings) = generate_source(&SourceFile::new("m.toml", &with)).expect("accepted");
    assert!(warnings.is_empty(), "{warnings:?}");
    let (b, warnings) = generate_source(&SourceFile::new("m.toml", FOUR_BAR)).expect("accepted");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    // Every line of the bodiless code, in order, is a line of the code with bodies (the INFO's
    // empty list of bodies apart).
    let mut lines = a.lines();
    for line in b.lines().filter(|l| !l.contains("bodies: &[]")) {
        assert!(
            lines.any(|l| l == line),
            "the bodies changed the generated code at `{line}`"
        );
    }
    for item in [
        "pub fn body_motion(",
        "pub fn mass_properties(",
        "fn bodies(",
    ] {
        assert!(a.contains(item) && !b.contains(item), "{item}");
    }
    assert!(a.contains(r#"bodies: &["crank", "rocker"]"#));
    let (compiled, diags) = analyze(&SourceFile::new("m.toml", &with));
    assert!(diags.is_empty(), "{diags:?}");
    let m = &compiled[0].model;
    assert!(m.gravity.is_some());
    assert_eq!(m.bodies.len(), 2);
    let crank = m
        .bodies
        .iter()
        .find(|b| b.name.text == "crank")
        .expect("crank");
    assert_eq!((crank.mass, crank.inertia), (7.85 * 1.0 / 10.0, 0.0));
    assert_eq!(crank.com, Centre::Point(0));
    let rocker = m
        .bodies
        .iter()
        .find(|b| b.name.text == "rocker")
        .expect("rocker");
    assert_eq!((rocker.mass, rocker.inertia), (2.5, 2.5 * 3.0 * 3.0 / 12.0));
    assert!(matches!(rocker.com, Centre::Vector(_)));
}

/// A param that only `gravity` names is used: no "never used" warning for it (found on a file
/// with `gravity = "c(0, -g0)"`, 2026-11-30); a param nothing names still has its warning.
#[test]
fn a_param_only_gravity_names_is_used() {
    let file = FOUR_BAR
        .replace("rho = 7.85", "rho = 7.85, g0 = 9.81, spare = 1.0")
        .replacen("points = {", "gravity = \"c(0, -g0)\"\npoints = {", 1)
        + &BODIES.replacen("gravity = \"c(0, -9.81)\"\n", "", 1);
    let (_, warnings) = generate_source(&SourceFile::new("m.toml", &file)).expect("accepted");
    let text: Vec<&str> = warnings.iter().map(|w| w.message.as_str()).collect();
    assert_eq!(text.len(), 1, "{text:?}");
    assert!(text[0].contains("param `spare` is never used"), "{text:?}");
}
