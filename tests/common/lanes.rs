//! Shared by `tests/lanes.rs` and `tests/fixtures.rs` (which CI runs on every fixture file): every
//! compiled-in mechanism ticked in SIMD lanes, W instances with different params and input
//! steps, against the scalar tick of each instance: every lane's status is the scalar tick's and
//! its state (and caches) the scalar tick's to the last bit, whether it passed a dead point, failed
//! to start, or ran next to lanes that did.

use mechgen::lanes::{F64x2, F64x4, Isa, Lanes, Vf64};
use mechgen::{
    Array, InputMotion, Kind, LaneMechanism, LaneScene, MechanismInfo, Scene, SceneVisitor,
    SolveOptions, StaticMechanism, StaticVisitor,
};
use proptest::test_runner::{Config, TestCaseError, TestRunner};

/// What a run saw: lane-ticks compared, how many of them failed (in the scalar tick too), and
/// how many ok lane-ticks ran beside a failed lane.
#[derive(Default, Debug)]
pub struct Seen {
    pub compared: usize,
    pub failed: usize,
    pub ok_beside_failed: usize,
}

/// Instance `i`'s params: the file's values scaled (lengths) or shifted (angles) by up to
/// `spread`, from `u` in [−1, 1].
fn params_of<M: StaticMechanism<f64>>(m: &M, u: &[f64], spread: f64) -> M {
    M::with_params(&param_values(&m.info().into(), u, spread)).expect("one value per param")
}

fn param_values(info: &MechanismInfo, u: &[f64], spread: f64) -> Vec<f64> {
    info.params
        .iter()
        .zip(u)
        .map(|(p, u)| match p.kind {
            Kind::Length => p.value * (1.0 + spread * u),
            _ => p.value + spread * u,
        })
        .collect()
}

/// The spread of the last lane's params in the root crate's checks: 40 % (it meets dead points).
pub const LAST_SPREAD: f64 = 0.4;

/// The spread of lane `i`'s params among `w`: none for lane 0, `last` for the last, 5 % for the
/// others.
fn spread(i: usize, w: usize, last: f64) -> f64 {
    if i == 0 {
        0.0
    } else if i == w - 1 {
        last
    } else {
        0.05
    }
}

