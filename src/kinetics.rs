//! Inverse dynamics along a sweep, what `mechgen dynamics` and Python's `Mechanism.dynamics`
//! print: loads that act over an angle range (the runtime's [`PointLoad`] with a range,
//! `--load P=FX,FY@A:B`), a solved
//! row's dynamics at an input rate and acceleration ([`row_dynamics`], on the runtime's one
//! [`dynamics`]), the CSV's column names ([`COLUMNS`]), and the [`flywheel`] an angle input needs
//! over one turn at constant speed: the mean effort, the largest swing of the work excess
//! ∫(mean − effort) dx and the flywheel inertia ΔW / (δ ω²), as integrals to rounding level,
//! independent of any sweep's row spacing: 8-point Gauss–Legendre on 1° panels (split where a
//! load starts or stops acting), each panel's effort interpolated through its nodes to find where
//! the work excess turns.

use std::f64::consts::TAU;

use mechgen_runtime::dynamics::{Dynamics, DynamicsWork, PointLoad, dynamics};
use mechgen_runtime::{DynMechanism, SolveError, State};

use crate::sweep::plan::Plan;
use crate::sweep::{Continuation, SolvedRef, sweep_each};

/// The dynamics columns of the CSV after the input and the unknowns, for input `x`: `effort_x`,
/// `inertia_x_x`, then these (interfaces.md, `mechgen dynamics`).
pub const COLUMNS: [&str; 5] = [
    "kinetic_energy",
    "potential_energy",
    "shaking_fx",
    "shaking_fy",
    "shaking_moment",
];

/// `Ok` for a mechanism with bodies; else the message every surface gives (`what`: "use
/// dynamics", "simulate it").
pub fn require_bodies(info: &mechgen_runtime::MechanismInfo, what: &str) -> Result<(), String> {
    if info.bodies.is_empty() {
        return Err(format!(
            "`{}` has no bodies: give each moving body a [mechanism.{}.bodies.NAME] table (angle, mass, com, inertia) to {what}",
            info.name, info.name
        ));
    }
    Ok(())
}

/// Every dynamics column's name for input `x`, in the CSV's order.
pub fn column_names(x: &str) -> Vec<String> {
    let mut out = vec![format!("effort_{x}"), format!("inertia_{x}_{x}")];
    out.extend(COLUMNS.iter().map(|c| c.to_string()));
    out
}

/// A [`Dynamics`]'s values in the order of [`column_names`].
pub fn values(d: &Dynamics<f64>) -> [f64; 7] {
    [
        d.effort,
        d.inertia,
        d.kinetic,
        d.potential,
        d.shaking_force[0],
        d.shaking_force[1],
        d.shaking_moment,
    ]
}

/// What [`row_dynamics`] works in, grown once for a mechanism ([`RowWork::new`]): then a row's
/// dynamics allocates nothing.
#[derive(Clone, Debug)]
pub struct RowWork {
    dynamics: DynamicsWork<f64>,
    xd: Vec<f64>,
    xdd: Vec<f64>,
    qdd: Vec<f64>,
}

impl RowWork {
    /// Sized for the mechanism `info` describes.
    pub fn new(info: &mechgen_runtime::MechanismInfo) -> Self {
        let (ni, nu) = (info.inputs.len(), info.unknowns.len());
        RowWork {
            dynamics: DynamicsWork::new(info),
            xd: vec![0.0; ni],
            xdd: vec![0.0; ni],
            qdd: vec![0.0; nu],
        }
    }
}

