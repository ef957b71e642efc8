//! Generic engine, evaluation: the roots of an expression DAG compiled into a flat register
//! program (a tape) and interpreted. Only the nodes the roots need are kept, children before
//! parents, and a `sin` and `cos` of the same argument become one `sin_cos`.

use std::sync::Arc;

use mechgen_codegen::{Dag, Node, NodeId, Var};

use mechgen_runtime::error::SolveError;
use mechgen_runtime::scalar::Real;
use mechgen_runtime::twofold::{Arith, Twofold};

use super::op::{Op, eval_range, kept_sin_cos, op_of, slot};

/// The values the variables of a tape take. Slices a tape does not read may be empty; a missing
/// value reads as zero (callers check lengths before evaluating).
#[derive(Clone, Copy, Debug)]
pub struct Env<'a, T> {
    pub x: &'a [T],
    pub q: &'a [T],
    pub p: &'a [f64],
    pub xd: &'a [T],
    pub qd: &'a [T],
    pub xdd: &'a [T],
    pub qdd: &'a [T],
    /// (sin, cos) of each unknown kept in step with `q` through a solve (the runtime's
    /// `TrigSlices`); empty: computed from `q`.
    pub sc: &'a [(T, T)],
    /// (sin, cos) of each input as the tick keeps them (rotated from the last tick's); empty:
    /// computed from `x`.
    pub sx: &'a [(T, T)],
}

impl<'a, T: Real> Env<'a, T> {
    /// Only positions (and params) known.
    pub fn position(x: &'a [T], q: &'a [T], p: &'a [f64]) -> Self {
        Env {
            x,
            q,
            p,
            xd: &[],
            qd: &[],
            xdd: &[],
            qdd: &[],
            sc: &[],
            sx: &[],
        }
    }

    /// `v`'s value ([`Tape::eval`] has checked that every value its program reads is there; the
    /// 0 after an index past a slice is never read).
    #[inline]
    pub(super) fn get(&self, v: Var) -> T {
        let (slice, i) = match v {
            Var::X(i) => (self.x, i),
            Var::Q(i) => (self.q, i),
            Var::P(i) => return self.p.get(i as usize).map_or(T::zero(), |&p| T::lit(p)),
            Var::Xd(i) => (self.xd, i),
            Var::Qd(i) => (self.qd, i),
            Var::Xdd(i) => (self.xdd, i),
            Var::Qdd(i) => (self.qdd, i),
        };
        slice.get(i as usize).copied().unwrap_or(T::zero())
    }
}

/// A compiled program: evaluates some roots of a DAG.
#[derive(Clone, Debug, Default)]
pub struct Tape {
    /// Shared by clones: a mechanism's tapes are made once and cloned with every param set.
    ops: Arc<[Op]>,
    outputs: Arc<[u32]>,
    /// How many values of each of `x, q, p, xd, qd, xdd, qdd` the program reads (one past the
    /// largest index): [`Tape::eval`] refuses an environment with fewer.
    reads: [usize; 7],
    /// The same program as machine code (the JIT back end), run in f64 when set.
    #[cfg(feature = "jit")]
    compiled: Option<super::jit::Function>,
}

