//! SVG plots of sweeps (`motion_svg`, `dynamics_svg`), drawings of the mechanism (`drawing_svg`, frames from its
//! structure by `sweep_frames`), its animation (`animation_svg`, `write_animation`) and labelled
//! log-log scatter plots (`log_log_scatter_svg`), drawn with `plotters` into a `String`. Text is
//! laid out with the bundled DejaVu Sans (no system fonts); non-finite values are never drawn, and
//! failed rows are gaps, never joined across.

mod animation;
mod axis;
#[cfg(feature = "runtime")]
mod branches;
mod drawing;
mod dynamics;
#[cfg(feature = "runtime")]
mod frames;
mod log_axis;
mod motion;
mod scatter;
mod symbols;

use std::fmt;
use std::sync::OnceLock;

use plotters::style::{FontStyle, RGBColor};

use axis::{Ticked, tick_text, ticks};

pub use animation::animation_svg;
#[cfg(feature = "runtime")]
pub use branches::branches_svg;
pub use drawing::{drawing_svg, point_paths};
pub use dynamics::{DynamicsRow, dynamics_svg};
#[cfg(feature = "runtime")]
pub use frames::{sweep_frames, write_animation};
pub use motion::motion_svg;
pub use scatter::{Marker, ScatterLayout, log_log_scatter_svg};
pub use symbols::{Frame, Slider};

/// The family name text is registered under and written into the SVG: a generic CSS family, so a
/// viewer without DejaVu Sans still shows a sans-serif face.
const FAMILY: &str = "sans-serif";

/// DejaVu Sans, for text layout (see `assets/fonts/LICENSE-DejaVu.txt`).
static FONT: &[u8] = include_bytes!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/fonts/DejaVuSans.ttf"
));

/// Why a plot could not be made.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PlotError {
    /// The bundled font could not be registered with plotters.
    Font,
    /// The swept input index is not an input of the mechanism.
    BadInput { index: usize, inputs: usize },
    /// Nothing finite to draw.
    NoData,
    /// plotters failed while drawing.
    Drawing(String),
    /// A plot file could not be written (the path and the reason).
    Write(String, String),
}

impl fmt::Display for PlotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PlotError::Font => write!(f, "the bundled plot font could not be loaded"),
            PlotError::BadInput { index, inputs } => write!(
                f,
                "input index {index} out of range (the mechanism has {inputs} input(s))"
            ),
            PlotError::NoData => write!(f, "nothing finite to plot"),
            PlotError::Drawing(e) => write!(f, "plot drawing failed: {e}"),
            PlotError::Write(path, e) => write!(f, "cannot write {path}: {e}"),
        }
    }
}

impl std::error::Error for PlotError {}

/// Maps a plotters drawing error.
fn drawing_error<E: fmt::Display>(e: E) -> PlotError {
    PlotError::Drawing(e.to_string())
}

/// Registers the bundled font once per process; later calls return the first outcome.
fn ensure_font() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED
        .get_or_init(|| plotters::style::register_font(FAMILY, FontStyle::Normal, FONT).is_ok());
    if ok { Ok(()) } else { Err(PlotError::Font) }
}

/// Series colours (a colour-blind-friendly qualitative palette), cycled.
const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(120, 120, 120),
    RGBColor(160, 40, 40),
];

fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Runs of consecutive finite points of one curve.
type Runs = Vec<Vec<(f64, f64)>>;

/// Splits a sequence of optional points into runs of consecutive finite points: `None` and
/// non-finite coordinates end a run.
fn finite_runs<I>(points: I) -> Runs
where
    I: IntoIterator<Item = Option<(f64, f64)>>,
{
    let mut runs = Vec::new();
    let mut run = Vec::new();
    for p in points {
        match p {
            Some((x, y)) if x.is_finite() && y.is_finite() => run.push((x, y)),
            _ => {
                if !run.is_empty() {
                    runs.push(std::mem::take(&mut run));
                }
            }
        }
    }
    if !run.is_empty() {
        runs.push(run);
    }
    runs
}

/// The finite range of `values`, padded by `pad` of its width on each side (and to a nonzero width
/// when all values are equal). `None` when no value is finite.
fn padded_range(values: impl IntoIterator<Item = f64>, pad: f64) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return None;
    }
    let mut width = hi - lo;
    let (mut lo, mut hi) = (lo, hi);
    if !(width > 1e-12 * lo.abs().max(hi.abs()) && width.is_finite()) {
        // All (nearly) equal: a band around the value.
        let mid = lo / 2.0 + hi / 2.0;
        width = mid.abs().max(1.0) * 0.1;
        (lo, hi) = (mid - width / 2.0, mid + width / 2.0);
    }
    let (lo, hi) = (lo - pad * width, hi + pad * width);
    (lo.is_finite() && hi.is_finite()).then_some((lo, hi))
}

