//! Branch identification, crossings: singular configurations where two tracks of different
//! assembly modes meet and go on (a toggle or a parallelogram with equal links), as opposed to
//! dead points, where one track turns back. Rounding can make the count drop on a tiny window
//! around a crossing (the discriminant that touches zero dips below it): such a pair of count
//! changes is a `Zone`, not two dead points, and no track is sampled inside it. A crossing is
//! found where the difference of two tracks of one interval reverses between two samples, then
//! located by secants on that difference, closer and closer, to about 1e-10.

use std::f64::consts::TAU;

use super::dead::GUARD;
use super::setup::Setup;
use super::trace::{Interval, turn_rem};

/// A crossing found on the tracks of an interval.
#[derive(Clone, Debug)]
pub(super) struct Found {
    pub input: f64,
    pub q: Vec<f64>,
    /// The interval and its two tracks that meet.
    pub iv: usize,
    pub tracks: [usize; 2],
    /// dq/dx of each track there.
    pub slopes: [Vec<f64>; 2],
}

impl Setup {
    /// The difference of two configurations, angles through their short arc, lengths relative to
    /// the length scale.
    fn diff(&self, a: &[f64], b: &[f64]) -> Vec<f64> {
        let mut d = vec![0.0; a.len().min(b.len())];
        self.diff_into(a, b, &mut d);
        d
    }

    /// [`Setup::diff`] into `out`; whether every component is below 1 in size.
    fn diff_into(&self, a: &[f64], b: &[f64], out: &mut [f64]) -> bool {
        let mut small = true;
        for (((x, y), &ang), d) in a.iter().zip(b).zip(&self.angle).zip(out) {
            *d = if ang {
                turn_rem(x - y + TAU / 2.0) - TAU / 2.0
            } else {
                (x - y) / self.scale
            };
            small &= d.abs() < 1.0;
        }
        small
    }

    /// `a + t (b − a)` (angles through their short arc).
    fn lerp(&self, a: &[f64], b: &[f64], t: f64) -> Vec<f64> {
        let d = self.diff(b, a);
        a.iter()
            .zip(d)
            .zip(&self.angle)
            .map(|((x, d), &ang)| x + t * if ang { d } else { d * self.scale })
            .collect()
    }

    /// The crossings of the tracks of interval `iv`: every pair whose difference reverses between
    /// two samples and vanishes there.
    pub(super) fn crossings(&self, iv: usize, v: &Interval, unit: f64) -> Vec<Found> {
        let mut out = Vec::new();
        let n = v.tracks.len();
        // Each sample's difference once (it is the next pair of samples' first), in two buffers.
        let width = self.angle.len();
        let (mut d0, mut d1) = (vec![0.0; width], vec![0.0; width]);
        for a in 0..n {
            for b in a + 1..n {
                let (ta, tb) = (&v.tracks[a], &v.tracks[b]);
                let samples = ta.len().min(tb.len());
                if samples == 0 {
                    continue;
                }
                let mut small0 = self.diff_into(&ta[0].1, &tb[0].1, &mut d0);
                for i in 1..samples {
                    let small1 = self.diff_into(&ta[i].1, &tb[i].1, &mut d1);
                    let dot: f64 = d0.iter().zip(&d1).map(|(x, y)| x * y).sum();
                    let reverses = dot < 0.0 && small0 && small1;
                    std::mem::swap(&mut d0, &mut d1);
                    small0 = small1;
                    if !reverses {
                        continue;
                    }
                    let ends = [
                        (ta[i - 1].clone(), tb[i - 1].clone()),
                        (ta[i].clone(), tb[i].clone()),
                    ];
                    if let Some((input, q, slopes)) = self.locate(ends, unit) {
                        out.push(Found {
                            input,
                            q,
                            iv,
                            tracks: [a, b],
                            slopes,
                        });
                    }
                }
            }
        }
        out
    }

