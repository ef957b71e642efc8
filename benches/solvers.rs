//! `cargo bench --bench solvers`: every compiled-in mechanism, both engines, ids
//! `<mechanism>/<stage>/<engine>` with stage `position`, `velocity`, `acceleration` or `step`.
//!
//! Work: a set of states along the start branch, 1 degree apart (1/360 of the length scale for a
//! length input), precomputed. Each iteration takes the next state in turn:
//! - `position`: positions at the next input, Newton from the state's `q`;
//! - `velocity`, `acceleration`: the linear solves at the state;
//! - `step` (one simulator tick, interfaces.md): from the full state (x, q, q̇, q̈), advance the input
//!   by one step, predict q + q'·Δx + q''·Δx²/2 (input rate 1, so q' = q̇ and q'' = q̈), solve
//!   positions, velocities, accelerations and all points. Both engines tick in place along the
//!   states, 1° at a time, there and back: the generated engine with `StaticMechanism::tick` (its state,
//!   a `Tick`, also holds the sines and cosines, and it predicts itself), the run-time engines
//!   (`generic`, `jit`) with their own tick (`DynMechanism::ticker`: the runtime's predictor and
//!   rotated sines and cosines); each iteration keeps the tick (`black_box`) without reading it.
//!
//! - `sweep/generated`, `sweep/generic`: one row of the sweep core (`sweep_each`, what the CLI,
//!   `batch` and Python run per row), no output, time per row of a 1° sweep over the start's
//!   branch.
//! - `sensitivity/generated`: the generated tick followed by every sensitivity (dq/dp, dP/dp)
//!   at its state, so that their cost reads off against `step/generated`.
//! - `dynamics/generated` (mechanisms with bodies): one generated tick with the inverse dynamics
//!   of its state (`mechgen::dynamics::tick_with_dynamics`: the bodies computed in the tick's own
//!   body, then effort, generalized inertia, energies, shaking).
//! - `simulate/generated` (mechanisms with bodies): one error-controlled step of `simulate`'s
//!   integrator (Dormand–Prince 5(4): six new stages, each a tick and the inverse dynamics),
//!   released from rest at the start under gravity; time per step.
//!
//! - `step/lanes`: W instances in f64 lanes (`NAME::Lanes`) of the width a batch runs on this
//!   CPU (`mechgen::sweep::lane_width`: `Vf64<8>` with AVX-512, `Vf64<4>` otherwise), ticked with
//!   the CPU's widest vectors chosen at run time (`tick_widest`), each with its own params and its
//!   own place on the walk, one lane tick per iteration; the time per instance. The lanes' inputs
//!   along their walks are made before the clock starts (`walk_cycle`), as `step/generated`'s are.
//! - `step/batch`: 4096 instances in lane groups of W, each group at its own place in that cycle
//!   of inputs (each lane walking the branch from its own place), every group ticked once per
//!   iteration through `mechgen::batch::for_each_mut` on every
//!   core (the loop on a worker of `mechgen::batch::workers`, as a simulator's frame loop); the
//!   time per instance.
//! - `<scene>/step/generated`: one tick of each compiled-in scene along its mechanism's walk (the
//!   same states), right after its mechanism's benches, so a scene's saving reads off against
//!   `<mechanism>/step/generated` under the same load.
//!
//! The generated engine runs with static dispatch (`visit_all`, fixed arrays); the generic engine
//! is loaded at run time from the same file.

use std::hint::black_box;
use std::time::Duration;

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, criterion_group, criterion_main};
use mechgen::dynamics::{DynamicsWork, tick_with_dynamics};
use mechgen::lanes::{Vf64, WithLanes};
use mechgen::simulate::{Simulation, SimulationOptions};
use mechgen::sweep::{Continuation, sweep, sweep_each};
use mechgen::{
    Array, CoordDesc, DynMechanism, InputMotion, Kind, LaneMechanism, LaneScene, Lanes, Scene,
    SceneVisitor, SolveOptions, StaticMechanism, StaticVisitor,
};

