//! Writes motion and drawing SVGs of some compiled-in mechanisms, swept over a full turn, into a
//! folder: `cargo run --example plots -- OUT_DIR`.

use std::error::Error;
use std::f64::consts::PI;
use std::path::Path;

use mechgen::MechanismInfo;
use mechgen::plot::{Frame, drawing_svg, motion_svg, point_paths};
use mechgen::sweep::{Continuation, Row, Solved, sweep};

fn param(info: &MechanismInfo, name: &str) -> Result<f64, String> {
    let p = info.params.iter().find(|p| p.0 == name);
    p.map(|p| p.2)
        .ok_or_else(|| format!("{}: no param {name}", info.name))
}

fn point(info: &MechanismInfo, s: &Solved, name: &str) -> Result<[f64; 2], String> {
    let i = info.points.iter().position(|p| p == name);
    i.and_then(|i| s.points.get(i))
        .map(|p| p.position)
        .ok_or_else(|| format!("{}: no point {name}", info.name))
}

fn unknown(info: &MechanismInfo, s: &Solved, name: &str) -> Result<f64, String> {
    let i = info.unknowns.iter().position(|u| u.0 == name);
    i.and_then(|i| s.q.get(i).copied())
        .ok_or_else(|| format!("{}: no unknown {name}", info.name))
}

fn at(origin: [f64; 2], length: f64, angle: f64) -> [f64; 2] {
    [
        origin[0] + length * angle.cos(),
        origin[1] + length * angle.sin(),
    ]
}

/// The links, pivots and labelled joints of one solved row (input `x` in radians).
fn frame(info: &MechanismInfo, x: f64, s: &Solved) -> Result<Frame, String> {
    let named =
        |names: &[(&str, [f64; 2])]| names.iter().map(|(n, p)| (n.to_string(), *p)).collect();
    let input = x.to_degrees();
    match info.name.as_str() {
        "four_bar" | "rocker_four_bar" => {
            let (a, d) = ([0.0, 0.0], [param(info, "l4")?, 0.0]);
            let (b, c) = (point(info, s, "B")?, point(info, s, "C")?);
            let mut links = vec![vec![a, b, c, d]];
            let mut points = vec![("A", a), ("B", b), ("C", c), ("D", d)];
            if let Ok(p) = point(info, s, "P") {
                links.push(vec![b, p, c]);
                points.push(("P", p));
            }
            Ok(Frame {
                input,
                links,
                ground: vec![a, d],
                points: named(&points),
            })
        }
        "sixbar" => {
            let (a, d) = ([0.0, 0.0], [param(info, "l4")?, 0.0]);
            let g = [param(info, "xg")?, param(info, "yg")?];
            let b = at(a, param(info, "l1")?, x);
            let c = at(d, param(info, "l3")?, unknown(info, s, "q3")?);
            let e = point(info, s, "E")?;
            let f = at(g, param(info, "l6")?, unknown(info, s, "q6")?);
            let links = vec![vec![a, b, c, d], vec![b, e, c], vec![e, f, g]];
            let points = [
                ("A", a),
                ("B", b),
                ("C", c),
                ("D", d),
                ("E", e),
                ("F", f),
                ("G", g),
            ];
            Ok(Frame {
                input,
                links,
                ground: vec![a, d, g],
                points: named(&points),
            })
        }
        "shaper" => {
            let (a, c) = ([0.0, param(info, "lAC")?], [0.0, 0.0]);
            let b = at(a, param(info, "l1")?, x);
            let (d, e) = (point(info, s, "D")?, point(info, s, "E")?);
            let links = vec![vec![a, b], vec![c, b, d], vec![d, e]];
            let points = [("A", a), ("B", b), ("C", c), ("D", d), ("E", e)];
            Ok(Frame {
                input,
                links,
                ground: vec![a, c],
                points: named(&points),
            })
        }
        other => Err(format!("no drawing for {other}")),
    }
}

fn main() -> Result<(), Box<dyn Error>> {
    let out = std::env::args().nth(1).ok_or("usage: plots OUT_DIR")?;
    let out = Path::new(&out);
    std::fs::create_dir_all(out)?;
    for name in ["four_bar", "shaper", "sixbar", "rocker_four_bar"] {
        let k = mechgen::lookup::<f64>(name).ok_or(format!("{name} is not compiled in"))?;
        let info = k.info();
        let kind = info.inputs.first().ok_or("no input")?.1;
        let values: Vec<f64> = (0..=360).map(|i| f64::from(i).to_radians()).collect();
        let rows: Vec<Row> = sweep(
            k.as_ref(),
            0,
            &values,
            1.0,
            &Continuation::for_input(kind, 2.0 * PI),
        );
        std::fs::write(
            out.join(format!("{name}-motion.svg")),
            motion_svg(&info, 0, &rows)?,
        )?;

        // Four frames, every 90 degrees, where the row solved.
        let frames = rows
            .iter()
            .step_by(90)
            .take(4)
            .filter_map(|r| r.result.as_ref().ok().map(|s| frame(&info, r.input, s)))
            .collect::<Result<Vec<_>, _>>()?;
        let title = format!(
            "{name}: {} every 90 deg, point paths over a turn",
            info.inputs[0].0
        );
        let svg = drawing_svg(&title, &frames, &point_paths(&info, &rows))?;
        std::fs::write(out.join(format!("{name}-drawing.svg")), svg)?;
        println!("{name}: {} rows, {} frames", rows.len(), frames.len());
    }
    Ok(())
}
