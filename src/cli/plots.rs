//! CLI, plots: the motion curves, the mechanism drawing and the animation of a sweep, as SVG
//! files. Drawings come from the structure of the mechanism as the generic engine loaded it
//! (`plot::sweep_frames`), so they work for any mechanism file.

use std::path::{Path, PathBuf};

use mechgen::generic::Generic;
use mechgen::plot::{Frame, drawing_svg, motion_svg, point_paths, sweep_frames};
use mechgen::sweep::Row;
use mechgen::{CoordDesc, Kind, MechanismInfo};

/// How many configurations the drawing shows.
const FRAMES: usize = 4;

/// `--animate DIR`: `DIR/NAME-animation.svg`, the mechanism over every solved row of the sweep
/// (input `index` swept, the other inputs at their values in `x`), with its points' paths.
pub fn write_animation(
    dir: &Path,
    model: &Generic,
    index: usize,
    x: &[f64],
    rows: &[Row],
) -> Result<Vec<PathBuf>, String> {
    let path = mechgen::plot::write_animation(dir, model, x, index, rows)
        .map_err(|e| format!("{}: no animation: {e}", model.name()))?;
    Ok(vec![path])
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
        Err(e) => tell!("mechgen: {}: no motion plot: {e}", info.name),
    }
    let frames = frames(model, index, x, rows);
    if frames.is_empty() {
        tell!("mechgen: {}: no drawing: no row solved", info.name);
    } else {
        let CoordDesc { name, kind, .. } = &info.inputs[index];
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
            Err(e) => tell!("mechgen: {}: no drawing: {e}", info.name),
        }
    }
    Ok(written)
}

/// Up to [`FRAMES`] solved rows, spread evenly over the sweep (the last row left out: over a full
/// turn it repeats the first), drawn from the mechanism's structure.
fn frames(model: &Generic, index: usize, x: &[f64], rows: &[Row]) -> Vec<Frame> {
    let all = sweep_frames(model, x, index, rows);
    let n = all.len();
    if n <= FRAMES {
        return all;
    }
    let picks: Vec<usize> = (0..FRAMES).map(|i| i * n / FRAMES).collect();
    all.into_iter()
        .enumerate()
        .filter(|(i, _)| picks.contains(i))
        .map(|(_, f)| f)
        .collect()
}
