//! Branch identification, every assembly configuration at one input: block by block, a
//! closed-form block multiplies the partial configurations by its modes (the runtime's `*_modes`
//! kernels), a torn block by the roots of its scalar equation in the cut, one function per
//! combination of its sub-blocks' modes (`roots::roots_and_extrema`), the other unknowns in closed form.
//! On request, each block's margins (how far it is from gaining or losing a pair of
//! configurations) for the grid's search of hidden changes of the count.

use mechgen_codegen::ClosedForm;
use mechgen_runtime::closed_form::{
    Modes, angle1_modes, length1_modes, linear2_modes, rpr_modes, rrp_modes, rrr_modes,
};
use mechgen_runtime::error::SolveError;

use super::plan::{Form, Last, Step, Torn, slots};
use super::roots::roots_and_extrema;
use crate::generic::tape::{Env, Tape};

/// A mechanism's configuration enumerator.
#[derive(Clone, Debug)]
pub struct Solver {
    pub(super) steps: Vec<Step>,
    pub(super) params: Vec<f64>,
    pub(super) unknowns: usize,
}

thread_local! {
    /// Registers of the tapes (reused: the cut's function is evaluated many times per input).
    static REGS: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The roots of `tape` at `(x, q)` into `out` (at most 6 are read).
fn eval_into(tape: &Tape, x: &[f64], q: &[f64], p: &[f64], out: &mut [f64; 6]) {
    REGS.with_borrow_mut(|regs| tape.eval(&Env::position(x, q, p), regs, out));
}

fn eval(tape: &Tape, x: &[f64], q: &[f64], p: &[f64]) -> Vec<f64> {
    let mut out = [0.0; 6];
    eval_into(tape, x, q, p, &mut out);
    out[..tape.outputs().min(6)].to_vec()
}

/// All modes of a closed form whose roots are `v`.
fn modes(block: usize, form: &ClosedForm, v: &[f64]) -> Result<Modes<f64>, SolveError> {
    match form {
        ClosedForm::Rrr(_) => rrr_modes(block, [v[0], v[1]], (v[2], v[3]), (v[4], v[5])),
        ClosedForm::Rrp { .. } => rrp_modes(block, [v[0], v[1]], (v[2], v[3]), [v[4], v[5]]),
        ClosedForm::Rpr { .. } => rpr_modes(block, [v[0], v[1]], (v[2], v[3]), (v[4], v[5])),
        ClosedForm::Linear2 { .. } => {
            linear2_modes(block, [v[0], v[1]], [v[2], v[3]], [v[4], v[5]])
        }
        ClosedForm::Angle1 { .. } => angle1_modes(block, v[0], (v[1], v[2])),
        ClosedForm::Length1 { .. } => length1_modes(block, v[0], v[1]),
    }
}

/// How far a closed form with roots `v` is from losing (positive) or gaining (negative) its pair
/// of modes: the distance by which its circles and lines meet or miss, the gap its kernel reports
/// past the dead point. `None` for the forms with one mode (linear) and non-finite roots.
pub(super) fn margin(form: &ClosedForm, v: &[f64]) -> Option<f64> {
    let m = match form {
        ClosedForm::Rrr(_) => {
            let (l, la, lb) = (v[0].hypot(v[1]), v[2].hypot(v[3]), v[4].hypot(v[5]));
            (la + lb - l).min(l - la + lb).min(l + la - lb)
        }
        ClosedForm::Rrp { .. } => {
            // The circle of radius |M| about −K against the line along u through the origin.
            let ul = v[4].hypot(v[5]);
            let h = (v[4] * -v[1] - v[5] * -v[0]) / ul;
            v[2].hypot(v[3]) - h.abs()
        }
        ClosedForm::Rpr { .. } => {
            // In the frame of N: |g| against |b|, scaled back by |N|.
            let nn = v[4] * v[4] + v[5] * v[5];
            let g = (-v[0] * v[4] - v[1] * v[5]) / nn;
            let g1 = (-v[1] * v[4] + v[0] * v[5]) / nn;
            let b = (v[3] * v[4] - v[2] * v[5]) / nn;
            (g.hypot(g1) - b.abs()) * nn.sqrt()
        }
        ClosedForm::Angle1 { .. } => v[1].hypot(v[2]) - v[0].abs(),
        ClosedForm::Linear2 { .. } | ClosedForm::Length1 { .. } => return None,
    };
    m.is_finite().then_some(m)
}

/// `q` with every mode of `f` written in: one configuration per mode.
fn expand(
    block: usize,
    f: &Form,
    x: &[f64],
    q: &[f64],
    p: &[f64],
) -> Result<Vec<Vec<f64>>, SolveError> {
    let v = eval(&f.roots, x, q, p);
    if v.iter().any(|x| !x.is_finite()) {
        return Err(SolveError::Unassemblable {
            block,
            residual: f64::INFINITY,
            iterations: 0,
        });
    }
    let (idx, n) = slots(&f.form);
    Ok(modes(block, &f.form, &v)?
        .as_slice()
        .iter()
        .map(|m| {
            let mut q = q.to_vec();
            for s in 0..n {
                q[idx[s]] = m.values[s];
            }
            q
        })
        .collect())
}

impl Solver {
    /// Every configuration at the inputs `x`, in a fixed order (block by block, mode by mode,
    /// cut roots ascending). An error only for a degenerate state (a block singular for every
    /// value of its unknowns, overflow).
    pub fn configurations(&self, x: &[f64]) -> Result<Vec<Vec<f64>>, SolveError> {
        self.walk(x, None)
    }

    /// [`Solver::configurations`] and the closed-form blocks' margins met on the way (see
    /// [`margin`]), in a fixed order: block by block, partial configuration by configuration.
    pub(super) fn with_margins(&self, x: &[f64]) -> Result<(Vec<Vec<f64>>, Vec<f64>), SolveError> {
        let mut margins = Vec::new();
        let qs = self.walk(x, Some(&mut margins))?;
        Ok((qs, margins))
    }

    fn walk(
        &self,
        x: &[f64],
        mut margins: Option<&mut Vec<f64>>,
    ) -> Result<Vec<Vec<f64>>, SolveError> {
        let mut all = vec![vec![0.0; self.unknowns]];
        for (b, step) in self.steps.iter().enumerate() {
            let mut next = Vec::new();
            for q in &all {
                match step {
                    Step::Closed(f) => {
                        if let Some(ms) = margins.as_deref_mut()
                            && let Some(m) = margin(&f.form, &eval(&f.roots, x, q, &self.params))
                        {
                            ms.push(m);
                        }
                        next.extend(expand(b, f, x, q, &self.params)?)
                    }
                    Step::Torn(t) => next.extend(self.torn(b, t, x, q, margins.as_deref_mut())),
                }
            }
            all = next;
            if all.is_empty() {
                break;
            }
        }
        Ok(all)
    }

    /// The configurations of a torn block at cut roots; into `margins` (when given) the values
    /// of its scalar equation at its extrema in the cut.
    fn torn(
        &self,
        b: usize,
        t: &Torn,
        x: &[f64],
        q: &[f64],
        mut margins: Option<&mut Vec<f64>>,
    ) -> Vec<Vec<f64>> {
        let mut out = Vec::new();
        for sigma in 0..1usize << t.subs.len() {
            let mut g = |c: f64| self.cut_value(b, t, sigma, x, q, c).map(|(v, _)| v);
            for root in roots_and_extrema(&mut g, margins.as_deref_mut()) {
                if let Some((_, q)) = self.cut_value(b, t, sigma, x, q, root) {
                    out.push(q);
                }
            }
        }
        out
    }

    /// The scalar equation of a torn block at cut value `c` with its sub-blocks in modes `sigma`
    /// (bit j: mode of sub-block j), and the configuration it gives; `None` where a sub-block has
    /// no such mode.
    fn cut_value(
        &self,
        b: usize,
        t: &Torn,
        sigma: usize,
        x: &[f64],
        q: &[f64],
        c: f64,
    ) -> Option<(f64, Vec<f64>)> {
        let p = &self.params;
        let mut q = q.to_vec();
        q[t.cut] = c;
        let mut v = [0.0; 6];
        for (j, sub) in t.subs.iter().enumerate() {
            eval_into(&sub.roots, x, &q, p, &mut v);
            if v.iter().any(|x| !x.is_finite()) {
                return None;
            }
            let ms = modes(b, &sub.form, &v).ok()?;
            let m = ms.as_slice().get((sigma >> j) & 1)?;
            let (idx, n) = slots(&sub.form);
            for s in 0..n {
                q[idx[s]] = m.values[s];
            }
        }
        let value = match &t.last {
            Last::Scalar { roots } => eval(roots, x, &q, p)[0],
            Last::Angle { q: u, roots } => {
                let v = eval(roots, x, &q, p);
                let (kx, px, qx, ky, py, qy) = (v[0], v[1], v[2], v[3], v[4], v[5]);
                let det = px * qy - qx * py;
                let (cn, sn) = (-(qy * kx - qx * ky), -(px * ky - py * kx));
                if det == 0.0 || !det.is_finite() {
                    return None;
                }
                q[*u] = (sn / det).atan2(cn / det);
                // In length (a link of length L has |det| = L²), as the margins are compared.
                (cn.hypot(sn) - det.abs()) / det.abs().sqrt()
            }
            Last::Length { s, roots } => {
                let v = eval(roots, x, &q, p);
                let (kx, ax, ky, ay) = (v[0], v[1], v[2], v[3]);
                let n2 = ax * ax + ay * ay;
                if n2 == 0.0 || !n2.is_finite() {
                    return None;
                }
                q[*s] = -(kx * ax + ky * ay) / n2;
                (kx * ay - ky * ax) / n2.sqrt()
            }
        };
        value.is_finite().then_some((value, q))
    }
}
