//! Stage 3: a checked [`Model`] → scalar residuals and point coordinates in a [`Dag`]: a total
//! match over the model's resolved trees (typed ids, no names). Each loop becomes two residuals
//! (x, y); a scalar term of a vector sum is the vector (s, 0).

use crate::ir::dag::{Dag, Func, Node, NodeId, Var};
use crate::sema::model::{Centre, Model};
use crate::sema::resolved::{Fn1, Fn2, Op, Scalar, Term, Vector};

/// The position-level system of one mechanism.
#[derive(Clone, Debug)]
pub struct System {
    pub dag: Dag,
    /// Residual `2*l` is the x component of loop `l`, `2*l + 1` its y component ([`Equation`]
    /// reads this layout; nothing else does).
    pub residuals: Vec<NodeId>,
    /// Each point's (x, y).
    pub points: Vec<[NodeId; 2]>,
    /// Each body's centre of mass, angle, mass and inertia (`Model::bodies` order).
    pub bodies: Vec<BodyNodes>,
    /// The acceleration of gravity (`None` without a `gravity` key: zero).
    pub gravity: Option<[NodeId; 2]>,
}

/// A body's kinematic and mass quantities as DAG nodes.
#[derive(Clone, Copy, Debug)]
pub struct BodyNodes {
    pub com: [NodeId; 2],
    pub angle: NodeId,
    pub mass: NodeId,
    pub inertia: NodeId,
}

/// Which component of its loop a scalar equation is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    X,
    Y,
}

impl Axis {
    pub fn name(self) -> &'static str {
        match self {
            Axis::X => "x",
            Axis::Y => "y",
        }
    }
}

/// A scalar equation of the system: residual `index` (the layout invariant of [`System`]:
/// residual `2 l` is loop `l`'s x component and `2 l + 1` its y component; nothing else reads
/// the layout).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Equation(pub usize);

impl Equation {
    /// The two equations of loop `l`.
    pub fn of_loop(l: usize) -> [Equation; 2] {
        [Equation(2 * l), Equation(2 * l + 1)]
    }

    /// The loop it belongs to (0-based).
    pub fn loop_index(self) -> usize {
        self.0 / 2
    }

    pub fn axis(self) -> Axis {
        if self.0.is_multiple_of(2) {
            Axis::X
        } else {
            Axis::Y
        }
    }

    /// Whether `[a, b]` are one loop's x and y, in that order.
    pub fn one_loop(a: Equation, b: Equation) -> bool {
        a.axis() == Axis::X && b == Equation(a.0 + 1)
    }

    pub fn index(self) -> usize {
        self.0
    }
}

/// A lowered expression: a scalar stays one until a vector sum reads it as (s, 0).
#[derive(Clone, Copy)]
enum Value {
    Scalar(NodeId),
    Vector(NodeId, NodeId),
}

/// Lowers a checked model: a total match over its resolved trees.
pub fn lower(model: &Model) -> System {
    let mut dag = Dag::new();
    let mut lw = Lowering {
        dag: &mut dag,
        model,
    };
    let mut residuals = Vec::with_capacity(2 * model.loop_vectors.len());
    for l in &model.loop_vectors {
        residuals.extend(lw.vector(l));
    }
    let points: Vec<[NodeId; 2]> = model.point_vectors.iter().map(|p| lw.vector(p)).collect();
    // After the points, so that a mechanism without bodies keeps every node id.
    let bodies = model
        .bodies
        .iter()
        .map(|b| BodyNodes {
            com: match &b.com {
                Centre::Point(i) => points[*i],
                Centre::Vector(v) => lw.vector(v),
            },
            angle: lw.scalar(&b.angle),
            mass: lw.scalar(&b.mass_expr),
            inertia: lw.scalar(&b.inertia_expr),
        })
        .collect();
    let gravity = model.gravity.as_ref().map(|g| lw.vector(g));
    System {
        dag,
        residuals,
        points,
        bodies,
        gravity,
    }
}

struct Lowering<'a> {
    dag: &'a mut Dag,
    model: &'a Model,
}

