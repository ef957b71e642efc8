//! The animated SVG of a sweep (`plot::animation_svg`, `plot::write_animation`): valid XML, one
//! frame group per solved row shown in turn by a discrete SMIL animation, failed rows skipped,
//! point paths split at them, no non-finite number, a bounded size.
#![cfg(all(feature = "plot", feature = "runtime"))]

use std::path::{Path, PathBuf};

use mechgen::generic::{self, Generic};
use mechgen::plot::{Frame, PlotError, animation_svg, point_paths, sweep_frames, write_animation};
use mechgen::sweep::{Continuation, Row, sweep};
use mechgen::{DynMechanism, Kind, MechanismInfo, SolveError};

fn compiled_in(name: &str) -> Generic {
    let all = generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE).expect("source");
    all.into_iter()
        .find(|m| m.name() == name)
        .unwrap_or_else(|| panic!("{name} in the default file"))
}

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

fn fail(row: &mut Row) {
    row.result = Err(SolveError::Unassemblable {
        block: 0,
        residual: 1.0,
        iterations: 6,
    });
}

/// Parses the SVG and checks its frames: `n` groups of class `f`, the first visible and the
/// others hidden, each (when n > 1) with one discrete visibility animation whose keyTimes start
/// at 0, rise, stay in [0, 1] and switch it on at i/n. Returns the document's text for more checks.
fn check_frames(svg: &str, n: usize) {
    for bad in ["NaN", "inf"] {
        assert!(!svg.contains(bad), "`{bad}` in the SVG");
    }
    let doc = roxmltree::Document::parse(svg).expect("well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    assert_eq!(
        root.tag_name().namespace(),
        Some("http://www.w3.org/2000/svg")
    );
    assert!(doc.descendants().all(|e| e.tag_name().name() != "script"));
    let frames: Vec<_> = doc
        .descendants()
        .filter(|e| e.has_tag_name("g") && e.attribute("class") == Some("f"))
        .collect();
    assert_eq!(frames.len(), n);
    let mut durations = Vec::new();
    for (i, g) in frames.iter().enumerate() {
        let shown = if i == 0 { "visible" } else { "hidden" };
        assert_eq!(g.attribute("visibility"), Some(shown), "frame {i}");
        let animations: Vec<_> = g.children().filter(|c| c.has_tag_name("animate")).collect();
        if n == 1 {
            assert!(animations.is_empty());
            continue;
        }
        assert_eq!(animations.len(), 1, "frame {i}");
        let a = animations[0];
        assert_eq!(a.attribute("attributeName"), Some("visibility"));
        assert_eq!(a.attribute("calcMode"), Some("discrete"));
        assert_eq!(a.attribute("repeatCount"), Some("indefinite"));
        durations.push(a.attribute("dur").expect("dur").to_string());
        let times: Vec<f64> = a
            .attribute("keyTimes")
            .expect("keyTimes")
            .split(';')
            .map(|t| t.parse().expect("a number"))
            .collect();
        let values: Vec<&str> = a.attribute("values").expect("values").split(';').collect();
        assert_eq!(times.len(), values.len());
        assert_eq!(times[0], 0.0);
        assert!(times.windows(2).all(|w| w[0] < w[1]) && times.iter().all(|t| *t <= 1.0));
        // Visible from i/n (to (i + 1)/n).
        let on = values.iter().position(|v| *v == "visible").expect("shown");
        assert!(
            (times[on] - i as f64 / n as f64).abs() < 1e-6,
            "frame {i}: {times:?}"
        );
        if let Some(t) = times.get(on + 1) {
            assert!((t - (i + 1) as f64 / n as f64).abs() < 1e-6);
        }
    }
    durations.dedup();
    assert!(durations.len() <= 1, "one duration for all frames");
}

