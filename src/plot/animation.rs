//! `animation_svg`: the mechanism moving over a sweep as one self-contained animated SVG (SMIL, no
//! script, plays in a browser): one group per frame, shown in turn by a discrete `visibility`
//! animation (the first frame is visible without animation, so a still renderer shows it). What
//! does not move (ground pivots, guides fixed to the ground, the paths of the points) is drawn
//! once. Written by hand rather than through plotters, with coordinates rounded to 0.1 px.

use std::fmt::Write as _;

use super::symbols::axes;
use super::symbols::{Frame, Slider};
use super::{PlotError, color, finite_runs, padded_range};

const WIDTH: f64 = 800.0;
const MARGIN: f64 = 40.0;
const TOP: f64 = 44.0;
const LEGEND: f64 = 26.0;
/// Seconds per frame (a whole animation lasts 4 s to 60 s).
const FRAME_TIME: f64 = 1.0 / 36.0;
/// Half length and half height of a slider block, in pixels.
const BLOCK: (f64, f64) = (15.0, 8.0);
const INK: &str = "#232323";

/// A number rounded to 0.1 (never `-0`).
fn num(v: f64) -> String {
    let s = format!("{:.1}", v);
    let s = s.strip_suffix(".0").unwrap_or(&s).to_string();
    if s == "-0" { "0".into() } else { s }
}

/// A number with up to three decimals, trailing zeros dropped.
pub(super) fn short(v: f64) -> String {
    if !v.is_finite() {
        return "?".into();
    }
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

/// Escapes text for XML.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn hex(c: plotters::style::RGBColor) -> String {
    format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2)
}

/// Page coordinates: equal scale, y up in file units, down on the page.
struct Page {
    x0: f64,
    y1: f64,
    scale: f64,
    left: f64,
}

impl Page {
    fn at(&self, p: &[f64; 2]) -> Option<(f64, f64)> {
        let q = (
            self.left + (p[0] - self.x0) * self.scale,
            TOP + (self.y1 - p[1]) * self.scale,
        );
        (q.0.is_finite() && q.1.is_finite()).then_some(q)
    }

    fn points(&self, ps: &[[f64; 2]]) -> Option<String> {
        let mut out = String::new();
        for p in ps {
            let (x, y) = self.at(p)?;
            let _ = write!(
                out,
                "{}{},{}",
                if out.is_empty() { "" } else { " " },
                num(x),
                num(y)
            );
        }
        Some(out)
    }
}

