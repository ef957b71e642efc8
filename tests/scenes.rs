//! Scenes (issue 12) on the compiled-in file: outputs equal to the full solver's over full
//! sweeps (both engines, f64 and f32), the columns of interfaces.md, ticks, the registry, and
//! `mechgen sweep SCENE` / `check` on the command line.

mod common;

use common::scenes::{check_compiled_in_scene_ticks, check_compiled_in_scenes, expected_columns};
use mechgen::{InputMotion, SolveOptions};

#[test]
fn scene_outputs_equal_the_full_solvers() {
    assert!(!mechgen::SCENES.is_empty(), "the default file has scenes");
    let fails = check_compiled_in_scenes();
    assert!(fails.is_empty(), "{}", fails.join("\n"));
}

#[test]
fn scene_ticks_follow_the_sweep() {
    let fails = check_compiled_in_scene_ticks();
    assert!(fails.is_empty(), "{}", fails.join("\n"));
}

#[test]
fn the_default_scenes_keep_what_the_issue_says() {
    let info = |n: &str| mechgen::lookup_scene::<f64>(n).unwrap().info();
    let e = info("sixbar_e_path");
    assert_eq!(
        (e.mechanism.as_str(), e.order, e.blocks.as_slice()),
        ("sixbar", 0, &[0][..])
    );
    assert_eq!(e.columns, ["E_x", "E_y"]);
    // E sits on the coupler: its tick needs q2's sine and cosine, not q2, and nothing of q3.
    assert_eq!(e.angles_skipped, [0, 1]);
    assert_eq!(info("shaper_ram").angles_skipped, [1, 2]);
    assert_eq!(info("sixbar_output").columns, ["q6", "q6_vel", "q6_acc"]);
    assert_eq!(info("shaper_ram").columns, ["sE", "sE_vel", "sE_acc"]);
    assert_eq!(
        info("coupler_curve").columns,
        ["P_x", "P_y", "P_vx", "P_vy"]
    );
    assert!(mechgen::lookup_scene::<f64>("sixbar").is_none());
}

/// The typed API a simulator uses: the scene's own `Outputs` fields.
#[test]
fn the_typed_scene_api() {
    use mechgen::sixbar_e_path::{Inputs, SixbarEPath};
    let scene = SixbarEPath::<f64>::default();
    let (x, q) = SixbarEPath::<f64>::start();
    let options = SolveOptions::default();
    let input = InputMotion::new(x, Inputs { q1: 1.0 }, Inputs { q1: 0.0 });
    let out = scene.solve(&input, &q, &options).unwrap().out;
    let full = mechgen::sixbar::Sixbar::<f64>::default()
        .solve(&input, &q, &options)
        .unwrap();
    assert_eq!([out.E_x, out.E_y], full.points.E.position);
    let mut t = scene
        .tick_start(
            &InputMotion::new(Inputs { q1: 0.0 }, Inputs { q1: 1.0 }, Inputs { q1: 0.0 }),
            &q,
            &options,
        )
        .unwrap();
    scene
        .tick(
            &mut t,
            &InputMotion::new(Inputs { q1: 0.01 }, Inputs { q1: 1.0 }, Inputs { q1: 0.0 }),
            &options,
        )
        .unwrap();
    assert!(SixbarEPath::outputs(&t).E_x.is_finite());
}

