//! Branch identification, every assembly configuration at one input: block by block, a
//! closed-form block multiplies the partial configurations by its modes (the runtime's `*_modes`
//! kernels), a torn block by the roots of its scalar equation in the cut, one function per
//! combination of its sub-blocks' modes (`roots::roots_and_extrema`), the other unknowns in closed form.
//! On request, each block's margins (how far it is from gaining or losing a pair of
//! configurations) for the grid's search of hidden changes of the count.

use mechgen_runtime::error::SolveError;

use super::plan::{Form, Last, Step, Torn};
use super::roots::roots_and_extrema;
use crate::generic::tape::{Env, Tape};

/// The most configurations at one input the branch analysis follows: each two-mode block
/// doubles them (a chain of n dyads has 2ⁿ), and matching them from one input to the next takes
/// time that grows with their square (256, a chain of eight dyads: about 3 s on a 2-core VM).
pub const MAX_CONFIGURATIONS: usize = 256;

/// Why the configurations at an input could not be listed.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Enumeration {
    /// A block's solve failed (overflow, a non-finite value).
    Solve(SolveError),
    /// More than [`MAX_CONFIGURATIONS`] after block `block`.
    TooMany { block: usize },
}

impl From<SolveError> for Enumeration {
    fn from(e: SolveError) -> Self {
        Enumeration::Solve(e)
    }
}

impl std::fmt::Display for Enumeration {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Enumeration::Solve(e) => e.fmt(f),
            Enumeration::TooMany { block } => write!(
                f,
                "over {MAX_CONFIGURATIONS} assembly configurations by block {block} (each block \
                 with two modes doubles them): more than the branch analysis follows"
            ),
        }
    }
}

/// A mechanism's configuration enumerator.
#[derive(Clone, Debug)]
pub struct Solver {
    pub(super) steps: Vec<Step>,
    pub(super) params: Vec<f64>,
    pub(super) unknowns: usize,
    /// Mode combinations seen to make a block degenerate (see [`Solver::degenerate`]).
    pub(super) degenerate: std::cell::RefCell<std::collections::BTreeSet<(usize, Vec<u8>)>>,
}

