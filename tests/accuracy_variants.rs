//! The solver variants of `examples/accuracy` (its `variants.rs`, included here) against the
//! 40-digit reference over a full turn in 1° steps, to their expected orders: no timing. The
//! seed shaper's variants (`shaper.rs`) too.
#![cfg(feature = "runtime")]

#[path = "../examples/accuracy/shaper.rs"]
mod shaper;
#[path = "../examples/accuracy/variants.rs"]
mod variants;

use mechgen::SolveOptions;
use variants::{
    Budget, Engine, Errors, FiniteDifferences, Generated, Pass, SAMPLE_EVERY, STEPS, Scheme,
    Stepper, errors, inputs, reference, run,
};

fn turn<S: Stepper>(mut s: S) -> (Pass, Errors) {
    let r = reference().expect("reference");
    let (pass, _) = run(&mut s, &inputs()).expect("a full turn");
    let e = errors(&pass.samples, &r);
    eprintln!(
        "{e:?}, {} iterations, {} failed",
        pass.iterations, pass.failed
    );
    (pass, e)
}

fn generic() -> mechgen::generic::Generic {
    let loaded = mechgen::generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
        .expect("the compiled-in file loads");
    loaded
        .into_iter()
        .find(|g| g.name() == "sixbar")
        .expect("sixbar")
}

fn options(tolerance: f64, max_iterations: u32) -> Budget {
    Budget::Options {
        tolerance,
        max_iterations,
    }
}

#[test]
fn samples_fall_on_the_reference_rows() {
    let r = reference().expect("reference");
    let xs = inputs();
    assert_eq!(xs.len(), STEPS + 1);
    assert_eq!(r.rows.len(), STEPS / SAMPLE_EVERY + 1);
    for (i, x) in r.x.iter().enumerate() {
        assert!((xs[i * SAMPLE_EVERY] - x).abs() < 1e-15, "row {i}");
    }
    // A state off by 1e-3 in one angle and 1 % in one rate is measured as such.
    let mut off = r.rows.clone();
    off[3].q[2] += 1e-3 + 2.0 * std::f64::consts::PI;
    off[5].qd[1] *= 1.01;
    let e = errors(&off, &r);
    assert!((e.position - 1e-3).abs() < 1e-12, "{e:?}");
    assert!(
        e.velocity > 1e-4 && e.velocity < 1e-2 && e.acceleration == 0.0,
        "{e:?}"
    );
    assert_eq!(errors(&off[1..], &r).max(), f64::INFINITY);
}

#[test]
fn generated_f64_is_exact_to_rounding_and_loose_tolerances_to_their_order() {
    let (pass, e) = turn(Generated::<f64>::new(options(1e-12, 64)));
    assert!(e.max() < 1e-13, "{e:?}");
    assert_eq!(pass.failed, 0);
    // Two iterations per block: the predictor is good to about 1e-5.
    assert_eq!(pass.iterations, 4 * STEPS as u64);
    // One iteration from that predictor leaves about its square.
    let (_, e) = turn(Generated::<f64>::new(options(1e-4, 64)));
    assert!(e.max() > 1e-11 && e.max() < 1e-7, "{e:?}");
    let (pass, e) = turn(Generated::<f64>::new(Budget::Fixed(1)));
    assert!(e.max() > 1e-11 && e.max() < 1e-7, "{e:?}");
    assert_eq!((pass.iterations, pass.failed), (2 * STEPS as u64, 0));
    let (pass, e) = turn(Generated::<f64>::new(Budget::Fixed(2)));
    assert!(e.max() < 1e-13, "{e:?}");
    assert_eq!(pass.iterations, 4 * STEPS as u64);
}

#[test]
fn a_cap_of_one_fails_every_tick_and_the_prediction_drifts() {
    let (pass, e) = turn(Generated::<f64>::new(options(1e-12, 1)));
    assert_eq!(pass.failed, STEPS);
    // The predictor alone integrates the rates: a drift of order Δx².
    assert!(e.position > 1e-5 && e.max() < 1e-1, "{e:?}");
    let (pass, e) = turn(Generated::<f64>::new(options(1e-12, 2)));
    assert_eq!(pass.failed, 0);
    assert!(e.max() < 1e-13, "{e:?}");
}

#[test]
fn generated_f32_and_the_generic_engine() {
    let (_, e) = turn(Generated::<f32>::new(options(1e-5, 64)));
    assert!(e.max() < 1e-4 && e.max() > 1e-8, "{e:?}");
    let g = generic();
    // Block Newton (two iterations per dyad block per step from the last step's answer) …
    let newton = SolveOptions {
        closed_forms: false,
        ..SolveOptions::default()
    };
    let (pass, e) = turn(Engine::new(&g, newton));
    assert!(e.max() < 1e-13, "{e:?}");
    assert_eq!(pass.iterations, 4 * STEPS as u64);
    // … and, by default, the dyads' closed forms: no iterations, as exact.
    let (pass, e) = turn(Engine::new(&g, SolveOptions::default()));
    assert!(e.max() < 1e-13, "{e:?}");
    assert_eq!(pass.iterations, 0);
}

