//! Scenes generated in a crate of its own (this one's `build.rs`, through the build library), one
//! of them for the runtime path `::mechgen_runtime` and named like the items of a module: every
//! tick along a turn of the input equals the full mechanism's solve at the same input (1e-12),
//! through the typed API under the alternative names and through the registry.

use mechgen::{InputMotion, SolveOptions};
use mechgen_odd_files as odd;

const STEPS: usize = 144;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * b.abs().max(1.0)
}

/// The inputs of a turn of q1 in 2.5° steps, moving at rate 1.
fn turn() -> impl Iterator<Item = (f64, [f64; 1])> {
    (0..=STEPS).map(|i| {
        let x = i as f64 * std::f64::consts::TAU / STEPS as f64;
        (x, [x])
    })
}

#[test]
fn the_c_path_follows_its_four_bar() {
    use odd::c_path::CPath;
    use odd::generic::{Generic, Inputs};
    let (scene, full) = (CPath::<f64>::default(), Generic::<f64>::default());
    let (_, mut q) = CPath::<f64>::start();
    let options = SolveOptions::default();
    let at = |x: f64| InputMotion::new(Inputs { q1: x }, Inputs { q1: 1.0 }, Inputs { q1: 0.0 });
    let mut t = scene.tick_start(&at(0.0), &q, &options).unwrap();
    for (x, _) in turn().skip(1) {
        scene.tick(&mut t, &at(x), &options).unwrap();
        let out = CPath::outputs(&t);
        let want = full.solve(&at(x), &q, &options).unwrap();
        q = want.q;
        let c = want.points.C.position;
        assert!(close(out.C_x, c[0]) && close(out.C_y, c[1]), "at {x}");
    }
    assert_eq!(odd::c_path::INFO.angles_skipped, [0, 1]);
}

#[test]
fn scenes_named_like_items_follow_their_slider_crank() {
    use odd::other::outputs::{OutputValues, Outputs};
    use odd::other::points::{Inputs, Points};
    use odd::other::tick::{Tick, TickState};
    let full = Points::<f64>::default();
    let (slider, rod) = (Tick::<f64>::default(), Outputs::<f64>::default());
    let (_, mut q) = Points::<f64>::start();
    let options = SolveOptions::default();
    let at = |x: f64| InputMotion::new(Inputs { q1: x }, Inputs { q1: 1.0 }, Inputs { q1: 0.0 });
    let mut ts: TickState<f64> = slider.tick_start(&at(0.0), &q, &options).unwrap();
    let mut tr = rod.tick_start(&at(0.0), &q, &options).unwrap();
    for (x, _) in turn().skip(1) {
        slider.tick(&mut ts, &at(x), &options).unwrap();
        rod.tick(&mut tr, &at(x), &options).unwrap();
        let want = full.solve(&at(x), &q, &options).unwrap();
        q = want.q;
        let m = want.points.Motion;
        let s = Tick::outputs(&ts);
        for (got, w) in [
            (s.Motion_x, m.position[0]),
            (s.Motion_y, m.position[1]),
            (s.Motion_vx, m.velocity[0]),
            (s.Motion_vy, m.velocity[1]),
        ] {
            assert!(close(got, w), "slider at {x}: {got} vs {w}");
        }
        let b: OutputValues<f64> = Outputs::outputs(&tr);
        for (got, w) in [(b.b, want.q.b), (b.b_vel, want.qd.b), (b.b_acc, want.qdd.b)] {
            assert!(close(got, w), "rod at {x}: {got} vs {w}");
        }
    }
    // The registry of the runtime-path file lists them.
    assert_eq!(odd::other::SCENES, ["tick", "outputs"]);
    assert!(odd::other::lookup_scene::<f64>("tick").is_some());
    // The slider reads only the rod's cosine: its tick skips the angle b; the rod's scene reads b.
    assert_eq!(odd::other::tick::INFO.angles_skipped, [0]);
    assert!(odd::other::outputs::INFO.angles_skipped.is_empty());
}

/// A scene whose name no generated comment line can hold (its comments once broke the build).
#[test]
fn a_scene_with_a_very_long_name_builds_and_solves() {
    use odd::generic::{Generic, Inputs};
    use odd::a_scene_with_a_name_long_enough_that_no_generated_comment_line_can_hold_it_whole_and_prettyplease_splits_it::ASceneWithANameLongEnoughThatNoGeneratedCommentLineCanHoldItWholeAndPrettypleaseSplitsIt as Long;
    let (scene, full) = (Long::<f64>::default(), Generic::<f64>::default());
    let (_, q) = Long::<f64>::start();
    let options = SolveOptions::default();
    let input = InputMotion::new(Inputs { q1: 0.7 }, Inputs { q1: 1.0 }, Inputs { q1: 0.0 });
    let out = scene.solve(&input, &q, &options).unwrap().out;
    let want = full.solve(&input, &q, &options).unwrap();
    assert!(close(out.q3, want.q.q3) && close(out.q3_vel, want.qd.q3));
}
