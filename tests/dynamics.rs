//! Inverse dynamics (`mechgen::dynamics`) on every engine against independent computations:
//! `slider_crank` against the 40-digit reference of `tests/data/dynamics/make_slider_crank.py`
//! (closed form in the crank angle, Lagrange's equation; mechgen sums virtual work over the
//! bodies' accelerations), and the shaper (two loops, the ram's centre of mass on the length
//! unknown `sE`) against the energy balance: at a constant input rate and without loads the
//! effort is d(kinetic + potential)/dx.

use mechgen::dynamics::{Dynamics, DynamicsWork, PointLoad, dynamics};
use mechgen::{DynMechanism, DynState, InputMotion, SolveOptions};

/// Every engine the compiled-in `name` runs on: generated, interpreter, and the JIT.
fn engines(name: &str) -> Vec<(&'static str, Box<dyn DynMechanism<f64>>)> {
    let generated = mechgen::lookup::<f64>(name).expect("compiled in");
    let loaded = mechgen::generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
        .expect("the compiled-in file loads");
    let generic = loaded
        .into_iter()
        .find(|g| g.name() == name)
        .expect("in the file");
    #[allow(unused_mut)]
    let mut all: Vec<(&'static str, Box<dyn DynMechanism<f64>>)> = vec![
        ("generated", generated),
        ("generic", Box::new(generic.clone())),
    ];
    #[cfg(feature = "jit")]
    {
        let mut jit = generic;
        jit.compile().expect("compiles");
        all.push(("jit", Box::new(jit)));
    }
    all
}

/// A whole solve at `(x, ẋ, ẍ)` from `guess`, then the dynamics for input 0.
fn at(
    m: &dyn DynMechanism<f64>,
    motion: [f64; 3],
    guess: &[f64],
    loads: &[PointLoad<f64>],
) -> (DynState<f64>, Dynamics<f64>) {
    let [x, xd, xdd] = motion.map(|v| [v]);
    let input = InputMotion::new(&x[..], &xd[..], &xdd[..]);
    let state = m
        .solve(input, guess, &SolveOptions::default())
        .expect("solves");
    let mut ws = DynamicsWork::new(&m.info());
    let d = dynamics(m, &state.view(), 0, loads, &mut ws).expect("dynamics");
    (state, d)
}

fn columns(d: &Dynamics<f64>) -> [f64; 7] {
    [
        d.effort,
        d.inertia,
        d.kinetic,
        d.potential,
        d.shaking_force[0],
        d.shaking_force[1],
        d.shaking_moment,
    ]
}

#[test]
fn slider_crank_against_its_closed_form() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/dynamics/slider_crank.csv"
    );
    let text = std::fs::read_to_string(path).expect("reference");
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|c| c.parse().expect("number")).collect())
        .collect();
    assert_eq!(rows.len(), 96);
    // Each column's scale: its largest magnitude over the table.
    let mut scale = [0.0f64; 7];
    for r in &rows {
        for (s, v) in scale.iter_mut().zip(&r[5..]) {
            *s = s.max(v.abs());
        }
    }
    let (r, l, off) = (0.05f64, 0.2f64, 0.02f64);
    for (engine, m) in engines("slider_crank") {
        let slider = m.info().points.iter().position(|p| p == "C").expect("C");
        let mut worst = 0.0f64;
        for row in &rows {
            let t = row[0].to_radians();
            // The guess from the closed form, on the file's branch.
            let q2 = ((off - r * t.sin()) / l).asin();
            let guess = [q2, r * t.cos() + l * q2.cos()];
            let loads = [PointLoad::new(slider, [row[3], row[4]])];
            let (_, d) = at(m.as_ref(), [t, row[1], row[2]], &guess, &loads);
            for ((got, want), s) in columns(&d).iter().zip(&row[5..]).zip(&scale) {
                let e = (got - want).abs() / s;
                assert!(
                    e < 1e-12,
                    "{engine} at {} deg (rate {}, acc {}, load {:?}): {got} against {want} ({e:.1e} of the column)",
                    row[0],
                    row[1],
                    row[2],
                    &row[3..5]
                );
                worst = worst.max(e);
            }
        }
        eprintln!("slider_crank on {engine}: largest difference {worst:.1e} of a column");
    }
}

