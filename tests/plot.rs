//! SVG plots (`mechgen::plot`) from real sweeps of compiled-in mechanisms: well-formed output,
//! labels, curves split at failed rows, no NaN, equal axis scaling of drawings.
#![cfg(feature = "plot")]

use mechgen::plot::{Frame, PlotError, drawing_svg, motion_svg, point_paths};
use mechgen::sweep::{Continuation, Row, Solved, sweep};
use mechgen::{Kind, MechanismInfo, SolveError};

/// Sweeps the first input of `name` over `from..=to` degrees in `step` degree steps at rate 1.
fn sweep_degrees(name: &str, from: i32, to: i32, step: usize) -> (MechanismInfo, Vec<Row>) {
    let k = mechgen::lookup::<f64>(name).unwrap_or_else(|| panic!("{name}: compiled in"));
    let info = k.info();
    assert_eq!(info.inputs[0].kind, Kind::Angle);
    let values: Vec<f64> = (from..=to)
        .step_by(step)
        .map(|d| f64::from(d).to_radians())
        .collect();
    let c = Continuation::for_input(Kind::Angle, f64::from(to - from).to_radians());
    let rows = sweep(k.as_ref(), 0, &values, 1.0, &c);
    (info, rows)
}

fn param(info: &MechanismInfo, name: &str) -> f64 {
    info.params
        .iter()
        .find(|p| p.name == name)
        .expect("param")
        .value
}

fn point(info: &MechanismInfo, s: &Solved, name: &str) -> [f64; 2] {
    let i = info.points.iter().position(|p| p == name).expect("point");
    s.points[i].position
}

fn unknown(info: &MechanismInfo, s: &Solved, name: &str) -> f64 {
    s.q[info
        .unknowns
        .iter()
        .position(|u| u.name == name)
        .expect("unknown")]
}

/// The plotted curves of one colour at stroke width 2 (the series of one unknown or path).
fn curves(svg: &str, colour: &str) -> usize {
    svg.matches(&format!("stroke=\"{colour}\" stroke-width=\"2\""))
        .count()
}

/// Checks the basic shape of an SVG document and the absence of non-finite numbers.
fn well_formed(svg: &str) {
    assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(80)]);
    assert!(svg.trim_end().ends_with("</svg>"));
    assert_eq!(svg.matches("<text").count(), svg.matches("</text>").count());
    for bad in ["NaN", "inf"] {
        assert!(!svg.contains(bad), "`{bad}` in the SVG");
    }
}

const FIRST: &str = "#0072B2";
const SECOND: &str = "#D55E00";

#[test]
fn four_bar_motion_has_three_panels_of_every_unknown() {
    let (info, rows) = sweep_degrees("four_bar", 0, 360, 5);
    assert!(rows.iter().all(|r| r.result.is_ok()));
    let svg = motion_svg(&info, 0, &rows).expect("plot");
    well_formed(&svg);
    for label in [
        "four_bar",
        ">\nq2\n<",
        ">\nq3\n<",
        "q1 [deg]",
        "position [deg]",
        "velocity [deg/s]",
        "acceleration [deg/s²]",
    ] {
        assert!(svg.contains(label), "no `{label}`");
    }
    // One unbroken curve per unknown in each of the three panels.
    assert_eq!(curves(&svg, FIRST), 3);
    assert_eq!(curves(&svg, SECOND), 3);
    assert!(!svg.contains("no solution"));
}

#[test]
fn shaper_motion_puts_angles_and_lengths_in_separate_columns() {
    let (info, rows) = sweep_degrees("shaper", 0, 360, 10);
    let svg = motion_svg(&info, 0, &rows).expect("plot");
    well_formed(&svg);
    for label in [
        "angles: position",
        "lengths: position",
        "angles: acceleration",
        "lengths: velocity",
        "position [units]",
        "acceleration [units/s²]",
        "velocity [deg/s]",
    ] {
        assert!(svg.contains(label), "no `{label}`");
    }
    // Four unknowns, three panels each.
    let series = ["#0072B2", "#D55E00", "#009E73", "#CC79A7"];
    assert_eq!(series.map(|c| curves(&svg, c)), [3; 4]);
}

