//! The JIT back end against the interpreter and the generated solvers: the same sweeps row for
//! row **bit for bit** (unknowns, rates, points, condition, statuses), on every compiled-in
//! mechanism against the generated solvers (their own ticks, and whole solves), every fixture and
//! sweep test file against the interpreter, random params around each, closed forms on and off,
//! every scene and the single evaluations (J, Φx, J̇, γ, sensitivities, drawing chains); a
//! refused tick leaves every engine's state as it was.
#![cfg(feature = "jit")]

mod common;

use common::sweep::Counting;
use mechgen::generic::{self, Generic};
use mechgen::sweep::{Continuation, Row, sweep};
use mechgen::{DynMechanism, DynScene, InputMotion, Kind, Quantity, SolveError, SolveOptions};
use proptest::prelude::*;

/// Every bit of two sweeps' rows: `None` when equal, else the first difference.
fn first_difference(a: &[Row], b: &[Row]) -> Option<String> {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for (ra, rb) in a.iter().zip(b) {
        let same = match (&ra.result, &rb.result) {
            (Ok(sa), Ok(sb)) => {
                let points = |ps: &[mechgen::PointMotion<f64>]| {
                    let all = ps.iter().flat_map(|p| {
                        p.position
                            .into_iter()
                            .chain(p.velocity)
                            .chain(p.acceleration)
                    });
                    all.collect::<Vec<_>>()
                };
                let (pa, pb) = (points(&sa.points), points(&sb.points));
                bits(&sa.q) == bits(&sb.q)
                    && bits(&sa.qd) == bits(&sb.qd)
                    && bits(&sa.qdd) == bits(&sb.qdd)
                    && bits(&pa) == bits(&pb)
                    && sa.condition.to_bits() == sb.condition.to_bits()
            }
            (Err(ea), Err(eb)) => ea == eb && ra.stopped == rb.stopped,
            _ => false,
        };
        if !same {
            return Some(format!(
                "input {}: {:?} vs {:?}",
                ra.input, ra.result, rb.result
            ));
        }
    }
    (a.len() != b.len()).then(|| "row counts differ".into())
}

/// A full turn around the start (a length input: ±20 % of it) in 2° rows.
fn values_and_continuation(g: &Generic) -> (Vec<f64>, Continuation) {
    let info = DynMechanism::<f64>::info(g);
    let input = &info.inputs[0];
    if input.kind == Kind::Length {
        let s = input.start;
        let v = (0..=40).map(|i| s * (0.8 + 0.01 * f64::from(i))).collect();
        (
            v,
            Continuation::for_input(Kind::Length, 0.2 * s.abs().max(1.0)),
        )
    } else {
        let first = input.start.to_degrees() - 180.0;
        let v = (0..=180)
            .map(|i| (first + 2.0 * f64::from(i)).to_radians())
            .collect();
        (v, Continuation::for_input(Kind::Angle, 1.0))
    }
}

fn compiled(g: &Generic) -> Generic {
    let mut j = g.clone();
    let took = j.compile().expect("the host has a Cranelift back end");
    assert!(j.is_compiled() && !g.is_compiled());
    assert!(
        took.as_secs_f64() < 5.0,
        "{}: compiled in {took:?}",
        g.name()
    );
    j
}

/// Every file's mechanisms, each beside its JIT-compiled copy: loaded and compiled once for all
/// the tests of this binary (a debug build of Cranelift takes about a second for the compiled-in
/// file, and twelve random-param cases used to compile it twelve times). `compiled_in` marks the
/// mechanisms of the compiled-in file.
struct Pair {
    compiled_in: bool,
    g: Generic,
    j: Generic,
}

fn pairs() -> &'static [Pair] {
    static PAIRS: std::sync::OnceLock<Vec<Pair>> = std::sync::OnceLock::new();
    PAIRS.get_or_init(|| {
        let mut all = Vec::new();
        for (name, text) in files() {
            let compiled_in = name == mechgen::source::SOURCE_NAME;
            let ms = match generic::load(&name, &text) {
                Ok(ms) => ms,
                Err(e) if name.contains("diagnostics") => {
                    drop(e);
                    continue;
                }
                Err(e) => panic!("{name}: {e}"),
            };
            all.extend(ms.into_iter().map(|g| Pair {
                compiled_in,
                j: compiled(&g),
                g,
            }));
        }
        all
    })
}

