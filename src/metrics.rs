//! Design metrics over the start's branch (`mechgen metrics`): each unknown's and point
//! coordinate's min and max with the inputs where they occur, refined between rows to a zero of
//! its rate; the time ratio of an output with exactly two extremes over a full turn; and the
//! transmission angle of every RRR block (the acute angle between its two links). Works on any
//! [`DynMechanism`] (generated or generic); the continuation is the sweep's ([`crate::sweep`]).

use mechgen_codegen::{Compiled, Var};
use mechgen_runtime::{DynMechanism, InputMotion, Kind, PointMotion};

use crate::sweep::{Continuation, Row, continue_to, sweep_holding};

/// The extremes of one output over the range.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputMetrics {
    /// `q3`, `E_x`, …, or `transmission(qa,qb)`.
    pub name: String,
    /// Angle (radians) or length (file units).
    pub kind: Kind,
    pub min: f64,
    pub max: f64,
    /// Where the extremes occur; `None` for an output that does not vary over the range (its rate
    /// is zero on every row: min = max, no input singled out).
    pub input_at_min: Option<f64>,
    pub input_at_max: Option<f64>,
    /// Over a full turn of an angle input, for an output with exactly two extremes: the longer
    /// input travel between them over the shorter (≥ 1). `None` otherwise.
    pub time_ratio: Option<f64>,
}

/// The links of an RRR block: unknowns `a` and `b`, whose links point along `q_a + offsets[0]` and
/// `q_b + offsets[1]` (the arguments of the block's `M_a` and `M_b`, at the start).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RrrLinks {
    pub a: usize,
    pub b: usize,
    pub offsets: [f64; 2],
}

/// Every RRR block of a mechanism's analysis, with its links' angle offsets.
pub fn rrr_links(c: &Compiled) -> Vec<RrrLinks> {
    let m = &c.model;
    let var = |v: Var| match v {
        Var::X(i) => m.inputs[usize::from(i)].start,
        Var::Q(i) => m.unknowns[usize::from(i)].start,
        Var::P(i) => m.params[usize::from(i)].value,
        _ => 0.0,
    };
    c.blocks
        .iter()
        .filter_map(|b| b.dyad.as_ref())
        .map(|d| {
            let v = c.system.dag.eval(&d.roots[2..], &var);
            let at = |n: usize| v[d.roots[n].index()];
            RrrLinks {
                a: d.a,
                b: d.b,
                offsets: [at(3).atan2(at(2)), at(5).atan2(at(4))],
            }
        })
        .collect()
}

/// The metrics of a sweep of input `index` over `values` (from the start, on its branch, the
/// other inputs at `held`): rows that fail (past a dead point) are left out, so the extremes of an
/// input that cannot complete a turn lie on its branch, the last solved rows at the latest.
/// `full_turn`: `values` cover one whole turn of an angle input (for the time ratio).
/// `dead_ends`: the states (input, unknowns) of the dead points that end the branch just outside
/// `values` (as [`crate::branches`] finds them), whose outputs are candidates too: an output's
/// extreme at a dead point is read there, not at the last row before it.
pub fn metrics(
    k: &dyn DynMechanism<f64>,
    index: usize,
    values: &[f64],
    held: &[(usize, f64)],
    full_turn: bool,
    rrr: &[RrrLinks],
    dead_ends: &[(f64, Vec<f64>)],
) -> Vec<OutputMetrics> {
    let info = k.info();
    let kind = info.inputs[index].kind;
    let span = values.last().copied().unwrap_or(0.0) - values.first().copied().unwrap_or(0.0);
    let c = Continuation::for_input(kind, span);
    let rows = sweep_holding(k, index, values, 1.0, held, &c);
    let ok: Vec<&Row> = rows.iter().filter(|r| r.result.is_ok()).collect();
    // Where the branch ends at a dead point inside the range: the extremes of an input that
    // cannot go on lie there (the state the continuation reached, within 1e-10 of it), reached
    // from the solved row next to it.
    let mut ends: Vec<(&Row, f64)> = Vec::new();
    for w in rows.windows(2) {
        match (&w[0].result, &w[1].result) {
            (Ok(_), Err(_)) => ends.extend(w[1].dead_point().map(|s| (&w[0], s.input))),
            (Err(_), Ok(_)) => ends.extend(w[0].dead_point().map(|s| (&w[1], s.input))),
            _ => {}
        }
    }
    let full_turn = full_turn && ok.len() == rows.len();
    let mut x0: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
    for &(i, v) in held {
        x0[i] = v;
    }
    let dead = dead_states(k, &x0, index, &ok, dead_ends);
    let probe = Probe { k, index, x: x0, c };
    let mut outputs: Vec<(String, Kind, Output)> = Vec::new();
    for (i, u) in info.unknowns.iter().enumerate() {
        outputs.push((u.name.clone(), u.kind, Output::Unknown(i)));
    }
    for (p, name) in info.points.iter().enumerate() {
        outputs.push((format!("{name}_x"), Kind::Length, Output::Point(p, 0)));
        outputs.push((format!("{name}_y"), Kind::Length, Output::Point(p, 1)));
    }
    for l in rrr {
        let (a, b) = (&info.unknowns[l.a].name, &info.unknowns[l.b].name);
        outputs.push((
            format!("transmission({a},{b})"),
            Kind::Angle,
            Output::Transmission(*l),
        ));
    }
    outputs
        .into_iter()
        .map(|(name, kind, out)| {
            let mut m = extremes(&probe, &ok, &ends, name, kind, out, full_turn);
            widen(&mut m, &dead, out);
            m
        })
        .collect()
}

