//! Frames of a sweep drawn from the mechanism's structure (features `plot` and `runtime`): every
//! solved row of a [`Generic`] mechanism as a [`Frame`] (bodies, ground pivots, sliders), for
//! `drawing_svg` and `animation_svg`; `write_animation` writes the animation file of a sweep. A
//! guide fixed to the ground spans its block's whole travel over the sweep, so it stands still
//! from frame to frame.

use std::path::{Path, PathBuf};

use crate::generic::{Generic, Sketch, SliderAt};
use crate::sweep::Row;
use mechgen_runtime::{CoordDesc, DynMechanism, Kind};

use super::animation::short;
use super::drawing::point_paths;
use super::symbols::{Frame, Slider};
use super::{PlotError, animation_svg};

/// How far a guide runs past its block's travel, as a share of the mechanism's size.
const GUIDE_MARGIN: f64 = 0.08;

/// One frame per solved row of a sweep of input `input`, the other inputs held at `x` (whose
/// entry `input` is replaced by each row's value); failed rows give none. A frame's input is in
/// degrees for an angle input. Empty when `x` or `input` do not fit the mechanism.
pub fn sweep_frames(model: &Generic, x: &[f64], input: usize, rows: &[Row]) -> Vec<Frame> {
    let info = DynMechanism::<f64>::info(model);
    let Some(CoordDesc { kind, .. }) = info.inputs.get(input) else {
        return Vec::new();
    };
    let angle = *kind == Kind::Angle;
    let mut x = x.to_vec();
    let sketches: Vec<(&Row, Sketch)> = rows
        .iter()
        .filter_map(|row| {
            let s = row.result.as_ref().ok()?;
            *x.get_mut(input)? = row.input;
            Some((row, model.sketch(&x, &s.q).ok()?))
        })
        .collect();
    let size = mechanism_size(sketches.iter().map(|s| &s.1));
    let margin = GUIDE_MARGIN * size;
    // Ground guides: the travel of their block along the guide, over every frame.
    let slider_count = sketches.first().map_or(0, |s| s.1.sliders.len());
    // A ground guide's base is a point of the ground: the first frame's, in every frame.
    let bases: Vec<[f64; 2]> = sketches
        .first()
        .map_or(Vec::new(), |s| s.1.sliders.iter().map(|s| s.base).collect());
    let mut travel = vec![(f64::INFINITY, f64::NEG_INFINITY); slider_count];
    for (_, sk) in &sketches {
        if sk.sliders.len() != slider_count {
            continue;
        }
        for ((t, s), base) in travel.iter_mut().zip(&sk.sliders).zip(&bases) {
            let along = along(*base, s.block, s.direction);
            if along.is_finite() {
                *t = (t.0.min(along), t.1.max(along));
            }
        }
    }
    // A rail lies on the guide's right: run each ground guide so the links at its block lie
    // mostly on its left, and the rail on the side they do not cross.
    let mut left = vec![0.0; slider_count];
    for (_, sk) in sketches
        .iter()
        .filter(|s| s.1.sliders.len() == slider_count)
    {
        for (side, s) in left.iter_mut().zip(&sk.sliders) {
            *side += side_of_links(&sk.links, s.block, s.direction, 1e-9 * size);
        }
    }
    sketches
        .into_iter()
        .map(|(row, sk)| {
            let same_shape = sk.sliders.len() == slider_count;
            let sliders = sk
                .sliders
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    let base = match bases.get(i) {
                        Some(b) if s.ground && same_shape => *b,
                        _ => s.base,
                    };
                    let s = SliderAt { base, ..*s };
                    let at = |t: f64| {
                        [
                            s.base[0] + t * s.direction[0],
                            s.base[1] + t * s.direction[1],
                        ]
                    };
                    let t = along(s.base, s.block, s.direction);
                    let (lo, hi) = match travel.get(i) {
                        Some(&(lo, hi)) if s.ground && same_shape && lo <= hi => {
                            (lo - margin, hi + margin)
                        }
                        // A moving guide: from its base on the body past the block.
                        _ if t >= 0.0 => (0.0, t + margin),
                        _ => (t - margin, 0.0),
                    };
                    let flip = s.ground && left.get(i).is_some_and(|l| *l < 0.0);
                    Slider {
                        guide: if flip {
                            [at(hi), at(lo)]
                        } else {
                            [at(lo), at(hi)]
                        },
                        block: s.block,
                        ground: s.ground,
                    }
                })
                .collect();
            let points = match &row.result {
                Ok(s) => info
                    .points
                    .iter()
                    .zip(&s.points)
                    .map(|(n, p)| (n.clone(), p.position))
                    .collect(),
                Err(_) => Vec::new(),
            };
            Frame {
                input: if angle {
                    row.input.to_degrees()
                } else {
                    row.input
                },
                links: sk.links,
                ground: sk.pivots,
                points,
                sliders,
            }
        })
        .collect()
}

