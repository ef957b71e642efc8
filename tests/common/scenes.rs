//! Shared by `tests/scenes.rs` and `tests/fixtures.rs` (which CI runs on every fixture file):
//! every compiled-in scene against its full mechanism over a full sweep of its first input. The
//! expected columns and values are built here from interfaces.md, not from the generator.
#![allow(dead_code)]

use mechgen::generic::Generic;
use mechgen::sweep::{Continuation, Row, sweep};
use mechgen::{
    Array, DynScene, Scene, SceneVisitor, StaticMechanism, StaticVisitor, lookup, lookup_scene,
};
use mechgen::{
    DynMechanism, InputMotion, Kind, MechanismInfo, PointMotion, SceneDescription, SolveOptions,
};

/// The columns interfaces.md asks for: per unknown `u`, `u_vel`, `u_acc`; per point `P_x, P_y`,
/// `P_vx, P_vy`, `P_ax, P_ay`; each up to the order; unknowns first, then points.
pub fn expected_columns(s: &SceneDescription) -> Vec<String> {
    let n = usize::from(s.order) + 1;
    let mut c = Vec::new();
    for u in &s.unknowns {
        c.extend(["", "_vel", "_acc"][..n].iter().map(|x| format!("{u}{x}")));
    }
    for p in &s.points {
        for o in &[["x", "y"], ["vx", "vy"], ["ax", "ay"]][..n] {
            c.extend(o.iter().map(|x| format!("{p}_{x}")));
        }
    }
    c
}

/// The scene's columns read off the full solver's state.
fn full_values<T: Copy>(
    s: &SceneDescription,
    info: &MechanismInfo,
    q: [&[T]; 3],
    points: &[PointMotion<T>],
) -> Vec<T> {
    let n = usize::from(s.order) + 1;
    let mut v = Vec::new();
    for u in &s.unknowns {
        let k = info
            .unknowns
            .iter()
            .position(|c| &c.name == u)
            .expect("unknown");
        v.extend(q[..n].iter().map(|a| a[k]));
    }
    for p in &s.points {
        let m = points[info.points.iter().position(|c| c == p).expect("point")];
        for a in &[m.position, m.velocity, m.acceleration][..n] {
            v.extend(a);
        }
    }
    v
}

/// Solved rows of a sweep of the mechanism's first input: a full turn (1° apart) for an angle,
/// the start ± a quarter of the length scale (101 rows) for a length.
pub fn full_sweep(k: &dyn DynMechanism<f64>) -> Vec<Row> {
    let info = k.info();
    let (kind, start) = (info.inputs[0].kind, info.inputs[0].start);
    let values: Vec<f64> = match kind {
        Kind::Angle => (0..=360)
            .map(|i| start + f64::from(i).to_radians())
            .collect(),
        _ => {
            let scale = info.params.iter().filter(|p| p.kind == Kind::Length);
            let half = scale.fold(0.0f64, |m, p| m.max(p.value.abs())) / 4.0;
            (0..=100)
                .map(|i| start - half + f64::from(i) * half / 50.0)
                .collect()
        }
    };
    let span = values[values.len() - 1] - values[0];
    sweep(k, 0, &values, 1.0, &Continuation::for_input(kind, span))
}

/// `a` within `tol` of `b`, relative to the larger of |b| and the column's scale over the sweep.
fn close(a: f64, b: f64, scale: f64, tol: f64) -> bool {
    a.is_finite() && (a - b).abs() <= tol * b.abs().max(scale)
}

