//! Generic engine, the instruction set of a tape: each instruction defined once, read by the
//! interpreter (`tape.rs`) and lowered by the JIT (`jit/lower.rs`).

use mechgen_codegen::{Func, Var};

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
