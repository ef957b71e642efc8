//! Generic engine, the block driver: the one place a run-time solve runs a plan (the whole
//! mechanism, or a scene's kept blocks up to its order). Positions block by block (a closed-form
//! block by the runtime's kernel, any other by the runtime's Newton), one refinement step per
//! block near a dead point, then per block one factorization of the Jacobian for both rates. The
//! errors are the runtime's (`factor_in_place`, `solve_factored`), as generated code's are.

use mechgen_runtime::error::{Quantity, SolveError, Stage};
use mechgen_runtime::mechanism::InputMotion;
use mechgen_runtime::nalgebra::{DMatrix, DVector};
use mechgen_runtime::scalar::Real;
use mechgen_runtime::sensitivity::{block_sensitivities, point_sensitivities};
use mechgen_runtime::solve::{NewtonReport, SolveOptions, check_finite};
use mechgen_runtime::trig::TrigSlices;
use mechgen_runtime::twofold::{REFINE_BELOW, refinement_in_place};

use super::closed;
use super::engine::Generic;
use super::factors::{Factors, fill};
use super::scratch::{Scratch, Sized, sized};
use super::tape::Env;

/// The buffers a block's Newton solve works in: a tape's registers, its outputs, the matrices
/// by block size.
pub(super) type BlockWork<'a, T> = (
    &'a mut Vec<T>,
    &'a mut Vec<T>,
    &'a mut Vec<Option<Sized<T>>>,
);

/// Which rates a run solves after (or without) the positions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Rates {
    /// Velocities only.
    Velocity,
    /// Accelerations only, the velocities given.
    Acceleration,
    /// Both, each block's Jacobian factored once for the two.
    Both,
}

/// The part of a mechanism one run solves: `blocks` in solve order, tolerances relative to the
/// length `scale`, rates up to `order` (0 positions, 1 velocities, 2 accelerations).
#[derive(Clone, Copy, Debug)]
pub(super) struct Plan<'a> {
    pub blocks: &'a [usize],
    pub scale: f64,
    pub order: u8,
}

