//! Param sets swept in SIMD lanes (`mechgen::batch::lanes::sweep_group`, what `batch` runs on a
//! compiled-in mechanism) give every set's rows bit for bit as the scalar sweep gives them: every
//! compiled-in mechanism, sets within ±6 % of the file's params (enough that some sets' branches
//! end at a dead point inside the range, or cannot start), ranges from the start row up, around
//! it (rows below it first), up to it (every row below it), in steps the tick takes in one
//! substep and in several. The rows come as solved, each with its index: each row once. The sets
//! that leave the lanes are swept by the scalar sweep, as the batch does. Groups of eight sets
//! (eight lanes), of this CPU's `lane_width` and of three (four lanes, one a copy).
#![cfg(feature = "sweep")]

use mechgen::Kind;
use mechgen::batch::lanes::{Group, LANES, lane_width, sweep_group};
use mechgen::sweep::{Continuation, Row, sweep_each};

/// A deterministic generator of numbers in [-1, 1) (xorshift).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// The scalar sweep's rows of one set.
fn scalar(name: &str, params: &[f64], values: &[f64], c: &Continuation) -> Vec<Row> {
    let k = mechgen::lookup_with_params::<f64>(name, params).expect("compiled in");
    let mut rows = Vec::new();
    sweep_each(k.as_ref(), 0, values, 1.0, &[], c, &mut |r| {
        rows.push(r.to_row())
    });
    rows
}

/// Bit equality of two rows (NaN-free: every number compared by its bits).
fn same(a: &Row, b: &Row) -> bool {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    a.input.to_bits() == b.input.to_bits()
        && a.stopped == b.stopped
        && match (&a.result, &b.result) {
            (Ok(s), Ok(t)) => {
                bits(&s.q) == bits(&t.q)
                    && bits(&s.qd) == bits(&t.qd)
                    && bits(&s.qdd) == bits(&t.qdd)
                    && s.condition.to_bits() == t.condition.to_bits()
                    && s.points == t.points
            }
            (Err(e), Err(f)) => e == f,
            _ => false,
        }
}

/// Sets of `name` swept in lanes and by the scalar sweep: (sets whose every row is `ok`, of
/// those the ones that stayed in the lanes).
fn check(
    name: &str,
    (from, to, step): (f64, f64, f64),
    sets: usize,
    spread: f64,
    seed: u64,
) -> (usize, usize) {
    let info = mechgen::lookup::<f64>(name).expect("compiled in").info();
    assert_eq!(info.inputs[0].kind, Kind::Angle);
    let n = ((to - from) / step).round() as usize;
    let values: Vec<f64> = (0..=n)
        .map(|i| (from + step * i as f64).to_radians())
        .collect();
    let c = Continuation::for_input(Kind::Angle, values[n] - values[0]);
    let mut rng = Rng(seed);
    let params: Vec<Vec<f64>> = (0..sets)
        .map(|_| {
            info.params
                .iter()
                .map(|p| p.value * (1.0 + spread * rng.next()))
                .collect()
        })
        .collect();
    let wants: Vec<Vec<Row>> = params
        .iter()
        .map(|p| scalar(name, p, &values, &c))
        .collect();
    let (mut whole, mut in_lanes) = (0, 0);
    // Groups of eight (eight lanes), of this CPU's width (what a batch hands over: four lanes
    // without AVX-512) and of three (four lanes, one of them a copy).
    for size in [LANES, lane_width(), 3] {
        let (w, l) = check_groups(name, &params, &wants, size, (&values, &c));
        whole += w;
        in_lanes += l;
    }
    (whole, in_lanes)
}