/// The mechanism over a sweep: one frame per entry of `frames` (a solved row), drawn in turn and
/// looping, with the `paths` of named points (a non-finite entry is a gap) and a label of the
/// input in each frame (as [`Frame::input`] gives it, followed by `unit`). Non-finite coordinates
/// are skipped.
pub fn animation_svg(
    title: &str,
    input: (&str, &str),
    frames: &[Frame],
    paths: &[(String, Vec<[f64; 2]>)],
) -> Result<String, PlotError> {
    let all = frames
        .iter()
        .flat_map(|f| {
            let sliders = f
                .sliders
                .iter()
                .flat_map(|s| s.guide.iter().chain([&s.block]));
            f.links.iter().flatten().chain(&f.ground).chain(sliders)
        })
        .chain(paths.iter().flat_map(|p| &p.1));
    let all: Vec<[f64; 2]> = all.copied().collect();
    let xr = padded_range(all.iter().map(|p| p[0]), 0.04).ok_or(PlotError::NoData)?;
    let yr = padded_range(all.iter().map(|p| p[1]), 0.04).ok_or(PlotError::NoData)?;
    if frames.is_empty() {
        return Err(PlotError::NoData);
    }
    let inner = WIDTH - 2.0 * MARGIN;
    let scale = (inner / (xr.1 - xr.0)).min(inner * 1.25 / (yr.1 - yr.0));
    let plot_height = (yr.1 - yr.0) * scale;
    let legend = LEGEND * paths.len().div_ceil(3) as f64;
    let height = TOP + plot_height + MARGIN + legend;
    let page = Page {
        x0: xr.0,
        y1: yr.1,
        scale,
        left: MARGIN + (inner - (xr.1 - xr.0) * scale) / 2.0,
    };
    if !(scale.is_finite() && scale > 0.0 && height.is_finite()) {
        return Err(PlotError::NoData);
    }

    let mut svg = String::with_capacity(2000 + 1200 * frames.len());
    let _ = write!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif">
<style>.f polyline{{fill:none;stroke:{INK};stroke-width:3;stroke-linejoin:round;stroke-linecap:round}}.f polygon{{fill:#D6E2F0;fill-opacity:.7}}.f .k{{fill:#E1E1E1;fill-opacity:1;stroke:{INK};stroke-width:2}}.f circle{{fill:#fff;stroke:{INK};stroke-width:2}}.f text{{font-size:16px;fill:{INK}}}</style>
<rect width="100%" height="100%" fill="white"/>
<text x="{cx}" y="28" font-size="20" text-anchor="middle" fill="{INK}">{t}</text>
"#,
        w = num(WIDTH),
        h = num(height),
        cx = num(WIDTH / 2.0),
        t = escape(title),
    );
    // Paths and their legend.
    for (i, (name, path)) in paths.iter().enumerate() {
        let c = hex(color(i));
        for run in finite_runs(path.iter().map(|p| Some((p[0], p[1])))) {
            let run: Vec<[f64; 2]> = run.into_iter().map(|p| [p.0, p.1]).collect();
            if let Some(pts) = page.points(&run) {
                let _ = writeln!(
                    svg,
                    r#"<polyline points="{pts}" fill="none" stroke="{c}" stroke-width="2"/>"#
                );
            }
        }
        let (lx, ly) = (
            MARGIN + (i % 3) as f64 * 240.0,
            TOP + plot_height + MARGIN + (i / 3) as f64 * LEGEND,
        );
        let _ = writeln!(
            svg,
            r#"<line x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="{c}" stroke-width="2"/><text x="{}" y="{}" font-size="15" fill="{INK}">path of {}</text>"#,
            num(lx),
            num(lx + 28.0),
            num(lx + 36.0),
            num(ly + 5.0),
            escape(name),
            y = num(ly),
        );
    }
    // What stands still: guides fixed to the ground and ground pivots, from the first frame.
    let first = &frames[0];
    for s in first.sliders.iter().filter(|s| s.ground) {
        rail(&mut svg, &page, s);
    }
    for p in &first.ground {
        if let Some((x, y)) = page.at(p) {
            let _ = writeln!(
                svg,
                r##"<g transform="translate({},{})" stroke="{INK}"><path d="M0 0L-10 16H10Z" fill="#C8C8C8"/><path d="M-15 16H15" stroke-width="2"/><path d="M-12 22L-6 16M-3 22L3 16M6 22L12 16"/></g>"##,
                num(x),
                num(y)
            );
        }
    }
    // The frames.
    let n = frames.len();
    let dur = format!("{}s", num((n as f64 * FRAME_TIME).clamp(4.0, 60.0)));
    let key = |i: usize| format!("{:.6}", i as f64 / n as f64);
    let (name, unit) = input;
    for (i, f) in frames.iter().enumerate() {
        let visible = if i == 0 { "visible" } else { "hidden" };
        let _ = write!(svg, r#"<g class="f" visibility="{visible}">"#);
        if n > 1 {
            let (values, times) = if i == 0 {
                ("visible;hidden".to_string(), format!("0;{}", key(1)))
            } else if i + 1 == n {
                ("hidden;visible".to_string(), format!("0;{}", key(i)))
            } else {
                (
                    "hidden;visible;hidden".to_string(),
                    format!("0;{};{}", key(i), key(i + 1)),
                )
            };
            let _ = write!(
                svg,
                r#"<animate attributeName="visibility" values="{values}" keyTimes="{times}" calcMode="discrete" dur="{dur}" repeatCount="indefinite"/>"#
            );
        }
        frame(&mut svg, &page, f, paths.len());
        let _ = writeln!(
            svg,
            r#"<text x="{}" y="{}">{} = {}{}</text></g>"#,
            num(MARGIN),
            num(TOP + 4.0),
            escape(name),
            short(f.input),
            escape(unit)
        );
    }
    svg.push_str("</svg>\n");
    Ok(svg)
}

/// The moving parts of one frame: bodies, guides that move, blocks, joints, named points.
fn frame(svg: &mut String, page: &Page, f: &Frame, paths: usize) {
    // Bodies' shading first, so that no shading hides a link.
    for link in f
        .links
        .iter()
        .filter(|l| l.len() > 3 && l.first() == l.last())
    {
        if let Some(pts) = page.points(link) {
            let _ = write!(svg, r#"<polygon points="{pts}"/>"#);
        }
    }
    for pts in f.links.iter().filter_map(|l| page.points(l)) {
        let _ = write!(svg, r#"<polyline points="{pts}"/>"#);
    }
    for s in &f.sliders {
        let (Some(a), Some(b), Some(k)) = (
            page.at(&s.guide[0]),
            page.at(&s.guide[1]),
            page.at(&s.block),
        ) else {
            continue;
        };
        if !s.ground {
            let _ = write!(
                svg,
                r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="{INK}" stroke-width="3"/>"#,
                num(a.0),
                num(a.1),
                num(b.0),
                num(b.1)
            );
        }
        let (u, v) = frame_axes(a, b);
        let corner = |s: f64, t: f64| {
            format!(
                "{},{}",
                num(k.0 + s * BLOCK.0 * u.0 + t * BLOCK.1 * v.0),
                num(k.1 + s * BLOCK.0 * u.1 + t * BLOCK.1 * v.1)
            )
        };
        let _ = write!(
            svg,
            r#"<polygon class="k" points="{} {} {} {}"/>"#,
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0)
        );
    }
    let joints = f.links.iter().flatten().chain(&f.ground);
    let mut seen: Vec<(String, String)> = Vec::new();
    for p in joints.chain(f.sliders.iter().map(|s| &s.block)) {
        let Some(q) = page.at(p).map(|q| (num(q.0), num(q.1))) else {
            continue;
        };
        if !seen.contains(&q) {
            let _ = write!(svg, r#"<circle cx="{}" cy="{}" r="5"/>"#, q.0, q.1);
            seen.push(q);
        }
    }
    for (i, (_, p)) in f.points.iter().enumerate().take(paths) {
        if let Some(q) = page.at(p) {
            let _ = write!(
                svg,
                r#"<circle cx="{}" cy="{}" r="4" style="fill:{};stroke:none"/>"#,
                num(q.0),
                num(q.1),
                hex(color(i))
            );
        }
    }
}

/// The unit vector from `a` to `b` on the page and its right normal (see [`axes`]).
fn frame_axes(a: (f64, f64), b: (f64, f64)) -> ((f64, f64), (f64, f64)) {
    axes((b.0 - a.0, b.1 - a.1))
}

/// A guide fixed to the ground: a rail on its right under the block, hatched further right.
fn rail(svg: &mut String, page: &Page, s: &Slider) {
    let (Some(a), Some(b)) = (page.at(&s.guide[0]), page.at(&s.guide[1])) else {
        return;
    };
    let (u, v) = frame_axes(a, b);
    let len = (b.0 - a.0).hypot(b.1 - a.1);
    let p = |t: f64, h: f64| {
        format!(
            "{} {}",
            num(a.0 + t * u.0 + h * v.0),
            num(a.1 + t * u.1 + h * v.1)
        )
    };
    let mut d = format!("M{}L{}", p(0.0, BLOCK.1), p(len, BLOCK.1));
    let mut t = 4.0;
    while t <= len {
        let _ = write!(d, "M{}L{}", p(t, BLOCK.1), p(t - 6.0, BLOCK.1 + 7.0));
        t += 10.0;
    }
    let _ = writeln!(
        svg,
        r#"<path d="{d}" fill="none" stroke="{INK}" stroke-width="1.5"/>"#
    );
}