/// A scene's tick skips the angles its outputs do not read (the dyads' turn series): it must
/// still follow its mechanism when closed forms are switched off and on between ticks (Newton
/// then predicts from those angles) and when params change, read ones (including `alpha`,
/// whose sine and cosine the tick caches) and unread ones.
#[test]
fn scene_ticks_survive_option_switches_and_param_changes() {
    use mechgen::sixbar::Sixbar;
    use mechgen::sixbar_e_path::{Inputs, SixbarEPath};
    let mut scene = SixbarEPath::<f64>::default();
    let mut full = Sixbar::<f64>::default();
    let (_, mut q) = SixbarEPath::<f64>::start();
    let at = |q1: f64| InputMotion::new(Inputs { q1 }, Inputs { q1: 1.0 }, Inputs { q1: 0.0 });
    let closed = SolveOptions::default();
    let newton = SolveOptions {
        closed_forms: false,
        ..SolveOptions::default()
    };
    let mut t = scene.tick_start(&at(0.0), &q, &closed).unwrap();
    let mut worst = 0.0f64;
    for i in 1..=720 {
        let x = i as f64 * 0.5f64.to_radians();
        match i {
            200 => {
                scene.params.alpha = 0.9;
                full.params.alpha = 0.9;
            }
            300 => {
                scene.params.l2e = 70.0;
                full.params.l2e = 70.0;
            }
            // Read by the dyad that the scene never solves: no effect on E.
            400 => scene.params.l5 = f64::NAN,
            _ => {}
        }
        // Closed forms off for three ticks out of every ten.
        let options = if i % 10 < 3 { &newton } else { &closed };
        scene.tick(&mut t, &at(x), options).unwrap();
        // Newton starts from the last tick's configuration, 0.5° away: three iterations. (From
        // the stale angle the tick skipped, it took four or five at resyncs and at the change of
        // `alpha`, before the tick restored the angle from its sine and cosine.)
        if i % 10 < 3 {
            let iterations = t.report().iterations;
            assert!(iterations <= 3, "tick {i}: {iterations} Newton iterations");
        }
        let e = SixbarEPath::outputs(&t);
        let solved = full.solve(&at(x), &q, &closed).unwrap();
        q = solved.q;
        let want = solved.points.E.position;
        for (a, b) in [e.E_x, e.E_y].into_iter().zip(want) {
            worst = worst.max((a - b).abs() / b.abs().max(1.0));
        }
    }
    // Newton stops at its tolerance (1e-12 relative by default); closed forms agree to rounding.
    assert!(worst < 1e-11, "largest relative difference {worst:e}");
}

fn mechgen_bin(args: &[&str]) -> (bool, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_mechgen"))
        .args(args)
        .output()
        .expect("runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn sweep_scene_writes_only_the_scene_columns() {
    let dir = std::env::temp_dir().join(format!("mechgen-scenes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for name in mechgen::SCENES {
        let s = mechgen::lookup_scene::<f64>(name).unwrap().info();
        let full = mechgen::lookup::<f64>(&s.mechanism).unwrap().info();
        let mut want = vec![full.inputs[0].name.clone()];
        want.extend(expected_columns(&s));
        for engine in ["generated", "generic"] {
            let csv = dir.join(format!("{name}-{engine}.csv"));
            let (ok, stdout, stderr) = mechgen_bin(&[
                "sweep",
                name,
                "--engine",
                engine,
                "--step",
                "30",
                "--csv",
                csv.to_str().unwrap(),
            ]);
            assert!(ok, "{name} {engine}: {stderr}");
            let text = std::fs::read_to_string(&csv).unwrap();
            let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
            let (cols, tail) = header.split_at(header.len() - 2);
            assert_eq!(cols, want, "{name} {engine}");
            assert_eq!(tail, ["cond", "status"]);
            assert_eq!(text.lines().count(), 14, "{name}: 13 rows");
            assert!(text.lines().skip(1).all(|l| l.ends_with(",ok")), "{text}");
            for c in expected_columns(&s) {
                assert!(stdout.contains(&c), "{name}: table lacks {c}");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn check_lists_each_scene_with_what_it_keeps() {
    let (ok, stdout, _) = mechgen_bin(&["check"]);
    assert!(ok);
    let e = stdout.split("scene sixbar_e_path").nth(1).expect("listed");
    let e: String = e.lines().take(6).collect::<Vec<_>>().join("\n");
    assert!(e.contains("order:    0"), "{e}");
    assert!(e.contains("keeps:    0 [q2, q3]"), "{e}");
    assert!(e.contains("skipped:  1 [q5, q6]"), "{e}");
    assert!(e.contains("points:   E"), "{e}");
    assert!(e.contains("sin/cos:  q2, q3 (read"), "{e}");
    for name in mechgen::SCENES {
        assert!(stdout.contains(&format!("scene {name} ")), "{name}");
    }
}
