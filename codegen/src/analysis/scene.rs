//! Stage 5 (analysis), after planning: what one scene needs. A pure function from a compiled
//! mechanism and one of its scenes to a [`ScenePlan`]: the blocks its outputs depend on (closed
//! transitively through the block order), the derivative orders it asks for, and its points. Both
//! engines solve a scene from this plan, so they compute the same subset.
//!
//! Invariants: `blocks` is a subsequence of the mechanism's block order (each kept block's
//! dependencies are kept and come before it); every output unknown lies in a kept block and every
//! unknown an output point reads does too.

use super::closed_form::ClosedForm;
use super::plan::BlockForms;
use super::structure::BlockId;
use crate::ir::dag::{Node, NodeId, Var};
use crate::ir::differentiate::Derivatives;
use crate::ir::lower::System;
use crate::sema::model::Model;
use crate::sema::model::Scene;
use crate::sema::resolved::UnknownId;

/// What a scene's plan reads of its mechanism's analysis (the parts of [`crate::Compiled`] that
/// exist before the scenes are planned).
pub(crate) struct Parts<'a> {
    pub model: &'a Model,
    pub system: &'a System,
    pub derivatives: &'a Derivatives,
    pub blocks: &'a [BlockForms],
}

impl Parts<'_> {
    fn block(&self, id: BlockId) -> &BlockForms {
        &self.blocks[id.index()]
    }
}

/// How far a scene differentiates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Order {
    Positions,
    Velocities,
    Accelerations,
}

impl Order {
    /// From the file's `order` (0, 1 or 2; the checker rejects anything else).
    pub fn from_file(order: u8) -> Order {
        match order {
            0 => Order::Positions,
            1 => Order::Velocities,
            _ => Order::Accelerations,
        }
    }

    pub fn as_number(self) -> u8 {
        self as u8
    }
}

/// What a scene computes, as indices into its mechanism's analysis ([`crate::Compiled`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScenePlan {
    pub name: String,
    /// The mechanism's name.
    pub mechanism: String,
    pub order: Order,
    /// Kept blocks, in solve order.
    pub blocks: Vec<BlockId>,
    /// Output unknowns, in the order the scene lists them.
    pub unknowns: Vec<usize>,
    /// Output points, in the order the scene lists them.
    pub points: Vec<usize>,
    /// Every unknown a kept block solves, in block order: what the scene's solver keeps as state.
    pub solved: Vec<usize>,
    /// The base params the scene's code reads (its length scale is over these).
    pub params_read: Vec<bool>,
    /// Per unknown, whether the scene reads its value (not only its sine and cosine).
    pub values_read: Vec<bool>,
    /// Angles whose value the scene's tick skips.
    pub angles_skipped: Vec<usize>,
    /// The scene's CSV columns after the input.
    pub columns: Vec<String>,
}

impl ScenePlan {
    /// The kept blocks' indices (for comments and run-time descriptions).
    pub fn block_indices(&self) -> Vec<usize> {
        self.blocks.iter().map(|b| b.index()).collect()
    }

    /// Every unknown a kept block solves, in block order: what the scene's solver keeps as state.
    fn find_solved_unknowns(&self, c: &Parts<'_>) -> Vec<usize> {
        self.blocks
            .iter()
            .flat_map(|&b| c.block(b).block.unknowns.iter().map(|u| u.index()))
            .collect()
    }
}

impl ScenePlan {
    /// The params the scene's code reads (`read[i]` for base param `i`): those in its kept
    /// blocks' equations and in its points' expressions. Derivatives read no other params, so
    /// these are all a scene's results depend on (its Newton tolerances too: they are relative to
    /// the largest length param it reads); a tick compares and checks only these.
    fn find_params_read(&self, c: &Parts<'_>) -> Vec<bool> {
        let mut read = vec![false; c.model.params.len()];
        let equations = self
            .blocks
            .iter()
            .flat_map(|&b| c.block(b).block.equations.iter())
            .map(|&e| c.system.residuals[e.index()]);
        let points = self.points.iter().flat_map(|&p| c.system.points[p]);
        for root in equations.chain(points) {
            for v in c.system.dag.vars_of(root) {
                if let Var::P(i) = v {
                    read[usize::from(i)] = true;
                }
            }
        }
        read
    }
}

