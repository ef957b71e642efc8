//! The generic runtime engine (feature `runtime`): loads a mechanism file at run time and solves
//! it by interpreting the same derivatives the generator emits ([`tape`]), with the same block
//! Newton and error values (`engine.rs`). It is the `--file` path of the CLI and the honest
//! comparison for the generated solvers. [`DynMechanism`] is implemented here, and the drawings'
//! structure ([`Linkage`], [`Sketch`]) is read from the loaded model.

#[cfg(feature = "jit")]
mod backend;
mod closed;
mod driver;
mod engine;
mod factors;
#[cfg(feature = "jit")]
pub mod jit;
mod linkage;
mod op;
mod program;
mod scene;
mod scene_tapes;
mod scratch;
mod sketch;
mod stages;
pub mod tape;
mod terms;
mod tick;
mod walk;

pub use engine::{
    Generic, LoadError, load, load_file, load_with_start_warnings, load_with_warnings,
    start_warning,
};
pub use linkage::Linkage;
pub use scene::GenericScene;
pub use sketch::{Sketch, SliderAt};

use driver::Rates;
use mechgen_runtime::InputMotion;
use mechgen_runtime::error::{Quantity, SolveError};
use mechgen_runtime::scalar::Real;
use mechgen_runtime::solve::{NewtonReport, SolveOptions, check_finite};
use mechgen_runtime::{
    BodyMass, BodyMotion, DynMechanism, DynState, MechanismInfo, PointMotion, dynamic::len,
};
use scratch::{Scratch, Scratched};
use tape::Env;

/// One chain of the mechanism drawing at a configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct ChainPosition {
    /// Joint positions, the origin first.
    pub vertices: Vec<[f64; 2]>,
    /// How many leading segments are ground offsets (not links).
    pub ground_segments: usize,
}

impl Generic {
    /// `NonFinite` for the first non-finite value among the params and `[x, q, xd, qd, xdd]` (or
    /// a prefix), in that order, as the generated velocity and acceleration solves check.
    fn finite<T: Real>(&self, slices: &[&[T]]) -> Result<(), SolveError> {
        check_finite(Quantity::Param, &self.params)?;
        let kinds = [
            Quantity::Input,
            Quantity::Position,
            Quantity::InputRate,
            Quantity::Rate,
            Quantity::InputAcceleration,
        ];
        for (s, k) in slices.iter().zip(kinds) {
            check_finite(k, s)?;
        }
        Ok(())
    }

    /// Checks the lengths of `[x, q, xd, qd, xdd, qdd]` (or a prefix): inputs, then unknowns.
    fn lengths<T>(&self, slices: &[&[T]]) -> Result<(), SolveError> {
        let (ni, nu) = (self.info.inputs.len(), self.info.unknowns.len());
        for (i, s) in slices.iter().enumerate() {
            len(s, if i % 2 == 0 { ni } else { nu })?;
        }
        Ok(())
    }

    /// Every point's position, velocity and acceleration at `env` (`regs` and `v` workspace).
    fn eval_points<T: Real>(
        &self,
        env: Env<'_, T>,
        out: &mut [PointMotion<T>],
        regs: &mut Vec<T>,
        v: &mut Vec<T>,
    ) -> Result<(), SolveError> {
        v.resize(6 * self.info.points.len(), T::zero());
        self.points.eval(&env, regs, v)?;
        Self::set_points(out, v);
        Ok(())
    }

    /// The points' motion from their values, six per point (x, y, vx, vy, ax, ay).
    fn set_points<T: Real>(out: &mut [PointMotion<T>], v: &[T]) {
        for (o, c) in out.iter_mut().zip(v.chunks_exact(6)) {
            *o = PointMotion {
                position: [c[0], c[1]],
                velocity: [c[2], c[3]],
                acceleration: [c[4], c[5]],
            };
        }
    }