/// Compares a scene's solver (`scene`, any engine and scalar, through `solve`) with the full
/// solver (`full`) from the same guesses along `rows`; returns the failures and the rows compared.
#[allow(clippy::type_complexity)]
pub fn compare<T: mechgen::Real>(
    what: &str,
    scene: &dyn DynScene<T>,
    full: &dyn DynMechanism<T>,
    rows: &[Row],
    tol: f64,
) -> (Vec<String>, usize) {
    let (s, info) = (scene.info(), full.info());
    let ni = info.inputs.len();
    let lit = |v: f64| T::lit(v);
    let mut pairs = Vec::new();
    let mut fails = Vec::new();
    for r in rows {
        let Ok(solved) = &r.result else { continue };
        let mut x: Vec<T> = info.inputs.iter().map(|i| lit(i.start)).collect();
        x[0] = lit(r.input);
        let mut xd = vec![lit(0.0); ni];
        xd[0] = lit(1.0);
        let xdd = vec![lit(0.0); ni];
        let guess: Vec<T> = solved.q.iter().map(|&v| lit(v)).collect();
        let input = InputMotion::new(&x[..], &xd[..], &xdd[..]);
        let full_ok = full.solve(input, &guess, &SolveOptions::default());
        let scene_ok = scene.solve(input, &guess, &SolveOptions::default());
        match (full_ok, scene_ok) {
            (Ok(f), Ok(g)) => pairs.push((
                full_values(&s, &info, [&f.q, &f.qd, &f.qdd], &f.points),
                g.out,
            )),
            (f, g) => fails.push(format!("{what} at {}: full {f:?}, scene {g:?}", r.input)),
        }
    }
    let to64 = |v: T| v.to_f64();
    for (c, name) in s.columns.iter().enumerate() {
        let scale = pairs
            .iter()
            .fold(0.0f64, |m, (f, _)| m.max(to64(f[c]).abs()));
        for (f, g) in &pairs {
            let (a, b) = (to64(g[c]), to64(f[c]));
            if !close(a, b, scale, tol) {
                fails.push(format!(
                    "{what}.{name}: scene {a:e}, full {b:e} (tolerance {tol:e})"
                ));
                break;
            }
        }
    }
    (fails, pairs.len())
}

/// A generated scene against the generic engine's scene of the same plan, from the same guesses
/// along `rows` (a failed row takes the last solved configuration), closed forms on and off:
/// the same status on every row and outputs within 1e-13 of the row's largest magnitude (at
/// least 1). Returns the failures and the rows solved.
pub fn compare_engines(
    what: &str,
    generated: &dyn DynScene<f64>,
    generic: &dyn DynScene<f64>,
    full: &MechanismInfo,
    rows: &[Row],
) -> (Vec<String>, usize) {
    let (ni, mut solved, mut fails) = (full.inputs.len(), 0, Vec::new());
    for closed_forms in [true, false] {
        let options = SolveOptions {
            closed_forms,
            ..SolveOptions::default()
        };
        let mut guess: Vec<f64> = full.unknowns.iter().map(|u| u.start).collect();
        for r in rows {
            if let Ok(s) = &r.result {
                guess.clone_from(&s.q);
            }
            let mut x: Vec<f64> = full.inputs.iter().map(|i| i.start).collect();
            x[0] = r.input;
            let (mut xd, xdd) = (vec![0.0; ni], vec![0.0; ni]);
            xd[0] = 1.0;
            let input = InputMotion::new(&x[..], &xd[..], &xdd[..]);
            let ra = generated.solve(input, &guess, &options);
            let rb = generic.solve(input, &guess, &options);
            let at = format!("{what} at {} (closed forms {closed_forms})", r.input);
            match (&ra, &rb) {
                (Ok(sa), Ok(sb)) => {
                    let (a, b) = (&sa.out, &sb.out);
                    solved += 1;
                    let scale = a.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                    if a.iter().zip(b).any(|(u, v)| !close(*u, *v, scale, 1e-13)) {
                        fails.push(format!("{at}: generated {a:?}, generic {b:?}"));
                    }
                }
                (Err(ea), Err(eb)) if ea.status() == eb.status() => {}
                _ => fails.push(format!("{at}: generated {ra:?}, generic {rb:?}")),
            }
        }
    }
    (fails, solved)
}