    /// The configurations at `x` nearest to the predictions `pa`, `pb` (each its own, and the
    /// nearest by a clear margin), or `None`.
    fn pick(&self, x: f64, pa: &[f64], pb: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
        let qs = self.count(x).ok()?;
        let nearest = |p: &[f64]| {
            let mut d: Vec<(f64, usize)> = qs
                .iter()
                .enumerate()
                .map(|(k, q)| (self.dist(p, q), k))
                .collect();
            d.sort_by(|a, b| a.0.total_cmp(&b.0));
            match d.as_slice() {
                [] => None,
                [one] => Some(one.1),
                [first, second, ..] => (first.0 <= 0.5 * second.0).then_some(first.1),
            }
        };
        let (ka, kb) = (nearest(pa)?, nearest(pb)?);
        (ka != kb).then(|| (qs[ka].clone(), qs[kb].clone()))
    }

    /// The crossing between two samples `ends` (input, track a's and b's configurations, as
    /// `((x, qa), (x, qb))`), when the two tracks meet there: its input, configuration and the
    /// two tracks' slopes.
    #[allow(clippy::type_complexity)]
    fn locate(
        &self,
        ends: [((f64, Vec<f64>), (f64, Vec<f64>)); 2],
        unit: f64,
    ) -> Option<(f64, Vec<f64>, [Vec<f64>; 2])> {
        let [
            ((mut xl, mut al), (_, mut bl)),
            ((mut xr, mut ar), (_, mut br)),
        ] = ends;
        let u = self.diff(&al, &bl);
        let proj = |a: &[f64], b: &[f64]| -> f64 {
            self.diff(a, b).iter().zip(&u).map(|(x, y)| x * y).sum()
        };
        // Secant steps on the projected difference while the bracket is wide.
        for _ in 0..60 {
            if xr - xl <= 1e-3 * unit {
                break;
            }
            let (fl, fr) = (proj(&al, &bl), proj(&ar, &br));
            let t = (fl / (fl - fr)).clamp(0.1, 0.9);
            let x = xl + t * (xr - xl);
            let (pa, pb) = (self.lerp(&al, &ar, t), self.lerp(&bl, &br, t));
            let (qa, qb) = self.pick(x, &pa, &pb)?;
            if proj(&qa, &qb) > 0.0 {
                (xl, al, bl) = (x, qa, qb);
            } else {
                (xr, ar, br) = (x, qa, qb);
            }
        }
        // Symmetric probes about the secant's root, closer each time.
        let (fl, fr) = (proj(&al, &bl), proj(&ar, &br));
        let mut x = xl + (xr - xl) * fl / (fl - fr);
        let (mut lo, mut hi) = ((xl, al, bl), (xr, ar, br));
        for h in [1e-4 * unit, GUARD * unit] {
            if 2.0 * h >= hi.0 - lo.0 || x - h <= lo.0 || x + h >= hi.0 {
                continue;
            }
            let at = |y: f64| {
                let t = (y - lo.0) / (hi.0 - lo.0);
                self.pick(y, &self.lerp(&lo.1, &hi.1, t), &self.lerp(&lo.2, &hi.2, t))
            };
            let (a0, b0) = at(x - h)?;
            let (a1, b1) = at(x + h)?;
            let (f0, f1) = (proj(&a0, &b0), proj(&a1, &b1));
            if !(f0 > 0.0 && f1 < 0.0) {
                return None;
            }
            let root = (x - h) + 2.0 * h * f0 / (f0 - f1);
            lo = (x - h, a0, b0);
            hi = (x + h, a1, b1);
            x = root;
        }
        // The configuration: both tracks interpolated to the root, which must meet.
        let span = hi.0 - lo.0;
        let t = (x - lo.0) / span;
        let (qa, qb) = (self.lerp(&lo.1, &hi.1, t), self.lerp(&lo.2, &hi.2, t));
        if self.dist(&qa, &qb) > 1e-7 {
            return None;
        }
        let slope = |a: &[f64], b: &[f64]| -> Vec<f64> {
            self.diff(b, a)
                .iter()
                .zip(&self.angle)
                .map(|(d, &ang)| d * if ang { 1.0 } else { self.scale } / span)
                .collect()
        };
        let slopes = [slope(&lo.1, &hi.1), slope(&lo.2, &hi.2)];
        Some((x, self.lerp(&qa, &qb, 0.5), slopes))
    }
}