/// The shaper's energies along a constant-rate motion, differentiated by a five-point stencil,
/// equal its effort; and every engine's dynamics equal the generated one's to 1e-12.
#[test]
fn shaper_effort_is_the_rate_of_its_energy() {
    let rate = 7.0;
    let all = engines("shaper");
    let guess: Vec<f64> = all[0].1.info().unknowns.iter().map(|u| u.start).collect();
    let (_, generated) = &all[0];
    let energy = |x: f64, guess: &[f64]| {
        let (s, d) = at(generated.as_ref(), [x, rate, 0.0], guess, &[]);
        (d.kinetic + d.potential, s.q)
    };
    let mut q = guess.clone();
    let mut largest = 0.0f64;
    let mut worst = 0.0f64;
    for deg in (0..360).step_by(10) {
        let x = f64::from(deg).to_radians();
        let (_, d) = at(generated.as_ref(), [x, rate, 0.0], &q, &[]);
        let h = 1e-3;
        let e = |k: f64| energy(x + k * h, &q).0;
        let derivative = (-e(2.0) + 8.0 * e(1.0) - 8.0 * e(-1.0) + e(-2.0)) / (12.0 * h);
        largest = largest.max(d.effort.abs());
        worst = worst.max((d.effort - derivative).abs());
        for (engine, m) in &all[1..] {
            let (_, other) = at(m.as_ref(), [x, rate, 0.0], &q, &[]);
            for (a, b) in columns(&d).iter().zip(columns(&other)) {
                assert!(
                    (a - b).abs() <= 1e-12 * a.abs().max(1.0),
                    "{engine} against generated at {deg} deg: {b} and {a}"
                );
            }
        }
        q = energy(x, &q).1;
    }
    eprintln!("shaper: effort against d(T + V)/dx, largest difference {worst:.1e} of {largest:.3}");
    assert!(worst < 1e-9 * largest, "{worst:e} against {largest:e}");
}

/// `mechgen dynamics` (interfaces.md) on the command line: its CSV against the reference, the
/// same bytes on every engine, `--flywheel` against the closed-form integrals of the reference
/// script whatever `--step`, and a mechanism without bodies refused.
#[cfg(feature = "cli")]
#[path = "common/cli.rs"]
mod helpers;

#[cfg(feature = "cli")]
mod cli {
    use super::helpers::{mechgen, temp, text};
    use mechgen::dynamics::{DynamicsWork, dynamics};
    use mechgen::{InputMotion, SolveOptions};

    fn read(path: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
        let t = std::fs::read_to_string(path).expect("csv");
        let mut lines = t.lines().map(|l| l.split(',').map(String::from).collect());
        (lines.next().expect("header"), lines.collect())
    }

