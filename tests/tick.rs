//! Predictor stepping (`tick_start` / `tick`): every tick equals a fresh solve to rounding, over
//! long runs (the cached sines and cosines do not drift), when the params change, across the
//! closed-form dyads (six-bar), block Newton (`sixbar_g`) and length unknowns (shaper); a failed
//! tick leaves the state unchanged.

mod common;

use common::angle_diff;
use mechgen::{Array, InputMotion, Kind, SolveError, SolveOptions, StaticMechanism, StaticVisitor};

/// Largest difference between two states (angles folded, rates relative to max(1, |v|)).
fn difference(kinds: &[Kind], a: [&[f64]; 3], b: [&[f64]; 3]) -> f64 {
    let mut worst: f64 = 0.0;
    for (s, (u, v)) in a.iter().zip(b.iter()).enumerate() {
        for k in 0..u.len() {
            let d = if s == 0 && kinds[k] == Kind::Angle {
                angle_diff(u[k], v[k])
            } else {
                u[k] - v[k]
            };
            worst = worst.max(d.abs() / v[k].abs().max(1.0));
        }
    }
    worst
}

/// Ticks `turns` full turns of input 0 in steps of `step_deg` and compares every tick with a
/// whole `solve` from the previous state's positions. Returns the largest difference.
fn run<M: StaticMechanism<f64>>(m: &M, turns: u32, step_deg: f64) -> f64 {
    run_with(m, turns, step_deg, SolveOptions::default())
}

/// [`run`] with given solver options.
fn run_with<M: StaticMechanism<f64>>(
    m: &M,
    turns: u32,
    step_deg: f64,
    opts: SolveOptions<f64>,
) -> f64 {
    let info = m.info();
    let kinds: Vec<Kind> = info.unknowns.iter().map(|u| u.kind).collect();
    let mut x = M::X::zeros();
    let mut guess = M::Q::zeros();
    for (v, c) in x.as_mut().iter_mut().zip(info.inputs) {
        *v = c.start;
    }
    for (v, c) in guess.as_mut().iter_mut().zip(info.unknowns) {
        *v = c.start;
    }
    let mut xd = M::X::zeros();
    xd.as_mut()[0] = 1.3;
    let mut input = InputMotion::new(x, xd, M::X::zeros());
    let mut t = m
        .tick_start(&input, &guess, &opts)
        .expect("the start assembles");
    let steps = (f64::from(turns) * 360.0 / step_deg.abs()).round() as u32;
    let mut worst: f64 = 0.0;
    for _ in 0..steps {
        input.x.as_mut()[0] += step_deg.to_radians();
        let q = t.q;
        m.tick(&mut t, &input, &opts)
            .unwrap_or_else(|e| panic!("{}: tick to {:?}: {e}", info.name, input.x.as_ref()));
        let s = m.solve(&input, &q, &opts).expect("a fresh solve");
        let d = difference(
            &kinds,
            [t.q.as_ref(), t.qd.as_ref(), t.qdd.as_ref()],
            [s.q.as_ref(), s.qd.as_ref(), s.qdd.as_ref()],
        );
        worst = worst.max(d);
    }
    worst
}

#[test]
fn ticks_equal_fresh_solves() {
    let sixbar = mechgen::sixbar::Sixbar::<f64>::default();
    let d = run(&sixbar, 1, 1.0);
    eprintln!("sixbar, 360 ticks of 1°: {d:e}");
    assert!(d < 1e-12, "sixbar: {d:e}");
    let shaper = mechgen::shaper::Shaper::<f64>::default();
    let d = run(&shaper, 1, 1.0);
    eprintln!("shaper, 360 ticks of 1°: {d:e}");
    assert!(d < 1e-12, "shaper: {d:e}");
    let four_bar = mechgen::four_bar::FourBar::<f64>::default();
    let d = run(&four_bar, 1, 5.0);
    assert!(d < 1e-12, "four_bar: {d:e}");
}

#[test]
fn large_ticks_and_newton_on_dyads() {
    let sixbar = mechgen::sixbar::Sixbar::<f64>::default();
    // 15° ticks: links turn by more than the turn series covers, so the dyads' angles come from
    // atan2 (nearest the last tick's); backwards too.
    let d = run(&sixbar, 1, 15.0);
    eprintln!("sixbar, 24 ticks of 15°: {d:e}");
    assert!(d < 1e-12, "sixbar 15°: {d:e}");
    let d = run(&sixbar, 1, -7.5);
    eprintln!("sixbar, 48 ticks of −7.5°: {d:e}");
    assert!(d < 1e-12, "sixbar −7.5°: {d:e}");
    // Newton on the dyad blocks: their unknowns are predicted and their caches rotated.
    let newton = SolveOptions {
        closed_forms: false,
        ..SolveOptions::default()
    };
    let d = run_with(&sixbar, 1, 1.0, newton);
    eprintln!("sixbar, Newton on dyads, 360 ticks of 1°: {d:e}");
    assert!(d < 1e-12, "sixbar Newton: {d:e}");
}

