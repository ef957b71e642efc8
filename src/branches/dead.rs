//! Branch identification, dead points and the rounding zones among them: a dead point as tracing
//! finds it, and the windows around a crossing where rounding drops the count for a moment (a
//! pair of count changes that is a `Zone`, not two dead points), which tracing keeps `GUARD` away
//! from and the crossing search looks into.

use std::f64::consts::TAU;

/// A dead point: its input, configuration, and the count below and above it.
#[derive(Clone, Debug)]
pub(super) struct Dead {
    pub input: f64,
    pub q: Vec<f64>,
    pub counts: [usize; 2],
}

/// Widest window (in radians, or in units of the range for a length input) of a count drop that
/// is rounding at a crossing rather than two dead points.
const ZONE: f64 = 1e-6;

/// How far from a crossing (same units) tracks are sampled at least: there the configurations are
/// still good to about 1e-11, and the two tracks are told apart.
pub(super) const GUARD: f64 = 1e-5;

/// A window of inputs around a crossing where rounding drops the count.
#[derive(Clone, Copy, Debug)]
pub(super) struct Zone {
    pub lo: f64,
    pub hi: f64,
}

/// The dead points less those that bound a zone, and the zones: runs of dead points each within
/// `ZONE` of the next, with the same count on both outer sides and fewer configurations inside
/// (at the crossing the kernels give one configuration where the discriminant is within rounding
/// of zero, none where rounding made it negative).
pub(super) fn zones(dead: Vec<Dead>, circular: bool, unit: f64) -> (Vec<Dead>, Vec<Zone>) {
    let m = dead.len();
    if m < 2 {
        return (dead, Vec::new());
    }
    // Runs as index ranges `start..start + len` (indices modulo m for a whole turn).
    let close = |k: usize| {
        let (j, shift) = if k + 1 < m { (k + 1, 0.0) } else { (0, TAU) };
        (k + 1 < m || circular) && dead[j].input + shift - dead[k].input <= ZONE * unit
    };
    // A run starts after a wide gap (on a whole turn, after the first wide gap found).
    let Some(first) = (0..m).find(|&k| !close(k)) else {
        return (dead, Vec::new());
    };
    let start0 = if circular { (first + 1) % m } else { 0 };
    let mut gone = vec![false; m];
    let mut out = Vec::new();
    let mut k = 0;
    while k < m {
        let s = (start0 + k) % m;
        let mut len = 1;
        while k + len < m && close((s + len - 1) % m) {
            len += 1;
        }
        let (a, b) = (&dead[s], &dead[(s + len - 1) % m]);
        let outer = a.counts[0];
        let inner_lower = (0..len).all(|i| dead[(s + i) % m].counts[1] < outer || i + 1 == len);
        if len >= 2 && b.counts[1] == outer && inner_lower {
            let hi = b.input + if (s + len - 1) % m < s { TAU } else { 0.0 };
            out.push(Zone { lo: a.input, hi });
            for i in 0..len {
                gone[(s + i) % m] = true;
            }
        }
        k += len;
    }
    let kept = dead
        .into_iter()
        .zip(gone)
        .filter(|(_, g)| !g)
        .map(|(d, _)| d)
        .collect();
    (kept, out)
}

/// Whether `x` (or `x` ± a turn) lies within `guard` of a zone.
pub(super) fn near_zone(zones: &[Zone], x: f64, guard: f64, circular: bool) -> bool {
    let shifts: &[f64] = if circular { &[-TAU, 0.0, TAU] } else { &[0.0] };
    zones.iter().any(|z| {
        shifts
            .iter()
            .any(|s| x + s > z.lo - guard && x + s < z.hi + guard)
    })
}
