//! Stage 5c: closed-form dyad blocks. A 2×2 block whose equations are the x and y of one loop and
//! whose unknowns are two angles entering only as `e(q_a + const)` and `e(q_b + const)` terms is a
//! dyad: `K + M_a e(q_a) + M_b e(q_b) = 0` with `K` and the rotation-scalings `M = [[p, −r], [r, p]]`
//! free of the block's unknowns. Two circles intersect there, so the generated solver computes the
//! answer directly (`mechgen::solve_dyad`) instead of iterating. Anything else stays Newton.

use std::collections::HashMap;

use crate::analysis::structure::Block;
use crate::ir::dag::{Dag, Node, NodeId, Var};
use crate::ir::lower::Equation;
use crate::sema::model::{Kind, Model};

/// A dyad block as DAG nodes: `K + M_a e(q_a) + M_b e(q_b) = 0`, `M = [[p, −r], [r, p]]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Dyad {
    /// Unknown indices of q_a and q_b.
    pub a: usize,
    pub b: usize,
    /// K, then (p, r) of M_a, then (p, r) of M_b.
    pub roots: [NodeId; 6],
}

/// The four trig nodes of a dyad: cos q_a, sin q_a, cos q_b, sin q_b.
struct Trig {
    nodes: [NodeId; 4],
    vars: [NodeId; 2],
}

/// Recognises a dyad block; `None` when the block is anything else.
pub fn dyad(dag: &mut Dag, model: &Model, residuals: &[NodeId], block: &Block) -> Option<Dyad> {
    let (&[a, b], &[ex, ey]) = (block.unknowns.as_slice(), block.equations.as_slice()) else {
        return None;
    };
    if !Equation::one_loop(ex, ey) {
        return None;
    }
    if model.unknowns[a.index()].kind != Kind::Angle
        || model.unknowns[b.index()].kind != Kind::Angle
    {
        return None;
    }
    let (va, vb) = (dag.var(Var::Q(a.0)), dag.var(Var::Q(b.0)));
    let trig = Trig {
        nodes: [dag.cos(va), dag.sin(va), dag.cos(vb), dag.sin(vb)],
        vars: [va, vb],
    };
    let (rx, ry) = (residuals[ex.index()], residuals[ey.index()]);
    let mut degrees = HashMap::new();
    if degree(dag, rx, &trig, &mut degrees)? > 1 || degree(dag, ry, &trig, &mut degrees)? > 1 {
        return None;
    }
    let mut coef = HashMap::new();
    let mut c = |dag: &mut Dag, f: NodeId, t: usize| coefficient(dag, f, trig.nodes[t], &mut coef);
    // r_x = Kx + p_a cos a − r_a sin a + …, r_y = Ky + r_a cos a + p_a sin a + …
    let (pa, ra) = (c(dag, rx, 0), c(dag, ry, 0));
    let (pa_y, ra_x) = (c(dag, ry, 1), c(dag, rx, 1));
    let (pb, rb) = (c(dag, rx, 2), c(dag, ry, 2));
    let (pb_y, rb_x) = (c(dag, ry, 3), c(dag, rx, 3));
    let rotation =
        |dag: &mut Dag, p: NodeId, p2: NodeId, r: NodeId, r2: NodeId| p == p2 && dag.neg(r) == r2;
    if !rotation(dag, pa, pa_y, ra, ra_x) || !rotation(dag, pb, pb_y, rb, rb_x) {
        return None;
    }
    if [pa, ra].iter().all(|&n| dag.is_zero(n)) || [pb, rb].iter().all(|&n| dag.is_zero(n)) {
        return None;
    }
    let mut zeroed = HashMap::new();
    let kx = without_trig(dag, rx, &trig, &mut zeroed);
    let ky = without_trig(dag, ry, &trig, &mut zeroed);
    Some(Dyad {
        a: a.index(),
        b: b.index(),
        roots: [kx, ky, pa, ra, pb, rb],
    })
}

/// Degree of `f` in the trig nodes; `None` when a block unknown appears outside them.
fn degree(dag: &Dag, f: NodeId, t: &Trig, memo: &mut HashMap<NodeId, u8>) -> Option<u8> {
    if let Some(&d) = memo.get(&f) {
        return (d != u8::MAX).then_some(d);
    }
    let d = if t.nodes.contains(&f) {
        Some(1)
    } else if t.vars.contains(&f) {
        None
    } else {
        match dag.node(f) {
            Node::Const(_) | Node::Var(_) => Some(0),
            Node::Add(x, y) | Node::Sub(x, y) => {
                Some(degree(dag, x, t, memo)?.max(degree(dag, y, t, memo)?))
            }
            Node::Mul(x, y) => Some(degree(dag, x, t, memo)? + degree(dag, y, t, memo)?),
            Node::Div(x, y) => match degree(dag, y, t, memo)? {
                0 => degree(dag, x, t, memo),
                _ => None,
            },
            Node::Neg(x) => degree(dag, x, t, memo),
            Node::Sin(x) | Node::Cos(x) | Node::Tan(x) | Node::Sqrt(x) => {
                match degree(dag, x, t, memo)? {
                    0 => Some(0),
                    _ => None,
                }
            }
            // Params only: constant.
            Node::Func(..) => Some(0),
        }
    };
    memo.insert(f, d.unwrap_or(u8::MAX));
    d
}