    /// `tape` at a solved state (`width` outputs per item of `out`, each made by `make`):
    /// the points' or the bodies' motion.
    fn eval_motion<T: Real + Scratched, O>(
        &self,
        input: InputMotion<&[T]>,
        [q, qd, qdd]: [&[T]; 3],
        tape: &tape::Tape,
        width: usize,
        out: &mut [O],
        make: impl Fn(&[T]) -> O,
    ) -> Result<(), SolveError> {
        let InputMotion { x, xd, xdd } = input;
        self.lengths(&[x, q, xd, qd, xdd, qdd])?;
        let env = Env {
            xd,
            qd,
            xdd,
            qdd,
            ..Env::position(x, q, &self.params)
        };
        T::with_scratch(|ws| {
            let Scratch {
                regs, points: v, ..
            } = ws;
            v.resize(width * out.len(), T::zero());
            tape.eval(&env, regs, v)?;
            for (o, c) in out.iter_mut().zip(v.chunks_exact(width)) {
                *o = make(c);
            }
            Ok(())
        })
    }

    /// The drawing chains (links and ground offsets of every loop) at `(x, q)`.
    pub fn chains(&self, x: &[f64], q: &[f64]) -> Result<Vec<ChainPosition>, SolveError> {
        self.lengths(&[x, q])?;
        let mut out = vec![0.0; self.chains.outputs()];
        self.chains.eval(
            &Env::position(x, q, &self.params),
            &mut Vec::new(),
            &mut out,
        )?;
        let mut at = 0;
        Ok(self
            .chain_shape
            .iter()
            .map(|&(n, ground_segments)| {
                let vertices = (0..n)
                    .map(|i| [out[at + 2 * i], out[at + 2 * i + 1]])
                    .collect();
                at += 2 * n;
                ChainPosition {
                    vertices,
                    ground_segments,
                }
            })
            .collect())
    }

    /// The mechanism drawn at `(x, q)` from its structure: bodies, ground pivots and sliders
    /// (see [`Linkage`]).
    pub fn sketch(&self, x: &[f64], q: &[f64]) -> Result<Sketch, SolveError> {
        self.lengths(&[x, q])?;
        Ok(self.linkage.sketch(x, q, &self.params))
    }

    /// The drawing structure.
    pub fn linkage(&self) -> &Linkage {
        &self.linkage
    }

    /// The bodies tape's outputs of one body (centre x, y, angle; their velocities; their
    /// accelerations) as its motion: the one place that layout is read.
    pub(super) fn body_motion<T: Real>(c: &[T]) -> BodyMotion<T> {
        BodyMotion {
            com: PointMotion {
                position: [c[0], c[1]],
                velocity: [c[3], c[4]],
                acceleration: [c[6], c[7]],
            },
            angle: [c[2], c[5], c[8]],
        }
    }

    fn eval_into<T: Real>(
        &self,
        tape: &tape::Tape,
        env: Env<'_, T>,
        out: &mut [T],
    ) -> Result<(), SolveError> {
        len(out, tape.outputs())?;
        tape.eval(&env, &mut Vec::new(), out)
    }
}

