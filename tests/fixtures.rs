//! Whatever mechanism file this build compiled in (`mechanism.toml`, or `MECHGEN_MECHANISM`), every
//! compiled-in mechanism that has an independent reference CSV in `tests/data/` or
//! `tests/fixtures/` is swept and compared with it. CI builds once per fixture file with
//! `MECHGEN_MECHANISM` set and `MECHGEN_EXPECT_COMPARED` naming how many must be compared. Every
//! compiled-in scene is held to its full mechanism (`common::scenes`).

mod common;

use common::engines::check_engines_agree;
use common::scenes::{check_compiled_in_scene_ticks, check_compiled_in_scenes};
use common::{Table, compare};
use mechgen::sweep::{Continuation, sweep};

fn reference_for(name: &str) -> Option<(Table, Option<[f64; 3]>)> {
    let root = env!("CARGO_MANIFEST_DIR");
    for dir in ["tests/data", "tests/fixtures"] {
        let csv = format!("{root}/{dir}/{name}.csv");
        if std::path::Path::new(&csv).exists() {
            let range = std::fs::read_to_string(format!("{root}/{dir}/{name}.sweep"))
                .ok()
                .map(|s| {
                    let v: Vec<f64> = s
                        .split_whitespace()
                        .map(|t| t.parse().expect("number in .sweep"))
                        .collect();
                    [v[0], v[1], v[2]]
                });
            return Some((Table::read(&csv), range));
        }
    }
    None
}

#[test]
fn compiled_in_mechanisms_match_their_references() {
    let mut compared = Vec::new();
    for name in mechgen::MECHANISMS {
        let Some((reference, _)) = reference_for(name) else {
            continue;
        };
        let k = mechgen::lookup::<f64>(name).expect("listed");
        let info = k.info();
        let values = reference.column(&reference.header[0]);
        let span = values.last().copied().unwrap_or(0.0) - values[0];
        let rows = sweep(
            k.as_ref(),
            0,
            &values,
            1.0,
            &Continuation::for_input(info.inputs[0].kind, span),
        );
        for (i, r) in rows.iter().enumerate() {
            assert!(
                r.result.is_ok(),
                "{name}: row {i} ({}) failed: {:?}",
                r.input,
                r.result
            );
        }
        for (col, err) in compare(&info, &rows, &reference) {
            assert!(err <= 1e-10, "{name}.{col}: error {err:e}");
        }
        compared.push(name);
    }
    eprintln!("compared with references: {compared:?}");
    if let Ok(n) = std::env::var("MECHGEN_EXPECT_COMPARED") {
        let n: usize = n.parse().expect("MECHGEN_EXPECT_COMPARED is a number");
        assert_eq!(
            compared.len(),
            n,
            "expected {n} mechanisms compared, got {compared:?}"
        );
    }
}

#[test]
fn compiled_in_scene_ticks_follow_their_sweeps() {
    let fails = check_compiled_in_scene_ticks();
    assert!(fails.is_empty(), "{}", fails.join("\n"));
}

#[test]
fn compiled_in_scenes_equal_their_mechanisms() {
    let fails = check_compiled_in_scenes();
    assert!(fails.is_empty(), "{}", fails.join("\n"));
}

#[test]
fn compiled_in_sensitivities_equal_differences_on_both_engines() {
    let (fails, _) = common::sensitivity::check_sensitivities();
    assert!(fails.is_empty(), "{}", fails.join("\n"));
}

#[test]
fn compiled_in_mechanisms_alike_on_both_engines() {
    let fails = check_engines_agree();
    assert!(fails.is_empty(), "{}", fails.join("\n"));
}

/// Every compiled-in mechanism in SIMD lanes: each lane is its scalar tick, bit for bit
/// (`common::lanes`, fewer cases than `tests/lanes.rs`, on whatever file this build compiled in).
#[test]
fn compiled_in_lanes_are_their_scalar_ticks() {
    let (fails, seen) = common::lanes::check_lanes(4, 200);
    eprintln!("{seen:?}");
    assert!(fails.is_empty(), "{}", fails.join("\n"));
    assert!(seen.compared > 0);
    // Every compiled-in scene too (none in some files).
    let (fails, seen) = common::lanes::check_scene_lanes(3, 200);
    eprintln!("scenes: {seen:?}");
    assert!(fails.is_empty(), "{}", fails.join("\n"));
}