/// One case: W instances of `m` (lane 0 at the file's params, the others perturbed, the last by
/// up to `last`; the root crate: 40 %, so that it meets dead points), each input stepped at its own rate for `ticks`
/// ticks (a length input by its own span per tick), every lane checked against its scalar tick.
fn case<M: StaticMechanism<f64>, L: Lanes<Scalar = f64>>(
    isa: Option<Isa>,
    m: &M,
    last: f64,
    u: &[f64],
    steps: &[f64],
    ticks: usize,
    seen: &mut Seen,
) -> Result<(), String> {
    let info = m.info();
    let w = L::W;
    let npar = info.params.len();
    let mechs: Vec<M> = (0..w)
        .map(|i| params_of(m, &u[i * npar..(i + 1) * npar], spread(i, w, last)))
        .collect();
    let lanes = M::Lanes::<L>::from_fn(|i| mechs[i].clone());
    let opts = SolveOptions::default();
    let (ni, nu) = (info.inputs.len(), info.unknowns.len());
    // Per lane: the input step (radians, or a fraction of the start for a length).
    let step: Vec<f64> = (0..w)
        .map(|i| match info.inputs[0].kind {
            Kind::Angle => steps[i].to_radians(),
            _ => steps[i] * 0.01 * info.inputs[0].start.abs().max(1e-3),
        })
        .collect();
    let mut x = <M::Lanes<L> as LaneMechanism<L>>::X::default();
    let mut xd = x;
    let mut guess = <M::Lanes<L> as LaneMechanism<L>>::Q::default();
    for k in 0..ni {
        x.as_mut()[k] = L::splat(info.inputs[k].start);
    }
    xd.as_mut()[0] = L::from_fn(|i| step[i]);
    for k in 0..nu {
        guess.as_mut()[k] = L::splat(info.unknowns[k].start);
    }
    let lane_input = |x: &<M::Lanes<L> as LaneMechanism<L>>::X, i: usize| {
        let mut xs = M::X::zeros();
        let mut xds = M::X::zeros();
        for k in 0..ni {
            xs.as_mut()[k] = x.as_ref()[k].lane(i);
            xds.as_mut()[k] = xd.as_ref()[k].lane(i);
        }
        InputMotion::new(xs, xds, M::X::zeros())
    };
    let mut guesses = vec![M::Q::zeros(); w];
    for g in &mut guesses {
        for k in 0..nu {
            g.as_mut()[k] = info.unknowns[k].start;
        }
    }
    let input = InputMotion::new(x, xd, Default::default());
    let mut t = lanes.tick_start(&input, &guess, &opts);
    let mut scalar: Vec<Option<M::Tick>> = (0..w)
        .map(|i| {
            mechs[i]
                .tick_start(&lane_input(&x, i), &guesses[i], &opts)
                .ok()
        })
        .collect();
    for tick in 0..=ticks {
        if tick > 0 {
            let a = x.as_mut();
            a[0] = a[0] + L::from_fn(|i| step[i]);
            let input = InputMotion::new(x, xd, Default::default());
            match isa {
                None => lanes.tick(&mut t, &input, &opts),
                Some(isa) => assert!(lanes.tick_on(isa, &mut t, &input, &opts)),
            }
        }
        let statuses: Vec<bool> = (0..w)
            .map(|i| {
                let input = lane_input(&x, i);
                let r = if tick == 0 {
                    scalar[i].map(|_| ()).ok_or(())
                } else {
                    match &mut scalar[i] {
                        Some(s) => mechs[i].tick(s, &input, &opts).map_err(|_| ()),
                        None => match mechs[i].tick_start(&input, &guesses[i], &opts) {
                            Ok(s) => {
                                scalar[i] = Some(s);
                                Ok(())
                            }
                            Err(_) => Err(()),
                        },
                    }
                };
                r.is_ok()
            })
            .collect();
        let any_failed = statuses.iter().any(|ok| !ok);
        for i in 0..w {
            let (status, lane) = <M::Lanes<L> as LaneMechanism<L>>::lane(&t, i).expect("i < W");
            let at = format!("{} lane {i}/{w} tick {tick}", info.name);
            seen.compared += 1;
            if status.is_ok() != statuses[i] {
                return Err(format!(
                    "{at}: lanes {status:?}, scalar ok = {}",
                    statuses[i]
                ));
            }
            if let Err(e) = status {
                seen.failed += 1;
                // The scalar tick's own error, from the same state.
                let input = lane_input(&x, i);
                let again = match scalar[i] {
                    Some(mut s) => mechs[i].tick(&mut s, &input, &opts).err(),
                    None => mechs[i].tick_start(&input, &guesses[i], &opts).err(),
                };
                if again != Some(e) {
                    return Err(format!("{at}: lanes {e:?}, scalar {again:?}"));
                }
            } else if any_failed {
                seen.ok_beside_failed += 1;
            }
            if let Some(s) = &scalar[i]
                && lane != *s
            {
                return Err(format!("{at}: lanes {:?}\nscalar {:?}", *lane, **s));
            }
        }
    }
    Ok(())
}

/// One mechanism in `F64x4` and `F64x2` lanes, and in `Vf64<8>` lanes on every instruction set
/// this CPU has ([`Isa`]), over `cases` random cases of `ticks` ticks each
/// (random params and input rates per lane, the last lane's params up to `last` off): the first
/// failing case, if any. Also what a crate with mechanisms of its own runs
/// (`tests/odd-files/tests/lanes.rs`).
pub fn check_mechanism_lanes<M: StaticMechanism<f64>>(
    m: &M,
    last: f64,
    cases: u32,
    ticks: usize,
    seen: &mut Seen,
) -> Result<(), String> {
    let npar = m.info().params.len();
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    let strategy = (
        proptest::collection::vec(-1.0f64..1.0, 8 * npar),
        proptest::collection::vec(0.3f64..4.0, 8),
    );
    let seen = std::cell::RefCell::new(seen);
    runner
        .run(&strategy, |(u, steps)| {
            let seen = &mut **seen.borrow_mut();
            case::<M, F64x4>(None, m, last, &u, &steps, ticks, seen)
                .map_err(TestCaseError::fail)?;
            case::<M, F64x2>(None, m, last, &u, &steps, ticks, seen)
                .map_err(TestCaseError::fail)?;
            // The eight lanes of `WithLanes`, compiled for every instruction set this CPU has.
            for isa in Isa::ALL.into_iter().filter(|isa| isa.available()) {
                case::<M, Vf64<8>>(Some(isa), m, last, &u, &steps, ticks, seen)
                    .map_err(TestCaseError::fail)?;
            }
            Ok(())
        })
        .map_err(|e| format!("{}: {e}", m.info().name))
}

