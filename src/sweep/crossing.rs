//! A row at a crossing (two branches of the configuration curve meeting, as in a parallelogram
//! or kite linkage folding flat): the Jacobian is singular there, so the row's state is not
//! solved but interpolated along the followed branch, whose motion is smooth through the crossing.
//! Part of [`crate::sweep`]: the walker finds the crossing and solves four states on the branch
//! at `target ± h`, `target ± 2h`; this file turns them into the row.
//!
//! The interpolant is the degree-11 Hermite polynomial through the four states' values, first and
//! second derivatives with respect to the input (weights below, exact rationals, derived with
//! sympy); at the middle its value, slope and curvature err by ∝ h¹², h¹¹ and h¹⁰ of the motion's
//! twelfth derivative, so that states a regular distance away (h = half the continuation's
//! largest substep) give the row to the solver's accuracy.

use mechgen_runtime::PointMotion;

/// Weights of the nodes at `t = −2, −1, 1, 2` (in units of h): of their values, of their
/// first derivatives (per unit of t) and of their second derivatives (per unit of t²).
type Weights = ([f64; 4], [f64; 4], [f64; 4]);

/// The polynomial's value at 0.
const VALUE: Weights = (
    [-47.0 / 162.0, 64.0 / 81.0, 64.0 / 81.0, -47.0 / 162.0],
    [-7.0 / 72.0, 4.0 / 27.0, -4.0 / 27.0, 7.0 / 72.0],
    [-1.0 / 108.0, 4.0 / 27.0, 4.0 / 27.0, -1.0 / 108.0],
);
/// Its first derivative at 0 (per unit of t).
const SLOPE: Weights = (
    [445.0 / 2592.0, -100.0 / 81.0, 100.0 / 81.0, -445.0 / 2592.0],
    [23.0 / 432.0, -4.0 / 9.0, -4.0 / 9.0, 23.0 / 432.0],
    [1.0 / 216.0, -4.0 / 27.0, 4.0 / 27.0, -1.0 / 216.0],
);
/// Its second derivative at 0 (per unit of t²).
const CURVE: Weights = (
    [160.0 / 81.0, -160.0 / 81.0, -160.0 / 81.0, 160.0 / 81.0],
    [145.0 / 216.0, 10.0 / 27.0, -10.0 / 27.0, -145.0 / 216.0],
    [7.0 / 108.0, -22.0 / 27.0, -22.0 / 27.0, 7.0 / 108.0],
);

/// The state of the branch at one node: positions and their time rates and accelerations for
/// the input's rate `xd` (zero input acceleration).
#[derive(Clone, Debug, Default)]
pub(super) struct Node {
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    pub qdd: Vec<f64>,
    pub points: Vec<PointMotion<f64>>,
}

/// The row between the nodes: unknowns, their rates and accelerations, points.
#[derive(Clone, Debug, Default)]
pub(super) struct Between {
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    pub qdd: Vec<f64>,
    pub points: Vec<PointMotion<f64>>,
}

/// The value, rate and acceleration at the middle of one quantity whose values, time rates and
/// time accelerations at the nodes are `f`, `g`, `a` (the input moving at `xd`, zero input
/// acceleration; nodes `h` apart in the input).
fn middle(f: [f64; 4], g: [f64; 4], a: [f64; 4], h: f64, xd: f64) -> (f64, f64, f64) {
    // Derivatives per unit of t: d/dt = h d/dx = h/xd d/dtime.
    let g = g.map(|g| g / xd * h);
    let a = a.map(|a| a / (xd * xd) * h * h);
    let at = |(wf, wg, wa): Weights| {
        (0..4)
            .map(|k| wf[k] * f[k] + wg[k] * g[k] + wa[k] * a[k])
            .sum::<f64>()
    };
    let (v, s, c) = (at(VALUE), at(SLOPE), at(CURVE));
    (v, s / h * xd, c / (h * h) * xd * xd)
}

impl Between {
    /// The row at the middle of `nodes` (at `t = −2, −1, 1, 2` times `h` from it), the input
    /// moving at `xd` (nonzero).
    pub fn fill(&mut self, nodes: &[Node; 4], h: f64, xd: f64) {
        let nu = nodes[0].q.len();
        let np = nodes[0].points.len();
        self.q.resize(nu, 0.0);
        self.qd.resize(nu, 0.0);
        self.qdd.resize(nu, 0.0);
        self.points.resize(np, PointMotion::default());
        for u in 0..nu {
            let (v, r, a) = middle(
                nodes.each_ref().map(|n| n.q[u]),
                nodes.each_ref().map(|n| n.qd[u]),
                nodes.each_ref().map(|n| n.qdd[u]),
                h,
                xd,
            );
            (self.q[u], self.qd[u], self.qdd[u]) = (v, r, a);
        }
        for p in 0..np {
            for c in 0..2 {
                let (v, r, a) = middle(
                    nodes.each_ref().map(|n| n.points[p].position[c]),
                    nodes.each_ref().map(|n| n.points[p].velocity[c]),
                    nodes.each_ref().map(|n| n.points[p].acceleration[c]),
                    h,
                    xd,
                );
                let m = &mut self.points[p];
                (m.position[c], m.velocity[c], m.acceleration[c]) = (v, r, a);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_middle_of_a_smooth_motion_is_found_to_its_derivatives() {
        // f(x) = sin(3x + 0.2) around x0 = 0.7, the input moving at 2 per second.
        let (x0, h, xd) = (0.7f64, 0.02, 2.0);
        let f = |x: f64| (3.0 * x + 0.2).sin();
        let df = |x: f64| 3.0 * (3.0 * x + 0.2).cos();
        let t = [-2.0, -1.0, 1.0, 2.0];
        let (v, r, a) = middle(
            t.map(|t| f(x0 + t * h)),
            t.map(|t| df(x0 + t * h) * xd),
            t.map(|t| -9.0 * f(x0 + t * h) * xd * xd),
            h,
            xd,
        );
        assert!((v - f(x0)).abs() < 1e-15, "{v}");
        assert!((r - df(x0) * xd).abs() < 1e-13, "{r}");
        let acc = -9.0 * f(x0) * xd * xd;
        assert!((a - acc).abs() < 1e-11 * acc.abs(), "{a} {acc}");
        // A polynomial of degree 11 is reproduced to rounding.
        let p = |x: f64| x.powi(11) - 2.0 * x.powi(3) + x;
        let dp = |x: f64| 11.0 * x.powi(10) - 6.0 * x * x + 1.0;
        let ddp = |x: f64| 110.0 * x.powi(9) - 12.0 * x;
        let (v, r, a) = middle(t.map(p), t.map(dp), t.map(ddp), 1.0, 1.0);
        assert!(
            v.abs() < 1e-12 && (r - 1.0).abs() < 1e-12 && a.abs() < 1e-11,
            "{v} {r} {a}"
        );
    }
}
