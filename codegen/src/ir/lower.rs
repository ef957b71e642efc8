//! Stage 3: a checked [`Model`] → scalar residuals and point coordinates in a [`Dag`]. Each loop
//! becomes two residuals (x, y); a scalar term of a vector sum is the vector (s, 0).

use crate::front::ast::{BinOp, Expr, ExprKind};
use crate::ir::dag::{Dag, Func, Node, NodeId, Var};
use crate::sema::builtin::Builtin;
use crate::sema::model::{Model, Symbol};

/// The position-level system of one mechanism.
#[derive(Clone, Debug)]
pub struct System {
    pub dag: Dag,
    /// Residual `2*l` is the x component of loop `l`, `2*l + 1` its y component.
    pub residuals: Vec<NodeId>,
    /// Each point's (x, y).
    pub points: Vec<[NodeId; 2]>,
}

#[derive(Clone, Copy)]
enum Value {
    Scalar(NodeId),
    Vector(NodeId, NodeId),
}

/// Lowers a checked model. The model is well typed, so every expression lowers.
pub fn lower(model: &Model) -> System {
    let mut dag = Dag::new();
    let mut residuals = Vec::with_capacity(2 * model.loops.len());
    for l in &model.loops {
        let [x, y] = vector(&mut dag, model, l);
        residuals.extend([x, y]);
    }
    let points = model
        .points
        .iter()
        .map(|(_, e)| vector(&mut dag, model, e))
        .collect();
    System {
        dag,
        residuals,
        points,
    }
}

fn vector(dag: &mut Dag, model: &Model, e: &Expr) -> [NodeId; 2] {
    match value(dag, model, e) {
        Value::Vector(x, y) => [x, y],
        Value::Scalar(s) => [s, dag.constant(0.0)],
    }
}

fn as_vector(dag: &mut Dag, v: Value) -> (NodeId, NodeId) {
    match v {
        Value::Vector(x, y) => (x, y),
        Value::Scalar(s) => (s, dag.constant(0.0)),
    }
}

fn scalar(v: Value) -> NodeId {
    match v {
        Value::Scalar(s) => s,
        // Unreachable for a checked model; the x component keeps lowering total.
        Value::Vector(x, _) => x,
    }
}

fn value(dag: &mut Dag, model: &Model, e: &Expr) -> Value {
    match &e.kind {
        ExprKind::Number(x) => Value::Scalar(dag.constant(*x)),
        ExprKind::Name(n) if Builtin::from_name(n) == Some(Builtin::Pi) => {
            Value::Scalar(dag.constant(std::f64::consts::PI))
        }
        ExprKind::Name(n) => {
            let var = match model.symbols.get(n) {
                Some(Symbol::Input(i)) => Var::X(*i as u16),
                Some(Symbol::Unknown(i)) => Var::Q(*i as u16),
                Some(Symbol::Param(i)) => Var::P(*i as u16),
                // A derived param is its expression of the base params (hash-consing shares it).
                Some(Symbol::Derived(j)) => {
                    return model
                        .derived
                        .get(*j)
                        .map_or(Value::Scalar(dag.constant(0.0)), |p| {
                            value(dag, model, &p.expr)
                        });
                }
                None => return Value::Scalar(dag.constant(0.0)),
            };
            Value::Scalar(dag.var(var))
        }
        ExprKind::Neg(a) => match value(dag, model, a) {
            Value::Scalar(s) => Value::Scalar(dag.neg(s)),
            Value::Vector(x, y) => Value::Vector(dag.neg(x), dag.neg(y)),
        },
        ExprKind::Binary(op, a, b) => {
            let (va, vb) = (value(dag, model, a), value(dag, model, b));
            binary(dag, *op, va, vb)
        }
        ExprKind::Call(f, args) => {
            // Arity is checked: a missing argument (unreachable) reads as 0.
            let zero = dag.constant(0.0);
            let mut arg_values = [Value::Scalar(zero); 2];
            for (slot, a) in arg_values.iter_mut().zip(args) {
                *slot = value(dag, model, a);
            }
            let arg = |i: usize| arg_values[i.min(1)];
            // A checked model calls only built-ins that loops and points allow.
            let Some(builtin) = Builtin::from_name(&f.text) else {
                return Value::Scalar(dag.constant(0.0));
            };
            match builtin {
                Builtin::E => {
                    let t = scalar(arg(0));
                    let (c, s) = cos_sin(dag, t);
                    Value::Vector(c, s)
                }
                Builtin::C => {
                    let (x, y) = (scalar(arg(0)), scalar(arg(1)));
                    Value::Vector(x, y)
                }
                Builtin::Sin => Value::Scalar(cos_sin(dag, scalar(arg(0))).1),
                Builtin::Cos => Value::Scalar(cos_sin(dag, scalar(arg(0))).0),
                Builtin::Tan => Value::Scalar(dag.tan(scalar(arg(0)))),
                Builtin::Sqrt => Value::Scalar(dag.sqrt(scalar(arg(0)))),
                Builtin::Deg => {
                    let k = dag.constant(std::f64::consts::PI / 180.0);
                    Value::Scalar(dag.mul(k, scalar(arg(0))))
                }
                // Params only: in derived params, which lowering substitutes.
                Builtin::Asin => Value::Scalar(func(dag, Func::Asin, arg(0), arg(0))),
                Builtin::Acos => Value::Scalar(func(dag, Func::Acos, arg(0), arg(0))),
                Builtin::Atan => Value::Scalar(func(dag, Func::Atan, arg(0), arg(0))),
                Builtin::Abs => Value::Scalar(func(dag, Func::Abs, arg(0), arg(0))),
                Builtin::Atan2 => Value::Scalar(func(dag, Func::Atan2, arg(0), arg(1))),
                Builtin::Hypot => Value::Scalar(func(dag, Func::Hypot, arg(0), arg(1))),
                // A constant, not a call (the checker says so).
                Builtin::Pi => Value::Scalar(dag.constant(0.0)),
            }
        }
    }
}

