//! Scenes (issue 12) on the compiled-in file: outputs equal to the full solver's over full
//! sweeps (both engines, f64 and f32), the columns of interfaces.md, ticks, the registry, and
//! `mechgen sweep SCENE` / `check` on the command line.

mod common;

use common::scenes::{check_compiled_in_scenes, expected_columns, full_sweep};
use mechgen::{InputMotion, Scene, SceneVisitor, SolveOptions};

#[test]
fn scene_outputs_equal_the_full_solvers() {
    assert!(!mechgen::SCENES.is_empty(), "the default file has scenes");
    let fails = check_compiled_in_scenes();
    assert!(fails.is_empty(), "{}", fails.join("\n"));
}

/// Ticks a scene along its mechanism's sweep and compares each tick's outputs with the full
/// solver at the same input (Newton blocks converge from different guesses: 1e-9 relative).
struct Ticks {
    fails: Vec<String>,
    visited: Vec<&'static str>,
}

impl SceneVisitor<f64> for Ticks {
    fn visit<S: Scene<f64> + 'static>(&mut self, scene: &S) {
        self.visited.push(S::NAME);
        let info = scene.info();
        let full = mechgen::lookup::<f64>(info.mechanism).unwrap();
        let rows = full_sweep(full.as_ref());
        let options = SolveOptions::default();
        let mut tick: Option<S::Tick> = None;
        for r in rows.iter() {
            let Ok(solved) = &r.result else { break };
            let mut x = S::X::zeros();
            let (mut xd, xdd) = (S::X::zeros(), S::X::zeros());
            x.as_mut().copy_from_slice(&[r.input]);
            xd.as_mut()[0] = 1.0;
            let input = InputMotion::new(x, xd, xdd);
            let outputs = match &mut tick {
                None => {
                    let mut q = S::Q::zeros();
                    q.as_mut().copy_from_slice(&solved.q);
                    let t = scene.tick_start(&input, &q, &options).unwrap();
                    tick.insert(t)
                }
                Some(t) => {
                    scene.tick(t, &input, &options).unwrap();
                    t
                }
            };
            let got = scene.outputs(outputs);
            let mut q = S::Q::zeros();
            q.as_mut().copy_from_slice(&solved.q);
            let (want, _) = scene.solve(&input, &mut q, &options).unwrap();
            for (c, (a, b)) in got.as_ref().iter().zip(want.as_ref()).enumerate() {
                if (a - b).abs() > 1e-9 * b.abs().max(1.0) {
                    self.fails.push(format!(
                        "{} tick at {}: column {c}: {a} vs {b}",
                        S::NAME,
                        r.input
                    ));
                }
            }
        }
    }
}

use mechgen::Array;

#[test]
fn scene_ticks_follow_the_sweep() {
    let mut v = Ticks {
        fails: Vec::new(),
        visited: Vec::new(),
    };
    mechgen::visit_scenes(&mut v);
    assert_eq!(v.visited, mechgen::SCENES);
    assert!(v.fails.is_empty(), "{}", v.fails.join("\n"));
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
    let (out, _, _) = scene.solve(&input, &q, &options).unwrap();
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
    for name in mechgen::SCENES {
        assert!(stdout.contains(&format!("scene {name} ")), "{name}");
    }
}
