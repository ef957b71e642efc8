//! Central finite differences against every generated derivative, for every compiled-in mechanism,
//! at randomized (deterministic) configurations:
//!
//! * J = ∂Φ/∂q and Φx = ∂Φ/∂x against the residual Φ;
//! * J̇ against J along the motion (ẋ, q̇);
//! * γ against −(J̇ q̇ + Φ̇x ẋ) − Φx ẍ, with J̇, Φ̇x and Φx all from finite differences;
//! * point velocities against the point positions along (ẋ, q̇), point accelerations against the
//!   point velocities along (ẋ, q̇, ẍ, q̈);
//! * at assembled configurations, the velocity solve against position solves along ẋ and the
//!   acceleration solve against velocity solves along (ẋ, ẍ).
//!
//! Errors are relative to the largest entry of the compared matrix or vector. Deliberately wrong
//! values (one sign flipped) go through the same comparisons and must be seen as wrong, so the
//! checks cannot pass vacuously.

use std::collections::BTreeMap;

use mechgen::sweep::{Continuation, continue_to};
use mechgen::{DynMechanism, InputMotion, Kind, MechanismInfo, PointMotion, SolveOptions};

/// Configurations per mechanism.
const CONFIGURATIONS: usize = 20;
/// Central-difference step, relative to the coordinates' scale (1 rad, or the length scale).
const STEP: f64 = 1e-6;
/// Largest accepted relative error.
const TOLERANCE: f64 = 1e-6;
/// Smallest relative error a deliberately wrong value must show (largest over the configurations).
const DETECTABLE: f64 = 1e-3;

/// SplitMix64: a tiny deterministic generator.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [−1, 1).
    fn signed(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// One value per coordinate, uniform in ±`amplitude` times the coordinate's scale.
    fn coords(&mut self, scales: &[f64], amplitude: f64) -> Vec<f64> {
        scales
            .iter()
            .map(|s| amplitude * s * self.signed())
            .collect()
    }
}

/// `a + t da`.
fn along(a: &[f64], da: &[f64], t: f64) -> Vec<f64> {
    a.iter().zip(da).map(|(a, d)| a + t * d).collect()
}

fn add(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(a, b)| a + b).collect()
}

fn neg(a: &[f64]) -> Vec<f64> {
    a.iter().map(|v| -v).collect()
}

/// Row-major (rows × cols) matrix times vector.
fn mat_vec(m: &[f64], v: &[f64]) -> Vec<f64> {
    let cols = v.len();
    m.chunks(cols)
        .map(|row| row.iter().zip(v).map(|(a, b)| a * b).sum())
        .collect()
}

/// Central difference of a vector-valued function of one variable at 0.
fn central(h: f64, f: impl Fn(f64) -> Vec<f64>) -> Vec<f64> {
    let (plus, minus) = (f(h), f(-h));
    plus.iter()
        .zip(&minus)
        .map(|(p, m)| (p - m) / (2.0 * h))
        .collect()
}

/// Largest difference relative to the largest magnitude in either array.
fn error(got: &[f64], want: &[f64]) -> f64 {
    assert_eq!(got.len(), want.len());
    let scale = got
        .iter()
        .chain(want)
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    got.iter().zip(want).fold(0.0f64, |m, (g, w)| {
        let d = (g - w).abs() / scale;
        if d.is_nan() { f64::INFINITY } else { m.max(d) }
    })
}

fn velocities(p: &[PointMotion<f64>]) -> Vec<f64> {
    p.iter().flat_map(|m| m.velocity).collect()
}

fn accelerations(p: &[PointMotion<f64>]) -> Vec<f64> {
    p.iter().flat_map(|m| m.acceleration).collect()
}

fn positions(p: &[PointMotion<f64>]) -> Vec<f64> {
    p.iter().flat_map(|m| m.position).collect()
}

