//! Drawing symbols in pixels, shared by `drawing_svg` and its legend: the ground pivot (a hatched
//! triangle), the slider block on its guide (a guide fixed to the ground is a hatched rail the
//! block rests on), the joint; and the legend beside the drawing. Also what a drawing is made of:
//! its frames (links, pivots, points, sliders in file units) and its inks.

use plotters::coord::CoordTranslate;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{FAMILY, PlotError, color, drawing_error, tick_text};

pub(super) const INK: RGBColor = RGBColor(35, 35, 35);
pub(super) const FADED: RGBColor = RGBColor(140, 140, 140);
pub(super) const FADED_ALPHA: f64 = 0.6;

/// One frame of the mechanism drawing, in file units.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Frame {
    /// The input value this frame shows (shown in the legend for the first frame, as given).
    pub input: f64,
    /// Links as polylines: each inner `Vec` a chain of joints (a closed body repeats its first
    /// joint at the end).
    pub links: Vec<Vec<[f64; 2]>>,
    /// Ground pivots.
    pub ground: Vec<[f64; 2]>,
    /// Named points, labelled in the first frame.
    pub points: Vec<(String, [f64; 2])>,
    /// Sliders: blocks on their guides.
    pub sliders: Vec<Slider>,
}

/// A slider block on its guide, in file units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Slider {
    /// The stretch of guide drawn, from end to end (the block is oriented along it). A guide fixed
    /// to the ground is drawn as a rail on its right, looking from the first end to the second.
    pub guide: [[f64; 2]; 2],
    /// The centre of the block (a joint).
    pub block: [f64; 2],
    /// The guide is fixed to the ground (a hatched rail), not part of a moving body.
    pub ground: bool,
}

/// Pixel polygons (filled) and polylines, relative to an anchor point.
#[derive(Default)]
pub(super) struct Shape {
    pub fills: Vec<(Vec<(i32, i32)>, ShapeStyle)>,
    pub lines: Vec<(Vec<(i32, i32)>, ShapeStyle)>,
}

/// Half the length and half the height of a slider block, in pixels.
const BLOCK: (f64, f64) = (15.0, 8.0);

/// Draws `shape` anchored at `at` (in the area's coordinates).
pub(super) fn draw_shape<CT: CoordTranslate>(
    area: &DrawingArea<SVGBackend<'_>, CT>,
    at: CT::From,
    shape: &Shape,
) -> Result<(), PlotError>
where
    CT::From: Clone,
{
    for (points, style) in &shape.fills {
        let e = EmptyElement::at(at.clone()) + Polygon::new(points.clone(), *style);
        area.draw(&e).map_err(drawing_error)?;
    }
    for (points, style) in &shape.lines {
        let e = EmptyElement::at(at.clone()) + PathElement::new(points.clone(), *style);
        area.draw(&e).map_err(drawing_error)?;
    }
    Ok(())
}

/// The ground pivot: a grey triangle under the joint on a hatched ground line.
pub(super) fn pivot() -> Shape {
    let thin = INK.stroke_width(1);
    Shape {
        fills: vec![(
            vec![(0, 0), (-10, 16), (10, 16)],
            RGBColor(200, 200, 200).filled(),
        )],
        lines: vec![
            (vec![(0, 0), (-10, 16), (10, 16), (0, 0)], thin),
            (vec![(-15, 16), (15, 16)], INK.stroke_width(2)),
            (vec![(-12, 22), (-6, 16)], thin),
            (vec![(-3, 22), (3, 16)], thin),
            (vec![(6, 22), (12, 16)], thin),
        ],
    }
}

fn round(p: (f64, f64)) -> (i32, i32) {
    (p.0.round() as i32, p.1.round() as i32)
}

/// The unit vector along `d` (pixels, y down; x when `d` is shorter than a pixel) and its right
/// normal (down the page for a guide running right).
pub(super) fn axes(d: (f64, f64)) -> ((f64, f64), (f64, f64)) {
    let len = d.0.hypot(d.1);
    let u = if len >= 1.0 {
        (d.0 / len, d.1 / len)
    } else {
        (1.0, 0.0)
    };
    (u, (-u.1, u.0))
}