/// ∂f/∂t treating the node `t` as a variable (exact for `f` affine in the trig nodes).
pub(crate) fn coefficient(
    dag: &mut Dag,
    f: NodeId,
    t: NodeId,
    memo: &mut HashMap<(NodeId, NodeId), NodeId>,
) -> NodeId {
    if f == t {
        return dag.constant(1.0);
    }
    if let Some(&c) = memo.get(&(f, t)) {
        return c;
    }
    let c = match dag.node(f) {
        Node::Add(x, y) => {
            let (cx, cy) = (coefficient(dag, x, t, memo), coefficient(dag, y, t, memo));
            dag.add(cx, cy)
        }
        Node::Sub(x, y) => {
            let (cx, cy) = (coefficient(dag, x, t, memo), coefficient(dag, y, t, memo));
            dag.sub(cx, cy)
        }
        Node::Mul(x, y) => {
            let (cx, cy) = (coefficient(dag, x, t, memo), coefficient(dag, y, t, memo));
            let (l, r) = (dag.mul(cx, y), dag.mul(x, cy));
            dag.add(l, r)
        }
        Node::Div(x, y) => {
            let cx = coefficient(dag, x, t, memo);
            dag.div(cx, y)
        }
        Node::Neg(x) => {
            let cx = coefficient(dag, x, t, memo);
            dag.neg(cx)
        }
        _ => dag.constant(0.0),
    };
    memo.insert((f, t), c);
    c
}

/// `f` with the trig nodes set to zero.
fn without_trig(dag: &mut Dag, f: NodeId, t: &Trig, memo: &mut HashMap<NodeId, NodeId>) -> NodeId {
    zeroed(dag, f, &t.nodes, memo)
}

/// `f` with the nodes `atoms` set to zero.
pub(crate) fn zeroed(
    dag: &mut Dag,
    f: NodeId,
    atoms: &[NodeId],
    memo: &mut HashMap<NodeId, NodeId>,
) -> NodeId {
    if atoms.contains(&f) {
        return dag.constant(0.0);
    }
    if let Some(&z) = memo.get(&f) {
        return z;
    }
    let mut sub = |dag: &mut Dag, x: NodeId| zeroed(dag, x, atoms, memo);
    let z = match dag.node(f) {
        Node::Add(x, y) => {
            let (x, y) = (sub(dag, x), sub(dag, y));
            dag.add(x, y)
        }
        Node::Sub(x, y) => {
            let (x, y) = (sub(dag, x), sub(dag, y));
            dag.sub(x, y)
        }
        Node::Mul(x, y) => {
            let (x, y) = (sub(dag, x), sub(dag, y));
            dag.mul(x, y)
        }
        Node::Div(x, y) => {
            let (x, y) = (sub(dag, x), sub(dag, y));
            dag.div(x, y)
        }
        Node::Neg(x) => {
            let x = sub(dag, x);
            dag.neg(x)
        }
        // Constants, other variables, and functions of degree 0 (checked): unchanged.
        _ => f,
    };
    memo.insert(f, z);
    z
}

#[cfg(test)]
mod tests {
    use crate::{SourceFile, analyze};

    fn dyads(loops: &str, unknowns: &str, start: &str) -> Vec<bool> {
        let text = format!(
            "[mechanism.m]\ninputs = [\"q1\"]\nunknowns = [{unknowns}]\nloops = [{loops}]\n\
             params = {{ a = 1.0, b = 3.0, k = 3.0, d = 3.5, al = 0.3 }}\nstart = {{ {start} }}\n"
        );
        let (mechs, diags) = analyze(&SourceFile::new("m.toml", text));
        assert!(diags.iter().all(|d| !d.is_error()), "{diags:?}");
        mechs[0].blocks.iter().map(|b| b.dyad.is_some()).collect()
    }

    #[test]
    fn four_bar_loops_are_dyads() {
        let start = "q1 = 0.0, q2 = 1.0, q3 = 2.0";
        let u = "\"q2\", \"q3\"";
        assert_eq!(
            dyads("\"a*e(q1) + b*e(q2) - d - k*e(q3)\"", u, start),
            [true]
        );
        // A coupler offset angle and a sum of terms on one link still make a dyad.
        assert_eq!(
            dyads(
                "\"a*e(q1) + b*e(q2) + a*e(q2 - al) - d - k*e(q3)\"",
                u,
                start
            ),
            [true]
        );
    }

    #[test]
    fn other_blocks_stay_newton() {
        let start = "q1 = 0.0, q2 = 1.0, s = 2.0";
        // A slider (a length unknown) is not a two-angle dyad.
        assert_eq!(
            dyads(
                "\"a*e(q1) + b*e(q2) - s - c(0, al)\"",
                "\"q2\", \"s\"",
                start
            ),
            [false, false]
        );
        // An unknown inside a length (q3 * e(q3)) is not affine in the link directions.
        let start = "q1 = 0.0, q2 = 1.0, q3 = 2.0";
        assert_eq!(
            dyads(
                "\"a*e(q1) + b*e(q2) - d - q3*e(q3)\"",
                "\"q2\", \"q3\"",
                start
            ),
            [false]
        );
    }
}
