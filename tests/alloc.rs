//! The typed generated solvers allocate nothing: 100 full solves (position from the previous
//! solution at an input 1° further on, velocity, acceleration, points) of every seed mechanism, in
//! f64 and f32, and of every compiled-in scene (solves and ticks), under a counting global allocator.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::hint::black_box;
use std::sync::atomic::{AtomicUsize, Ordering};

use mechgen::{InputMotion, Lanes, SolveError, SolveOptions};

/// Allocations (alloc, alloc_zeroed, realloc) made while a thread had counting switched on.
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    /// Counting is per thread: the harness's allocations on other threads never count.
    static COUNTING: Cell<bool> = const { Cell::new(false) };
}

fn counting() -> bool {
    // `try_with`: the allocator may run while this thread's locals are being torn down.
    COUNTING.try_with(Cell::get).unwrap_or(false)
}

/// `System`, counting the allocations of threads that switched counting on.
struct Counting;

// The crate allows no `unsafe` anywhere else: this test file is the one exception, because a
// `GlobalAlloc` can only be implemented as an `unsafe impl` with `unsafe fn`s. Every method
// forwards to `System` unchanged.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if counting() {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: forwarded unchanged; the caller upholds `GlobalAlloc::alloc`'s contract.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if counting() {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: forwarded unchanged; the caller upholds `GlobalAlloc::alloc_zeroed`'s contract.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if counting() {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: forwarded unchanged; `ptr` came from this allocator, i.e. from `System`.
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged; `ptr` came from this allocator, i.e. from `System`.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Runs `f` with counting on for this thread; returns the allocations it made and its result.
fn count<R>(f: impl FnOnce() -> R) -> (usize, R) {
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    COUNTING.with(|c| c.set(true));
    let result = f();
    COUNTING.with(|c| c.set(false));
    (ALLOCATIONS.load(Ordering::SeqCst) - before, result)
}

const SOLVES: usize = 100;

/// (allocations, solves done, the first error).
type Outcome = (usize, usize, Option<SolveError>);

