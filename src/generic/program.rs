//! Generic engine, the tick's program: a whole motion (positions block by block, the refinement
//! near a dead point, per block one factorization for both rates, the points) as one
//! straight-line list of instructions over shared registers, with the calls into the runtime's
//! kernels between them: the plan of a tick and of a whole solve that both back ends walk (the
//! interpreter in `walk.rs`, the JIT lowering it into one function in `jit/fused.rs`). A value
//! two stages need is computed once, as in the generated tick.

use std::ops::Range;

use mechgen_codegen::{Compiled, Dag, Node, NodeId, Var};
use mechgen_runtime::closed_form::ClosedKind;

use super::op::{Op, kept_sin_cos, op_of};

/// One step of a [`Program`], in order.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Step {
    /// The instructions `ops[range]` (each writes the register of its index).
    Ops(Range<usize>),
    /// Block `block` solved by its closed-form kernel (of `kind`, its unknowns `slots` as
    /// `ClosedForm::slots` gives them) from the roots in these registers.
    Closed {
        block: usize,
        kind: ClosedKind,
        slots: [usize; 2],
        roots: Vec<u32>,
    },
    /// Block `block` solved by Newton (its own position tape).
    Newton { block: usize },
    /// One refinement step per block when the positions' pivot ratio asks for it; every value of
    /// the unknowns computed before it is computed again after it.
    Refine,
    /// Block `block`'s velocity right-hand side (k registers) then its Jacobian (k×k, row-major):
    /// factored, solved, the solution stored as the velocities of `unknowns`.
    Velocity {
        block: usize,
        unknowns: Vec<usize>,
        values: Vec<u32>,
    },
    /// Block `block`'s acceleration right-hand side, solved with the factors of its velocity
    /// step, stored as the accelerations of `unknowns`.
    Acceleration {
        block: usize,
        unknowns: Vec<usize>,
        values: Vec<u32>,
    },
    /// The outputs, in order (each point's x, y, vx, vy, ax, ay).
    Output(Vec<u32>),
}

/// A whole motion as steps over one instruction list.
#[derive(Clone, Debug)]
pub(crate) struct Program {
    pub ops: Vec<Op>,
    pub steps: Vec<Step>,
    /// The params-only values the instructions read as the params after the file's own (param
    /// `n + j`, for `n` params, is the value of node `prelude[j]`, which reads params alone):
    /// computed once per param set, as generated code keeps them in its fixed caches.
    pub prelude: Vec<NodeId>,
    /// What a tick does before this motion (see [`TickShape`]; read by the JIT).
    #[cfg_attr(not(feature = "jit"), allow(dead_code))]
    pub tick: TickShape,
}

/// A tick's prelude to the motion: the inputs' sines and cosines rotated from the last tick's
/// (`mechgen_runtime::tick::inputs_trig`) and, where every block is solved in closed form, the
/// last tick's unknowns carried as the guess with theirs. The JIT compiles it into the motion's
/// function (`jit/prelude.rs`); the interpreter's tick runs the runtime's functions.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TickShape {
    /// Which inputs are angles (their sines and cosines are kept and rotated).
    pub input_angle: Vec<bool>,
    pub unknowns: usize,
    /// Every block solved in closed form: nothing to predict.
    pub carried: bool,
}

impl Program {
    /// The program of every block of `c` (whose nodes are in `dag`) in solve order up to
    /// accelerations, then the points; the sine or cosine partners of the prelude's are added
    /// to `dag`. `None` when the prelude would not fit the params' index range.
    pub(crate) fn motion(c: &Compiled, dag: &mut Dag) -> Option<Program> {
        let mut b = Builder::new(dag, c.model.params.len());
        for (block, f) in c.blocks.iter().enumerate() {
            match &f.closed_form {
                Some(form) => {
                    let roots = b.need(form.roots())?;
                    let (kind, slots) = (form.kind(), form.slots());
                    b.steps.push(Step::Closed {
                        block,
                        kind,
                        slots,
                        roots,
                    });
                }
                None => b.steps.push(Step::Newton { block }),
            }
        }
        b.refine();
        for (block, f) in c.blocks.iter().enumerate() {
            let unknowns: Vec<usize> = f.block.unknowns.iter().map(|u| u.index()).collect();
            let mut roots = f.velocity_rhs.clone();
            roots.extend(f.jacobian.iter().flatten());
            let values = b.need(&roots)?;
            b.steps.push(Step::Velocity {
                block,
                unknowns: unknowns.clone(),
                values,
            });
            let values = b.need(&f.acceleration_rhs)?;
            b.steps.push(Step::Acceleration {
                block,
                unknowns,
                values,
            });
        }
        let d = &c.derivatives;
        let mut points = Vec::new();
        for p in 0..c.model.points.len() {
            points.extend(c.system.points[p]);
            points.extend(d.point_velocity[p]);
            points.extend(d.point_acceleration[p]);
        }
        let outputs = b.need(&points)?;
        b.steps.push(Step::Output(outputs));
        let Builder {
            ops,
            steps,
            prelude,
            ..
        } = b;
        let prelude = (prelude.into_iter())
            .map(|p| match p {
                Pre::Node(n) => n,
                Pre::Sin(a) => dag.sin(a),
                Pre::Cos(a) => dag.cos(a),
            })
            .collect();
        let tick = TickShape {
            input_angle: (c.model.inputs.iter())
                .map(|i| i.kind == mechgen_codegen::Kind::Angle)
                .collect(),
            unknowns: c.model.unknowns.len(),
            carried: c.blocks.iter().all(|f| f.closed_form.is_some()),
        };
        Some(Program {
            ops,
            steps,
            prelude,
            tick,
        })
    }