/// A compiled-in mechanism behind the object-safe API, with vector-returning helpers.
struct Case {
    k: Box<dyn DynMechanism<f64>>,
    info: MechanismInfo,
    n: usize,
    m: usize,
    np: usize,
    /// Scale of each input and unknown: 1 for an angle, the largest length param for a length.
    x_scale: Vec<f64>,
    q_scale: Vec<f64>,
}

impl Case {
    fn new(name: &str) -> Case {
        let k = mechgen::lookup::<f64>(name).unwrap_or_else(|| panic!("{name}: compiled in"));
        let info = k.info();
        let length = info
            .params
            .iter()
            .filter(|p| p.kind == Kind::Length)
            .fold(0.0f64, |m, p| m.max(p.value.abs()));
        let length = if length > 0.0 { length } else { 1.0 };
        let scale = |kind: Kind| match kind {
            Kind::Angle => 1.0,
            _ => length,
        };
        Case {
            n: info.unknowns.len(),
            m: info.inputs.len(),
            np: info.points.len(),
            x_scale: info.inputs.iter().map(|c| scale(c.kind)).collect(),
            q_scale: info.unknowns.iter().map(|c| scale(c.kind)).collect(),
            k,
            info,
        }
    }

    fn residual(&self, x: &[f64], q: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n];
        self.k.residual(x, q, &mut out).expect("residual");
        out
    }

    fn jacobian(&self, x: &[f64], q: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n * self.n];
        self.k.jacobian(x, q, &mut out).expect("jacobian");
        out
    }

    fn input_jacobian(&self, x: &[f64], q: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n * self.m];
        self.k
            .input_jacobian(x, q, &mut out)
            .expect("input_jacobian");
        out
    }

    fn jacobian_dot(&self, x: &[f64], q: &[f64], xd: &[f64], qd: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n * self.n];
        self.k
            .jacobian_dot(x, q, xd, qd, &mut out)
            .expect("jacobian_dot");
        out
    }

    fn gamma(&self, x: &[f64], q: &[f64], xd: &[f64], qd: &[f64], xdd: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n];
        self.k
            .acceleration_rhs(x, q, xd, qd, xdd, &mut out)
            .expect("acceleration_rhs");
        out
    }

    fn points(&self, state: &State, qdd: &[f64]) -> Vec<PointMotion<f64>> {
        let mut out = vec![PointMotion::default(); self.np];
        self.k
            .points(
                InputMotion::new(&state.x, &state.xd, &state.xdd),
                &state.q,
                &state.qd,
                qdd,
                &mut out,
            )
            .expect("points");
        out
    }

    fn solve_position(&self, x: &[f64], guess: &[f64]) -> Vec<f64> {
        let mut q = guess.to_vec();
        self.k
            .solve_position(x, &mut q, &SolveOptions::default())
            .unwrap_or_else(|e| panic!("solve_position at {x:?}: {e:?}"));
        q
    }

    fn solve_velocity(&self, x: &[f64], q: &[f64], xd: &[f64]) -> Vec<f64> {
        let mut qd = vec![0.0; self.n];
        self.k
            .solve_velocity(x, q, xd, &mut qd)
            .unwrap_or_else(|e| panic!("solve_velocity at {x:?}: {e:?}"));
        qd
    }

    fn solve_acceleration(
        &self,
        x: &[f64],
        q: &[f64],
        xd: &[f64],
        qd: &[f64],
        xdd: &[f64],
    ) -> Vec<f64> {
        let mut qdd = vec![0.0; self.n];
        self.k
            .solve_acceleration(x, q, xd, qd, xdd, &mut qdd)
            .unwrap_or_else(|e| panic!("solve_acceleration at {x:?}: {e:?}"));
        qdd
    }

    /// The step t for differences along a motion with these rates: the coordinates move by about
    /// `STEP` times their scale.
    fn motion_step(&self, xd: &[f64], qd: &[f64]) -> f64 {
        let rate = xd
            .iter()
            .zip(&self.x_scale)
            .chain(qd.iter().zip(&self.q_scale))
            .fold(0.0f64, |m, (v, s)| m.max(v.abs() / s));
        STEP / rate.max(1e-3)
    }

    /// Random configuration near the start one (not assembled), with random rates.
    fn random_state(&self, rng: &mut Rng) -> State {
        let x0: Vec<f64> = self.info.inputs.iter().map(|c| c.start).collect();
        let q0: Vec<f64> = self.info.unknowns.iter().map(|c| c.start).collect();
        State {
            x: add(&x0, &rng.coords(&self.x_scale, 0.5)),
            q: add(&q0, &rng.coords(&self.q_scale, 0.1)),
            xd: rng.coords(&self.x_scale, 2.0),
            qd: rng.coords(&self.q_scale, 2.0),
            xdd: rng.coords(&self.x_scale, 5.0),
        }
    }
}

