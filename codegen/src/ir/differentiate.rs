//! Stage 4: symbolic derivatives on the [`Dag`]: J = ∂Φ/∂q, Φx = ∂Φ/∂x, J̇, the velocity and
//! acceleration right-hand sides, and point velocities and accelerations. New nodes go into the
//! same DAG, so everything shares subexpressions with the residuals.

use std::collections::HashMap;

use crate::ir::dag::{Dag, Func, Node, NodeId, Var};
use crate::ir::lower::System;

/// Every derivative the emitter needs, as nodes of the system's DAG.
#[derive(Clone, Debug)]
pub struct Derivatives {
    /// `jacobian[i][k]` = ∂Φi/∂qk.
    pub jacobian: Vec<Vec<NodeId>>,
    /// `input_jacobian[i][j]` = ∂Φi/∂xj.
    pub input_jacobian: Vec<Vec<NodeId>>,
    /// d/dt of the Jacobian, in terms of (x, q, ẋ, q̇).
    pub jacobian_dot: Vec<Vec<NodeId>>,
    /// −Φx ẋ: J q̇ = velocity_rhs.
    pub velocity_rhs: Vec<NodeId>,
    /// γ = −(J̇ q̇ + Φ̇x ẋ) − Φx ẍ: J q̈ = acceleration_rhs.
    pub acceleration_rhs: Vec<NodeId>,
    /// `point_jacobian[p][c][k]` = ∂(point p, component c)/∂qk.
    pub point_jacobian: Vec<[Vec<NodeId>; 2]>,
    pub point_velocity: Vec<[NodeId; 2]>,
    pub point_acceleration: Vec<[NodeId; 2]>,
    /// `param_jacobian[i][j]` = ∂Φi/∂pj over the base params (derived params are expressions of
    /// them in the DAG, so they are differentiated through).
    pub param_jacobian: Vec<Vec<NodeId>>,
    /// `point_param_jacobian[p][c][j]` = ∂(point p, component c)/∂pj.
    pub point_param_jacobian: Vec<[Vec<NodeId>; 2]>,
    /// Each body's (Ġx, Ġy, φ̇) and (G̈x, G̈y, φ̈): its centre of mass and angle differentiated
    /// in time.
    pub body_velocity: Vec<[NodeId; 3]>,
    pub body_acceleration: Vec<[NodeId; 3]>,
}

/// Memoised partial derivatives on one DAG.
pub struct Differentiator<'a> {
    pub dag: &'a mut Dag,
    memo: HashMap<(NodeId, Var), NodeId>,
}

impl<'a> Differentiator<'a> {
    pub fn new(dag: &'a mut Dag) -> Self {
        Differentiator {
            dag,
            memo: HashMap::new(),
        }
    }

