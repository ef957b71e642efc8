//! The generic runtime engine against the generated solvers: same file, same sweeps, same
//! answers (1e-13; the same arithmetic, in fact bit for bit), same errors; and single evaluations (J, Φx, J̇, γ, residual) agree too.
#![cfg(feature = "runtime")]

mod common;

use common::engines::{check_engines_agree, engines};
use mechgen::sweep::{Continuation, sweep};
use mechgen::{DynMechanism, Kind, generic};

#[test]
fn generic_and_generated_agree_over_full_sweeps() {
    let fails = check_engines_agree();
    assert!(fails.is_empty(), "{}", fails.join("\n"));
}

#[test]
fn single_evaluations_agree() {
    for (k, g) in engines() {
        let info = k.info();
        let (ni, nu) = (info.inputs.len(), info.unknowns.len());
        let x: Vec<f64> = (0..ni).map(|i| 0.3 + 0.1 * i as f64).collect();
        let q: Vec<f64> = (0..nu).map(|i| 0.7 + 0.37 * i as f64).collect();
        let xd: Vec<f64> = (0..ni).map(|i| 1.1 - 0.2 * i as f64).collect();
        let qd: Vec<f64> = (0..nu).map(|i| -0.4 + 0.3 * i as f64).collect();
        let xdd = vec![0.25; ni];
        let mut a = vec![0.0; nu * nu.max(ni)];
        let mut b = a.clone();
        let close = |a: &[f64], b: &[f64], what: &str| {
            for (u, v) in a.iter().zip(b) {
                assert!(
                    (u - v).abs() <= 1e-13 * u.abs().max(1.0),
                    "{}: {what}: {u} vs {v}",
                    info.name
                );
            }
        };
        k.residual(&x, &q, &mut a[..nu]).unwrap();
        g.residual(&x, &q, &mut b[..nu]).unwrap();
        close(&a[..nu], &b[..nu], "residual");
        k.jacobian(&x, &q, &mut a[..nu * nu]).unwrap();
        g.jacobian(&x, &q, &mut b[..nu * nu]).unwrap();
        close(&a[..nu * nu], &b[..nu * nu], "jacobian");
        k.input_jacobian(&x, &q, &mut a[..nu * ni]).unwrap();
        g.input_jacobian(&x, &q, &mut b[..nu * ni]).unwrap();
        close(&a[..nu * ni], &b[..nu * ni], "input jacobian");
        k.jacobian_dot(&x, &q, &xd, &qd, &mut a[..nu * nu]).unwrap();
        g.jacobian_dot(&x, &q, &xd, &qd, &mut b[..nu * nu]).unwrap();
        close(&a[..nu * nu], &b[..nu * nu], "jacobian dot");
        k.acceleration_rhs(&x, &q, &xd, &qd, &xdd, &mut a[..nu])
            .unwrap();
        g.acceleration_rhs(&x, &q, &xd, &qd, &xdd, &mut b[..nu])
            .unwrap();
        close(&a[..nu], &b[..nu], "acceleration rhs");
    }
}

#[test]
fn same_error_values() {
    for (k, g) in engines() {
        let info = k.info();
        let (ni, nu) = (info.inputs.len(), info.unknowns.len());
        let x = vec![f64::NAN; ni];
        let mut q: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
        let opts = mechgen::SolveOptions::default();
        assert_eq!(
            k.solve_position(&x, &mut q.clone(), &opts),
            g.solve_position(&x, &mut q, &opts)
        );
        let short = vec![0.0; nu + 1];
        assert_eq!(
            k.solve_position(&vec![0.0; ni], &mut short.clone(), &opts)
                .unwrap_err(),
            g.solve_position(&vec![0.0; ni], &mut short.clone(), &opts)
                .unwrap_err()
        );
        let mut qd = vec![0.0; nu];
        let xs: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
        let q0: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
        assert_eq!(
            k.solve_velocity(&xs, &q0, &vec![f64::INFINITY; ni], &mut qd),
            g.solve_velocity(&xs, &q0, &vec![f64::INFINITY; ni], &mut qd)
        );
    }
}

#[test]
fn generic_f32_runs() {
    for (_, g) in engines() {
        let info = DynMechanism::<f32>::info(&g);
        let x: Vec<f32> = info.inputs.iter().map(|i| i.start as f32).collect();
        let mut q: Vec<f32> = info.unknowns.iter().map(|u| u.start as f32).collect();
        let r = g.solve_position(&x, &mut q, &mechgen::SolveOptions::default());
        assert!(r.is_ok(), "{}: {r:?}", info.name);
        assert!(q.iter().all(|v| v.is_finite()));
    }
}

#[test]
fn a_failed_position_solve_leaves_the_guess_alone_in_both_engines() {
    for (k, g) in engines() {
        let info = k.info();
        if info.name != "rocker_four_bar" {
            continue;
        }
        // 170°: past the dead point at 135.95°, no configuration exists.
        let x = [170f64.to_radians()];
        let guess: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
        for engine in [k.as_ref(), &g as &dyn DynMechanism<f64>] {
            let mut q = guess.clone();
            let r = engine.solve_position(&x, &mut q, &mechgen::SolveOptions::default());
            assert!(
                matches!(r, Err(mechgen::SolveError::Unassemblable { .. })),
                "{r:?}"
            );
            assert_eq!(q, guess);
        }
    }
}