    /// The largest number of values one call step hands over.
    #[cfg(feature = "jit")]
    pub(crate) fn call_width(&self) -> usize {
        (self.steps.iter())
            .map(|s| match s {
                Step::Closed { roots: v, .. }
                | Step::Velocity { values: v, .. }
                | Step::Acceleration { values: v, .. } => v.len(),
                _ => 0,
            })
            .max()
            .unwrap_or(0)
    }
}

/// A root of the prelude: a node, or the sine or cosine of an argument the DAG lacks yet.
enum Pre {
    Node(NodeId),
    Sin(NodeId),
    Cos(NodeId),
}

/// Builds a [`Program`]: each node emitted the first time a step needs it.
struct Builder<'d> {
    dag: &'d Dag,
    params: usize,
    ops: Vec<Op>,
    steps: Vec<Step>,
    /// Per node: its register (`u32::MAX`: not computed, or computed before the refinement
    /// from the unknowns).
    reg: Vec<u32>,
    /// Per argument: the register of its sine (its cosine is the next).
    sincos: Vec<u32>,
    /// Per node: whether it reads params and constants only, and whether it reads an unknown.
    params_only: Vec<bool>,
    on_q: Vec<bool>,
    /// The prelude's roots; per node its index there.
    prelude: Vec<Pre>,
    slot: Vec<u32>,
}

impl<'d> Builder<'d> {
    fn new(dag: &'d Dag, params: usize) -> Self {
        let nodes = dag.nodes();
        let (mut params_only, mut on_q) = (vec![false; nodes.len()], vec![false; nodes.len()]);
        for (i, n) in nodes.iter().enumerate() {
            let (po, q) = match *n {
                Node::Const(_) | Node::Var(Var::P(_)) => (true, false),
                Node::Var(v) => (false, matches!(v, Var::Q(_))),
                _ => n.children().fold((true, false), |(po, q), c| {
                    (po && params_only[c.index()], q || on_q[c.index()])
                }),
            };
            (params_only[i], on_q[i]) = (po, q);
        }
        Builder {
            dag,
            params,
            ops: Vec::new(),
            steps: Vec::new(),
            reg: vec![u32::MAX; nodes.len()],
            sincos: vec![u32::MAX; nodes.len()],
            params_only,
            on_q,
            prelude: Vec::new(),
            slot: vec![u32::MAX; nodes.len()],
        }
    }

    /// Whether node `i` is a prelude value (params-only, not a leaf).
    fn in_prelude(&self, i: usize) -> bool {
        self.params_only[i] && !matches!(self.dag.nodes()[i], Node::Const(_) | Node::Var(_))
    }

    /// The registers of `roots`, emitting (as one `Ops` step) every node they need that has none.
    fn need(&mut self, roots: &[NodeId]) -> Option<Vec<u32>> {
        let nodes = self.dag.nodes();
        let mut wanted = vec![false; nodes.len()];
        let mut stack = roots.to_vec();
        while let Some(n) = stack.pop() {
            let i = n.index();
            if self.reg[i] != u32::MAX || std::mem::replace(&mut wanted[i], true) {
                continue;
            }
            if !self.in_prelude(i) {
                stack.extend(nodes[i].children());
            }
        }
        let start = self.ops.len();
        // Children before parents: a node's id is larger than its children's.
        for i in (0..nodes.len()).filter(|&i| wanted[i]) {
            self.emit(i)?;
        }
        if self.ops.len() > start {
            self.steps.push(Step::Ops(start..self.ops.len()));
        }
        Some(roots.iter().map(|r| self.reg[r.index()]).collect())
    }

