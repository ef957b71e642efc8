//! SIMD lanes (`NAME::Lanes<L>`): every compiled-in mechanism, W instances with random params and
//! input rates, some past dead points: each lane equals its scalar tick bit for bit, failed lanes
//! carry the scalar tick's error, other lanes are unaffected (`common::lanes`). The typed API on
//! the six-bar in f32 lanes.

mod common;

use mechgen::generated::sixbar::{Lanes as SixbarLanes, Params, Sixbar};
use mechgen::lanes::{F32x8, Lanes};
use mechgen::{InputMotion, SolveOptions};

#[test]
fn every_lane_is_its_scalar_tick() {
    let (fails, seen) = common::lanes::check_lanes(12, 400);
    eprintln!("{seen:?}");
    assert!(fails.is_empty(), "{}", fails.join("\n"));
    // The cases reached failures and lanes that went on beside them.
    assert!(seen.failed > 0 && seen.ok_beside_failed > 0, "{seen:?}");
}

#[test]
fn six_bar_in_f32_lanes_is_the_scalar_f32_tick() {
    let d = Params::<f32>::default();
    let mechs: Vec<Sixbar<f32>> = (0..8)
        .map(|i| {
            let mut p = d;
            p.l1 *= 1.0 + 0.01 * i as f32;
            Sixbar::new(p)
        })
        .collect();
    let mut lanes = SixbarLanes::<F32x8>::from_fn(|i| mechs[i]);
    // Out of range: errors and `None`, never a panic.
    assert!(lanes.set(8, mechs[0]).is_err() && lanes.mechanism(8).is_none());
    assert!(lanes.set(3, mechs[3]).is_ok());
    let (x0, q0) = Sixbar::<f32>::start();
    let opts = SolveOptions::default();
    let mut x = [F32x8::splat(x0.q1)];
    let xd = [F32x8::splat(1.0f32.to_radians())];
    let guess = q0.to_array().map(F32x8::splat);
    let mut t = lanes.tick_start(&InputMotion::new(x, xd, [F32x8::zero()]), &guess, &opts);
    let mut scalar: Vec<_> = mechs
        .iter()
        .map(|m| {
            let input = InputMotion::new(
                x0,
                mechgen::generated::sixbar::Inputs::from_array([1.0f32.to_radians()]),
                Default::default(),
            );
            m.tick_start(&input, &q0, &opts).expect("starts")
        })
        .collect();
    assert!(t.lane(8).is_none() && t.report(8).is_none() && t.status(8).is_err() && !t.started(8));
    for _ in 0..720 {
        x[0] = x[0] + xd[0];
        lanes.tick(&mut t, &InputMotion::new(x, xd, [F32x8::zero()]), &opts);
        for (i, (m, s)) in mechs.iter().zip(&mut scalar).enumerate() {
            let input = InputMotion::new(
                mechgen::generated::sixbar::Inputs::from_array([x[0].lane(i)]),
                mechgen::generated::sixbar::Inputs::from_array([xd[0].lane(i)]),
                Default::default(),
            );
            let r = m.tick(s, &input, &opts);
            assert_eq!(r, t.status(i));
            assert_eq!(t.lane(i), Some(*s), "lane {i}");
        }
    }
}