/// The y range of a panel whose values may spike (rates near a dead point): the padded full range,
/// unless it is more than three times as wide as the 2nd..98th percentile band; then the range
/// stops one band width past the band and `true` says values were clipped.
fn robust_range(values: &[f64], pad: f64) -> Option<((f64, f64), bool)> {
    let mut v: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    let (&min, &max) = (v.first()?, v.last()?);
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    let (lo, hi) = (at(0.02), at(0.98));
    let band = hi - lo;
    let (a, b) = if max - min > 3.0 * band {
        ((lo - band).max(min), (hi + band).min(max))
    } else {
        (min, max)
    };
    let clipped = a > min || b < max;
    padded_range([a, b], pad).map(|r| (r, clipped))
}

/// Cuts runs of points to the band `y0..=y1`: a segment leaving the band ends its run where it
/// crosses the edge, and one entering starts a new run there.
fn clip_runs(runs: Runs, y0: f64, y1: f64) -> Runs {
    let inside = |p: (f64, f64)| (y0..=y1).contains(&p.1);
    let mut out = Vec::new();
    for run in runs {
        let mut cur: Vec<(f64, f64)> = Vec::new();
        if let Some(&p) = run.first().filter(|p| inside(**p)) {
            cur.push(p);
        }
        for w in run.windows(2) {
            let (p, q) = (w[0], w[1]);
            // The part of the segment inside the band, as parameters t0..t1 along it.
            let (mut t0, mut t1) = (0.0f64, 1.0f64);
            let dy = q.1 - p.1;
            if dy == 0.0 {
                if !inside(p) {
                    continue;
                }
            } else {
                let (ta, tb) = ((y0 - p.1) / dy, (y1 - p.1) / dy);
                t0 = t0.max(ta.min(tb));
                t1 = t1.min(ta.max(tb));
                if t0 > t1 {
                    continue;
                }
            }
            let at = |t: f64| (p.0 + t * (q.0 - p.0), p.1 + t * dy);
            if t0 > 0.0 {
                if cur.len() > 1 {
                    out.push(std::mem::take(&mut cur));
                }
                cur = vec![at(t0)];
            }
            cur.push(if t1 < 1.0 { at(t1) } else { q });
            if t1 < 1.0 {
                if cur.len() > 1 {
                    out.push(std::mem::take(&mut cur));
                }
                cur.clear();
            }
        }
        if !cur.is_empty() {
            out.push(cur);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_split_at_gaps_and_non_finite_values() {
        let pts = [
            Some((0.0, 1.0)),
            Some((1.0, 2.0)),
            None,
            Some((2.0, f64::NAN)),
            Some((3.0, 1.0)),
            Some((f64::INFINITY, 1.0)),
        ];
        let runs = finite_runs(pts);
        assert_eq!(runs, vec![vec![(0.0, 1.0), (1.0, 2.0)], vec![(3.0, 1.0)]]);
    }

    #[test]
    fn ranges_skip_non_finite_values_and_widen_constants() {
        assert_eq!(padded_range([f64::NAN, f64::INFINITY], 0.05), None);
        let (lo, hi) = padded_range([2.0, f64::NAN, 2.0], 0.0).unwrap_or((0.0, 0.0));
        assert!(lo < 2.0 && hi > 2.0);
        assert_eq!(padded_range([0.0, 10.0], 0.1), Some((-1.0, 11.0)));
    }

    #[test]
    fn spikes_are_clipped_and_runs_cut_at_the_band() {
        let mut v: Vec<f64> = (0..100).map(|i| f64::from(i % 10)).collect();
        v.push(1e6);
        let ((lo, hi), clipped) = robust_range(&v, 0.0).unwrap_or(((0.0, 0.0), false));
        assert!(clipped && lo == 0.0 && hi > 9.0 && hi < 20.0, "{lo} {hi}");
        let mut w = v[..100].to_vec();
        w.push(20.0);
        assert!(!robust_range(&w, 0.0).is_some_and(|r| r.1));
        let ((_, hi), clipped) = robust_range(&v[..100], 0.0).unwrap_or(((0.0, 0.0), true));
        assert!(!clipped && hi == 9.0);

        let run = vec![(0.0, 0.0), (1.0, 2.0), (2.0, 0.0), (3.0, 0.5)];
        let cut = clip_runs(vec![run], -1.0, 1.0);
        assert_eq!(
            cut,
            vec![
                vec![(0.0, 0.0), (0.5, 1.0)],
                vec![(1.5, 1.0), (2.0, 0.0), (3.0, 0.5)]
            ]
        );
        assert!(clip_runs(vec![vec![(0.0, 5.0), (1.0, 6.0)]], -1.0, 1.0).is_empty());
    }

    #[test]
    fn font_registers() {
        assert_eq!(ensure_font(), Ok(()));
        assert_eq!(ensure_font(), Ok(()));
    }
}
