//! Tests of the `closed_form` stage: the kinds of the default file's and the fixtures' blocks,
//! hand-written systems of each kind, near misses, and every classified block rebuilt from its
//! roots against the residual it came from.

use super::{ClosedForm, closed_form};
use crate::ir::dag::Var;
use crate::{Compiled, SourceFile, analyze};

/// Each mechanism's name and its blocks' kinds (`None`: Newton). Every classified block is also
/// checked by [`rebuild`].
fn kinds_of(name: &str, text: &str) -> Vec<(String, Vec<Option<&'static str>>)> {
    let (mechs, diags) = analyze(&SourceFile::new(name, text.to_string()));
    assert!(diags.iter().all(|d| !d.is_error()), "{diags:?}");
    mechs
        .iter()
        .map(|m| {
            let kinds = m
                .blocks
                .iter()
                .map(|b| {
                    let mut dag = m.system.dag.clone();
                    let cf = closed_form(&mut dag, &m.model, &m.system.residuals, &b.block)?;
                    rebuild(m, &dag, &cf, &b.block.equations);
                    Some(cf.name())
                })
                .collect();
            (m.model.name.text.clone(), kinds)
        })
        .collect()
}

/// The residuals of the block against `K + …` rebuilt from the roots, at two arbitrary states;
/// the roots must not depend on the block's unknowns.
fn rebuild(
    m: &Compiled,
    dag: &crate::ir::dag::Dag,
    cf: &ClosedForm,
    equations: &[crate::ir::lower::Equation],
) {
    let unknowns: Vec<usize> = match cf {
        ClosedForm::Rrr(d) => vec![d.a, d.b],
        ClosedForm::Rrp { q, s, .. } | ClosedForm::Rpr { q, s, .. } => vec![*q, *s],
        ClosedForm::Linear2 { s1, s2, .. } => vec![*s1, *s2],
        ClosedForm::Angle1 { q, .. } => vec![*q],
        ClosedForm::Length1 { s, .. } => vec![*s],
    };
    for &r in cf.roots() {
        for v in dag.vars_of(r) {
            assert!(
                !unknowns.iter().any(|&k| v == Var::Q(k as u16)),
                "{}: a root depends on a block unknown",
                m.model.name.text
            );
        }
    }
    for seed in [0.37, 1.91] {
        let value = |v: Var| match v {
            Var::X(i) => seed + 0.61 * f64::from(i),
            Var::Q(i) => 2.0 * seed - 0.83 * f64::from(i) + 0.1,
            Var::P(i) => m.model.params[i as usize].value,
            _ => 0.0,
        };
        let mut roots: Vec<_> = cf.roots().to_vec();
        roots.extend(equations.iter().map(|&e| m.system.residuals[e.index()]));
        let all = dag.eval(&roots, &value);
        let v: Vec<f64> = cf.roots().iter().map(|r| all[r.index()]).collect();
        let want: Vec<f64> = equations
            .iter()
            .map(|&e| all[m.system.residuals[e.index()].index()])
            .collect();
        let q = |k: usize| value(Var::Q(k as u16));
        let rot = |p: f64, r: f64, a: f64| (p * a.cos() - r * a.sin(), r * a.cos() + p * a.sin());
        let got: Vec<f64> = match *cf {
            ClosedForm::Rrr(ref d) => {
                let (a, b) = (rot(v[2], v[3], q(d.a)), rot(v[4], v[5], q(d.b)));
                vec![v[0] + a.0 + b.0, v[1] + a.1 + b.1]
            }
            ClosedForm::Rrp { q: qa, s, .. } => {
                let a = rot(v[2], v[3], q(qa));
                vec![v[0] + a.0 + q(s) * v[4], v[1] + a.1 + q(s) * v[5]]
            }
            ClosedForm::Rpr { q: qa, s, .. } => {
                let a = rot(v[2] + q(s) * v[4], v[3] + q(s) * v[5], q(qa));
                vec![v[0] + a.0, v[1] + a.1]
            }
            ClosedForm::Linear2 { s1, s2, .. } => vec![
                v[0] + q(s1) * v[2] + q(s2) * v[4],
                v[1] + q(s1) * v[3] + q(s2) * v[5],
            ],
            ClosedForm::Angle1 { q: qa, .. } => {
                vec![v[0] + v[1] * q(qa).cos() + v[2] * q(qa).sin()]
            }
            ClosedForm::Length1 { s, .. } => vec![v[0] + v[1] * q(s)],
        };
        let size = want.iter().chain(&v).fold(1.0f64, |m, x| m.max(x.abs()));
        for (g, w) in got.iter().zip(&want) {
            assert!(
                (g - w).abs() <= 1e-13 * size,
                "{}: {g} vs {w}",
                m.model.name.text
            );
        }
    }
}