/// Every compiled-in mechanism as [`check_mechanism_lanes`]: the failures and what was seen. The
/// cases are run on two threads, half on each (each runner draws its own random cases): a debug
/// build takes tens of seconds on a Newton six-bar alone, while the test binary's other tests are
/// done long before.
pub fn check_lanes(cases: u32, ticks: usize) -> (Vec<String>, Seen) {
    struct Visit {
        cases: u32,
        ticks: usize,
        fails: Vec<String>,
        seen: Seen,
    }
    impl StaticVisitor<f64> for Visit {
        fn visit<M: StaticMechanism<f64> + 'static>(&mut self, m: &M) {
            if let Err(e) =
                check_mechanism_lanes(m, LAST_SPREAD, self.cases, self.ticks, &mut self.seen)
            {
                self.fails.push(e);
            }
        }
    }
    let run = |cases| {
        let mut v = Visit {
            cases,
            ticks,
            fails: Vec::new(),
            seen: Seen::default(),
        };
        if cases > 0 {
            mechgen::visit_all(&mut v);
        }
        (v.fails, v.seen)
    };
    let (a, (mut fails, mut seen)) = std::thread::scope(|s| {
        let a = s.spawn(|| run(cases / 2));
        let b = run(cases - cases / 2);
        (a.join().unwrap_or_else(|e| std::panic::resume_unwind(e)), b)
    });
    fails.extend(a.0);
    seen.compared += a.1.compared;
    seen.failed += a.1.failed;
    seen.ok_beside_failed += a.1.ok_beside_failed;
    (fails, seen)
}

/// One case of a scene, as [`case`] for a mechanism: W instances (lane 0 at the file's params,
/// the last 40 % off), each input stepped at its own rate, closed forms off in one tick of ten
/// (every lane then ticks in scalar, its Newton predictor on the lane's own rate history); every
/// lane's status, state and outputs are its scalar scene tick's.
fn scene_case<S: Scene<f64>, L: Lanes<Scalar = f64>>(
    isa: Option<Isa>,
    info: &MechanismInfo,
    u: &[f64],
    steps: &[f64],
    ticks: usize,
    seen: &mut Seen,
) -> Result<(), String> {
    let w = L::W;
    let npar = info.params.len();
    let scenes: Vec<S> = (0..w)
        .map(|i| {
            let p = param_values(
                info,
                &u[i * npar..(i + 1) * npar],
                spread(i, w, LAST_SPREAD),
            );
            S::with_params(&p).expect("one value per param")
        })
        .collect();
    let lanes = S::Lanes::<L>::from_fn(|i| {
        let p = param_values(
            info,
            &u[i * npar..(i + 1) * npar],
            spread(i, w, LAST_SPREAD),
        );
        S::with_params(&p).expect("one value per param")
    });
    let (ni, nu) = (info.inputs.len(), info.unknowns.len());
    let step: Vec<f64> = (0..w)
        .map(|i| match info.inputs[0].kind {
            Kind::Angle => steps[i].to_radians(),
            _ => steps[i] * 0.01 * info.inputs[0].start.abs().max(1e-3),
        })
        .collect();
    type LX<S, L> = <<S as Scene<f64>>::Lanes<L> as LaneScene<L>>::X;
    let mut x = LX::<S, L>::default();
    let mut xd = x;
    let mut guess = <S::Lanes<L> as LaneScene<L>>::Q::default();
    for k in 0..ni {
        x.as_mut()[k] = L::splat(info.inputs[k].start);
    }
    xd.as_mut()[0] = L::from_fn(|i| step[i]);
    for k in 0..nu {
        guess.as_mut()[k] = L::splat(info.unknowns[k].start);
    }
    let lane_input = |x: &LX<S, L>, i: usize| {
        let (mut xs, mut xds) = (S::X::zeros(), S::X::zeros());
        for k in 0..ni {
            xs.as_mut()[k] = x.as_ref()[k].lane(i);
            xds.as_mut()[k] = xd.as_ref()[k].lane(i);
        }
        InputMotion::new(xs, xds, S::X::zeros())
    };
    let mut guess1 = S::Q::zeros();
    for k in 0..nu {
        guess1.as_mut()[k] = info.unknowns[k].start;
    }
    let options = |tick: usize| SolveOptions {
        closed_forms: tick % 10 != 9,
        ..SolveOptions::default()
    };
    let input = InputMotion::new(x, xd, Default::default());
    let mut t = lanes.tick_start(&input, &guess, &options(0));
    let mut scalar: Vec<Result<S::Tick, mechgen::SolveError>> = (0..w)
        .map(|i| scenes[i].tick_start(&lane_input(&x, i), &guess1, &options(0)))
        .collect();
    let mut status: Vec<_> = scalar
        .iter()
        .map(|s| s.as_ref().map(|_| ()).map_err(|e| *e))
        .collect();
    for tick in 0..=ticks {
        let opts = options(tick);
        if tick > 0 {
            let a = x.as_mut();
            a[0] = a[0] + L::from_fn(|i| step[i]);
            let input = InputMotion::new(x, xd, Default::default());
            match isa {
                None => lanes.tick(&mut t, &input, &opts),
                Some(isa) => assert!(lanes.tick_on(isa, &mut t, &input, &opts)),
            }
            for i in 0..w {
                let input = lane_input(&x, i);
                status[i] = match &mut scalar[i] {
                    Ok(s) => scenes[i].tick(s, &input, &opts),
                    Err(_) => scenes[i].tick_start(&input, &guess1, &opts).map(|s| {
                        scalar[i] = Ok(s);
                    }),
                };
            }
        }
        let any_failed = status.iter().any(|s| s.is_err());
        let outputs = <S::Lanes<L> as LaneScene<L>>::outputs(&t);
        for i in 0..w {
            let (lane_status, lane) = <S::Lanes<L> as LaneScene<L>>::lane(&t, i).expect("i < W");
            let at = format!("{} lane {i}/{w} tick {tick}", scenes[0].info().name);
            seen.compared += 1;
            if lane_status != status[i] {
                return Err(format!(
                    "{at}: lanes {lane_status:?}, scalar {:?}",
                    status[i]
                ));
            }
            if lane_status.is_err() {
                seen.failed += 1;
            } else if any_failed {
                seen.ok_beside_failed += 1;
            }
            // A failed lane too holds what its scalar tick state holds (if it ever started).
            let Ok(s) = &scalar[i] else { continue };
            if lane != *s {
                return Err(format!("{at}: lanes {lane:?}\nscalar {s:?}"));
            }
            if lane_status.is_err() {
                continue;
            }
            let out = scenes[i].outputs(s);
            let lane_out: Vec<f64> = outputs.as_ref().iter().map(|v| v.lane(i)).collect();
            if lane_out[..] != *out.as_ref() {
                return Err(format!(
                    "{at}: outputs {lane_out:?}, scalar {:?}",
                    out.as_ref()
                ));
            }
        }
    }
    Ok(())
}