#[test]
fn long_runs_do_not_drift() {
    // 20 turns in 0.1° ticks: 72 000 ticks, caches resynchronised every RESYNC_TICKS.
    let sixbar = mechgen::sixbar::Sixbar::<f64>::default();
    let d = run(&sixbar, 20, 0.1);
    eprintln!("sixbar, 72 000 ticks of 0.1°: {d:e}");
    assert!(d < 1e-12, "sixbar: {d:e}");
    let shaper = mechgen::shaper::Shaper::<f64>::default();
    let d = run(&shaper, 5, 0.1);
    eprintln!("shaper, 18 000 ticks of 0.1°: {d:e}");
    assert!(d < 1e-12, "shaper: {d:e}");
}

#[test]
fn block_newton_ticks_inside_the_range() {
    use mechgen::sixbar_g::{Inputs, SixbarG, Tick, Unknowns};
    let m = SixbarG::<f64>::default();
    let (x0, q0) = SixbarG::<f64>::start();
    let opts = SolveOptions::default();
    let at = |x: f64| InputMotion::new([x], [1.0], [0.0]).map(|a| Inputs::from_array(*a));
    let mut t: Tick<f64> = m
        .tick_start(&at(x0.to_array()[0]), &q0, &opts)
        .expect("start");
    // From 280.7° down to 250° and up to 340°, inside the dead points (244.5°, 344.1°).
    let mut worst: f64 = 0.0;
    let path = (0..=30)
        .map(|i| 280.0 - f64::from(i))
        .chain((250..=340).map(f64::from));
    for deg in path {
        let input = at(deg.to_radians());
        let guess = Unknowns::from_array(t.q);
        m.tick(&mut t, &input, &opts).expect("inside the range");
        let s = m.solve(&input, &guess, &opts).expect("fresh");
        let (q, qd, qdd) = (s.q.to_array(), s.qd.to_array(), s.qdd.to_array());
        for k in 0..4 {
            worst = worst
                .max(angle_diff(t.q[k], q[k]).abs())
                .max((t.qd[k] - qd[k]).abs() / qd[k].abs().max(1.0))
                .max((t.qdd[k] - qdd[k]).abs() / qdd[k].abs().max(1.0));
        }
    }
    eprintln!("sixbar_g, 122 ticks: {worst:e}");
    assert!(worst < 1e-11, "{worst:e}");
}

#[test]
fn params_changes_and_failures() {
    use mechgen::rocker_four_bar::{Inputs, RockerFourBar};
    let mut m = RockerFourBar::<f64>::default();
    let (x0, q0) = RockerFourBar::<f64>::start();
    let opts = SolveOptions::default();
    let at = |x: f64| InputMotion::new([x], [1.0], [0.0]).map(|a| Inputs::from_array(*a));
    let mut t = m
        .tick_start(&at(x0.to_array()[0]), &q0, &opts)
        .expect("start");
    m.tick(&mut t, &at(0.1), &opts).expect("tick");
    // A longer coupler: the cached param trig is not used, the answer is the new mechanism's.
    m.params.l2 = 0.36;
    m.tick(&mut t, &at(0.2), &opts).expect("tick");
    let mut q = t.q;
    m.solve_position(&[0.2], &mut q, &opts).expect("fresh");
    assert!(
        (0..2).all(|k| angle_diff(t.q[k], q[k]).abs() < 1e-14),
        "{:?} {q:?}",
        t.q
    );
    // Past the dead point: an error, and the state is left as it was.
    let before = t;
    let r = m.tick(&mut t, &at(170f64.to_radians()), &opts);
    assert!(matches!(r, Err(SolveError::Unassemblable { .. })), "{r:?}");
    assert_eq!(t, before);
    let r = m.tick(&mut t, &at(f64::NAN), &opts);
    assert!(matches!(r, Err(SolveError::NonFinite { .. })), "{r:?}");
    assert_eq!(t, before);
}

/// Every compiled-in mechanism can tick (the bench's `step` uses this path).
#[test]
fn every_mechanism_ticks_from_its_start() {
    struct Check;
    impl StaticVisitor<f64> for Check {
        fn visit<M: StaticMechanism<f64> + 'static>(&mut self, m: &M) {
            let info = m.info();
            let (mut x, mut q) = (M::X::zeros(), M::Q::zeros());
            for (v, c) in x.as_mut().iter_mut().zip(info.inputs) {
                *v = c.start;
            }
            for (v, c) in q.as_mut().iter_mut().zip(info.unknowns) {
                *v = c.start;
            }
            let input = InputMotion::new(x, x, M::X::zeros());
            let opts = SolveOptions::default();
            let mut t = m.tick_start(&input, &q, &opts).expect("start");
            assert!(m.tick(&mut t, &input, &opts).is_ok(), "{}", info.name);
        }
    }
    mechgen::visit_all(&mut Check);
}