/// Configuration and rates (q̈ is passed separately where it matters).
struct State {
    x: Vec<f64>,
    q: Vec<f64>,
    xd: Vec<f64>,
    qd: Vec<f64>,
    xdd: Vec<f64>,
}

/// Largest errors seen per check, and per deliberately wrong value.
#[derive(Default)]
struct Record {
    errors: BTreeMap<&'static str, f64>,
    mutants: BTreeMap<&'static str, f64>,
    failures: Vec<String>,
}

impl Record {
    fn check(&mut self, check: &'static str, config: usize, got: &[f64], want: &[f64]) {
        let e = error(got, want);
        let worst = self.errors.entry(check).or_insert(0.0);
        *worst = worst.max(e);
        if e >= TOLERANCE {
            self.failures.push(format!(
                "{check} at configuration {config}: error {e:e}\n  generated {got:?}\n  finite differences {want:?}"
            ));
        }
    }

    fn mutant(&mut self, mutant: &'static str, got: &[f64], want: &[f64]) {
        let e = error(got, want);
        let best = self.mutants.entry(mutant).or_insert(0.0);
        *best = best.max(e);
    }
}

/// The checks at a random (unassembled) configuration.
fn check_configuration(c: &Case, s: &State, qdd: &[f64], config: usize, r: &mut Record) {
    let (n, m) = (c.n, c.m);

    // J = ∂Φ/∂q, column by column.
    let jac = c.jacobian(&s.x, &s.q);
    let mut jac_fd = vec![0.0; n * n];
    for j in 0..n {
        let mut e = vec![0.0; n];
        e[j] = 1.0;
        let col = central(STEP * c.q_scale[j], |t| {
            c.residual(&s.x, &along(&s.q, &e, t))
        });
        for i in 0..n {
            jac_fd[i * n + j] = col[i];
        }
    }
    r.check("J", config, &jac, &jac_fd);
    // One column with its sign flipped.
    let mut wrong = jac.clone();
    for i in 0..n {
        wrong[i * n + config % n] *= -1.0;
    }
    r.mutant("J, one column negated", &wrong, &jac_fd);

    // Φx = ∂Φ/∂x, column by column.
    let phix = c.input_jacobian(&s.x, &s.q);
    let mut phix_fd = vec![0.0; n * m];
    for j in 0..m {
        let mut e = vec![0.0; m];
        e[j] = 1.0;
        let col = central(STEP * c.x_scale[j], |t| {
            c.residual(&along(&s.x, &e, t), &s.q)
        });
        for i in 0..n {
            phix_fd[i * m + j] = col[i];
        }
    }
    r.check("Phi_x", config, &phix, &phix_fd);
    r.mutant("Phi_x negated", &neg(&phix), &phix_fd);

    // J̇ and Φ̇x along (ẋ, q̇).
    let h = c.motion_step(&s.xd, &s.qd);
    let jac_dot_fd = central(h, |t| {
        c.jacobian(&along(&s.x, &s.xd, t), &along(&s.q, &s.qd, t))
    });
    let phix_dot_fd = central(h, |t| {
        c.input_jacobian(&along(&s.x, &s.xd, t), &along(&s.q, &s.qd, t))
    });
    r.check(
        "J_dot",
        config,
        &c.jacobian_dot(&s.x, &s.q, &s.xd, &s.qd),
        &jac_dot_fd,
    );
    // The rate of one unknown with its sign flipped.
    let mut qd_wrong = s.qd.clone();
    qd_wrong[config % n] *= -1.0;
    r.mutant(
        "J_dot, one rate negated",
        &c.jacobian_dot(&s.x, &s.q, &s.xd, &qd_wrong),
        &jac_dot_fd,
    );

    // γ = −(J̇ q̇ + Φ̇x ẋ) − Φx ẍ, every factor from finite differences.
    let quadratic = neg(&add(
        &mat_vec(&jac_dot_fd, &s.qd),
        &mat_vec(&phix_dot_fd, &s.xd),
    ));
    let linear = neg(&mat_vec(&phix_fd, &s.xdd));
    let gamma_fd = add(&quadratic, &linear);
    let gamma = c.gamma(&s.x, &s.q, &s.xd, &s.qd, &s.xdd);
    r.check("gamma", config, &gamma, &gamma_fd);
    // The Φx ẍ term with its sign flipped.
    r.mutant(
        "gamma, +Phi_x xdd",
        &c.gamma(&s.x, &s.q, &s.xd, &s.qd, &neg(&s.xdd)),
        &gamma_fd,
    );
    // The velocity terms with their sign flipped.
    let zero = vec![0.0; m];
    let q_part = c.gamma(&s.x, &s.q, &s.xd, &s.qd, &zero);
    let l_part: Vec<f64> = gamma.iter().zip(&q_part).map(|(g, p)| g - p).collect();
    r.mutant(
        "gamma, +(J_dot qd + Phi_x_dot xd)",
        &add(&neg(&q_part), &l_part),
        &gamma_fd,
    );

    // Point velocities: positions along (ẋ, q̇).
    let pts = c.points(s, qdd);
    let vel_fd = central(h, |t| {
        let moved = State {
            x: along(&s.x, &s.xd, t),
            q: along(&s.q, &s.qd, t),
            xd: s.xd.clone(),
            qd: s.qd.clone(),
            xdd: s.xdd.clone(),
        };
        positions(&c.points(&moved, qdd))
    });
    r.check("point velocity", config, &velocities(&pts), &vel_fd);
    let wrong = s.clone_with_qd(qd_wrong);
    r.mutant(
        "point velocity, one rate negated",
        &velocities(&c.points(&wrong, qdd)),
        &vel_fd,
    );

    // Point accelerations: velocities along (ẋ, q̇, ẍ, q̈).
    let acc_fd = central(h, |t| {
        let moved = State {
            x: along(&s.x, &s.xd, t),
            q: along(&s.q, &s.qd, t),
            xd: along(&s.xd, &s.xdd, t),
            qd: along(&s.qd, qdd, t),
            xdd: s.xdd.clone(),
        };
        velocities(&c.points(&moved, qdd))
    });
    r.check("point acceleration", config, &accelerations(&pts), &acc_fd);
    let mut qdd_wrong = qdd.to_vec();
    qdd_wrong[config % n] *= -1.0;
    r.mutant(
        "point acceleration, one qdd negated",
        &accelerations(&c.points(s, &qdd_wrong)),
        &acc_fd,
    );
    // The velocity terms (centripetal and the like) with their sign flipped.
    let still = State {
        x: s.x.clone(),
        q: s.q.clone(),
        xd: s.xd.clone(),
        qd: s.qd.clone(),
        xdd: vec![0.0; m],
    };
    let q_part = accelerations(&c.points(&still, &vec![0.0; n]));
    let l_part: Vec<f64> = accelerations(&pts)
        .iter()
        .zip(&q_part)
        .map(|(a, p)| a - p)
        .collect();
    r.mutant(
        "point acceleration, velocity terms negated",
        &add(&neg(&q_part), &l_part),
        &acc_fd,
    );
}