/// The dynamics of a solved sweep row `s` at inputs `x`, the input `index` moving at `rate` and
/// accelerating at `acc` (its accelerations solved again when `acc` is not 0: the sweep solves
/// them at rest), the other inputs at rest, under the loads acting at `x[index]`. Slices of the
/// wrong length for `ws`'s mechanism: `BadLength`.
pub fn row_dynamics(
    k: &dyn DynMechanism<f64>,
    x: &[f64],
    index: usize,
    s: &SolvedRef<'_>,
    (rate, acc): (f64, f64),
    loads: &[PointLoad<f64>],
    ws: &mut RowWork,
) -> Result<Dynamics<f64>, SolveError> {
    let RowWork {
        dynamics: work,
        xd,
        xdd,
        qdd,
    } = ws;
    mechgen_runtime::error::len(x, xd.len())?;
    mechgen_runtime::error::len(s.qdd, qdd.len())?;
    xd.fill(0.0);
    xdd.fill(0.0);
    if let (Some(v), Some(a)) = (xd.get_mut(index), xdd.get_mut(index)) {
        (*v, *a) = (rate, acc);
    }
    qdd.copy_from_slice(s.qdd);
    if acc != 0.0 {
        k.solve_acceleration(x, s.q, xd, s.qd, xdd, qdd)?;
    }
    let state = State {
        x,
        xd: &xd[..],
        xdd: &xdd[..],
        q: s.q,
        qd: s.qd,
        qdd: &qdd[..],
        points: s.points,
        report: Default::default(),
    };
    dynamics(k, &state, index, loads, work)
}

/// What `--flywheel` prints.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flywheel {
    /// The turn's start (radians).
    pub from: f64,
    pub mean_effort: f64,
    pub max_energy_fluctuation: f64,
    pub flywheel_inertia: f64,
}

/// Gauss–Legendre nodes on [−1, 1] (positive half) and weights, 8 points.
const NODES: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
const WEIGHTS: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// The 8 nodes (ascending) and weights of `[a, b]`.
fn rule(a: f64, b: f64) -> [(f64, f64); 8] {
    let (m, h) = ((a + b) / 2.0, (b - a) / 2.0);
    let mut out = [(0.0, 0.0); 8];
    for i in 0..4 {
        out[3 - i] = (m - h * NODES[i], h * WEIGHTS[i]);
        out[4 + i] = (m + h * NODES[i], h * WEIGHTS[i]);
    }
    out
}

/// The polynomial through `(xs, ys)` at `x` (barycentric form, Lagrange weights).
fn interpolate(xs: &[f64; 8], ys: &[f64; 8], x: f64) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for i in 0..8 {
        if x == xs[i] {
            return ys[i];
        }
        let mut w = 1.0;
        for j in 0..8 {
            if j != i {
                w /= xs[i] - xs[j];
            }
        }
        let t = w / (x - xs[i]);
        num += t * ys[i];
        den += t;
    }
    num / den
}

