//! `closed.toml` in generated code: the offset slot (RPR with a perpendicular offset `h != 0`),
//! the inclined slide (RRP) and the cross slide (two lengths), the closed-form kinds no other file
//! of the repository has.
//!
//! * 200 deterministic pseudo-random parameter sets each, set through the generated `Params`, on
//!   both assembly modes: generated positions = the closed forms written here (quadratic formula,
//!   atan2) ≤ 1e-12 (lengths relative to the length scale), velocities = central differences of
//!   those closed forms, the generic engine (same file text) = generated ≤ 1e-12, no Newton
//!   iteration; the cross slide's lengths = Cramer's rule written here (positions and rates);
//! * δ = 1e-2 … 1e-10 before the dead points (the pin at distance |h| from the slot's pivot; the
//!   coupler's circle tangent to the slide), on data chosen so that the reference is exact to
//!   rounding: positions within a few ε/√δ; just past them `Unassemblable`, guess left alone.

use std::f64::consts::PI;

use mechgen::generic::{self, Generic};
use mechgen::{DynMechanism, InputMotion, SolveError, SolveOptions};
use mechgen_odd_files::closed::{cross_slide, inclined_slide, offset_slot};

const TEXT: &str = include_str!("../closed.toml");
const CASES: usize = 200;
const SAME: f64 = 1e-12;
/// Velocities against central differences of step `FD_STEP` (relative to the rates' scale).
const FD: f64 = 1e-6;
const FD_STEP: f64 = 1e-5;
/// Position errors near the dead points in units of ε/√δ (as the root crate's stress suite).
const BOUND: f64 = 16.0;

/// splitmix64: a deterministic pseudo-random sequence in [0, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
    /// A length log-uniform in [0.1, 10].
    fn length(&mut self) -> f64 {
        10f64.powf(self.range(-1.0, 1.0))
    }
}

fn engine(name: &str) -> Generic {
    generic::load("closed.toml", TEXT)
        .expect("closed.toml loads")
        .into_iter()
        .find(|g| g.name() == name)
        .expect("in closed.toml")
}

/// The angle difference wrapped to (−π, π].
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(2.0 * PI);
    if d > PI { d - 2.0 * PI } else { d }
}

#[test]
fn the_blocks_are_the_three_closed_forms() {
    assert_eq!(engine("offset_slot").block_kinds(), ["closed form (RPR)"]);
    assert_eq!(
        engine("inclined_slide").block_kinds(),
        ["closed form (RRP)"]
    );
    assert_eq!(
        engine("cross_slide").block_kinds(),
        ["closed form (linear 2x2)"]
    );
}

/// |got − want| per unknown, angles wrapped, lengths divided by `scale`.
fn error(got: &[f64], want: &[f64], angle: [bool; 2], scale: f64) -> f64 {
    (0..2)
        .map(|i| {
            if angle[i] {
                angle_diff(got[i], want[i]).abs()
            } else {
                (got[i] - want[i]).abs() / scale
            }
        })
        .fold(0.0, f64::max)
}

/// The offset slot `s e(q) + h e(q + π/2) = a e(q1) + (d, 0)`: [q, s] on the mode `plus`
/// (s > 0) or not, `None` past the dead point |P| = |h|.
fn slot_closed(a: f64, d: f64, h: f64, q1: f64, plus: bool) -> Option<[f64; 2]> {
    let (px, py) = (a * q1.cos() + d, a * q1.sin());
    let rho = px.hypot(py);
    if rho < h.abs() {
        return None;
    }
    let s = ((rho - h.abs()) * (rho + h.abs())).sqrt();
    let s = if plus { s } else { -s };
    // P = R(q) (s, h).
    Some([py.atan2(px) - h.atan2(s), s])
}

/// The inclined slide `a e(q1) + b e(q2) = s e(al) + (x0, y0)`: [q2, s] on the mode `plus` (the
/// larger s) or not, `None` past the tangency.
fn slide_closed(p: &inclined_slide::Params<f64>, q1: f64, plus: bool) -> Option<[f64; 2]> {
    let (ux, uy) = (p.al.cos(), p.al.sin());
    // b e(q2) = s u + w.
    let (wx, wy) = (p.x0 - p.a * q1.cos(), p.y0 - p.a * q1.sin());
    let cross = (ux * wy - uy * wx).abs();
    if cross > p.b {
        return None;
    }
    let root = ((p.b - cross) * (p.b + cross)).sqrt();
    let s = -(ux * wx + uy * wy) + if plus { root } else { -root };
    Some([(s * uy + wy).atan2(s * ux + wx), s])
}