fn kinds(text: &str) -> Vec<Option<&'static str>> {
    kinds_of("m.toml", text).remove(0).1
}

/// A one-mechanism file with the params every hand-written case uses.
fn mech(unknowns: &str, loops: &str, start: &str) -> String {
    format!(
        "[mechanism.m]\ninputs = [\"q1\"]\nunknowns = [{unknowns}]\nloops = [{loops}]\n\
         params = {{ a = 0.3, b = 1.0, d = 1.2, h = 0.1, al = 0.4 }}\nstart = {{ q1 = 0.0, {start} }}\n"
    )
}

#[test]
fn the_default_file() {
    let text = include_str!("../../../mechanism.toml");
    let got = kinds_of("mechanism.toml", text);
    let want: Vec<(&str, Vec<Option<&str>>)> = vec![
        ("sixbar", vec![Some("RRR"), Some("RRR")]),
        // The ram's slide is horizontal: its loop's y equation holds q4 alone, so the RRP group
        // splits into one angle, then one length.
        (
            "shaper",
            vec![Some("RPR"), Some("one angle"), Some("one length")],
        ),
        ("four_bar", vec![Some("RRR")]),
        ("slider_crank", vec![Some("one angle"), Some("one length")]),
        ("rocker_four_bar", vec![Some("RRR")]),
        ("sixbar_g", vec![None]),
    ];
    let got: Vec<(&str, Vec<Option<&str>>)> =
        got.iter().map(|(n, k)| (n.as_str(), k.clone())).collect();
    assert_eq!(got, want);
}

#[test]
fn the_fixtures() {
    let fixture = |f: &str| {
        let path = format!("{}/../tests/fixtures/{f}", env!("CARGO_MANIFEST_DIR"));
        kinds_of(&path, &std::fs::read_to_string(&path).expect("fixture"))
            .remove(0)
            .1
    };
    assert_eq!(fixture("actuator.toml"), [Some("RRR")]);
    assert_eq!(fixture("dyad_driven.toml"), [None]);
    assert_eq!(
        fixture("param_exprs.toml"),
        [Some("one angle"), Some("one length")]
    );
    assert_eq!(fixture("wide_scale.toml"), [Some("RRR")]);
}

#[test]
fn hand_written_systems_of_each_kind() {
    // A slider on an inclined line: RRP (the line's direction is a param).
    let rrp = mech(
        "\"q2\", \"s\"",
        "\"a*e(q1) + b*e(q2) - s*e(al) - d\"",
        "q2 = 0.5, s = 0.4",
    );
    assert_eq!(kinds(&rrp), [Some("RRP")]);
    // PRR: the slider first, on a line through an input-driven point.
    let prr = mech(
        "\"s\", \"q2\"",
        "\"s*e(al + 1) + a*e(q1) + b*e(q2 + al) - c(d, h)\"",
        "s = 0.1, q2 = 0.3",
    );
    assert_eq!(kinds(&prr), [Some("RRP")]);
    // Inverted slider-crank: a slotted guide through the pivot, and an offset slot.
    let rpr = mech(
        "\"s\", \"q2\"",
        "\"s*e(q2) - a*e(q1) - c(0, d)\"",
        "s = 1.0, q2 = 1.3",
    );
    assert_eq!(kinds(&rpr), [Some("RPR")]);
    let slot = mech(
        "\"s\", \"q2\"",
        "\"s*e(q2) + h*e(q2 + pi/2) - a*e(q1) - c(0, d)\"",
        "s = 1.0, q2 = 1.3",
    );
    assert_eq!(kinds(&slot), [Some("RPR")]);
    let guide = mech(
        "\"s\", \"q2\"",
        "\"(s + h)*e(q2 - al) + a*e(q2) - a*e(q1) - d\"",
        "s = 1.0, q2 = 0.3",
    );
    assert_eq!(kinds(&guide), [Some("RPR")]);
    // Two lengths, and a length driven by an earlier block's angle.
    let lin = mech(
        "\"s\", \"t\"",
        "\"s*e(al) + t*e(q1 + 1) - a*e(q1) - c(d, h)\"",
        "s = 1.0, t = 0.2",
    );
    assert_eq!(kinds(&lin), [Some("linear 2x2")]);
    let sc = mech(
        "\"q2\", \"s\"",
        "\"a*e(q1) + b*e(q2) - s - c(0, h)\"",
        "q2 = 0.1, s = 1.3",
    );
    assert_eq!(kinds(&sc), [Some("one angle"), Some("one length")]);
    // Four-bar with a sum of terms on one link.
    let fb = mech(
        "\"q2\", \"q3\"",
        "\"a*e(q1) + b*e(q2) + h*e(q2 - al) - d - b*e(q3)\"",
        "q2 = 1.0, q3 = 2.0",
    );
    assert_eq!(kinds(&fb), [Some("RRR")]);
}