/// The first tick in lanes from eight different guesses and inputs, some not finite (a guess,
/// a param, an input, an input rate), some far from the default branch: each lane is the scalar
/// `tick_start` from its own guess (state, caches and report bit for bit, or its error), and a
/// far guess starts on another branch than the default one beside it.
#[test]
fn a_start_in_lanes_is_each_lanes_scalar_start() {
    use mechgen::lanes::F64x8;
    let (x0, q0) = Sixbar::<f64>::start();
    let q0 = q0.to_array();
    let mut mechs = [Sixbar::new(Params::<f64>::default()); 8];
    mechs[2].params.l1 = f64::INFINITY;
    mechs[7].params.l5 *= 1.05;
    let mut guesses = [q0; 8];
    guesses[1][2] = f64::NAN;
    // The second loop's dyad on its other assembly: q5 and q6 mirrored about the line between
    // their ends (roughly: swapped and turned half a turn).
    guesses[5] = [
        q0[0],
        q0[1],
        q0[3] + std::f64::consts::PI,
        q0[2] + std::f64::consts::PI,
    ];
    guesses[6] = [q0[1], q0[0], q0[2], q0[3]];
    let mut x = [x0.q1; 8];
    let mut xd = [1f64.to_radians(); 8];
    x[3] = f64::NAN;
    xd[4] = f64::NEG_INFINITY;
    x[6] += 0.3;
    let lanes = SixbarLanes::<F64x8>::from_fn(|i| mechs[i]);
    let input = InputMotion::new(
        [F64x8::from_fn(|i| x[i])],
        [F64x8::from_fn(|i| xd[i])],
        [F64x8::zero()],
    );
    let guess: [F64x8; 4] = core::array::from_fn(|k| F64x8::from_fn(|i| guesses[i][k]));
    let opts = SolveOptions::default();
    let t = lanes.tick_start(&input, &guess, &opts);
    let mut failed = 0;
    for i in 0..8 {
        let scalar = mechgen::StaticMechanism::tick_start(
            &mechs[i],
            &InputMotion::new([x[i]], [xd[i]], [0.0]),
            &guesses[i],
            &opts,
        );
        match scalar {
            Ok(s) => {
                assert_eq!(t.status(i), Ok(()), "lane {i}");
                assert!(t.started(i), "lane {i}");
                assert_eq!(t.lane(i), Some(s), "lane {i}");
            }
            Err(e) => {
                failed += 1;
                assert_eq!(t.status(i), Err(e), "lane {i}");
                assert!(!t.started(i), "lane {i}");
                // A lane that failed keeps its guess.
                assert_eq!(
                    t.lane(i).expect("i < W").q.map(f64::to_bits),
                    guesses[i].map(f64::to_bits)
                );
            }
        }
    }
    assert_eq!(failed, 4, "the four lanes with a value not finite");
    let branch_differs = |i: usize| (0..4).any(|k| (t.q[k].lane(i) - t.q[k].lane(0)).abs() > 0.1);
    assert!(branch_differs(5), "{:?}", t.q);
}

/// A fleet of 103 six-bars (not a multiple of W; different params and input rates) ticked over
/// a turn through `mechgen::fleet::Fleet` on every core: every instance is its scalar tick.
#[test]
fn a_fleet_is_its_scalar_ticks() {
    use mechgen::fleet::Fleet;
    use mechgen::lanes::F64x4;
    let n = 103;
    let mechs: Vec<Sixbar<f64>> = (0..n)
        .map(|i| {
            let mut p = Params::<f64>::default();
            p.l1 *= 1.0 + 0.002 * i as f64;
            p.l5 *= 1.0 - 0.001 * i as f64;
            Sixbar::new(p)
        })
        .collect();
    let (x0, q0) = Sixbar::<f64>::start();
    let rate = |i: usize| (0.5 + 0.01 * i as f64).to_radians();
    let input_at =
        |i: usize, tick: usize| InputMotion::new([x0.q1 + rate(i) * tick as f64], [rate(i)], [0.0]);
    let opts = SolveOptions::default();
    let inputs: Vec<_> = (0..n).map(|i| input_at(i, 0)).collect();
    let mut fleet =
        Fleet::<_, F64x4>::start(&mechs, &inputs, &vec![q0.to_array(); n], &opts).expect("sizes");
    assert_eq!(fleet.len(), n);
    let mut scalar: Vec<_> = (0..n)
        .map(|i| {
            mechgen::StaticMechanism::tick_start(&mechs[i], &inputs[i], &q0.to_array(), &opts)
                .expect("starts")
        })
        .collect();
    for tick in 1..=360 {
        let inputs: Vec<_> = (0..n).map(|i| input_at(i, tick)).collect();
        fleet.tick(&inputs, &opts).expect("sizes");
        for i in 0..n {
            let r = mechgen::StaticMechanism::tick(&mechs[i], &mut scalar[i], &inputs[i], &opts);
            let (status, t) = fleet.state(i).expect("in range");
            assert_eq!(status, r, "instance {i} tick {tick}");
            assert_eq!(t, scalar[i], "instance {i} tick {tick}");
        }
    }
    assert!(fleet.tick(&inputs[..3], &opts).is_err());
    assert!(fleet.state(n).is_err());
}

