//! The logarithmic axes of `log_log_scatter_svg` (`scatter.rs`): a plotters axis over log10 values
//! with grid lines at powers of ten (and their multiples on short spans), the tick text
//! (`10⁻⁸`, `2·10⁻⁸`, plain from 1 to 10000) and the padded range of the data.

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::types::RangedCoordf64;

/// A log10 axis: bold grid lines and labels at powers of ten (and at 2 and 5 times them when the
/// axis spans fewer than three decades), light lines at the other multiples when it spans fewer
/// than six.
pub(super) struct LogAxis {
    inner: RangedCoordf64,
    bold: Vec<f64>,
    light: Vec<f64>,
}

impl LogAxis {
    /// Over `lo..hi` given in log10 units.
    pub(super) fn new(lo: f64, hi: f64) -> LogAxis {
        let span = hi - lo;
        let mut bold = Vec::new();
        let mut light = Vec::new();
        for d in lo.floor() as i32..=hi.ceil() as i32 {
            for m in 1..10 {
                let v = f64::from(d) + f64::from(m).log10();
                if !(lo..=hi).contains(&v) {
                    continue;
                }
                if m == 1 || (span < 3.0 && (m == 2 || m == 5)) {
                    bold.push(v);
                } else if span < 6.0 {
                    light.push(v);
                }
            }
        }
        LogAxis {
            inner: RangedCoordf64::from(lo..hi),
            bold,
            light,
        }
    }
}

impl Ranged for LogAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.inner.map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.light.clone()
        } else {
            self.bold.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.inner.range()
    }
}

/// Tick text of 10^`exponent`: plain from 1 to 10000, `10⁻⁸` or `2·10⁻⁸` style otherwise.
pub(super) fn decade_text(exponent: f64) -> String {
    let e = exponent.floor();
    let mantissa = 10f64.powf(exponent - e).round() as i64;
    let e = e as i32;
    if (0..=4).contains(&e) {
        return (mantissa * 10i64.pow(e as u32)).to_string();
    }
    let sup: String = e
        .to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            _ => '⁹',
        })
        .collect();
    if mantissa == 1 {
        format!("10{sup}")
    } else {
        format!("{mantissa}·10{sup}")
    }
}

/// The log10 range of positive finite values, padded by `pad` decades and to at least one decade.
pub(super) fn log_range(values: impl IntoIterator<Item = f64>, pad: f64) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite() && *v > 0.0)
        .map(f64::log10)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return None;
    }
    let (lo, hi) = (lo - pad, hi + pad);
    let short = (1.0 - (hi - lo)).max(0.0) / 2.0;
    Some((lo - short, hi + short))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decades_read_as_powers_of_ten() {
        assert_eq!(decade_text(2.0), "100");
        assert_eq!(decade_text(-8.0), "10⁻⁸");
        assert_eq!(decade_text(5.0), "10⁵");
        assert_eq!(
            log_range([1e-3, 1e-5, 0.0, f64::NAN], 0.0),
            Some((-5.0, -3.0))
        );
        assert_eq!(log_range([100.0], 0.0), Some((1.5, 2.5)));
    }

    #[test]
    fn short_spans_get_more_grid_lines() {
        // Under three decades: bold lines at 1, 2 and 5 times the powers of ten.
        let short = LogAxis::new(0.0, 2.0);
        assert_eq!(short.bold.len(), 7);
        // Six or more: powers of ten only, no light lines.
        let long = LogAxis::new(-8.0, 0.0);
        assert_eq!((long.bold.len(), long.light.len()), (9, 0));
    }
}