    #[test]
    fn rows_against_the_reference_and_alike_on_every_engine() {
        let reference = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/data/dynamics/slider_crank.csv"
        );
        let (rh, rrows) = read(std::path::Path::new(reference));
        let csv = temp("dynamics", "rows.csv");
        for (acc, load) in [("0", None), ("-40", Some("C=-150,40"))] {
            let mut outputs = Vec::new();
            for engine in [
                &[][..],
                &["--file", "mechanism.toml"],
                &["--file", "mechanism.toml", "--engine", "generic"],
            ] {
                let mut args = vec!["dynamics", "slider_crank", "--rate", "12.5", "--acc", acc];
                args.extend([
                    "--step",
                    "15",
                    "--to",
                    "345",
                    "--csv",
                    csv.to_str().unwrap(),
                ]);
                if let Some(l) = load {
                    args.extend(["--load", l]);
                }
                args.extend(engine);
                let out = mechgen(&args);
                assert!(out.status.success(), "{}", text(&out.stderr));
                outputs.push(std::fs::read(&csv).expect("csv"));
            }
            assert!(outputs.iter().all(|o| o == &outputs[0]), "engines differ");
            let (h, rows) = read(&csv);
            assert_eq!(rows.len(), 24);
            let wanted: Vec<&Vec<String>> = rrows
                .iter()
                .filter(|r| {
                    r[2].parse::<f64>() == acc.parse::<f64>() && (r[3] != "0.0") == load.is_some()
                })
                .collect();
            assert_eq!(wanted.len(), 24);
            for (name, rname) in [
                ("effort_q1", "effort_q1"),
                ("inertia_q1_q1", "inertia_q1_q1"),
                ("kinetic_energy", "kinetic_energy"),
                ("potential_energy", "potential_energy"),
                ("shaking_fx", "shaking_fx"),
                ("shaking_fy", "shaking_fy"),
                ("shaking_moment", "shaking_moment"),
            ] {
                let c = h.iter().position(|x| x == name).expect(name);
                let rc = rh.iter().position(|x| x == rname).expect(rname);
                let scale = wanted
                    .iter()
                    .map(|r| r[rc].parse::<f64>().unwrap().abs())
                    .fold(0.0, f64::max);
                for (row, want) in rows.iter().zip(&wanted) {
                    assert_eq!(row.last().map(String::as_str), Some("ok"));
                    let (got, want) = (
                        row[c].parse::<f64>().unwrap(),
                        want[rc].parse::<f64>().unwrap(),
                    );
                    assert!(
                        (got - want).abs() <= 1e-12 * scale,
                        "{name} at {}: {got} against {want}",
                        row[0]
                    );
                }
            }
        }
    }

    #[test]
    fn the_flywheel_is_an_integral_not_a_sum_over_rows() {
        let reference = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/data/dynamics/slider_crank_flywheel.csv"
        );
        let (_, r) = read(std::path::Path::new(reference));
        let want: Vec<f64> = r[0].iter().map(|v| v.parse().unwrap()).collect();
        let mut summaries = Vec::new();
        for step in ["30", "1", "0.37"] {
            let path = temp("dynamics", &format!("flywheel-{step}.csv"));
            let out = mechgen(&[
                "dynamics",
                "slider_crank",
                "--rate",
                "12.5",
                "--step",
                step,
                "--load",
                "C=-150,40@60:200",
                "--flywheel",
                "0.04",
                "--summary",
                path.to_str().unwrap(),
            ]);
            assert!(out.status.success(), "{}", text(&out.stderr));
            assert!(text(&out.stdout).contains("flywheel_inertia"));
            summaries.push(std::fs::read_to_string(&path).expect("summary"));
        }
        assert!(
            summaries.iter().all(|s| s == &summaries[0]),
            "{summaries:?}"
        );
        let got: Vec<f64> = summaries[0]
            .lines()
            .nth(1)
            .unwrap()
            .split(',')
            .map(|v| v.parse().unwrap())
            .collect();
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() <= 1e-9 * w.abs(), "{got:?} against {want:?}");
        }
        // The shaper with a cutting force over its working stroke (wrapping through 0): the
        // same figures whatever the rows.
        let mut shaper = Vec::new();
        for step in ["30", "0.7"] {
            let path = temp("dynamics", &format!("shaper-flywheel-{step}.csv"));
            let out = mechgen(&[
                "dynamics",
                "shaper",
                "--rate",
                "6.283",
                "--step",
                step,
                "--load",
                "E=5000,0@350:190",
                "--flywheel",
                "0.05",
                "--summary",
                path.to_str().unwrap(),
            ]);
            assert!(out.status.success(), "{}", text(&out.stderr));
            shaper.push(std::fs::read_to_string(&path).expect("summary"));
        }
        assert_eq!(shaper[0], shaper[1]);
    }

    /// `mechgen simulate four_bar` for 10 s: the same bytes on every engine; from its CSV, the
    /// total energy within 1e-9 relative, every row's equation of motion (the library's inverse
    /// dynamics at the row's x, ẋ, ẍ: effort 0 to 1e-9 of the largest term) and loop closure.
    #[test]
    fn simulate_rows_keep_energy_motion_and_loops() {
        let mut outputs = Vec::new();
        let csv = temp("dynamics", "sim.csv");
        for engine in [&[][..], &["--file", "mechanism.toml"]] {
            let mut args = vec!["simulate", "four_bar", "--time", "10", "--dt", "0.01"];
            args.extend(["--csv", csv.to_str().unwrap()]);
            args.extend(engine);
            let out = mechgen(&args);
            assert!(out.status.success(), "{}", text(&out.stderr));
            assert!(text(&out.stdout).contains("largest change of kinetic + potential energy"));
            outputs.push(std::fs::read(&csv).expect("csv"));
        }
        assert!(outputs[0] == outputs[1], "engines differ");
        let (h, rows) = read(&csv);
        assert_eq!(rows.len(), 1001);
        let col = |n: &str| h.iter().position(|c| c == n).expect(n);
        let v = |r: &Vec<String>, n: &str| r[col(n)].parse::<f64>().expect("number");
        let m = mechgen::lookup::<f64>("four_bar").expect("compiled in");
        let info = m.info();
        let e0 = v(&rows[0], "kinetic_energy") + v(&rows[0], "potential_energy");
        let mut ws = DynamicsWork::new(&info);
        for r in &rows {
            assert_eq!(r.last().map(String::as_str), Some("ok"));
            let e = v(r, "kinetic_energy") + v(r, "potential_energy");
            assert!(
                (e - e0).abs() <= 1e-9 * e0.abs(),
                "energy {e} against {e0} at t = {}",
                r[0]
            );
            let (x, xd, xdd) = ([v(r, "q1")], [v(r, "q1_vel")], [v(r, "q1_acc")]);
            let q = [v(r, "q2"), v(r, "q3")];
            let mut res = [0.0; 2];
            m.residual(&x, &q, &mut res).expect("residual");
            assert!(
                res.iter().all(|e| e.abs() < 1e-13),
                "loop {res:?} at t = {}",
                r[0]
            );
            let input = InputMotion::new(&x[..], &xd[..], &xdd[..]);
            let s = m
                .solve(input, &q, &SolveOptions::default())
                .expect("solves");
            let d = dynamics(m.as_ref(), &s.view(), 0, &[], &mut ws).expect("dynamics");
            // The equation's terms: M ẍ, gravity's (the effort at rest), the rate terms (the rest).
            let zero = [0.0];
            let rest = InputMotion::new(&x[..], &zero[..], &zero[..]);
            let at_rest = m.solve(rest, &q, &SolveOptions::default()).expect("solves");
            let gravity = dynamics(m.as_ref(), &at_rest.view(), 0, &[], &mut ws)
                .expect("dynamics")
                .effort;
            let inertial = d.inertia * xdd[0];
            let largest = inertial
                .abs()
                .max(gravity.abs())
                .max((d.effort - inertial - gravity).abs());
            assert!(
                d.effort.abs() <= 1e-9 * largest,
                "effort {} at t = {}",
                d.effort,
                r[0]
            );
        }
    }

    /// A non-Grashof rocker driven into its dead point (q1 = 135.95°): the row that reaches it
    /// has that status and is the last; the command says so and exits 0.
    #[test]
    fn simulate_stops_at_a_dead_point() {
        let csv = temp("dynamics", "rocker.csv");
        let file = "tests/data/dynamics/rocker.toml";
        let out = mechgen(&[
            "simulate",
            "rocker",
            "--file",
            file,
            "--time",
            "2",
            "--dt",
            "0.01",
            "--torque",
            "5",
            "--csv",
            csv.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        assert!(text(&out.stderr).contains("the simulation stopped"));
        let (h, rows) = read(&csv);
        let (last, ok) = rows.split_last().expect("rows");
        assert_eq!(last.last().map(String::as_str), Some("singular"));
        assert!(
            ok.iter()
                .all(|r| r.last().map(String::as_str) == Some("ok"))
        );
        assert!(rows.len() < 201, "it stops before 2 s");
        let q1 = h.iter().position(|c| c == "q1").expect("q1");
        let reached = ok.last().expect("ok rows")[q1]
            .parse::<f64>()
            .unwrap()
            .to_degrees();
        assert!((125.0..135.96).contains(&reached), "{reached} deg");
    }

    /// The energy drift `simulate` prints is measured against the run's energy, not the start's
    /// total alone: an oscillating cylinder released from rest where every centre of mass is at
    /// y = 0 starts with a total of 0 (rounding aside), and its drift reads small against the
    /// largest kinetic energy.
    #[test]
    fn simulate_measures_the_drift_against_the_runs_energy() {
        let file = "tests/data/dynamics/oscillating_cylinder.toml";
        let args = [
            "simulate", "osc", "--file", file, "--time", "2", "--dt", "0.01",
        ];
        let out = mechgen(&args);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let said = text(&out.stdout);
        let line = said
            .lines()
            .find(|l| l.starts_with("largest change of kinetic + potential energy: "))
            .expect("the drift line");
        let of = " of the larger of the start's total and the largest kinetic energy)";
        let (head, _) = line.split_once(of).expect(line);
        let relative: f64 = head.rsplit_once('(').expect(line).1.parse().expect(line);
        assert!(relative < 1e-9, "{line}");
    }

    #[test]
    fn a_mechanism_without_bodies_is_refused() {
        let out = mechgen(&["dynamics", "rocker_four_bar"]);
        assert_eq!(out.status.code(), Some(1));
        let err = text(&out.stderr);
        assert!(
            err.contains("has no bodies")
                && err.contains("[mechanism.rocker_four_bar.bodies.NAME]"),
            "{err}"
        );
        let out = mechgen(&["dynamics", "slider_crank", "--load", "Z=1,2"]);
        assert_eq!(out.status.code(), Some(1));
        assert!(text(&out.stderr).contains("no point `Z`"));
    }
}

/// `Simulation` (forward dynamics): the compiled-in four-bar released from rest under gravity
/// for 10 s on every engine: total energy within 1e-9 relative (nothing but gravity works on it),
/// every row's equation of motion (the inverse dynamics of the row's state, its acceleration
/// solved at the row's ẍ, gives effort 0 to 1e-9 of its largest term), the loops closed at
/// rounding level; the engines' rows equal to 1e-9.
#[test]
fn a_four_bar_falls_under_gravity_conserving_its_energy() {
    use mechgen::simulate::{Simulation, SimulationOptions};
    let mut runs = Vec::new();
    for (engine, m) in engines("four_bar") {
        let info = m.info();
        let x0: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
        let guess: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
        let mut free = |_: f64, _: f64, _: f64| 0.0;
        let options = SimulationOptions::default();
        let mut sim = Simulation::new(m.as_ref(), 0, &x0, 0.0, &guess, &[], options, &mut free)
            .expect("starts");
        let energy = |s: &Simulation<'_, f64>| {
            let state = s.tick().state().expect("state");
            let mut ws = DynamicsWork::new(&info);
            let d = dynamics(m.as_ref(), &state, 0, &[], &mut ws).expect("dynamics");
            d.kinetic + d.potential
        };
        let e0 = energy(&sim);
        let (mut worst_energy, mut worst_motion, mut worst_loop) = (0.0f64, 0.0f64, 0.0f64);
        let mut rows = Vec::new();
        let mut travelled = 0.0f64;
        for i in 1..=1000 {
            let t = f64::from(i) * 0.01;
            sim.advance_to(t, &mut free)
                .expect("no dead point on a crank");
            let (x, xd, xdd) = (sim.position(), sim.rate(), sim.acceleration_now());
            travelled = travelled.max((x - x0[0]).abs());
            worst_energy = worst_energy.max((energy(&sim) - e0).abs() / e0.abs());
            // The equation of motion at the row, from a whole solve at its (x, ẋ, ẍ).
            let q = sim.tick().state().expect("state").q.to_vec();
            let (state, d) = at(m.as_ref(), [x, xd, xdd], &q, &[]);
            let mut rest = DynamicsWork::new(&info);
            let still = {
                let xd0 = [xd];
                let mut qd = vec![0.0; q.len()];
                m.solve_velocity(&[x], &state.q, &xd0, &mut qd)
                    .expect("velocity");
                let mut s = state.clone();
                s.xdd = vec![0.0];
                m.solve_acceleration(&[x], &state.q, &xd0, &qd, &[0.0], &mut s.qdd)
                    .expect("acceleration");
                dynamics(m.as_ref(), &s.view(), 0, &[], &mut rest).expect("dynamics")
            };
            let largest = (d.inertia * xdd).abs().max(still.effort.abs());
            worst_motion = worst_motion.max(d.effort.abs() / largest);
            let mut r = vec![0.0; q.len()];
            m.residual(&[x], &state.q, &mut r).expect("residual");
            worst_loop = worst_loop.max(r.iter().fold(0.0f64, |a, v| a.max(v.abs())));
            rows.push([x, xd, xdd]);
        }
        eprintln!(
            "four_bar on {engine}: 10 s, input moved up to {travelled:.3} rad; energy drift {worst_energy:.1e}, equation of motion {worst_motion:.1e}, loop residual {worst_loop:.1e}"
        );
        assert!(travelled > 0.5, "it falls");
        assert!(worst_energy < 1e-9, "energy drift {worst_energy:e}");
        assert!(worst_motion < 1e-9, "equation of motion {worst_motion:e}");
        assert!(worst_loop < 1e-13, "loop residual {worst_loop:e}");
        runs.push(rows);
    }
    for other in &runs[1..] {
        for (a, b) in runs[0].iter().zip(other) {
            for (u, v) in a.iter().zip(b) {
                assert!(
                    (u - v).abs() <= 1e-9 * u.abs().max(1.0),
                    "{a:?} against {b:?}"
                );
            }
        }
    }
}

