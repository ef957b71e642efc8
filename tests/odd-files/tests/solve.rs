//! Every mechanism of the odd files, compiled in this crate's build, solved along a full turn of
//! its crank (20° steps, each from the last answer) against `reference/NAME.csv` (closed forms at
//! 40 digits, `reference/make_reference.py`): positions, velocities, accelerations and points.

use std::f64::consts::TAU;

use mechgen::{DynMechanism, DynState, InputMotion, Kind, MechanismInfo, SolveOptions};
use mechgen_odd_files as odd;

const XD: f64 = 1.3;
const XDD: f64 = -0.7;
/// Relative to 1 + |reference|: every quantity here is of order one.
const TOL: f64 = 1e-12;

fn reference(name: &str) -> Vec<Vec<f64>> {
    let path = format!("{}/reference/{name}.csv", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| l.split(',').map(|c| c.parse().expect("number")).collect())
        .collect()
}

fn close(got: f64, want: f64, angle: bool) -> bool {
    let d = if angle {
        let d = (got - want).rem_euclid(TAU);
        d.min(TAU - d)
    } else {
        (got - want).abs()
    };
    got.is_finite() && d <= TOL * (1.0 + want.abs())
}

/// Solves `m` at every reference row and compares every column; returns the rows checked.
fn check(m: &dyn DynMechanism<f64>) -> usize {
    let info: MechanismInfo = m.info();
    let rows = reference(&info.name);
    let (ni, nu, np) = (info.inputs.len(), info.unknowns.len(), info.points.len());
    assert_eq!(
        rows[0].len(),
        ni + 3 * nu + 6 * np,
        "{}: reference columns",
        info.name
    );
    let start: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
    let (xd, xdd) = (vec![XD; ni], vec![XDD; ni]);
    let mut state = DynState::new(InputMotion::new(&rows[0][..ni], &xd, &xdd), &start, np);
    for (r, row) in rows.iter().enumerate() {
        state.x.copy_from_slice(&row[..ni]);
        m.solve_in_place(&mut state, &SolveOptions::default())
            .unwrap_or_else(|e| panic!("{} row {r}: {e}", info.name));
        let DynState {
            q, qd, qdd, points, ..
        } = &state;
        for (k, u) in info.unknowns.iter().enumerate() {
            let want = &row[ni + 3 * k..ni + 3 * k + 3];
            let angle = u.kind == Kind::Angle;
            for (what, got, want, angle) in [
                ("", q[k], want[0], angle),
                ("_vel", qd[k], want[1], false),
                ("_acc", qdd[k], want[2], false),
            ] {
                assert!(
                    close(got, want, angle),
                    "{} row {r}: {}{what} = {got}, reference {want}",
                    info.name,
                    u.name
                );
            }
        }
        for (j, p) in points.iter().enumerate() {
            let want = &row[ni + 3 * nu + 6 * j..ni + 3 * nu + 6 * j + 6];
            let got = [
                p.position[0],
                p.position[1],
                p.velocity[0],
                p.velocity[1],
                p.acceleration[0],
                p.acceleration[1],
            ];
            for c in 0..6 {
                assert!(
                    close(got[c], want[c], false),
                    "{} row {r}: point {} column {c} = {}, reference {}",
                    info.name,
                    info.points[j],
                    got[c],
                    want[c]
                );
            }
        }
    }
    rows.len()
}

#[test]
fn every_mechanism_of_the_main_file_solves_to_its_reference() {
    assert_eq!(odd::MECHANISMS.len(), 12);
    for name in odd::MECHANISMS {
        let m = odd::lookup::<f64>(name).expect("compiled in");
        assert_eq!(check(&*m), 19, "{name}");
    }
}

#[test]
fn every_mechanism_of_the_builder_file_solves_to_its_reference() {
    assert_eq!(odd::other::MECHANISMS, ["points", "motion", "std"]);
    for name in odd::other::MECHANISMS {
        let m = odd::other::lookup::<f64>(name).expect("compiled in");
        assert_eq!(check(&*m), 19, "{name}");
    }
}

/// The typed API under the names the names table gave: the mechanism keeps its type name, the
/// colliding item takes its alternative.
#[test]
fn typed_api_with_colliding_names() {
    use mechgen::StaticMechanism;
    let options = SolveOptions::default();

    // `tick::Tick` is the mechanism; its tick state is `tick::TickState`.
    let m = odd::tick::Tick::<f64>::default();
    let (_, start) = odd::tick::Tick::<f64>::start();
    // The typed form (named inputs) starts, the static-dispatch trait's (arrays) steps.
    let input = InputMotion::new([0.0], [XD], [XDD]).map(|a| odd::tick::Inputs::from_array(*a));
    let mut state: odd::tick::TickState<f64> =
        m.tick_start(&input, &start, &options).expect("start");
    let want = reference("tick");
    for (r, row) in want.iter().enumerate().skip(1).take(3) {
        let input = InputMotion::new([row[0]], [XD], [XDD]);
        StaticMechanism::tick(&m, &mut state, &input, &options).expect("tick");
        assert!(
            close(state.q[0], row[1], true) && close(state.qd[0], row[2], false),
            "tick row {r}"
        );
        assert!(
            close(state.q[1], row[4], false) && close(state.qdd[1], row[6], false),
            "tick row {r}"
        );
    }

    // No params, named `params`: `params::ParamValues` holds nothing but is a type all the same.
    let p = odd::params::ParamValues::<f64>::default();
    assert_eq!(p.to_array(), [0.0f64; 0]);
    let _ = odd::params::Params::<f64>::new(p);

    // Two inputs, named `inputs`: the inputs struct is `inputs::InputValues`.
    let x = odd::inputs::InputValues { x0: 0.1, q1: 0.0 };
    let m = odd::inputs::Inputs::<f64>::default();
    let (_, guess) = odd::inputs::Inputs::<f64>::start();
    let s = m
        .solve(
            &InputMotion {
                x,
                xd: x,
                xdd: odd::inputs::InputValues { x0: 0.0, q1: 0.0 },
            },
            &guess,
            &options,
        )
        .expect("solve");
    assert!(close(s.q.s, 1.25, false) && close(s.points.B.position[0], 0.35, false));

    // The mechanism `t` has type `T`; its scalar parameter is `S`.
    let m = odd::t::T::<f64>::default();
    assert_eq!(m.params.r, 0.2);

    // No points: `Points` has no field and still a type parameter.
    let pts: odd::tick::Points<f32> = Default::default();
    assert_eq!(pts, odd::tick::Points::from_array([]));

    // Named like generated structs (in the runtime-path file): `points::PointValues`, `motion::MotionState`.
    let pv: odd::other::points::PointValues<f64> = Default::default();
    assert_eq!(pv.Points.position, [0.0, 0.0]);
    let _: Option<odd::other::motion::MotionState<f64>> = None;
    assert_eq!(odd::other::std::Std::<f64>::INPUTS, 1);
}