    fn emit(&mut self, i: usize) -> Option<()> {
        let n = self.dag.nodes()[i];
        if self.in_prelude(i) {
            let j = self.prelude_slot(i);
            let p = u16::try_from(self.params + j as usize).ok()?;
            self.reg[i] = self.push(Op::Var(Var::P(p)));
            return Some(());
        }
        if let Node::Sin(a) | Node::Cos(a) = n {
            let at = a.index();
            if self.sincos[at] == u32::MAX {
                let r = self.reg[at];
                let op = kept_sin_cos(self.dag.nodes()[at], r).unwrap_or(Op::SinCos(r));
                self.sincos[at] = self.push(op);
                self.push(Op::Cos2);
            }
            self.reg[i] = self.sincos[at] + u32::from(matches!(n, Node::Cos(_)));
            return Some(());
        }
        let reg = &self.reg;
        let op = op_of(n, |c| reg[c.index()]);
        self.reg[i] = self.push(op);
        Some(())
    }

    fn push(&mut self, op: Op) -> u32 {
        self.ops.push(op);
        self.ops.len() as u32 - 1
    }

    /// Node `i`'s index among the prelude's roots; a sine or cosine brings its partner, so that
    /// the prelude computes the two as one `sin_cos` (as generated code's fixed caches do).
    fn prelude_slot(&mut self, i: usize) -> u32 {
        if self.slot[i] == u32::MAX {
            self.slot[i] = self.prelude.len() as u32;
            self.prelude.push(Pre::Node(NodeId(i as u32)));
            let partner = match self.dag.nodes()[i] {
                Node::Sin(a) => Some((Node::Cos(a), Pre::Cos(a))),
                Node::Cos(a) => Some((Node::Sin(a), Pre::Sin(a))),
                _ => None,
            };
            match partner.map(|(n, p)| (self.dag.find(&n), p)) {
                Some((Some(n), _)) if self.slot[n.index()] == u32::MAX => {
                    self.slot[n.index()] = self.prelude.len() as u32;
                    self.prelude.push(Pre::Node(n));
                }
                Some((None, p)) => self.prelude.push(p),
                _ => {}
            }
        }
        self.slot[i]
    }

    /// The refinement step: values of the unknowns are computed afresh after it.
    fn refine(&mut self) {
        self.steps.push(Step::Refine);
        for i in 0..self.reg.len() {
            if self.on_q[i] {
                self.reg[i] = u32::MAX;
                self.sincos[i] = u32::MAX;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every default mechanism: each block solved before the refinement, then each block's
    /// velocity and acceleration in order, the points last; no sine or cosine computed in the
    /// program but an unknown's or an input's (the params' are in the prelude); every
    /// instruction a step's.
    #[test]
    fn stages_in_order_and_params_only_values_in_the_prelude() {
        let file =
            mechgen_codegen::SourceFile::new(crate::source::SOURCE_NAME, crate::source::SOURCE);
        let (compiled, _) = mechgen_codegen::analyze(&file);
        assert!(compiled.len() >= 4);
        let mut preludes = 0;
        for c in &compiled {
            let mut dag = c.system.dag.clone();
            let p = Program::motion(c, &mut dag).expect("a program");
            let calls: Vec<&Step> = p
                .steps
                .iter()
                .filter(|s| !matches!(s, Step::Ops(_)))
                .collect();
            let n = c.blocks.len();
            assert_eq!(calls.len(), 3 * n + 2, "{}", c.model.name.text);
            for (b, s) in calls[..n].iter().enumerate() {
                assert!(
                    matches!(s, Step::Closed { block, .. } | Step::Newton { block } if *block == b)
                );
            }
            assert_eq!(calls[n], &Step::Refine);
            for (b, pair) in calls[n + 1..3 * n + 1].chunks(2).enumerate() {
                assert!(matches!(pair[0], Step::Velocity { block, .. } if *block == b));
                assert!(matches!(pair[1], Step::Acceleration { block, .. } if *block == b));
            }
            assert!(
                matches!(calls[3 * n + 1], Step::Output(v) if v.len() == 6 * c.model.points.len())
            );
            let covered: usize = (p.steps.iter())
                .map(|s| match s {
                    Step::Ops(r) => r.len(),
                    _ => 0,
                })
                .sum();
            assert_eq!(covered, p.ops.len());
            assert!(
                !p.ops
                    .iter()
                    .any(|o| matches!(o, Op::SinCos(_) | Op::Sin(_) | Op::Cos(_)))
            );
            preludes += p.prelude.len();
        }
        // The four-bar's coupler angle and the six-bar's offsets are params-only sines.
        assert!(preludes > 0);
    }
}
