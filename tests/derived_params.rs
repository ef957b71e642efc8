//! Derived params (defined by expressions of other params) follow their bases at run time: the
//! generic engine's params are the base params, the derived ones are computed from them inside
//! its expressions (and reported by `derived_params`), setting one is an error, and a solve
//! after a base param changed uses the new derived values (checked against the four-bar's closed
//! form written here).
#![cfg(feature = "runtime")]

use mechgen::{DynMechanism, SolveOptions, generic};

const FILE: &str = r#"
[mechanism.derived_four_bar]
inputs = ["q1"]
unknowns = ["q2", "q3"]
loops = ["l1*e(q1) + l2*e(q2) - l4 - l3*e(q3)"]
[mechanism.derived_four_bar.params]
l1 = 0.1
a = 0.21
b = 0.28
l2 = "hypot(a, b)"
l3 = 0.3
l4 = "l3 * 4 / 3"
[mechanism.derived_four_bar.start]
q1 = 0.0
q2 = 0.9479697413828936
q3 = 1.8959394827657874
"#;

fn param(g: &generic::Generic, name: &str) -> f64 {
    let base = DynMechanism::<f64>::info(g)
        .params
        .iter()
        .position(|p| p.name == name)
        .map(|i| g.params()[i]);
    base.unwrap_or_else(|| {
        let derived = g.derived_params().unwrap();
        derived.iter().find(|(n, _)| n == name).unwrap().1
    })
}

/// The rocker angle of the crank-rocker at crank angle `q1` on the start's branch (C above the
/// line DB), from the law of cosines: an independent closed form.
fn rocker_angle(l1: f64, l2: f64, l3: f64, l4: f64, q1: f64) -> f64 {
    let (bx, by) = (l1 * q1.cos(), l1 * q1.sin());
    let d = (bx - l4).hypot(by);
    // The direction of DB, less the angle at D between DB and DC.
    let gamma = ((l3 * l3 + d * d - l2 * l2) / (2.0 * l3 * d)).acos();
    by.atan2(bx - l4) - gamma
}

#[test]
fn setting_a_base_param_recomputes_its_derived_params_and_the_solution() {
    let mut g = generic::load("derived.toml", FILE).unwrap().remove(0);
    assert!((param(&g, "l2") - 0.35).abs() < 1e-15);
    assert!((param(&g, "l4") - 0.4).abs() < 1e-15);

    g.set_param("a", 0.12).unwrap();
    let l2 = 0.12f64.hypot(0.28);
    assert!((param(&g, "l2") - l2).abs() < 1e-15, "l2 follows a");
    g.set_param("l3", 0.33).unwrap();
    assert!((param(&g, "l4") - 0.44).abs() < 1e-15, "l4 follows l3");

    // The solver uses the new values.
    let q1 = 0.7;
    let mut q = [0.9, 1.9];
    DynMechanism::<f64>::solve_position(&g, &[q1], &mut q, &SolveOptions::default()).unwrap();
    let want = rocker_angle(0.1, l2, 0.33, 0.44, q1);
    let diff = (q[1] - want + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
        - std::f64::consts::PI;
    assert!(diff.abs() < 1e-12, "q3 = {} against {want}", q[1]);
}

#[test]
fn a_derived_param_cannot_be_set_and_is_not_a_free_value() {
    let mut g = generic::load("derived.toml", FILE).unwrap().remove(0);
    let names: Vec<String> = DynMechanism::<f64>::info(&g)
        .params
        .iter()
        .map(|p| p.name.clone())
        .collect();
    assert_eq!(names, ["l1", "a", "b", "l3"], "the base params");
    let err = g.set_param("l2", 1.0).unwrap_err();
    assert!(err.contains("`l2` is derived from `a`, `b`"), "{err}");
    assert!((param(&g, "l2") - 0.35).abs() < 1e-15);
    assert!(g.set_param("nope", 1.0).is_err());
}
