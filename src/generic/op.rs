//! Generic engine, the instruction set of a tape: each instruction defined once, read by the
//! interpreter (`tape.rs`) and lowered by the JIT (`jit/lower.rs`).

use std::ops::Range;

use mechgen_codegen::{Func, Node, NodeId, Var};
use mechgen_runtime::twofold::Arith;

/// One instruction; operands are register numbers (every instruction writes the next register).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Op {
    Const(f64),
    Var(Var),
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Div(u32, u32),
    Neg(u32),
    /// Writes `sin` to this register and `cos` to the next one (whose op is [`Op::Cos2`]).
    SinCos(u32),
    /// [`Op::SinCos`] of unknown `k` (in register `a`): read from the state's sines and cosines
    /// (`Env::sc` of `tape.rs`) when it has them, as generated code reads its `TrigState`.
    SinCosQ(u32, u32),
    /// [`Op::SinCos`] of input `i` (in register `a`): read from the tick's rotated sines and
    /// cosines of the inputs (`Env::sx`) when it has them, as generated code reads its `tx`.
    SinCosX(u32, u32),
    /// Placeholder for the `cos` half of the preceding [`Op::SinCos`] or [`Op::SinCosQ`].
    Cos2,
    Sin(u32),
    Cos(u32),
    Tan(u32),
    Sqrt(u32),
    /// A params-only function of one or two registers.
    Func(Func, u32, u32),
}

/// The `Args` slot of a variable and its index there.
pub(crate) fn slot(v: Var) -> (usize, usize) {
    let (s, i) = match v {
        Var::X(i) => (0, i),
        Var::Q(i) => (1, i),
        Var::P(i) => (2, i),
        Var::Xd(i) => (3, i),
        Var::Qd(i) => (4, i),
        Var::Xdd(i) => (5, i),
        Var::Qdd(i) => (6, i),
    };
    (s, usize::from(i))
}

/// The instruction of one DAG node, its children in the registers `r` gives (a `sin` or `cos`
/// alone; pairing them into one `sin_cos` is the caller's).
pub(crate) fn op_of(n: Node, r: impl Fn(NodeId) -> u32) -> Op {
    match n {
        Node::Const(b) => Op::Const(f64::from_bits(b)),
        Node::Var(v) => Op::Var(v),
        Node::Add(a, b) => Op::Add(r(a), r(b)),
        Node::Sub(a, b) => Op::Sub(r(a), r(b)),
        Node::Mul(a, b) => Op::Mul(r(a), r(b)),
        Node::Div(a, b) => Op::Div(r(a), r(b)),
        // `-(a - b)` as generated code computes it: the difference, then its negation
        // (`b - a` would be `+0.0` where it is `-0.0`).
        Node::Neg(d) => Op::Neg(r(d)),
        Node::Sin(a) => Op::Sin(r(a)),
        Node::Cos(a) => Op::Cos(r(a)),
        Node::Tan(a) => Op::Tan(r(a)),
        Node::Sqrt(a) => Op::Sqrt(r(a)),
        Node::Func(f, a, b) => Op::Func(f, r(a), r(b)),
    }
}

/// The kept-sine-and-cosine instruction of an unknown's or an input's `sin_cos` (argument in
/// register `r`), whose values the state may keep.
pub(crate) fn kept_sin_cos(arg: Node, r: u32) -> Option<Op> {
    match arg {
        Node::Var(Var::Q(k)) => Some(Op::SinCosQ(r, u32::from(k))),
        Node::Var(Var::X(i)) => Some(Op::SinCosX(r, u32::from(i))),
        _ => None,
    }
}

/// The interpreter: the instructions `ops[range]` in order, in the arithmetic `A`, each into the
/// register of its index in `regs` (as long as `ops`). `var` gives a variable's value, `sc` an
/// unknown's kept sine and cosine (if any), `sx` an input's.
pub(crate) fn eval_range<A: Arith>(
    ops: &[Op],
    range: Range<usize>,
    var: impl Fn(Var) -> A,
    sc: impl Fn(u32) -> Option<(A, A)>,
    sx: impl Fn(u32) -> Option<(A, A)>,
    regs: &mut [A],
) {
    for i in range {
        let g = |k: u32| regs[k as usize];
        let v = match ops[i] {
            Op::Const(c) => A::constant(c),
            Op::Var(v) => var(v),
            Op::Add(a, b) => g(a) + g(b),
            Op::Sub(a, b) => g(a) - g(b),
            Op::Mul(a, b) => g(a) * g(b),
            Op::Div(a, b) => g(a) / g(b),
            Op::Neg(a) => -g(a),
            Op::SinCos(a) | Op::SinCosQ(a, _) | Op::SinCosX(a, _) => {
                let kept = match ops[i] {
                    Op::SinCosQ(_, k) => sc(k),
                    Op::SinCosX(_, k) => sx(k),
                    _ => None,
                };
                let (s, c) = kept.unwrap_or_else(|| g(a).sin_cos_of());
                if let Some(next) = regs.get_mut(i + 1) {
                    *next = c;
                }
                s
            }
            Op::Cos2 => continue,
            Op::Sin(a) => g(a).sin_of(),
            Op::Cos(a) => g(a).cos_of(),
            Op::Tan(a) => g(a).tan_of(),
            Op::Sqrt(a) => g(a).sqrt_of(),
            Op::Func(f, a, b) => A::func(f.method(), g(a), g(b)),
        };
        regs[i] = v;
    }
}
