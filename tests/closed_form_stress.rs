//! The generic engine's closed forms near the dead points of each new kind, end to end (file →
//! classification → tapes → kernel): a slider-crank whose rod turns perpendicular to the slide
//! (one angle, then one length), an offset slot tangent to the crank pin's circle (RPR), and a
//! slide tangent to the rod's circle (RRP). Approaching along the branch from 1e-2 to 1e-10 rad
//! of input, positions stay within a few ε/√δ and rates within a few ε/δ of independent closed
//! forms (δ: the relative distance of the equations from their dead point); just past the dead
//! point the solve is `Unassemblable`, with no Newton iteration anywhere.
#![cfg(feature = "runtime")]

use mechgen::generic::{self, Generic};
use mechgen::{DynMechanism, SolveError, SolveOptions};

/// Errors in units of ε/√δ (positions) and ε/δ (rates) at most this.
const BOUND: f64 = 16.0;

/// Unknowns in file order, their rates per unit input rate (where given), and δ.
type Closed = (Vec<f64>, Option<Vec<f64>>, f64);

struct Case {
    name: &'static str,
    text: &'static str,
    /// The dead point's input, and the side the branch lies on (−1: below it).
    dead: f64,
    side: f64,
    /// Independent closed form at x: unknowns in file order, their rates per unit input rate
    /// (where given), and δ.
    closed: fn(f64) -> Closed,
}

fn slider_crank(x: f64) -> Closed {
    let (r, l, off) = (0.3, 0.2, 0.05);
    // The y equation: l sin q2 = off − r sin x; the rod points right (cos q2 > 0).
    let sin2 = (off - r * x.sin()) / l;
    let q2 = sin2.asin();
    let s = r * x.cos() + l * q2.cos();
    let q2d = -r * x.cos() / (l * q2.cos());
    let sd = -r * x.sin() - l * q2.sin() * q2d;
    (vec![q2, s], Some(vec![q2d, sd]), 1.0 - sin2.abs())
}

fn slot(x: f64) -> Closed {
    let (r, h, dx) = (0.8, 0.5, 1.0);
    // B = (dx, 0) + r e(x) = |(s, h)| e(q2 + atan2(h, s)), s > 0.
    let (bx, by) = (dx + r * x.cos(), r * x.sin());
    let rho = bx.hypot(by);
    let s = (rho * rho - h * h).sqrt();
    (vec![s, by.atan2(bx) - h.atan2(s)], None, 1.0 - h / rho)
}

fn inclined(x: f64) -> Closed {
    let (r, l, al, dy) = (0.5, 0.3, 0.3f64, 0.6);
    // C = (0, dy) + s e(al), |C − r e(x)| = l: s² + 2 (w·u) s + |w|² − l² = 0, larger root.
    let (ux, uy) = (al.cos(), al.sin());
    let (wx, wy) = (-r * x.cos(), dy - r * x.sin());
    let b = wx * ux + wy * uy;
    let disc = b * b - (wx * wx + wy * wy) + l * l;
    let s = -b + disc.max(0.0).sqrt();
    (
        vec![(wy + s * uy).atan2(wx + s * ux), s],
        None,
        disc / (2.0 * l * l),
    )
}

fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "slider-crank (one angle, one length)",
            text: "[mechanism.m]\ninputs = [\"q1\"]\nunknowns = [\"q2\", \"s\"]\n\
                   loops = [\"r*e(q1) + l*e(q2) - s - c(0, off)\"]\n\
                   params = { r = 0.3, l = 0.2, off = 0.05 }\n\
                   start = { q1 = 0.0, q2 = 0.25268025514207865, s = 0.49370039370059057 }\n",
            // r sin x = off + l
            dead: (0.25f64 / 0.3).asin(),
            side: -1.0,
            closed: slider_crank,
        },
        Case {
            name: "offset slot (RPR)",
            text: "[mechanism.m]\ninputs = [\"q1\"]\nunknowns = [\"s\", \"q2\"]\n\
                   loops = [\"s*e(q2) + h*e(q2 + pi/2) - r*e(q1) - c(dx, 0)\"]\n\
                   params = { r = 0.8, h = 0.5, dx = 1.0 }\n\
                   start = { q1 = 0.0, s = 1.7291616465790582, q2 = -0.2817718841003002 }\n",
            // |B| = h: dx² + r² + 2 dx r cos x = h²
            dead: ((0.25f64 - 1.0 - 0.64) / 1.6).acos(),
            side: -1.0,
            closed: slot,
        },
        Case {
            name: "inclined slider-crank (RRP)",
            text: "[mechanism.m]\ninputs = [\"q1\"]\nunknowns = [\"q2\", \"s\"]\n\
                   loops = [\"r*e(q1) + l*e(q2) - s*e(al) - c(0, dy)\"]\n\
                   params = { r = 0.5, l = 0.3, al = 0.3, dy = 0.6 }\n\
                   start = { q1 = 1.5, q2 = 0.0, s = 0.0 }\n",
            // The distance of B from the slide is l: r sin(x − al) = dy cos al − l.
            dead: 0.3 + ((0.6 * 0.3f64.cos() - 0.3) / 0.5).asin(),
            side: 1.0,
            closed: inclined,
        },
    ]
}

fn load(c: &Case) -> Generic {
    generic::load("m.toml", c.text)
        .unwrap_or_else(|e| panic!("{}: {e}", c.name))
        .remove(0)
}

#[test]
fn approaching_and_passing_dead_points() {
    for c in cases() {
        let g = load(&c);
        let options = SolveOptions::default();
        // Along the branch from 0.3 rad inside, each solve from the previous answer.
        let x0 = c.dead + c.side * 0.3;
        let mut q = (c.closed)(x0).0;
        let (mut worst_q, mut worst_qd): (f64, Option<f64>) = (0.0, None);
        for k in 2..=10 {
            let x = c.dead + c.side * 10f64.powi(-k);
            let report = g
                .solve_position(&[x], &mut q, &options)
                .unwrap_or_else(|e| panic!("{} at 1e-{k}: {e}", c.name));
            assert_eq!(report.iterations, 0, "{}: closed forms", c.name);
            let (want, rates, delta) = (c.closed)(x);
            let unit = f64::EPSILON / delta.sqrt();
            for i in 0..2 {
                let err = (q[i] - want[i]).abs() / unit;
                assert!(
                    err <= BOUND,
                    "{} 1e-{k} rad: unknown {i}: {err:.1} ε/√δ",
                    c.name
                );
                worst_q = worst_q.max(err);
            }
            if let Some(rates) = rates {
                let mut qd = vec![0.0; 2];
                g.solve_velocity(&[x], &q, &[1.0], &mut qd)
                    .expect("regular inside");
                for i in 0..2 {
                    let err =
                        (qd[i] - rates[i]).abs() / (rates[i].abs().max(1.0) * f64::EPSILON / delta);
                    assert!(
                        err <= BOUND,
                        "{} 1e-{k} rad: rate {i}: {err:.1} ε/δ",
                        c.name
                    );
                    worst_qd = Some(worst_qd.unwrap_or(0.0).max(err));
                }
            }
        }
        let rates = worst_qd.map_or("-".to_string(), |w| format!("{w:.2} ε/δ"));
        eprintln!("{:<36} positions {worst_q:.2} ε/√δ, rates {rates}", c.name);
        // Just past: no configuration, told at once.
        for past in [1e-6, 1e-3] {
            let mut trial = q.clone();
            let r = g.solve_position(&[c.dead - c.side * past], &mut trial, &options);
            assert!(
                matches!(r, Err(SolveError::Unassemblable { iterations: 0, .. })),
                "{} {past} past: {r:?}",
                c.name
            );
            assert_eq!(trial, q, "the guess is left alone");
        }
    }
}
