//! CLI, plots: the motion curves and the mechanism drawing of a sweep, as SVG files, and the
//! `--animate` hook. Drawings come from the loop chains of the generic engine, so they work for
//! any mechanism file.

use std::path::{Path, PathBuf};

use mechgen::generic::Generic;
use mechgen::plot::{Frame, drawing_svg, motion_svg, point_paths};
use mechgen::sweep::Row;
use mechgen::{Kind, MechanismInfo};

/// How many configurations the drawing shows.
const FRAMES: usize = 4;

/// `--animate DIR`: an animated SVG of the mechanism over the sweep (input `index` swept, the
/// other inputs at their values in `x`).
///
/// TODO(merge): wire `mechgen::plot::animation_svg` (being written in `src/plot/`) here: build
/// its frames from the solved rows (as [`frames`] does, every solved row), write
/// `DIR/NAME-animation.svg` and return the path. This is the only call site of `--animate`
/// (`mechgen sweep … --animate DIR` and the main job's `--animate DIR` both come here).
pub fn write_animation(
    dir: &Path,
    model: &Generic,
    info: &MechanismInfo,
    index: usize,
    x: &[f64],
    rows: &[Row],
) -> Result<Vec<PathBuf>, String> {
    let _ = (dir, model, info, index, x, rows);
    Err("--animate: animations are not yet available in this build".into())
}

/// Writes `NAME-motion.svg` and `NAME-drawing.svg` into `dir` for a sweep of input `index` (the
/// other inputs at their values in `x`); returns the files written.
pub fn write(
    dir: &Path,
    model: &Generic,
    info: &MechanismInfo,
    index: usize,
    x: &[f64],
    rows: &[Row],
) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let mut written = Vec::new();
    let mut save = |file: String, svg: String| -> Result<(), String> {
        let path = dir.join(file);
        std::fs::write(&path, svg).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        written.push(path);
        Ok(())
    };
    match motion_svg(info, index, rows) {
        Ok(svg) => save(format!("{}-motion.svg", info.name), svg)?,
        Err(e) => eprintln!("mechgen: {}: no motion plot: {e}", info.name),
    }
    let frames = frames(model, info, index, x, rows);
    if frames.is_empty() {
        eprintln!("mechgen: {}: no drawing: no row solved", info.name);
    } else {
        let (name, kind, _) = &info.inputs[index];
        let shown: Vec<String> = frames
            .iter()
            .map(|f| {
                let t = format!("{:.4}", f.input);
                t.trim_end_matches('0').trim_end_matches('.').to_string()
            })
            .collect();
        let unit = if *kind == Kind::Angle { " deg" } else { "" };
        let title = format!(
            "{}: {name} = {}{unit} (first in bold)",
            info.name,
            shown.join(", ")
        );
        match drawing_svg(&title, &frames, &point_paths(info, rows)) {
            Ok(svg) => save(format!("{}-drawing.svg", info.name), svg)?,
            Err(e) => eprintln!("mechgen: {}: no drawing: {e}", info.name),
        }
    }
    Ok(written)
}

/// Up to [`FRAMES`] solved rows, spread evenly over the sweep (the last row left out: over a full
/// turn it repeats the first), drawn from the loop chains.
fn frames(
    model: &Generic,
    info: &MechanismInfo,
    index: usize,
    x: &[f64],
    rows: &[Row],
) -> Vec<Frame> {
    let solved: Vec<&Row> = rows.iter().filter(|r| r.result.is_ok()).collect();
    let picks: Vec<&Row> = if solved.len() <= FRAMES {
        solved
    } else {
        (0..FRAMES)
            .map(|i| solved[i * solved.len() / FRAMES])
            .collect()
    };
    let angle = info.inputs[index].1 == Kind::Angle;
    picks
        .into_iter()
        .filter_map(|row| {
            let s = row.result.as_ref().ok()?;
            let mut x = x.to_vec();
            x[index] = row.input;
            let chains = model.chains(&x, &s.q).ok()?;
            let mut frame = Frame {
                input: if angle {
                    row.input.to_degrees()
                } else {
                    row.input
                },
                ..Frame::default()
            };
            for ch in chains {
                let g = ch.ground_segments.min(ch.vertices.len() - 1);
                let pivot = ch.vertices[g];
                if !frame.ground.contains(&pivot) {
                    frame.ground.push(pivot);
                }
                if ch.vertices.len() > g + 1 {
                    frame.links.push(ch.vertices[g..].to_vec());
                }
            }
            frame.points = info
                .points
                .iter()
                .zip(&s.points)
                .map(|(n, p)| (n.clone(), p.position))
                .collect();
            Some(frame)
        })
        .collect()
}