/// A five-bar (two inputs, the second held) whose `start` is far off its loops: Newton from it
/// must not wander whole turns away (steps are capped, angles kept near the file's), so the sweep
/// of the first input goes round a full turn with every row solved and angles of normal size.
#[test]
fn a_far_off_start_settles_nearby_and_sweeps_a_full_turn() {
    let text = r#"[mechanism.fivebar]
inputs = ["a", "b"]
unknowns = ["q2", "q3"]
loops = ["l1*e(a) + l2*e(q2) - l5 - l4*e(b) - l3*e(q3)"]
params = { l1 = 1.0, l2 = 3.0, l3 = 3.0, l4 = 1.0, l5 = 2.0 }
start = { a = 1.5, b = 1.5, q2 = 0.0, q3 = 3.14159 }
"#;
    let (mechs, warnings) = generic::load_with_warnings("fivebar.toml", text).expect("loads");
    assert!(
        warnings.contains("does not satisfy the loops"),
        "{warnings}"
    );
    let values: Vec<f64> = (0..=12)
        .map(|i| f64::from(i) * 30f64.to_radians())
        .collect();
    let rows = sweep(
        &mechs[0],
        0,
        &values,
        1.0,
        &Continuation::for_input(Kind::Angle, 1.0),
    );
    for r in &rows {
        let s = r
            .result
            .as_ref()
            .unwrap_or_else(|e| panic!("{}: {e}", r.input));
        assert!(s.q.iter().all(|v| v.abs() < 10.0), "{:?}", s.q);
        let mut phi = [0.0; 2];
        let x = [r.input, 1.5];
        DynMechanism::<f64>::residual(&mechs[0], &x, &s.q, &mut phi).expect("sizes");
        assert!(phi.iter().all(|v| v.abs() < 1e-13), "{phi:?}");
    }
}

/// Blocks the generator classifies as closed forms (every block of these mechanisms but those of
/// `sixbar_g`, one 4×4) take no Newton iterations in the generic engine, and all iterate with
/// `closed_forms: false`; both answers agree.
#[test]
fn closed_form_blocks_take_no_iterations() {
    for (k, g) in engines() {
        let info = k.info();
        let closed = match info.name.as_str() {
            "sixbar" | "shaper" | "four_bar" | "slider_crank" | "rocker_four_bar" | "actuator"
            | "derived_slider" | "wide_four_bar" => true,
            "sixbar_g" => false,
            _ => continue,
        };
        let x: Vec<f64> = info.inputs.iter().map(|i| i.start * 1.01 + 0.01).collect();
        let start: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
        let newton = mechgen::SolveOptions {
            closed_forms: false,
            ..mechgen::SolveOptions::default()
        };
        let (mut a, mut b) = (start.clone(), start);
        let ra = g.solve_position(&x, &mut a, &mechgen::SolveOptions::default());
        let rb = g.solve_position(&x, &mut b, &newton);
        let (ra, rb) = (ra.expect("solves"), rb.expect("solves"));
        assert_eq!(ra.iterations == 0, closed, "{}: {ra:?}", info.name);
        assert!(rb.iterations > 0, "{}: {rb:?}", info.name);
        for (u, v) in a.iter().zip(&b) {
            assert!(
                (u - v).abs() <= 1e-12 * u.abs().max(1.0),
                "{}: {a:?} vs {b:?}",
                info.name
            );
        }
    }
}

/// A batch's `set_params` (every base param at once) is the same engine as setting each param
/// by name: the params, the description and a sweep's rows bit for bit, on a clone that shares
/// the model's tapes with the original (which keeps its own params).
#[test]
fn setting_every_param_at_once_is_setting_each() {
    let loaded = generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE).unwrap();
    for g in &loaded {
        let info = DynMechanism::<f64>::info(g);
        let values: Vec<f64> = info.params.iter().map(|p| p.value * 1.01).collect();
        let mut by_name = g.clone();
        for (p, &v) in info.params.iter().zip(&values) {
            by_name.set_param(&p.name, v).unwrap();
        }
        let mut at_once = g.clone();
        at_once.set_params(&values);
        assert_eq!(by_name.params(), at_once.params(), "{}", info.name);
        assert_eq!(
            DynMechanism::<f64>::info(&by_name),
            DynMechanism::<f64>::info(&at_once)
        );
        assert_ne!(
            g.params(),
            at_once.params(),
            "{}: the original keeps its params",
            info.name
        );
        let kind = info.inputs[0].kind;
        let step = if kind == Kind::Angle { 0.2 } else { 0.01 };
        let values: Vec<f64> = (0..30)
            .map(|i| info.inputs[0].start + step * f64::from(i))
            .collect();
        let c = Continuation::for_input(kind, values[29] - values[0]);
        let a = sweep(&by_name, 0, &values, 1.0, &c);
        let b = sweep(&at_once, 0, &values, 1.0, &c);
        assert_eq!(a, b, "{}", info.name);
        assert!(
            a.iter().any(|r| r.result.is_ok()),
            "{}: no row solved",
            info.name
        );
    }
}
