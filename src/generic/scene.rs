//! Scenes on the generic engine: the same `ScenePlan` as the generated scene solvers (kept
//! blocks, order, points), so `mechgen sweep SCENE --engine generic` computes the same subset:
//! Newton or closed forms on the kept blocks only, rates only up to the order, a tape of the
//! scene's points only.

use mechgen_runtime::dynamic::len;
use mechgen_runtime::error::SolveError;
use mechgen_runtime::mechanism::InputMotion;
use mechgen_runtime::scalar::Real;
use mechgen_runtime::scene::{DynScene, DynSceneState, SceneDescription};
use mechgen_runtime::solve::{NewtonReport, SolveOptions};

use super::driver::Plan;
use super::engine::Generic;
use super::scratch::{Scratch, Scratched};
use super::tape::Env;

/// A scene of a [`Generic`] mechanism (`Generic::scene`).
#[derive(Clone, Debug)]
pub struct GenericScene {
    mechanism: Generic,
    index: usize,
}

impl Generic {
    /// The names of the file's scenes on this mechanism.
    pub fn scene_names(&self) -> Vec<&str> {
        self.scenes.iter().map(|s| s.desc.name.as_str()).collect()
    }

    /// Scene `name` of this mechanism, solved by this engine (with its current params).
    pub fn scene(&self, name: &str) -> Option<GenericScene> {
        let index = self.scenes.iter().position(|s| s.desc.name == name)?;
        Some(GenericScene {
            mechanism: self.clone(),
            index,
        })
    }
}

impl GenericScene {
    fn solve<T: Scratched>(
        &self,
        input: InputMotion<&[T]>,
        q: &mut [T],
        out: &mut [T],
        options: &SolveOptions<T>,
    ) -> Result<NewtonReport<T>, SolveError> {
        let InputMotion { x, xd, xdd } = input;
        let (g, s) = (&self.mechanism, &self.mechanism.scenes[self.index]);
        let (ni, nu) = (g.info.inputs.len(), g.info.unknowns.len());
        for (v, n) in [(x, ni), (xd, ni), (xdd, ni)] {
            len(v, n)?;
        }
        len(q, nu)?;
        len(out, s.desc.columns.len())?;
        let order = s.desc.order;
        let plan = Plan {
            blocks: &s.desc.blocks,
            scale: g.length_scale_of(Some(&s.params_read)),
            order,
        };
        T::with_scratch(|ws| {
            let mut rates = std::mem::take(&mut ws.state);
            rates.clear();
            rates.resize(2 * nu, T::zero());
            let (qd, qdd) = rates.split_at_mut(nu);
            let solved = g.drive(plan, input, q, qd, qdd, options, ws);
            if let Ok(report) = solved {
                let Scratch { sc, regs, .. } = ws;
                self.write(x, xd, xdd, q, (qd, qdd), sc, regs, out);
                ws.state = rates;
                return Ok(report);
            }
            ws.state = rates;
            solved
        })
    }

    /// The scene's outputs at a solved state: its unknowns and their rates, then its points.
    #[allow(clippy::too_many_arguments)]
    fn write<T: Real>(
        &self,
        x: &[T],
        xd: &[T],
        xdd: &[T],
        q: &[T],
        (qd, qdd): (&[T], &[T]),
        sc: &[(T, T)],
        regs: &mut Vec<T>,
        out: &mut [T],
    ) {
        let (g, s) = (&self.mechanism, &self.mechanism.scenes[self.index]);
        let order = s.desc.order;
        let rates = [q, qd, qdd];
        let mut at = 0;
        for &u in &s.unknowns {
            for r in rates.iter().take(usize::from(order) + 1) {
                out[at] = r[u];
                at += 1;
            }
        }
        let env = Env {
            x,
            q,
            p: &g.params,
            xd,
            qd,
            xdd,
            qdd,
            sc,
            sx: &[],
        };
        s.points
            .eval_or_nan(&env, regs, &mut out[at..at + s.point_values]);
    }
}

/// Implemented for f64 and f32, as `DynMechanism` is for [`Generic`].
macro_rules! scene_kinematics {
    ($t:ty) => {
        impl DynScene<$t> for GenericScene {
            fn info(&self) -> SceneDescription {
                self.mechanism.scenes[self.index].desc.clone()
            }
            fn solve_in_place(
                &self,
                state: &mut DynSceneState<$t>,
                options: &SolveOptions<$t>,
            ) -> Result<(), SolveError> {
                // Solved on copies: on error the state is unchanged.
                let (mut q, mut out) = (state.q.clone(), state.out.clone());
                state.report = self.solve(state.input_slices(), &mut q, &mut out, options)?;
                state.q.copy_from_slice(&q);
                state.out.copy_from_slice(&out);
                Ok(())
            }
        }
    };
}

scene_kinematics!(f64);
scene_kinematics!(f32);
