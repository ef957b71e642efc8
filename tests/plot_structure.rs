//! Drawings from a mechanism's structure (`generic::Generic::sketch`, `plot::sweep_frames`): a
//! Jansen leg whose third loop starts at a moving joint, sliders on fixed and moving guides,
//! points off every loop hung on their bodies, ground pivots; each checked against joints
//! computed independently from the solved unknowns.
#![cfg(all(feature = "plot", feature = "runtime"))]

use std::path::Path;

use mechgen::generic::{self, Generic, Sketch};
use mechgen::plot::{drawing_svg, point_paths, sweep_frames};
use mechgen::sweep::{Continuation, Row, sweep};
use mechgen::{DynMechanism, Kind, MechanismInfo};

type P = [f64; 2];

fn compiled_in(name: &str) -> Generic {
    let all = generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE).expect("source");
    all.into_iter()
        .find(|m| m.name() == name)
        .unwrap_or_else(|| panic!("{name} in the default file"))
}

fn jansen() -> Generic {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/jansen.toml");
    let mut all = generic::load_file(&path).expect("jansen.toml loads");
    assert_eq!(all.len(), 1);
    all.remove(0)
}

/// Sweeps input 0 from `from` to `to` degrees in `step` degree steps.
fn sweep_degrees(model: &Generic, from: i32, to: i32, step: usize) -> (MechanismInfo, Vec<Row>) {
    let info = DynMechanism::<f64>::info(model);
    let values: Vec<f64> = (from..=to)
        .step_by(step)
        .map(|d| f64::from(d).to_radians())
        .collect();
    let c = Continuation::for_input(Kind::Angle, f64::from(to - from).to_radians());
    let rows = sweep(model, 0, &values, 1.0, &c);
    (info, rows)
}

fn param(info: &MechanismInfo, name: &str) -> f64 {
    info.params
        .iter()
        .find(|p| p.name == name)
        .expect("param")
        .value
}

fn unknown(info: &MechanismInfo, q: &[f64], name: &str) -> f64 {
    q[info
        .unknowns
        .iter()
        .position(|u| u.name == name)
        .expect("unknown")]
}

fn at(o: P, l: f64, a: f64) -> P {
    [o[0] + l * a.cos(), o[1] + l * a.sin()]
}

fn near(a: P, b: P) -> bool {
    (a[0] - b[0]).hypot(a[1] - b[1]) <= 1e-9 * (1.0 + b[0].abs().max(b[1].abs()))
}

/// A link's distinct joints (a closed outline repeats its first).
fn joints(link: &[P]) -> Vec<P> {
    let mut v: Vec<P> = Vec::new();
    for p in link {
        if !v.iter().any(|q| near(*q, *p)) {
            v.push(*p);
        }
    }
    v
}

/// Every link of the sketch is one of `expected` (as sets of joints) and each expected one is
/// drawn exactly once.
fn assert_links(sketch: &Sketch, expected: &[Vec<P>], what: &str) {
    let same =
        |a: &[P], b: &[P]| a.len() == b.len() && a.iter().all(|p| b.iter().any(|q| near(*p, *q)));
    for link in &sketch.links {
        let j = joints(link);
        assert!(
            expected.iter().any(|e| same(&j, e)),
            "{what}: unexpected link {link:?}"
        );
        if j.len() > 2 {
            assert!(
                near(link[0], link[link.len() - 1]),
                "{what}: body outline not closed"
            );
        }
    }
    for e in expected {
        let n = sketch.links.iter().filter(|l| same(&joints(l), e)).count();
        assert_eq!(n, 1, "{what}: link {e:?} drawn {n} times");
    }
}

fn assert_pivots(sketch: &Sketch, expected: &[P], what: &str) {
    assert_eq!(
        sketch.pivots.len(),
        expected.len(),
        "{what}: {:?}",
        sketch.pivots
    );
    for p in expected {
        assert!(
            sketch.pivots.iter().any(|q| near(*q, *p)),
            "{what}: no pivot at {p:?}"
        );
    }
}

