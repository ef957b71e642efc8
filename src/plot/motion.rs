//! `motion_svg`: position, velocity and acceleration of every unknown against the swept input, in
//! three stacked rows of panels, angles and lengths in separate columns, failed rows as shaded gaps.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{
    FAMILY, PlotError, Runs, Ticked, clip_runs, color, drawing_error, ensure_font, finite_runs,
    padded_range, robust_range, tick_text,
};
use crate::sweep::{Row, Solved};
use mechgen_runtime::{CoordDesc, Kind, MechanismInfo};

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

const COLUMN_WIDTH: u32 = 720;
const HEADER: u32 = 84;
const PANEL_HEIGHT: u32 = 250;
const GAP_FILL: RGBColor = RGBColor(214, 39, 40);
const GRID: RGBColor = RGBColor(225, 225, 225);

const QUANTITIES: [&str; 3] = ["position", "velocity", "acceleration"];

fn unit(kind: Kind, derivative: usize) -> &'static str {
    match (kind, derivative) {
        (Kind::Angle, 0) => "deg",
        (Kind::Angle, 1) => "deg/s",
        (Kind::Angle, _) => "deg/s²",
        (_, 0) => "units",
        (_, 1) => "units/s",
        (_, _) => "units/s²",
    }
}

fn to_display(kind: Kind) -> f64 {
    match kind {
        Kind::Angle => 180.0 / std::f64::consts::PI,
        _ => 1.0,
    }
}

/// One panel: the curves of some unknowns for one derivative order.
struct Panel {
    caption: String,
    y_desc: String,
    x_desc: Option<String>,
    kind: Kind,
    /// 0, 1, 2: position, velocity, acceleration.
    derivative: usize,
    /// (unknown index, runs of finite points)
    series: Vec<(usize, Runs)>,
}

/// Position, velocity and acceleration curves against the input: three stacked rows (positions;
/// velocities; accelerations) of every unknown against input `input` of `rows`, angles in degrees
/// and lengths in file units, in separate columns when the mechanism has both. Failed rows (and
/// non-finite values) are gaps in the curves, never joined across, and the input ranges without
/// a solution are shaded. Velocities and accelerations are those the sweep computed (per second at
/// its input rate).
pub fn motion_svg(info: &MechanismInfo, input: usize, rows: &[Row]) -> Result<String, PlotError> {
    ensure_font()?;
    let CoordDesc {
        name: input_name,
        kind: input_kind,
        ..
    } = info.inputs.get(input).ok_or(PlotError::BadInput {
        index: input,
        inputs: info.inputs.len(),
    })?;
    let xs = to_display(*input_kind);
    let x_range = padded_range(rows.iter().map(|r| r.input * xs), 0.0).ok_or(PlotError::NoData)?;
    let gaps = gap_spans(rows, xs);

    let kinds: Vec<Kind> = [Kind::Angle, Kind::Length]
        .into_iter()
        .filter(|k| info.unknowns.iter().any(|u| u.kind == *k))
        .collect();
    let columns = kinds.len().max(1);
    let x_desc = format!("{input_name} [{}]", unit(*input_kind, 0));

    let mut panels = Vec::new();
    for (d, quantity) in QUANTITIES.iter().enumerate() {
        for kind in &kinds {
            let ys = to_display(*kind);
            let series = info
                .unknowns
                .iter()
                .enumerate()
                .filter(|(_, u)| u.kind == *kind)
                .map(|(j, _)| {
                    let points = rows.iter().map(|r| {
                        let v = r
                            .result
                            .as_ref()
                            .ok()
                            .and_then(|s| derivative(s, d).get(j))?;
                        Some((r.input * xs, v * ys))
                    });
                    (j, finite_runs(points))
                })
                .collect();
            let group = match (columns, kind) {
                (1, _) => String::new(),
                (_, Kind::Angle) => "angles: ".into(),
                _ => "lengths: ".into(),
            };
            panels.push(Panel {
                caption: format!("{group}{quantity}"),
                y_desc: format!("{quantity} [{}]", unit(*kind, d)),
                x_desc: (d == 2).then(|| x_desc.clone()),
                kind: *kind,
                derivative: d,
                series,
            });
        }
    }

    let size = (COLUMN_WIDTH * columns as u32, HEADER + 3 * PANEL_HEIGHT);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(drawing_error)?;
        let (header, body) = root.split_vertically(HEADER);
        let title = format!("{}: unknowns against {input_name}", info.name);
        draw_header(&header, &title, &info.description, info, !gaps.is_empty())?;
        let areas = body.split_evenly((3, columns));
        for (area, panel) in areas.iter().zip(&panels) {
            draw_panel(area, panel, x_range, *input_kind == Kind::Angle, &gaps)?;
        }
        root.present().map_err(drawing_error)?;
    }
    Ok(svg)
}

fn derivative(s: &Solved, d: usize) -> &[f64] {
    match d {
        0 => &s.q,
        1 => &s.qd,
        _ => &s.qdd,
    }
}

/// The input intervals (display units) that failed rows leave without curves: from the last
/// solved row before a run of failures to the first solved row after it.
fn gap_spans(rows: &[Row], xs: f64) -> Vec<(f64, f64)> {
    let mut spans = Vec::new();
    let mut i = 0;
    while i < rows.len() {
        if rows[i].result.is_ok() {
            i += 1;
            continue;
        }
        let start = i;
        while i < rows.len() && rows[i].result.is_err() {
            i += 1;
        }
        let from = rows[start.saturating_sub(1)].input * xs;
        let to = rows[i.min(rows.len() - 1)].input * xs;
        if from.is_finite() && to.is_finite() {
            spans.push((from.min(to), from.max(to)));
        }
    }
    spans
}