impl Tape {
    /// Compiles the nodes `roots` depend on.
    pub fn new(dag: &Dag, roots: &[NodeId]) -> Tape {
        let nodes = dag.nodes();
        let mut needed = vec![false; nodes.len()];
        let mut stack: Vec<NodeId> = roots.to_vec();
        while let Some(n) = stack.pop() {
            if !std::mem::replace(&mut needed[n.index()], true) {
                stack.extend(nodes[n.index()].children());
            }
        }
        // Arguments of both a needed sin and a needed cos.
        let mut has_sin = vec![false; nodes.len()];
        let mut has_cos = vec![false; nodes.len()];
        for (n, _) in nodes.iter().zip(&needed).filter(|(_, k)| **k) {
            match *n {
                Node::Sin(a) => has_sin[a.index()] = true,
                Node::Cos(a) => has_cos[a.index()] = true,
                _ => {}
            }
        }
        let mut reg = vec![u32::MAX; nodes.len()];
        // Register of the sin of each paired argument (its cos is the next register).
        let mut sincos = vec![u32::MAX; nodes.len()];
        let mut ops = Vec::new();
        // An unknown's or an input's sine and cosine may be kept by the state.
        let kept = |a: NodeId, r: u32| kept_sin_cos(nodes[a.index()], r);
        for (i, n) in nodes.iter().enumerate() {
            if !needed[i] {
                continue;
            }
            let r = |id: NodeId| reg[id.index()];
            if let Node::Sin(a) | Node::Cos(a) = *n
                && ((has_sin[a.index()] && has_cos[a.index()]) || kept(a, 0).is_some())
            {
                let at = a.index();
                if sincos[at] == u32::MAX {
                    sincos[at] = ops.len() as u32;
                    ops.push(kept(a, r(a)).unwrap_or(Op::SinCos(r(a))));
                    ops.push(Op::Cos2);
                }
                let cos = matches!(n, Node::Cos(_));
                reg[i] = sincos[at] + u32::from(cos);
                continue;
            }
            let op = op_of(*n, r);
            reg[i] = ops.len() as u32;
            ops.push(op);
        }
        let outputs: Arc<[u32]> = roots.iter().map(|r| reg[r.index()]).collect();
        let mut reads = [0; 7];
        for op in &ops {
            if let Op::Var(v) = *op {
                let (k, i) = slot(v);
                reads[k] = reads[k].max(i + 1);
            }
        }
        Tape {
            ops: ops.into(),
            outputs,
            reads,
            #[cfg(feature = "jit")]
            compiled: None,
        }
    }

    /// The instructions and the output registers (what a back end lowers).
    #[cfg(feature = "jit")]
    pub(super) fn program(&self) -> (&[Op], &[u32]) {
        (&self.ops, &self.outputs)
    }

    /// Runs `f` (this program compiled) instead of interpreting it, from now on.
    #[cfg(feature = "jit")]
    pub(super) fn set_compiled(&mut self, f: Option<super::jit::Function>) {
        self.compiled = f;
    }

    /// Whether the compiled program runs.
    pub fn is_compiled(&self) -> bool {
        #[cfg(feature = "jit")]
        return self.compiled.is_some();
        #[cfg(not(feature = "jit"))]
        false
    }

    /// The compiled program on `env` in f64, if there is one and every slice it reads is long
    /// enough; `false`: not run.
    #[cfg(feature = "jit")]
    fn run_compiled<T: Real>(&self, env: &Env<'_, T>, out: &mut [T]) -> bool {
        let Some(f) = &self.compiled else {
            return false;
        };
        let s = T::as_f64s;
        let vars = [env.x, env.q, env.xd, env.qd, env.xdd, env.qdd].map(s);
        let [Some(x), Some(q), Some(xd), Some(qd), Some(xdd), Some(qdd)] = vars else {
            return false;
        };
        let kept = (T::pairs_as_f64s(env.sc), T::pairs_as_f64s(env.sx));
        let ((Some(sc), Some(sx)), Some(out)) = (kept, T::as_f64s_mut(out)) else {
            return false;
        };
        f.call([x, q, env.p, xd, qd, xdd, qdd], [sc, sx], out)
    }

    /// Number of instructions.
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// Number of roots.
    pub fn outputs(&self) -> usize {
        self.outputs.len()
    }