#[test]
fn finite_differences_converge_positions_but_not_rates() {
    let g = generic();
    // Newton converges with an approximate Jacobian: positions to rounding either way.
    let (_, forward) = turn(FiniteDifferences::new(&g, Scheme::Forward));
    let (_, central) = turn(FiniteDifferences::new(&g, Scheme::Central));
    assert!(forward.position < 1e-13 && central.position < 1e-13);
    // Rates carry the difference error: about √ε (forward), ε^(2/3) (central) times the
    // condition, and √ε for the second difference in the accelerations.
    assert!(
        forward.velocity > 1e-10 && forward.velocity < 1e-5,
        "{forward:?}"
    );
    assert!(
        central.velocity > 1e-13 && central.velocity < 1e-8,
        "{central:?}"
    );
    for e in [forward, central] {
        assert!(e.acceleration > 1e-10 && e.acceleration < 1e-5, "{e:?}");
    }
    // The same solver on the generated residual gives the same orders.
    let m = mechgen::sixbar::Sixbar::<f64>::default();
    let (_, e) = turn(FiniteDifferences::new(&m, Scheme::Forward));
    assert!(
        e.position < 1e-13 && e.velocity < 1e-5 && e.acceleration < 1e-5,
        "{e:?}"
    );
}

#[test]
fn closed_form_dyads_are_exact_without_iterations() {
    let (pass, e) = turn(Generated::<f64>::new(Budget::ClosedForm));
    assert!(e.max() < 1e-13, "{e:?}");
    assert_eq!((pass.iterations, pass.failed), (0, 0));
    let (pass, e) = turn(Generated::<f64>::new(Budget::Ticked));
    assert!(e.max() < 1e-13, "{e:?}");
    assert_eq!((pass.iterations, pass.failed), (0, 0));
    let (pass, e) = turn(Generated::<f32>::new(Budget::ClosedForm));
    assert!(e.max() < 1e-4 && e.max() > 1e-8, "{e:?}");
    assert_eq!(pass.iterations, 0);
}

fn shaper_turn<S: Stepper>(mut s: S) -> (Pass, Errors) {
    let r = shaper::reference().expect("shaper reference");
    let (pass, _) = run(&mut s, &inputs()).expect("a full turn of the shaper");
    let e = shaper::errors(&pass.samples, &r);
    eprintln!(
        "shaper: {e:?}, {} iterations, {} failed",
        pass.iterations, pass.failed
    );
    (pass, e)
}

#[test]
fn shaper_errors_measure_angles_and_lengths() {
    let r = shaper::reference().expect("shaper reference");
    assert_eq!(r.rows.len(), STEPS / SAMPLE_EVERY + 1);
    for (i, x) in r.x.iter().enumerate() {
        assert!((inputs()[i * SAMPLE_EVERY] - x).abs() < 1e-15, "row {i}");
    }
    assert_eq!(shaper::errors(&r.rows, &r).max(), 0.0);
    // s3 and sE are lengths, q3 and q4 angles (the order of the file's unknowns).
    let scale = shaper::largest_length_param();
    assert_eq!(scale, 0.6);
    let mut off = r.rows.clone();
    off[2].q[0] += 6e-4; // s3: 1e-3 of the largest length
    let e = shaper::errors(&off, &r);
    assert!((e.position - 1e-3).abs() < 1e-12, "{e:?}");
    let mut off = r.rows.clone();
    off[4].q[2] += 2e-3 - 2.0 * std::f64::consts::PI; // q4, an angle: modulo 2π
    let e = shaper::errors(&off, &r);
    assert!((e.position - 2e-3).abs() < 1e-12, "{e:?}");
    assert_eq!(shaper::errors(&off[1..], &r).max(), f64::INFINITY);
}

#[test]
fn shaper_variants_to_their_orders() {
    use mechgen::SolveOptions;
    // Closed forms (the default), f64: exact to rounding, no iterations.
    let (pass, e) = shaper_turn(shaper::Generated::<f64>::new(SolveOptions::default()));
    assert!(e.position <= 1e-12 && e.max() < 1e-12, "{e:?}");
    assert_eq!((pass.iterations, pass.failed), (0, 0));
    // Newton on every block at the default tolerance: as exact.
    let (pass, e) = shaper_turn(shaper::Generated::<f64>::new(shaper::newton(1e-12)));
    assert!(e.position <= 1e-12 && e.max() < 1e-11, "{e:?}");
    assert_eq!(pass.failed, 0);
    assert!(pass.iterations > 0);
    // At 1e-6: looser, but within the tolerance.
    let (pass, e) = shaper_turn(shaper::Generated::<f64>::new(shaper::newton(1e-6)));
    assert!(e.position <= 1e-6 && e.max() < 1e-5, "{e:?}");
    assert_eq!(pass.failed, 0);
    // f32 closed forms: single-precision rounding.
    let (pass, e) = shaper_turn(shaper::Generated::<f32>::new(SolveOptions::default()));
    assert!(e.max() <= 1e-4 && e.max() > 1e-9, "{e:?}");
    assert_eq!(pass.failed, 0);
    // The generic engine (closed forms by default).
    let g = shaper::generic().expect("shaper");
    let (_, e) = shaper_turn(Engine::new(&g, SolveOptions::default()).with_start(shaper::start()));
    assert!(e.position <= 1e-12 && e.max() < 1e-11, "{e:?}");
}
