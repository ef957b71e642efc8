//! A scene whose mechanism has a length param (1e12) that the scene does not read (issue 17): the
//! generated scene's tolerances are relative to the length params it reads, and so must the
//! generic engine's be. Over a sweep of the rocker four-bar through both dead points (±135.95°),
//! with closed forms and with Newton, both engines give the same status on every row and the same
//! outputs within 1e-13 of the row's largest (the same arithmetic: in fact bit for bit); past the
//! dead points both say `Unassemblable` (with the whole mechanism's 1e12 as the scale, the generic
//! engine once accepted rows 2 degrees past a dead point).

use mechgen::{DynScene, InputMotion, SolveError, SolveOptions};
use mechgen_odd_files::unread;

#[test]
fn a_scene_that_reads_no_huge_param_solves_alike_on_both_engines() {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/unread.toml")).expect("file");
    let mechanisms = mechgen::generic::load("unread.toml", &text).expect("loads");
    let generic = mechanisms[0].scene("rocker_only").expect("scene");
    let generated = unread::lookup_scene::<f64>("rocker_only").expect("compiled in");
    let (_, start) = unread::far_rocker::FarRocker::<f64>::start();
    for closed_forms in [true, false] {
        let options = SolveOptions {
            closed_forms,
            ..SolveOptions::default()
        };
        let mut past = 0;
        for direction in [1.0, -1.0] {
            let mut guess = start.to_array().to_vec();
            for i in 0..=360 {
                let x = [direction * f64::from(i) * 0.5f64.to_radians()];
                let input = InputMotion::new(&x[..], &[1.0][..], &[0.0][..]);
                let ra = generated.solve(input, &guess, &options);
                let rb = generic.solve(input, &guess, &options);
                let at = format!(
                    "q1 = {:.1} deg, closed forms {closed_forms}",
                    x[0].to_degrees()
                );
                match (&ra, &rb) {
                    (Ok(sa), Ok(sb)) => {
                        let (a, b) = (&sa.out, &sb.out);
                        // Relative to the row's largest output (rates grow without bound at the
                        // dead points).
                        let scale = b.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                        for (u, v) in a.iter().zip(b) {
                            assert!((u - v).abs() <= 1e-13 * scale, "{at}: {a:?} {b:?}");
                        }
                        guess.clone_from(&sa.q);
                    }
                    (Err(ea), Err(eb)) => {
                        assert_eq!(ea.status(), eb.status(), "{at}: {ea:?} {eb:?}");
                        past += usize::from(matches!(ea, SolveError::Unassemblable { .. }));
                    }
                    _ => panic!("{at}: generated {ra:?}, generic {rb:?}"),
                }
            }
        }
        // Both sides of the turn end at a dead point: 136° to 180° fail on each.
        assert!(past >= 2 * 80, "{past} rows past the dead points");
    }
}