    /// ∂f/∂v.
    pub fn partial(&mut self, f: NodeId, v: Var) -> NodeId {
        if let Some(&d) = self.memo.get(&(f, v)) {
            return d;
        }
        let d = match self.dag.node(f) {
            Node::Const(_) => self.dag.constant(0.0),
            Node::Var(w) => self.dag.constant(if w == v { 1.0 } else { 0.0 }),
            Node::Add(a, b) => {
                let (da, db) = (self.partial(a, v), self.partial(b, v));
                self.dag.add(da, db)
            }
            Node::Sub(a, b) => {
                let (da, db) = (self.partial(a, v), self.partial(b, v));
                self.dag.sub(da, db)
            }
            Node::Mul(a, b) => {
                let (da, db) = (self.partial(a, v), self.partial(b, v));
                let (l, r) = (self.dag.mul(da, b), self.dag.mul(a, db));
                self.dag.add(l, r)
            }
            Node::Div(a, b) => {
                // (a/b)' = (a' − (a/b)·b') / b
                let (da, db) = (self.partial(a, v), self.partial(b, v));
                let t = self.dag.mul(f, db);
                let n = self.dag.sub(da, t);
                self.dag.div(n, b)
            }
            Node::Neg(a) => {
                let da = self.partial(a, v);
                self.dag.neg(da)
            }
            Node::Sin(a) => {
                let da = self.partial(a, v);
                let c = self.dag.cos(a);
                self.dag.mul(c, da)
            }
            Node::Cos(a) => {
                let da = self.partial(a, v);
                let s = self.dag.sin(a);
                let m = self.dag.mul(s, da);
                self.dag.neg(m)
            }
            Node::Tan(a) => {
                // (tan a)' = a' (1 + tan² a)
                let da = self.partial(a, v);
                let t2 = self.dag.mul(f, f);
                let one = self.dag.constant(1.0);
                let s = self.dag.add(one, t2);
                self.dag.mul(s, da)
            }
            Node::Sqrt(a) => {
                let da = self.partial(a, v);
                let two = self.dag.constant(2.0);
                let d = self.dag.mul(two, f);
                self.dag.div(da, d)
            }
            Node::Func(func, a, b) => self.partial_func(func, f, a, b, v),
        };
        self.memo.insert((f, v), d);
        d
    }

    /// ∂/∂v of `f = func(a, b)`. Params-only functions hold no coordinate, so this is zero for
    /// every variable the solvers differentiate by; the rules are the general ones all the same.
    fn partial_func(&mut self, func: Func, f: NodeId, a: NodeId, b: NodeId, v: Var) -> NodeId {
        let da = self.partial(a, v);
        let db = if func.arity() == 2 {
            self.partial(b, v)
        } else {
            self.dag.constant(0.0)
        };
        if self.dag.is_zero(da) && self.dag.is_zero(db) {
            return da;
        }
        let one = self.dag.constant(1.0);
        let a2 = self.dag.mul(a, a);
        match func {
            Func::Asin | Func::Acos => {
                // ±a' / √(1 − a²)
                let r = self.dag.sub(one, a2);
                let r = self.dag.sqrt(r);
                let d = self.dag.div(da, r);
                if func == Func::Asin {
                    d
                } else {
                    self.dag.neg(d)
                }
            }
            Func::Atan => {
                let r = self.dag.add(one, a2);
                self.dag.div(da, r)
            }
            Func::Abs => {
                // a' · a / |a|
                let sign = self.dag.div(a, f);
                self.dag.mul(da, sign)
            }
            Func::Atan2 => {
                // (x y' − y x') / (x² + y²) with y = a, x = b
                let (bda, adb) = (self.dag.mul(b, da), self.dag.mul(a, db));
                let num = self.dag.sub(bda, adb);
                let b2 = self.dag.mul(b, b);
                let den = self.dag.add(a2, b2);
                self.dag.div(num, den)
            }
            Func::Hypot => {
                // (a a' + b b') / hypot(a, b)
                let (ada, bdb) = (self.dag.mul(a, da), self.dag.mul(b, db));
                let num = self.dag.add(ada, bdb);
                self.dag.div(num, f)
            }
        }
    }

    /// Σ ∂f/∂v · v̇ over the time-varying variables of `f` for which `keep(v)` holds.
    pub fn time_derivative(&mut self, f: NodeId, keep: &dyn Fn(Var) -> bool) -> NodeId {
        let mut sum = self.dag.constant(0.0);
        for v in self.dag.vars_of(f) {
            let Some(rate) = v.rate() else { continue };
            if !keep(v) {
                continue;
            }
            let d = self.partial(f, v);
            let r = self.dag.var(rate);
            let term = self.dag.mul(d, r);
            sum = self.dag.add(sum, term);
        }
        sum
    }

    /// Σ a_k b_k with structural zeros skipped by the DAG's simplification.
    pub fn dot(&mut self, a: &[NodeId], b: &[NodeId]) -> NodeId {
        let mut sum = self.dag.constant(0.0);
        for (&x, &y) in a.iter().zip(b) {
            let t = self.dag.mul(x, y);
            sum = self.dag.add(sum, t);
        }
        sum
    }
}