/// The sets `params` swept in lane groups of `size`, against their scalar rows `wants`.
fn check_groups(
    name: &str,
    params: &[Vec<f64>],
    wants: &[Vec<Row>],
    size: usize,
    (values, c): (&[f64], &Continuation),
) -> (usize, usize) {
    let (mut whole, mut in_lanes) = (0, 0);
    for (g, chunk) in params.chunks(size).enumerate() {
        let mut got: Vec<Vec<Option<Row>>> = vec![vec![None; values.len()]; chunk.len()];
        let group = Group {
            params: chunk,
            index: 0,
            values,
            rate: 1.0,
            held: &[],
            continuation: c,
        };
        let left = sweep_group(name, &group, &mut |i, at, r| {
            let slot = &mut got[i][at];
            assert!(
                slot.is_none(),
                "{name}: row {at} of set {i} handed out twice"
            );
            *slot = Some(r.to_row());
        })
        .expect("a compiled-in mechanism");
        for i in 0..chunk.len() {
            let want = &wants[g * size + i];
            let ok = want.iter().all(|r| r.result.is_ok());
            whole += usize::from(ok);
            if left >> i & 1 == 1 {
                continue;
            }
            in_lanes += usize::from(ok);
            assert_eq!(got[i].len(), want.len(), "{name} set {}", g * size + i);
            for (a, b) in got[i].iter().zip(want) {
                let a = a.as_ref().expect("every row handed out");
                assert!(
                    same(a, b),
                    "{name} set {}: lane row\n{a:?}\nscalar row\n{b:?}",
                    g * size + i
                );
            }
        }
    }
    (whole, in_lanes)
}

/// The sets of every other compiled-in mechanism (`part` 0 or 1): how many had every row ok, and
/// how many of those were swept in lanes.
fn check_mechanisms(part: usize) -> (usize, usize) {
    let (mut whole, mut in_lanes) = (0, 0);
    for (s, name) in mechgen::MECHANISMS.iter().enumerate() {
        if s % 2 != part {
            continue;
        }
        let seed = 0x9e37_79b9_7f4a_7c15 ^ s as u64;
        // The start's branch: a full turn, or between the dead points of the rocking inputs.
        let (from, to): (f64, f64) = match *name {
            "rocker_four_bar" => (-120.0, 120.0),
            "sixbar_g" => (250.0, 340.0),
            _ => (0.0, 360.0),
        };
        let mid = (from + to) / 2.0;
        let start = mechgen::lookup::<f64>(name)
            .expect("compiled in")
            .info()
            .inputs[0]
            .start
            .to_degrees();
        for (range, sets, spread) in [
            // From the start row up, one substep a row (the largest substep is 2°).
            ((from, to, 1.0), 24, 0.06),
            // Several substeps a row.
            ((from, to - 4.0, 7.0), 17, 0.06),
            // Rows below the start row first.
            ((from - mid / 4.0, to - mid / 4.0, 3.0), 9, 0.03),
            // Every row below the start row.
            ((from.max(start - 359.0), start, 2.0), 9, 0.03),
        ] {
            let (w, l) = check(name, range, sets, spread, seed + sets as u64);
            whole += w;
            in_lanes += l;
        }
    }
    (whole, in_lanes)
}

#[test]
fn every_set_swept_in_lanes_is_its_scalar_sweep() {
    // Every other mechanism on a second thread (a debug build takes seconds a mechanism).
    let ((w1, l1), (w0, l0)) = std::thread::scope(|s| {
        let odd = s.spawn(|| check_mechanisms(1));
        let even = check_mechanisms(0);
        (
            odd.join().unwrap_or_else(|e| std::panic::resume_unwind(e)),
            even,
        )
    });
    let (whole, in_lanes) = (w0 + w1, l0 + l1);
    // The sets whose rows all solve stay in the lanes (else this would test the scalar sweep
    // against itself); the others leave for the scalar sweep and its statuses.
    assert!(whole > 600, "{whole} sets with every row ok");
    assert!(
        in_lanes as f64 >= 0.9 * whole as f64,
        "{in_lanes} of {whole} sets with every row ok swept in lanes"
    );
}