/// A solved state and the input one step further (which is solvable too).
struct State {
    x: Vec<f64>,
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    x_next: Vec<f64>,
}

/// States along the start branch with a solvable next step, input rate 1.
fn states(k: &dyn DynMechanism<f64>) -> (Vec<State>, f64) {
    let info = k.info();
    let CoordDesc { kind, start, .. } = info.inputs[0].clone();
    let dx = match kind {
        Kind::Angle => 1f64.to_radians(),
        _ => {
            let scale = info
                .params
                .iter()
                .filter(|p| p.kind == Kind::Length)
                .fold(0.0f64, |m, p| m.max(p.value.abs()));
            (if scale > 0.0 { scale } else { 1.0 }) / 360.0
        }
    };
    let values: Vec<f64> = (-180..=180).map(|i| start + f64::from(i) * dx).collect();
    let rows = sweep(
        k,
        0,
        &values,
        1.0,
        &Continuation::for_input(kind, 360.0 * dx),
    );
    let mut out = Vec::new();
    for pair in rows.windows(2) {
        if let (Ok(s), Ok(_)) = (&pair[0].result, &pair[1].result) {
            let mut x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
            x[0] = pair[0].input;
            let mut x_next = x.clone();
            x_next[0] = pair[1].input;
            out.push(State {
                x,
                q: s.q.clone(),
                qd: s.qd.clone(),
                qdd: s.qdd.clone(),
                x_next,
            });
        }
    }
    if out.is_empty() {
        // No step of the sweep could be taken (a start at a dead point, say): time ticks that stay
        // at the start input, so every mechanism still has its benches.
        let x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
        let mut q: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
        let n = q.len();
        if k.solve_position(&x, &mut q, &SolveOptions::default())
            .is_ok()
        {
            eprintln!(
                "{}: no step along the input solves; timing ticks in place",
                info.name
            );
        } else {
            eprintln!(
                "{}: the start does not assemble; timing failing ticks",
                info.name
            );
        }
        out.push(State {
            x_next: x.clone(),
            x,
            q,
            qd: vec![0.0; n],
            qdd: vec![0.0; n],
        });
    }
    (out, dx)
}

/// Indices 0, 1, …, n−1, n−2, …, 0, 1, …: a state walking along the solved inputs and back.
/// Instances in a `step/batch` fleet (interfaces.md).
const BATCH: usize = 4096;

#[derive(Clone)]
struct Walk {
    at: usize,
    n: usize,
    up: bool,
}

impl Walk {
    fn new(n: usize) -> Self {
        Walk { at: 0, n, up: true }
    }

    /// A walk that stands at `at`.
    fn at(n: usize, at: usize) -> Self {
        Walk { at, n, up: true }
    }

    fn next(&mut self) -> usize {
        if self.n > 1 {
            if (self.up && self.at + 1 == self.n) || (!self.up && self.at == 0) {
                self.up = !self.up;
            }
            self.at = if self.up { self.at + 1 } else { self.at - 1 };
        }
        self.at
    }
}

/// The lanes' inputs along their walks, each entry one step of every walk further, with the walks
/// there: made before the clock starts, as `step/generated`'s inputs are, so that a lane bench
/// times the tick, not gathering its inputs lane by lane. Every walk over `n` states is back where
/// it began after 2(n − 1) steps, so the entries are a cycle whose last is the walks' start.
fn walk_cycle<I>(
    mut walks: Vec<Walk>,
    n: usize,
    input: impl Fn(&[Walk]) -> I,
) -> Vec<(Vec<Walk>, I)> {
    (0..(2 * n).saturating_sub(2).max(1))
        .map(|_| {
            for walk in walks.iter_mut() {
                walk.next();
            }
            (walks.clone(), input(&walks))
        })
        .collect()
}