/// Every compiled-in scene: its columns (interfaces.md), and its outputs equal to the full
/// solver's over a full sweep, generated f64 (1e-14), generated f32 (1e-5) and the generic
/// engine's scene against the generic full solver (1e-14). Returns the failures.
pub fn check_compiled_in_scenes() -> Vec<String> {
    let generic = mechgen::generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
        .expect("the compiled-in file loads");
    let mut fails = Vec::new();
    for name in mechgen::SCENES {
        let scene = lookup_scene::<f64>(name).expect("listed scene");
        let s = scene.info();
        if s.columns != expected_columns(&s) {
            fails.push(format!("{name}: columns {:?}", s.columns));
        }
        let full = lookup::<f64>(&s.mechanism).expect("its mechanism");
        let rows = full_sweep(full.as_ref());
        let solved = rows.iter().filter(|r| r.result.is_ok()).count();
        if solved < rows.len() / 2 {
            fails.push(format!(
                "{name}: only {solved} of {} rows solved",
                rows.len()
            ));
        }
        let (f, n) = compare(name, scene.as_ref(), full.as_ref(), &rows, 1e-14);
        fails.extend(f);
        let (scene32, full32) = (
            lookup_scene::<f32>(name).unwrap(),
            lookup::<f32>(&s.mechanism).unwrap(),
        );
        let (f, n32) = compare(
            &format!("{name} f32"),
            scene32.as_ref(),
            full32.as_ref(),
            &rows,
            1e-5,
        );
        fails.extend(f);
        let g: &Generic = generic
            .iter()
            .find(|g| g.name() == s.mechanism)
            .expect("generic");
        let gs = g.scene(name).expect("generic scene");
        if DynScene::<f64>::info(&gs) != s {
            fails.push(format!("{name}: the generic engine's plan differs"));
        }
        let (f, ng) = compare::<f64>(&format!("{name} generic"), &gs, g, &rows, 1e-14);
        fails.extend(f);
        let (f, ne) = compare_engines(name, scene.as_ref(), &gs, &full.info(), &rows);
        fails.extend(f);
        if ne < solved {
            fails.push(format!("{name}: {ne} rows solved alike by both engines"));
        }
        eprintln!("{name}: {n} rows f64, {n32} f32, {ng} generic");
        if n != solved || n32 == 0 || ng != solved {
            fails.push(format!("{name}: compared {n}/{n32}/{ng} of {solved} rows"));
        }
    }
    fails
}

/// Ticks every compiled-in scene along its mechanism's sweep, closed forms switched off for three
/// ticks out of every ten (a tick skips the angles its outputs do not read; Newton then predicts
/// from them), and compares each tick's outputs with the scene's `solve` at the same input from
/// the sweep's configuration (Newton stops at its tolerance: 1e-9 relative). Returns the failures.
pub fn check_compiled_in_scene_ticks() -> Vec<String> {
    let mut mechanisms = MechanismTicks(Vec::new());
    mechgen::visit_all(&mut mechanisms);
    let mut v = Ticks {
        fails: Vec::new(),
        visited: Vec::new(),
        mechanisms: mechanisms.0,
    };
    mechgen::visit_scenes(&mut v);
    if v.visited != mechgen::SCENES {
        v.fails.push(format!(
            "visited {:?}, listed {:?}",
            v.visited,
            mechgen::SCENES
        ));
    }
    v.fails
}

