//! Branch identification, tracing: the number of configurations on the grid of the input (`grid`);
//! each cell where it changes holds a dead point, bisected on the count to rounding level (its
//! configuration: the midpoint of the two that merge). The dead points cut the range into
//! intervals of constant count; on each, every configuration is followed from end to end (grid
//! samples, geometric samples down to 1e-10 from a dead point, the `--at` inputs; a linear
//! predictor and an unambiguous nearest match, halving the step otherwise). At a dead point the
//! two tracks that merge are joined as a fold (one circuit, two branches), the others continue. A
//! change of the count met on the way is reported (the analysis adds that input to the grid).

use std::f64::consts::TAU;

use super::dead::{Dead, GUARD, Zone, near_zone};
use super::setup::Setup;

/// One traced configuration: its samples `(input, configuration)` in increasing input.
pub(super) type Track = Vec<(f64, Vec<f64>)>;

/// An interval between dead points (or range ends), inputs unwrapped.
#[derive(Clone, Debug)]
pub(super) struct Interval {
    pub lo: f64,
    pub hi: f64,
    /// Index of the dead point at each end, `None` at a range end.
    pub dead: [Option<usize>; 2],
    /// Per track, its samples `(input, configuration)` in increasing input.
    pub tracks: Vec<Track>,
}

/// What following the configurations across an interval gave.
pub(super) enum Traced {
    Tracks(Vec<Track>),
    /// The count changes at this input: a dead point the grid did not see.
    Changes(f64),
}

/// `d.rem_euclid(2π)`, bit for bit, without its division where `|d| < 2π` (the distances the
/// analysis takes by the million are between angles of one turn).
#[inline]
pub(super) fn turn_rem(d: f64) -> f64 {
    if (0.0..TAU).contains(&d) {
        d
    } else if d > -TAU && d < 0.0 {
        d + TAU
    } else {
        d.rem_euclid(TAU)
    }
}

impl Setup {
    /// [`Setup::configurations`] and the closed-form blocks' margins, remembered for the analysis.
    pub(super) fn solved(&self, x: f64) -> Result<(Vec<Vec<f64>>, Vec<f64>), String> {
        if let Some(r) = self.cache.borrow().get(&x.to_bits()) {
            return Ok(r.clone());
        }
        let r = self.solve_at(x)?;
        self.cache.borrow_mut().insert(x.to_bits(), r.clone());
        Ok(r)
    }

    /// [`Setup::configurations`], remembered for the analysis.
    pub(super) fn count(&self, x: f64) -> Result<Vec<Vec<f64>>, String> {
        self.solved(x).map(|r| r.0)
    }

    /// Distance of two configurations: angles modulo 2π, lengths relative to the length scale
    /// (the largest of the unknowns' differences).
    pub fn dist(&self, a: &[f64], b: &[f64]) -> f64 {
        self.components(a, b).fold(0.0, f64::max)
    }

