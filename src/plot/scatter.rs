//! `log_log_scatter_svg`: labelled markers on logarithmic x and y axes (e.g. time against error),
//! one colour and shape per group, labels placed beside their markers without overlapping.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::log_axis::{LogAxis, decade_text, log_range};
use super::{FAMILY, PlotError, color, drawing_error, ensure_font};

const WIDTH: u32 = 1100;
const HEIGHT: u32 = 760;
const GRID: RGBColor = RGBColor(215, 215, 215);
const LIGHT_GRID: RGBColor = RGBColor(240, 240, 240);
const MARKER: i32 = 6;

/// One labelled marker: `x` and `y` must be positive and finite to be drawn; `group` indexes the
/// plot's groups (colour, shape and legend entry).
#[derive(Clone, Debug, PartialEq)]
pub struct Marker {
    pub label: String,
    pub x: f64,
    pub y: f64,
    pub group: usize,
}

/// Titles and axis descriptions of a [`log_log_scatter_svg`] plot, and the legend's group names.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ScatterLayout {
    pub title: String,
    pub subtitle: String,
    pub x_desc: String,
    pub y_desc: String,
    pub groups: Vec<String>,
}

/// A pixel rectangle: (left, top, right, bottom).
type Rect = (i32, i32, i32, i32);

fn overlaps(a: Rect, b: Rect) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// Draws a group's marker shape (circle, square, triangle, diamond, cycled) at a pixel position.
fn draw_marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    group: usize,
    (x, y): (i32, i32),
) -> Result<(), PlotError> {
    let style = color(group).filled();
    let r = MARKER;
    match group / 8 % 4 {
        0 => area.draw(&Circle::new((x, y), r, style)),
        1 => area.draw(&Rectangle::new(
            [(x - r + 1, y - r + 1), (x + r - 1, y + r - 1)],
            style,
        )),
        2 => area.draw(&Polygon::new(
            vec![(x, y - r - 1), (x + r, y + r - 2), (x - r, y + r - 2)],
            style,
        )),
        _ => area.draw(&Polygon::new(
            vec![
                (x, y - r - 1),
                (x + r + 1, y),
                (x, y + r + 1),
                (x - r - 1, y),
            ],
            style,
        )),
    }
    .map_err(drawing_error)
}