/// For one mechanism type and scalar: counts the allocations of `SOLVES` full solves through the
/// separate stages (with the sensitivities), `SOLVES` more through `solve`, `SOLVES` through `solve_in_place`, `SOLVES` ticks (`tick_start`, `tick`) and `SOLVES` lane ticks of W instances (`Lanes`), all
/// continuing from the start configuration 1° at a time.
macro_rules! solves {
    ($fn:ident, $module:ident :: $ty:ident, $t:ty) => {
        fn $fn() -> Outcome {
            use mechgen::$module::{Inputs, Unknowns, $ty};
            let m = black_box($ty::<$t>::default());
            let options = SolveOptions::<$t>::default();
            let (x0, q0) = $ty::<$t>::start();
            let x0 = x0.to_array();
            let step = (1.0f64).to_radians() as $t;
            let xd = [1.0 as $t];
            let xdd = [0.0 as $t];
            let (allocations, (done, error)) = count(|| {
                let mut done = 0;
                // Stage by stage.
                let mut q = q0.to_array();
                for i in 0..SOLVES {
                    let x = [x0[0] + step * i as $t];
                    let stages = m.solve_position(&x, &mut q, &options).and_then(|_| {
                        let qd = m.solve_velocity(&x, &q, &xd)?;
                        let qdd = m.solve_acceleration(&x, &q, &xd, &qd, &xdd)?;
                        black_box(m.sensitivities(&x, &q)?);
                        Ok(m.point_motion(&x, &q, &xd, &qd, &xdd, &qdd))
                    });
                    match stages {
                        Ok(points) => {
                            black_box((&q, points));
                            done += 1;
                        }
                        Err(e) => return (done, Some(e)),
                    }
                }
                // All at once.
                let mut guess: Unknowns<$t> = q0;
                for i in 0..SOLVES {
                    let input = InputMotion {
                        x: Inputs::from_array([x0[0] + step * i as $t]),
                        xd: Inputs::from_array(xd),
                        xdd: Inputs::from_array(xdd),
                    };
                    match m.solve(&input, &guess, &options) {
                        Ok(motion) => {
                            guess = motion.q;
                            black_box(motion);
                            done += 1;
                        }
                        Err(e) => return (done, Some(e)),
                    }
                }
                // All at once, in place.
                let start = InputMotion::new(x0, xd, xdd).map(|a| Inputs::from_array(*a));
                let mut state = match m.solve(&start, &q0, &options) {
                    Ok(s) => s,
                    Err(e) => return (done, Some(e)),
                };
                for _ in 0..SOLVES {
                    state.x = Inputs::from_array([state.x.to_array()[0] + step]);
                    match m.solve_in_place(&mut state, &options) {
                        Ok(()) => done += 1,
                        Err(e) => return (done, Some(e)),
                    }
                    black_box(&state);
                }
                // Predictor stepping.
                let at = |x: [$t; 1]| InputMotion::new(x, xd, xdd).map(|a| Inputs::from_array(*a));
                let mut tick = match m.tick_start(&at(x0), &q0, &options) {
                    Ok(t) => t,
                    Err(e) => return (done, Some(e)),
                };
                for i in 1..SOLVES {
                    let x = [x0[0] + step * i as $t];
                    match m.tick(&mut tick, &at(x), &options) {
                        Ok(()) => {
                            black_box(&tick);
                            done += 1;
                        }
                        Err(e) => return (done, Some(e)),
                    }
                }
                // W instances in SIMD lanes (f64: 4, f32: 8), each with its own params.
                type L = <$t as mechgen::lanes::WithLanes>::Lanes;
                let lanes = mechgen::$module::Lanes::<L>::from_fn(|i| {
                    let mut p = m.params.to_array();
                    p[0] *= 1.0 + 0.001 * i as $t;
                    $ty::new(mechgen::$module::Params::from_array(p))
                });
                let lane_at =
                    |x: $t| InputMotion::new([L::splat(x)], [L::splat(xd[0])], [L::splat(xdd[0])]);
                let mut t =
                    lanes.tick_start(&lane_at(x0[0]), &q0.to_array().map(L::splat), &options);
                for i in 1..SOLVES {
                    lanes.tick(&mut t, &lane_at(x0[0] + step * i as $t), &options);
                    for k in 0..L::W {
                        match t.status(k) {
                            Ok(()) => done += 1,
                            Err(e) => return (done, Some(e)),
                        }
                    }
                    black_box(&t);
                }
                (done, None)
            });
            (allocations, done, error)
        }
    };
}

solves!(sixbar_f64, sixbar::Sixbar, f64);
solves!(shaper_f64, shaper::Shaper, f64);
solves!(four_bar_f64, four_bar::FourBar, f64);
solves!(slider_crank_f64, slider_crank::SliderCrank, f64);
solves!(sixbar_f32, sixbar::Sixbar, f32);
solves!(shaper_f32, shaper::Shaper, f32);
solves!(four_bar_f32, four_bar::FourBar, f32);
solves!(slider_crank_f32, slider_crank::SliderCrank, f32);
/// Newton (a 4×4 block) in lanes: `sixbar_g` ticked 1° at a time over the 60° from its start
/// that it assembles along, W instances at once (f64: 4, f32: 8); allocations counted.
fn sixbar_g_lanes<T: mechgen::lanes::WithLanes>() -> Outcome {
    use mechgen::sixbar_g::{Lanes as GLanes, SixbarG};
    type L<T> = <T as mechgen::lanes::WithLanes>::Lanes;
    let lanes = GLanes::<L<T>>::from_fn(|_| SixbarG::<T>::default());
    let (x0, q0) = SixbarG::<T>::start();
    let options = SolveOptions::<T>::default();
    let step = T::lit(1f64.to_radians());
    let at = |x: T| {
        InputMotion::new(
            [L::<T>::splat(x)],
            [L::<T>::splat(T::one())],
            [L::<T>::zero()],
        )
    };
    let guess = q0.to_array().map(L::<T>::splat);
    let (allocations, (done, error)) = count(|| {
        let mut done = 0;
        let mut x = x0.q6;
        let mut t = lanes.tick_start(&at(x), &guess, &options);
        for _ in 0..60 {
            x += step;
            lanes.tick(&mut t, &at(x), &options);
            for k in 0..<L<T> as Lanes>::W {
                match t.status(k) {
                    Ok(()) => done += 1,
                    Err(e) => return (done, Some(e)),
                }
            }
            black_box(&t);
        }
        (done, None)
    });
    (allocations, done, error)
}