#[test]
fn jansen_leg_is_drawn_from_its_structure_at_every_row() {
    let model = jansen();
    let (info, rows) = sweep_degrees(&model, 0, 360, 10);
    assert!(rows.iter().all(|r| r.result.is_ok()));
    let p = |n| param(&info, n);
    let (beta, gamma) = (p("beta"), p("gamma"));
    for row in &rows {
        let s = row.result.as_ref().expect("solved");
        let u = |n| unknown(&info, &s.q, n);
        let (o, b) = ([0.0, 0.0], [-p("la"), -p("ll")]);
        let m = at(o, p("lm"), row.input);
        let j1 = at(b, p("lb"), u("q3"));
        let j2 = at(b, p("lc"), u("q5"));
        let j3 = at(b, p("ld"), u("q3") + beta);
        let j4 = at(j2, p("lg"), u("q7"));
        let foot = at(j2, p("li"), u("q7") + gamma);
        // The solver's own points agree with the joints computed here.
        assert!(near(s.points[0].position, j3) && near(s.points[1].position, foot));
        let sketch = model.sketch(&[row.input], &s.q).expect("sketch");
        let what = format!("jansen at {:.0} deg", row.input.to_degrees());
        assert_links(
            &sketch,
            &[
                vec![o, m],
                vec![m, j1],
                vec![m, j2],
                vec![b, j1, j3],
                vec![b, j2],
                vec![j3, j4],
                vec![j2, j4, foot],
            ],
            &what,
        );
        // Only the crank starts at the origin: the third loop is not drawn from there.
        let at_origin = sketch
            .links
            .iter()
            .filter(|l| l.iter().any(|q| near(*q, o)));
        assert_eq!(at_origin.count(), 1, "{what}");
        assert_pivots(&sketch, &[o, b], &what);
        assert!(sketch.sliders.is_empty());
    }
}

#[test]
fn slider_crank_has_a_block_on_a_fixed_guide_and_its_rod_midpoint_on_the_rod() {
    let model = compiled_in("slider_crank");
    let (info, rows) = sweep_degrees(&model, 0, 360, 15);
    let (r, l, off) = (param(&info, "r"), param(&info, "l"), param(&info, "off"));
    for row in &rows {
        let s = row.result.as_ref().expect("solved");
        let b = at([0.0, 0.0], r, row.input);
        let c = [unknown(&info, &s.q, "sC"), off];
        assert!(((c[0] - b[0]).hypot(c[1] - b[1]) - l).abs() < 1e-9);
        let sketch = model.sketch(&[row.input], &s.q).expect("sketch");
        let what = format!("slider_crank at {:.0} deg", row.input.to_degrees());
        assert_links(&sketch, &[vec![[0.0, 0.0], b], vec![b, c]], &what);
        // The guide's reference point (0, off) is not a pivot.
        assert_pivots(&sketch, &[[0.0, 0.0]], &what);
        assert_eq!(sketch.sliders.len(), 1, "{what}");
        let slider = sketch.sliders[0];
        assert!(slider.ground && near(slider.block, c) && near(slider.base, [0.0, off]));
        assert!(near(
            [slider.direction[0].abs(), slider.direction[1]],
            [1.0, 0.0]
        ));
        // M (the rod's midpoint, in no loop) lies on the rod.
        let mid = s.points[2].position;
        assert!(near(mid, [(b[0] + c[0]) / 2.0, (b[1] + c[1]) / 2.0]));
    }
}

