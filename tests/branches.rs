//! Branch identification (`mechgen::branches`) against the independent mpmath oracle in
//! `tests/data/branches/` (half-angle polynomials, Sylvester's resultant, traced circuits):
//! the number of configurations at every reference input (also 1e-6° from each dead point),
//! every configuration to 1e-10, every dead point's input to 1e-10 rad, and the circuit and
//! branch structure up to a relabelling; plus analytic dead points and files not compiled in.

use std::collections::HashMap;
use std::f64::consts::{PI, TAU};

use mechgen::branches::{Analysis, Setup};
use mechgen_codegen::SourceFile;

fn setup_from(text: &str, name: &str) -> Setup {
    let (compiled, diags) = mechgen_codegen::analyze(&SourceFile::new("m.toml", text));
    assert!(!diags.iter().any(|d| d.is_error()), "{diags:?}");
    let c = compiled.iter().find(|c| c.model.name.text == name).unwrap();
    Setup::new(c, 0).unwrap()
}

fn csv(name: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let path = format!("{}/tests/data/branches/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.is_empty());
    let head = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (head, rows)
}

fn gap(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    d.min(TAU - d)
}

/// A relabelling that must stay one-to-one.
#[derive(Default)]
struct Bijection(HashMap<usize, usize>, HashMap<usize, usize>);

impl Bijection {
    fn add(&mut self, theirs: usize, mine: usize, what: &str) {
        assert_eq!(
            *self.0.entry(theirs).or_insert(mine),
            mine,
            "{what} {theirs}"
        );
        assert_eq!(
            *self.1.entry(mine).or_insert(theirs),
            theirs,
            "{what} {theirs}"
        );
    }
}

/// Everything the oracle says about `name`, checked.
fn against_oracle(name: &str) -> Analysis {
    let s = setup_from(mechgen::source::SOURCE, name);
    let n = s.unknown_names.len();
    let angle = s.angle.clone();
    let close = |a: &[f64], b: &[f64]| {
        a.iter().zip(b).zip(&angle).all(|((x, y), &ang)| {
            if ang {
                gap(*x, *y) <= 1e-10
            } else {
                (x - y).abs() <= 1e-10
            }
        })
    };
    let (_, at_rows) = csv(&format!("{name}-at.csv"));
    let mut inputs: Vec<f64> = at_rows.iter().map(|r| r[0].parse().unwrap()).collect();
    inputs.dedup();
    let a = s.analyze(-PI, PI, &inputs).unwrap();
    let (mut circuits, mut branches) = (Bijection::default(), Bijection::default());
    let mut checked = 0;
    for &x in &inputs {
        let theirs: Vec<&Vec<String>> = at_rows
            .iter()
            .filter(|r| r[0].parse::<f64>().unwrap() == x)
            .collect();
        let count: usize = theirs[0][n + 3].parse().unwrap();
        let mine: Vec<_> = a.at.iter().filter(|c| c.input == x).collect();
        assert_eq!(mine.len(), count, "{name} at {x}: configurations");
        assert_eq!(s.configurations(x).unwrap().len(), count);
        for r in theirs.iter().filter(|_| count > 0) {
            let q: Vec<f64> = r[1..=n].iter().map(|v| v.parse().unwrap()).collect();
            let m = mine
                .iter()
                .find(|c| close(&c.q, &q))
                .unwrap_or_else(|| panic!("{name} at {x}: {q:?} not found in {mine:?}"));
            circuits.add(r[n + 1].parse().unwrap(), m.circuit, "circuit");
            branches.add(r[n + 2].parse().unwrap(), m.branch, "branch");
            checked += 1;
        }
    }
    assert!(checked > 0 || name == "never");
    // Dead points: inputs and configurations to 1e-12 (rad or file units), circuits.
    let (_, dead) = csv(&format!("{name}-dead-points.csv"));
    assert_eq!(a.dead_points.len(), dead.len(), "{name}: dead points");
    for r in &dead {
        let x: f64 = r[0].parse().unwrap();
        let q: Vec<f64> = r[1..=n].iter().map(|v| v.parse().unwrap()).collect();
        let d = a
            .dead_points
            .iter()
            .find(|d| gap(d.input, x) <= 1e-12)
            .unwrap_or_else(|| panic!("{name}: dead point {x} not found"));
        let err =
            d.q.iter()
                .zip(&q)
                .zip(&angle)
                .map(|((a, b), &ang)| if ang { gap(*a, *b) } else { (a - b).abs() })
                .fold(0.0, f64::max);
        eprintln!("{name}: dead point {x}: configuration off by {err:.2e}");
        assert!(
            err <= 1e-12,
            "{name}: dead point {x}: configuration off by {err}"
        );
        circuits.add(r[n + 1].parse().unwrap(), d.circuit, "dead point circuit");
    }
    // Branches: the same ranges under the relabelling found above.
    let (_, br) = csv(&format!("{name}-branches.csv"));
    assert_eq!(a.branches.len(), br.len(), "{name}: branches");
    let mut circuits_seen = std::collections::HashSet::new();
    for r in &br {
        let theirs: usize = r[0].parse().unwrap();
        let mine = &a.branches[branches.0[&theirs]];
        circuits.add(r[1].parse().unwrap(), mine.circuit, "branch circuit");
        circuits_seen.insert(mine.circuit);
        assert_eq!(mine.full_turn, r[4] == "true", "{name}: branch {theirs}");
        if !mine.full_turn {
            let (from, to): (f64, f64) = (r[2].parse().unwrap(), r[3].parse().unwrap());
            assert!(
                gap(mine.from, from) <= 1e-10,
                "{name}: branch {theirs} from"
            );
            assert!(gap(mine.to, to) <= 1e-10, "{name}: branch {theirs} to");
            assert!(
                (mine.to - mine.from - (to - from)).abs() <= 1e-9,
                "{name}: arc"
            );
        }
    }
    assert_eq!(a.circuits, circuits_seen.len());
    a
}

#[test]
fn grashof_crank_rocker_two_circuits_no_dead_point() {
    let a = against_oracle("four_bar");
    assert_eq!(
        (a.circuits, a.dead_points.len(), a.branches.len()),
        (2, 0, 2)
    );
}

#[test]
fn non_grashof_four_bar_one_circuit_and_its_analytic_dead_points() {
    let a = against_oracle("rocker_four_bar");
    assert_eq!((a.circuits, a.dead_points.len()), (1, 2));
    // |BD| = l2 + l3: cos q1 = (l1² + l4² − (l2 + l3)²) / (2 l1 l4).
    let (l1, l2, l3, l4) = (0.3f64, 0.35, 0.3, 0.4);
    let q = ((l1 * l1 + l4 * l4 - (l2 + l3) * (l2 + l3)) / (2.0 * l1 * l4)).acos();
    for d in &a.dead_points {
        assert!(
            gap(d.input.abs(), q) <= 1e-13 || gap(d.input, -q) <= 1e-13,
            "{}",
            d.input
        );
    }
    // At the dead point itself and 1e-12 rad to either side: one or two configurations there,
    // two on the inner side, none on the outer, all labelled with the one circuit.
    let s = setup_from(mechgen::source::SOURCE, "rocker_four_bar");
    let x = a.dead_points[1].input;
    let xs = [x, x + 1e-12, x - 1e-12];
    let b = s.analyze(-PI, PI, &xs).unwrap();
    let counts: Vec<usize> = xs
        .iter()
        .map(|&v| b.at.iter().filter(|c| c.input == v).count())
        .collect();
    assert!(
        (1..=2).contains(&counts[0]) && counts[1] + counts[2] == 2,
        "{counts:?}"
    );
    assert!(b.at.iter().all(|c| c.circuit == 0));
}

#[test]
fn seed_six_bar_and_sixbar_g_agree_with_the_oracle() {
    let a = against_oracle("sixbar");
    assert_eq!((a.circuits, a.dead_points.len()), (2, 0));
    let g = against_oracle("sixbar_g");
    assert_eq!(
        (g.circuits, g.branches.len(), g.dead_points.len()),
        (2, 6, 6)
    );
}

#[test]
fn slider_crank_and_shaper_agree_with_the_oracle() {
    against_oracle("slider_crank");
    against_oracle("shaper");
}

/// An inverted slider-crank driven by the slider (a length input), not compiled in: its dead
/// points are where the rod and the crank line up, sC = ±√((l ± r)² − off²).
#[test]
fn length_input_from_a_file() {
    let text = r#"
[mechanism.slid]
inputs = ["sC"]
unknowns = ["q1", "q2"]
loops = ["r*e(q1) + l*e(q2) - sC - c(0, off)"]
params = { r = 0.05, l = 0.2, off = 0.02 }
start = { sC = 0.2, q1 = 1.6, q2 = -0.15 }
"#;
    let s = setup_from(text, "slid");
    let a = s.analyze(-0.3, 0.3, &[0.2, 0.15 + 1e-9, -0.2]).unwrap();
    let (r, l, off) = (0.05f64, 0.2f64, 0.02f64);
    let mut want: Vec<f64> = [l + r, l - r]
        .iter()
        .flat_map(|d| {
            let x = (d * d - off * off).sqrt();
            [x, -x]
        })
        .collect();
    want.sort_by(f64::total_cmp);
    let got: Vec<f64> = a.dead_points.iter().map(|d| d.input).collect();
    assert_eq!(got.len(), 4, "{got:?}");
    for (g, w) in got.iter().zip(&want) {
        assert!((g - w).abs() <= 1e-12, "{g} vs {w}");
    }
    assert_eq!((a.circuits, a.branches.len()), (2, 4));
    assert_eq!(a.at.len(), 6);
}

/// The fixtures and the sweep test files: every mechanism is analysed or cleanly refused, and
/// every configuration found closes its loops.
#[test]
fn fixtures_and_other_files() {
    let root = env!("CARGO_MANIFEST_DIR");
    for dir in ["tests/fixtures", "tests/data/sweep"] {
        for entry in std::fs::read_dir(format!("{root}/{dir}")).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().and_then(|e| e.to_str()) != Some("toml") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            let (compiled, diags) = mechgen_codegen::analyze(&SourceFile::new("f", &text));
            if diags.iter().any(|d| d.is_error()) {
                continue;
            }
            let mechs = mechgen::generic::load("f", &text).unwrap();
            for (c, g) in compiled.iter().zip(&mechs) {
                let s = match Setup::new(c, 0) {
                    Ok(s) => s,
                    Err(e) => {
                        assert!(e.contains("not supported"), "{}: {e}", path.display());
                        continue;
                    }
                };
                let x0 = c.model.inputs[0].start;
                let (from, to) = if s.input_is_angle {
                    (-PI, PI)
                } else {
                    (x0 - 0.1 * s.scale, x0 + 0.1 * s.scale)
                };
                let a = s
                    .analyze(from, to, &[x0])
                    .unwrap_or_else(|e| panic!("{} {}: {e}", path.display(), s.name));
                let mut x = c.model.inputs.iter().map(|i| i.start).collect::<Vec<_>>();
                // An angle `at` is taken into the analysed turn (as the analysis does).
                x[0] = if s.input_is_angle {
                    -PI + (x0 + PI).rem_euclid(TAU)
                } else {
                    x0
                };
                for l in &a.at {
                    let mut res = vec![0.0; 2 * c.model.loops.len()];
                    mechgen::DynMechanism::<f64>::residual(g, &x, &l.q, &mut res).unwrap();
                    let worst = res.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    assert!(
                        worst <= 1e-9 * s.scale,
                        "{} {}: residual {worst}",
                        path.display(),
                        s.name
                    );
                }
                // The start configuration is one of them.
                let start: Vec<f64> = c.model.unknowns.iter().map(|u| u.start).collect();
                let near = a.at.iter().any(|l| {
                    l.q.iter().zip(&start).zip(&s.angle).all(|((a, b), &ang)| {
                        if ang {
                            gap(*a, *b) < 0.05
                        } else {
                            (a - b).abs() < 0.05 * s.scale
                        }
                    })
                });
                assert!(
                    near || a.at.is_empty(),
                    "{} {}: start not among {:?}",
                    path.display(),
                    s.name,
                    a.at
                );
            }
        }
    }
}