/// A slider's guide running `d` pixels from the anchor (its first end). A guide fixed to the ground
/// is a rail on its right (looking from the first end), a block's half height away from its axis
/// so the block rests on it, hatched further right; a moving guide is a line along its axis.
pub(super) fn guide(d: (f64, f64), ground: bool, style: (RGBColor, f64, u32)) -> Shape {
    let (ink, alpha, width) = style;
    let (len, (u, n)) = (d.0.hypot(d.1), axes(d));
    let at = |t: f64, h: f64| round((t * u.0 + h * n.0, t * u.1 + h * n.1));
    let mut shape = Shape::default();
    if len < 1.0 {
        return shape;
    }
    let offset = if ground { BLOCK.1 } else { 0.0 };
    let line = ink.mix(alpha).stroke_width(width);
    shape
        .lines
        .push((vec![at(0.0, offset), at(len, offset)], line));
    let mut t = 4.0;
    while ground && t <= len {
        let hatch = vec![at(t, offset), at(t - 6.0, offset + 7.0)];
        shape.lines.push((hatch, ink.mix(alpha).stroke_width(1)));
        t += 10.0;
    }
    shape
}

/// A slider block centred on the anchor, its long side along the unit vector `u` (pixels).
pub(super) fn block(u: (f64, f64), style: (RGBColor, f64, u32)) -> Shape {
    let (ink, alpha, width) = style;
    let n = (-u.1, u.0);
    let corners: Vec<(i32, i32)> = [
        (-1.0, -1.0),
        (1.0, -1.0),
        (1.0, 1.0),
        (-1.0, 1.0),
        (-1.0, -1.0),
    ]
    .iter()
    .map(|(a, b)| {
        let (t, h) = (a * BLOCK.0, b * BLOCK.1);
        round((t * u.0 + h * n.0, t * u.1 + h * n.1))
    })
    .collect();
    let fill = RGBColor(225, 225, 225).mix(alpha).filled();
    Shape {
        fills: vec![(corners[..4].to_vec(), fill)],
        lines: vec![(corners, ink.mix(alpha).stroke_width(width))],
    }
}

/// The legend beside the plot: one entry per path, the frames and the symbols.
pub(super) fn draw_legend(
    area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    frames: &[Frame],
    paths: &[(String, Vec<[f64; 2]>)],
) -> Result<(), PlotError> {
    let text = (FAMILY, 16)
        .into_font()
        .color(&INK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let mut y = 80;
    let x = 8;
    let label = |label: &str, y: i32| {
        area.draw(&Text::new(label.to_string(), (x + 40, y), text.clone()))
            .map_err(drawing_error)
    };
    let line = |text: &str, style: ShapeStyle, y: i32| -> Result<(), PlotError> {
        area.draw(&PathElement::new(vec![(x, y), (x + 30, y)], style))
            .map_err(drawing_error)?;
        label(text, y)
    };
    for (i, (name, _)) in paths.iter().enumerate() {
        line(&format!("path of {name}"), color(i).stroke_width(2), y)?;
        y += 28;
    }
    let Some(first) = frames.first() else {
        return Ok(());
    };
    y += 8;
    let input = tick_text(first.input, 1e-3);
    line(&format!("input = {input}"), INK.stroke_width(3), y)?;
    y += 28;
    if frames.len() > 1 {
        let n = frames.len() - 1;
        let text = format!("{n} other input{}", if n == 1 { "" } else { "s" });
        line(&text, FADED.mix(FADED_ALPHA).stroke_width(1), y)?;
        y += 28;
    }
    y += 8;
    if frames.iter().any(|f| !f.ground.is_empty()) {
        let mut small = pivot();
        small.lines.truncate(1);
        draw_shape(area, (x + 15, y - 8), &small)?;
        label("ground pivot", y)?;
        y += 28;
    }
    if frames.iter().any(|f| f.sliders.iter().any(|s| s.ground)) {
        draw_shape(area, (x - 4, y), &guide((38.0, 0.0), true, (INK, 1.0, 2)))?;
        draw_shape(area, (x + 15, y), &block((1.0, 0.0), (INK, 1.0, 2)))?;
        label("slider on a fixed guide", y)?;
        y += 32;
    }
    if frames.iter().any(|f| f.sliders.iter().any(|s| !s.ground)) {
        draw_shape(area, (x - 4, y), &guide((38.0, 0.0), false, (INK, 1.0, 2)))?;
        draw_shape(area, (x + 15, y), &block((1.0, 0.0), (INK, 1.0, 2)))?;
        label("slider on a moving guide", y)?;
        y += 30;
    }
    let joint = EmptyElement::at((x + 15, y))
        + Circle::new((0, 0), 5, WHITE.filled())
        + Circle::new((0, 0), 5, INK.stroke_width(2));
    area.draw(&joint).map_err(drawing_error)?;
    label("joint", y)
}