/// The entry after `at` in a cycle of `len`.
fn next_in(at: usize, len: usize) -> usize {
    if at + 1 >= len { 0 } else { at + 1 }
}

fn unit_rate(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut xd = vec![0.0; n];
    xd[0] = 1.0;
    (xd, vec![0.0; n])
}

/// The generated solvers, statically typed.
struct Generated<'c> {
    c: &'c mut Criterion,
}

fn arr<A: Array<f64>>(v: &[f64]) -> A {
    let mut a = A::zeros();
    a.as_mut().copy_from_slice(v);
    a
}

/// Lane `i`'s params in the lane benches: the file's, scaled by 1 + 1e-9·i (different in every
/// lane, solvable along the same walk).
fn lane_params(file: impl Iterator<Item = f64>, i: usize) -> Vec<f64> {
    file.map(|v| v * (1.0 + 1e-9 * i as f64)).collect()
}

/// `step/lanes` and `step/batch` of `m` in lanes of `L`, along the solved `states` (input and
/// unknowns).
fn lane_benches<M, L>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    m: &M,
    states: &[(M::X, M::Q)],
    opts: &SolveOptions<f64>,
) where
    M: StaticMechanism<f64>,
    L: Lanes<Scalar = f64>,
{
    let n = states.len();
    // `step/lanes`: W instances in f64 lanes (run with the CPU's widest vectors), each with its
    // own params (the file's, scaled by 1 + 1e-9·i: different in every lane, solvable along the
    // same walk) and its own place on the walk; one lane tick per iteration, the time per
    // instance.
    let w = L::W;
    let lanes = M::Lanes::<L>::from_fn(|i| {
        let p = lane_params(m.info().params.iter().map(|p| p.default), i);
        M::with_params(&p).expect("one value per param")
    });
    let lane_x = |walks: &[Walk]| {
        let mut x = <M::Lanes<L> as LaneMechanism<L>>::X::default();
        for (k, v) in x.as_mut().iter_mut().enumerate() {
            *v = L::from_fn(|i| states[walks[i].at].0.as_ref()[k]);
        }
        x
    };
    let mut lane_xd = <M::Lanes<L> as LaneMechanism<L>>::X::default();
    lane_xd.as_mut()[0] = L::splat(1.0);
    let start_lanes = |walks: &[Walk]| {
        let mut guess = <M::Lanes<L> as LaneMechanism<L>>::Q::default();
        for (k, v) in guess.as_mut().iter_mut().enumerate() {
            *v = L::from_fn(|i| states[walks[i].at].1.as_ref()[k]);
        }
        let input = InputMotion::new(lane_x(walks), lane_xd, Default::default());
        lanes.tick_start(&input, &guess, opts)
    };
    let walks: Vec<Walk> = (0..w).map(|i| Walk::at(n, (i * 37) % n)).collect();
    let cycle = walk_cycle(walks, n, |walks| {
        InputMotion::new(lane_x(walks), lane_xd, Default::default())
    });
    let mut at = cycle.len() - 1;
    let mut lane_tick = start_lanes(&cycle[at].0);
    g.bench_function("step/lanes", |b| {
        b.iter_custom(|iters| {
            let start = std::time::Instant::now();
            for _ in 0..iters {
                at = next_in(at, cycle.len());
                lanes.tick_widest(&mut lane_tick, black_box(&cycle[at].1), opts);
            }
            black_box(&lane_tick);
            start.elapsed() / w as u32
        })
    });
    // `step/batch`: a fleet of BATCH instances in lane groups of W, each group at its
    // own place in the lanes' cycle (so each lane at its own place on the walk), every
    // group ticked once per iteration through the batch API on every core; the time per
    // instance.
    let mut fleet: Vec<(_, usize)> = (0..BATCH / w)
        .map(|g| {
            let at = (g * 7919) % cycle.len();
            (start_lanes(&cycle[at].0), at)
        })
        .collect();
    // The loop runs on a worker of the pool (`pool.install`), as a simulator's frame
    // loop would: each tick's parallel call is not a hand-over to sleeping threads.
    let pool = mechgen::batch::workers(None).expect("worker threads");
    g.bench_function("step/batch", |b| {
        b.iter_custom(|iters| {
            pool.install(|| {
                let start = std::time::Instant::now();
                for _ in 0..iters {
                    mechgen::batch::for_each_mut(&mut fleet, |_, (t, at)| {
                        *at = next_in(*at, cycle.len());
                        lanes.tick_widest(t, &cycle[*at].1, opts);
                    });
                }
                black_box(&fleet);
                start.elapsed() / (BATCH as u32)
            })
        })
    });
}