/// The compiled-in file's mechanisms and their JIT copies.
fn compiled_in() -> impl Iterator<Item = (&'static Generic, &'static Generic)> {
    pairs()
        .iter()
        .filter(|p| p.compiled_in)
        .map(|p| (&p.g, &p.j))
}

/// The interpreter and the JIT over the sweep, closed forms on and off: bit for bit.
fn check_sweeps(g: &Generic, j: &Generic, fails: &mut Vec<String>) -> usize {
    let (values, c) = values_and_continuation(g);
    let mut ok = 0;
    for closed_forms in [true, false] {
        let c = Continuation {
            options: SolveOptions {
                closed_forms,
                ..c.options
            },
            ..c
        };
        let a = sweep(g, 0, &values, 1.3, &c);
        let b = sweep(j, 0, &values, 1.3, &c);
        ok += a.iter().filter(|r| r.result.is_ok()).count();
        if let Some(d) = first_difference(&a, &b) {
            fails.push(format!("{} (closed forms {closed_forms}): {d}", g.name()));
        }
    }
    ok
}

/// Every file the tests sweep: the compiled-in one, the fixtures, the sweep tests' mechanisms.
fn files() -> Vec<(String, String)> {
    let mut all = vec![(
        mechgen::source::SOURCE_NAME.to_string(),
        mechgen::source::SOURCE.to_string(),
    )];
    for dir in ["tests/fixtures", "tests/data/sweep", "tests/odd-files"] {
        let mut paths: Vec<_> = std::fs::read_dir(dir)
            .expect("test data")
            .map(|e| e.expect("entry").path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .filter(|p| !p.ends_with("Cargo.toml"))
            .collect();
        paths.sort();
        for p in paths {
            let text = std::fs::read_to_string(&p).expect("readable");
            all.push((p.display().to_string(), text));
        }
    }
    all
}

#[test]
fn jit_equals_interpreter_bit_for_bit_on_every_file() {
    let (mut fails, mut solved, mut n) = (Vec::new(), 0, 0);
    for p in pairs() {
        solved += check_sweeps(&p.g, &p.j, &mut fails);
        n += 1;
    }
    eprintln!("{n} mechanisms, {solved} rows solved");
    assert!(n >= 15 && solved > 3000, "{n} mechanisms, {solved} rows");
    assert!(fails.is_empty(), "{}", fails.join("\n"));
}

#[test]
fn every_file_runs_its_program_compiled() {
    // The bit-for-bit tests hold whichever path runs; this one holds that ticks and whole solves
    // walk the mechanism's program (compiled into one function by the JIT), not the block
    // driver they fall back to without one.
    let mut n = 0;
    for Pair { g, j, .. } in pairs() {
        assert!(g.has_program(), "{}: no program", g.name());
        assert!(j.has_compiled_program(), "{}: not compiled", g.name());
        n += 1;
    }
    assert!(n >= 15, "{n} mechanisms");
}

#[test]
fn jit_whole_solves_equal_generated_bit_for_bit() {
    for (g, j) in compiled_in() {
        let k = mechgen::lookup::<f64>(g.name()).expect("compiled in");
        let (values, c) = values_and_continuation(g);
        // Whole solves: both stepped by the runtime's `SolveTick` (the predictor, then one
        // whole solve), as in tests/generic.rs.
        let (ka, kb) = (Counting::new(k.as_ref()), Counting::new(j));
        let a = sweep(&ka, 0, &values, 1.3, &c);
        let b = sweep(&kb, 0, &values, 1.3, &c);
        assert!(a.iter().filter(|r| r.result.is_ok()).count() > 20);
        if let Some(d) = first_difference(&a, &b) {
            panic!("{}: generated and JIT differ: {d}", g.name());
        }
    }
}

/// The default tickers: the generated `Tick` and the JIT's (the runtime's one predictor on
/// slices, rotated sines and cosines): every row bit for bit, closed forms on and off.
#[test]
fn jit_ticks_equal_generated_ticks_bit_for_bit() {
    for (g, j) in compiled_in() {
        let k = mechgen::lookup::<f64>(g.name()).expect("compiled in");
        let (values, c) = values_and_continuation(g);
        for closed_forms in [true, false] {
            let c = Continuation {
                options: SolveOptions {
                    closed_forms,
                    ..c.options
                },
                ..c
            };
            let a = sweep(k.as_ref(), 0, &values, 1.3, &c);
            let b = sweep(j, 0, &values, 1.3, &c);
            assert!(a.iter().filter(|r| r.result.is_ok()).count() > 20);
            if let Some(d) = first_difference(&a, &b) {
                panic!(
                    "{} (closed forms {closed_forms}): generated and JIT ticks differ: {d}",
                    g.name()
                );
            }
        }
    }
}

#[test]
fn single_evaluations_and_scenes_bit_for_bit() {
    let mut scenes = 0;
    for Pair { g, j, .. } in pairs() {
        let info = DynMechanism::<f64>::info(g);
        let (ni, nu, np) = (info.inputs.len(), info.unknowns.len(), info.params.len());
        let x: Vec<f64> = info.inputs.iter().map(|i| i.start + 0.01).collect();
        let q: Vec<f64> = info
            .unknowns
            .iter()
            .map(|u| u.start * 1.001 + 0.002)
            .collect();
        let xd = vec![1.1; ni];
        let qd: Vec<f64> = (0..nu).map(|i| -0.4 + 0.3 * i as f64).collect();
        let xdd = vec![0.25; ni];
        let run = |m: &Generic| {
            let mut out = vec![0.0; nu * nu.max(ni)];
            let mut all = Vec::new();
            m.residual(&x, &q, &mut out[..nu]).unwrap();
            all.extend_from_slice(&out[..nu]);
            m.jacobian(&x, &q, &mut out[..nu * nu]).unwrap();
            all.extend_from_slice(&out[..nu * nu]);
            m.input_jacobian(&x, &q, &mut out[..nu * ni]).unwrap();
            all.extend_from_slice(&out[..nu * ni]);
            m.jacobian_dot(&x, &q, &xd, &qd, &mut out[..nu * nu])
                .unwrap();
            all.extend_from_slice(&out[..nu * nu]);
            m.acceleration_rhs(&x, &q, &xd, &qd, &xdd, &mut out[..nu])
                .unwrap();
            all.extend_from_slice(&out[..nu]);
            let (mut s, mut p) = (vec![0.0; nu * np], vec![0.0; 2 * info.points.len() * np]);
            if m.sensitivities(&x, &q, &mut s, &mut p).is_ok() {
                all.extend(s.into_iter().chain(p));
            }
            for ch in m.chains(&x, &q).unwrap() {
                all.extend(ch.vertices.into_iter().flatten());
            }
            all.into_iter().map(f64::to_bits).collect::<Vec<_>>()
        };
        assert_eq!(run(g), run(j), "{}", g.name());
        // Scenes: each solved from the start on both.
        for name in g.scene_names() {
            let (a, b) = (g.scene(name).unwrap(), j.scene(name).unwrap());
            let guess: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
            let xs: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
            let input = InputMotion::new(&xs[..], &xd[..], &xdd[..]);
            let o = SolveOptions::default();
            let (ra, rb) = (a.solve(input, &guess, &o), b.solve(input, &guess, &o));
            let bits = |r: &Result<mechgen::DynSceneState<f64>, mechgen::SolveError>| match r {
                Ok(s) => Ok(s
                    .out
                    .iter()
                    .chain(&s.q)
                    .map(|v: &f64| v.to_bits())
                    .collect::<Vec<_>>()),
                Err(e) => Err(*e),
            };
            assert_eq!(bits(&ra), bits(&rb), "scene {name}");
            scenes += 1;
        }
    }
    assert!(scenes >= 3, "{scenes} scenes");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// Random params (each length and angle param within ±5 %) on every compiled-in mechanism:
    /// the interpreter and the JIT still agree bit for bit, through dead points and failures.
    #[test]
    fn random_params_bit_for_bit(seed in any::<u64>()) {
        let mut fails = Vec::new();
        for (i, (g0, j0)) in compiled_in().enumerate() {
            // The JIT's code reads the params at run time: the compiled copy takes new values
            // without compiling again.
            let (mut g, mut j) = (g0.clone(), j0.clone());
            let info = DynMechanism::<f64>::info(g0);
            for (k, p) in info.params.iter().enumerate() {
                let h = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15).rotate_left((7 * (i + k)) as u32);
                let f = 1.0 + 0.1 * ((h >> 11) as f64 / (1u64 << 53) as f64 - 0.5);
                let (a, b) = (g.set_param(&p.name, p.value * f), j.set_param(&p.name, p.value * f));
                prop_assert_eq!(a, b);
            }
            prop_assert!(j.is_compiled() && !g.is_compiled());
            check_sweeps(&g, &j, &mut fails);
        }
        prop_assert!(fails.is_empty(), "{}", fails.join("\n"));
    }
}

