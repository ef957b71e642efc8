//! Stage 3 data structure: a hash-consed expression DAG (egg's `RecExpr` + memo idea). Children are
//! always inserted before parents and equal nodes are stored once, so node order is a valid
//! evaluation order and sharing (CSE) falls out of insertion. Constructors simplify as they go, to
//! one canonical form up to sign: operands of `+` and `*` by id, a difference `a - b` with a < b
//! (its negative is `-(a - b)`), negations pulled out of products and sums of negatives.

use std::collections::HashMap;

/// Index of a node in a [`Dag`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeId(pub u32);

impl NodeId {
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A variable of the kinematic system. `X` inputs, `Q` unknowns, `P` params; `d` one time
/// derivative, `dd` two.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Var {
    X(u16),
    Q(u16),
    P(u16),
    Xd(u16),
    Qd(u16),
    Xdd(u16),
    Qdd(u16),
}

impl Var {
    /// d/dt of this variable, if it is not constant in time.
    pub fn rate(self) -> Option<Var> {
        match self {
            Var::X(i) => Some(Var::Xd(i)),
            Var::Q(i) => Some(Var::Qd(i)),
            Var::Xd(i) => Some(Var::Xdd(i)),
            Var::Qd(i) => Some(Var::Qdd(i)),
            Var::P(_) | Var::Xdd(_) | Var::Qdd(_) => None,
        }
    }
}

/// A function that only derived params use (`asin`, …, from the file's params-only built-ins): its
/// arguments hold params only, never a coordinate, so it is constant during a solve.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Func {
    Asin,
    Acos,
    Atan,
    Abs,
    /// `atan2(y, x)`: the first argument is y.
    Atan2,
    Hypot,
}

impl Func {
    pub fn arity(self) -> usize {
        match self {
            Func::Atan2 | Func::Hypot => 2,
            Func::Asin | Func::Acos | Func::Atan | Func::Abs => 1,
        }
    }

    /// Its value (`b` is ignored by the one-argument functions).
    pub fn eval(self, a: f64, b: f64) -> f64 {
        match self {
            Func::Asin => a.asin(),
            Func::Acos => a.acos(),
            Func::Atan => a.atan(),
            Func::Abs => a.abs(),
            Func::Atan2 => a.atan2(b),
            Func::Hypot => a.hypot(b),
        }
    }

    /// The method of `Real` (and of f64) that computes it on the first argument.
    pub fn method(self) -> &'static str {
        match self {
            Func::Asin => "asin",
            Func::Acos => "acos",
            Func::Atan => "atan",
            Func::Abs => "abs",
            Func::Atan2 => "atan2",
            Func::Hypot => "hypot",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    /// An f64 constant, stored by its bits (so it can be hashed).
    Const(u64),
    Var(Var),
    Add(NodeId, NodeId),
    Sub(NodeId, NodeId),
    Mul(NodeId, NodeId),
    Div(NodeId, NodeId),
    Neg(NodeId),
    Sin(NodeId),
    Cos(NodeId),
    Tan(NodeId),
    Sqrt(NodeId),
    /// A params-only function; a one-argument function stores its argument twice.
    Func(Func, NodeId, NodeId),
}

impl Node {
    pub fn children(&self) -> impl Iterator<Item = NodeId> {
        let (a, b) = match *self {
            Node::Const(_) | Node::Var(_) => (None, None),
            Node::Add(a, b) | Node::Sub(a, b) | Node::Mul(a, b) | Node::Div(a, b) => {
                (Some(a), Some(b))
            }
            Node::Neg(a) | Node::Sin(a) | Node::Cos(a) | Node::Tan(a) | Node::Sqrt(a) => {
                (Some(a), None)
            }
            Node::Func(f, a, b) => (Some(a), (f.arity() == 2).then_some(b)),
        };
        a.into_iter().chain(b)
    }
}

/// The expression DAG of one mechanism.
#[derive(Clone, Debug, Default)]
pub struct Dag {
    nodes: Vec<Node>,
    memo: HashMap<Node, NodeId>,
}

impl Dag {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    pub fn node(&self, id: NodeId) -> Node {
        self.nodes[id.index()]
    }

    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// The node `n`, if the DAG holds it.
    pub fn find(&self, n: &Node) -> Option<NodeId> {
        self.memo.get(n).copied()
    }

