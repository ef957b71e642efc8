//! `drawing_svg`: the mechanism drawn at several inputs (first frame bold, the others faded), the
//! paths of its named points (`point_paths` takes them from a sweep), ground pivots and sliders on
//! their guides marked (symbols and legend in `symbols.rs`), at equal scale on both axes.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::sweep::Row;
use mechgen_runtime::MechanismInfo;

use super::symbols::{
    FADED, FADED_ALPHA, Frame, INK, Slider, axes, block, draw_legend, draw_shape, guide, pivot,
};
use super::{
    FAMILY, PlotError, Ticked, color, drawing_error, ensure_font, finite_runs, padded_range,
    tick_text, ticks,
};

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

const WIDTH: u32 = 1000;
const LEGEND: u32 = 230;
/// The fill of a body with three or more joints (first frame).
const BODY: RGBColor = RGBColor(214, 226, 240);

fn finite(p: &[f64; 2]) -> bool {
    p[0].is_finite() && p[1].is_finite()
}

fn pair(p: &[f64; 2]) -> (f64, f64) {
    (p[0], p[1])
}

/// The mechanism: links as polylines (a closed one is a body, shaded), joints as circles, ground
/// pivots as hatched triangles, sliders as blocks on their guides (a hatched rail for a guide fixed
/// to the ground), the first frame bold and the others faded, the `paths` of named points over the sweep as thin
/// curves (a non-finite entry is a gap), equal scale on both axes and a legend beside the plot.
/// Non-finite coordinates are skipped.
pub fn drawing_svg(
    title: &str,
    frames: &[Frame],
    paths: &[(String, Vec<[f64; 2]>)],
) -> Result<String, PlotError> {
    ensure_font()?;
    let all: Vec<[f64; 2]> = frames
        .iter()
        .flat_map(|f| {
            let links = f.links.iter().flatten();
            let sliders = f
                .sliders
                .iter()
                .flat_map(|s| s.guide.iter().chain([&s.block]));
            links
                .chain(&f.ground)
                .chain(f.points.iter().map(|p| &p.1))
                .chain(sliders)
        })
        .chain(paths.iter().flat_map(|p| &p.1))
        .copied()
        .filter(finite)
        .collect();
    let xr = padded_range(all.iter().map(|p| p[0]), 0.0).ok_or(PlotError::NoData)?;
    let yr = padded_range(all.iter().map(|p| p[1]), 0.0).ok_or(PlotError::NoData)?;
    // Room for pivot triangles and labels: a share of the larger span on every side.
    let pad = 0.1 * (xr.1 - xr.0).max(yr.1 - yr.0);
    let (xr, yr) = ((xr.0 - pad, xr.1 + pad), (yr.0 - pad, yr.1 + pad));
    let plot_width = f64::from(WIDTH - LEGEND - 100);
    let height = (plot_width * (yr.1 - yr.0) / (xr.1 - xr.0)).clamp(320.0, 1000.0) as u32 + 120;

    // Equal scale: measure the plotting area this layout leaves, then widen one range to fit it.
    let (pw, ph) = {
        let mut scratch = String::new();
        let area = SVGBackend::with_string(&mut scratch, (WIDTH, height)).into_drawing_area();
        let (left, _) = area.split_horizontally(WIDTH - LEGEND);
        let chart = builder(&left, title, xr, yr)?;
        chart.plotting_area().dim_in_pixel()
    };
    let scale = (f64::from(pw) / (xr.1 - xr.0)).min(f64::from(ph) / (yr.1 - yr.0));
    let widen = |r: (f64, f64), px: u32| {
        let (mid, half) = ((r.0 + r.1) / 2.0, f64::from(px) / scale / 2.0);
        (mid - half, mid + half)
    };
    let (xr, yr) = (widen(xr, pw), widen(yr, ph));

    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing_error)?;
        let (left, right) = root.split_horizontally(WIDTH - LEGEND);
        let mut chart = builder(&left, title, xr, yr)?;
        let (x_step, y_step) = (ticks(xr.0, xr.1, 8, false).1, ticks(yr.0, yr.1, 8, false).1);
        let x_fmt = move |v: &f64| tick_text(*v, x_step);
        let y_fmt = move |v: &f64| tick_text(*v, y_step);
        chart
            .configure_mesh()
            .bold_line_style(RGBColor(230, 230, 230))
            .light_line_style(TRANSPARENT)
            .label_style((FAMILY, 15))
            .axis_desc_style((FAMILY, 16))
            .x_label_formatter(&x_fmt)
            .y_label_formatter(&y_fmt)
            .x_desc("x [units]")
            .y_desc("y [units]")
            .draw()
            .map_err(drawing_error)?;

        if let Some(first) = frames.first() {
            draw_rails(&chart, first)?;
        }
        for frame in frames.iter().skip(1) {
            draw_frame(&mut chart, frame, false)?;
        }
        for (i, (_, path)) in paths.iter().enumerate() {
            let runs = finite_runs(path.iter().map(|p| Some(pair(p))));
            for run in runs {
                let line = LineSeries::new(run, color(i).stroke_width(2));
                chart.draw_series(line).map_err(drawing_error)?;
            }
        }
        if let Some(first) = frames.first() {
            draw_frame(&mut chart, first, true)?;
        }
        draw_legend(&right, frames, paths)?;
        root.present().map_err(drawing_error)?;
    }
    Ok(svg)
}

