//! Shared by `tests/generic.rs` and `tests/fixtures.rs` (which CI runs on every fixture file):
//! every compiled-in mechanism on the generated solvers and on the generic engine loaded from the
//! same file, over full sweeps: the same statuses and the same values.

use super::angle_diff;
use mechgen::sweep::{Continuation, sweep};
use mechgen::{DynMechanism, Kind, MechanismInfo, generic};

pub fn engines() -> Vec<(Box<dyn DynMechanism<f64>>, generic::Generic)> {
    let loaded = generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
        .expect("the compiled-in file loads at run time");
    assert_eq!(loaded.len(), mechgen::MECHANISMS.len());
    loaded
        .into_iter()
        .map(|g| {
            let k = mechgen::lookup::<f64>(g.name()).expect("compiled in");
            (k, g)
        })
        .collect()
}

/// Largest difference over two sweeps: angles folded, everything relative to the column's
/// largest magnitude (at least 1). Failed rows must fail alike, with the same status.
fn sweep_difference(
    info: &MechanismInfo,
    a: &[mechgen::sweep::Row],
    b: &[mechgen::sweep::Row],
) -> f64 {
    let mut worst: f64 = 0.0;
    let nu = info.unknowns.len();
    for (ra, rb) in a.iter().zip(b) {
        match (&ra.result, &rb.result) {
            (Ok(sa), Ok(sb)) => {
                for i in 0..nu {
                    let d = if info.unknowns[i].kind == Kind::Angle {
                        angle_diff(sa.q[i], sb.q[i])
                    } else {
                        sa.q[i] - sb.q[i]
                    };
                    worst = worst.max(d.abs() / sa.q[i].abs().max(1.0));
                    worst = worst.max((sa.qd[i] - sb.qd[i]).abs() / sa.qd[i].abs().max(1.0));
                    worst = worst.max((sa.qdd[i] - sb.qdd[i]).abs() / sa.qdd[i].abs().max(1.0));
                }
                for (pa, pb) in sa.points.iter().zip(&sb.points) {
                    for c in 0..2 {
                        for (u, v) in [
                            (pa.position[c], pb.position[c]),
                            (pa.velocity[c], pb.velocity[c]),
                            (pa.acceleration[c], pb.acceleration[c]),
                        ] {
                            worst = worst.max((u - v).abs() / u.abs().max(1.0));
                        }
                    }
                }
            }
            (Err(ea), Err(eb)) => assert_eq!(
                ea.status(),
                eb.status(),
                "{}: input {}: {ea} vs {eb}",
                info.name,
                ra.input
            ),
            (x, y) => panic!("{}: input {}: {x:?} vs {y:?}", info.name, ra.input),
        }
    }
    worst
}

/// Every compiled-in mechanism on both engines over a full turn around its start (a length input:
/// 20 steps of 1 %): the same status on every row, values within 1e-13 (`sweep_difference`).
/// Returns the failures.
pub fn check_engines_agree() -> Vec<String> {
    let mut fails = Vec::new();
    for (k, g) in engines() {
        let info = k.info();
        assert_eq!(info, DynMechanism::<f64>::info(&g), "same description");
        // A full turn around the start input, from 170° below it (rounded down to 10°): an angle
        // input's start is moved by whole turns to the representative nearest the first value,
        // so this keeps the start where it is and the sweep covers its whole branch (`sixbar_g`,
        // start 280.67°, dead points 244.53° and 344.13°: from 110° to 470°).
        let first = ((info.inputs[0].start.to_degrees() - 170.0) / 10.0).floor() * 10.0;
        let values: Vec<f64> = (0..=72)
            .map(|i| (first + f64::from(i) * 5.0).to_radians())
            .collect();
        let c = Continuation::for_input(info.inputs[0].kind, 1.0);
        let (values, c) = if info.inputs[0].kind == Kind::Length {
            let s = info.inputs[0].start;
            let v: Vec<f64> = (0..=20).map(|i| s * (1.0 + 0.01 * f64::from(i))).collect();
            (
                v,
                Continuation::for_input(Kind::Length, 0.2 * s.abs().max(1.0)),
            )
        } else {
            (values, c)
        };
        // Both engines step alike (the runtime's predictor, then a whole solve: the generated
        // engine's own tick rotates its cached sines and cosines instead, which near a dead point
        // moves accelerations by rounding times the conditioning), so that their arithmetic is
        // what is compared.
        let counted = super::sweep::Counting::new(k.as_ref());
        let a = sweep(&counted, 0, &values, 1.3, &c);
        let counted = super::sweep::Counting::new(&g);
        let b = sweep(&counted, 0, &values, 1.3, &c);
        let ok = a.iter().filter(|r| r.result.is_ok()).count();
        if ok <= values.len() / 4 {
            fails.push(format!("{}: only {ok} rows solved", info.name));
        }
        let d = sweep_difference(&info, &a, &b);
        eprintln!(
            "{}: {ok}/{} rows, largest difference {d:e}",
            info.name,
            values.len()
        );
        if d.is_nan() || d > 1e-13 {
            fails.push(format!(
                "{}: generic and generated differ by {d:e}",
                info.name
            ));
        }
    }
    fails
}
