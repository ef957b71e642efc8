//! Sweeps through crossings (`crossings.toml`): a parallelogram, a kite, a deltoid and an
//! isosceles slider-crank, each over a full turn in 1° rows (the crossings among them) on its start's
//! branch, generated engine and generic engine alike: every row `ok`, positions within 1e-12 and
//! rates (velocities, accelerations, points' too) within 1e-9 of the geometry written here
//! (closed forms of each branch; their rates by Richardson-extrapolated central differences of
//! those closed forms), the crossing rows included.

use std::f64::consts::PI;

use mechgen::generic;
use mechgen::sweep::{Continuation, Row, sweep};
use mechgen::{DynMechanism, Kind};
use mechgen_odd_files::crossings::{
    deltoid::Deltoid, kite::Kite, parallelogram::Parallelogram, toggle::Toggle,
};

const TEXT: &str = include_str!("../crossings.toml");

/// The branch's unknowns and points (flattened x, y per point) at input q1, in closed form.
type Geometry = fn(f64) -> Vec<f64>;

fn parallelogram(q1: f64) -> Vec<f64> {
    let (a, b) = (1.0, 3.0);
    vec![
        0.0,
        q1,
        a * q1.cos(),
        a * q1.sin(),
        b + a * q1.cos(),
        a * q1.sin(),
    ]
}

fn kite(q1: f64) -> Vec<f64> {
    mirrored(q1, 1.0, 3.0)
}

fn deltoid(q1: f64) -> Vec<f64> {
    mirrored(q1, 3.0, 1.0)
}

/// The branch of a four-bar with crank = coupler = `a`, rocker = ground = `d` on which C is the
/// mirror image of the crank's pivot O in the line BD.
fn mirrored(q1: f64, a: f64, d: f64) -> Vec<f64> {
    let (bx, by) = (a * q1.cos(), a * q1.sin());
    // C: the mirror image of O in the line BD.
    let (ux, uy) = (d - bx, -by);
    let n = ux.hypot(uy);
    let (ux, uy) = (ux / n, uy / n);
    let t = -(bx * ux + by * uy);
    let (cx, cy) = (2.0 * (bx + t * ux), 2.0 * (by + t * uy));
    vec![(cy - by).atan2(cx - bx), cy.atan2(cx - d), bx, by, cx, cy]
}

fn toggle(q1: f64) -> Vec<f64> {
    vec![-q1, 2.0 * q1.cos(), q1.cos(), q1.sin()]
}

/// A mechanism (generated), its branch's geometry, its crossings (degrees), its name.
type Case<'a> = (&'a dyn DynMechanism<f64>, Geometry, &'a [f64], &'a str);

/// An angle's difference, modulo a turn.
fn turn(a: f64) -> f64 {
    (a + PI).rem_euclid(2.0 * PI) - PI
}

/// First and second derivatives of `g` at `x` (central differences, Richardson-extrapolated).
fn rates(g: Geometry, x: f64, angle: &[bool]) -> (Vec<f64>, Vec<f64>) {
    let at = |h: f64| {
        let (p, m, c) = (g(x + h), g(x - h), g(x));
        let fix = |v: f64, k: usize| if angle[k] { turn(v) } else { v };
        let d1: Vec<f64> = (0..c.len())
            .map(|k| fix(p[k] - m[k], k) / (2.0 * h))
            .collect();
        let d2: Vec<f64> = (0..c.len())
            .map(|k| (fix(p[k] - c[k], k) - fix(c[k] - m[k], k)) / (h * h))
            .collect();
        (d1, d2)
    };
    // Three levels of Richardson extrapolation: the errors ∝ h² and h⁴ removed.
    let (a, b, c) = (at(2e-2), at(1e-2), at(5e-3));
    let rich = |a: &[f64], b: &[f64], c: &[f64]| -> Vec<f64> {
        (0..a.len())
            .map(|k| {
                let (ab, bc) = ((4.0 * b[k] - a[k]) / 3.0, (4.0 * c[k] - b[k]) / 3.0);
                (16.0 * bc - ab) / 15.0
            })
            .collect()
    };
    (rich(&a.0, &b.0, &c.0), rich(&a.1, &b.1, &c.1))
}

/// Every row of a full-turn sweep of `k` against `geometry`, the rows on the crossings
/// (`crossings`, degrees) among them.
fn check(k: &dyn DynMechanism<f64>, geometry: Geometry, crossings: &[f64], what: &str) {
    let info = k.info();
    let angle: Vec<bool> = info
        .unknowns
        .iter()
        .map(|u| u.kind == Kind::Angle)
        .chain((0..2 * info.points.len()).map(|_| false))
        .collect();
    let values: Vec<f64> = (0..=360).map(|d| f64::from(d).to_radians()).collect();
    let c = Continuation::for_input(Kind::Angle, 2.0 * PI);
    let rows: Vec<Row> = sweep(k, 0, &values, 1.0, &c);
    let mut on_crossing = 0;
    for row in &rows {
        let deg = row.input.to_degrees();
        let s = row
            .result
            .as_ref()
            .unwrap_or_else(|e| panic!("{what} at {deg} deg: {e} ({})", row.status()));
        let want = geometry(row.input);
        let (d1, d2) = rates(geometry, row.input, &angle);
        let mut got = s.q.to_vec();
        let mut got_d1 = s.qd.to_vec();
        let mut got_d2 = s.qdd.to_vec();
        for p in &s.points {
            got.extend(p.position);
            got_d1.extend(p.velocity);
            got_d2.extend(p.acceleration);
        }
        for k in 0..want.len() {
            let e = if angle[k] {
                turn(got[k] - want[k])
            } else {
                got[k] - want[k]
            };
            assert!(
                e.abs() < 1e-12,
                "{what} at {deg} deg, value {k}: {} vs {}",
                got[k],
                want[k]
            );
            assert!(
                (got_d1[k] - d1[k]).abs() < 1e-9,
                "{what} at {deg} deg, rate {k}: {} vs {}",
                got_d1[k],
                d1[k]
            );
            assert!(
                (got_d2[k] - d2[k]).abs() < 1e-9,
                "{what} at {deg} deg, acceleration {k}: {} vs {}",
                got_d2[k],
                d2[k]
            );
        }
        if crossings
            .iter()
            .any(|c| (deg.rem_euclid(360.0) - c).abs() < 1e-9)
        {
            on_crossing += 1;
        }
    }
    assert_eq!(
        on_crossing,
        crossings.len() + usize::from(crossings.contains(&0.0)),
        "{what}"
    );
}

#[test]
fn full_turns_pass_their_crossings_on_their_branch_on_both_engines() {
    let all = generic::load("crossings.toml", TEXT).expect("loads");
    let generic = |name: &str| all.iter().find(|m| m.name() == name).expect(name).clone();
    let cases: [Case<'_>; 4] = [
        (
            &Parallelogram::<f64>::default(),
            parallelogram,
            &[0.0, 180.0],
            "parallelogram",
        ),
        (&Kite::<f64>::default(), kite, &[0.0, 180.0], "kite"),
        (
            &Deltoid::<f64>::default(),
            deltoid,
            &[0.0, 180.0],
            "deltoid",
        ),
        (&Toggle::<f64>::default(), toggle, &[90.0, 270.0], "toggle"),
    ];
    for (k, g, crossings, name) in cases {
        check(k, g, crossings, &format!("{name} (generated)"));
        check(&generic(name), g, crossings, &format!("{name} (generic)"));
    }
}