impl Lowering<'_> {
    /// A vector expression's components.
    fn vector(&mut self, v: &Vector) -> [NodeId; 2] {
        let value = self.vector_value(v);
        let (x, y) = self.padded(value);
        [x, y]
    }

    /// A value's components: a scalar is (s, 0).
    fn padded(&mut self, v: Value) -> (NodeId, NodeId) {
        match v {
            Value::Vector(x, y) => (x, y),
            Value::Scalar(s) => (s, self.dag.constant(0.0)),
        }
    }

    /// A vector expression, its scalar terms kept scalar until the sum that reads them pads them.
    fn vector_value(&mut self, v: &Vector) -> Value {
        match v {
            Vector::Real(s) => Value::Scalar(self.scalar(s)),
            Vector::E(t) => {
                let t = self.scalar(t);
                let (c, s) = cos_sin(self.dag, t);
                Value::Vector(c, s)
            }
            Vector::C(x, y) => Value::Vector(self.scalar(x), self.scalar(y)),
            Vector::Neg(a) => match self.vector_value(a) {
                Value::Scalar(s) => Value::Scalar(self.dag.neg(s)),
                Value::Vector(x, y) => Value::Vector(self.dag.neg(x), self.dag.neg(y)),
            },
            Vector::Add(a, b) | Vector::Sub(a, b) => {
                let (a_value, b_value) = (self.vector_value(a), self.vector_value(b));
                let ((ax, ay), (bx, by)) = (self.padded(a_value), self.padded(b_value));
                let dag = &mut *self.dag;
                if matches!(v, Vector::Add(..)) {
                    Value::Vector(dag.add(ax, bx), dag.add(ay, by))
                } else {
                    Value::Vector(dag.sub(ax, bx), dag.sub(ay, by))
                }
            }
            Vector::Scale(s, v) => {
                let s = self.scalar(s);
                let value = self.vector_value(v);
                self.scaled(s, value)
            }
            Vector::Times(v, s) => {
                let value = self.vector_value(v);
                let s = self.scalar(s);
                self.scaled(s, value)
            }
            Vector::Div(v, s) => {
                let value = self.vector_value(v);
                let s = self.scalar(s);
                let (x, y) = self.padded(value);
                Value::Vector(self.dag.div(x, s), self.dag.div(y, s))
            }
        }
    }

    fn scaled(&mut self, s: NodeId, v: Value) -> Value {
        let (x, y) = self.padded(v);
        Value::Vector(self.dag.mul(s, x), self.dag.mul(s, y))
    }

    fn scalar(&mut self, s: &Scalar) -> NodeId {
        let dag = &mut *self.dag;
        match s {
            Scalar::Number(x) => dag.constant(*x),
            Scalar::Input(i) => dag.var(Var::X(i.0)),
            Scalar::Unknown(i) => dag.var(Var::Q(i.0)),
            Scalar::Param(i) => dag.var(Var::P(i.0)),
            // A derived param is its expression of the base params (hash-consing shares it).
            Scalar::Derived(j) => {
                let model = self.model;
                self.scalar(&model.derived[j.index()].resolved)
            }
            Scalar::Neg(a) => {
                let a = self.scalar(a);
                self.dag.neg(a)
            }
            Scalar::Binary(op, a, b) => {
                let (a, b) = (self.scalar(a), self.scalar(b));
                let dag = &mut *self.dag;
                match op {
                    Op::Add => dag.add(a, b),
                    Op::Sub => dag.sub(a, b),
                    Op::Mul => dag.mul(a, b),
                    Op::Div => dag.div(a, b),
                }
            }
            Scalar::Call1(f, a) => {
                let a = self.scalar(a);
                let dag = &mut *self.dag;
                match f {
                    Fn1::Sin => cos_sin(dag, a).1,
                    Fn1::Cos => cos_sin(dag, a).0,
                    Fn1::Tan => dag.tan(a),
                    Fn1::Sqrt => dag.sqrt(a),
                    Fn1::Deg => {
                        let k = dag.constant(std::f64::consts::PI / 180.0);
                        dag.mul(k, a)
                    }
                    // Params only: in derived params, which lowering substitutes.
                    Fn1::Asin => dag.func(Func::Asin, a, a),
                    Fn1::Acos => dag.func(Func::Acos, a, a),
                    Fn1::Atan => dag.func(Func::Atan, a, a),
                    Fn1::Abs => dag.func(Func::Abs, a, a),
                }
            }
            Scalar::Call2(f, a, b) => {
                let (a, b) = (self.scalar(a), self.scalar(b));
                let f = match f {
                    Fn2::Atan2 => Func::Atan2,
                    Fn2::Hypot => Func::Hypot,
                };
                self.dag.func(f, a, b)
            }
        }
    }
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
    let mut lw = Lowering { dag, model };
    for l in &model.loop_vectors {
        let mut terms = Vec::new();
        l.terms(true, &mut terms);
        let (plus, mut minus): (Vec<_>, Vec<_>) = terms.into_iter().partition(|(_, s)| *s);
        minus.reverse();
        for side in [plus, minus] {
            let lowered: Vec<([NodeId; 2], bool)> = side
                .into_iter()
                .map(|(term, _)| {
                    let v = match term {
                        Term::Vector(v) => lw.vector(v),
                        Term::Scalar(s) => {
                            let s = lw.scalar(s);
                            [s, lw.dag.constant(0.0)]
                        }
                    };
                    let dag = &*lw.dag;
                    let ground = v
                        .iter()
                        .all(|&c| dag.vars_of(c).iter().all(|var| matches!(var, Var::P(_))));
                    (v, ground)
                })
                .collect();
            let ground_segments = lowered.iter().filter(|(_, g)| *g).count();
            let dag = &mut *lw.dag;
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