/// The command: `sweep NAME --file F` (the JIT, the default for a file) writes the same CSV bytes
/// as `sweep NAME` on the build that compiled F in, for every compiled-in mechanism and scene
/// (CI does the same for every fixture file compiled in through `MECHGEN_MECHANISM`); and
/// `--engine generic` the same again.
#[cfg(feature = "cli")]
#[test]
fn a_file_sweeps_to_the_bytes_of_the_build_that_compiled_it_in() {
    use common::cli::{mechgen, temp, text};
    let loaded = generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE).unwrap();
    let mut names: Vec<String> = loaded.iter().map(|g| g.name().to_string()).collect();
    names.extend(
        loaded
            .iter()
            .flat_map(|g| g.scene_names())
            .map(str::to_string),
    );
    let path = temp("jit", "compiled-in.toml");
    std::fs::write(&path, mechgen::source::SOURCE).unwrap();
    let file = path.to_str().unwrap();
    for name in &names {
        let csv = |engine: &[&str]| {
            let path = temp("jit", &format!("{name}-{}.csv", engine.len()));
            let p = path.to_str().unwrap();
            let mut args = vec!["sweep", name.as_str(), "--step", "2", "--csv", p];
            args.extend_from_slice(engine);
            let out = mechgen(&args);
            assert!(
                out.status.success(),
                "{name} {engine:?}: {}",
                text(&out.stderr)
            );
            std::fs::read(&path).unwrap()
        };
        let generated = csv(&[]);
        assert!(generated.len() > 1000, "{name}");
        assert!(generated == csv(&["--file", file]), "{name}: jit");
        assert!(
            generated == csv(&["--file", file, "--engine", "generic"]),
            "{name}: generic"
        );
    }
}