#[test]
fn shaper_has_a_block_on_its_turning_guide_bar_and_a_ram_on_a_fixed_guide() {
    let model = compiled_in("shaper");
    let (info, rows) = sweep_degrees(&model, 0, 360, 20);
    let (l1, l3, l4) = (param(&info, "l1"), param(&info, "l3"), param(&info, "l4"));
    let (a, c) = ([0.0, param(&info, "lAC")], [0.0, 0.0]);
    for row in &rows {
        let s = row.result.as_ref().expect("solved");
        let q3 = unknown(&info, &s.q, "q3");
        let b = at(a, l1, row.input);
        let d = at(c, l3, q3);
        let e = at(d, l4, unknown(&info, &s.q, "q4"));
        let sketch = model.sketch(&[row.input], &s.q).expect("sketch");
        let what = format!("shaper at {:.0} deg", row.input.to_degrees());
        assert_links(&sketch, &[vec![c, d], vec![a, b], vec![d, e]], &what);
        assert_pivots(&sketch, &[a, c], &what);
        assert_eq!(sketch.sliders.len(), 2, "{what}");
        let moving = sketch
            .sliders
            .iter()
            .find(|s| !s.ground)
            .expect("moving guide");
        assert!(
            near(moving.base, c) && near(moving.block, b),
            "{what}: {moving:?}"
        );
        assert!(near(moving.direction, [q3.cos(), q3.sin()]));
        let fixed = sketch
            .sliders
            .iter()
            .find(|s| s.ground)
            .expect("fixed guide");
        assert!(near(fixed.block, e) && near(fixed.block, s.points[0].position));
    }
}

#[test]
fn points_off_every_loop_hang_on_their_bodies() {
    // P on the four-bar's coupler; Q on its rocker, reached from D through C.
    let text = r#"
[mechanism.rocker_point]
inputs = ["q1"]
unknowns = ["q2", "q3"]
loops = ["l1*e(q1) + l2*e(q2) - l4 - l3*e(q3)"]
params = { l1 = 0.1, l2 = 0.35, l3 = 0.3, l4 = 0.4, lp = 0.2, lq = 0.15 }
points = { P = "l1*e(q1) + lp*e(q2 + 0.5)", Q = "l4 + l3*e(q3) + lq*e(q3 - 1.2)" }
start = { q1 = 0.0, q2 = 0.9479697413828936, q3 = 1.8959394827657874 }
"#;
    let model = generic::load("rocker_point.toml", text)
        .expect("loads")
        .remove(0);
    let (info, rows) = sweep_degrees(&model, 0, 360, 30);
    for row in &rows {
        let s = row.result.as_ref().expect("solved");
        let (q2, q3) = (unknown(&info, &s.q, "q2"), unknown(&info, &s.q, "q3"));
        let (a, d) = ([0.0, 0.0], [0.4, 0.0]);
        let b = at(a, 0.1, row.input);
        let c = at(d, 0.3, q3);
        let (p, q) = (at(b, 0.2, q2 + 0.5), at(c, 0.15, q3 - 1.2));
        let sketch = model.sketch(&[row.input], &s.q).expect("sketch");
        let what = format!("rocker_point at {:.0} deg", row.input.to_degrees());
        assert_links(&sketch, &[vec![a, b], vec![b, c, p], vec![d, c, q]], &what);
        assert_pivots(&sketch, &[a, d], &what);
    }
}