impl State {
    fn clone_with_qd(&self, qd: Vec<f64>) -> State {
        State {
            x: self.x.clone(),
            q: self.q.clone(),
            xd: self.xd.clone(),
            qd,
            xdd: self.xdd.clone(),
        }
    }
}

/// The velocity and acceleration solves at an assembled configuration, against position and
/// velocity solves along the motion.
fn check_solves(c: &Case, rng: &mut Rng, config: usize, r: &mut Record) {
    // Assemble from the start configuration, then follow the branch to a random input.
    let mut x: Vec<f64> = c.info.inputs.iter().map(|i| i.start).collect();
    let mut q = c.solve_position(
        &x,
        &c.info.unknowns.iter().map(|u| u.start).collect::<Vec<_>>(),
    );
    let target = add(&x, &rng.coords(&c.x_scale, 0.5));
    for (i, kind) in c.info.inputs.iter().map(|i| i.kind).enumerate() {
        continue_to(
            c.k.as_ref(),
            &mut x,
            &mut q,
            i,
            target[i],
            &Continuation::for_input(kind, c.x_scale[i]),
        )
        .unwrap_or_else(|e| panic!("continuation to {target:?}: {e:?}"));
    }
    let xd = rng.coords(&c.x_scale, 2.0);
    let xdd = rng.coords(&c.x_scale, 5.0);
    let qd = c.solve_velocity(&x, &q, &xd);
    let qdd = c.solve_acceleration(&x, &q, &xd, &qd, &xdd);

    // q̇ against positions solved along ẋ (from the tangent prediction, on the same branch).
    let h = c.motion_step(&xd, &qd);
    let solved_at = |t: f64| c.solve_position(&along(&x, &xd, t), &along(&q, &qd, t));
    let qd_fd = central(h, solved_at);
    r.check("solve_velocity", config, &qd, &qd_fd);

    // q̈ against velocities solved along (ẋ, ẍ), at the positions solved along ẋ.
    let qdd_fd = central(h, |t| {
        c.solve_velocity(&along(&x, &xd, t), &solved_at(t), &along(&xd, &xdd, t))
    });
    r.check("solve_acceleration", config, &qdd, &qdd_fd);
    r.mutant(
        "solve_acceleration with -xdd",
        &c.solve_acceleration(&x, &q, &xd, &qd, &neg(&xdd)),
        &qdd_fd,
    );
}