/// The bits of a tick's state: inputs, unknowns, rates, points.
fn state_bits(t: &dyn mechgen::DynTick<f64>) -> Vec<u64> {
    let s = t.state().expect("started");
    let points = s.points.iter().flat_map(|p| {
        p.position
            .into_iter()
            .chain(p.velocity)
            .chain(p.acceleration)
    });
    (s.x.iter()
        .chain(s.xd)
        .chain(s.xdd)
        .chain(s.q)
        .chain(s.qd)
        .chain(s.qdd))
    .copied()
    .chain(points)
    .map(f64::to_bits)
    .collect()
}

/// `m`'s tick started at `input` from `guess` (default options); `what` names it in a panic.
fn started<'a>(
    m: &'a dyn DynMechanism<f64>,
    input: InputMotion<&[f64]>,
    guess: &[f64],
    what: &str,
) -> Box<dyn mechgen::DynTick<f64> + 'a> {
    let mut t = m.ticker();
    t.start(input, guess, &SolveOptions::default())
        .unwrap_or_else(|e| panic!("{what}: start: {e:?}"));
    t
}

/// A run-time engine's tick solves in its other state and makes it its own only on success: a
/// tick refused (a non-finite input, input rate or acceleration, inputs of the wrong length)
/// leaves the state as it was, bit for bit, and the ticks after it are the generated tick's, bit
/// for bit, on the interpreter and the JIT alike, for every compiled-in mechanism.
#[test]
fn a_refused_tick_leaves_the_state_and_the_next_ticks_are_the_generated_ones() {
    let options = SolveOptions::default();
    for (g, j) in compiled_in() {
        let info = DynMechanism::<f64>::info(g);
        let (ni, name) = (info.inputs.len(), g.name().to_string());
        let x0: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
        let guess: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
        let step = if info.inputs[0].kind == Kind::Length {
            1e-3 * x0[0].abs().max(1.0)
        } else {
            0.01
        };
        let mut xd = vec![0.0; ni];
        xd[0] = 1.0;
        let xdd = vec![0.0; ni];
        let k = mechgen::lookup::<f64>(&name).expect("compiled in");
        let mut runs = Vec::new();
        for (engine, m) in [("generated", k.as_ref()), ("interpreter", g), ("jit", j)] {
            let start = InputMotion::new(&x0[..], &xd[..], &xdd[..]);
            let mut t = started(m, start, &guess, &format!("{name} ({engine})"));
            let mut states = Vec::new();
            let mut x = x0.clone();
            for i in 1..=12 {
                if i == 6 {
                    let before = state_bits(t.as_ref());
                    let mut bad = x.clone();
                    bad[0] = f64::NAN;
                    let nan_rate = vec![f64::NAN; ni];
                    let refused = [
                        t.tick(InputMotion::new(&bad[..], &xd[..], &xdd[..]), &options),
                        t.tick(InputMotion::new(&x[..], &nan_rate[..], &xdd[..]), &options),
                        t.tick(InputMotion::new(&x[..], &xd[..], &nan_rate[..]), &options),
                        // All three: the input is named (the checks' order).
                        t.tick(
                            InputMotion::new(&bad[..], &nan_rate[..], &nan_rate[..]),
                            &options,
                        ),
                        t.tick(
                            InputMotion::new(&x[..], &nan_rate[..], &nan_rate[..]),
                            &options,
                        ),
                        t.tick(InputMotion::new(&x[1..], &xd[1..], &xdd[1..]), &options),
                    ];
                    let non_finite = |quantity| Err(SolveError::NonFinite { quantity, index: 0 });
                    let named = [
                        non_finite(Quantity::Input),
                        non_finite(Quantity::InputRate),
                        non_finite(Quantity::InputAcceleration),
                        non_finite(Quantity::Input),
                        non_finite(Quantity::InputRate),
                    ];
                    for (r, want) in refused.iter().zip(&named) {
                        assert_eq!(r, want, "{name} ({engine}): the error of a bad tick");
                    }
                    for r in refused {
                        assert!(r.is_err(), "{name} ({engine}): a bad tick was taken");
                        assert_eq!(
                            state_bits(t.as_ref()),
                            before,
                            "{name} ({engine}): a refused tick moved the state"
                        );
                    }
                }
                x[0] = x0[0] + step * f64::from(i);
                t.tick(InputMotion::new(&x[..], &xd[..], &xdd[..]), &options)
                    .unwrap_or_else(|e| panic!("{name} ({engine}): tick {i}: {e:?}"));
                states.push(state_bits(t.as_ref()));
            }
            runs.push((engine, states));
        }
        let (_, generated) = &runs[0];
        for (engine, states) in &runs[1..] {
            for (i, (a, b)) in generated.iter().zip(states).enumerate() {
                assert_eq!(
                    a,
                    b,
                    "{name}: tick {} of {engine} differs from generated",
                    i + 1
                );
            }
        }
    }
}

