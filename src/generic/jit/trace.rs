//! The JIT, kernels by tracing: the runtime's lane kernels (`mechgen_runtime::lanes`: the
//! closed forms, a small block's factors and solves) run once at compile time on [`Traced`]
//! values, a one-lane [`Lanes`] whose every operation is recorded, then lowered into the
//! compiled function ([`lower`]). The kernels are branch-free and repeat the scalar's operations
//! in order, clearing a mask where the scalar would leave its common path; compiled code takes
//! the traced path where the mask holds and calls the scalar kernel otherwise. So the kernels
//! are written once, in the runtime, for every back end.

use std::cell::RefCell;
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use cranelift_codegen::ir::condcodes::FloatCC;
use cranelift_codegen::ir::{InstBuilder, Value};
use cranelift_frontend::FunctionBuilder;
use mechgen_runtime::lanes::Lanes;

use super::emit::{abs, constant_second, neg};
use super::error::JitError;

/// The value a kernel's `tolerance` (a plain `f64` argument of the lane kernels) is traced with:
/// a NaN whose payload no arithmetic makes, recorded as [`Node::Tolerance`] where the kernel
/// splats it, so that compiled code reads the caller's tolerance at run time.
pub(super) const TOLERANCE: f64 = f64::from_bits(0x7ff8_dead_beef_0001);

/// A comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Cmp {
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
}

/// One recorded operation; operands are indices of earlier nodes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Node {
    Const(f64),
    /// The `i`-th value the caller gives the lowering.
    Input(u32),
    /// The run-time tolerance (see [`TOLERANCE`]).
    Tolerance,
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Div(u32, u32),
    Neg(u32),
    Sqrt(u32),
    Abs(u32),
    /// A mask.
    Cmp(Cmp, u32, u32),
    /// A mask: finite (neither infinite nor NaN).
    Finite(u32),
    And(u32, u32),
    Or(u32, u32),
    Not(u32),
    /// `if mask { a } else { b }`.
    Select(u32, u32, u32),
}

#[derive(Default)]
struct Recording {
    nodes: Vec<Node>,
    /// An operation a lowering cannot express was asked for (a lane read as a number).
    broken: bool,
}

thread_local! {
    static RECORDING: RefCell<Recording> = RefCell::default();
}

fn push(n: Node) -> u32 {
    RECORDING.with(|r| {
        let mut r = r.borrow_mut();
        r.nodes.push(n);
        u32::try_from(r.nodes.len() - 1).unwrap_or(u32::MAX)
    })
}

fn break_trace() {
    RECORDING.with(|r| r.borrow_mut().broken = true);
}

/// A traced value: one lane of f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Traced(pub u32);

/// A traced lane mask.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct TracedMask(pub u32);

impl Traced {
    /// The caller's `i`-th value.
    pub fn input(i: u32) -> Traced {
        Traced(push(Node::Input(i)))
    }
}

impl TracedMask {
    /// The mask of a lane on the common path.
    pub fn all() -> TracedMask {
        let one = Traced::splat(1.0);
        one.eq(one)
    }
}

/// What [`record`] gives: the operations in order, and the kernel's result.
pub(super) struct Trace<R> {
    pub nodes: Vec<Node>,
    pub result: R,
}

/// Runs `kernel` on traced values (made by [`Traced::input`] inside it), recording every
/// operation; an error when it asked for something a lowering cannot express.
pub(super) fn record<R>(kernel: impl FnOnce() -> R) -> Result<Trace<R>, JitError> {
    RECORDING.with(|r| *r.borrow_mut() = Recording::default());
    let result = kernel();
    let Recording { nodes, broken } = RECORDING.with(|r| std::mem::take(&mut *r.borrow_mut()));
    // The tolerance is only splatted: any other NaN constant came from arithmetic on it.
    let stray = nodes
        .iter()
        .any(|n| matches!(n, Node::Const(c) if c.is_nan()));
    if broken || stray {
        return Err(JitError::Tape);
    }
    Ok(Trace { nodes, result })
}

macro_rules! binary {
    ($($tr:ident $f:ident $node:ident),*) => {$(
        impl $tr for Traced {
            type Output = Traced;
            fn $f(self, o: Traced) -> Traced {
                Traced(push(Node::$node(self.0, o.0)))
            }
        }
    )*};
}
binary!(Add add Add, Sub sub Sub, Mul mul Mul, Div div Div);

impl Neg for Traced {
    type Output = Traced;
    fn neg(self) -> Traced {
        Traced(push(Node::Neg(self.0)))
    }
}

impl Default for Traced {
    fn default() -> Self {
        Traced::splat(0.0)
    }
}

impl BitAnd for TracedMask {
    type Output = TracedMask;
    fn bitand(self, o: TracedMask) -> TracedMask {
        TracedMask(push(Node::And(self.0, o.0)))
    }
}

impl BitOr for TracedMask {
    type Output = TracedMask;
    fn bitor(self, o: TracedMask) -> TracedMask {
        TracedMask(push(Node::Or(self.0, o.0)))
    }
}

impl Not for TracedMask {
    type Output = TracedMask;
    fn not(self) -> TracedMask {
        TracedMask(push(Node::Not(self.0)))
    }
}

impl Traced {
    fn cmp(self, c: Cmp, o: Traced) -> TracedMask {
        TracedMask(push(Node::Cmp(c, self.0, o.0)))
    }
}

