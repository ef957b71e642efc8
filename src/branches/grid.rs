//! Branch identification, the grid of the input: `CELLS` uniform cells over the range, the start
//! input and the `--at` inputs, and the inputs found where a cell hides a change of the count (a
//! circuit whose whole range lies inside one cell, two dead points closer than a cell). Per cell
//! whose ends have the same count, each closed-form block's margin (`solve::margin`, the distance
//! by which its circles and lines meet or miss) at both ends: when it has one sign at both and is
//! small against how much it can change over the cell, the cell is searched by golden section on
//! the margin, and an input where the count differs is added to the grid.

use super::setup::Setup;

/// Grid cells over the range.
pub(super) const CELLS: usize = 720;

/// Rounds of refining the grid when tracking meets a change of the count inside an interval.
pub(super) const ROUNDS: usize = 8;

/// Passes of the hidden-change search per round: each searches the cells the last one split.
pub(super) const PASSES: usize = 4;

/// How fast a margin may change over a cell, as a multiple of the fastest it changes over that
/// cell and its two neighbours (a smooth margin's slope changes little from cell to cell; near a
/// minimum inside the cell the neighbours' slopes are the larger).
const RATE: f64 = 4.0;

/// The largest slope of margin `i` over cell `k` of `xs` and its neighbours (those with the
/// same count and margins).
fn slope(xs: &[f64], margins: &[(usize, Vec<f64>)], k: usize, i: usize) -> f64 {
    let same = |j: usize| margins[j].0 == margins[k].0 && margins[j].1.len() == margins[k].1.len();
    (k.saturating_sub(1)..(k + 2).min(xs.len() - 1))
        .filter(|&j| same(j) && same(j + 1))
        .map(|j| ((margins[j + 1].1[i] - margins[j].1[i]) / (xs[j + 1] - xs[j])).abs())
        .fold(0.0, f64::max)
}

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

/// The margin searched in a cell: its index, its sign at the ends, the ends' count and number of
/// margins, how fast it may change.
struct Target {
    i: usize,
    sign: f64,
    count: usize,
    len: usize,
    rate: f64,
}

/// The least a margin with these samples (sorted inputs, values) can reach between them.
fn lower_bound(pts: &[(f64, f64)], rate: f64) -> f64 {
    pts.windows(2)
        .map(|w| 0.5 * (w[0].1 + w[1].1 - rate * (w[1].0 - w[0].0)))
        .fold(f64::INFINITY, f64::min)
}

impl Setup {
    /// Inputs inside cells of `xs` whose ends have one count where the count differs.
    pub(super) fn hidden(&self, xs: &[f64]) -> Result<Vec<f64>, String> {
        let margins = xs
            .iter()
            .map(|&x| self.solved(x).map(|(q, m)| (q.len(), m)))
            .collect::<Result<Vec<_>, _>>()?;
        let mut found = Vec::new();
        for k in 0..xs.len() - 1 {
            let (a, b) = (xs[k], xs[k + 1]);
            let ((ca, ma), (cb, mb)) = (&margins[k], &margins[k + 1]);
            if ca != cb || ma.len() != mb.len() {
                continue;
            }
            for i in 0..ma.len() {
                let sign = ma[i].signum();
                let rate = RATE * slope(xs, &margins, k, i);
                let ends = [(a, sign * ma[i]), (b, sign * mb[i])];
                if sign == 0.0 || mb[i].signum() != sign || lower_bound(&ends, rate) > 0.0 {
                    continue;
                }
                let t = Target {
                    i,
                    sign,
                    count: *ca,
                    len: ma.len(),
                    rate,
                };
                if let Some(x) = self.search(ends, &t)? {
                    found.push(x);
                    break;
                }
            }
        }
        Ok(found)
    }

    /// The probe of the margin `t` at `x`.
    fn probe(&self, x: f64, t: &Target) -> Result<Probe, String> {
        let (q, m) = self.solved(x)?;
        Ok(if q.len() != t.count {
            Probe::Changed
        } else if m.len() != t.len {
            Probe::Lost
        } else {
            Probe::Value(t.sign * m[t.i])
        })
    }

    /// Golden-section search of the cell between `ends` (inputs, signed margins) for the least
    /// of the margin `t`: an input where the count differs from the ends', or `None` (also as
    /// soon as the margin cannot reach zero between the samples, given its rate).
    fn search(&self, ends: [(f64, f64); 2], t: &Target) -> Result<Option<f64>, String> {
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let [(a, _), (b, _)] = ends;
        let tol = 1e-13 * (b - a).max(a.abs()).max(b.abs()).max(1.0);
        // The bracket's ends and two inner points, each `(input, value)`.
        let mut p = [
            ends[0],
            (b - g * (b - a), 0.0),
            (a + g * (b - a), 0.0),
            ends[1],
        ];
        for k in [1, 2] {
            match self.probe(p[k].0, t)? {
                Probe::Changed => return Ok(Some(p[k].0)),
                Probe::Lost => return Ok(None),
                Probe::Value(v) => p[k].1 = v,
            }
        }
        while p[3].0 - p[0].0 > tol && lower_bound(&p, t.rate) <= 0.0 {
            let (lo, hi) = (p[0].0, p[3].0);
            let k = if p[1].1 < p[2].1 {
                (p[3], p[2]) = (p[2], p[1]);
                p[1].0 = p[3].0 - g * (p[3].0 - lo);
                1
            } else {
                (p[0], p[1]) = (p[1], p[2]);
                p[2].0 = p[0].0 + g * (hi - p[0].0);
                2
            };
            if !(p[k].0 > p[k - 1].0 && p[k].0 < p[k + 1].0) {
                break;
            }
            match self.probe(p[k].0, t)? {
                Probe::Changed => return Ok(Some(p[k].0)),
                Probe::Lost => return Ok(None),
                Probe::Value(v) => p[k].1 = v,
            }
        }
        Ok(None)
    }
}