/// Title, description and the legend (one colour per unknown, the same in every panel).
fn draw_header(
    area: &Area,
    title: &str,
    description: &str,
    info: &MechanismInfo,
    gaps: bool,
) -> Result<(), PlotError> {
    let (w, _) = area.dim_in_pixel();
    let centre = Pos::new(HPos::Center, VPos::Top);
    let title_style = (FAMILY, 24).into_font().color(&BLACK).pos(centre);
    area.draw(&Text::new(
        title.to_string(),
        (w as i32 / 2, 8),
        title_style,
    ))
    .map_err(drawing_error)?;
    let sub_style = (FAMILY, 15)
        .into_font()
        .color(&RGBColor(90, 90, 90))
        .pos(centre);
    area.draw(&Text::new(
        description.to_string(),
        (w as i32 / 2, 36),
        sub_style,
    ))
    .map_err(drawing_error)?;

    let label = (FAMILY, 16)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let mut entries: Vec<(String, ShapeStyle, bool)> = info
        .unknowns
        .iter()
        .enumerate()
        .map(|(j, u)| (u.name.clone(), color(j).stroke_width(3), false))
        .collect();
    if gaps {
        entries.push(("no solution".into(), GAP_FILL.mix(0.15).filled(), true));
    }
    let widths: Vec<i32> = entries
        .iter()
        .map(|(t, _, _)| {
            area.estimate_text_size(t, &label)
                .map(|(tw, _)| tw as i32 + 28 + 22)
                .map_err(drawing_error)
        })
        .collect::<Result<_, _>>()?;
    let y = 66;
    let mut x = (w as i32 - widths.iter().sum::<i32>()) / 2;
    for ((text, style, swatch), width) in entries.iter().zip(widths) {
        if *swatch {
            area.draw(&Rectangle::new([(x, y - 7), (x + 22, y + 7)], *style))
                .map_err(drawing_error)?;
        } else {
            area.draw(&PathElement::new(vec![(x, y), (x + 22, y)], *style))
                .map_err(drawing_error)?;
        }
        area.draw(&Text::new(text.clone(), (x + 28, y), label.clone()))
            .map_err(drawing_error)?;
        x += width;
    }
    Ok(())
}

fn draw_panel(
    area: &Area,
    panel: &Panel,
    x_range: (f64, f64),
    degrees: bool,
    gaps: &[(f64, f64)],
) -> Result<(), PlotError> {
    let values: Vec<f64> = panel
        .series
        .iter()
        .flat_map(|(_, runs)| runs.iter().flatten().map(|p| p.1))
        .collect();
    // Positions are bounded; rates may spike at a dead point, so their range may clip.
    let y_range = if panel.derivative == 0 {
        padded_range(values, 0.06).map(|r| (r, false))
    } else {
        robust_range(&values, 0.06)
    };
    let ((y0, y1), clipped) = y_range.unwrap_or(((-1.0, 1.0), false));
    let (x_axis, x_step) = Ticked::new(x_range.0, x_range.1, 8, degrees);
    let angle = panel.derivative == 0 && panel.kind == Kind::Angle;
    let (y_axis, y_step) = Ticked::new(y0, y1, 6, angle);
    let caption = if clipped {
        format!("{} (off-scale values clipped)", panel.caption)
    } else {
        panel.caption.clone()
    };

    let mut chart = ChartBuilder::on(area)
        .caption(caption, (FAMILY, 18).into_font())
        .margin_top(4)
        .margin_left(8)
        .margin_right(24)
        .margin_bottom(if panel.x_desc.is_some() { 4 } else { 10 })
        .x_label_area_size(if panel.x_desc.is_some() { 50 } else { 26 })
        .y_label_area_size(82)
        .build_cartesian_2d(x_axis, y_axis)
        .map_err(drawing_error)?;
    let x_fmt = move |v: &f64| tick_text(*v, x_step);
    let y_fmt = move |v: &f64| tick_text(*v, y_step);
    let mut mesh = chart.configure_mesh();
    mesh.bold_line_style(GRID)
        .light_line_style(TRANSPARENT)
        .label_style((FAMILY, 15))
        .axis_desc_style((FAMILY, 16))
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .y_desc(&panel.y_desc);
    if let Some(desc) = &panel.x_desc {
        mesh.x_desc(desc);
    }
    mesh.draw().map_err(drawing_error)?;

    chart
        .draw_series(
            gaps.iter()
                .map(|&(a, b)| Rectangle::new([(a, y0), (b, y1)], GAP_FILL.mix(0.12).filled())),
        )
        .map_err(drawing_error)?;
    if y0 < 0.0 && y1 > 0.0 {
        let axis = LineSeries::new(
            [(x_range.0, 0.0), (x_range.1, 0.0)],
            RGBColor(150, 150, 150),
        );
        chart.draw_series(axis).map_err(drawing_error)?;
    }
    for (j, runs) in &panel.series {
        let style = color(*j).stroke_width(2);
        for run in clip_runs(runs.clone(), y0, y1) {
            if let [single] = run.as_slice() {
                let dot = Circle::new(*single, 3, color(*j).filled());
                chart.draw_series([dot]).map_err(drawing_error)?;
            } else {
                chart
                    .draw_series(LineSeries::new(run.iter().copied(), style))
                    .map_err(drawing_error)?;
            }
        }
    }
    if y_range.is_none() {
        let style = (FAMILY, 16).into_font().color(&RGBColor(120, 120, 120));
        let centre = ((x_range.0 + x_range.1) / 2.0, 0.0);
        let text = Text::new(
            "no finite values",
            centre,
            style.pos(Pos::new(HPos::Center, VPos::Center)),
        );
        chart.draw_series([text]).map_err(drawing_error)?;
    }
    Ok(())
}