/// A dead point's state: its input, unknowns (angles moved by whole turns to the nearest solved
/// row's) and point positions.
struct DeadState {
    input: f64,
    q: Vec<f64>,
    points: Vec<PointMotion<f64>>,
}

/// The states of `dead_ends` with their point positions (rates left zero: they are infinite at a
/// dead point and no extreme needs them); ends the mechanism cannot evaluate are left out.
fn dead_states(
    k: &dyn DynMechanism<f64>,
    x0: &[f64],
    index: usize,
    ok: &[&Row],
    dead_ends: &[(f64, Vec<f64>)],
) -> Vec<DeadState> {
    let info = k.info();
    let mut out = Vec::new();
    for (input, q) in dead_ends {
        let Some(near) = ok
            .iter()
            .min_by(|a, b| (a.input - input).abs().total_cmp(&(b.input - input).abs()))
            .and_then(|r| r.result.as_ref().ok())
        else {
            continue;
        };
        let q: Vec<f64> = q
            .iter()
            .zip(&near.q)
            .zip(&info.unknowns)
            .map(|((&v, &n), u)| match u.kind {
                Kind::Angle => crate::sweep::nearest_turn(v, n),
                _ => v,
            })
            .collect();
        let mut x = x0.to_vec();
        x[index] = *input;
        let zeros = vec![0.0; q.len()];
        let xz = vec![0.0; x.len()];
        let mut points = vec![PointMotion::default(); info.points.len()];
        let motion = InputMotion::new(&x[..], &xz[..], &xz[..]);
        if k.points(motion, &q, &zeros, &zeros, &mut points).is_ok() {
            out.push(DeadState {
                input: *input,
                q,
                points,
            });
        }
    }
    out
}

/// `m` widened by the outputs' values at the dead points that end the branch.
fn widen(m: &mut OutputMetrics, dead: &[DeadState], out: Output) {
    if m.input_at_min.is_none() {
        return; // an output that does not vary
    }
    let zeros = vec![0.0; dead.first().map_or(0, |d| d.q.len())];
    for d in dead {
        let mut v = out.at(&d.q, &zeros, &d.points).0;
        if matches!(out, Output::Transmission(_)) {
            let m = v.rem_euclid(std::f64::consts::PI);
            v = m.min(std::f64::consts::PI - m);
        }
        if !v.is_finite() {
            continue;
        }
        if v < m.min {
            (m.min, m.input_at_min) = (v, Some(d.input));
        }
        if v > m.max {
            (m.max, m.input_at_max) = (v, Some(d.input));
        }
    }
}