/// Every compiled-in scene: `SOLVES` solves through `Scene::solve` and `SOLVES` ticks from the
/// start, 1° (or 1/360 of the start value of a length input) at a time; allocations counted.
struct SceneSolves<T> {
    outcome: Outcome,
    _t: std::marker::PhantomData<T>,
}

impl<T: mechgen::lanes::WithLanes> mechgen::SceneVisitor<T> for SceneSolves<T> {
    fn visit<S: mechgen::Scene<T> + 'static>(&mut self, scene: &S) {
        use mechgen::{Array, LaneScene};
        let k = mechgen::lookup::<f64>(scene.info().mechanism).expect("its mechanism");
        let info = k.info();
        let lit = |v: f64| T::lit(v);
        let mut x0 = S::X::zeros();
        let mut q0 = S::Q::zeros();
        x0.as_mut()
            .iter_mut()
            .zip(&info.inputs)
            .for_each(|(x, i)| *x = lit(i.start));
        q0.as_mut()
            .iter_mut()
            .zip(&info.unknowns)
            .for_each(|(q, u)| *q = lit(u.start));
        let step = lit(1f64.to_radians());
        let (mut xd, xdd) = (S::X::zeros(), S::X::zeros());
        xd.as_mut()[0] = lit(1.0);
        let options = SolveOptions::<T>::default();
        let scene = black_box(scene);
        let params: Vec<T> = info.params.iter().map(|p| lit(p.value)).collect();
        type L<T> = <T as mechgen::lanes::WithLanes>::Lanes;
        let (allocations, (done, error)) = count(|| {
            let mut done = 0;
            let mut q = q0;
            let mut input = InputMotion::new(x0, xd, xdd);
            for _ in 0..SOLVES {
                input.x.as_mut()[0] += step;
                match scene.solve(&input, &q, &options) {
                    Ok(s) => {
                        q = s.q;
                        black_box(s.out);
                        done += 1;
                    }
                    Err(e) => return (done, Some(e)),
                }
            }
            // In place.
            let mut state = match scene.solve(&input, &q0, &options) {
                Ok(s) => s,
                Err(e) => return (done, Some(e)),
            };
            for _ in 0..SOLVES {
                state.x.as_mut()[0] += step;
                match scene.solve_in_place(&mut state, &options) {
                    Ok(()) => done += 1,
                    Err(e) => return (done, Some(e)),
                }
                black_box(&state);
            }
            let mut input = InputMotion::new(x0, xd, xdd);
            let mut tick = match scene.tick_start(&input, &q0, &options) {
                Ok(t) => t,
                Err(e) => return (done, Some(e)),
            };
            for _ in 1..SOLVES {
                input.x.as_mut()[0] += step;
                match scene.tick(&mut tick, &input, &options) {
                    Ok(()) => {
                        black_box(scene.outputs(&tick));
                        done += 1;
                    }
                    Err(e) => return (done, Some(e)),
                }
            }
            // W instances of the scene in SIMD lanes (f64: 4, f32: 8).
            let lanes = S::Lanes::<L<T>>::from_fn(|_| S::with_params(&params).expect("params"));
            let splat = |a: &S::X| {
                let mut v = <S::Lanes<L<T>> as LaneScene<L<T>>>::X::default();
                v.as_mut()
                    .iter_mut()
                    .zip(a.as_ref())
                    .for_each(|(v, a)| *v = L::<T>::splat(*a));
                v
            };
            let mut guess = <S::Lanes<L<T>> as LaneScene<L<T>>>::Q::default();
            guess
                .as_mut()
                .iter_mut()
                .zip(q0.as_ref())
                .for_each(|(v, a)| *v = L::<T>::splat(*a));
            let mut input = InputMotion::new(x0, xd, xdd);
            let lane_input =
                |i: &InputMotion<S::X>| InputMotion::new(splat(&i.x), splat(&i.xd), splat(&i.xdd));
            let mut t = lanes.tick_start(&lane_input(&input), &guess, &options);
            for _ in 1..SOLVES {
                input.x.as_mut()[0] += step;
                lanes.tick(&mut t, &lane_input(&input), &options);
                for k in 0..<L<T> as Lanes>::W {
                    match <S::Lanes<L<T>> as LaneScene<L<T>>>::lane(&t, k).map(|l| l.0) {
                        Some(Ok(())) => done += 1,
                        Some(Err(e)) => return (done, Some(e)),
                        None => {
                            return (
                                done,
                                Some(SolveError::BadLength {
                                    expected: 0,
                                    got: k,
                                }),
                            );
                        }
                    }
                }
                black_box(<S::Lanes<L<T>> as LaneScene<L<T>>>::outputs(&t));
            }
            (done, None)
        });
        let o = &mut self.outcome;
        o.0 += allocations;
        o.1 += done;
        if o.2.is_none() {
            o.2 = error;
        }
    }
}

