//! Axis ticks of the plots: round tick positions (1-2-5 steps, or 15°, 30°, 45°, 90°… for
//! degrees), a plotters axis whose grid lines and labels sit on them (`Ticked`), and tick-label
//! text that never reads `-0` or `NaN`.

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::types::RangedCoordf64;

/// Tick positions in `[lo, hi]`, about `target` of them, at 1-2-5 steps (at 15°, 30°, 45°, 90°…
/// steps when `degrees`), and the step.
pub(super) fn ticks(lo: f64, hi: f64, target: usize, degrees: bool) -> (Vec<f64>, f64) {
    let span = hi - lo;
    if !(span > 0.0 && span.is_finite()) {
        return (Vec::new(), 1.0);
    }
    let raw = span / target.max(1) as f64;
    let step = if degrees && raw >= 1.0 {
        [1.0, 2.0, 5.0, 10.0, 15.0, 30.0, 45.0, 90.0, 180.0, 360.0]
            .into_iter()
            .find(|s| *s >= raw)
            .unwrap_or(360.0 * (raw / 360.0).ceil())
    } else {
        let mag = 10f64.powf(raw.log10().floor());
        let n = raw / mag;
        mag * if n <= 1.0 {
            1.0
        } else if n <= 2.0 {
            2.0
        } else if n <= 2.5 {
            2.5
        } else if n <= 5.0 {
            5.0
        } else {
            10.0
        }
    };
    let (first, last) = ((lo / step).ceil(), (hi / step).floor());
    if !(first.is_finite() && last.is_finite()) || last - first > 1000.0 {
        return (Vec::new(), step);
    }
    let mut v = Vec::new();
    let mut k = first;
    while k <= last {
        // Snap rounding noise (and -0) to the grid value.
        let t = k * step;
        v.push(if t.abs() < step * 1e-9 { 0.0 } else { t });
        k += 1.0;
    }
    (v, step)
}

/// A linear f64 axis whose grid lines and labels sit at the given round values.
pub(super) struct Ticked {
    inner: RangedCoordf64,
    ticks: Vec<f64>,
}

impl Ticked {
    pub(super) fn new(lo: f64, hi: f64, target: usize, degrees: bool) -> (Ticked, f64) {
        let (ticks, step) = ticks(lo, hi, target, degrees);
        let inner = RangedCoordf64::from(lo..hi);
        (Ticked { inner, ticks }, step)
    }
}

impl Ranged for Ticked {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.inner.map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        // Bold grid lines and labels only; no light lines.
        if hint.weight().allow_light_points() {
            Vec::new()
        } else {
            self.ticks.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.inner.range()
    }
}

/// Tick-label text for ticks `step` apart: as few decimals as the step needs, scientific notation
/// for very large or very small values, never `-0` or `NaN`.
pub(super) fn tick_text(v: f64, step: f64) -> String {
    if !v.is_finite() || v == 0.0 {
        return "0".into();
    }
    let scale = v.abs().max(step.abs());
    if !(1e-4..1e6).contains(&scale) || step.abs() < 1e-4 || step.is_nan() {
        let s = format!("{v:.2e}");
        return match s.split_once('e') {
            Some((m, e)) => {
                let m = m.trim_end_matches('0').trim_end_matches('.');
                format!("{m}e{e}")
            }
            None => s,
        };
    }
    let decimals = (0..=6)
        .find(|d| {
            let f = step * 10f64.powi(*d);
            (f - f.round()).abs() < 1e-6 * f.abs().max(1.0)
        })
        .unwrap_or(6);
    let s = format!("{v:.*}", decimals as usize);
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        "0".into()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_land_on_round_values() {
        assert_eq!(
            ticks(0.0, 360.0, 8, true).0,
            vec![0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0, 360.0]
        );
        assert_eq!(ticks(-0.13, 0.27, 5, false).0.len(), 4);
        assert_eq!(ticks(1.0, 1.0, 5, false).0, Vec::<f64>::new());
        assert_eq!(tick_text(90.0, 45.0), "90");
        assert_eq!(tick_text(-0.25, 0.05), "-0.25");
        assert_eq!(tick_text(0.30000000000000004, 0.1), "0.3");
        assert_eq!(tick_text(2.5e-5, 5e-6), "2.5e-5");
        assert_eq!(tick_text(2.0e6, 5e5), "2e6");
        assert_eq!(tick_text(-1e-12, 0.1), "0");
    }
}