/// A four-bar `l1 e(q1) + l2 e(q2) = l4 e(gamma) + l3 e(q3)` from `tests/data/branches/`.
fn four_bar_file(name: &str) -> Setup {
    let path = format!(
        "{}/tests/data/branches/{name}.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    setup_from(&std::fs::read_to_string(path).unwrap(), name)
}

/// Law of cosines: the inputs q1 where |l1 e(q1) − l4 e(gamma)| = d, ascending.
fn cosine_dead_points(l1: f64, l4: f64, gamma: f64, d: f64) -> [f64; 2] {
    let a = ((l1 * l1 + l4 * l4 - d * d) / (2.0 * l1 * l4)).acos();
    [gamma - a, gamma + a]
}

fn dead_inputs(a: &Analysis) -> Vec<f64> {
    let mut got: Vec<f64> = a.dead_points.iter().map(|d| d.input).collect();
    got.sort_by(f64::total_cmp);
    got
}

/// The links barely reach (l2 + l3 = 2.00001 against a least ground-to-crank-pin distance of 2):
/// the crank moves over q1 ∈ [0.04°, 0.46°] only, a circuit inside one 0.5° cell of the grid.
#[test]
fn a_circuit_inside_one_grid_cell() {
    let s = four_bar_file("narrow");
    let (l1, l2, l3, l4, gamma) = (1.0f64, 1.0f64, 1.00001f64, 3.0f64, 0.25f64.to_radians());
    let x = 0.25f64.to_radians();
    for (from, to) in [(0.0, TAU), (-PI, PI)] {
        let a = s.analyze(from, to, &[x]).unwrap();
        assert_eq!(
            (a.circuits, a.branches.len(), a.dead_points.len()),
            (1, 2, 2),
            "{a:?}"
        );
        let want = cosine_dead_points(l1, l4, gamma, l2 + l3);
        for (g, w) in dead_inputs(&a).iter().zip(want) {
            assert!((g - w).abs() <= 1e-9, "{g} vs {w}");
        }
        // At 0.25°: l2 e(q2) − l3 e(q3) = D = l4 e(gamma) − l1 e(q1), the two triangles on D.
        let (dx, dy) = (
            l4 * gamma.cos() - l1 * x.cos(),
            l4 * gamma.sin() - l1 * x.sin(),
        );
        let (dl, phi) = (dx.hypot(dy), dy.atan2(dx));
        let c = ((l2 * l2 + dl * dl - l3 * l3) / (2.0 * l2 * dl)).acos();
        assert_eq!(a.at.len(), 2);
        for sign in [1.0, -1.0] {
            let q2 = phi + sign * c;
            let q3 = (l2 * q2.sin() - dy).atan2(l2 * q2.cos() - dx);
            let m = a.at.iter().find(|l| gap(l.q[0], q2) <= 1e-9);
            let m = m.unwrap_or_else(|| panic!("q2 = {q2} not in {:?}", a.at));
            assert!(gap(m.q[1], q3) <= 1e-9, "{:?} vs {q3}", m.q);
            assert_eq!(m.circuit, 0);
        }
        assert_ne!(a.at[0].branch, a.at[1].branch);
    }
}

/// |l3 − l2| = 2.00001 against a least distance of 2: no assembly over q1 ∈ [0.04°, 0.46°], two
/// dead points inside one 0.5° cell whose ends both have two configurations (2 → 0 → 2).
#[test]
fn two_dead_points_inside_one_grid_cell() {
    let s = four_bar_file("gap");
    let (l1, l2, l3, l4, gamma) = (1.0f64, 1.0f64, 3.00001f64, 3.0f64, 0.25f64.to_radians());
    let want = cosine_dead_points(l1, l4, gamma, l3 - l2);
    let inside = 0.5 * (want[0] + want[1]);
    for (from, to) in [(0.0, TAU), (-PI, PI)] {
        let a = s.analyze(from, to, &[inside, 0.5f64.to_radians()]).unwrap();
        assert_eq!(
            (a.circuits, a.branches.len(), a.dead_points.len()),
            (1, 2, 2),
            "{a:?}"
        );
        for (g, w) in dead_inputs(&a).iter().zip(want) {
            assert!((g - w).abs() <= 1e-9, "{g} vs {w}");
        }
        let count = |x: f64| a.at.iter().filter(|l| l.input == x).count();
        assert_eq!((count(inside), count(0.5f64.to_radians())), (0, 2));
    }
}

/// The inclined double slider driven by a length input: both dead points, input and
/// configuration, within 1e-12 of the 50-digit geometry of `make_singular.py` (the bordered
/// system, not the bisection on the count, gives the configuration).
#[test]
fn double_slider_dead_points_to_full_precision() {
    let dir = format!("{}/tests/data/branches", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(format!("{dir}/double_slider.toml")).unwrap();
    let s = setup_from(&text, "double_slider");
    let a = s.analyze(-2.0, 2.0, &[]).unwrap();
    let (_, want) = csv("double_slider-dead-points.csv");
    assert_eq!(
        (a.circuits, a.branches.len(), a.dead_points.len()),
        (1, 2, 2)
    );
    for (d, r) in a.dead_points.iter().zip(&want) {
        let w: Vec<f64> = r.iter().map(|v| v.parse().unwrap()).collect();
        let errs = [
            (d.input - w[0]).abs(),
            gap(d.q[0], w[1]),
            (d.q[1] - w[2]).abs(),
        ];
        eprintln!("double slider dead point {}: errors {errs:?}", w[0]);
        assert!(errs.iter().all(|&e| e <= 1e-12), "{errs:?} at {}", w[0]);
    }
}