    /// Runs the program; `regs` is workspace (resized as needed). Returns the root values through
    /// `out` (as many as fit). An environment without a value the program reads: `BadLength`
    /// (the first such slice's), nothing run.
    pub fn eval<T: Real>(
        &self,
        env: &Env<'_, T>,
        regs: &mut Vec<T>,
        out: &mut [T],
    ) -> Result<(), SolveError> {
        let have = [env.x, env.q, &[], env.xd, env.qd, env.xdd, env.qdd].map(<[T]>::len);
        let have = [
            have[0],
            have[1],
            env.p.len(),
            have[3],
            have[4],
            have[5],
            have[6],
        ];
        if let Some((&expected, &got)) = self.reads.iter().zip(&have).find(|(r, h)| h < r) {
            return Err(SolveError::BadLength { expected, got });
        }
        #[cfg(feature = "jit")]
        if self.run_compiled(env, out) {
            return Ok(());
        }
        let sc = |k: u32| env.sc.get(k as usize).copied();
        let sx = |i: u32| env.sx.get(i as usize).copied();
        self.run(|v| env.get(v), sc, sx, regs);
        for (o, &r) in out.iter_mut().zip(self.outputs.iter()) {
            *o = regs[r as usize];
        }
        Ok(())
    }

    /// [`Tape::eval`] where its error cannot be returned (inside a solver's callback): the
    /// outputs NaN instead, so that the solve fails rather than run on missing values.
    pub fn eval_or_nan<T: Real>(&self, env: &Env<'_, T>, regs: &mut Vec<T>, out: &mut [T]) {
        if self.eval(env, regs, out).is_err() {
            out.fill(T::lit(f64::NAN));
        }
    }

    /// Runs the program in double-word arithmetic at positions `(x, q)` (rates read as zero):
    /// the root values to about 1e-32 relative of the terms (a params-only function in f64).
    pub fn eval_twofold(&self, x: &[f64], q: &[f64], p: &[f64]) -> Vec<Twofold> {
        let zeros = vec![0.0; self.reads[3..].iter().copied().max().unwrap_or(0)];
        let env = Env {
            xd: &zeros,
            qd: &zeros,
            xdd: &zeros,
            qdd: &zeros,
            ..Env::position(x, q, p)
        };
        let mut regs = Vec::new();
        self.run(|v| Twofold::from(env.get(v)), |_| None, |_| None, &mut regs);
        self.outputs.iter().map(|&r| regs[r as usize]).collect()
    }

    /// The interpreter: every instruction in order, in the arithmetic `A`, into `regs`.
    /// `sc` gives an unknown's kept sine and cosine, if any, `sx` an input's.
    fn run<A: Arith>(
        &self,
        var: impl Fn(Var) -> A,
        sc: impl Fn(u32) -> Option<(A, A)>,
        sx: impl Fn(u32) -> Option<(A, A)>,
        regs: &mut Vec<A>,
    ) {
        regs.clear();
        regs.resize(self.ops.len(), A::constant(0.0));
        eval_range(&self.ops, 0..self.ops.len(), var, sc, sx, regs);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A program reading a rate, run where only positions are known: `BadLength` naming the
    /// slice it lacks, not the rate read as 0; with the rate given, its value.
    #[test]
    fn a_missing_value_is_an_error_not_zero() {
        let mut dag = Dag::new();
        let (q, qd) = (dag.var(Var::Q(0)), dag.var(Var::Qd(1)));
        let root = dag.mul(q, qd);
        let tape = Tape::new(&dag, &[root]);
        let (x, q, p) = ([0.5], [2.0, 7.0], []);
        let mut out = [0.0f64];
        let env = Env::position(&x, &q, &p);
        let got = tape.eval(&env, &mut Vec::new(), &mut out);
        assert_eq!(
            got,
            Err(SolveError::BadLength {
                expected: 2,
                got: 0
            })
        );
        let short = Env { qd: &[3.0], ..env };
        let got = tape.eval(&short, &mut Vec::new(), &mut out);
        assert_eq!(
            got,
            Err(SolveError::BadLength {
                expected: 2,
                got: 1
            })
        );
        let full = Env {
            qd: &[3.0, 5.0],
            ..env
        };
        assert_eq!(tape.eval(&full, &mut Vec::new(), &mut out), Ok(()));
        assert_eq!(out, [10.0]);
        tape.eval_or_nan(&env, &mut Vec::new(), &mut out);
        assert!(out[0].is_nan());
    }
}