/// Ticks whose input turns past the range of the rotation's series (0.1 rad: the sines and
/// cosines computed afresh) and across two resyncs (every 64 ticks), forth and back, on every
/// compiled-in mechanism with an angle input: the generated, interpreted and compiled ticks
/// give the same state (or the same error) at every tick, bit for bit.
#[test]
fn large_turns_and_resyncs_tick_alike_on_every_engine() {
    let options = SolveOptions::default();
    let mut compared = 0;
    for (g, j) in compiled_in() {
        let info = DynMechanism::<f64>::info(g);
        if info.inputs[0].kind != Kind::Angle {
            continue;
        }
        let (ni, name) = (info.inputs.len(), g.name().to_string());
        let x0: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
        let guess: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
        let (mut xd, xdd) = (vec![0.0; ni], vec![0.0; ni]);
        xd[0] = 1.0;
        // Turns of 0.15 and 0.04 rad in turn, forth for 70 ticks and back for 70.
        let turns: Vec<f64> = (0..140)
            .map(|i| {
                let turn = if i % 2 == 0 { 0.15 } else { 0.04 };
                if i < 70 { turn } else { -turn }
            })
            .collect();
        let k = mechgen::lookup::<f64>(&name).expect("compiled in");
        let mut runs = Vec::new();
        for (engine, m) in [("generated", k.as_ref()), ("interpreter", g), ("jit", j)] {
            let start = InputMotion::new(&x0[..], &xd[..], &xdd[..]);
            let mut t = started(m, start, &guess, &format!("{name} ({engine})"));
            let mut x = x0.clone();
            let mut ticks = Vec::new();
            for turn in &turns {
                x[0] += turn;
                xd[0] = turn.signum();
                let r = t.tick(InputMotion::new(&x[..], &xd[..], &xdd[..]), &options);
                ticks.push(r.map(|()| state_bits(t.as_ref())));
            }
            runs.push((engine, ticks));
        }
        let (_, generated) = &runs[0];
        assert!(
            generated.iter().filter(|r| r.is_ok()).count() > 20,
            "{name}: too few ticks taken to compare"
        );
        for (engine, ticks) in &runs[1..] {
            for (i, (a, b)) in generated.iter().zip(ticks).enumerate() {
                assert_eq!(
                    a,
                    b,
                    "{name}: tick {} of {engine} differs from generated",
                    i + 1
                );
            }
        }
        compared += 1;
    }
    assert!(
        compared >= 3,
        "only {compared} mechanisms with an angle input"
    );
}