struct Ticks {
    fails: Vec<String>,
    visited: Vec<&'static str>,
    /// Each mechanism's Newton iterations per tick along the same walk (`MechanismTicks`).
    mechanisms: Vec<(&'static str, f64)>,
}

/// The inputs of the ticks along a mechanism's sweep, and whether each runs closed forms (three
/// ticks in ten do not).
fn tick_walk(k: &dyn DynMechanism<f64>) -> Vec<(f64, Vec<f64>, bool)> {
    full_sweep(k)
        .into_iter()
        .map_while(|r| r.result.ok().map(|s| (r.input, s.q)))
        .enumerate()
        .map(|(i, (x, q))| (x, q, i % 10 >= 3))
        .collect()
}

/// The input motion of a tick at `x` (rate 1 along the first input) and the configuration `q`.
fn tick_state<X: Array<f64>, Q: Array<f64>>(x: f64, q: &[f64]) -> (InputMotion<X>, Q) {
    let (mut xs, mut xd, mut qa) = (X::zeros(), X::zeros(), Q::zeros());
    xs.as_mut()[0] = x;
    xd.as_mut()[0] = 1.0;
    qa.as_mut().copy_from_slice(q);
    (InputMotion::new(xs, xd, X::zeros()), qa)
}

fn options(closed_forms: bool) -> SolveOptions<f64> {
    SolveOptions {
        closed_forms,
        ..SolveOptions::default()
    }
}

/// Newton iterations per tick of every compiled-in mechanism along `tick_walk`, closed forms on
/// (the ticks with them off are run, not counted).
struct MechanismTicks(Vec<(&'static str, f64)>);

impl StaticVisitor<f64> for MechanismTicks {
    fn visit<M: StaticMechanism<f64> + 'static>(&mut self, m: &M) {
        let mut tick: Option<M::Tick> = None;
        let (mut iterations, mut counted) = (0u32, 0u32);
        for (x, q, closed) in tick_walk(m) {
            let (input, qa): (InputMotion<M::X>, M::Q) = tick_state(x, &q);
            let t = match tick.as_mut() {
                None => match m.tick_start(&input, &qa, &options(closed)) {
                    Ok(t) => tick.insert(t),
                    Err(_) => break,
                },
                Some(t) => match m.tick(t, &input, &options(closed)) {
                    Ok(()) => t,
                    Err(_) => break,
                },
            };
            if closed {
                iterations += t.report.iterations;
                counted += 1;
            }
        }
        let mean = f64::from(iterations) / f64::from(counted.max(1));
        self.0.push((M::NAME, mean));
    }
}

impl SceneVisitor<f64> for Ticks {
    fn visit<S: Scene<f64> + 'static>(&mut self, scene: &S) {
        self.visited.push(S::NAME);
        let mechanism = scene.info().mechanism;
        let full = lookup::<f64>(mechanism).expect("its mechanism");
        let mut tick: Option<S::Tick> = None;
        let (mut iterations, mut counted) = (0u32, 0u32);
        for (x, q, closed) in tick_walk(full.as_ref()) {
            let (input, qa): (InputMotion<S::X>, S::Q) = tick_state(x, &q);
            let step = match tick.as_mut() {
                None => scene
                    .tick_start(&input, &qa, &options(closed))
                    .map(|t| &*tick.insert(t)),
                Some(t) => scene.tick(t, &input, &options(closed)).map(|()| &*t),
            };
            let t = match step {
                Ok(t) => t,
                Err(e) => {
                    self.fails.push(format!("{} tick at {x}: {e}", S::NAME));
                    return;
                }
            };
            if closed {
                iterations += scene.report(t).iterations;
                counted += 1;
            }
            let got = scene.outputs(t);
            let want = scene.solve(&input, &qa, &options(true)).expect("solves");
            for (c, (a, b)) in got.as_ref().iter().zip(want.out.as_ref()).enumerate() {
                let close = (a - b).abs() <= 1e-9 * b.abs().max(1.0);
                if !close {
                    self.fails
                        .push(format!("{} tick at {x}: column {c}: {a} vs {b}", S::NAME));
                }
            }
        }
        // The same predictor as the full tick (estimated rates below order 2): a scene's Newton
        // blocks are a subset of its mechanism's, so they iterate no more per tick.
        let mean = f64::from(iterations) / f64::from(counted.max(1));
        let full_mean = self
            .mechanisms
            .iter()
            .find(|(n, _)| *n == mechanism)
            .map_or(f64::NAN, |m| m.1);
        eprintln!(
            "{}: {mean:.3} Newton iterations per tick, {mechanism} {full_mean:.3}",
            S::NAME
        );
        let no_more = mean <= full_mean + 1e-9;
        if !no_more {
            self.fails.push(format!(
                "{}: {mean:.3} Newton iterations per tick, more than {mechanism}'s {full_mean:.3}",
                S::NAME
            ));
        }
    }
}