impl StaticVisitor<f64> for Generated<'_> {
    fn visit<M: StaticMechanism<f64> + 'static>(&mut self, m: &M) {
        let (states, _) = states(m);
        type Typed<M> = (
            <M as StaticMechanism<f64>>::X,
            <M as StaticMechanism<f64>>::Q,
            <M as StaticMechanism<f64>>::Q,
            <M as StaticMechanism<f64>>::Q,
            <M as StaticMechanism<f64>>::X,
        );
        let typed: Vec<Typed<M>> = states
            .iter()
            .map(|s| {
                (
                    arr(&s.x),
                    arr(&s.q),
                    arr(&s.qd),
                    arr(&s.qdd),
                    arr(&s.x_next),
                )
            })
            .collect();
        let (xd_v, xdd_v) = unit_rate(M::INPUTS);
        let (xd, xdd): (M::X, M::X) = (arr(&xd_v), arr(&xdd_v));
        let opts = SolveOptions::default();
        let n = typed.len();
        let mut g = self.c.benchmark_group(M::NAME);
        let mut i = 0;
        g.bench_function("position/generated", |b| {
            b.iter(|| {
                i = (i + 1) % n;
                let (_, q, _, _, xn) = &typed[i];
                let mut q = *q;
                black_box(m.solve_position(black_box(xn), &mut q, &opts)).ok();
                q
            })
        });
        g.bench_function("velocity/generated", |b| {
            b.iter(|| {
                i = (i + 1) % n;
                let (x, q, ..) = &typed[i];
                m.solve_velocity(black_box(x), black_box(q), &xd)
            })
        });
        g.bench_function("acceleration/generated", |b| {
            b.iter(|| {
                i = (i + 1) % n;
                let (x, q, qd, ..) = &typed[i];
                m.solve_acceleration(black_box(x), black_box(q), &xd, qd, &xdd)
            })
        });
        // A simulator ticks in place: the state walks along the precomputed inputs (there and
        // back at the ends of the list), each tick from the previous one.
        let inputs: Vec<InputMotion<M::X>> = typed
            .iter()
            .map(|s| InputMotion::new(s.0, xd, xdd))
            .collect();
        let mut walk = Walk::new(inputs.len());
        let mut tick = m.tick_start(&inputs[0], &typed[0].1, &opts).ok();
        if tick.is_some() {
            g.bench_function("step/generated", |b| {
                b.iter(|| {
                    let j = walk.next();
                    let Some(t) = tick.as_mut() else { return };
                    if m.tick(t, black_box(&inputs[j]), &opts).is_err() {
                        // Off the branch (not expected along solved states): start again there.
                        tick = m.tick_start(&inputs[j], &typed[j].1, &opts).ok();
                    }
                    black_box(&tick);
                })
            });
            // `sensitivity/generated`: the same tick, then every dq/dp and dP/dp at its state.
            let mut walk = Walk::new(inputs.len());
            let mut tick = m.tick_start(&inputs[0], &typed[0].1, &opts).ok();
            g.bench_function("sensitivity/generated", |b| {
                b.iter(|| {
                    let j = walk.next();
                    let Some(t) = tick.as_mut() else { return };
                    if m.tick(t, black_box(&inputs[j]), &opts).is_err() {
                        tick = m.tick_start(&inputs[j], &typed[j].1, &opts).ok();
                        return;
                    }
                    black_box(m.tick_sensitivities(t)).ok();
                })
            });
            // `dynamics/generated` (a mechanism with bodies): the same tick, then the inverse
            // dynamics of its state (effort, generalized inertia, energies, shaking).
            if !m.info().bodies.is_empty() {
                let mut walk = Walk::new(inputs.len());
                let mut tick = m.tick_start(&inputs[0], &typed[0].1, &opts).ok();
                let mut ws = DynamicsWork::new(&DynMechanism::info(m));
                g.bench_function("dynamics/generated", |b| {
                    b.iter(|| {
                        let j = walk.next();
                        let Some(t) = tick.as_mut() else { return };
                        let d = tick_with_dynamics(
                            m,
                            t,
                            black_box(&inputs[j]),
                            &opts,
                            (0, &[]),
                            &mut ws,
                        );
                        if d.is_err() {
                            tick = m.tick_start(&inputs[j], &typed[j].1, &opts).ok();
                        }
                        black_box(&d);
                    })
                });
                // `simulate/generated`: one error-controlled step of `simulate`'s integrator (all
                // its stages, each a tick and the inverse dynamics), released from rest at the
                // start under gravity.
                let info = DynMechanism::info(m);
                let x0: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
                let q0: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
                let mut free = |_: f64, _: f64, _: f64| 0.0;
                let options = SimulationOptions::default();
                let start = |free: &mut dyn FnMut(f64, f64, f64) -> f64| {
                    Simulation::new(m, 0, &x0, 0.0, &q0, &[], options, free).ok()
                };
                let mut sim = start(&mut free);
                if sim.is_some() {
                    g.bench_function("simulate/generated", |b| {
                        b.iter(|| {
                            let stepped = sim.as_mut().map(|s| s.step(&mut free));
                            if !matches!(stepped, Some(Ok(_))) {
                                sim = start(&mut free);
                            }
                            black_box(stepped);
                        })
                    });
                }
            }
            // `step/lanes` and `step/batch` in the lanes a batch runs on this CPU
            // (`mechgen::sweep::lane_width`: eight with AVX-512, four otherwise).
            let states: Vec<(M::X, M::Q)> = typed.iter().map(|s| (s.0, s.1)).collect();
            if mechgen::sweep::lane_width() >= 8 {
                lane_benches::<M, Vf64<8>>(&mut g, m, &states, &opts);
            } else {
                lane_benches::<M, Vf64<4>>(&mut g, m, &states, &opts);
            }
        }
        sweep_rows(&mut g, "sweep/generated", m, &states);
        g.finish();
        mechgen::visit_scenes(&mut Scenes {
            c: self.c,
            mechanism: M::NAME,
        });
    }
}