/// Solves `m` (generated) and `g` (generic) from `guess` at `q1`, asserts 0 iterations and that
/// they agree to `SAME`; returns the generated (q, qd).
fn solve_both(
    m: &dyn DynMechanism<f64>,
    g: &Generic,
    q1: f64,
    guess: [f64; 2],
    angle: [bool; 2],
    scale: f64,
    what: &str,
) -> ([f64; 2], [f64; 2]) {
    let options = SolveOptions::default();
    let mut out = Vec::new();
    for engine in [m, g as &dyn DynMechanism<f64>] {
        let s = engine
            .solve(InputMotion::new(&[q1], &[1.0], &[0.0]), &guess, &options)
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!(
            s.report.iterations, 0,
            "{what}: a closed form takes no iteration"
        );
        let (q, qd) = (&s.q, &s.qd);
        out.push(([q[0], q[1]], [qd[0], qd[1]]));
    }
    let e = error(&out[0].0, &out[1].0, angle, scale);
    assert!(
        e <= SAME,
        "{what}: generated {:?} vs generic {:?}",
        out[0].0,
        out[1].0
    );
    let rates = out[0].1[0].abs().max(out[0].1[1].abs() / scale).max(1.0);
    let e = (0..2)
        .map(|i| (out[0].1[i] - out[1].1[i]).abs() / if angle[i] { 1.0 } else { scale })
        .fold(0.0, f64::max);
    assert!(
        e <= SAME * rates,
        "{what}: rates {:?} vs {:?}",
        out[0].1,
        out[1].1
    );
    out[0]
}

fn check_rates(qd: [f64; 2], fd: [f64; 2], angle: [bool; 2], scale: f64, what: &str) {
    let rates = fd[0].abs().max(fd[1].abs() / scale).max(1.0);
    for i in 0..2 {
        let unit = if angle[i] { 1.0 } else { scale };
        assert!(
            (qd[i] - fd[i]).abs() / unit <= FD * rates,
            "{what}: rate {i} {} vs central difference {}",
            qd[i],
            fd[i]
        );
    }
}

#[test]
fn offset_slot_is_the_closed_form_on_both_modes() {
    let mut rng = Rng(11);
    let mut g = engine("offset_slot");
    let angle = [true, false];
    let mut worst: f64 = 0.0;
    let mut done = 0;
    while done < CASES {
        let (a, d, q1) = (rng.length(), rng.length(), rng.range(-PI, PI));
        let rho = (a * q1.cos() + d).hypot(a * q1.sin());
        let scale = a.max(d);
        // Keep the pin away from the pivot (the angle's conditioning) and from the dead point.
        if rho < 1e-2 * scale {
            continue;
        }
        let h = rho * rng.range(-0.9, 0.9);
        let p = offset_slot::Params { a, d, h };
        for (name, value) in [("a", a), ("d", d), ("h", h)] {
            g.set_param(name, value).expect("a param");
        }
        let m = offset_slot::OffsetSlot { params: p };
        for plus in [true, false] {
            let want = slot_closed(a, d, h, q1, plus).expect("reachable");
            let guess = [
                want[0] + 1e-3 * rng.range(-1.0, 1.0),
                want[1] * (1.0 + 1e-3),
            ];
            let what = format!("a = {a}, d = {d}, h = {h}, q1 = {q1}, plus = {plus}");
            let (q, qd) = solve_both(&m, &g, q1, guess, angle, scale, &what);
            let e = error(&q, &want, angle, scale);
            assert!(e <= SAME, "{what}: {q:?} vs closed form {want:?}");
            worst = worst.max(e);
            let (hi, lo) = (
                slot_closed(a, d, h, q1 + FD_STEP, plus).expect("reachable"),
                slot_closed(a, d, h, q1 - FD_STEP, plus).expect("reachable"),
            );
            let fd = [
                angle_diff(hi[0], lo[0]) / (2.0 * FD_STEP),
                (hi[1] - lo[1]) / (2.0 * FD_STEP),
            ];
            check_rates(qd, fd, angle, scale, &what);
        }
        done += 1;
    }
    eprintln!(
        "offset slot: worst error against the closed form {worst:.2e} over {CASES} cases × 2 modes"
    );
}