    /// The unknowns' distances that [`Setup::dist`] takes the largest of.
    fn components<'s>(&'s self, a: &'s [f64], b: &'s [f64]) -> impl Iterator<Item = f64> + 's {
        a.iter().zip(b).zip(&self.angle).map(|((x, y), &ang)| {
            if ang {
                let d = turn_rem(x - y);
                d.min(TAU - d)
            } else {
                (x - y).abs() / self.scale
            }
        })
    }

    /// The midpoint of two nearby configurations (angles through their short arc).
    fn midpoint(&self, a: &[f64], b: &[f64]) -> Vec<f64> {
        a.iter()
            .zip(b)
            .zip(&self.angle)
            .map(|((x, y), &ang)| {
                if ang {
                    let d = turn_rem(y - x + TAU / 2.0) - TAU / 2.0;
                    let m = turn_rem(x + 0.5 * d);
                    if m > TAU / 2.0 { m - TAU } else { m }
                } else {
                    0.5 * (x + y)
                }
            })
            .collect()
    }

    /// Whether `a` and `b` are farther apart than `bound` (by [`Setup::dist`]): decided at the first
    /// component farther apart.
    fn farther(&self, a: &[f64], b: &[f64], bound: f64) -> bool {
        self.components(a, b).any(|d| d > bound)
    }

    /// Whether two of `qs` are within `bound` of each other (by [`Setup::dist`]), each pair left
    /// at its first component farther apart.
    fn any_pair_within(&self, qs: &[Vec<f64>], bound: f64) -> bool {
        (0..qs.len()).any(|i| (i + 1..qs.len()).any(|j| !self.farther(&qs[i], &qs[j], bound)))
    }

    /// The closest pair among `qs`.
    pub(super) fn closest_pair(&self, qs: &[Vec<f64>]) -> Option<(usize, usize)> {
        let mut best: Option<(f64, usize, usize)> = None;
        for i in 0..qs.len() {
            for j in i + 1..qs.len() {
                let d = self.dist(&qs[i], &qs[j]);
                if best.is_none_or(|b| d < b.0) {
                    best = Some((d, i, j));
                }
            }
        }
        best.map(|b| (b.1, b.2))
    }

    /// Dead points in `[from, to]` (grid `xs` with their configurations), by input.
    pub(super) fn dead_points(
        &self,
        xs: &[f64],
        grid: &[Vec<Vec<f64>>],
    ) -> Result<Vec<Dead>, String> {
        let mut dead: Vec<Dead> = Vec::new();
        for i in 0..xs.len() - 1 {
            let (c0, c1) = (grid[i].len(), grid[i + 1].len());
            if c0 == c1 {
                continue;
            }
            let (mut lo, mut hi) = (xs[i], xs[i + 1]);
            let (mut qlo, mut qhi) = (grid[i].clone(), grid[i + 1].clone());
            for _ in 0..200 {
                let m = 0.5 * (lo + hi);
                if m <= lo || m >= hi {
                    break;
                }
                // Keep the full count on its side (at the dead point itself the count is odd).
                let qm = self.count(m)?;
                if (qm.len() >= c0.max(c1)) == (c0 > c1) {
                    (lo, qlo) = (m, qm);
                } else {
                    (hi, qhi) = (m, qm);
                }
            }
            let more = if c0 > c1 { &qlo } else { &qhi };
            let Some((a, b)) = self.closest_pair(more) else {
                continue;
            };
            let input = 0.5 * (lo + hi);
            if dead.last().is_some_and(|d| (d.input - input).abs() <= 1e-9) {
                continue;
            }
            let (input, q) = self.refine_fold(input, self.midpoint(&more[a], &more[b]));
            dead.push(Dead {
                input,
                q,
                counts: [c0, c1],
            });
        }
        Ok(dead)
    }

    /// Follows every configuration across `[lo, hi]` through `xs` (sorted, inside the interval).
    pub(super) fn track(&self, xs: &[f64]) -> Result<Traced, String> {
        let Some(&x0) = xs.first() else {
            return Ok(Traced::Tracks(Vec::new()));
        };
        let mut tracks: Vec<Vec<(f64, Vec<f64>)>> =
            self.count(x0)?.into_iter().map(|q| vec![(x0, q)]).collect();
        let m = tracks.len();
        if m == 0 {
            // Nothing to follow; the count is checked at the grid already.
            return Ok(Traced::Tracks(tracks));
        }
        let mut pending: Vec<f64> = xs[1..].iter().rev().copied().collect();
        // Where each track's configuration was in the last sample's list (the solver lists them
        // in the same order of modes from one input to the next, so usually where it is now).
        let mut guess: Vec<usize> = (0..m).collect();
        let mut depth = 0;
        while let Some(x) = pending.pop() {
            let qs = self.count(x)?;
            if qs.len() != m {
                return Ok(Traced::Changes(x));
            }
            if self.any_pair_within(&qs, 1e-7) {
                // A sample on a crossing: two tracks there cannot be told apart; skip it.
                continue;
            }
            let last = tracks[0].last().map_or(x0, |p| p.0);
            match self.assign(&tracks, x, &qs, &guess) {
                Some(perm) => {
                    depth = 0;
                    for (j, &k) in perm.iter().enumerate() {
                        tracks[j].push((x, qs[k].clone()));
                    }
                    guess = perm;
                }
                None if depth < 40 && (x - last).abs() > 1e-13 => {
                    depth += 1;
                    pending.push(x);
                    pending.push(0.5 * (last + x));
                }
                None => {
                    return Err(format!(
                        "configurations cannot be told apart near input {x} (a crossing?)"
                    ));
                }
            }
        }
        Ok(Traced::Tracks(tracks))
    }

    /// The configuration of `qs` each track continues to, when the match is unambiguous.
    /// `guess[j]`: where track `j`'s configuration is likely to be in `qs`; when it is nearer to
    /// the prediction than half of every other's distance, it is the one (as the full search would
    /// find), and the other distances are cut short.
    fn assign(
        &self,
        tracks: &[Vec<(f64, Vec<f64>)>],
        x: f64,
        qs: &[Vec<f64>],
        guess: &[usize],
    ) -> Option<Vec<usize>> {
        let mut used = vec![false; qs.len()];
        let mut perm = Vec::with_capacity(tracks.len());
        for (j, t) in tracks.iter().enumerate() {
            let (x1, q1) = &t[t.len() - 1];
            let predicted: Vec<f64> = match t.len() {
                1 => q1.clone(),
                n => {
                    let (x0, q0) = &t[n - 2];
                    let r = (x - x1) / (x1 - x0);
                    q1.iter()
                        .zip(q0)
                        .zip(&self.angle)
                        .map(|((a, b), &ang)| {
                            let d = if ang {
                                turn_rem(a - b + TAU / 2.0) - TAU / 2.0
                            } else {
                                a - b
                            };
                            a + d * r
                        })
                        .collect()
                }
            };
            if let Some(&g) = guess.get(j).filter(|&&g| g < qs.len()) {
                let dg = self.dist(&predicted, &qs[g]);
                let clear = (0..qs.len())
                    .filter(|&k| k != g)
                    .all(|k| self.farther(&predicted, &qs[k], 2.0 * dg));
                if dg.is_finite() && clear {
                    if std::mem::replace(&mut used[g], true) {
                        return None;
                    }
                    perm.push(g);
                    continue;
                }
            }
            // The nearest and the distance of the next nearest (the first of equals nearest).
            let (mut best, mut second) = (None::<(f64, usize)>, f64::INFINITY);
            for (k, q) in qs.iter().enumerate() {
                let d = self.dist(&predicted, q);
                if d.is_nan() {
                    continue;
                }
                match best {
                    Some((b, _)) if d >= b => second = second.min(d),
                    _ => {
                        second = best.map_or(f64::INFINITY, |b| b.0);
                        best = Some((d, k));
                    }
                }
            }
            let (d0, k0) = best?;
            if qs.len() > 1 && d0 > 0.5 * second {
                return None;
            }
            if std::mem::replace(&mut used[k0], true) {
                return None;
            }
            perm.push(k0);
        }
        Some(perm)
    }
}