#[test]
fn near_misses_stay_newton() {
    // A length squared, a length inside its own coefficient.
    let sq = mech(
        "\"q2\", \"s\"",
        "\"a*e(q1) + b*e(q2) - s*s*e(al) - d\"",
        "q2 = 0.5, s = 0.6",
    );
    assert_eq!(kinds(&sq), [None]);
    // Both a fixed direction and the angle's own: K + s u + s N e(q) is neither RRP nor RPR.
    let both = mech(
        "\"s\", \"q2\"",
        "\"s*e(q2) + s*e(al) - a*e(q1) - c(0, d)\"",
        // Near the assembled s = 1.0306, q2 = 2.2516 (the start check's Newton is the runtime's).
        "s = 1.0, q2 = 2.2",
    );
    assert_eq!(kinds(&both), [None]);
    // The angle unknown in a coefficient (its own link length), and a double angle.
    let own = mech(
        "\"q2\", \"s\"",
        "\"a*e(q1) + q2*e(q2) - s*e(al) - d\"",
        // Near the assembled q2 = 3.638, s = -4.445.
        "q2 = 3.6, s = -4.4",
    );
    assert_eq!(kinds(&own), [None]);
    let double = mech(
        "\"q2\", \"s\"",
        "\"a*e(q1) + b*e(2*q2) - s - c(0, h)\"",
        "q2 = 0.05, s = 1.3",
    );
    assert_eq!(kinds(&double)[0], None);
    // A length in a denominator, and two lengths multiplied.
    let div = mech(
        "\"s\", \"t\"",
        "\"c(b/s, t) - a*e(q1) - c(d, h)\"",
        "s = 0.8, t = 0.4",
    );
    assert_eq!(kinds(&div)[0], None);
    let prod = mech(
        "\"s\", \"t\"",
        "\"c(s*t, t - s) - a*e(q1) - c(d, h)\"",
        "s = 1.2, t = 1.1",
    );
    assert_eq!(kinds(&prod), [None]);
    // Not a rotation: an ellipse-like link.
    let ellipse = mech(
        "\"q2\", \"s\"",
        "\"a*e(q1) + c(b*cos(q2), h*sin(q2)) - s*e(al) - d\"",
        "q2 = 0.5, s = 0.4",
    );
    assert_eq!(kinds(&ellipse), [None]);
}

#[test]
fn a_two_by_two_block_of_two_loops_stays_newton() {
    // s and t from the x equations of two loops (linear, but not one loop's x and y).
    let text = "[mechanism.m]\ninputs = [\"q1\"]\nunknowns = [\"s\", \"t\", \"u\", \"v\"]\n\
        loops = [\"c(s + t, u) - a*e(q1)\", \"c(s - t, v) - c(1, 2)\"]\n\
        params = { a = 0.3 }\nstart = { q1 = 0.0, s = 0.65, t = -0.35, u = 0.0, v = 2.0 }\n";
    let k = kinds(text);
    assert_eq!(k.len(), 3, "{k:?}");
    assert!(k.contains(&None), "{k:?}");
    assert_eq!(
        k.iter().filter(|x| **x == Some("one length")).count(),
        2,
        "{k:?}"
    );
}