#[test]
fn sweep_frames_hold_fixed_guides_still_and_draw_blocks_and_rails() {
    let model = compiled_in("slider_crank");
    let (info, mut rows) = sweep_degrees(&model, 0, 360, 5);
    rows[3].result = Err(mechgen::SolveError::BadLength {
        expected: 2,
        got: 1,
    });
    let ok = rows.iter().filter(|r| r.result.is_ok()).count();
    let frames = sweep_frames(&model, &[0.0], 0, &rows);
    assert_eq!(frames.len(), ok);
    let travel = rows
        .iter()
        .filter_map(|r| r.result.as_ref().ok())
        .map(|s| unknown(&info, &s.q, "sC"));
    let (lo, hi) = travel.fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
    let guide = frames[0].sliders[0].guide;
    let (g0, g1) = (guide[0][0].min(guide[1][0]), guide[0][0].max(guide[1][0]));
    assert!(g0 < lo && hi < g1, "guide {g0}..{g1}, travel {lo}..{hi}");
    for f in &frames {
        assert_eq!(f.sliders.len(), 1);
        assert_eq!(f.sliders[0].guide, guide, "a fixed guide stands still");
        assert!(f.sliders[0].ground);
        assert_eq!(f.ground.len(), 1);
    }
    // Input 1 does not exist: no frames, no panic.
    assert!(sweep_frames(&model, &[0.0], 1, &rows).is_empty());
    assert!(sweep_frames(&model, &[], 0, &rows).is_empty());

    let picks: Vec<_> = frames.iter().step_by(18).cloned().collect();
    let svg = drawing_svg("slider_crank", &picks, &point_paths(&info, &rows)).expect("drawing");
    assert!(svg.contains("slider on a fixed guide") && svg.contains("ground pivot"));
    assert!(!svg.contains("moving guide"));
    // One block per frame and one in the legend (blocks are filled #E1E1E1).
    assert_eq!(svg.matches("fill=\"#E1E1E1\"").count(), picks.len() + 1);
    for bad in ["NaN", "inf"] {
        assert!(!svg.contains(bad));
    }

    let shaper = compiled_in("shaper");
    let (info, rows) = sweep_degrees(&shaper, 0, 360, 90);
    let frames = sweep_frames(&shaper, &[0.0], 0, &rows);
    let svg = drawing_svg("shaper", &frames, &point_paths(&info, &rows)).expect("drawing");
    assert!(svg.contains("slider on a fixed guide") && svg.contains("slider on a moving guide"));
    assert_eq!(
        svg.matches("fill=\"#E1E1E1\"").count(),
        2 * frames.len() + 2
    );
}

#[test]
fn sketches_of_bad_arguments_are_errors_or_gaps_never_panics() {
    let model = jansen();
    assert!(model.sketch(&[0.0, 1.0], &[0.0; 6]).is_err());
    assert!(model.sketch(&[0.0], &[0.0; 5]).is_err());
    let sketch = model
        .sketch(&[f64::NAN], &[f64::INFINITY; 6])
        .expect("sketch");
    let frame = mechgen::plot::Frame {
        links: sketch.links,
        ground: sketch.pivots,
        ..Default::default()
    };
    // What is finite (the ground pivots) is drawn, the rest skipped.
    let svg = drawing_svg("non-finite configuration", &[frame], &[]).expect("drawing");
    for bad in ["NaN", "inf"] {
        assert!(!svg.contains(bad));
    }
}

#[test]
fn a_trammel_has_two_fixed_guides_and_no_pivot_and_a_cylinder_turns_about_its_pivot() {
    let text = r#"
[mechanism.trammel]
inputs = ["sx"]
unknowns = ["q", "sy"]
loops = ["sx + l*e(q) - sy*e(th)"]
params = { l = 0.3, th = "deg(60)" }
start = { sx = 0.1, q = 1.9586, sy = 0.3 }

[mechanism.cylinder]
inputs = ["q1"]
unknowns = ["s", "qc"]
loops = ["r*e(q1) - s*e(qc) - off*e(qc + pi/2) - c(d, 0)"]
params = { r = 0.1, d = 0.4, off = 0.03 }
start = { q1 = 0.0, s = 0.3, qc = 3.1 }
"#;
    let mut models = generic::load("two.toml", text).expect("loads");
    let (trammel, cylinder) = (models.remove(0), models.remove(0));

    let info = DynMechanism::<f64>::info(&trammel);
    let values: Vec<f64> = (0..=10).map(|i| 0.02 + 0.02 * f64::from(i)).collect();
    let c = Continuation::for_input(Kind::Length, 0.2);
    let rows = sweep(&trammel, 0, &values, 1.0, &c);
    assert!(rows.iter().all(|r| r.result.is_ok()));
    let th = 60f64.to_radians();
    for row in &rows {
        let s = row.result.as_ref().expect("solved");
        let (a, b) = (
            [row.input, 0.0],
            at([0.0, 0.0], unknown(&info, &s.q, "sy"), th),
        );
        let sketch = trammel.sketch(&[row.input], &s.q).expect("sketch");
        assert_links(&sketch, &[vec![a, b]], "trammel");
        assert!(sketch.pivots.is_empty(), "{:?}", sketch.pivots);
        assert_eq!(sketch.sliders.len(), 2);
        assert!(
            sketch
                .sliders
                .iter()
                .all(|s| s.ground && near(s.base, [0.0, 0.0]))
        );
        assert!(near(sketch.sliders[0].block, a) && near(sketch.sliders[1].block, b));
        assert!(near(sketch.sliders[1].direction, [th.cos(), th.sin()]));
    }
    let frames = sweep_frames(&trammel, &[0.1], 0, &rows);
    let svg = drawing_svg("trammel", &frames[..2], &[]).expect("drawing");
    assert!(svg.contains("slider on a fixed guide") && !svg.contains("ground pivot"));

    let info = DynMechanism::<f64>::info(&cylinder);
    let (_, rows) = sweep_degrees(&cylinder, 0, 360, 30);
    for row in &rows {
        let s = row.result.as_ref().expect("solved");
        let qc = unknown(&info, &s.q, "qc");
        let (o, p) = ([0.0, 0.0], [0.4, 0.0]);
        let b = at(o, 0.1, row.input);
        let x = at(p, 0.03, qc + std::f64::consts::FRAC_PI_2);
        let sketch = cylinder.sketch(&[row.input], &s.q).expect("sketch");
        assert_links(&sketch, &[vec![o, b], vec![p, x]], "cylinder");
        assert_pivots(&sketch, &[o, p], "cylinder");
        let slider = sketch.sliders[0];
        assert!(!slider.ground && near(slider.base, x) && near(slider.block, b));
        assert!(near(slider.direction, [qc.cos(), qc.sin()]));
    }
}