#[test]
fn generated_derivatives_match_finite_differences() {
    let mut failures = Vec::new();
    let mut undetected = Vec::new();
    for (index, name) in mechgen::MECHANISMS.iter().enumerate() {
        let c = Case::new(name);
        let mut rng = Rng(0x6d65_6368_6765_6e00 ^ index as u64);
        let mut r = Record::default();
        for config in 0..CONFIGURATIONS {
            let s = c.random_state(&mut rng);
            let qdd = rng.coords(&c.q_scale, 5.0);
            check_configuration(&c, &s, &qdd, config, &mut r);
            check_solves(&c, &mut rng, config, &mut r);
        }
        eprintln!("{name}: largest relative error over {CONFIGURATIONS} configurations");
        for (check, e) in &r.errors {
            eprintln!("  {check:<20} {e:.2e}");
        }
        eprintln!("  deliberately wrong values (must exceed {DETECTABLE:e}):");
        for (mutant, e) in &r.mutants {
            eprintln!("  {mutant:<42} {e:.2e}");
            if *e <= DETECTABLE {
                undetected.push(format!("{name}: {mutant} not detected (error {e:e})"));
            }
        }
        assert_eq!(
            r.errors.len(),
            8,
            "{name}: every check ran: {:?}",
            r.errors.keys()
        );
        failures.extend(r.failures.into_iter().map(|f| format!("{name}: {f}")));
    }
    assert!(
        failures.is_empty(),
        "{} derivative checks failed (tolerance {TOLERANCE:e}):\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(undetected.is_empty(), "{}", undetected.join("\n"));
}
