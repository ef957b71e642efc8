//! `branches_svg`: every unknown against the input over the analysed range, one colour per branch
//! (lines broken where an angle wraps past ±180°), dead points marked with black crosses, and a
//! legend of the branches with their circuits (`mechgen branches --plot`).

use plotters::prelude::*;

use super::axis::{Ticked, tick_text};
use super::{FAMILY, PlotError, color, drawing_error, ensure_font, padded_range};
use crate::branches::{Analysis, Setup};

const WIDTH: u32 = 1000;
const PANEL: u32 = 300;
const HEADER: u32 = 70;

/// The SVG text of the branch plot.
pub fn branches_svg(setup: &Setup, a: &Analysis) -> Result<String, PlotError> {
    ensure_font()?;
    let deg_in = setup.input_is_angle;
    let xv = |x: f64| if deg_in { x.to_degrees() } else { x };
    let (x0, x1) = (xv(a.from), xv(a.to));
    let n = setup.unknown_names.len();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, HEADER + PANEL * n.max(1) as u32))
            .into_drawing_area();
        root.fill(&WHITE).map_err(drawing_error)?;
        let (header, body) = root.split_vertically(HEADER);
        let title = format!(
            "{}: {} circuit(s), {} branch(es), {} dead point(s) (x), {} crossing(s) (o) along {}",
            setup.name,
            a.circuits,
            a.branches.len(),
            a.dead_points.len(),
            a.crossings.len(),
            setup.input_name
        );
        header
            .draw(&Text::new(title, (20, 10), (FAMILY, 20).into_font()))
            .map_err(drawing_error)?;
        for (i, b) in a.branches.iter().enumerate() {
            let label = format!("branch {i} (circuit {})", b.circuit);
            let x = 20 + (i as i32 % 6) * 160;
            let y = 40 + (i as i32 / 6) * 16;
            header
                .draw(&Text::new(
                    label,
                    (x, y),
                    (FAMILY, 14).into_font().color(&color(i)),
                ))
                .map_err(drawing_error)?;
        }
        for (k, area) in body.split_evenly((n.max(1), 1)).iter().enumerate().take(n) {
            let angle = setup.angle[k];
            let yv = |q: f64| if angle { q.to_degrees() } else { q };
            let values = a
                .branches
                .iter()
                .flat_map(|b| b.curve.iter().map(|(_, q)| yv(q[k])));
            let (y0, y1) = padded_range(values, 0.06).unwrap_or((-1.0, 1.0));
            let (x_axis, x_step) = Ticked::new(x0, x1, 8, deg_in);
            let (y_axis, y_step) = Ticked::new(y0, y1, 6, angle);
            let unit = if angle { " [deg]" } else { "" };
            let mut chart = ChartBuilder::on(area)
                .margin(8)
                .margin_right(24)
                .x_label_area_size(40)
                .y_label_area_size(82)
                .build_cartesian_2d(x_axis, y_axis)
                .map_err(drawing_error)?;
            let x_fmt = move |v: &f64| tick_text(*v, x_step);
            let y_fmt = move |v: &f64| tick_text(*v, y_step);
            chart
                .configure_mesh()
                .light_line_style(TRANSPARENT)
                .label_style((FAMILY, 14))
                .axis_desc_style((FAMILY, 15))
                .x_label_formatter(&x_fmt)
                .y_label_formatter(&y_fmt)
                .x_desc(format!(
                    "{}{}",
                    setup.input_name,
                    if deg_in { " [deg]" } else { "" }
                ))
                .y_desc(format!("{}{unit}", setup.unknown_names[k]))
                .draw()
                .map_err(drawing_error)?;
            for (i, b) in a.branches.iter().enumerate() {
                let mut run: Vec<(f64, f64)> = Vec::new();
                let mut runs = Vec::new();
                for (x, q) in &b.curve {
                    // The input wrapped into the plotted turn; angles jump at ±180°.
                    let mut x = xv(*x);
                    if deg_in && a.full_turn {
                        x = x0 + (x - x0).rem_euclid(360.0);
                    }
                    let p = (x, yv(q[k]));
                    if let Some(&(px, py)) = run.last()
                        && ((p.1 - py).abs() > if angle { 90.0 } else { f64::INFINITY }
                            || (p.0 - px).abs() > 0.5 * (x1 - x0))
                    {
                        runs.push(std::mem::take(&mut run));
                    }
                    if p.0.is_finite() && p.1.is_finite() {
                        run.push(p);
                    }
                }
                runs.push(run);
                for r in runs.into_iter().filter(|r| r.len() > 1) {
                    chart
                        .draw_series(LineSeries::new(r, color(i).stroke_width(2)))
                        .map_err(drawing_error)?;
                }
            }
            let crosses = a.dead_points.iter().map(|d| {
                let mut x = xv(d.input);
                if deg_in && a.full_turn {
                    x = x0 + (x - x0).rem_euclid(360.0);
                }
                Cross::new((x, yv(d.q[k])), 6, BLACK.stroke_width(2))
            });
            chart.draw_series(crosses).map_err(drawing_error)?;
            // Crossings: an open circle where two branches meet and go on.
            let meets = a.crossings.iter().map(|c| {
                let mut x = xv(c.input);
                if deg_in && a.full_turn {
                    x = x0 + (x - x0).rem_euclid(360.0);
                }
                Circle::new((x, yv(c.q[k])), 5, BLACK.stroke_width(2))
            });
            chart.draw_series(meets).map_err(drawing_error)?;
        }
        root.present().map_err(drawing_error)?;
    }
    Ok(svg)
}
