//! CLI, plots: the motion curves and the mechanism drawing of a sweep, as SVG files. Drawings come
//! from the structure of the mechanism as the generic engine loaded it (`plot::sweep_frames`), so
//! they work for any mechanism file.

use std::path::{Path, PathBuf};

use mechgen::generic::Generic;
use mechgen::plot::{Frame, drawing_svg, motion_svg, point_paths, sweep_frames};
use mechgen::sweep::Row;
use mechgen::{Kind, MechanismInfo};

/// How many configurations the drawing shows.
const FRAMES: usize = 4;

/// Writes `NAME-motion.svg` and `NAME-drawing.svg` into `dir`; returns the files written.
pub fn write(
    dir: &Path,
    model: &Generic,
    info: &MechanismInfo,
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
    match motion_svg(info, 0, rows) {
        Ok(svg) => save(format!("{}-motion.svg", info.name), svg)?,
        Err(e) => eprintln!("mechgen: {}: no motion plot: {e}", info.name),
    }
    let frames = frames(model, info, rows);
    if frames.is_empty() {
        eprintln!("mechgen: {}: no drawing: no row solved", info.name);
    } else {
        let (name, kind, _) = &info.inputs[0];
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
/// turn it repeats the first), drawn from the mechanism's structure.
fn frames(model: &Generic, info: &MechanismInfo, rows: &[Row]) -> Vec<Frame> {
    let x: Vec<f64> = info.inputs.iter().map(|i| i.2).collect();
    let all = sweep_frames(model, &x, 0, rows);
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