/// Implemented for f64 and f32 (a blanket `impl<T: Real>` would overlap the one for generated
/// mechanisms).
macro_rules! kinematics {
    ($t:ty) => {
        impl DynMechanism<$t> for Generic {
            fn ticker(&self) -> Box<dyn mechgen_runtime::DynTick<$t> + '_> {
                Box::new(tick::GenericTick::<$t>::new(self))
            }
            fn info(&self) -> MechanismInfo {
                self.info.clone()
            }
            fn info_ref(&self) -> std::borrow::Cow<'_, MechanismInfo> {
                std::borrow::Cow::Borrowed(&self.info)
            }

            fn residual(&self, x: &[$t], q: &[$t], out: &mut [$t]) -> Result<(), SolveError> {
                self.lengths(&[x, q])?;
                self.eval_into(&self.residual, Env::position(x, q, &self.params), out)
            }

            fn jacobian(&self, x: &[$t], q: &[$t], out: &mut [$t]) -> Result<(), SolveError> {
                self.lengths(&[x, q])?;
                self.eval_into(&self.jacobian, Env::position(x, q, &self.params), out)
            }

            fn sensitivities(
                &self,
                x: &[$t],
                q: &[$t],
                unknowns: &mut [$t],
                points: &mut [$t],
            ) -> Result<(), SolveError> {
                self.lengths(&[x, q])?;
                self.finite(&[x, q])?;
                let npar = self.params.len();
                len(unknowns, self.info.unknowns.len() * npar)?;
                len(points, 2 * self.info.points.len() * npar)?;
                Generic::sensitivities(self, x, q, unknowns, points)
            }

            fn input_jacobian(&self, x: &[$t], q: &[$t], out: &mut [$t]) -> Result<(), SolveError> {
                self.lengths(&[x, q])?;
                self.eval_into(&self.input_jacobian, Env::position(x, q, &self.params), out)
            }

            fn jacobian_dot(
                &self,
                x: &[$t],
                q: &[$t],
                xd: &[$t],
                qd: &[$t],
                out: &mut [$t],
            ) -> Result<(), SolveError> {
                self.lengths(&[x, q, xd, qd])?;
                let env = Env {
                    xd,
                    qd,
                    ..Env::position(x, q, &self.params)
                };
                self.eval_into(&self.jacobian_dot, env, out)
            }

            fn acceleration_rhs(
                &self,
                x: &[$t],
                q: &[$t],
                xd: &[$t],
                qd: &[$t],
                xdd: &[$t],
                out: &mut [$t],
            ) -> Result<(), SolveError> {
                self.lengths(&[x, q, xd, qd, xdd])?;
                let env = Env {
                    xd,
                    qd,
                    xdd,
                    ..Env::position(x, q, &self.params)
                };
                self.eval_into(&self.acceleration_rhs, env, out)
            }

            fn solve_position(
                &self,
                x: &[$t],
                q: &mut [$t],
                options: &SolveOptions<$t>,
            ) -> Result<NewtonReport<$t>, SolveError> {
                self.lengths(&[x, q])?;
                <$t>::with_scratch(|ws| self.positions(self.whole(), x, q, options, ws))
            }

            fn solve_velocity(
                &self,
                x: &[$t],
                q: &[$t],
                xd: &[$t],
                qd: &mut [$t],
            ) -> Result<(), SolveError> {
                self.lengths(&[x, q, xd, qd])?;
                self.finite(&[x, q, xd])?;
                let env = Env {
                    xd,
                    ..Env::position(x, q, &self.params)
                };
                <$t>::with_scratch(|ws| {
                    self.rates(&self.order, Rates::Velocity, env, qd, &mut [], ws)
                })
            }

            fn solve_acceleration(
                &self,
                x: &[$t],
                q: &[$t],
                xd: &[$t],
                qd: &[$t],
                xdd: &[$t],
                qdd: &mut [$t],
            ) -> Result<(), SolveError> {
                self.lengths(&[x, q, xd, qd, xdd, qdd])?;
                self.finite(&[x, q, xd, qd, xdd])?;
                let env = Env {
                    xd,
                    xdd,
                    ..Env::position(x, q, &self.params)
                };
                <$t>::with_scratch(|ws| {
                    // The rates' stage reads q̇ from a buffer it may write: the scratch's (no
                    // allocation once grown).
                    let mut buf = std::mem::take(&mut ws.state);
                    buf.clear();
                    buf.extend_from_slice(qd);
                    let r = self.rates(&self.order, Rates::Acceleration, env, &mut buf, qdd, ws);
                    ws.state = buf;
                    r
                })
            }

            fn solve_in_place(
                &self,
                state: &mut DynState<$t>,
                options: &SolveOptions<$t>,
            ) -> Result<(), SolveError> {
                let DynState {
                    x,
                    xd,
                    xdd,
                    q,
                    qd,
                    qdd,
                    points,
                    report,
                } = state;
                self.lengths(&[x, q, xd, qd, xdd, qdd])?;
                len(points, self.info.points.len())?;
                <$t>::with_scratch(|ws| {
                    // Solved into the workspace: on error the state is unchanged.
                    let nu = q.len();
                    let mut solved = std::mem::take(&mut ws.state);
                    solved.clear();
                    solved.extend_from_slice(q);
                    solved.extend_from_slice(qd);
                    solved.extend_from_slice(qdd);
                    let (q_new, rates) = solved.split_at_mut(nu);
                    let (qd_new, qdd_new) = rates.split_at_mut(nu);
                    let input = InputMotion::new(&x[..], &xd[..], &xdd[..]);
                    // The mechanism's program from the guess, where it has one (the arguments
                    // checked first, in the order the driver checks them).
                    if let Some(run) =
                        self.whole_motion(input, q_new, options, ws, [&mut *qd_new, &mut *qdd_new])
                    {
                        if let Ok(r) = run {
                            q.copy_from_slice(&ws.trial);
                            qd.copy_from_slice(qd_new);
                            qdd.copy_from_slice(qdd_new);
                            Self::set_points(points, &ws.points);
                            *report = r;
                        }
                        ws.state = solved;
                        return run.map(|_| ());
                    }
                    let run = self.drive(self.whole(), input, q_new, qd_new, qdd_new, options, ws);
                    let run = run.and_then(|r| {
                        let Scratch {
                            sc,
                            regs,
                            points: v,
                            ..
                        } = ws;
                        let env = Env {
                            xd,
                            qd: qd_new,
                            xdd,
                            qdd: qdd_new,
                            sc,
                            ..Env::position(x, q_new, &self.params)
                        };
                        self.eval_points(env, points, regs, v).map(|()| r)
                    });
                    if let Ok(r) = run {
                        q.copy_from_slice(q_new);
                        qd.copy_from_slice(qd_new);
                        qdd.copy_from_slice(qdd_new);
                        *report = r;
                    }
                    ws.state = solved;
                    run.map(|_| ())
                })
            }

            fn points(
                &self,
                input: InputMotion<&[$t]>,
                q: &[$t],
                qd: &[$t],
                qdd: &[$t],
                out: &mut [PointMotion<$t>],
            ) -> Result<(), SolveError> {
                len(out, self.info.points.len())?;
                self.eval_motion(input, [q, qd, qdd], &self.points, 6, out, |c| PointMotion {
                    position: [c[0], c[1]],
                    velocity: [c[2], c[3]],
                    acceleration: [c[4], c[5]],
                })
            }

            fn bodies(
                &self,
                input: InputMotion<&[$t]>,
                q: &[$t],
                qd: &[$t],
                qdd: &[$t],
                out: &mut [BodyMotion<$t>],
            ) -> Result<(), SolveError> {
                len(out, self.info.bodies.len())?;
                self.eval_motion(input, [q, qd, qdd], &self.bodies, 9, out, Self::body_motion)
            }

            fn mass_properties(&self, out: &mut [BodyMass<$t>]) -> Result<[$t; 2], SolveError> {
                len(out, self.info.bodies.len())?;
                let env = Env::position(&[], &[], &self.params);
                let gravity = <$t>::with_scratch(|ws| {
                    let Scratch {
                        regs, points: v, ..
                    } = ws;
                    v.resize(self.masses.outputs(), 0.0);
                    self.masses.eval(&env, regs, v)?;
                    let (gravity, masses) = if self.gravity {
                        ([v[0], v[1]], &v[2..])
                    } else {
                        ([0.0; 2], &v[..])
                    };
                    for (o, c) in out.iter_mut().zip(masses.chunks_exact(2)) {
                        *o = BodyMass {
                            mass: c[0],
                            inertia: c[1],
                        };
                    }
                    Ok(gravity)
                })?;
                Ok(gravity)
            }
        }
    };
}

kinematics!(f64);
kinematics!(f32);