/// The generated scenes: `<scene>/step/generated`, the same walk of states as their mechanism's
/// `step` (from the mechanism's sweep), each tick from the previous one.
struct Scenes<'c> {
    c: &'c mut Criterion,
    /// Only the scenes of this mechanism: they run right after its benches, so that a scene and
    /// its mechanism are timed under the same load of this shared machine.
    mechanism: &'static str,
}

impl SceneVisitor<f64> for Scenes<'_> {
    fn visit<S: Scene<f64> + 'static>(&mut self, scene: &S) {
        if scene.info().mechanism != self.mechanism {
            return;
        }
        let k = mechgen::lookup::<f64>(scene.info().mechanism).expect("its mechanism");
        let (states, _) = states(k.as_ref());
        let qs: Vec<S::Q> = states.iter().map(|s| arr(&s.q)).collect();
        let (xd_v, xdd_v) = unit_rate(states[0].x.len());
        let (xd, xdd): (S::X, S::X) = (arr(&xd_v), arr(&xdd_v));
        let inputs: Vec<InputMotion<S::X>> = states
            .iter()
            .map(|s| InputMotion::new(arr(&s.x), xd, xdd))
            .collect();
        let opts = SolveOptions::default();
        let mut walk = Walk::new(inputs.len());
        let mut tick = scene.tick_start(&inputs[0], &qs[0], &opts).ok();
        let mut g = self.c.benchmark_group(S::NAME);
        if tick.is_some() {
            g.bench_function("step/generated", |b| {
                b.iter(|| {
                    let j = walk.next();
                    let Some(t) = tick.as_mut() else { return };
                    if scene.tick(t, black_box(&inputs[j]), &opts).is_err() {
                        tick = scene.tick_start(&inputs[j], &qs[j], &opts).ok();
                    }
                    black_box(&tick);
                })
            });
            // `step/lanes`: W instances of the scene in SIMD lanes, each its own place on the
            // walk and its own params (as the mechanism's `step/lanes`), time per instance.
            type Wide = <f64 as WithLanes>::Lanes;
            let w = Wide::W;
            let lanes = S::Lanes::<Wide>::from_fn(|i| {
                let p = lane_params(k.info().params.iter().map(|p| p.value), i);
                S::with_params(&p).expect("one value per param")
            });
            let n = inputs.len();
            let walks: Vec<Walk> = (0..w).map(|i| Walk::at(n, (i * 37) % n)).collect();
            let lane_x = |walks: &[Walk]| {
                let mut x = <S::Lanes<Wide> as LaneScene<Wide>>::X::default();
                for (k, v) in x.as_mut().iter_mut().enumerate() {
                    *v = Wide::from_fn(|i| inputs[walks[i].at].x.as_ref()[k]);
                }
                x
            };
            let mut lane_xd = <S::Lanes<Wide> as LaneScene<Wide>>::X::default();
            lane_xd.as_mut()[0] = Wide::splat(1.0);
            let cycle = walk_cycle(walks, n, |walks| {
                InputMotion::new(lane_x(walks), lane_xd, Default::default())
            });
            let mut at = cycle.len() - 1;
            let mut guess = <S::Lanes<Wide> as LaneScene<Wide>>::Q::default();
            for (k, v) in guess.as_mut().iter_mut().enumerate() {
                *v = Wide::from_fn(|i| qs[cycle[at].0[i].at].as_ref()[k]);
            }
            let mut lane_tick = lanes.tick_start(&cycle[at].1, &guess, &opts);
            g.bench_function("step/lanes", |b| {
                b.iter_custom(|iters| {
                    let start = std::time::Instant::now();
                    for _ in 0..iters {
                        at = next_in(at, cycle.len());
                        lanes.tick_widest(&mut lane_tick, black_box(&cycle[at].1), &opts);
                    }
                    black_box(&lane_tick);
                    start.elapsed() / w as u32
                })
            });
        }
        g.finish();
    }
}

