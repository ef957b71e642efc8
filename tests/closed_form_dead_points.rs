//! The closed-form kernels (`mechgen::runtime::closed_form`) from 1e-2 to 1e-14 (relative) away from
//! their dead points, on generic (rounded) data, against the exact solutions of that very f64
//! data (`tests/data/closed_form/dead_points.txt`, mpmath at 60 digits, made by
//! `make_dead_points.py` beside it): both modes, by the solve from each mode's side and by the
//! `*_modes` lists, to within a few ε/√δ (angles in radians, lengths of order 1).

use mechgen::NewtonReport;
use mechgen::runtime::closed_form::{
    Modes, angle1_modes, rpr_modes, rrp_modes, solve_angle1, solve_rpr, solve_rrp,
};
use mechgen::runtime::trig::TrigState;

/// Errors in units of ε/√δ at most this.
const BOUND: f64 = 4.0;

fn angle_gap(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

/// Kernel answer `(q, s)` from a guess at `q` (`s` is 0 for the one-angle kind).
fn solve(kind: &str, v: &[f64], guess: f64) -> (f64, f64) {
    let mut st = TrigState::new([guess, 0.0], [true, false]);
    let mut report = NewtonReport::new();
    let k = [v[0], v[1]];
    let r = match kind {
        "rrp" => solve_rrp(
            0,
            &mut st,
            0,
            1,
            k,
            (v[2], v[3]),
            [v[4], v[5]],
            || 1.0,
            1e-12,
            &mut report,
            true,
        ),
        "rpr" => solve_rpr(
            0,
            &mut st,
            0,
            1,
            k,
            (v[2], v[3]),
            (v[4], v[5]),
            || 1.0,
            1e-12,
            &mut report,
            true,
        ),
        _ => solve_angle1(
            0,
            &mut st,
            0,
            v[0],
            (v[1], v[2]),
            || 1.0,
            1e-12,
            &mut report,
            true,
        ),
    };
    r.unwrap_or_else(|e| panic!("{kind} {v:?}: {e}"));
    (st.q[0], st.q[1])
}

fn modes(kind: &str, v: &[f64]) -> Modes<f64> {
    let k = [v[0], v[1]];
    match kind {
        "rrp" => rrp_modes(0, k, (v[2], v[3]), [v[4], v[5]]),
        "rpr" => rpr_modes(0, k, (v[2], v[3]), (v[4], v[5])),
        _ => angle1_modes(0, v[0], (v[1], v[2])),
    }
    .expect("assembles")
}

#[test]
fn near_dead_points_on_rounded_data() {
    let text = include_str!("data/closed_form/dead_points.txt");
    let mut worst: Vec<(String, f64)> = Vec::new();
    let mut rows = 0;
    for line in text.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        let kind = f[0];
        let delta: f64 = f[1].parse().expect("δ");
        let n_in = if kind == "angle1" { 3 } else { 6 };
        let nums: Vec<f64> = f[2..].iter().map(|x| x.parse().expect("number")).collect();
        let (v, refs) = nums.split_at(n_in);
        assert_eq!(refs.len(), 4, "{line}");
        let unit = f64::EPSILON / delta.sqrt();
        let listed = modes(kind, v);
        assert_eq!(listed.len(), 2, "{kind} δ = {delta}");
        for (m, want) in refs.chunks(2).enumerate() {
            let (q, s) = solve(kind, v, want[0]);
            let err = angle_gap(q, want[0]).max((s - want[1]).abs()) / unit;
            let got = listed.as_slice()[m].values;
            let err_listed = angle_gap(got[0], want[0]).max((got[1] - want[1]).abs()) / unit;
            assert!(
                err <= BOUND && err_listed <= BOUND,
                "{kind} δ = {delta:e}, mode {m}: solve {err:.2}, modes {err_listed:.2} ε/√δ"
            );
            match worst.iter_mut().find(|(k, _)| k == kind) {
                Some((_, w)) => *w = w.max(err).max(err_listed),
                None => worst.push((kind.to_string(), err.max(err_listed))),
            }
        }
        rows += 1;
    }
    assert_eq!(rows, 39, "13 distances for each of 3 kinds");
    for (kind, w) in worst {
        eprintln!("{kind:<7} largest error {w:.2} ε/√δ");
    }
}