/// One lane, every operation recorded. A lane cannot be read as a number at compile time: the
/// methods that would (`lane`, `set_lane`, `bits`, and the lane-by-lane functions built on
/// them) break the trace, and [`record`] refuses it.
impl Lanes for Traced {
    type Scalar = f64;
    type Mask = TracedMask;
    type Array<U: Copy + std::fmt::Debug + Send + Sync> = [U; 1];
    const W: usize = 1;

    fn splat(v: f64) -> Self {
        let same = v.to_bits() == TOLERANCE.to_bits();
        Traced(push(if same {
            Node::Tolerance
        } else {
            Node::Const(v)
        }))
    }
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        Traced::splat(f(0))
    }
    fn array<U: Copy + std::fmt::Debug + Send + Sync>(mut f: impl FnMut(usize) -> U) -> [U; 1] {
        [f(0)]
    }
    fn lane(self, _: usize) -> f64 {
        break_trace();
        0.0
    }
    fn set_lane(&mut self, _: usize, _: f64) {
        break_trace();
    }
    fn sqrt(self) -> Self {
        Traced(push(Node::Sqrt(self.0)))
    }
    fn abs(self) -> Self {
        Traced(push(Node::Abs(self.0)))
    }
    fn lt(self, o: Self) -> TracedMask {
        self.cmp(Cmp::Lt, o)
    }
    fn le(self, o: Self) -> TracedMask {
        self.cmp(Cmp::Le, o)
    }
    fn gt(self, o: Self) -> TracedMask {
        self.cmp(Cmp::Gt, o)
    }
    fn ge(self, o: Self) -> TracedMask {
        self.cmp(Cmp::Ge, o)
    }
    fn eq(self, o: Self) -> TracedMask {
        self.cmp(Cmp::Eq, o)
    }
    fn is_finite(self) -> TracedMask {
        TracedMask(push(Node::Finite(self.0)))
    }
    fn select(m: TracedMask, a: Self, b: Self) -> Self {
        Traced(push(Node::Select(m.0, a.0, b.0)))
    }
    fn bits(_: TracedMask) -> u32 {
        break_trace();
        1
    }
    fn mask(_: u32) -> TracedMask {
        break_trace();
        TracedMask::all()
    }
}

/// Lowers `nodes` into `b` at its current block, `inputs[i]` standing for `Node::Input(i)` and
/// `tolerance` for the tolerance: a value per node (f64, or a mask of type `i8`, 1 where set).
pub(super) fn lower(
    b: &mut FunctionBuilder,
    nodes: &[Node],
    inputs: &[Value],
    tolerance: Option<Value>,
) -> Result<Vec<Value>, JitError> {
    let mut v: Vec<Value> = Vec::with_capacity(nodes.len());
    let at = |v: &[Value], i: u32| v.get(i as usize).copied().ok_or(JitError::Tape);
    for n in nodes {
        let x = match *n {
            Node::Const(c) => b.ins().f64const(c),
            Node::Input(i) => at(inputs, i)?,
            Node::Tolerance => tolerance.ok_or(JitError::Tape)?,
            Node::Add(x, y) => {
                let (x, y) = constant_second(b, at(&v, x)?, at(&v, y)?);
                b.ins().fadd(x, y)
            }
            Node::Sub(x, y) => b.ins().fsub(at(&v, x)?, at(&v, y)?),
            Node::Mul(x, y) => {
                let (x, y) = constant_second(b, at(&v, x)?, at(&v, y)?);
                b.ins().fmul(x, y)
            }
            Node::Div(x, y) => b.ins().fdiv(at(&v, x)?, at(&v, y)?),
            Node::Neg(x) => neg(b, at(&v, x)?),
            Node::Sqrt(x) => b.ins().sqrt(at(&v, x)?),
            Node::Abs(x) => abs(b, at(&v, x)?),
            Node::Cmp(c, x, y) => {
                let cc = match c {
                    Cmp::Lt => FloatCC::LessThan,
                    Cmp::Le => FloatCC::LessThanOrEqual,
                    Cmp::Gt => FloatCC::GreaterThan,
                    Cmp::Ge => FloatCC::GreaterThanOrEqual,
                    Cmp::Eq => FloatCC::Equal,
                };
                b.ins().fcmp(cc, at(&v, x)?, at(&v, y)?)
            }
            Node::Finite(x) => {
                // |x| < ∞: false for both infinities and NaN.
                let a = abs(b, at(&v, x)?);
                let inf = b.ins().f64const(f64::INFINITY);
                b.ins().fcmp(FloatCC::LessThan, a, inf)
            }
            Node::And(x, y) => b.ins().band(at(&v, x)?, at(&v, y)?),
            Node::Or(x, y) => b.ins().bor(at(&v, x)?, at(&v, y)?),
            // Masks are 0 or 1: not is xor with 1.
            Node::Not(x) => b.ins().bxor_imm_u(at(&v, x)?, 1),
            Node::Select(m, x, y) => b.ins().select(at(&v, m)?, at(&v, x)?, at(&v, y)?),
        };
        v.push(x);
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_kernel_is_recorded_in_order_and_a_lane_read_refused() {
        let t = record(|| {
            let (x, y) = (Traced::input(0), Traced::input(1));
            let s = (x * x + y * y).sqrt();
            (s, s.gt(Traced::splat(TOLERANCE)))
        })
        .expect("records");
        assert_eq!(t.nodes[0], Node::Input(0));
        assert!(matches!(t.nodes[t.result.0.0 as usize], Node::Sqrt(_)));
        assert!(t.nodes.contains(&Node::Tolerance));
        assert!(record(|| Traced::input(0).lane(0)).is_err());
        assert!(record(|| Traced::input(0) + Traced::splat(f64::NAN)).is_err());
    }
}
