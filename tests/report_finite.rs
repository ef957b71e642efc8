//! A solved row is written as `ok` only when every number in it is finite
//! (`mechgen::report::all_finite`, asked of every row the CSV and Python write): one NaN or
//! infinity anywhere (an unknown, a rate, an acceleration, any of a point's six numbers) makes
//! it `non-finite`, whatever its place.
#![cfg(feature = "runtime")]

use mechgen::PointMotion;
use mechgen::report::all_finite;
use mechgen::sweep::SolvedRef;

/// Every number of a row of three unknowns and two points set in turn to NaN, +inf and -inf.
#[test]
fn one_number_not_finite_anywhere_makes_the_row_not_finite() {
    let base = |v: f64| (vec![v; 3], vec![v + 1.0; 3], vec![v + 2.0; 3]);
    let point = PointMotion {
        position: [1.0, 2.0],
        velocity: [3.0, 4.0],
        acceleration: [5.0, 6.0],
    };
    let (q, qd, qdd) = base(0.5);
    let points = vec![point; 2];
    let row = |q: &[f64], qd: &[f64], qdd: &[f64], points: &[PointMotion<f64>]| {
        let s: SolvedRef<'_> = mechgen::sweep::Solved {
            q,
            qd,
            qdd,
            points,
            condition: 1.0,
        };
        all_finite(&s)
    };
    assert!(row(&q, &qd, &qdd, &points), "a finite row");
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for i in 0..3 {
            for which in 0..3 {
                let (mut q, mut qd, mut qdd) = base(0.5);
                [&mut q, &mut qd, &mut qdd][which][i] = bad;
                assert!(!row(&q, &qd, &qdd, &points), "{bad} at {which}/{i}");
            }
        }
        for p in 0..2 {
            for k in 0..6 {
                let mut points = points.clone();
                let m = &mut points[p];
                let slot = match k {
                    0 | 1 => &mut m.position[k],
                    2 | 3 => &mut m.velocity[k - 2],
                    _ => &mut m.acceleration[k - 4],
                };
                *slot = bad;
                assert!(
                    !row(&q, &qd, &qdd, &points),
                    "{bad} at point {p}, number {k}"
                );
            }
        }
    }
    // Huge, tiny and subnormal numbers of either sign are finite; a NaN with its sign bit set
    // is not.
    for finite in [f64::MAX, f64::MIN, f64::MIN_POSITIVE, 5e-324, -5e-324, -0.0] {
        let (mut q, qd, qdd) = base(0.5);
        q[1] = finite;
        assert!(row(&q, &qd, &qdd, &points), "{finite:e}");
    }
    let (mut q, qd, qdd) = base(0.5);
    q[2] = -f64::NAN;
    assert!(!row(&q, &qd, &qdd, &points), "-NaN");
}