fn scenes<T: mechgen::lanes::WithLanes>() -> Outcome {
    let mut v = SceneSolves::<T> {
        outcome: (0, 0, None),
        _t: std::marker::PhantomData,
    };
    mechgen::visit_scenes(&mut v);
    v.outcome
}

/// Every compiled-in mechanism (with bodies only: `bodies`) on the generated engine, the
/// interpreter and, built with it, the JIT.
fn engines(bodies: bool) -> Vec<(String, Box<dyn mechgen::DynMechanism<f64>>)> {
    let loaded = mechgen::generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
        .expect("the compiled-in file loads");
    let mut engines: Vec<(String, Box<dyn mechgen::DynMechanism<f64>>)> = Vec::new();
    for g in &loaded {
        if bodies && mechgen::DynMechanism::<f64>::info(g).bodies.is_empty() {
            continue;
        }
        let k = mechgen::lookup::<f64>(g.name()).expect("compiled in");
        engines.push((format!("{} (generated)", g.name()), k));
        engines.push((format!("{} (generic)", g.name()), Box::new(g.clone())));
        #[cfg(feature = "jit")]
        {
            let mut j = g.clone();
            j.compile().expect("the host has a Cranelift back end");
            engines.push((format!("{} (jit)", g.name()), Box::new(j)));
        }
    }
    engines
}

