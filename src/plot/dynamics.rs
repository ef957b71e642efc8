//! `dynamics_svg`: the input's effort, and the kinetic, potential and total energy, against the
//! swept input (what `mechgen dynamics` and the main job compute per row), in two stacked panels
//! beside the motion plot; failed rows are gaps.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{
    FAMILY, PlotError, Ticked, clip_runs, color, drawing_error, ensure_font, finite_runs,
    padded_range, robust_range, tick_text,
};
use mechgen_runtime::{Kind, MechanismInfo};

const WIDTH: u32 = 760;
const HEADER: u32 = 60;
const PANEL_HEIGHT: u32 = 300;

/// One row's values for the plot: effort, kinetic and potential energy (`None`: a failed row).
pub type DynamicsRow = Option<[f64; 3]>;

/// Effort (top) and energies (bottom: kinetic, potential, their sum) against input `input`, whose
/// values are `xs` (radians or file units) with one [`DynamicsRow`] each.
pub fn dynamics_svg(
    info: &MechanismInfo,
    input: usize,
    xs: &[f64],
    rows: &[DynamicsRow],
) -> Result<String, PlotError> {
    ensure_font()?;
    let coord = info.inputs.get(input).ok_or(PlotError::BadInput {
        index: input,
        inputs: info.inputs.len(),
    })?;
    let degrees = coord.kind == Kind::Angle;
    let scale = if degrees {
        180.0 / std::f64::consts::PI
    } else {
        1.0
    };
    let x_range = padded_range(xs.iter().map(|x| x * scale), 0.0).ok_or(PlotError::NoData)?;
    let series = |f: &dyn Fn(&[f64; 3]) -> f64| {
        finite_runs(
            xs.iter()
                .zip(rows)
                .map(|(x, r)| r.as_ref().map(|r| (x * scale, f(r)))),
        )
    };
    let unit = if degrees { "deg" } else { "units" };
    let x_desc = format!("{} [{unit}]", coord.name);
    let panels = [
        (
            format!(
                "effort_{} (the driver's, against inertia, gravity and loads)",
                coord.name
            ),
            vec![(format!("effort_{}", coord.name), series(&|r| r[0]))],
        ),
        (
            "energy".to_string(),
            vec![
                ("kinetic".to_string(), series(&|r| r[1])),
                ("potential".to_string(), series(&|r| r[2])),
                ("total".to_string(), series(&|r| r[1] + r[2])),
            ],
        ),
    ];
    let mut svg = String::new();
    {
        let size = (WIDTH, HEADER + 2 * PANEL_HEIGHT);
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(drawing_error)?;
        let (header, body) = root.split_vertically(HEADER);
        let centre = Pos::new(HPos::Center, VPos::Top);
        let title = format!("{}: inverse dynamics against {}", info.name, coord.name);
        header
            .draw(&Text::new(
                title,
                (WIDTH as i32 / 2, 14),
                (FAMILY, 24).into_font().color(&BLACK).pos(centre),
            ))
            .map_err(drawing_error)?;
        for (area, (caption, curves)) in body.split_evenly((2, 1)).iter().zip(&panels) {
            let values: Vec<f64> = curves
                .iter()
                .flat_map(|(_, runs)| runs.iter().flatten().map(|p| p.1))
                .collect();
            let ((y0, y1), _) = robust_range(&values, 0.06).unwrap_or(((-1.0, 1.0), false));
            let (x_axis, x_step) = Ticked::new(x_range.0, x_range.1, 8, degrees);
            let (y_axis, y_step) = Ticked::new(y0, y1, 6, false);
            let mut chart = ChartBuilder::on(area)
                .caption(caption, (FAMILY, 18).into_font())
                .margin(10)
                .x_label_area_size(46)
                .y_label_area_size(82)
                .build_cartesian_2d(x_axis, y_axis)
                .map_err(drawing_error)?;
            let x_fmt = move |v: &f64| tick_text(*v, x_step);
            let y_fmt = move |v: &f64| tick_text(*v, y_step);
            chart
                .configure_mesh()
                .bold_line_style(RGBColor(225, 225, 225))
                .light_line_style(TRANSPARENT)
                .label_style((FAMILY, 15))
                .axis_desc_style((FAMILY, 16))
                .x_label_formatter(&x_fmt)
                .y_label_formatter(&y_fmt)
                .x_desc(&x_desc)
                .draw()
                .map_err(drawing_error)?;
            for (j, (name, runs)) in curves.iter().enumerate() {
                let style = color(j).stroke_width(2);
                for (i, run) in clip_runs(runs.clone(), y0, y1).into_iter().enumerate() {
                    let drawn = chart
                        .draw_series(LineSeries::new(run, style))
                        .map_err(drawing_error)?;
                    if i == 0 {
                        drawn.label(name.clone()).legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 20, y)], style)
                        });
                    }
                }
            }
            if curves.len() > 1 {
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.85))
                    .border_style(RGBColor(180, 180, 180))
                    .label_font((FAMILY, 15))
                    .draw()
                    .map_err(drawing_error)?;
            }
        }
        root.present().map_err(drawing_error)?;
    }
    Ok(svg)
}