    fn insert(&mut self, n: Node) -> NodeId {
        if let Some(&id) = self.memo.get(&n) {
            return id;
        }
        let id = NodeId(self.nodes.len() as u32);
        self.nodes.push(n);
        self.memo.insert(n, id);
        id
    }

    pub fn constant(&mut self, x: f64) -> NodeId {
        // -0.0 and 0.0 are one constant.
        let x = if x == 0.0 { 0.0 } else { x };
        self.insert(Node::Const(x.to_bits()))
    }

    pub fn var(&mut self, v: Var) -> NodeId {
        self.insert(Node::Var(v))
    }

    pub fn as_const(&self, id: NodeId) -> Option<f64> {
        match self.node(id) {
            Node::Const(b) => Some(f64::from_bits(b)),
            _ => None,
        }
    }

    pub fn is_zero(&self, id: NodeId) -> bool {
        self.as_const(id) == Some(0.0)
    }

    fn is_const(&self, id: NodeId, x: f64) -> bool {
        self.as_const(id) == Some(x)
    }

    pub fn add(&mut self, a: NodeId, b: NodeId) -> NodeId {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x + y),
            (Some(x), _) if x == 0.0 => return b,
            (_, Some(y)) if y == 0.0 => return a,
            _ => {}
        }
        // a + (-b) = a - b
        if let Node::Neg(nb) = self.node(b) {
            return self.sub(a, nb);
        }
        if let Node::Neg(na) = self.node(a) {
            return self.sub(b, na);
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        self.insert(Node::Add(a, b))
    }