/// A negation in compiled code (on x86-64 an xor with −0.0, not Cranelift's `fneg`: see
/// `jit/emit.rs::neg`) has the interpreter's bits for signed zeros, infinities, NaNs of either
/// sign and subnormals, as well as for plain numbers.
#[test]
fn a_negation_keeps_the_bits_of_every_special_value() {
    let text = "[mechanism.signs]\ninputs = [\"x\"]\nunknowns = [\"a\", \"b\"]\n\
                loops = [\"c(-a, -(b*x))\"]\n\n[mechanism.signs.start]\nx = 1.0\na = 0.5\nb = 0.5\n";
    let g = generic::load("signs.toml", text).expect("loads").remove(0);
    let j = compiled(&g);
    let special = [
        0.0,
        -0.0,
        1.5,
        -2.5,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
        -f64::NAN,
        f64::from_bits(1),
        -f64::MIN_POSITIVE,
    ];
    let mut compared = 0;
    for v in special {
        let run = |m: &Generic| {
            let mut out = [7.0; 2];
            m.residual(&[1.0], &[v, v], &mut out)
                .map(|()| out.map(f64::to_bits))
        };
        let (a, b) = (run(&g), run(&j));
        assert_eq!(a, b, "{v:?} ({:#x})", v.to_bits());
        if let Ok(out) = a {
            assert_eq!(out[0], (-v).to_bits(), "-a at {v:?}");
            compared += 1;
        }
    }
    assert_eq!(compared, special.len(), "every value evaluated");
}