#[test]
fn inclined_slide_is_the_closed_form_on_both_modes() {
    let mut rng = Rng(12);
    let mut g = engine("inclined_slide");
    let angle = [true, false];
    let mut worst: f64 = 0.0;
    for _ in 0..CASES {
        let (a, x0, y0) = (
            rng.length(),
            rng.length() * rng.range(-1.0, 1.0),
            rng.length() * rng.range(-1.0, 1.0),
        );
        let (al, q1) = (rng.range(-PI, PI), rng.range(-PI, PI));
        let (wx, wy) = (x0 - a * q1.cos(), y0 - a * q1.sin());
        let cross = (al.cos() * wy - al.sin() * wx).abs();
        // The coupler reaches the slide with a margin: the distance of the line from the crank
        // pin is at most 0.9 b.
        let b = (cross / rng.range(0.05, 0.9)).max(0.1 * a);
        let p = inclined_slide::Params { a, b, al, x0, y0 };
        for (name, value) in [("a", a), ("b", b), ("al", al), ("x0", x0), ("y0", y0)] {
            g.set_param(name, value).expect("a param");
        }
        let scale = a.max(b).max(x0.abs()).max(y0.abs());
        let m = inclined_slide::InclinedSlide { params: p };
        for plus in [true, false] {
            let want = slide_closed(&p, q1, plus).expect("reachable");
            let guess = [
                want[0] + 1e-3 * rng.range(-1.0, 1.0),
                want[1] + 1e-3 * b * rng.range(-1.0, 1.0),
            ];
            let what = format!("{p:?}, q1 = {q1}, plus = {plus}");
            let (q, qd) = solve_both(&m, &g, q1, guess, angle, scale, &what);
            let e = error(&q, &want, angle, scale);
            assert!(e <= SAME, "{what}: {q:?} vs closed form {want:?}");
            worst = worst.max(e);
            let (hi, lo) = (
                slide_closed(&p, q1 + FD_STEP, plus).expect("reachable"),
                slide_closed(&p, q1 - FD_STEP, plus).expect("reachable"),
            );
            let fd = [
                angle_diff(hi[0], lo[0]) / (2.0 * FD_STEP),
                (hi[1] - lo[1]) / (2.0 * FD_STEP),
            ];
            check_rates(qd, fd, angle, scale, &what);
        }
    }
    eprintln!(
        "inclined slide: worst error against the closed form {worst:.2e} over {CASES} cases × 2 modes"
    );
}

/// The cross slide `s1 e(a1) + s2 e(a2) = r e(q1) + (x0, y0)` by Cramer's rule, and its rates
/// (the right side's derivative `r e(q1 + π/2)` by the same rule).
fn cross_closed(p: &cross_slide::Params<f64>, q1: f64) -> ([f64; 2], [f64; 2]) {
    let (c1, s1, c2, s2) = (p.a1.cos(), p.a1.sin(), p.a2.cos(), p.a2.sin());
    let det = c1 * s2 - c2 * s1;
    let cramer = |x: f64, y: f64| [(x * s2 - y * c2) / det, (c1 * y - s1 * x) / det];
    let (c, s) = (q1.cos(), q1.sin());
    (
        cramer(p.r * c + p.x0, p.r * s + p.y0),
        cramer(-p.r * s, p.r * c),
    )
}

#[test]
fn cross_slide_is_cramers_rule() {
    let mut rng = Rng(13);
    let mut g = engine("cross_slide");
    let angle = [false, false];
    let mut worst: f64 = 0.0;
    for _ in 0..CASES {
        let r = rng.length();
        let (x0, y0) = (
            rng.length() * rng.range(-1.0, 1.0),
            rng.length() * rng.range(-1.0, 1.0),
        );
        // The slides at least 0.1 rad from parallel (the elimination's condition).
        let a1 = rng.range(-PI, PI);
        let a2 = a1 + rng.range(0.1, PI - 0.1) * if rng.next() < 0.5 { 1.0 } else { -1.0 };
        let q1 = rng.range(-PI, PI);
        let p = cross_slide::Params { r, a1, a2, x0, y0 };
        for (name, value) in [("r", r), ("a1", a1), ("a2", a2), ("x0", x0), ("y0", y0)] {
            g.set_param(name, value).expect("a param");
        }
        let scale = r.max(x0.abs()).max(y0.abs());
        let m = cross_slide::CrossSlide { params: p };
        let (want, rates) = cross_closed(&p, q1);
        // Any guess: the lengths are linear.
        let guess = [want[0] + scale, want[1] - scale];
        let what = format!("{p:?}, q1 = {q1}");
        let (q, qd) = solve_both(&m, &g, q1, guess, angle, scale, &what);
        let e = error(&q, &want, angle, scale).max(error(&qd, &rates, angle, scale));
        assert!(
            e <= SAME,
            "{what}: {q:?} {qd:?} vs Cramer {want:?} {rates:?}"
        );
        worst = worst.max(e);
    }
    eprintln!("cross slide: worst error against Cramer's rule {worst:.2e} over {CASES} cases");
}

/// δ = 1e-2 … 1e-10.
fn deltas() -> impl Iterator<Item = f64> {
    (2..=10).map(|k| 10f64.powi(-k))
}