/// What an output reads of a solved state.
#[derive(Clone, Copy, Debug)]
enum Output {
    Unknown(usize),
    Point(usize, usize),
    /// The signed angle between the links (continuous); the metric is its acute fold.
    Transmission(RrrLinks),
}

impl Output {
    /// Value and rate (per unit of input) at a solved state.
    fn at(self, q: &[f64], qd: &[f64], points: &[PointMotion<f64>]) -> (f64, f64) {
        match self {
            Output::Unknown(i) => (q[i], qd[i]),
            Output::Point(p, c) => (points[p].position[c], points[p].velocity[c]),
            Output::Transmission(l) => (
                q[l.a] + l.offsets[0] - q[l.b] - l.offsets[1],
                qd[l.a] - qd[l.b],
            ),
        }
    }
}

/// Solves states between rows: from a row's state by continuation, then rates at input rate 1.
struct Probe<'a> {
    k: &'a dyn DynMechanism<f64>,
    index: usize,
    x: Vec<f64>,
    c: Continuation,
}

impl Probe<'_> {
    /// Value and rate of `out` at input `t`, continuing from row `from`; `None` if unreachable.
    fn eval(&self, from: &Row, t: f64, out: Output) -> Option<(f64, f64)> {
        let s = from.result.as_ref().ok()?;
        let (mut x, mut q) = (self.x.clone(), s.q.clone());
        x[self.index] = from.input;
        continue_to(self.k, &mut x, &mut q, self.index, t, &self.c).ok()?;
        let mut xd = vec![0.0; x.len()];
        xd[self.index] = 1.0;
        let xdd = vec![0.0; x.len()];
        let mut qd = vec![0.0; q.len()];
        self.k.solve_velocity(&x, &q, &xd, &mut qd).ok()?;
        let mut points = vec![PointMotion::default(); s.points.len()];
        let qdd = vec![0.0; q.len()];
        let input = InputMotion::new(&x[..], &xd[..], &xdd[..]);
        self.k.points(input, &q, &qd, &qdd, &mut points).ok()?;
        Some(out.at(&q, &qd, &points))
    }

    /// The input in `[rows[i], rows[i+1]]` where the rate of `out` changes sign, by bisection to
    /// 1e-12 of the input's scale, with the value there.
    fn zero_of_rate(&self, lo: &Row, hi: &Row, r_lo: f64, out: Output) -> Option<(f64, f64)> {
        let (mut a, mut b, mut ra) = (lo.input, hi.input, r_lo);
        let mut best = None;
        for _ in 0..60 {
            let t = 0.5 * (a + b);
            let (v, r) = self.eval(lo, t, out)?;
            best = Some((t, v));
            if (r > 0.0) == (ra > 0.0) {
                (a, ra) = (t, r);
            } else {
                b = t;
            }
            if (b - a).abs() <= 1e-12 * lo.input.abs().max(1.0) {
                break;
            }
        }
        best
    }
}

impl Probe<'_> {
    /// The input in [lo, hi] where the links of a transmission angle cross at a right angle (the
    /// cosine of their angle changes sign), by bisection to 1e-12 of the input's scale.
    fn right_angle(&self, lo: &Row, hi: &Row, c_lo: f64, out: Output) -> Option<f64> {
        let (mut a, mut b, mut ca) = (lo.input, hi.input, c_lo);
        for _ in 0..60 {
            let t = 0.5 * (a + b);
            let c = self.eval(lo, t, out)?.0.cos();
            if (c > 0.0) == (ca > 0.0) {
                (a, ca) = (t, c);
            } else {
                b = t;
            }
            if (b - a).abs() <= 1e-12 * lo.input.abs().max(1.0) {
                break;
            }
        }
        Some(0.5 * (a + b))
    }
}