#[test]
fn failed_rows_past_the_dead_point_are_a_shaded_gap() {
    let (info, rows) = sweep_degrees("rocker_four_bar", 0, 360, 2);
    let failed = rows.iter().filter(|r| r.result.is_err()).count();
    assert!(failed > 100, "{failed} failed rows");
    assert!(rows[..60].iter().all(|r| r.result.is_ok()));
    let svg = motion_svg(&info, 0, &rows).expect("plot");
    well_formed(&svg);
    assert!(svg.contains("no solution"));
    // Background, one shading per panel and the legend swatch.
    assert_eq!(svg.matches("<rect").count(), 1 + 3 + 1);
    assert_eq!(curves(&svg, FIRST), 3);
}

#[test]
fn curves_split_at_failed_rows_and_skip_non_finite_values() {
    let (info, mut rows) = sweep_degrees("four_bar", 0, 360, 2);
    rows[60].result = Err(SolveError::Unassemblable {
        block: 0,
        residual: f64::NAN,
        iterations: 3,
    });
    if let Ok(s) = &mut rows[120].result {
        s.q[0] = f64::NAN;
        s.qdd[1] = f64::INFINITY;
    }
    let svg = motion_svg(&info, 0, &rows).expect("plot");
    well_formed(&svg);
    // q2: position split twice (failure, NaN), velocity and acceleration once.
    assert_eq!(curves(&svg, FIRST), 3 + 2 + 2);
    // q3: acceleration split twice (failure, inf).
    assert_eq!(curves(&svg, SECOND), 2 + 2 + 3);
    assert!(svg.contains("no solution"));
}

#[test]
fn motion_errors_and_empty_sweeps() {
    let (info, rows) = sweep_degrees("four_bar", 0, 90, 10);
    assert_eq!(
        motion_svg(&info, 1, &rows),
        Err(PlotError::BadInput {
            index: 1,
            inputs: 1
        })
    );
    assert_eq!(motion_svg(&info, 0, &[]), Err(PlotError::NoData));
    let failed: Vec<Row> = rows
        .iter()
        .map(|r| Row {
            input: r.input,
            result: Err(SolveError::BadLength {
                expected: 2,
                got: 1,
            }),
            stopped: None,
        })
        .collect();
    let svg = motion_svg(&info, 0, &failed).expect("plot of failures");
    well_formed(&svg);
    assert!(svg.contains("no finite values"));
    let message = PlotError::BadInput {
        index: 1,
        inputs: 1,
    }
    .to_string();
    assert!(message.contains("input index 1"));
}

fn four_bar_frame(info: &MechanismInfo, input: f64, s: &Solved) -> Frame {
    let (a, d) = ([0.0, 0.0], [param(info, "l4"), 0.0]);
    let (b, c, p) = (
        point(info, s, "B"),
        point(info, s, "C"),
        point(info, s, "P"),
    );
    let named = [("A", a), ("B", b), ("C", c), ("D", d), ("P", p)];
    Frame {
        input: input.to_degrees(),
        links: vec![vec![a, b, c, d], vec![b, p, c]],
        ground: vec![a, d],
        points: named.iter().map(|(n, p)| (n.to_string(), *p)).collect(),
        ..Frame::default()
    }
}

/// The pixel extent (width, height) of the first polyline of `colour`.
fn extent(svg: &str, colour: &str) -> (f64, f64) {
    let at = svg
        .find(&format!("stroke=\"{colour}\" stroke-width=\"2\""))
        .expect("curve");
    let points = &svg[at..];
    let points = &points[points.find("points=\"").expect("points") + 8..];
    let points = &points[..points.find('"').expect("end")];
    let xy: Vec<(f64, f64)> = points
        .split_whitespace()
        .map(|p| {
            let (x, y) = p.split_once(',').expect("x,y");
            (x.parse().expect("x"), y.parse().expect("y"))
        })
        .collect();
    let span = |f: fn(&(f64, f64)) -> f64| {
        let v = xy.iter().map(f);
        v.clone().fold(f64::MIN, f64::max) - v.fold(f64::MAX, f64::min)
    };
    (span(|p| p.0), span(|p| p.1))
}