thread_local! {
    /// Registers of the tapes (reused: the cut's function is evaluated many times per input).
    static REGS: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The roots of `tape` at `(x, q)` into `out` (at most 6 are read).
fn eval_into(tape: &Tape, x: &[f64], q: &[f64], p: &[f64], out: &mut [f64; 6]) {
    REGS.with_borrow_mut(|regs| tape.eval_or_nan(&Env::position(x, q, p), regs, out));
}

fn eval(tape: &Tape, x: &[f64], q: &[f64], p: &[f64]) -> Vec<f64> {
    let mut out = [0.0; 6];
    eval_into(tape, x, q, p, &mut out);
    out[..tape.outputs().min(6)].to_vec()
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
    let (idx, n) = (f.form.slots(), f.form.kind().unknowns());
    Ok(f.form
        .kind()
        .modes(block, &v)?
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
    /// cut roots ascending). A combination of modes that makes a later block singular (two of its
    /// points coincide: no isolated configuration) is left out and noted ([`Solver::degenerate`]).
    /// An error for overflow, a non-finite value, or more than [`MAX_CONFIGURATIONS`].
    pub fn configurations(&self, x: &[f64]) -> Result<Vec<Vec<f64>>, Enumeration> {
        self.walk(x, None)
    }

    /// [`Solver::configurations`] and the closed-form blocks' margins met on the way (see
    /// `margin`), in a fixed order: block by block, partial configuration by configuration.
    pub(super) fn with_margins(&self, x: &[f64]) -> Result<(Vec<Vec<f64>>, Vec<f64>), Enumeration> {
        let mut margins = Vec::new();
        let qs = self.walk(x, Some(&mut margins))?;
        Ok((qs, margins))
    }

    /// Whether there is a configuration at the inputs `x`: depth first, done at the first one
    /// (no list of every configuration, whose count doubles with each two-mode block); `None`
    /// when it cannot tell (overflow, a non-finite value, or [`MAX_CONFIGURATIONS`] partial
    /// configurations tried without an answer).
    pub fn assembles(&self, x: &[f64]) -> Option<bool> {
        let mut budget = MAX_CONFIGURATIONS;
        self.any_from(
            0,
            x,
            &vec![0.0; self.unknowns],
            &mut Vec::new(),
            &mut budget,
        )
    }

    /// [`Solver::assembles`] from block `b` on, `q` solved up to it by the modes `modes`.
    fn any_from(
        &self,
        b: usize,
        x: &[f64],
        q: &[f64],
        modes: &mut Vec<u8>,
        budget: &mut usize,
    ) -> Option<bool> {
        let Some(step) = self.steps.get(b) else {
            return Some(true);
        };
        *budget = budget.checked_sub(1)?;
        for (m, q) in self
            .step(b, step, x, q, modes, None)
            .ok()?
            .iter()
            .enumerate()
        {
            modes.push(u8::try_from(m).unwrap_or(u8::MAX));
            let found = self.any_from(b + 1, x, q, modes, budget);
            modes.pop();
            if found != Some(false) {
                return found;
            }
        }
        Some(false)
    }

    fn walk(
        &self,
        x: &[f64],
        mut margins: Option<&mut Vec<f64>>,
    ) -> Result<Vec<Vec<f64>>, Enumeration> {
        // Each partial configuration with the modes that made it (one label per block so far).
        let mut all = vec![(vec![0.0; self.unknowns], Vec::new())];
        for (b, step) in self.steps.iter().enumerate() {
            let mut next = Vec::new();
            for (q, modes) in &all {
                let qs = self.step(b, step, x, q, modes, margins.as_deref_mut())?;
                for (m, q) in qs.into_iter().enumerate() {
                    let mut modes: Vec<u8> = modes.clone();
                    modes.push(u8::try_from(m).unwrap_or(u8::MAX));
                    next.push((q, modes));
                }
                if next.len() > MAX_CONFIGURATIONS {
                    return Err(Enumeration::TooMany { block: b });
                }
            }
            all = next;
            if all.is_empty() {
                break;
            }
        }
        Ok(all.into_iter().map(|(q, _)| q).collect())
    }

    /// Block `b` (`step`) solved in every way from the partial configuration `q` (made by the
    /// modes `modes`); a closed form's margin into `margins`. A combination of modes that makes
    /// the block degenerate (two of its points coincide, as when two dyads on the same circles
    /// pick the same intersection) gives none, and is noted.
    fn step(
        &self,
        b: usize,
        step: &Step,
        x: &[f64],
        q: &[f64],
        modes: &[u8],
        margins: Option<&mut Vec<f64>>,
    ) -> Result<Vec<Vec<f64>>, SolveError> {
        match step {
            Step::Closed(f) => {
                if let Some(ms) = margins
                    && let Some(m) = f.form.kind().margin(&eval(&f.roots, x, q, &self.params))
                {
                    ms.push(m);
                }
                match expand(b, f, x, q, &self.params) {
                    Err(SolveError::Singular { .. }) => {
                        self.degenerate.borrow_mut().insert((b, modes.to_vec()));
                        Ok(Vec::new())
                    }
                    r => r,
                }
            }
            Step::Torn(t) => Ok(self.torn(b, t, x, q, margins)),
        }
    }

    /// The mode combinations met so far that make a later block degenerate: (that block, the
    /// earlier blocks' mode indices), in order.
    pub fn degenerate(&self) -> Vec<(usize, Vec<u8>)> {
        self.degenerate.borrow().iter().cloned().collect()
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
            let ms = sub.form.kind().modes(b, &v).ok()?;
            let m = ms.as_slice().get((sigma >> j) & 1)?;
            let (idx, n) = (sub.form.slots(), sub.form.kind().unknowns());
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