/// Min, max (refined), their inputs and the time ratio of one output over the solved rows.
fn extremes(
    p: &Probe,
    rows: &[&Row],
    ends: &[(&Row, f64)],
    name: String,
    kind: Kind,
    out: Output,
    full_turn: bool,
) -> OutputMetrics {
    let vr: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|r| r.result.as_ref().ok())
        .map(|s| out.at(&s.q, &s.qd, &s.points))
        .collect();
    let fold = matches!(out, Output::Transmission(_));
    let acute = |v: f64| {
        let m = v.rem_euclid(std::f64::consts::PI);
        m.min(std::f64::consts::PI - m)
    };
    let value = |v: f64| if fold { acute(v) } else { v };
    // Candidates: every row, and every refined zero of the rate between rows.
    let mut cand: Vec<(f64, f64)> = rows
        .iter()
        .zip(&vr)
        .map(|(r, vr)| (r.input, value(vr.0)))
        .collect();
    for &(row, t) in ends {
        if let Some((v, _)) = p.eval(row, t, out) {
            cand.push((t, value(v)));
        }
    }
    let mut turns = Vec::new();
    let scale = vr.iter().fold(0.0f64, |m, v| m.max(v.1.abs()));
    let flat = scale <= 1e-12;
    for i in 0..rows.len().saturating_sub(1) {
        let (r0, r1) = (vr[i].1, vr[i + 1].1);
        // (A zero exactly at a row is the row's own turn, below.)
        if !flat
            && r0 != 0.0
            && r1 != 0.0
            && (r0 > 0.0) != (r1 > 0.0)
            && let Some((t, v)) = p.zero_of_rate(rows[i], rows[i + 1], r0, out)
        {
            cand.push((t, value(v)));
            turns.push(t);
        }
        if fold {
            // The acute angle is 90° where the links cross at a right angle.
            let (a, b) = (vr[i].0, vr[i + 1].0);
            let half = std::f64::consts::FRAC_PI_2;
            if ((a - half) / std::f64::consts::PI).floor()
                != ((b - half) / std::f64::consts::PI).floor()
                && let Some(t) = p.right_angle(rows[i], rows[i + 1], a.cos(), out)
            {
                cand.push((t, half));
            }
        }
    }
    // A zero of the rate exactly at a row (a symmetric output at a row's input): a turn when the
    // rate changes sign across it (the first and last rows of a full turn are one state).
    let n = vr.len();
    for i in 0..n {
        let (prev, next) = match i {
            0 if full_turn && n > 2 => (vr[n - 2].1, vr[1].1),
            _ if i == 0 || i + 1 == n => continue,
            _ => (vr[i - 1].1, vr[i + 1].1),
        };
        if !flat && vr[i].1 == 0.0 && prev != 0.0 && (prev > 0.0) != (next > 0.0) {
            turns.push(rows[i].input);
        }
    }
    if flat {
        let v = cand.first().map_or(0.0, |c| c.1);
        return OutputMetrics {
            name,
            kind,
            min: v,
            max: v,
            input_at_min: None,
            input_at_max: None,
            time_ratio: None,
        };
    }
    let min = extreme(&cand, |a, b| a < b);
    let max = extreme(&cand, |a, b| a > b);
    let time_ratio = (full_turn && !fold && turns.len() == 2).then(|| {
        let tau = std::f64::consts::TAU;
        let a = (turns[1] - turns[0]).rem_euclid(tau);
        a.max(tau - a) / a.min(tau - a)
    });
    OutputMetrics {
        name,
        kind,
        min: min.1,
        max: max.1,
        input_at_min: Some(min.0),
        input_at_max: Some(max.0),
        time_ratio,
    }
}

/// The extreme of `cand` (input, value) by `better`, with the smallest input among the candidates
/// within rounding (1e-12 relative) of it: an output with two equal extremes (a symmetric one)
/// reports the first, whatever the last bits of each.
fn extreme(cand: &[(f64, f64)], better: impl Fn(f64, f64) -> bool) -> (f64, f64) {
    let best = cand
        .iter()
        .copied()
        .fold(None, |m: Option<(f64, f64)>, c| match m {
            Some(m) if !better(c.1, m.1) => Some(m),
            _ => Some(c),
        })
        .unwrap_or((f64::NAN, f64::NAN));
    let tol = 1e-12 * best.1.abs().max(1.0);
    let input = cand
        .iter()
        .filter(|c| (c.1 - best.1).abs() <= tol)
        .fold(best.0, |m, c| m.min(c.0));
    (input, best.1)
}