/// The generic engine (`engine` `generic`: interpreted tapes; `jit`: the same tapes compiled by
/// Cranelift), slices, `DMatrix`.
fn generic(c: &mut Criterion, k: &mechgen::generic::Generic, engine: &str) {
    let k: &dyn DynMechanism<f64> = k;
    let info = k.info();
    let (states, _) = states(k);
    let (xd, xdd) = unit_rate(info.inputs.len());
    let opts = SolveOptions::default();
    let n = states.len();
    let nu = info.unknowns.len();
    let mut g = c.benchmark_group(info.name.as_str());
    let mut i = 0;
    let mut q = vec![0.0; nu];
    let mut qd = vec![0.0; nu];
    let mut qdd = vec![0.0; nu];
    g.bench_function(format!("position/{engine}"), |b| {
        b.iter(|| {
            i = (i + 1) % n;
            let s = &states[i];
            q.copy_from_slice(&s.q);
            black_box(k.solve_position(black_box(&s.x_next), &mut q, &opts)).ok();
        })
    });
    g.bench_function(format!("velocity/{engine}"), |b| {
        b.iter(|| {
            i = (i + 1) % n;
            let s = &states[i];
            black_box(k.solve_velocity(black_box(&s.x), &s.q, &xd, &mut qd)).ok();
        })
    });
    g.bench_function(format!("acceleration/{engine}"), |b| {
        b.iter(|| {
            i = (i + 1) % n;
            let s = &states[i];
            black_box(k.solve_acceleration(black_box(&s.x), &s.q, &xd, &s.qd, &xdd, &mut qdd)).ok();
        })
    });
    // Ticking along the same walk with the engine's own tick (`DynMechanism::ticker`: the
    // runtime's predictor, rotated sines and cosines, then the block driver from there).
    let mut walk = Walk::new(n);
    let input = |j: usize| InputMotion::new(&states[j].x[..], &xd[..], &xdd[..]);
    let mut ticker = k.ticker();
    let started = ticker.start(input(0), &states[0].q, &opts).is_ok();
    if started {
        g.bench_function(format!("step/{engine}"), |b| {
            b.iter(|| {
                let j = walk.next();
                if ticker.tick(black_box(input(j)), &opts).is_err() {
                    // Off the branch (not expected along solved states): start again there.
                    ticker.start(input(j), &states[j].q, &opts).ok();
                }
                // As `step/generated`: the tick itself kept, its state not read.
                black_box(&ticker);
            })
        });
    }
    sweep_rows(&mut g, &format!("sweep/{engine}"), k, &states);
    g.finish();
}