/// A load that acts over a range of the input (`PointLoad::over`) in the simulator: every row
/// satisfies the equation of motion with the load acting exactly where the input lies in its
/// range (to 1e-9 of the largest term), the load does act (the motion differs from the free one),
/// and the step control keeps the rows accurate across the load's switching points.
#[test]
fn a_ranged_load_acts_in_the_simulator_where_the_input_lies_in_its_range() {
    use mechgen::simulate::{Simulation, SimulationOptions};
    let m = mechgen::four_bar::FourBar::<f64>::default();
    let info = DynMechanism::info(&m);
    let p = info.points.iter().position(|n| n == "P").expect("P");
    let x0: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
    let guess: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
    let ranged = [PointLoad::over(
        p,
        [0.0, -20.0],
        [210f64.to_radians(), 300f64.to_radians()],
    )];
    let mut free = |_: f64, _: f64, _: f64| 0.0;
    let options = SimulationOptions::default();
    let run = |loads: &[PointLoad<f64>], free: &mut dyn FnMut(f64, f64, f64) -> f64| {
        let mut sim =
            Simulation::new(&m, 0, &x0, 3.0, &guess, loads, options, free).expect("starts");
        let mut rows = Vec::new();
        for i in 1..=100 {
            sim.advance_to(f64::from(i) * 0.01, free).expect("turns");
            let q = sim.tick().state().expect("state").q.to_vec();
            rows.push(([sim.position(), sim.rate(), sim.acceleration_now()], q));
        }
        rows
    };
    let (with, without) = (run(&ranged, &mut free), run(&[], &mut free));
    let (mut inside, mut outside, mut worst) = (0, 0, 0.0f64);
    for ([x, xd, xdd], q) in &with {
        let (_, d) = at(&m, [*x, *xd, *xdd], q, &ranged);
        let (_, bare) = at(&m, [*x, *xd, 0.0], q, &[]);
        let largest = (d.inertia * xdd)
            .abs()
            .max(bare.effort.abs())
            .max(20.0 * 0.1);
        worst = worst.max(d.effort.abs() / largest);
        if ranged[0].acts_at(*x) {
            inside += 1;
        } else {
            outside += 1;
        }
    }
    let (lo, hi) = with.iter().fold((f64::MAX, f64::MIN), |(a, b), r| {
        (a.min(r.0[0]), b.max(r.0[0]))
    });
    eprintln!(
        "ranged load: x in [{lo:.3}, {hi:.3}] rad, {inside} rows inside, {outside} outside, equation of motion {worst:.1e}"
    );
    assert!(inside > 5 && outside > 5, "{inside} {outside}");
    assert!(worst < 1e-9, "equation of motion {worst:e}");
    let apart = with
        .iter()
        .zip(&without)
        .map(|(a, b)| (a.0[0] - b.0[0]).abs())
        .fold(0.0f64, f64::max);
    assert!(apart > 1e-3, "the load changes the motion ({apart:e})");
}