impl ScenePlan {
    /// Per unknown: whether the scene reads its value itself, not only through its sine and
    /// cosine (an output unknown; a point, Jacobian entry, right-hand side or closed-form root of
    /// the scene's orders and kept blocks that reads it outside `sin`/`cos`; every unknown of a
    /// kept Newton block). A closed-form block may skip an angle nobody reads (only its sine and
    /// cosine are needed, to place a point on the link, say). Conservative: whole Jacobian rows of
    /// the kept equations are counted.
    fn find_values_read(&self, c: &Parts<'_>) -> Vec<bool> {
        let dag = &c.system.dag;
        let d = &c.derivatives;
        let order = self.order.as_number();
        let mut read = vec![false; c.model.unknowns.len()];
        let mut roots: Vec<NodeId> = Vec::new();
        for &u in &self.unknowns {
            read[u] = true;
        }
        for &b in &self.blocks {
            let bf = c.block(b);
            match &bf.closed_form {
                Some(cf) => roots.extend_from_slice(cf.roots()),
                None => bf
                    .block
                    .unknowns
                    .iter()
                    .for_each(|&u| read[u.index()] = true),
            }
            for &e in &bf.block.equations {
                roots.push(c.system.residuals[e.index()]);
                if order >= 1 {
                    roots.extend(&d.jacobian[e.index()]);
                    roots.extend(&d.input_jacobian[e.index()]);
                    roots.push(d.velocity_rhs[e.index()]);
                }
                if order >= 2 {
                    roots.extend(&d.jacobian_dot[e.index()]);
                    roots.push(d.acceleration_rhs[e.index()]);
                }
            }
        }
        for &p in &self.points {
            roots.extend(c.system.points[p]);
            if order >= 1 {
                roots.extend(d.point_velocity[p]);
            }
            if order >= 2 {
                roots.extend(d.point_acceleration[p]);
            }
        }
        // A walk that does not step from a sine or cosine into its unknown.
        let mut seen = vec![false; dag.len()];
        while let Some(n) = roots.pop() {
            if std::mem::replace(&mut seen[n.index()], true) {
                continue;
            }
            match dag.node(n) {
                Node::Var(Var::Q(k)) => read[usize::from(k)] = true,
                Node::Sin(a) | Node::Cos(a) if matches!(dag.node(a), Node::Var(Var::Q(_))) => {}
                node => roots.extend(node.children()),
            }
        }
        read
    }
}

impl ScenePlan {
    /// The angles of kept closed-form blocks (RRR, RRP, RPR, one angle) whose value the scene does
    /// not read ([`ScenePlan::values_read`]), in unknown order: its tick solves only their sines
    /// and cosines.
    fn find_angles_skipped(&self, c: &Parts<'_>) -> Vec<usize> {
        let read = self.find_values_read(c);
        let mut skipped: Vec<usize> = self
            .blocks
            .iter()
            .filter_map(|&b| c.block(b).closed_form.as_ref())
            .flat_map(|cf| match *cf {
                ClosedForm::Rrr(ref d) => vec![d.a, d.b],
                ClosedForm::Rrp { q, .. }
                | ClosedForm::Rpr { q, .. }
                | ClosedForm::Angle1 { q, .. } => vec![q],
                ClosedForm::Linear2 { .. } | ClosedForm::Length1 { .. } => vec![],
            })
            .filter(|&u| !read[u])
            .collect();
        skipped.sort_unstable();
        skipped
    }
}

/// The CSV column suffixes of an unknown, by order: `u`, `u_vel`, `u_acc`.
pub const UNKNOWN_SUFFIXES: [&str; 3] = ["", "_vel", "_acc"];
/// The CSV column suffixes of a point, by order (two per order).
pub const POINT_SUFFIXES: [[&str; 2]; 3] = [["_x", "_y"], ["_vx", "_vy"], ["_ax", "_ay"]];

impl ScenePlan {
    /// The output columns (interfaces.md, "Scenes on the command line"): each output unknown up
    /// to the order (`u`, `u_vel`, `u_acc`), then each point (`P_x, P_y`, `P_vx, P_vy`,
    /// `P_ax, P_ay`).
    fn find_columns(&self, c: &Parts<'_>) -> Vec<String> {
        let orders = 0..=usize::from(self.order.as_number());
        let mut cols = Vec::new();
        for &u in &self.unknowns {
            let n = &c.model.unknowns[u].name.text;
            cols.extend(
                orders
                    .clone()
                    .map(|o| format!("{n}{}", UNKNOWN_SUFFIXES[o])),
            );
        }
        for &p in &self.points {
            let n = &c.model.points[p].0.text;
            for o in orders.clone() {
                cols.extend(POINT_SUFFIXES[o].iter().map(|s| format!("{n}{s}")));
            }
        }
        cols
    }
}

