//! Stage 2 (semantics): [`crate::front::ast::File`] → [`model::Model`]s. Names are resolved
//! (declared once, never reserved or a Rust keyword), expressions typed (scalar or vector),
//! coordinates and params classified as angle or length, params and start values evaluated,
//! scenes validated. Built-ins are the one [`builtin::Builtin`] enum.
//!
//! Names end resolved: each expression lowering reads is a [`resolved`] tree of typed ids.
//!
//! Dependencies inside the stage run one way: `resolved` and `builtin` are leaves, `model` uses
//! `resolved`, `eval` and `typing` use them, `check` uses all.

mod bodies;
pub mod builtin;
mod check;
pub mod eval;
pub mod model;
pub mod resolved;
mod typing;

#[allow(unused_imports)] // the emitters' names table reads it
pub use check::check;

#[cfg(test)]
mod tests {
    use crate::{SourceFile, analyze};
    use std::f64::consts::PI;

    /// A four-bar whose params use every params-only function; the expected values are exact.
    const FILE: &str = r#"
[mechanism.m]
inputs = ["q1"]
unknowns = ["q2", "q3"]
loops = ["l1*e(q1) + l2*e(q2) - l4 - l3*e(q3 + a + b + cc + d + f) - g - h"]
[mechanism.m.params]
l1 = 0.1
l2 = "hypot(0.21, 0.28)"
l3 = 0.3
l4 = 0.4
a = "atan2(1, -1) - 3*pi/4"
b = "acos(-0.5) - 2*pi/3"
cc = "asin(0.5) - pi/6"
d = "atan(1) - pi/4"
f = "abs(-0.25) - 0.25"
g = "abs(l1) - 0.1"
h = 0
[mechanism.m.start]
q1 = 0.0
q2 = 0.9479697413828936
q3 = 1.8959394827657874
"#;

    #[test]
    fn params_only_functions_evaluate_and_derived_params_know_their_bases() {
        let (mechs, diags) = analyze(&SourceFile::new("m.toml", FILE));
        assert!(diags.iter().all(|d| !d.is_error()), "{diags:?}");
        let model = &mechs[0].model;
        let all: Vec<_> = model.params.iter().chain(&model.derived).collect();
        let value = |n: &str| all.iter().find(|p| p.name.text == n).unwrap().value;
        assert!((value("l2") - 0.35).abs() <= f64::EPSILON * 0.35);
        for n in ["a", "b", "cc", "d", "f", "g"] {
            assert!(
                value(n).abs() < 4.0 * f64::EPSILON * PI,
                "{n} = {}",
                value(n)
            );
        }
        let uses = |n: &str| &all.iter().find(|p| p.name.text == n).unwrap().uses;
        assert!(uses("l2").is_empty() && uses("a").is_empty());
        // g = abs(l1) - 0.1 is derived from l1; every other param is a base param.
        assert_eq!(
            uses("g"),
            &[crate::Symbol::Param(crate::sema::resolved::ParamId(0))]
        );
        let derived: Vec<&str> = model.derived.iter().map(|d| d.name.text.as_str()).collect();
        assert_eq!(derived, ["g"]);
        assert_eq!(model.params.len(), 10);
    }
}