/// How many of the links' joints next to `block` lie left of `direction` through it, less how
/// many lie right.
fn side_of_links(links: &[Vec<[f64; 2]>], block: [f64; 2], direction: [f64; 2], tol: f64) -> f64 {
    let mut side = 0.0;
    for link in links {
        for (i, p) in link.iter().enumerate() {
            if (p[0] - block[0]).hypot(p[1] - block[1]) > tol {
                continue;
            }
            let next = [i.checked_sub(1).map(|k| link[k]), link.get(i + 1).copied()];
            for q in next.into_iter().flatten() {
                let cross = direction[0] * (q[1] - block[1]) - direction[1] * (q[0] - block[0]);
                if cross.is_finite() && cross != 0.0 {
                    side += cross.signum();
                }
            }
        }
    }
    side
}

/// The distance from `base` to `block` along `direction`.
fn along(base: [f64; 2], block: [f64; 2], direction: [f64; 2]) -> f64 {
    (block[0] - base[0]) * direction[0] + (block[1] - base[1]) * direction[1]
}

/// The larger side of the box around every joint of every sketch (1 when there is none).
fn mechanism_size<'a>(sketches: impl Iterator<Item = &'a Sketch>) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for sk in sketches {
        let joints = sk.links.iter().flatten().chain(&sk.pivots);
        let blocks = sk.sliders.iter().flat_map(|s| [&s.base, &s.block]);
        for p in joints.chain(blocks) {
            for k in 0..2 {
                if p[k].is_finite() {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
    }
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    if size > 0.0 && size.is_finite() {
        size
    } else {
        1.0
    }
}

/// Writes `NAME-animation.svg` into `dir` (created if missing): the mechanism over the solved rows
/// of a sweep of input `input` (the other inputs held at `x`), failed rows skipped, with the paths
/// of its points. Returns the file written; `NoData` when no row solved.
pub fn write_animation(
    dir: &Path,
    model: &Generic,
    x: &[f64],
    input: usize,
    rows: &[Row],
) -> Result<PathBuf, PlotError> {
    let info = DynMechanism::<f64>::info(model);
    let frames = sweep_frames(model, x, input, rows);
    let (Some(first), Some(last), Some(CoordDesc { name, kind, .. })) =
        (frames.first(), frames.last(), info.inputs.get(input))
    else {
        return Err(PlotError::NoData);
    };
    let unit = if *kind == Kind::Angle { " deg" } else { "" };
    let title = format!(
        "{}: {name} from {} to {}{unit}, {} frames",
        info.name,
        short(first.input),
        short(last.input),
        frames.len()
    );
    let svg = animation_svg(&title, (name, unit), &frames, &point_paths(&info, rows))?;
    let path = dir.join(format!("{}-animation.svg", info.name));
    let fail = |e: std::io::Error| PlotError::Write(path.display().to_string(), e.to_string());
    std::fs::create_dir_all(dir).map_err(fail)?;
    std::fs::write(&path, svg).map_err(fail)?;
    Ok(path)
}
