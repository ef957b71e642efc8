//! A walk through a crossing ([`Walker::cross`]): where the branch goes on past a singular
//! point, the row on it, solved past the crossing or interpolated along the branch
//! (`crossing.rs`). Part of `walker.rs`.

use mechgen_runtime::InputMotion;

use super::Walker;
use crate::sweep::crossing::Node;

impl Walker<'_> {
    /// The walk stopped at a singular point on its way from `from` to `target`: where the branch
    /// goes on past it (a crossing, not a dead point, which the branch cannot pass), the row at
    /// `target` on it (solved where it lies past the crossing, else interpolated along the branch
    /// from states at `target ± h`, `± 2h`: [`Between`](crate::sweep::crossing::Between)) and
    /// the walk standing past the crossing. False (the walk where it stopped) at a dead point.
    pub(super) fn cross(&mut self, target: f64) -> bool {
        let i = self.index;
        let from = self.from_x[i];
        if target == from || !target.is_finite() {
            return false;
        }
        let d = (target - from).signum();
        let h = self.h_max / 2.0;
        // Where the walk stopped (the singular point), and the state it left on the branch.
        let xs = self.x.clone();
        let (mut x, mut q) = (self.from_x.clone(), self.from_q.clone());
        let go = |walker: &mut Self, x: &mut Vec<f64>, q: &mut Vec<f64>, to: f64| {
            walker
                .follower
                .continue_within(walker.k, x, q, to, walker.c, &mut walker.allowance)
                .is_ok()
        };
        // To a regular point before it, then past it in one substep along the branch's tangent
        // there (a dead point has no branch past it), then on past the row.
        let at = xs[i];
        if !go(self, &mut x, &mut q, at - d * h) {
            return false;
        }
        let before = (x.clone(), q.clone());
        if !go(self, &mut x, &mut q, at + d * h) || !go(self, &mut x, &mut q, target + 2.0 * d * h)
        {
            return false;
        }
        let beyond = (x.clone(), q.clone());
        // The row itself, reached back from beyond and solved there when it lies past the
        // crossing (a regular state: next to it positions are known only to √ε).
        let reached = self.follower.continue_within(
            self.k,
            &mut x,
            &mut q,
            target,
            self.c,
            &mut self.allowance,
        );
        if reached.is_ok_and(|condition| condition < crate::sweep::DEAD_POINT_CONDITION) {
            (self.x, self.q) = (x, q);
            self.synced = true;
            if self.restart().is_ok() {
                return true;
            }
        }
        // On the crossing: four states on the branch, two on each side.
        let mut nodes: [Node; 4] = Default::default();
        for (k, t) in [-2.0, -1.0, 1.0, 2.0].into_iter().enumerate() {
            // Past the crossing from `beyond`, before it from where the walk stopped.
            let (mut x, mut q) = if t * d > 0.0 {
                beyond.clone()
            } else {
                before.clone()
            };
            if !go(self, &mut x, &mut q, target + t * h) {
                return false;
            }
            let input = InputMotion::new(&x[..], &self.xd[..], &self.xdd[..]);
            if self.ticker.start(input, &q, &self.c.options).is_err() {
                return false;
            }
            let Some(s) = self.ticker.state() else {
                return false;
            };
            nodes[k] = Node {
                q: s.q.to_vec(),
                qd: s.qd.to_vec(),
                qdd: s.qdd.to_vec(),
                points: s.points.to_vec(),
            };
        }
        self.between.fill(&nodes, h, self.xd[i]);
        // The walk goes on from the state past the crossing nearest the row.
        let next = usize::from(d > 0.0) + 1;
        (self.x, self.q) = (xs, nodes[next].q.clone());
        self.x[i] = target + if d > 0.0 { h } else { -h };
        self.synced = true;
        if self.restart().is_err() {
            return false;
        }
        self.at_crossing = true;
        true
    }
}