/// Labelled markers on log-log axes, as an SVG string, with a legend of the groups. Markers whose
/// coordinates are not positive and finite are left out (and listed under the plot); markers that
/// coincide on the page share one label (theirs, joined by commas). Each label goes at the first
/// of several positions around its marker, at growing distances, that overlaps no other label or
/// marker and stays inside the plot (joined to the marker by a thin line when it is not adjacent).
pub fn log_log_scatter_svg(
    layout: &ScatterLayout,
    markers: &[Marker],
) -> Result<String, PlotError> {
    ensure_font()?;
    let drawn: Vec<&Marker> = markers
        .iter()
        .filter(|m| m.x.is_finite() && m.y.is_finite() && m.x > 0.0 && m.y > 0.0)
        .collect();
    let left_out: Vec<&str> = markers
        .iter()
        .filter(|m| !drawn.contains(m))
        .map(|m| m.label.as_str())
        .collect();
    let (x0, x1) = log_range(drawn.iter().map(|m| m.x), 0.25).ok_or(PlotError::NoData)?;
    let (y0, y1) = log_range(drawn.iter().map(|m| m.y), 0.5).ok_or(PlotError::NoData)?;

    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing_error)?;
        let centre = Pos::new(HPos::Center, VPos::Top);
        root.draw(&Text::new(
            layout.title.clone(),
            (WIDTH as i32 / 2, 10),
            (FAMILY, 24).into_font().color(&BLACK).pos(centre),
        ))
        .map_err(drawing_error)?;
        let grey = RGBColor(90, 90, 90);
        root.draw(&Text::new(
            layout.subtitle.clone(),
            (WIDTH as i32 / 2, 40),
            (FAMILY, 15).into_font().color(&grey).pos(centre),
        ))
        .map_err(drawing_error)?;

        // Legend: group swatches under the titles, in as many centred rows as needed.
        let legend_font = (FAMILY, 15)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Center));
        let widths: Vec<i32> = layout
            .groups
            .iter()
            .map(|g| {
                root.estimate_text_size(g, &legend_font)
                    .map(|(w, _)| w as i32 + 20 + 28)
                    .map_err(drawing_error)
            })
            .collect::<Result<_, _>>()?;
        let mut legend_rows: Vec<Vec<usize>> = vec![Vec::new()];
        let mut row_width = 0;
        for (i, w) in widths.iter().enumerate() {
            if row_width + w > WIDTH as i32 - 40 && row_width > 0 {
                legend_rows.push(Vec::new());
                row_width = 0;
            }
            row_width += w;
            if let Some(row) = legend_rows.last_mut() {
                row.push(i);
            }
        }
        for (r, row) in legend_rows.iter().enumerate() {
            let y = 76 + 24 * r as i32;
            let mut lx = (WIDTH as i32 - row.iter().map(|&i| widths[i]).sum::<i32>()) / 2;
            for &i in row {
                draw_marker(&root, i, (lx + 7, y))?;
                root.draw(&Text::new(
                    layout.groups[i].clone(),
                    (lx + 20, y),
                    legend_font.clone(),
                ))
                .map_err(drawing_error)?;
                lx += widths[i];
            }
        }

        let top = 76 + 24 * legend_rows.len() as u32;
        let body = root.margin(top, 12, 12, 28);
        let mut chart = ChartBuilder::on(&body)
            .x_label_area_size(56)
            .y_label_area_size(78)
            .build_cartesian_2d(LogAxis::new(x0, x1), LogAxis::new(y0, y1))
            .map_err(drawing_error)?;
        let fmt = |v: &f64| decade_text(*v);
        chart
            .configure_mesh()
            .bold_line_style(GRID)
            .light_line_style(LIGHT_GRID)
            .x_labels(40)
            .y_labels(40)
            .label_style((FAMILY, 15))
            .axis_desc_style((FAMILY, 17))
            .x_label_formatter(&fmt)
            .y_label_formatter(&fmt)
            .x_desc(&layout.x_desc)
            .y_desc(&layout.y_desc)
            .draw()
            .map_err(drawing_error)?;

        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let bounds: Rect = (xr.start + 2, yr.start + 2, xr.end - 2, yr.end - 2);
        let at: Vec<(i32, i32)> = drawn
            .iter()
            .map(|m| chart.backend_coord(&(m.x.log10(), m.y.log10())))
            .collect();
        // Markers closer than a marker's size share one label: theirs, joined.
        let mut clusters: Vec<(usize, Vec<usize>)> = Vec::new();
        for (i, &(x, y)) in at.iter().enumerate() {
            let near = clusters.iter_mut().find(|(first, _)| {
                let (fx, fy) = at[*first];
                (fx - x).abs() <= MARKER && (fy - y).abs() <= MARKER
            });
            match near {
                Some((_, members)) => members.push(i),
                None => clusters.push((i, vec![i])),
            }
        }
        let cluster_of: Vec<usize> = (0..at.len())
            .map(|i| {
                clusters
                    .iter()
                    .position(|(_, members)| members.contains(&i))
                    .unwrap_or(0)
            })
            .collect();
        // Occupied boxes, with the cluster of the marker they belong to (None for labels).
        let mut taken: Vec<(Rect, Option<usize>)> = at
            .iter()
            .zip(&cluster_of)
            .map(|(&(x, y), &c)| {
                let r = MARKER + 1;
                ((x - r, y - r, x + r, y + r), Some(c))
            })
            .collect();
        for (m, &p) in drawn.iter().zip(&at) {
            draw_marker(&root, m.group, p)?;
        }

        let label_font = (FAMILY, 14).into_font().color(&BLACK);
        for (c, (first, members)) in clusters.iter().enumerate() {
            let text = members
                .iter()
                .map(|&i| drawn[i].label.as_str())
                .collect::<Vec<_>>()
                .join(", ");
            // The cluster's extent: (left, top, right, bottom) of its marker centres.
            let (px, py) = at[*first];
            let (l, t, r, b) = members.iter().fold((px, py, px, py), |(l, t, r, b), &i| {
                let (x, y) = at[i];
                (l.min(x), t.min(y), r.max(x), b.max(y))
            });
            let (cx, cy) = ((l + r) / 2, (t + b) / 2);
            let (w, h) = root
                .estimate_text_size(&text, &label_font)
                .map_err(drawing_error)?;
            let (w, h) = (w as i32, h as i32);
            // Candidate top-left corners: right, left, above, below, then the diagonals, at
            // growing distances from the cluster's extent.
            let mut place = None;
            'search: for ring in 0..12 {
                let d = MARKER + 4 + ring * 12;
                let candidates = [
                    (r + d, cy - h / 2),
                    (l - d - w, cy - h / 2),
                    (cx - w / 2, t - d - h),
                    (cx - w / 2, b + d),
                    (r + d, t - d - h / 2),
                    (r + d, b + d - h / 2),
                    (l - d - w, t - d - h / 2),
                    (l - d - w, b + d - h / 2),
                ];
                for (x, y) in candidates {
                    let rect = (x - 2, y - 1, x + w + 2, y + h + 1);
                    let inside = rect.0 >= bounds.0
                        && rect.1 >= bounds.1
                        && rect.2 <= bounds.2
                        && rect.3 <= bounds.3;
                    if inside
                        && !taken
                            .iter()
                            .any(|(t, owner)| *owner != Some(c) && overlaps(*t, rect))
                    {
                        place = Some((x, y, ring));
                        break 'search;
                    }
                }
            }
            // Nowhere free: to the right, overlapping.
            let (x, y, ring) = place.unwrap_or((r + MARKER + 4, cy - h / 2, 0));
            if ring > 0 {
                // To the nearest point of the label's box.
                let end = (cx.clamp(x, x + w), cy.clamp(y, y + h));
                root.draw(&PathElement::new(
                    vec![(cx, cy), end],
                    RGBColor(150, 150, 150).stroke_width(1),
                ))
                .map_err(drawing_error)?;
            }
            taken.push(((x - 2, y - 1, x + w + 2, y + h + 1), None));
            root.draw(&Text::new(
                text,
                (x, y),
                label_font.clone().pos(Pos::new(HPos::Left, VPos::Top)),
            ))
            .map_err(drawing_error)?;
        }

        if !left_out.is_empty() {
            let note = format!("not drawn (zero or not finite): {}", left_out.join(", "));
            root.draw(&Text::new(
                note,
                (WIDTH as i32 / 2, HEIGHT as i32 - 8),
                (FAMILY, 14)
                    .into_font()
                    .color(&grey)
                    .pos(Pos::new(HPos::Center, VPos::Bottom)),
            ))
            .map_err(drawing_error)?;
        }
        root.present().map_err(drawing_error)?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_and_markers_are_drawn() {
        let layout = ScatterLayout {
            title: "time against error".into(),
            subtitle: "test".into(),
            x_desc: "time [ns]".into(),
            y_desc: "error".into(),
            groups: vec!["a".into(), "b".into()],
        };
        let markers = [
            Marker {
                label: "first".into(),
                x: 120.0,
                y: 1e-12,
                group: 0,
            },
            Marker {
                label: "second".into(),
                x: 125.0,
                y: 1.2e-12,
                group: 1,
            },
            Marker {
                label: "zero".into(),
                x: 125.0,
                y: 0.0,
                group: 1,
            },
        ];
        let svg = log_log_scatter_svg(&layout, &markers).expect("plot");
        for text in [
            "first",
            "second",
            "time [ns]",
            "10⁻¹²",
            "not drawn (zero or not finite): zero",
        ] {
            assert!(svg.contains(text), "{text}");
        }
        assert!(!svg.contains("NaN"));
        assert_eq!(
            log_log_scatter_svg(&layout, &markers[2..]),
            Err(PlotError::NoData)
        );
    }
}