/// The sweep core allocates nothing per row: for every compiled-in mechanism on the generated
/// engine, the interpreter and the JIT, a sweep of 721 rows (0° to 360° by 0.5°) makes exactly
/// the allocations of one of 181 rows (by 2°): its workspace, made once per sweep (the run-time
/// engines' per-thread solve workspace grown by a first sweep). The rows are read through the
/// borrowed view `sweep_each` hands out; a mechanism with bodies computes each row's inverse
/// dynamics as well, as `mechgen dynamics` and Python do. Returns (name, allocations of the short sweep, of the long one).
fn sweeps() -> Vec<(String, usize, usize)> {
    use mechgen::dynamics::PointLoad;
    use mechgen::kinetics::{RowWork, row_dynamics};
    use mechgen::sweep::{Continuation, sweep_each};
    let mut out = Vec::new();
    for (name, k) in &engines(false) {
        let info = k.info();
        let kind = info.inputs[0].kind;
        let run = |step: f64| {
            let n = (360.0 / step) as usize;
            let scale = if kind == mechgen::Kind::Angle {
                std::f64::consts::PI / 180.0
            } else {
                info.inputs[0].start.abs().max(1.0) / 3600.0
            };
            let values: Vec<f64> = (0..=n)
                .map(|i| info.inputs[0].start + i as f64 * step * scale)
                .collect();
            let c = Continuation::for_input(kind, values[n] - values[0]);
            let mut ok = 0;
            let (allocations, ()) = count(|| {
                // A mechanism with bodies: each row's inverse dynamics too, as `mechgen
                // dynamics` and Python compute it (`kinetics::row_dynamics`): at the sweep's rate
                // (coefficients from the row's rates), accelerating (its accelerations solved
                // again) with a load on the first point over half a turn, and at rest (a velocity
                // solve at unit rate).
                let mut ws = RowWork::new(&info);
                let mut x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
                let x0 = x[0];
                let loads = [PointLoad::over(0, [2.0, -1.0], [x0, x0 + 3.0])];
                sweep_each(k.as_ref(), 0, &values, 1.0, &[], &c, &mut |r| {
                    ok += usize::from(black_box(&r).result.is_ok());
                    let Ok(s) = &r.result else { return };
                    if info.bodies.is_empty() {
                        return;
                    }
                    x[0] = r.input;
                    for (motion, loads) in [
                        ((1.0, 0.0), &[][..]),
                        ((1.0, 0.5), &loads),
                        ((0.0, 0.0), &[]),
                    ] {
                        let d = row_dynamics(k.as_ref(), &x, 0, s, motion, loads, &mut ws);
                        black_box(d.map(|d| d.effort).unwrap_or(0.0));
                    }
                });
            });
            (allocations, ok)
        };
        run(2.0);
        let (short, ok_short) = run(2.0);
        let (long, ok_long) = run(0.5);
        assert!(ok_short > 20 && ok_long > 80, "{name}: rows solved");
        out.push((name.clone(), short, long));
    }
    out
}

/// Param sets swept in SIMD lanes (`batch` on a compiled-in mechanism) allocate nothing per row:
/// eight sets of the six-bar and of the four-bar (params within 1 % of the file's, every set in
/// the lanes) swept 0° to 360° by 0.5° make the allocations of the same by 2°. Returns (name,
/// allocations of the short sweep, of the long one).
fn lane_batches() -> Vec<(String, usize, usize)> {
    use mechgen::batch::lanes::{Group, LANES, sweep_group};
    use mechgen::sweep::Continuation;
    let mut out = Vec::new();
    for name in ["sixbar", "four_bar"] {
        let info = mechgen::lookup::<f64>(name).expect("compiled in").info();
        let params: Vec<Vec<f64>> = (0..LANES)
            .map(|i| {
                let f = 1.0 + 0.01 * (i as f64 / LANES as f64 - 0.5);
                info.params.iter().map(|p| p.value * f).collect()
            })
            .collect();
        let run = |step: f64| {
            let n = (360.0 / step) as usize;
            let values: Vec<f64> = (0..=n).map(|i| (i as f64 * step).to_radians()).collect();
            let c = Continuation::for_input(mechgen::Kind::Angle, values[n] - values[0]);
            let group = Group {
                params: &params,
                index: 0,
                values: &values,
                rate: 1.0,
                held: &[],
                continuation: &c,
            };
            let mut ok = 0;
            let (allocations, left) = count(|| {
                sweep_group(name, &group, &mut |_, _, r| {
                    ok += usize::from(black_box(&r).result.is_ok());
                })
            });
            assert_eq!(left, Some(0), "{name}: every set stays in the lanes");
            assert_eq!(ok, LANES * (n + 1), "{name}: rows solved");
            allocations
        };
        // A first run makes what is made once per mechanism (in a release build it allocates
        // more than the runs after it), so that the two counted runs differ only in their rows.
        run(2.0);
        out.push((name.to_string(), run(2.0), run(0.5)));
    }
    out
}