    pub fn sub(&mut self, a: NodeId, b: NodeId) -> NodeId {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x - y),
            (Some(x), _) if x == 0.0 => return self.neg(b),
            (_, Some(y)) if y == 0.0 => return a,
            _ => {}
        }
        if a == b {
            return self.constant(0.0);
        }
        if let Node::Neg(nb) = self.node(b) {
            return self.add(a, nb);
        }
        // -x - b = -(x + b)
        if let Node::Neg(na) = self.node(a) {
            let s = self.add(na, b);
            return self.neg(s);
        }
        // One node for a difference and its negative: `a - b` with a < b, else `-(b - a)`, so
        // that no function computes both `a - b` and `b - a`.
        if a > b {
            let d = self.insert(Node::Sub(b, a));
            return self.insert(Node::Neg(d));
        }
        self.insert(Node::Sub(a, b))
    }

    pub fn mul(&mut self, a: NodeId, b: NodeId) -> NodeId {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x * y),
            (Some(x), _) if x == 0.0 => return a,
            (_, Some(y)) if y == 0.0 => return b,
            (Some(x), _) if x == 1.0 => return b,
            (_, Some(y)) if y == 1.0 => return a,
            (Some(x), _) if x == -1.0 => return self.neg(b),
            (_, Some(y)) if y == -1.0 => return self.neg(a),
            _ => {}
        }
        // A negative constant factor is a negation: `-2 * x` is `-(2 * x)`.
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), None) if x < 0.0 => {
                let (c, m) = (self.constant(-x), b);
                let p = self.mul(c, m);
                return self.neg(p);
            }
            (None, Some(y)) if y < 0.0 => {
                let (c, m) = (self.constant(-y), a);
                let p = self.mul(m, c);
                return self.neg(p);
            }
            _ => {}
        }
        // Pull negations out so that a product and its negative share one node.
        match (self.node(a), self.node(b)) {
            (Node::Neg(x), Node::Neg(y)) => return self.mul(x, y),
            (Node::Neg(x), _) => {
                let m = self.mul(x, b);
                return self.neg(m);
            }
            (_, Node::Neg(y)) => {
                let m = self.mul(a, y);
                return self.neg(m);
            }
            _ => {}
        }
        // Constants first, then by id: one canonical order for a commutative product.
        let (a, b) = match (self.as_const(a), self.as_const(b)) {
            (None, Some(_)) => (b, a),
            (Some(_), None) => (a, b),
            _ if a <= b => (a, b),
            _ => (b, a),
        };
        self.insert(Node::Mul(a, b))
    }

    pub fn div(&mut self, a: NodeId, b: NodeId) -> NodeId {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) if y != 0.0 => return self.constant(x / y),
            (Some(x), _) if x == 0.0 => return a,
            (_, Some(y)) if y == 1.0 => return a,
            (_, Some(y)) if y == -1.0 => return self.neg(a),
            _ => {}
        }
        if let Node::Neg(x) = self.node(a) {
            let d = self.div(x, b);
            return self.neg(d);
        }
        self.insert(Node::Div(a, b))
    }

    pub fn neg(&mut self, a: NodeId) -> NodeId {
        match self.node(a) {
            Node::Const(b) => self.constant(-f64::from_bits(b)),
            Node::Neg(x) => x,
            _ => self.insert(Node::Neg(a)),
        }
    }

    pub fn sin(&mut self, a: NodeId) -> NodeId {
        match self.as_const(a) {
            Some(x) => self.constant(x.sin()),
            None => self.insert(Node::Sin(a)),
        }
    }

    pub fn cos(&mut self, a: NodeId) -> NodeId {
        match self.as_const(a) {
            Some(x) => self.constant(x.cos()),
            None => self.insert(Node::Cos(a)),
        }
    }

    pub fn tan(&mut self, a: NodeId) -> NodeId {
        match self.as_const(a) {
            Some(x) => self.constant(x.tan()),
            None => self.insert(Node::Tan(a)),
        }
    }

    pub fn sqrt(&mut self, a: NodeId) -> NodeId {
        match self.as_const(a) {
            Some(x) if x >= 0.0 => self.constant(x.sqrt()),
            _ => self.insert(Node::Sqrt(a)),
        }
    }

    /// `f(a)` or `f(a, b)` (pass `a` twice for a one-argument function); folded when the
    /// arguments are constants and the value is finite.
    pub fn func(&mut self, f: Func, a: NodeId, b: NodeId) -> NodeId {
        let b = if f.arity() == 1 { a } else { b };
        if let (Some(x), Some(y)) = (self.as_const(a), self.as_const(b)) {
            let v = f.eval(x, y);
            if v.is_finite() {
                return self.constant(v);
            }
        }
        self.insert(Node::Func(f, a, b))
    }

    /// Whether `id` is `1.0` (used by emitters to drop `* 1`).
    pub fn is_one(&self, id: NodeId) -> bool {
        self.is_const(id, 1.0)
    }

    /// The variables an expression depends on, sorted.
    pub fn vars_of(&self, id: NodeId) -> Vec<Var> {
        let mut seen = vec![false; self.nodes.len()];
        let mut stack = vec![id];
        let mut out = Vec::new();
        while let Some(n) = stack.pop() {
            if std::mem::replace(&mut seen[n.index()], true) {
                continue;
            }
            match self.node(n) {
                Node::Var(v) => out.push(v),
                node => stack.extend(node.children()),
            }
        }
        out.sort();
        out
    }

    /// Evaluates nodes `0..=max(roots)` in f64 for the given variable values; returns all values.
    pub fn eval(&self, roots: &[NodeId], var: &dyn Fn(Var) -> f64) -> Vec<f64> {
        let end = roots.iter().map(|r| r.index() + 1).max().unwrap_or(0);
        let mut v: Vec<f64> = Vec::with_capacity(end);
        for n in &self.nodes[..end] {
            let g = |i: NodeId| v[i.index()];
            let x = match *n {
                Node::Const(b) => f64::from_bits(b),
                Node::Var(x) => var(x),
                Node::Add(a, b) => g(a) + g(b),
                Node::Sub(a, b) => g(a) - g(b),
                Node::Mul(a, b) => g(a) * g(b),
                Node::Div(a, b) => g(a) / g(b),
                Node::Neg(a) => -g(a),
                Node::Sin(a) => g(a).sin(),
                Node::Cos(a) => g(a).cos(),
                Node::Tan(a) => g(a).tan(),
                Node::Sqrt(a) => g(a).sqrt(),
                Node::Func(f, a, b) => f.eval(g(a), g(b)),
            };
            v.push(x);
        }
        v
    }
}