impl Generic {
    /// Every block up to accelerations, tolerances relative to the mechanism's largest length
    /// param.
    pub(super) fn whole(&self) -> Plan<'_> {
        Plan {
            blocks: &self.order,
            scale: self.length_scale(),
            order: 2,
        }
    }

    /// One whole solve of `plan`: every argument checked (params, inputs, guess, input rates, in
    /// this order, as generated solvers check them), positions from the guess in `q` (written only
    /// on success), then velocities into `qd` (`order` ≥ 1) and accelerations into `qdd` (`order` 2).
    /// Returns the report; the solved angles' sines and cosines are left in `ws.sc`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn drive<T: Real>(
        &self,
        plan: Plan<'_>,
        input: InputMotion<&[T]>,
        q: &mut [T],
        qd: &mut [T],
        qdd: &mut [T],
        options: &SolveOptions<T>,
        ws: &mut Scratch<T>,
    ) -> Result<NewtonReport<T>, SolveError> {
        let InputMotion { x, xd, xdd } = input;
        check_finite(Quantity::Param, &self.params)?;
        check_finite(Quantity::Input, x)?;
        check_finite(Quantity::Guess, q)?;
        check_finite(Quantity::InputRate, xd)?;
        check_finite(Quantity::InputAcceleration, xdd)?;
        let report = self.positions(plan, x, q, options, ws)?;
        let rates = match plan.order {
            0 => return Ok(report),
            1 => Rates::Velocity,
            _ => Rates::Both,
        };
        let sc = std::mem::take(&mut ws.sc);
        let env = Env {
            xd,
            xdd,
            sc: &sc,
            ..Env::position(x, q, &self.params)
        };
        let solved = self.rates(plan.blocks, rates, env, qd, qdd, ws);
        ws.sc = sc;
        solved.map(|()| report)
    }

    /// The positions of `plan`'s blocks in order, from the guess in `q`; `q` and the angles'
    /// sines and cosines `ws.sc` are written only on success (as the generated solvers do).
    pub(super) fn positions<T: Real>(
        &self,
        plan: Plan<'_>,
        x: &[T],
        q: &mut [T],
        options: &SolveOptions<T>,
        ws: &mut Scratch<T>,
    ) -> Result<NewtonReport<T>, SolveError> {
        check_finite(Quantity::Param, &self.params)?;
        check_finite(Quantity::Input, x)?;
        check_finite(Quantity::Guess, q)?;
        ws.trial.clear();
        ws.trial.extend_from_slice(q);
        ws.trial_sc.clear();
        ws.trial_sc.resize(q.len(), (T::zero(), T::one()));
        TrigSlices {
            q: &mut ws.trial,
            sc: &mut ws.trial_sc,
            angle: &self.angle,
        }
        .init();
        let report = self.positions_from(plan, x, &[], options, ws)?;
        q.copy_from_slice(&ws.trial);
        Ok(report)
    }

    /// The positions of `plan`'s blocks in order from the guess in `ws.trial` with its sines and
    /// cosines in `ws.trial_sc` (a whole solve's, or a tick's prediction); the inputs' sines and
    /// cosines `sx` (a tick's; empty: computed). On success `ws.trial` holds the unknowns and
    /// `ws.sc` their sines and cosines.
    pub(super) fn positions_from<T: Real>(
        &self,
        plan: Plan<'_>,
        x: &[T],
        sx: &[(T, T)],
        options: &SolveOptions<T>,
        ws: &mut Scratch<T>,
    ) -> Result<NewtonReport<T>, SolveError> {
        let scale = T::lit(plan.scale);
        let mut report = NewtonReport::new();
        let Scratch {
            regs,
            out,
            trial,
            trial_sc,
            sc,
            by_size,
            ..
        } = ws;
        let mut st = TrigSlices {
            q: trial,
            sc: trial_sc,
            angle: &self.angle,
        };
        for &bi in plan.blocks {
            let b = &self.blocks[bi];
            if let Some(c) = b.closed.as_ref().filter(|_| options.closed_forms) {
                out.resize(c.form.roots().len(), T::zero());
                c.roots.eval(&self.env(x, sx, &st), regs, out)?;
                let tolerance = options.newton.tolerance;
                closed::solve(bi, &c.form, out, &mut st, scale, tolerance, &mut report)?;
                continue;
            }
            let ws = (&mut *regs, &mut *out, &mut *by_size);
            self.newton_block(bi, (x, sx), &mut st, options, scale, &mut report, ws)?;
        }
        self.refine_if(plan.blocks, x, sx, &mut st, &report);
        sc.clear();
        sc.extend_from_slice(st.sc);
        Ok(report)
    }

    /// Block `bi`'s positions by the runtime's Newton from the guess in `st`, on the block's
    /// position tape (the inputs `x` with their kept sines and cosines `sx`).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn newton_block<T: Real>(
        &self,
        bi: usize,
        (x, sx): (&[T], &[(T, T)]),
        st: &mut TrigSlices<'_, T>,
        options: &SolveOptions<T>,
        scale: T,
        report: &mut NewtonReport<T>,
        (regs, out, by_size): BlockWork<'_, T>,
    ) -> Result<(), SolveError> {
        let b = &self.blocks[bi];
        let k = b.unknowns.len();
        out.resize(k + k * k, T::zero());
        mechgen_runtime::solve::newton_in_place(
            bi,
            st,
            &b.unknowns,
            &b.length,
            scale,
            &options.newton,
            report,
            &mut sized(by_size, k).newton,
            |st, r, j| {
                b.position.eval_or_nan(&self.env(x, sx, st), regs, out);
                fill(out, k, r, j);
            },
        )
    }

    /// Near a dead point (the report's pivot ratio below `REFINE_BELOW`): the refinement of
    /// `which` blocks.
    pub(super) fn refine_if<T: Real>(
        &self,
        which: &[usize],
        x: &[T],
        sx: &[(T, T)],
        st: &mut TrigSlices<'_, T>,
        report: &NewtonReport<T>,
    ) {
        if report.pivot_ratio < T::lit(REFINE_BELOW) {
            self.refine(which, x, sx, st);
        }
    }

    /// The positions `(x, st)` with the kept sines and cosines.
    fn env<'a, T: Real>(
        &'a self,
        x: &'a [T],
        sx: &'a [(T, T)],
        st: &'a TrigSlices<'_, T>,
    ) -> Env<'a, T> {
        Env {
            sc: st.sc,
            sx,
            ..Env::position(x, st.q, &self.params)
        }
    }

    /// Near a dead point: per block in order, one Newton step with the residual in double-word
    /// arithmetic (the runtime's `refinement_in_place`, as generated code's `refine_block`).
    fn refine<T: Real>(&self, which: &[usize], x: &[T], sx: &[(T, T)], st: &mut TrigSlices<'_, T>) {
        let x64: Vec<f64> = x.iter().map(|v| v.to_f64()).collect();
        let mut regs = Vec::new();
        for b in which.iter().map(|&bi| &self.blocks[bi]) {
            let k = b.unknowns.len();
            let q64: Vec<f64> = st.q.iter().map(|v| v.to_f64()).collect();
            let exact = b.residual.eval_twofold(&x64, &q64, &self.params);
            let mut out = vec![T::zero(); k + k * k];
            b.position
                .eval_or_nan(&self.env(x, sx, st), &mut regs, &mut out);
            let (mut r, mut jac, mut scale) =
                (DVector::zeros(k), DMatrix::zeros(k, k), DVector::zeros(k));
            fill(&out, k, &mut r, &mut jac);
            for (ri, e) in r.iter_mut().zip(&exact) {
                *ri = T::lit(e.value());
            }
            if refinement_in_place(&mut jac, &mut r, &mut scale, |k| st.q[b.unknowns[k]]) {
                for (&u, d) in b.unknowns.iter().zip(r.iter()) {
                    st.set(u, st.q[u] - *d);
                }
            }
        }
    }

    /// The rates `which` asks for, block by block at the solved position of `env`: each block's
    /// Jacobian factored once, then its velocity (into `qd`) and its acceleration (into `qdd`,
    /// from the velocities in `qd`). What is solved is zeroed first outside the blocks.
    pub(super) fn rates<T: Real>(
        &self,
        which: &[usize],
        rates: Rates,
        env: Env<'_, T>,
        qd: &mut [T],
        qdd: &mut [T],
        ws: &mut Scratch<T>,
    ) -> Result<(), SolveError> {
        let velocity = rates != Rates::Acceleration;
        let acceleration = rates != Rates::Velocity;
        if velocity {
            qd.iter_mut().for_each(|v| *v = T::zero());
        }
        if acceleration {
            qdd.iter_mut().for_each(|v| *v = T::zero());
        }
        // A failed factorization belongs to the first rate solved, as in generated code.
        let stage = if velocity {
            Stage::Velocity
        } else {
            Stage::Acceleration
        };
        let Scratch {
            regs, out, by_size, ..
        } = ws;
        for &bi in which {
            let b = &self.blocks[bi];
            let k = b.unknowns.len();
            out.resize(k + k * k, T::zero());
            // Earlier blocks' velocities are on the right-hand side.
            let env_v = Env { qd: &*qd, ..env };
            b.velocity.eval(&env_v, regs, out)?;
            let mut lu = Factors::of_block(bi, stage, out, k, by_size)?;
            if velocity {
                lu.solve_into(bi, Stage::Velocity, &mut out[..k])?;
                for (&u, v) in b.unknowns.iter().zip(&out[..k]) {
                    qd[u] = *v;
                }
            }
            if acceleration {
                let env = Env {
                    qd: &*qd,
                    qdd: &*qdd,
                    ..env
                };
                b.acceleration.eval(&env, regs, &mut out[..k])?;
                lu.solve_into(bi, Stage::Acceleration, &mut out[..k])?;
                for (&u, v) in b.unknowns.iter().zip(&out[..k]) {
                    qdd[u] = *v;
                }
            }
        }
        Ok(())
    }
}