type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<Ticked, Ticked>>;

fn builder<'a, 'b>(
    area: &'a Area<'b>,
    title: &str,
    xr: (f64, f64),
    yr: (f64, f64),
) -> Result<Chart<'a, 'b>, PlotError> {
    let (x_axis, _) = Ticked::new(xr.0, xr.1, 8, false);
    let (y_axis, _) = Ticked::new(yr.0, yr.1, 8, false);
    ChartBuilder::on(area)
        .caption(title, (FAMILY, 24).into_font())
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(x_axis, y_axis)
        .map_err(drawing_error)
}

/// The guides fixed to the ground (the same in every frame), under everything else.
fn draw_rails(chart: &Chart, frame: &Frame) -> Result<(), PlotError> {
    for s in frame
        .sliders
        .iter()
        .filter(|s| s.ground && s.guide.iter().all(finite))
    {
        let (a, b) = (
            chart.backend_coord(&pair(&s.guide[0])),
            chart.backend_coord(&pair(&s.guide[1])),
        );
        let d = (f64::from(b.0 - a.0), f64::from(b.1 - a.1));
        let shape = guide(d, true, (INK, 1.0, 2));
        draw_shape(chart.plotting_area(), pair(&s.guide[0]), &shape)?;
    }
    Ok(())
}

/// Links, sliders, joints, ground pivots and (first frame only) point labels.
fn draw_frame(chart: &mut Chart, frame: &Frame, bold: bool) -> Result<(), PlotError> {
    let (ink, width, radius) = if bold { (INK, 3, 5) } else { (FADED, 1, 3) };
    let alpha = if bold { 1.0 } else { FADED_ALPHA };
    // Bodies' shading first, so that no shading hides a link.
    for link in frame.links.iter().filter(|_| bold) {
        if link.len() > 3 && link.first() == link.last() && link.iter().all(finite) {
            let outline = link.iter().map(pair).collect::<Vec<_>>();
            let body = Polygon::new(outline, BODY.mix(0.7).filled());
            chart.draw_series([body]).map_err(drawing_error)?;
        }
    }
    for link in &frame.links {
        for run in finite_runs(link.iter().map(|p| Some(pair(p)))) {
            let line = LineSeries::new(run, ink.mix(alpha).stroke_width(width));
            chart.draw_series(line).map_err(drawing_error)?;
        }
    }
    let ends = |s: &&Slider| s.guide.iter().chain([&s.block]).all(finite);
    for s in frame.sliders.iter().filter(ends) {
        let px = |p: &[f64; 2]| chart.backend_coord(&pair(p));
        let (a, b) = (px(&s.guide[0]), px(&s.guide[1]));
        let d = (f64::from(b.0 - a.0), f64::from(b.1 - a.1));
        if !s.ground {
            let shape = guide(d, false, (ink, alpha, width));
            draw_shape(chart.plotting_area(), pair(&s.guide[0]), &shape)?;
        }
        let shape = block(axes(d).0, (ink, alpha, width));
        draw_shape(chart.plotting_area(), pair(&s.block), &shape)?;
    }
    if bold {
        for p in frame.ground.iter().filter(|p| finite(p)) {
            draw_shape(chart.plotting_area(), pair(p), &pivot())?;
        }
    }
    let joints: Vec<(f64, f64)> = frame
        .links
        .iter()
        .flatten()
        .chain(&frame.ground)
        .chain(frame.sliders.iter().map(|s| &s.block))
        .filter(|p| finite(p))
        .map(pair)
        .collect();
    let fill = if bold {
        WHITE.mix(1.0)
    } else {
        WHITE.mix(alpha)
    };
    chart
        .draw_series(joints.iter().map(|&p| {
            EmptyElement::at(p)
                + Circle::new((0, 0), radius, fill.filled())
                + Circle::new((0, 0), radius, ink.mix(alpha).stroke_width(2))
        }))
        .map_err(drawing_error)?;
    if bold {
        draw_labels(chart, frame, &joints)?;
    }
    Ok(())
}