/// The plan of `scene` on the compiled mechanism `c`.
pub(crate) fn plan_scene(c: &Parts<'_>, scene: &Scene) -> ScenePlan {
    let dag = &c.system.dag;
    let block_of = |k: usize| {
        c.blocks
            .iter()
            .position(|b| b.block.unknowns.contains(&UnknownId::new(k)))
            .unwrap_or(0)
    };
    let mut needed = vec![false; c.blocks.len()];
    for &u in &scene.unknowns {
        needed[block_of(u)] = true;
    }
    for &p in &scene.points {
        for coord in c.system.points[p] {
            for v in dag.vars_of(coord) {
                if let Var::Q(k) = v {
                    needed[block_of(k as usize)] = true;
                }
            }
        }
    }
    // Later blocks depend only on earlier ones: one backward pass closes the set.
    for b in (0..c.blocks.len()).rev() {
        if !needed[b] {
            continue;
        }
        for &e in &c.blocks[b].block.equations {
            for (k, &d) in c.derivatives.jacobian[e.index()].iter().enumerate() {
                if !dag.is_zero(d) {
                    needed[block_of(k)] = true;
                }
            }
        }
    }
    let mut plan = ScenePlan {
        name: scene.name.text.clone(),
        mechanism: c.model.name.text.clone(),
        order: Order::from_file(scene.order),
        blocks: (0..c.blocks.len())
            .map(BlockId::new)
            .filter(|b| needed[b.index()])
            .collect(),
        unknowns: scene.unknowns.clone(),
        points: scene.points.clone(),
        solved: Vec::new(),
        params_read: Vec::new(),
        values_read: Vec::new(),
        angles_skipped: Vec::new(),
        columns: Vec::new(),
    };
    plan.solved = plan.find_solved_unknowns(c);
    plan.params_read = plan.find_params_read(c);
    plan.values_read = plan.find_values_read(c);
    plan.angles_skipped = plan.find_angles_skipped(c);
    plan.columns = plan.find_columns(c);
    plan
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::compiled::{Compiled, plan_scenes};
    use crate::{SourceFile, analyze};

    /// The seed six-bar (four-bar block, then the dyad on E) with scenes that keep one block or
    /// both; sixbar_g (one 4×4 block) to check a single block is kept whole.
    const FILE: &str = r#"
[mechanism.sixbar]
inputs = ["q1"]
unknowns = ["q2", "q3", "q5", "q6"]
loops = [
    "l1*e(q1) + l2*e(q2) - l4 - l3*e(q3)",
    "l1*e(q1) + l2*e(q2) + l2e*e(q2 - alpha) - l5*e(q5) - l6*e(q6) - c(xg, yg)",
]
params = { l1 = 26.5, l2 = 75.0, l3 = 59.0, l4 = 87.5, l5 = 48.4, l6 = 39.0, l2e = 65.0, xg = 153.5, yg = 41.7, alpha = "deg(60)" }
points = { E = "l1*e(q1) + l2*e(q2) + l2e*e(q2 - alpha)", F = "c(xg, yg) + l6*e(q6)" }
start = { q1 = 0.0, q2 = "deg(50.1)", q3 = "deg(102.7)", q5 = "deg(117.2)", q6 = "deg(280.7)" }

[scene.e_path]
mechanism = "sixbar"
outputs = ["E"]
order = 0

[scene.rocker]
mechanism = "sixbar"
outputs = ["q3"]
order = 1

[scene.output]
mechanism = "sixbar"
outputs = ["q6", "F"]
order = 2
"#;

    fn plans() -> (Vec<Compiled>, Vec<ScenePlan>) {
        let (c, diags) = analyze(&SourceFile::new("s.toml", FILE));
        assert!(diags.iter().all(|d| !d.is_error()), "{diags:?}");
        let plans = plan_scenes(&c);
        (c, plans)
    }

    #[test]
    fn a_point_of_the_first_block_keeps_only_that_block() {
        let (c, plans) = plans();
        assert_eq!(c[0].blocks.len(), 2);
        let e = &plans[0];
        assert_eq!((e.name.as_str(), e.order), ("e_path", Order::Positions));
        assert_eq!(e.blocks, [BlockId(0)]);
        assert_eq!(e.points, vec![0]);
        assert_eq!(e.solved, vec![0, 1]);
        assert_eq!(plans[1].blocks, [BlockId(0)]);
        assert_eq!(plans[1].order, Order::Velocities);
    }

    #[test]
    fn an_output_of_a_later_block_keeps_the_blocks_it_depends_on() {
        let (_, plans) = plans();
        let out = &plans[2];
        assert_eq!(out.blocks, [BlockId(0), BlockId(1)]);
        assert_eq!(out.unknowns, vec![3]);
        assert_eq!(out.points, vec![1]);
        assert_eq!(out.order, Order::Accelerations);
        assert_eq!(out.solved.len(), 4);
    }

    #[test]
    fn columns_follow_the_order() {
        let (_, plans) = plans();
        assert_eq!(plans[0].columns, ["E_x", "E_y"]);
        assert_eq!(plans[1].columns, ["q3", "q3_vel"]);
        assert_eq!(
            plans[2].columns,
            [
                "q6", "q6_vel", "q6_acc", "F_x", "F_y", "F_vx", "F_vy", "F_ax", "F_ay"
            ]
        );
    }

    #[test]
    fn params_read_are_those_of_the_kept_equations_and_points() {
        let (c, plans) = plans();
        let names = |p: &ScenePlan| -> Vec<String> {
            let read = p.params_read.clone();
            (c[0].model.params.iter().zip(read))
                .filter(|(_, r)| *r)
                .map(|(p, _)| p.name.text.clone())
                .collect()
        };
        // E reads l2e and alpha besides the four-bar loop's lengths; the dyad's are not read.
        assert_eq!(names(&plans[0]), ["l1", "l2", "l3", "l4", "l2e", "alpha"]);
        assert_eq!(names(&plans[1]), ["l1", "l2", "l3", "l4"]);
        assert_eq!(names(&plans[2]).len(), 10);
    }

    #[test]
    fn values_read_skip_angles_read_through_sin_and_cos_only() {
        let (_, plans) = plans();
        let read = |p: &ScenePlan| p.values_read.clone();
        // E reads q2 through its sine and cosine only, and nothing reads q3: the dyad skips both.
        assert_eq!(read(&plans[0]), [false; 4]);
        // q3 is an output; its rates read sines and cosines only.
        assert_eq!(read(&plans[1]), [false, true, false, false]);
        assert_eq!(read(&plans[2]), [false, false, false, true]);
        let skipped = |p: &ScenePlan| p.angles_skipped.clone();
        assert_eq!(skipped(&plans[0]), [0, 1]);
        assert_eq!(skipped(&plans[1]), [0]);
        assert_eq!(skipped(&plans[2]), [0, 1, 2]);
    }

    #[test]
    fn an_unknown_read_outside_sin_and_cos_is_read() {
        // A point that reads q2 itself (a rolling contact's arc length, say).
        let file = FILE
            .replace(
                r#"F = "c(xg, yg) + l6*e(q6)" }"#,
                r#"F = "c(xg, yg) + l6*e(q6)", R = "c(l2*q2, 0)" }"#,
            )
            .replace(r#"outputs = ["E"]"#, r#"outputs = ["R"]"#);
        let (c, diags) = analyze(&SourceFile::new("s.toml", &file));
        assert!(diags.iter().all(|d| !d.is_error()), "{diags:?}");
        let plans = plan_scenes(&c);
        assert_eq!(plans[0].values_read.clone(), [true, false, false, false]);
    }

    #[test]
    fn kept_blocks_are_closed_under_dependencies() {
        let (c, plans) = plans();
        for p in &plans {
            for &b in &p.blocks {
                for &e in &c[0].block(b).block.equations {
                    for (k, &d) in c[0].derivatives.jacobian[e.index()].iter().enumerate() {
                        if !c[0].system.dag.is_zero(d) {
                            assert!(p.solved.contains(&k), "{p:?} needs {k}");
                        }
                    }
                }
            }
        }
    }
}
