//! `simulate` at the edges of a load that acts over a range of the input: a crank lifting a
//! 3 kg head on a vertical slider against 50 N pressing on the head while the crank is in the
//! range, driven by a constant 2 N·m. Across an edge the motion keeps an invariant a test can
//! compute from the rows alone (each side is conservative); on an edge where both sides push
//! in, the input rests there instead of the integrator chattering.

use mechgen::DynMechanism;
use mechgen::dynamics::PointLoad;
use mechgen::simulation::{Setup, SimRow, simulate};

const LIFT: &str = include_str!("data/lift.toml");

const TORQUE: f64 = 2.0;
const PRESS: f64 = 50.0;

fn lift() -> mechgen::generic::Generic {
    let mut g = mechgen::generic::load("lift.toml", LIFT).expect("the file loads");
    g.remove(0)
}

/// The rows of a simulation of `time` s in rows of `dt` s, the head pressed over `range`
/// (degrees).
fn rows(range: [f64; 2], time: f64, dt: f64) -> Vec<SimRow> {
    let m = lift();
    let info = DynMechanism::<f64>::info(&m);
    let top = info.points.iter().position(|p| p == "Top").expect("Top");
    let loads = [PointLoad::over(
        top,
        [0.0, -PRESS],
        [range[0].to_radians(), range[1].to_radians()],
    )];
    let setup = Setup {
        index: 0,
        x: &[0.0],
        rate: 0.0,
        effort: TORQUE,
        loads: &loads,
        time,
        dt,
    };
    let guess: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
    let mut out = Vec::new();
    simulate(&m, &setup, &guess, &mut |r| out.push(r.clone())).expect("simulates");
    out
}

/// The head's height at crank angle `th`, from the loop: r cos th + l cos phi = 0.
fn height(th: f64) -> f64 {
    let (r, l) = (0.05, 0.2);
    let c = -r * th.cos() / l;
    r * th.sin() + l * (1.0 - c * c).sqrt()
}

/// Pressed from 10° on, the crank starts below the range, swings into it and is pushed back,
/// again and again. On each side the forces are conservative, so kinetic + gravity's potential −
/// torque × angle + (inside the range) the press's work from the edge is the same on every row
/// (to 1e-10 of the energy's scale: switching the load stage by stage inside steps that straddle
/// the edge keeps it only to 2e-10), so each crossing is landed on; every row is `ok`; the crank
/// does go in and come out.
#[test]
fn a_swing_across_a_load_edge_keeps_its_invariant() {
    let edge = 10f64.to_radians();
    let out = rows([10.0, 180.0], 2.0, 1e-3);
    assert_eq!(out.len(), 2001);
    let (y_edge, mut inside, mut worst) = (height(edge), 0, 0.0f64);
    let invariant = |r: &SimRow| {
        let th = r.input[0];
        let pressed = if th >= edge {
            PRESS * (height(th) - y_edge)
        } else {
            0.0
        };
        r.kinetic + r.potential - TORQUE * th + pressed
    };
    let e0 = invariant(&out[0]);
    for r in &out {
        assert_eq!(r.status(), "ok", "t = {}", r.t);
        assert!(r.q[1] == r.q[1] && (r.q[1] - height(r.input[0])).abs() < 1e-12);
        inside += usize::from(r.input[0] > edge);
        worst = worst.max((invariant(r) - e0).abs());
    }
    // The scale: the head's weight times the crank's reach.
    let scale = 3.0 * 9.81 * 0.05;
    eprintln!("{inside} of 2001 rows inside the range; invariant kept to {worst:.1e} J");
    assert!(inside > 100 && inside < 1900, "{inside}");
    assert!(worst < 1e-10 * scale, "{worst:e}");
}

/// Pressed from 0° on, the crank at rest at 0° is held by both sides: the torque and gravity turn
/// it up into the range, the press turns it back out. The simulation rests there (every row
/// `at-load-edge`, at 0° with no rate or acceleration) instead of chattering until its steps run
/// out (as it did before edges were handled: `no-convergence` after 10⁶ steps).
#[test]
fn on_an_edge_both_sides_push_into_the_input_rests() {
    let out = rows([0.0, 180.0], 1.0, 0.01);
    assert_eq!(out.len(), 101);
    for r in &out {
        assert_eq!(r.status(), "at-load-edge", "t = {}", r.t);
        assert_eq!(r.input, [0.0, 0.0, 0.0]);
    }
}