/// Point names, each placed away from the centre of the joints (beside a ground pivot, never on
/// its triangle) on a white box, so that links running under it do not hide it.
fn draw_labels(chart: &mut Chart, frame: &Frame, joints: &[(f64, f64)]) -> Result<(), PlotError> {
    let n = joints.len().max(1) as f64;
    let centre = joints
        .iter()
        .fold((0.0, 0.0), |c, p| (c.0 + p.0 / n, c.1 + p.1 / n));
    let font = (FAMILY, 17).into_font();
    for (name, p) in frame.points.iter().filter(|p| finite(&p.1)) {
        let (mut dx, mut dy) = (p[0] - centre.0, p[1] - centre.1);
        let norm = dx.hypot(dy);
        (dx, dy) = if norm > 0.0 && norm.is_finite() {
            (dx / norm, dy / norm)
        } else {
            (0.7, 0.7)
        };
        if dy < 0.0 && frame.ground.iter().any(|g| g == p) {
            // Beside a ground pivot, not on its triangle.
            (dx, dy) = (if dx < 0.0 { -1.0 } else { 1.0 }, 0.0);
        }
        let h = if dx > 0.35 {
            HPos::Left
        } else if dx < -0.35 {
            HPos::Right
        } else {
            HPos::Center
        };
        let v = if dy > 0.35 {
            VPos::Bottom
        } else if dy < -0.35 {
            VPos::Top
        } else {
            VPos::Center
        };
        // Pixel offset (y grows downwards): clear of a slider block at the point.
        let at = chart.backend_coord(&pair(p));
        let on_block = frame.sliders.iter().any(|s| {
            let b = chart.backend_coord(&pair(&s.block));
            (b.0 - at.0).abs() <= 2 && (b.1 - at.1).abs() <= 2
        });
        let reach = if on_block { 22.0 } else { 11.0 };
        let (ox, oy) = ((dx * reach).round() as i32, (-dy * reach).round() as i32);
        let style = font.color(&INK).pos(Pos::new(h, v));
        let (w, th) = chart
            .plotting_area()
            .estimate_text_size(name, &style)
            .map_err(drawing_error)?;
        let (w, th) = (w as i32, th as i32);
        let x0 = match h {
            HPos::Left => ox,
            HPos::Right => ox - w,
            HPos::Center => ox - w / 2,
        };
        let y0 = match v {
            VPos::Top => oy,
            VPos::Bottom => oy - th,
            VPos::Center => oy - th / 2,
        };
        let backdrop = Rectangle::new(
            [(x0 - 2, y0 - 1), (x0 + w + 2, y0 + th + 2)],
            WHITE.mix(0.85).filled(),
        );
        let label = EmptyElement::at(pair(p)) + backdrop + Text::new(name.clone(), (ox, oy), style);
        chart.draw_series([label]).map_err(drawing_error)?;
    }
    Ok(())
}

/// The path of every named point over a sweep, in file units: one entry per row, with a
/// non-finite entry (a gap) at every failed row, as [`drawing_svg`] expects.
pub fn point_paths(info: &MechanismInfo, rows: &[Row]) -> Vec<(String, Vec<[f64; 2]>)> {
    info.points
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let path = rows
                .iter()
                .map(|r| match &r.result {
                    Ok(s) => s.points.get(i).map_or([f64::NAN; 2], |p| p.position),
                    Err(_) => [f64::NAN; 2],
                })
                .collect();
            (name.clone(), path)
        })
        .collect()
}