/// Before the dead point at relative distance δ, both modes from a guess on each side, both
/// engines: positions within `BOUND` ε/√δ of `want` (angles in radians, lengths over `scale`, 1
/// here); past it (`past`) `Unassemblable` with the guess left alone.
fn near_dead_point(
    m: &dyn DynMechanism<f64>,
    g: &Generic,
    delta: f64,
    want: [[f64; 2]; 2],
    past: &dyn DynMechanism<f64>,
    g_past: &Generic,
    what: &str,
) -> f64 {
    let angle = [true, false];
    let options = SolveOptions::default();
    let bound = BOUND * f64::EPSILON / delta.sqrt();
    let mut worst: f64 = 0.0;
    for want in want {
        let guess = [want[0] + 1e-6, want[1] + 1e-3 * want[1].abs()];
        for engine in [m, g as &dyn DynMechanism<f64>] {
            let mut q = guess.to_vec();
            let report = engine
                .solve_position(&[0.0], &mut q, &options)
                .unwrap_or_else(|e| panic!("{what}, δ = {delta:e}: {e}"));
            assert_eq!(report.iterations, 0, "{what}: no iteration");
            let e = error(&q, &want, angle, 1.0);
            assert!(
                e <= bound,
                "{what}, δ = {delta:e}: {q:?} vs {want:?}: {:.1} ε/√δ",
                e / (f64::EPSILON / delta.sqrt())
            );
            worst = worst.max(e / (f64::EPSILON / delta.sqrt()));
        }
    }
    for engine in [past, g_past as &dyn DynMechanism<f64>] {
        let guess = want[0];
        let mut q = guess.to_vec();
        let r = engine.solve_position(&[0.0], &mut q, &options);
        assert!(
            matches!(r, Err(SolveError::Unassemblable { .. })),
            "{what}, δ = {delta:e} past the dead point: {r:?}"
        );
        assert_eq!(q, guess, "{what}: the guess is left alone");
    }
    worst
}

/// The offset slot with the pin at (1, 0) (`a = 1`, `d = 0`, `q1 = 0`: exact data) and
/// `h = 1 − δ`: `s = ±√((1 − h)(1 + h))` (1 − h exact), `q = −atan2(h, s)`. Past: `h = 1 + δ`.
#[test]
fn offset_slot_near_its_dead_point() {
    let mut worst: f64 = 0.0;
    for delta in deltas() {
        let h = 1.0 - delta;
        let s = ((1.0 - h) * (1.0 + h)).sqrt();
        let want = [[-h.atan2(s), s], [-h.atan2(-s), -s]];
        let slot = |h: f64| {
            let mut g = engine("offset_slot");
            for (name, value) in [("a", 1.0), ("d", 0.0), ("h", h)] {
                g.set_param(name, value).expect("a param");
            }
            (
                offset_slot::OffsetSlot {
                    params: offset_slot::Params { a: 1.0, d: 0.0, h },
                },
                g,
            )
        };
        let (m, g) = slot(h);
        let (m_past, g_past) = slot(1.0 + delta);
        worst = worst.max(near_dead_point(
            &m,
            &g,
            delta,
            want,
            &m_past,
            &g_past,
            "offset slot",
        ));
    }
    eprintln!("offset slot near its dead point: worst {worst:.2} ε/√δ");
}

/// The inclined slide with the crank pin at (x0, 0) (`a = x0`, `q1 = 0`), `y0 = 1`, so that the
/// pin's distance from the slide is `cos al` exactly (w = (0, 1)), and `b = cos al (1 + δ)`:
/// `s = −sin al ± √((b − cos al)(b + cos al))`, `q2 = atan2(s sin al + 1, s cos al)`. Past:
/// `b = cos al (1 − δ)`.
#[test]
fn inclined_slide_near_its_dead_point() {
    let al: f64 = 0.5;
    let (ux, uy) = (al.cos(), al.sin());
    let mut worst: f64 = 0.0;
    for delta in deltas() {
        let b = ux * (1.0 + delta);
        let root = ((b - ux) * (b + ux)).sqrt();
        let want = [1.0, -1.0].map(|sign| {
            let s = -uy + sign * root;
            [(s * uy + 1.0).atan2(s * ux), s]
        });
        let slide = |b: f64| {
            let p = inclined_slide::Params {
                a: 0.5,
                b,
                al,
                x0: 0.5,
                y0: 1.0,
            };
            let mut g = engine("inclined_slide");
            for (name, value) in [("a", p.a), ("b", b), ("al", al), ("x0", p.x0), ("y0", p.y0)] {
                g.set_param(name, value).expect("a param");
            }
            (inclined_slide::InclinedSlide { params: p }, g)
        };
        let (m, g) = slide(b);
        let (m_past, g_past) = slide(ux * (1.0 - delta));
        worst = worst.max(near_dead_point(
            &m,
            &g,
            delta,
            want,
            &m_past,
            &g_past,
            "inclined slide",
        ));
    }
    eprintln!("inclined slide near its dead point: worst {worst:.2} ε/√δ");
}