/// The generic engine through `DynFleet` (a whole solve per tick from its prediction, one
/// instance at a time, every core) against the generated six-bars in lanes through `Fleet`:
/// the same statuses on every tick of a turn and positions, rates and points within 1e-12 of
/// each value's scale, for 21 instances with different crank lengths.
#[test]
fn a_generic_fleet_follows_the_generated_one() {
    use mechgen::fleet::{DynFleet, Fleet};
    use mechgen::lanes::F64x4;
    let n = 21;
    let base = mechgen::generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
        .expect("the default file loads")
        .into_iter()
        .find(|g| g.name() == "sixbar")
        .expect("sixbar");
    let l1 = |i: usize| Params::<f64>::default().l1 * (1.0 + 0.003 * i as f64);
    let engines: Vec<_> = (0..n)
        .map(|i| {
            let mut g = base.clone();
            g.set_param("l1", l1(i)).expect("l1 is a base param");
            g
        })
        .collect();
    let mechs: Vec<Sixbar<f64>> = (0..n)
        .map(|i| {
            Sixbar::new(Params {
                l1: l1(i),
                ..Default::default()
            })
        })
        .collect();
    let (x0, q0) = Sixbar::<f64>::start();
    let step = 1f64.to_radians();
    let at = |k: usize| InputMotion::new([x0.q1 + step * k as f64], [step], [0.0]);
    let dyn_at = |k: usize| {
        let a = at(k);
        InputMotion::new(a.x.to_vec(), a.xd.to_vec(), a.xdd.to_vec())
    };
    let opts = SolveOptions::default();
    let mut lanes =
        Fleet::<_, F64x4>::start(&mechs, &vec![at(0); n], &vec![q0.to_array(); n], &opts)
            .expect("sizes");
    let mut generic = DynFleet::start(
        engines,
        &vec![dyn_at(0); n],
        &vec![q0.to_array().to_vec(); n],
        &opts,
    )
    .expect("sizes");
    let mut worst = 0.0f64;
    for k in 0..=360 {
        if k > 0 {
            lanes.tick(&vec![at(k); n], &opts).expect("sizes");
            generic.tick(&vec![dyn_at(k); n], &opts).expect("sizes");
        }
        for i in 0..n {
            let (s1, t) = lanes.state(i).expect("in range");
            let (s2, g) = generic.state(i).expect("in range");
            assert_eq!(s1, s2, "instance {i} tick {k}");
            let pairs = [
                (&t.q[..], &g.q[..]),
                (&t.qd[..], &g.qd[..]),
                (&t.qdd[..], &g.qdd[..]),
            ];
            for (a, b) in pairs {
                let scale = b.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                for (u, v) in a.iter().zip(b) {
                    worst = worst.max((u - v).abs() / scale);
                }
            }
            let (p, r) = (t.points[0].position, g.points[0].position);
            worst = worst.max((p[0] - r[0]).abs().max((p[1] - r[1]).abs()) / 200.0);
        }
    }
    eprintln!("generic vs generated fleet: {worst:.1e}");
    assert!(worst < 1e-12, "{worst:e}");
    assert!(generic.tick(&vec![dyn_at(0); 3], &opts).is_err());
}

#[test]
fn every_scene_lane_is_its_scalar_tick() {
    let (fails, seen) = common::lanes::check_scene_lanes(8, 300);
    eprintln!("{seen:?}");
    assert!(fails.is_empty(), "{}", fails.join("\n"));
    assert!(seen.failed > 0 && seen.ok_beside_failed > 0, "{seen:?}");
}
