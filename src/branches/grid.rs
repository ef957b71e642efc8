//! Branch identification, the grid of the input: `CELLS` uniform cells over the range, the start
//! input and the `--at` inputs, and the inputs found where a cell hides a change of the count (a
//! circuit whose whole range lies inside one cell, two dead points closer than a cell). Per cell
//! whose ends have the same count, each closed-form block's margin (`solve::margin`, the distance
//! by which its circles and lines meet or miss) at both ends: when it has one sign at both and is
//! small against how much it can change over the cell, the cell is searched by golden section on
//! the margin, and an input where the count differs is added to the grid.

use super::Setup;

/// Grid cells over the range.
pub(super) const CELLS: usize = 720;

/// Rounds of refining the grid when tracking meets a change of the count inside an interval.
pub(super) const ROUNDS: usize = 8;

/// How fast a margin may change, per radian of an angle input (times the length scale) or per
/// unit of a length input: a bound with a safety factor (a length moves by at most its lever arm
/// times the angle).
const RATE: f64 = 4.0;

/// The uniform grid: `CELLS + 1` inputs from `from` to `to` (both exact).
pub(super) fn uniform(from: f64, to: f64) -> Vec<f64> {
    (0..=CELLS)
        .map(|i| {
            if i == CELLS {
                to
            } else {
                from + (to - from) * i as f64 / CELLS as f64
            }
        })
        .collect()
}

/// `xs` with the inputs of `extra` inside `[xs[0], xs[last]]`, sorted, near-duplicates once.
pub(super) fn merged(xs: &[f64], extra: &[f64]) -> Vec<f64> {
    let (Some(&lo), Some(&hi)) = (xs.first(), xs.last()) else {
        return xs.to_vec();
    };
    let mut out: Vec<f64> = xs
        .iter()
        .chain(extra.iter().filter(|&&x| x > lo && x < hi))
        .copied()
        .collect();
    out.sort_by(f64::total_cmp);
    out.dedup_by(|a, b| (*a - *b).abs() <= 1e-14 * (1.0 + a.abs()));
    out
}

/// What a probe of a cell found.
enum Probe {
    /// The count differs from the cell's ends: a change hidden in the cell.
    Changed,
    /// The margin searched, signed so that its ends are positive.
    Value(f64),
    /// The margins are not comparable with the ends' (another block's count changed).
    Lost,
}

impl Setup {
    /// Inputs inside cells of `xs` whose ends have one count where the count differs.
    pub(super) fn hidden(&self, xs: &[f64]) -> Result<Vec<f64>, String> {
        let rate = RATE * if self.input_is_angle { self.scale } else { 1.0 };
        let mut found = Vec::new();
        for w in xs.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (qa, ma) = self.solved(a)?;
            let (qb, mb) = self.solved(b)?;
            if qa.len() != qb.len() || ma.len() != mb.len() {
                continue;
            }
            for i in 0..ma.len() {
                let s = ma[i].signum();
                let near = s * ma[i] + s * mb[i] <= rate * (b - a);
                if s == 0.0 || mb[i].signum() != s || !near {
                    continue;
                }
                if let Some(x) = self.search(a, b, i, s, qa.len(), ma.len())? {
                    found.push(x);
                    break;
                }
            }
        }
        Ok(found)
    }

    /// The probe of the margin `i` (of `len`, sign `s` at the ends, count `count`) at `x`.
    fn probe(&self, x: f64, i: usize, s: f64, count: usize, len: usize) -> Result<Probe, String> {
        let (q, m) = self.solved(x)?;
        Ok(if q.len() != count {
            Probe::Changed
        } else if m.len() != len {
            Probe::Lost
        } else {
            Probe::Value(s * m[i])
        })
    }

    /// Golden-section search of `(a, b)` for the least of margin `i`: an input where the count
    /// differs from the ends' `count`, or `None`.
    fn search(
        &self,
        a: f64,
        b: f64,
        i: usize,
        s: f64,
        count: usize,
        len: usize,
    ) -> Result<Option<f64>, String> {
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let (mut lo, mut hi) = (a, b);
        let tol = 1e-13 * (b - a).max(a.abs()).max(b.abs()).max(1.0);
        let mut xs = [hi - g * (hi - lo), lo + g * (hi - lo)];
        let mut vs = [0.0; 2];
        for k in 0..2 {
            match self.probe(xs[k], i, s, count, len)? {
                Probe::Changed => return Ok(Some(xs[k])),
                Probe::Lost => return Ok(None),
                Probe::Value(v) => vs[k] = v,
            }
        }
        while hi - lo > tol {
            let k = if vs[0] < vs[1] {
                hi = xs[1];
                (xs[1], vs[1]) = (xs[0], vs[0]);
                xs[0] = hi - g * (hi - lo);
                0
            } else {
                lo = xs[0];
                (xs[0], vs[0]) = (xs[1], vs[1]);
                xs[1] = lo + g * (hi - lo);
                1
            };
            if !(xs[k] > lo && xs[k] < hi) {
                break;
            }
            match self.probe(xs[k], i, s, count, len)? {
                Probe::Changed => return Ok(Some(xs[k])),
                Probe::Lost => return Ok(None),
                Probe::Value(v) => vs[k] = v,
            }
        }
        Ok(None)
    }
}