/// Samples of an interval: the grid inside it, geometric ones near dead ends, the `at` inputs.
pub(super) fn samples(
    iv: &Interval,
    grid: &[f64],
    at: &[f64],
    width: f64,
    circular: bool,
    zones: &[Zone],
) -> Vec<f64> {
    let (lo, hi) = (iv.lo, iv.hi);
    let span = hi - lo;
    let mut xs: Vec<f64> = Vec::new();
    // Closer to a dead end than the nearest geometric sample, a sample is left out (the count
    // there may be the dead point's own); an `at` input there is labelled by its nearest sample.
    let guard = 0.5e-10 * width.abs();
    // Near a crossing's zone only its two edge samples.
    let away = GUARD * width.abs();
    let edges: Vec<f64> = zones
        .iter()
        .flat_map(|z| [z.lo - away, z.hi + away])
        .collect();
    let inside = |x: f64| {
        x > lo
            && x < hi
            && (iv.dead[0].is_none() || x > lo + guard)
            && (iv.dead[1].is_none() || x < hi - guard)
            && !near_zone(zones, x, 0.999 * away, circular)
    };
    for &g in grid.iter().chain(at).chain(&edges) {
        for k in [-1.0, 0.0, 1.0, 2.0] {
            let x = g + k * if circular { TAU } else { 0.0 };
            if inside(x) || (x == lo && iv.dead[0].is_none()) || (x == hi && iv.dead[1].is_none()) {
                xs.push(x);
            }
        }
    }
    let w = width.abs();
    for k in 2..=10 {
        let off = w * 10f64.powi(-k);
        if off < 0.25 * span {
            if iv.dead[0].is_some() {
                xs.push(lo + off);
            }
            if iv.dead[1].is_some() {
                xs.push(hi - off);
            }
        }
    }
    if iv.dead[0].is_none() {
        xs.push(lo);
    }
    if iv.dead[1].is_none() {
        xs.push(hi);
    }
    xs.sort_by(f64::total_cmp);
    xs.dedup_by(|a, b| (*a - *b).abs() <= 1e-14 * (1.0 + a.abs()));
    xs
}

#[cfg(test)]
mod tests {
    use super::turn_rem;
    use std::f64::consts::TAU;

    /// `turn_rem` is `rem_euclid(2π)` bit for bit, on its fast path and off it.
    #[test]
    fn turn_rem_is_rem_euclid() {
        let mut d: f64 = -40.0;
        while d < 40.0 {
            for x in [
                d,
                d.next_up(),
                -d,
                1e-300,
                -1e-300,
                0.0,
                -0.0,
                TAU,
                -TAU,
                TAU.next_down(),
            ] {
                assert_eq!(turn_rem(x).to_bits(), x.rem_euclid(TAU).to_bits(), "{x:e}");
            }
            d += 0.0137;
        }
    }
}