#[test]
fn four_bar_drawing_is_to_scale_with_paths_and_labels() {
    let (info, rows) = sweep_degrees("four_bar", 0, 360, 2);
    let frames: Vec<Frame> = rows
        .iter()
        .step_by(45)
        .take(4)
        .filter_map(|r| Some(four_bar_frame(&info, r.input, r.result.as_ref().ok()?)))
        .collect();
    assert_eq!(frames.len(), 4);
    let paths = point_paths(&info, &rows);
    assert_eq!(paths.len(), 3);
    let svg = drawing_svg("four_bar", &frames, &paths).expect("drawing");
    well_formed(&svg);
    for label in [
        "path of B",
        "path of P",
        "ground pivot",
        ">\nA\n<",
        ">\nD\n<",
        ">\nP\n<",
        "x [units]",
        "input = 0",
        "3 other inputs",
    ] {
        assert!(svg.contains(label), "no `{label}`");
    }
    // B runs on a circle about A: as wide as high on the page.
    let (w, h) = extent(&svg, FIRST);
    assert!(w > 100.0 && (w - h).abs() <= 0.02 * w, "{w} x {h}");
}

#[test]
fn sixbar_drawing_from_the_coupler_point() {
    let (info, rows) = sweep_degrees("sixbar", 0, 360, 3);
    let (a, d) = ([0.0, 0.0], [param(&info, "l4"), 0.0]);
    let g = [param(&info, "xg"), param(&info, "yg")];
    let at = |o: [f64; 2], l: f64, q: f64| [o[0] + l * q.cos(), o[1] + l * q.sin()];
    let frames: Vec<Frame> = rows
        .iter()
        .step_by(30)
        .take(4)
        .filter_map(|r| {
            let s = r.result.as_ref().ok()?;
            let b = at(a, param(&info, "l1"), r.input);
            let c = at(d, param(&info, "l3"), unknown(&info, s, "q3"));
            let e = point(&info, s, "E");
            let f = at(g, param(&info, "l6"), unknown(&info, s, "q6"));
            Some(Frame {
                input: r.input.to_degrees(),
                links: vec![vec![a, b, c, d], vec![b, e, c], vec![e, f, g]],
                ground: vec![a, d, g],
                points: vec![("E".into(), e), ("F".into(), f), ("G".into(), g)],
                ..Frame::default()
            })
        })
        .collect();
    let mut paths = point_paths(&info, &rows);
    // A gap in the path (as from a failed row) and a stray non-finite point are skipped.
    paths[0].1[10] = [f64::NAN, 1.0];
    paths[0].1.push([f64::INFINITY, f64::NEG_INFINITY]);
    let svg = drawing_svg("sixbar", &frames, &paths).expect("drawing");
    well_formed(&svg);
    for label in ["path of E", ">\nG\n<", "3 other inputs"] {
        assert!(svg.contains(label), "no `{label}`");
    }
    assert_eq!(curves(&svg, FIRST), 2 + 1);
}

#[test]
fn drawing_of_nothing_finite_is_an_error() {
    let frame = Frame {
        input: 0.0,
        links: vec![vec![[f64::NAN, 0.0]]],
        ground: vec![],
        points: vec![],
        ..Frame::default()
    };
    assert_eq!(drawing_svg("x", &[frame], &[]), Err(PlotError::NoData));
    assert_eq!(drawing_svg("x", &[], &[]), Err(PlotError::NoData));
    // One point alone still draws.
    let single = Frame {
        input: 0.0,
        links: vec![],
        ground: vec![[1.0, 2.0]],
        points: vec![("O".into(), [1.0, 2.0])],
        ..Frame::default()
    };
    well_formed(&drawing_svg("one pivot", &[single], &[]).expect("drawing"));
}