impl Generic {
    /// The design derivatives at a solved position, row-major: dq/dp into `s` (unknowns ×
    /// params), dP/dp into `dp` (2·points × params); each block's Jacobian factored as for its
    /// rates, then the runtime's `block_sensitivities` and `point_sensitivities`, as generated
    /// code runs them.
    pub(super) fn sensitivities<T: Real>(
        &self,
        x: &[T],
        q: &[T],
        s: &mut [T],
        dp: &mut [T],
    ) -> Result<(), SolveError> {
        let (nu, npar) = (q.len(), self.params.len());
        let env = Env::position(x, q, &self.params);
        let mut regs = Vec::new();
        let mut jac = vec![T::zero(); nu * nu];
        self.jacobian.eval(&env, &mut regs, &mut jac)?;
        let mut all = vec![T::zero(); self.sensitivity.outputs()];
        self.sensitivity.eval(&env, &mut regs, &mut all)?;
        let (phi_p, points) = all.split_at(nu * npar);
        let (pq, pp) = points.split_at(points.len() / (nu + npar).max(1) * nu);
        s.iter_mut().for_each(|v| *v = T::zero());
        for &bi in &self.order {
            let b = &self.blocks[bi];
            let k = b.unknowns.len();
            let mut jb = DMatrix::from_fn(k, k, |i, j| jac[b.equations[i] * nu + b.unknowns[j]]);
            let (mut scale, mut swaps) = (DVector::zeros(k), vec![0; k]);
            let mut v = DVector::zeros(k);
            let lu = Factors::new(
                bi,
                Stage::Sensitivity,
                &mut jb,
                &mut scale,
                &mut swaps,
                &mut v,
            )?;
            let (j, f) = (|e, c| jac[e * nu + c], |e, p| phi_p[e * npar + p]);
            let mut rhs = vec![T::zero(); k];
            block_sensitivities(bi, &b.equations, &b.unknowns, &lu, j, f, npar, s, &mut rhs)?;
        }
        let (pq, pp) = (|r, c| pq[r * nu + c], |r, p| pp[r * npar + p]);
        point_sensitivities(pq, pp, s, nu, npar, dp);
        Ok(())
    }
}
