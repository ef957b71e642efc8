//! The first tick of W instances in lanes: each lane solved from its guess by the common path of
//! a tick (the generated `motion_lanes`, as the scalar `tick_start` solves by `motion_cached`),
//! with every sine and cosine computed afresh; each lane that leaves it started by the scalar
//! `tick_start`.

// Index loops over several parallel arrays read better than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use super::state::{LaneFixed, LaneState, LaneTick, Memo};
use super::tick::{LanePath, LaneShape, ScalarLane, restart, store};
use super::{LaneReport, LaneTrig, Lanes};
use crate::info::PointMotion;
use crate::scalar::Real;

/// The sines and cosines of the values in `v` with `angle[k]`, computed afresh lane by lane
/// (`(0, 1)` for the others), as the scalar `trig_fixed` and `TrigState::new` make them.
fn fresh<L: Lanes, const N: usize>(v: &[L; N], angle: [bool; N]) -> [(L, L); N] {
    core::array::from_fn(|k| {
        if angle[k] {
            v[k].sin_cos()
        } else {
            (L::zero(), L::one())
        }
    })
}

/// The first tick of W instances to the inputs `x` (rates `xd`, `xdd`) from `guess`, with the
/// params `params` (in lanes) and the mechanism's (or scene's) `shape`. `fast` is the common
/// path of its tick in lanes as its scalar start runs it (a scene's computing every value of
/// its subset; `None` where it has none): every lane with finite params, inputs and guess is solved by it from its
/// guess, and each lane it clears, or that it was not given, is started by `scalar` (with
/// `started` false) from its guess. A lane that fails keeps its guess and its error, and starts
/// again on the next tick. Every lane ends with the scalar `tick_start`'s result or error.
pub fn tick_start<
    L: Lanes,
    const NI: usize,
    const NU: usize,
    const NP: usize,
    const NPAR: usize,
    M: Memo,
>(
    (params, params_id): (&[L; NPAR], usize),
    [x, xd, xdd]: [&[L; NI]; 3],
    guess: &[L; NU],
    shape: &LaneShape<NI, NU, NPAR>,
    fast: Option<impl LanePath<L, NI, NU, NP, NPAR>>,
    mut scalar: impl ScalarLane<L::Scalar, NI, NU, NP, NPAR, M>,
) -> LaneTick<L, NI, NU, NP, NPAR, M> {
    let zero = L::zero();
    let unit = (zero, L::one());
    let mut t = LaneTick {
        state: LaneState {
            x: *x,
            xd: *xd,
            xdd: *xdd,
            q: *guess,
            qd: [zero; NU],
            qdd: [zero; NU],
            points: [PointMotion {
                position: [zero; 2],
                velocity: [zero; 2],
                acceleration: [zero; 2],
            }; NP],
            pivot_ratio: L::one(),
        },
        tx: [unit; NI],
        tq: [unit; NU],
        tp: [unit; NPAR],
        params: [zero; NPAR],
        params_id: 0,
        age: L::array(|_| 0),
        iterations: L::array(|_| 0),
        residual: zero,
        status: L::array(|_| Ok(())),
        failed: 0,
        started: 0,
        scalar_report: 0,
        memo: L::array(|_| M::default()),
    };
    let all = L::all_bits();
    let mut bad = all;
    if let Some(fast) = fast {
        // The scalar solve's checks (every param, the inputs and their rates, the guess) as a
        // mask; the lanes they clear fail in the scalar start with their own error.
        let mut ok = L::mask(all);
        for v in params.iter().chain(x).chain(xd).chain(xdd).chain(guess) {
            ok = ok & v.is_finite();
        }
        let tx = fresh(x, shape.angle_x);
        let tp = fresh(params, shape.angle_p);
        let mut st = LaneTrig {
            q: *guess,
            sc: fresh(guess, shape.angle_q),
        };
        let mut report = LaneReport::new();
        let fixed = LaneFixed {
            x,
            xd,
            xdd,
            tx: &tx,
            tp: &tp,
        };
        let (qd, qdd, points) = fast(fixed, &mut st, &mut report, &mut ok);
        bad = all & !L::bits(ok);
        let good = all & !bad;
        if good != 0 {
            // As the scalar `tick_start`: the solution's sines and cosines afresh.
            let solved = LaneTrig {
                q: st.q,
                sc: fresh(&st.q, shape.angle_q),
            };
            let rates = (qd, qdd, points, report.pivot_ratio);
            store(&mut t, good, [x, xd, xdd], &solved, rates, tx);
            let m = L::mask(good);
            for k in 0..NPAR {
                t.params[k] = L::select(m, params[k], t.params[k]);
                t.tp[k] = (
                    L::select(m, tp[k].0, t.tp[k].0),
                    L::select(m, tp[k].1, t.tp[k].1),
                );
            }
            if shape.predict.iter().any(|&p| p) {
                // Newton's report, lane by lane (a closed-form solve's: none, as made).
                for i in (0..L::W).filter(|i| good >> i & 1 == 1) {
                    t.iterations.as_mut()[i] = report.iterations.lane(i).to_f64() as u32;
                }
                t.residual = L::select(m, report.residual, t.residual);
            }
            t.started = good;
        }
    }
    for i in (0..L::W).filter(|i| bad >> i & 1 == 1) {
        restart(&mut t, i, [x, xd, xdd], &mut scalar);
    }
    t.learn_params_id(params, params_id, shape.read);
    t
}