#[test]
fn one_frame_per_solved_row_and_paths_split_at_failed_rows() {
    let model = compiled_in("slider_crank");
    let (info, mut rows) = sweep_degrees(&model, 0, 360, 10);
    for i in [5, 6, 20] {
        fail(&mut rows[i]);
    }
    let frames = sweep_frames(&model, &[0.0], 0, &rows);
    assert_eq!(frames.len(), rows.len() - 3);
    let svg = animation_svg(
        "slider_crank",
        ("q1", " deg"),
        &frames,
        &point_paths(&info, &rows),
    )
    .expect("animation");
    check_frames(&svg, rows.len() - 3);
    // The path of B (first colour) in three runs: before 5, 7..19, after 20.
    assert_eq!(
        svg.matches("stroke=\"#0072B2\" stroke-width=\"2\"").count(),
        3 + 1
    );
    // Every frame has its block, and the rail is drawn once.
    assert_eq!(svg.matches("class=\"k\"").count(), frames.len());
    // Failed rows (50, 60 and 200 deg) have no frame.
    assert!(svg.contains("q1 = 40 deg") && svg.contains("q1 = 70 deg"));
    for gone in ["q1 = 50 deg", "q1 = 60 deg", "q1 = 200 deg"] {
        assert!(!svg.contains(gone), "{gone}");
    }
    assert!(svg.contains("path of M"));
}

#[test]
fn write_animation_writes_the_file_and_reports_no_data() {
    let model = compiled_in("shaper");
    let (_, rows) = sweep_degrees(&model, 0, 360, 30);
    let dir: PathBuf =
        std::env::temp_dir().join(format!("mechgen-animation-{}", std::process::id()));
    let path = write_animation(&dir, &model, &[0.0], 0, &rows).expect("written");
    assert_eq!(path, dir.join("shaper-animation.svg"));
    let svg = std::fs::read_to_string(&path).expect("read back");
    check_frames(&svg, rows.len());
    assert!(svg.contains("shaper: q1 from 0 to 360 deg, 13 frames"));

    let mut failed = rows.clone();
    failed.iter_mut().for_each(fail);
    assert_eq!(
        write_animation(&dir, &model, &[0.0], 0, &failed),
        Err(PlotError::NoData)
    );
    // A file where the folder should be: an error that names it, no panic.
    let blocked = dir.join("shaper-animation.svg").join("x");
    let e = write_animation(&blocked, &model, &[0.0], 0, &rows).expect_err("not a folder");
    assert!(
        matches!(&e, PlotError::Write(p, _) if p.contains("shaper-animation.svg")),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_jansen_leg_over_a_turn_stays_small() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/jansen.toml");
    let model = generic::load_file(&path).expect("loads").remove(0);
    let (info, rows) = sweep_degrees(&model, 0, 360, 1);
    let frames = sweep_frames(&model, &[0.0], 0, &rows);
    assert_eq!(frames.len(), 361);
    let svg = animation_svg(
        "jansen",
        ("q1", " deg"),
        &frames,
        &point_paths(&info, &rows),
    )
    .expect("animation");
    check_frames(&svg, 361);
    assert!(svg.len() < 1500 * 361, "{} bytes", svg.len());
    // Coordinates are rounded to 0.1 px.
    let doc = roxmltree::Document::parse(&svg).expect("xml");
    for e in doc.descendants().filter(|e| e.has_tag_name("circle")) {
        for a in ["cx", "cy"] {
            let v = e.attribute(a).expect("coordinate");
            assert!(v.split('.').nth(1).is_none_or(|d| d.len() == 1), "{v}");
        }
    }
}

#[test]
fn single_frames_non_finite_values_and_nothing_to_draw() {
    let frame = Frame {
        input: f64::NAN,
        links: vec![
            vec![[0.0, 0.0], [1.0, f64::INFINITY], [1.0, 1.0]],
            vec![[0.0, 0.0], [1.0, 0.0]],
        ],
        ground: vec![[0.0, 0.0], [f64::NAN, 0.0]],
        points: vec![("P".into(), [f64::NAN, 1.0])],
        ..Frame::default()
    };
    let paths = vec![(
        "P".to_string(),
        vec![[0.0, 0.0], [f64::NAN, 0.0], [1.0, 1.0], [2.0, 1.0]],
    )];
    let svg = animation_svg("a <title> & more", ("x", ""), &[frame], &paths).expect("svg");
    check_frames(&svg, 1);
    assert!(svg.contains("a &lt;title&gt; &amp; more"));
    assert_eq!(
        animation_svg("none", ("x", ""), &[], &paths),
        Err(PlotError::NoData)
    );
    let empty = Frame {
        links: vec![vec![[f64::NAN, 0.0]]],
        ..Frame::default()
    };
    assert_eq!(
        animation_svg("none", ("x", ""), &[empty], &[]),
        Err(PlotError::NoData)
    );
}