/// The flywheel of the swept angle input of `plan` over one turn from its first value at
/// constant `rate` (rad/s), under `loads`, for a speed fluctuation `delta` (ω within ±δ/2). An
/// error where a turn's node does not solve (the branch ends inside the turn) or the rate is 0.
pub fn flywheel(
    k: &dyn DynMechanism<f64>,
    plan: &Plan,
    rate: f64,
    loads: &[PointLoad<f64>],
    delta: f64,
) -> Result<Flywheel, String> {
    if rate == 0.0 || delta.is_nan() || delta <= 0.0 {
        return Err("needs a non-zero --rate and DELTA > 0".into());
    }
    let from = plan.values.first().copied().unwrap_or(0.0);
    let mut ends: Vec<f64> = (0..=360)
        .map(|d| from + f64::from(d).to_radians())
        .collect();
    for l in loads {
        for e in l.range.into_iter().flatten() {
            // The load's ends inside the turn.
            let t = from + (e - from).rem_euclid(TAU);
            ends.push(t);
        }
    }
    ends.sort_by(f64::total_cmp);
    ends.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    let panels: Vec<[(f64, f64); 8]> = ends.windows(2).map(|w| rule(w[0], w[1])).collect();
    let nodes: Vec<f64> = panels.iter().flatten().map(|n| n.0).collect();
    let info = k.info();
    let index = plan.index;
    let mut x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
    for &(i, v) in &plan.held {
        x[i] = v;
    }
    let mut ws = RowWork::new(&info);
    let mut efforts = Vec::with_capacity(nodes.len());
    let mut failed = None;
    let continuation = Continuation::for_input(info.inputs[index].kind, TAU);
    sweep_each(
        k,
        index,
        &nodes,
        rate,
        &plan.held,
        &continuation,
        &mut |r| {
            let effort = r.result.map_err(|e| e.status()).and_then(|s| {
                x[index] = r.input;
                row_dynamics(k, &x, index, &s, (rate, 0.0), loads, &mut ws)
                    .map(|d| d.effort)
                    .map_err(|e| e.status())
            });
            match effort {
                Ok(e) if e.is_finite() => efforts.push(e),
                Ok(_) => failed = failed.or(Some((r.input, "overflow"))),
                Err(status) => failed = failed.or(Some((r.input, status))),
            }
        },
    );
    if let Some((at, status)) = failed {
        return Err(format!(
            "the row at {:.6} deg is {status}: the branch does not run a whole turn",
            at.to_degrees()
        ));
    }
    let total: f64 = panels
        .iter()
        .flatten()
        .zip(&efforts)
        .map(|((_, w), e)| w * e)
        .sum();
    let mean = total / TAU;
    // The work excess W(x) = ∫ from the start (mean − effort): at every panel's ends, and where
    // it turns inside a panel (mean − effort changes sign: found on the panel's interpolant).
    let (mut w, mut lo, mut hi) = (0.0f64, 0.0f64, 0.0f64);
    for (panel, e) in panels.iter().zip(efforts.chunks_exact(8)) {
        let xs: [f64; 8] = panel.map(|n| n.0);
        let ys: [f64; 8] = std::array::from_fn(|i| e[i]);
        let (a, b) = (ends_of(panel).0, ends_of(panel).1);
        let f = |t: f64| mean - interpolate(&xs, &ys, t);
        let excess_to = |t: f64| -> f64 { rule(a, t).iter().map(|&(u, wt)| wt * f(u)).sum() };
        let samples = 16;
        let at = |i: usize| a + (b - a) * i as f64 / samples as f64;
        for i in 0..samples {
            let (mut l, mut r) = (at(i), at(i + 1));
            if f(l).signum() == f(r).signum() {
                continue;
            }
            for _ in 0..80 {
                let m = 0.5 * (l + r);
                if m <= l || m >= r {
                    break;
                }
                if f(m).signum() == f(l).signum() {
                    l = m;
                } else {
                    r = m;
                }
            }
            let turn = w + excess_to(0.5 * (l + r));
            lo = lo.min(turn);
            hi = hi.max(turn);
        }
        w += panel
            .iter()
            .zip(e)
            .map(|(&(_, wt), e)| wt * (mean - e))
            .sum::<f64>();
        lo = lo.min(w);
        hi = hi.max(w);
    }
    let swing = hi - lo;
    Ok(Flywheel {
        from,
        mean_effort: mean,
        max_energy_fluctuation: swing,
        flywheel_inertia: swing / (delta * rate * rate),
    })
}

/// A panel's ends from its nodes' rule (the nodes are symmetric about the middle).
fn ends_of(panel: &[(f64, f64); 8]) -> (f64, f64) {
    let h: f64 = panel.iter().map(|n| n.1).sum::<f64>() / 2.0;
    let m = 0.5 * (panel[0].0 + panel[7].0);
    (m - h, m + h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rule_integrates_degree_fifteen_exactly() {
        let f = |x: f64| x.powi(15) - 3.0 * x.powi(8) + x;
        let exact = |x: f64| x.powi(16) / 16.0 - x.powi(9) / 3.0 + x * x / 2.0;
        let got: f64 = rule(0.3, 1.7).iter().map(|&(x, w)| w * f(x)).sum();
        let want = exact(1.7) - exact(0.3);
        assert!((got - want).abs() < 1e-13 * want.abs(), "{got} {want}");
        let (a, b) = ends_of(&rule(0.3, 1.7));
        assert!((a - 0.3).abs() < 1e-15 && (b - 1.7).abs() < 1e-15);
    }

    #[test]
    fn ranges_wrap_through_zero() {
        let l = |a: f64, b: f64| PointLoad::over(0, [1.0, 0.0], [a.to_radians(), b.to_radians()]);
        assert!(l(120.0, 300.0).acts_at(200f64.to_radians()));
        assert!(!l(120.0, 300.0).acts_at(30f64.to_radians()));
        assert!(l(300.0, 60.0).acts_at(10f64.to_radians()));
        assert!(l(300.0, 60.0).acts_at((-10f64).to_radians()));
        assert!(!l(300.0, 60.0).acts_at(100f64.to_radians()));
        assert!(l(0.0, 360.0).acts_at(1.0));
    }
}