/// One test only, so no two counting regions of this binary ever overlap.
/// `simulate`'s stepper allocates nothing per step: every compiled-in mechanism with bodies, on
/// the generated engine, the interpreter and the JIT, with a load over part of the turn (steps
/// landed on its edges), makes exactly the allocations of 20 steps in 80 (none: the workspace is
/// made by `Simulation::new`). Returns (name, allocations of the short run, of the long one).
fn simulations() -> Vec<(String, usize, usize)> {
    use mechgen::dynamics::PointLoad;
    use mechgen::simulate::{Simulation, SimulationOptions};
    let mut out = Vec::new();
    for (name, k) in &engines(true) {
        let info = k.info();
        let x0: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
        let guess: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
        let loads = [PointLoad::over(
            0,
            [1.0, -1.0],
            [x0[0] + 0.01, x0[0] + 0.02],
        )];
        let mut effort = |_: f64, _: f64, _: f64| 0.0;
        let options = SimulationOptions {
            max_step: 1e-3,
            ..SimulationOptions::default()
        };
        let run = |steps: usize, effort: &mut dyn FnMut(f64, f64, f64) -> f64| {
            let mut sim = Simulation::new(k.as_ref(), 0, &x0, 2.0, &guess, &loads, options, effort)
                .expect("starts");
            count(|| {
                for _ in 0..steps {
                    black_box(sim.step(effort)).ok();
                }
            })
            .0
        };
        let (short, long) = (run(20, &mut effort), run(80, &mut effort));
        out.push((name.clone(), short, long));
    }
    out
}

#[test]
fn generated_solvers_do_not_allocate() {
    // The counter works: an allocation on this thread, with counting on, is seen.
    let (seen, _) = count(|| black_box(Box::new(black_box(7u64))));
    assert!(
        seen >= 1,
        "the counting allocator saw {seen} allocations of a Box"
    );
    // ... and nothing is counted with counting off.
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    black_box(vec![0u8; 64]);
    assert_eq!(ALLOCATIONS.load(Ordering::SeqCst), before);

    let cases = [
        ("sixbar f64", sixbar_f64 as fn() -> Outcome),
        ("shaper f64", shaper_f64),
        ("four_bar f64", four_bar_f64),
        ("slider_crank f64", slider_crank_f64),
        ("sixbar f32", sixbar_f32),
        ("shaper f32", shaper_f32),
        ("four_bar f32", four_bar_f32),
        ("slider_crank f32", slider_crank_f32),
        ("sixbar_g lanes f64", sixbar_g_lanes::<f64>),
        ("sixbar_g lanes f32", sixbar_g_lanes::<f32>),
        ("every scene f64", scenes::<f64>),
        ("every scene f32", scenes::<f32>),
    ];
    let mut failures = Vec::new();
    for (name, run) in cases {
        let (allocations, done, error) = run();
        eprintln!("{name}: {done} full solves, {allocations} allocations");
        if let Some(e) = error {
            failures.push(format!("{name}: solve {} failed: {e:?}", done + 1));
        }
        if allocations != 0 {
            failures.push(format!(
                "{name}: {allocations} allocations in {done} full solves"
            ));
        }
    }
    for (name, short, long) in sweeps() {
        eprintln!("sweep of {name}: {short} allocations for 181 rows, {long} for 721");
        if long != short {
            failures.push(format!(
                "sweep of {name}: {short} allocations for 181 rows, {long} for 721"
            ));
        }
    }
    for (name, short, long) in lane_batches() {
        eprintln!("lane batch of {name}: {short} allocations for 181 rows, {long} for 721");
        if long != short {
            failures.push(format!(
                "lane batch of {name}: {short} allocations for 181 rows, {long} for 721"
            ));
        }
    }
    for (name, short, long) in simulations() {
        eprintln!("simulation of {name}: {short} allocations in 20 steps, {long} in 80");
        if long != short {
            failures.push(format!(
                "simulation of {name}: {short} allocations in 20 steps, {long} in 80"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