/// Every compiled-in scene in `F64x4`, `F64x2` and (every instruction set) `Vf64<8>` lanes over `cases` random cases of `ticks`
/// ticks each (as [`check_lanes`]): the failures and what was seen.
pub fn check_scene_lanes(cases: u32, ticks: usize) -> (Vec<String>, Seen) {
    struct Visit {
        cases: u32,
        ticks: usize,
        fails: Vec<String>,
        seen: Seen,
    }
    impl SceneVisitor<f64> for Visit {
        fn visit<S: Scene<f64> + 'static>(&mut self, scene: &S) {
            let name = scene.info().mechanism;
            let info = mechgen::lookup::<f64>(name).expect("its mechanism").info();
            let npar = info.params.len();
            let mut runner = TestRunner::new(Config {
                cases: self.cases,
                failure_persistence: None,
                ..Config::default()
            });
            let strategy = (
                proptest::collection::vec(-1.0f64..1.0, 8 * npar),
                proptest::collection::vec(0.3f64..4.0, 8),
            );
            let seen = std::cell::RefCell::new(std::mem::take(&mut self.seen));
            let ticks = self.ticks;
            let r = runner.run(&strategy, |(u, steps)| {
                let seen = &mut *seen.borrow_mut();
                scene_case::<S, F64x4>(None, &info, &u, &steps, ticks, seen)
                    .map_err(TestCaseError::fail)?;
                scene_case::<S, F64x2>(None, &info, &u, &steps, ticks, seen)
                    .map_err(TestCaseError::fail)?;
                for isa in Isa::ALL.into_iter().filter(|isa| isa.available()) {
                    scene_case::<S, Vf64<8>>(Some(isa), &info, &u, &steps, ticks, seen)
                        .map_err(TestCaseError::fail)?;
                }
                Ok(())
            });
            self.seen = seen.into_inner();
            if let Err(e) = r {
                self.fails.push(format!("{}: {e}", scene.info().name));
            }
        }
    }
    let mut v = Visit {
        cases,
        ticks,
        fails: Vec::new(),
        seen: Seen::default(),
    };
    mechgen::visit_scenes(&mut v);
    (v.fails, v.seen)
}
