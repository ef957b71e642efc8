//! Crossings (bifurcations) against closed-form geometry: linkages with equal links whose two
//! assembly modes meet where J is singular but the curve goes on (`tests/data/branches/
//! crossings.toml`). `branches` must report them as crossings, not dead points, keep one circuit
//! through them and the same branch labels on each side, and count every configuration there.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use mechgen::branches::{Analysis, Labelled, Setup};
use mechgen_codegen::SourceFile;

fn setup(name: &str) -> Setup {
    let path = format!(
        "{}/tests/data/branches/crossings.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(path).unwrap();
    let (compiled, diags) = mechgen_codegen::analyze(&SourceFile::new("crossings.toml", &text));
    assert!(!diags.iter().any(|d| d.is_error()), "{diags:?}");
    let c = compiled.iter().find(|c| c.model.name.text == name).unwrap();
    Setup::new(c, 0).unwrap()
}

fn gap(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    d.min(TAU - d)
}

/// Largest difference of two configurations (angles modulo a turn; `angle` per unknown).
fn off(a: &[f64], b: &[f64], angle: &[bool]) -> f64 {
    a.iter()
        .zip(b)
        .zip(angle)
        .map(|((x, y), &ang)| if ang { gap(*x, *y) } else { (x - y).abs() })
        .fold(0.0, f64::max)
}

/// The configuration at input `x` that equals `want` (within `tol`), or a panic.
fn find<'a>(a: &'a Analysis, x: f64, want: &[f64], angle: &[bool], tol: f64) -> &'a Labelled {
    let here: Vec<&Labelled> = a.at.iter().filter(|l| l.input == x).collect();
    here.iter()
        .copied()
        .find(|l| off(&l.q, want, angle) <= tol)
        .unwrap_or_else(|| panic!("at {x}: {want:?} not among {here:?}"))
}

/// Structure of a one-circuit linkage of two full-turn branches crossing at `crossings` (in the
/// order of the range −180° to 180°); each
/// mode (`modes`, geometry per input) keeps its branch label at every `at` input, on both sides of
/// every crossing; at each crossing two configurations (one per branch), equal to the geometry.
fn two_modes_crossing(
    name: &str,
    crossings: [f64; 2],
    modes: [fn(f64) -> Vec<f64>; 2],
) -> Analysis {
    let s = setup(name);
    let angle = s.angle.clone();
    let ats: Vec<f64> = (0..12)
        .map(|k| (15.0 + 30.0 * k as f64).to_radians())
        .chain(crossings)
        .collect();
    let a = s.analyze(-PI, PI, &ats).unwrap();
    assert_eq!(
        (a.circuits, a.branches.len(), a.dead_points.len()),
        (1, 2, 0),
        "{name}: {}",
        s.summary(&a)
    );
    assert!(a.branches.iter().all(|b| b.full_turn));
    assert_eq!(a.crossings.len(), 2, "{name}: {}", s.summary(&a));
    for (c, &x) in a.crossings.iter().zip(&crossings) {
        assert!(
            gap(c.input, x) <= 1e-9,
            "{name}: crossing at {} vs {x}",
            c.input
        );
        let want = modes[0](x);
        assert!(
            off(&c.q, &want, &angle) <= 1e-9,
            "{name}: {:?} vs {want:?}",
            c.q
        );
        assert_eq!(c.branches, vec![0, 1]);
    }
    // Each mode is one branch all the way round, through both crossings.
    for mode in modes {
        let labels: Vec<usize> = ats[..12]
            .iter()
            .map(|&x| find(&a, x, &mode(x), &angle, 1e-12).branch)
            .collect();
        assert!(labels.iter().all(|&l| l == labels[0]), "{name}: {labels:?}");
    }
    // At a crossing: both branches, the one configuration twice.
    for &x in &crossings {
        let here: Vec<&Labelled> = a.at.iter().filter(|l| l.input == x).collect();
        assert_eq!(here.len(), 2, "{name} at {x}: {here:?}");
        assert_ne!(here[0].branch, here[1].branch);
        for l in here {
            assert!(off(&l.q, &modes[0](x), &angle) <= 1e-9, "{name}: {l:?}");
        }
    }
    a
}

/// Isosceles slider-crank: AB = BC = l, C on the x axis. The modes are q2 = −q1 (s = 2 l cos q1)
/// and q2 = π + q1 (s = 0); they meet at q1 = ±90°.
#[test]
fn toggle_with_equal_links() {
    two_modes_crossing(
        "toggle",
        [-FRAC_PI_2, FRAC_PI_2],
        [|x| vec![-x, 2.0 * x.cos()], |x| vec![PI + x, 0.0]],
    );
}

/// Parallelogram four-bar (crank = rocker = a, coupler = ground = b): the parallelogram mode
/// (q2 = 0, q3 = q1) and the anti-parallelogram, C reflected over the diagonal BD; they meet
/// where all four links line up, q1 = 0 and 180°.
#[test]
fn parallelogram_four_bar() {
    fn anti(x: f64) -> Vec<f64> {
        let (a, b) = (0.3f64, 0.5f64);
        let (bx, by) = (a * x.cos(), a * x.sin());
        // C = B + (b, 0) reflected over the line through B and D = (b, 0).
        let (cx, cy) = (bx + b, by);
        let (ux, uy) = (b - bx, -by);
        let n = (ux * ux + uy * uy).sqrt();
        let (ux, uy) = (ux / n, uy / n);
        let t = (cx - bx) * ux + (cy - by) * uy;
        let (fx, fy) = (bx + t * ux, by + t * uy);
        let (rx, ry) = (2.0 * fx - cx, 2.0 * fy - cy);
        vec![(ry - by).atan2(rx - bx), ry.atan2(rx - b)]
    }
    two_modes_crossing("parallelogram", [PI, 0.0], [|x| vec![0.0, x], anti]);
}