fn func(dag: &mut Dag, f: Func, a: Value, b: Value) -> NodeId {
    let (a, b) = (scalar(a), scalar(b));
    dag.func(f, a, b)
}

/// cos and sin of `t`, sums and differences expanded by the addition theorems, so that only sines
/// and cosines of single variables (and of other non-sums) remain: `e(q2 - alpha)` becomes
/// `(cos q2 cos α + sin q2 sin α, sin q2 cos α − cos q2 sin α)`. The generated solvers keep the
/// sines and cosines of the unknowns up to date during Newton and share them between stages, so
/// they call `sin_cos` once per angle per solve.
fn cos_sin(dag: &mut Dag, t: NodeId) -> (NodeId, NodeId) {
    match dag.node(t) {
        Node::Add(a, b) | Node::Sub(a, b) => {
            let plus = matches!(dag.node(t), Node::Add(..));
            let ((ca, sa), (cb, sb)) = (cos_sin(dag, a), cos_sin(dag, b));
            let (cc, ss) = (dag.mul(ca, cb), dag.mul(sa, sb));
            let (sc, cs) = (dag.mul(sa, cb), dag.mul(ca, sb));
            if plus {
                (dag.sub(cc, ss), dag.add(sc, cs))
            } else {
                (dag.add(cc, ss), dag.sub(sc, cs))
            }
        }
        Node::Neg(a) => {
            let (c, s) = cos_sin(dag, a);
            (c, dag.neg(s))
        }
        _ => (dag.cos(t), dag.sin(t)),
    }
}

fn binary(dag: &mut Dag, op: BinOp, a: Value, b: Value) -> Value {
    use Value::{Scalar as S, Vector as V};
    match (op, a, b) {
        (BinOp::Add, S(x), S(y)) => S(dag.add(x, y)),
        (BinOp::Sub, S(x), S(y)) => S(dag.sub(x, y)),
        (BinOp::Mul, S(x), S(y)) => S(dag.mul(x, y)),
        (BinOp::Div, S(x), S(y)) => S(dag.div(x, y)),
        (BinOp::Add | BinOp::Sub, a, b) => {
            let ((ax, ay), (bx, by)) = (as_vector(dag, a), as_vector(dag, b));
            if op == BinOp::Add {
                V(dag.add(ax, bx), dag.add(ay, by))
            } else {
                V(dag.sub(ax, bx), dag.sub(ay, by))
            }
        }
        (BinOp::Mul, S(s), V(x, y)) | (BinOp::Mul, V(x, y), S(s)) => {
            V(dag.mul(s, x), dag.mul(s, y))
        }
        (BinOp::Div, V(x, y), S(s)) => V(dag.div(x, s), dag.div(y, s)),
        // Rejected by the checker (vector × vector, division by a vector).
        (_, a, _) => a,
    }
}

/// One side of a loop drawn as a chain of joints: the loop `Σ a − Σ b = 0` gives the chains
/// `a₁, a₁+a₂, …` and `b₁, b₁+b₂, …`, both from the origin, constant terms (ground offsets) first.
/// Used to draw the mechanism; nodes live in the system's DAG.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    /// Joint positions, the origin first.
    pub vertices: Vec<[NodeId; 2]>,
    /// How many leading segments are ground (constant terms).
    pub ground_segments: usize,
}

/// The drawing chains of every loop (two per loop: its added and its subtracted terms).
///
/// Loops are usually written as a path out from the origin, then back (`A + AB + BC − DC − AD`),
/// so the subtracted terms are taken in reverse order: `AD`, then `DC`.
pub fn chains(model: &Model, dag: &mut Dag) -> Vec<Chain> {
    let mut out = Vec::new();
    for l in &model.loops {
        let mut terms = Vec::new();
        flatten(l, true, &mut terms);
        let (plus, mut minus): (Vec<_>, Vec<_>) = terms.into_iter().partition(|(_, s)| *s);
        minus.reverse();
        for side in [plus, minus] {
            let lowered: Vec<([NodeId; 2], bool)> = side
                .into_iter()
                .map(|(e, _)| {
                    let v = vector(dag, model, e);
                    let ground = v
                        .iter()
                        .all(|&c| dag.vars_of(c).iter().all(|var| matches!(var, Var::P(_))));
                    (v, ground)
                })
                .collect();
            let ground_segments = lowered.iter().filter(|(_, g)| *g).count();
            let zero = dag.constant(0.0);
            let mut at = [zero, zero];
            let mut vertices = vec![at];
            // Ground offsets first, then the moving links in their written order.
            for (v, _) in lowered
                .iter()
                .filter(|(_, g)| *g)
                .chain(lowered.iter().filter(|(_, g)| !*g))
            {
                at = [dag.add(at[0], v[0]), dag.add(at[1], v[1])];
                vertices.push(at);
            }
            if vertices.len() > 1 {
                out.push(Chain {
                    vertices,
                    ground_segments,
                });
            }
        }
    }
    out
}

/// The terms of a sum with their signs (`true` = added).
fn flatten<'e>(e: &'e Expr, sign: bool, out: &mut Vec<(&'e Expr, bool)>) {
    match &e.kind {
        ExprKind::Binary(BinOp::Add, a, b) => {
            flatten(a, sign, out);
            flatten(b, sign, out);
        }
        ExprKind::Binary(BinOp::Sub, a, b) => {
            flatten(a, sign, out);
            flatten(b, !sign, out);
        }
        ExprKind::Neg(a) => flatten(a, !sign, out),
        _ => out.push((e, sign)),
    }
}