#[test]
fn a_four_bar_is_drawn_the_same_however_its_loop_is_written() {
    let loops = [
        "l1*e(q1) + l2*e(q2) - l4 - l3*e(q3)",
        "l1*e(q1) + l2*e(q2) - l3*e(q3) - l4",
        "-l4 - l3*e(q3) + l1*e(q1) + l2*e(q2)",
        "l4 + l3*e(q3) - l2*e(q2) - l1*e(q1)",
        // Negated: which way the walk goes is settled by the named joints B and C.
        "-l1*e(q1) - l2*e(q2) + l4 + l3*e(q3)",
    ];
    for (i, l) in loops.iter().enumerate() {
        let text = format!(
            r#"
[mechanism.fb{i}]
inputs = ["q1"]
unknowns = ["q2", "q3"]
loops = ["{l}"]
params = {{ l1 = 0.1, l2 = 0.35, l3 = 0.3, l4 = 0.4 }}
points = {{ B = "l1*e(q1)", C = "l4 + l3*e(q3)" }}
start = {{ q1 = 0.0, q2 = 0.9479697413828936, q3 = 1.8959394827657874 }}
"#
        );
        let model = generic::load("fb.toml", &text).expect("loads").remove(0);
        let (info, rows) = sweep_degrees(&model, 0, 360, 45);
        for row in &rows {
            let s = row.result.as_ref().expect("solved");
            let (a, d) = ([0.0, 0.0], [0.4, 0.0]);
            let b = at(a, 0.1, row.input);
            let c = at(d, 0.3, unknown(&info, &s.q, "q3"));
            let sketch = model.sketch(&[row.input], &s.q).expect("sketch");
            let what = format!("`{l}` at {:.0} deg", row.input.to_degrees());
            assert_links(&sketch, &[vec![a, b], vec![b, c], vec![d, c]], &what);
            assert_pivots(&sketch, &[a, d], &what);
        }
    }
}