/// `tick_dynamics` (the bodies on the sines and cosines a generated tick keeps) and
/// `tick_with_dynamics` (a second tick walking alongside, its bodies handed to the sums as the
/// tick's own body computes them; a third with a load over part of the turn) equal `dynamics` of
/// the same state (the bodies computed afresh) to 1e-13 of each
/// quantity's largest magnitude over the walk; the fused tick's state is the plain tick's,
/// along a turn of 1° ticks of every compiled-in mechanism with bodies; and both refuse a
/// negative mass that params changed at run time give (`BadMass`).
#[test]
fn tick_dynamics_equals_dynamics() {
    use mechgen::StaticMechanism;
    use mechgen::dynamics::{tick_dynamics, tick_with_dynamics};
    fn walk<M: StaticMechanism<f64> + 'static>(m: &M) -> f64 {
        let info = DynMechanism::info(m);
        let x0: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
        let q0: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
        let arr = |v: &[f64]| {
            let mut a = <M::X as mechgen::Array<f64>>::zeros();
            a.as_mut().copy_from_slice(v);
            a
        };
        let mut q = <M::Q as mechgen::Array<f64>>::zeros();
        q.as_mut().copy_from_slice(&q0);
        let opts = SolveOptions::default();
        let at = |deg: f64| {
            let mut x = x0.clone();
            x[0] += deg.to_radians();
            InputMotion::new(arr(&x), arr(&[2.5]), arr(&[0.0]))
        };
        let mut t = m.tick_start(&at(0.0), &q, &opts).expect("starts");
        let (mut fused, mut loaded) = (t, t);
        let (mut a, mut b) = (DynamicsWork::new(&info), DynamicsWork::new(&info));
        let mut c = DynamicsWork::new(&info);
        // A load on the first point over part of the turn (the input's start + 30°..200°).
        let x = x0[0];
        let loads = [PointLoad::over(
            0,
            [3.0, -2.0],
            [x + 30f64.to_radians(), x + 200f64.to_radians()],
        )];
        let (mut diff, mut scale) = ([0.0f64; 7], [0.0f64; 7]);
        for deg in 1..=360 {
            m.tick(&mut t, &at(f64::from(deg)), &opts).expect("ticks");
            let fast = tick_dynamics(m, &t, 0, &[], &mut a).expect("tick dynamics");
            let with =
                tick_with_dynamics(m, &mut fused, &at(f64::from(deg)), &opts, (0, &[]), &mut c)
                    .expect("tick with dynamics");
            assert_eq!(fused.q.as_ref(), t.q.as_ref(), "the fused tick's positions");
            assert_eq!(
                fused.qdd.as_ref(),
                t.qdd.as_ref(),
                "the fused tick's accelerations"
            );
            let state = mechgen::State {
                x: t.x.as_ref(),
                xd: t.xd.as_ref(),
                xdd: t.xdd.as_ref(),
                q: t.q.as_ref(),
                qd: t.qd.as_ref(),
                qdd: t.qdd.as_ref(),
                points: t.points.as_ref(),
                report: t.report,
            };
            let slow = dynamics(m, &state, 0, &[], &mut b).expect("dynamics");
            let with_load = tick_with_dynamics(
                m,
                &mut loaded,
                &at(f64::from(deg)),
                &opts,
                (0, &loads),
                &mut c,
            )
            .expect("tick with dynamics and a load");
            let slow_load = dynamics(m, &state, 0, &loads, &mut b).expect("dynamics, a load");
            for (i, (u, v)) in columns(&with_load)
                .iter()
                .zip(columns(&slow_load))
                .enumerate()
            {
                diff[i] = diff[i].max((u - v).abs());
                scale[i] = scale[i].max(v.abs());
            }
            for d in [fast, with] {
                for (i, (u, v)) in columns(&d).iter().zip(columns(&slow)).enumerate() {
                    diff[i] = diff[i].max((u - v).abs());
                    scale[i] = scale[i].max(v.abs());
                }
            }
        }
        // At rest (the input's rate zero): the effort and inertia through a velocity solve at
        // unit rate instead of over the rates.
        let mut x = x0.clone();
        x[0] += 0.7;
        let rest = InputMotion::new(arr(&x), arr(&[0.0]), arr(&[1.5]));
        let d = tick_with_dynamics(m, &mut fused, &rest, &opts, (0, &loads), &mut c).expect("rest");
        let state = mechgen::State {
            x: fused.x.as_ref(),
            xd: fused.xd.as_ref(),
            xdd: fused.xdd.as_ref(),
            q: fused.q.as_ref(),
            qd: fused.qd.as_ref(),
            qdd: fused.qdd.as_ref(),
            points: fused.points.as_ref(),
            report: fused.report,
        };
        let slow = dynamics(m, &state, 0, &loads, &mut b).expect("dynamics at rest");
        assert!(slow.inertia > 0.0 && d.kinetic == 0.0, "{d:?}");
        for (i, (u, v)) in columns(&d).iter().zip(columns(&slow)).enumerate() {
            diff[i] = diff[i].max((u - v).abs());
        }
        diff.iter()
            .zip(&scale)
            .map(|(d, s)| d / s)
            .fold(0.0, f64::max)
    }
    for (name, worst) in [
        ("sixbar", walk(&mechgen::sixbar::Sixbar::<f64>::default())),
        ("shaper", walk(&mechgen::shaper::Shaper::<f64>::default())),
        (
            "four_bar",
            walk(&mechgen::four_bar::FourBar::<f64>::default()),
        ),
        (
            "slider_crank",
            walk(&mechgen::slider_crank::SliderCrank::<f64>::default()),
        ),
    ] {
        eprintln!(
            "{name}: tick_dynamics, tick_with_dynamics against dynamics, largest difference {worst:.1e}"
        );
        assert!(worst < 1e-13, "{name}: {worst:e}");
    }
    // The four-bar's crank mass is `2.4*l1`: a negative l1 makes it negative.
    let m = mechgen::four_bar::FourBar::<f64>::default();
    let mut p = m.params.to_array();
    p[0] = -p[0];
    let bad = <mechgen::four_bar::FourBar<f64> as StaticMechanism<f64>>::with_params(&p).unwrap();
    let info = DynMechanism::info(&bad);
    let state = mechgen::State {
        x: &[0.0][..],
        xd: &[1.0][..],
        xdd: &[0.0][..],
        q: &[1.0, 2.0][..],
        qd: &[0.0, 0.0][..],
        qdd: &[0.0, 0.0][..],
        points: &vec![mechgen::PointMotion::default(); info.points.len()][..],
        report: Default::default(),
    };
    let mut ws = DynamicsWork::new(&info);
    assert_eq!(
        dynamics(&bad, &state, 0, &[], &mut ws),
        Err(mechgen::SolveError::BadMass { body: 0 })
    );
}
