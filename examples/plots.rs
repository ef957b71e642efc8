//! Writes the motion plot, the drawing and the animation of every compiled-in mechanism (and of
//! any mechanism files given), swept over a full turn in 1° steps (or `--step DEG`), into a folder:
//! `cargo run --example plots -- OUT_DIR [--step DEG] [FILE.toml ...]`. Drawings come from each mechanism's
//! structure (`mechgen::plot::sweep_frames`), through the generic engine.

use std::error::Error;
use std::f64::consts::PI;
use std::path::Path;

use mechgen::DynMechanism;
use mechgen::generic::{self, Generic};
use mechgen::plot::{Frame, drawing_svg, motion_svg, point_paths, sweep_frames, write_animation};
use mechgen::sweep::{Continuation, Row, sweep};

/// Four frames spread over the solved rows (a full turn's last row repeats its first).
fn four(frames: Vec<Frame>) -> Vec<Frame> {
    let n = frames.len().saturating_sub(1).max(1);
    let picks: Vec<usize> = (0..4).map(|i| i * n / 4).collect();
    frames
        .into_iter()
        .enumerate()
        .filter(|(i, _)| picks.contains(i))
        .map(|(_, f)| f)
        .collect()
}

fn plot(out: &Path, model: &Generic, steps: u32) -> Result<(), Box<dyn Error>> {
    let info = DynMechanism::<f64>::info(model);
    let name = &info.name;
    let mechgen::CoordDesc {
        name: input, kind, ..
    } = info.inputs.first().ok_or("no input")?;
    let x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
    // A full turn from the start value (a length input: from half its start value to 1.5 times).
    let (from, span) = match kind {
        mechgen::Kind::Angle => (x[0], 2.0 * PI),
        _ => (x[0] * 0.5, x[0].abs().max(1e-9)),
    };
    let values: Vec<f64> = (0..=steps)
        .map(|i| from + span * f64::from(i) / f64::from(steps))
        .collect();
    let c = Continuation::for_input(*kind, span);
    let rows: Vec<Row> = sweep(model, 0, &values, 1.0, &c);
    std::fs::write(
        out.join(format!("{name}-motion.svg")),
        motion_svg(&info, 0, &rows)?,
    )?;
    let frames = four(sweep_frames(model, &x, 0, &rows));
    let title = format!("{name}: {input}, four inputs of the sweep, point paths");
    let svg = drawing_svg(&title, &frames, &point_paths(&info, &rows))?;
    std::fs::write(out.join(format!("{name}-drawing.svg")), svg)?;
    let animation = write_animation(out, model, &x, 0, &rows)?;
    let solved = rows.iter().filter(|r| r.result.is_ok()).count();
    println!(
        "{name}: {solved}/{} rows, {}",
        rows.len(),
        animation.display()
    );
    Ok(())
}

fn main() -> Result<(), Box<dyn Error>> {
    let mut args = std::env::args().skip(1);
    let out = args.next().ok_or("usage: plots OUT_DIR [FILE.toml ...]")?;
    let out = Path::new(&out);
    std::fs::create_dir_all(out)?;
    let mut models = generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)?;
    let mut steps = 360;
    while let Some(arg) = args.next() {
        if arg == "--step" {
            let step: f64 = args.next().ok_or("--step DEG")?.parse()?;
            if !(step > 0.0 && step <= 360.0) {
                return Err("--step must be in (0, 360] degrees".into());
            }
            steps = (360.0 / step).round().max(1.0) as u32;
        } else {
            models.extend(generic::load_file(Path::new(&arg))?);
        }
    }
    for model in &models {
        plot(out, model, steps)?;
    }
    Ok(())
}