/// Kite (crank = coupler = a, rocker = ground = b): one mode folds C onto the crank's pivot
/// (q2 = q1 + π, q3 = π), the other reflects that over the diagonal BD; they meet at q1 = 0, 180°.
#[test]
fn kite_four_bar() {
    fn other(x: f64) -> Vec<f64> {
        let (a, b) = (0.3f64, 0.5f64);
        let (bx, by) = (a * x.cos(), a * x.sin());
        let (ux, uy) = (b - bx, -by);
        let n = (ux * ux + uy * uy).sqrt();
        let (ux, uy) = (ux / n, uy / n);
        // The origin reflected over the line through B along u.
        let t = -bx * ux - by * uy;
        let (fx, fy) = (bx + t * ux, by + t * uy);
        let (rx, ry) = (2.0 * fx, 2.0 * fy);
        vec![(ry - by).atan2(rx - bx), ry.atan2(rx - b)]
    }
    two_modes_crossing("kite", [PI, 0.0], [|x| vec![x + PI, PI], other]);
}

/// Toggle press: crank O + r e(q1), rod m to the knee B, upper link AB (A the origin), lower link
/// BC to the slider C on y = 0, with AB = BC = l. The lower pair crosses where B = (0, l), which
/// the rod reaches at the inputs with |O + r e(q1) − (0, l)| = m, in one of the two rod modes;
/// there 4 configurations (3 distinct), 3 circuits, 4 branches.
#[test]
fn toggle_press_counts_every_configuration_at_its_crossings() {
    let s = setup("press");
    let angle = s.angle.clone();
    let (xo, yo, r, m, l) = (0.8f64, 1.2f64, 0.3f64, 1.0f64, 1.0f64);
    // (xo + r cos)² + (yo − l + r sin)² = m²: A cos q1 + B sin q1 = C.
    let (ca, cb) = (2.0 * r * xo, 2.0 * r * (yo - l));
    let cc = m * m - xo * xo - (yo - l) * (yo - l) - r * r;
    let (rr, phi) = (ca.hypot(cb), cb.atan2(ca));
    let dq = (cc / rr).acos();
    let mut want = [phi - dq, phi + dq];
    want.sort_by(f64::total_cmp);
    // The configuration at a crossing: B = (0, l), q4 = −90°, s = 0; the rod from P to B.
    let at_crossing = |x: f64| {
        let (px, py) = (xo + r * x.cos(), yo + r * x.sin());
        vec![(l - py).atan2(-px), FRAC_PI_2, -FRAC_PI_2, 0.0]
    };
    let a = s.analyze(-PI, PI, &want).unwrap();
    assert_eq!(
        (
            a.circuits,
            a.branches.len(),
            a.dead_points.len(),
            a.crossings.len()
        ),
        (3, 4, 0, 2),
        "{}",
        s.summary(&a)
    );
    for (c, &x) in a.crossings.iter().zip(&want) {
        assert!(gap(c.input, x) <= 1e-9, "crossing at {} vs {x}", c.input);
        assert!(off(&c.q, &at_crossing(x), &angle) <= 1e-9, "{:?}", c.q);
        let here: Vec<&Labelled> = a.at.iter().filter(|l| l.input == x).collect();
        assert_eq!(here.len(), 4, "at {x}: {here:?}");
        let on: Vec<&&Labelled> = here
            .iter()
            .filter(|l| off(&l.q, &at_crossing(x), &angle) <= 1e-9)
            .collect();
        assert_eq!(on.len(), 2, "at {x}: {here:?}");
        assert_ne!(on[0].branch, on[1].branch);
        assert_eq!(c.branches, {
            let mut b = vec![on[0].branch, on[1].branch];
            b.sort();
            b
        });
    }
    // Through a crossing the slider's branch keeps its label: s = 0 below and above it.
    let (below, above) = (want[1] - 0.2, want[1] + 0.2);
    let b = s.analyze(-PI, PI, &[below, above]).unwrap();
    let label = |x: f64| {
        let c = a.crossings[1].circuit;
        b.at.iter()
            .find(|l| l.input == x && l.circuit == c && l.q[3].abs() <= 1e-12)
            .unwrap_or_else(|| panic!("no s = 0 configuration at {x}: {:?}", b.at))
            .branch
    };
    assert_eq!(label(below), label(above));
}

/// Mechanisms without equal links have no crossing.
#[test]
fn no_crossings_elsewhere() {
    for name in [
        "four_bar",
        "rocker_four_bar",
        "sixbar",
        "sixbar_g",
        "slider_crank",
        "shaper",
    ] {
        let (compiled, _) =
            mechgen_codegen::analyze(&SourceFile::new("m.toml", mechgen::source::SOURCE));
        let c = compiled.iter().find(|c| c.model.name.text == name).unwrap();
        let a = Setup::new(c, 0).unwrap().analyze(-PI, PI, &[]).unwrap();
        assert!(a.crossings.is_empty(), "{name}: {:?}", a.crossings);
    }
}
