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
    let lanes = SixbarLanes::<F32x8>::from_fn(|i| mechs[i]);
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
            assert_eq!(t.lane(i), *s, "lane {i}");
        }
    }
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