#[test]
fn a_named_joint_settles_which_way_a_side_of_a_loop_runs() {
    // The six-bar's second loop with its right side written out from G (G + GF + FE), not as a
    // walk back from E: the point F says which link is at G.
    let text = r#"
[mechanism.sixbar_sides]
inputs = ["q1"]
unknowns = ["q2", "q3", "q5", "q6"]
loops = [
    "l1*e(q1) + l2*e(q2) - l4 - l3*e(q3)",
    "l1*e(q1) + l2*e(q2) + l2e*e(q2 - alpha) - c(xg, yg) - l6*e(q6) - l5*e(q5)",
]
params = { l1 = 26.5, l2 = 75.0, l3 = 59.0, l4 = 87.5, l5 = 48.4, l6 = 39.0, l2e = 65.0, xg = 153.5, yg = 41.7, alpha = "deg(60)" }
points = { F = "c(xg, yg) + l6*e(q6)" }
start = { q1 = 0.0, q2 = "deg(50.1)", q3 = "deg(102.7)", q5 = "deg(117.2)", q6 = "deg(280.7)" }
"#;
    let model = generic::load("sides.toml", text).expect("loads").remove(0);
    let (info, rows) = sweep_degrees(&model, 0, 360, 60);
    for row in &rows {
        let s = row.result.as_ref().expect("solved");
        let u = |n| unknown(&info, &s.q, n);
        let (a, d, g) = ([0.0, 0.0], [87.5, 0.0], [153.5, 41.7]);
        let b = at(a, 26.5, row.input);
        let c = at(b, 75.0, u("q2"));
        let e = at(c, 65.0, u("q2") - 60f64.to_radians());
        let f = at(g, 39.0, u("q6"));
        let sketch = model.sketch(&[row.input], &s.q).expect("sketch");
        let what = format!("sixbar_sides at {:.0} deg", row.input.to_degrees());
        let links = [
            vec![a, b],
            vec![b, c, e],
            vec![d, c],
            vec![f, e],
            vec![g, f],
        ];
        assert_links(&sketch, &links, &what);
        assert_pivots(&sketch, &[a, d, g], &what);
    }
}

/// A Peaucellier–Lipkin linkage, whose third loop (B–P–D) has no ground term, drawn with the
/// same links whatever the order of that loop's terms: O–B, O–D, A–C, C–B, C–D, B–P, D–P, pivots
/// at O and A, at every row (the joints from the solved unknowns); P on its straight line.
#[test]
fn a_loop_without_ground_terms_is_drawn_through_its_joints_in_any_order() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/peaucellier.toml");
    let text = std::fs::read_to_string(&path).expect("peaucellier.toml");
    let written = "L*e(qB) + s*e(qBP) - L*e(qD) - s*e(qDP)";
    assert!(text.contains(written));
    for order in [
        written,
        "L*e(qB) + s*e(qBP) - s*e(qDP) - L*e(qD)",
        "s*e(qBP) - L*e(qD) + L*e(qB) - s*e(qDP)",
    ] {
        let mut all =
            generic::load("peaucellier.toml", &text.replace(written, order)).expect("loads");
        let model = all.remove(0);
        let (info, rows) = sweep_degrees(&model, -80, 80, 10);
        assert!(rows.iter().all(|r| r.result.is_ok()), "{order}");
        let p = |n| param(&info, n);
        let (a, l, s) = (p("a"), p("L"), p("s"));
        for row in &rows {
            let sol = row.result.as_ref().expect("solved");
            let u = |n| unknown(&info, &sol.q, n);
            let (o, pa) = ([0.0, 0.0], [a, 0.0]);
            let c = at(pa, a, row.input);
            let (b, d) = (at(o, l, u("qB")), at(o, l, u("qD")));
            let pp = at(b, s, u("qBP"));
            assert!(
                (pp[0] - (l * l - s * s) / (2.0 * a)).abs() < 1e-12,
                "P on its line"
            );
            let mut x = vec![0.0; info.inputs.len()];
            x[0] = row.input;
            let sketch = model.sketch(&x, &sol.q).expect("sketch");
            let what = format!("{order} at {:.1} deg", row.input.to_degrees());
            assert_links(
                &sketch,
                &[
                    vec![o, b],
                    vec![o, d],
                    vec![pa, c],
                    vec![c, b],
                    vec![c, d],
                    vec![b, pp],
                    vec![d, pp],
                ],
                &what,
            );
            assert_pivots(&sketch, &[o, pa], &what);
        }
    }
}