/// Derives everything for a lowered system with `n_inputs` inputs, `n_unknowns` unknowns and
/// `n_params` base params.
pub fn differentiate(
    sys: &mut System,
    n_inputs: usize,
    n_unknowns: usize,
    n_params: usize,
) -> Derivatives {
    let residuals = sys.residuals.clone();
    let points = sys.points.clone();
    let bodies = sys.bodies.clone();
    let mut d = Differentiator::new(&mut sys.dag);
    let q: Vec<Var> = (0..n_unknowns).map(|k| Var::Q(k as u16)).collect();
    let x: Vec<Var> = (0..n_inputs).map(|j| Var::X(j as u16)).collect();
    let jacobian: Vec<Vec<NodeId>> = residuals
        .iter()
        .map(|&r| q.iter().map(|&v| d.partial(r, v)).collect())
        .collect();
    let input_jacobian: Vec<Vec<NodeId>> = residuals
        .iter()
        .map(|&r| x.iter().map(|&v| d.partial(r, v)).collect())
        .collect();
    let all = |_: Var| true;
    let jacobian_dot = jacobian
        .iter()
        .map(|row| row.iter().map(|&e| d.time_derivative(e, &all)).collect())
        .collect();
    let xd: Vec<NodeId> = (0..n_inputs)
        .map(|j| d.dag.var(Var::Xd(j as u16)))
        .collect();
    let velocity_rhs = input_jacobian
        .iter()
        .map(|row| {
            let s = d.dot(row, &xd);
            d.dag.neg(s)
        })
        .collect();
    // Φ̇ = J q̇ + Φx ẋ; its time derivative without the J q̈ term, negated, is γ.
    let not_qd = |v: Var| !matches!(v, Var::Qd(_));
    let acceleration_rhs = residuals
        .iter()
        .map(|&r| {
            let phi_dot = d.time_derivative(r, &all);
            let dd = d.time_derivative(phi_dot, &not_qd);
            d.dag.neg(dd)
        })
        .collect();
    let point_jacobian = points
        .iter()
        .map(|p| p.map(|c| q.iter().map(|&v| d.partial(c, v)).collect()))
        .collect();
    let point_velocity: Vec<[NodeId; 2]> = points
        .iter()
        .map(|p| p.map(|c| d.time_derivative(c, &all)))
        .collect();
    let point_acceleration = point_velocity
        .iter()
        .map(|p| p.map(|c| d.time_derivative(c, &all)))
        .collect();
    // Last, so that every node made above keeps its id (and the generated solvers their text).
    let p: Vec<Var> = (0..n_params).map(|j| Var::P(j as u16)).collect();
    let param_jacobian = residuals
        .iter()
        .map(|&r| p.iter().map(|&v| d.partial(r, v)).collect())
        .collect();
    let point_param_jacobian = points
        .iter()
        .map(|pt| pt.map(|c| p.iter().map(|&v| d.partial(c, v)).collect()))
        .collect();
    // The bodies' rates after everything else: a mechanism without bodies keeps its node ids.
    let body_velocity: Vec<[NodeId; 3]> = bodies
        .iter()
        .map(|b| [b.com[0], b.com[1], b.angle].map(|c| d.time_derivative(c, &all)))
        .collect();
    let body_acceleration = body_velocity
        .iter()
        .map(|v| v.map(|c| d.time_derivative(c, &all)))
        .collect();
    Derivatives {
        jacobian,
        input_jacobian,
        jacobian_dot,
        velocity_rhs,
        acceleration_rhs,
        point_jacobian,
        point_velocity,
        point_acceleration,
        param_jacobian,
        point_param_jacobian,
        body_velocity,
        body_acceleration,
    }
}