/// `sweep/<engine>`: the sweep core (`sweep_each`: continuation to each row, positions, rates,
/// points, condition, status) over the start's branch in 1° rows (the inputs of `states`, which
/// are its solvable steps), no output; the time per row.
fn sweep_rows(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    id: &str,
    k: &dyn DynMechanism<f64>,
    states: &[State],
) {
    let info = k.info();
    let mut values: Vec<f64> = states.iter().map(|s| s.x[0]).collect();
    if let Some(last) = states.last() {
        values.push(last.x_next[0]);
    }
    values.dedup();
    // A branch that covers the whole walk (a full turn of a crank, or the whole span of a length
    // input) is swept from its start upward, as the default sweep runs; a shorter one (a rocker's)
    // over the walk's values around the start, the rows below it solved downward and handed out
    // in order.
    let start = info.inputs[0].start;
    if values.len() >= 361 {
        let dx = values[1] - values[0];
        values = (0..=360).map(|i| start + f64::from(i) * dx).collect();
    }
    let span = values.last().copied().unwrap_or(0.0) - values[0];
    let c = Continuation::for_input(info.inputs[0].kind, span);
    g.bench_function(id, |b| {
        b.iter_custom(|iters| {
            let rows = values.len() as u64;
            let sweeps = iters.div_ceil(rows).max(1);
            let start = std::time::Instant::now();
            for _ in 0..sweeps {
                sweep_each(k, 0, &values, 1.0, &[], &c, &mut |r| {
                    black_box(&r);
                });
            }
            start
                .elapsed()
                .mul_f64(iters as f64 / (sweeps * rows) as f64)
        })
    });
}

fn benches(c: &mut Criterion) {
    mechgen::visit_all(&mut Generated { c });
    let loaded = mechgen::generic::load(mechgen::source::SOURCE_NAME, mechgen::source::SOURCE)
        .expect("the compiled-in file loads");
    for k in &loaded {
        generic(c, k, "generic");
        let mut jit = k.clone();
        if jit.compile().is_ok() {
            generic(c, &jit, "jit");
        }
    }
}

criterion_group! {
    name = solvers;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(50);
    targets = benches
}
criterion_main!(solvers);
