//! Stage 5 (analysis), after planning: what one scene needs. A pure function from a compiled
//! mechanism and one of its scenes to a [`ScenePlan`]: the blocks its outputs depend on (closed
//! transitively through the block order), the derivative orders it asks for, and its points. Both
//! engines solve a scene from this plan, so they compute the same subset.
//!
//! Invariants: `blocks` is a subsequence of the mechanism's block order (each kept block's
//! dependencies are kept and come before it); every output unknown lies in a kept block and every
//! unknown an output point reads does too.

use super::Compiled;
use crate::ir::dag::Var;
use crate::sema::model::Scene;

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

/// What a scene computes, as indices into its mechanism's [`Compiled`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScenePlan {
    pub name: String,
    /// The mechanism's name.
    pub mechanism: String,
    pub order: Order,
    /// Kept blocks (indices into `Compiled::blocks`), in solve order.
    pub blocks: Vec<usize>,
    /// Output unknowns, in the order the scene lists them.
    pub unknowns: Vec<usize>,
    /// Output points, in the order the scene lists them.
    pub points: Vec<usize>,
}

impl ScenePlan {
    /// Every unknown a kept block solves, in block order: what the scene's solver keeps as state.
    pub fn solved_unknowns(&self, c: &Compiled) -> Vec<usize> {
        self.blocks
            .iter()
            .flat_map(|&b| c.blocks[b].block.unknowns.iter().copied())
            .collect()
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
    pub fn columns(&self, c: &Compiled) -> Vec<String> {
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
pub fn plan_scene(c: &Compiled, scene: &Scene) -> ScenePlan {
    let dag = &c.system.dag;
    let block_of = |k: usize| {
        c.blocks
            .iter()
            .position(|b| b.block.unknowns.contains(&k))
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
            for (k, &d) in c.derivatives.jacobian[e].iter().enumerate() {
                if !dag.is_zero(d) {
                    needed[block_of(k)] = true;
                }
            }
        }
    }
    ScenePlan {
        name: scene.name.text.clone(),
        mechanism: c.model.name.text.clone(),
        order: Order::from_file(scene.order),
        blocks: (0..c.blocks.len()).filter(|&b| needed[b]).collect(),
        unknowns: scene.unknowns.clone(),
        points: scene.points.clone(),
    }
}

/// The plans of every scene of the file, mechanism by mechanism, in file order.
pub fn plan_scenes(compiled: &[Compiled]) -> Vec<ScenePlan> {
    compiled
        .iter()
        .flat_map(|c| c.model.scenes.iter().map(move |s| plan_scene(c, s)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
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
        assert_eq!(e.blocks, vec![0]);
        assert_eq!(e.points, vec![0]);
        assert_eq!(e.solved_unknowns(&c[0]), vec![0, 1]);
        assert_eq!(plans[1].blocks, vec![0]);
        assert_eq!(plans[1].order, Order::Velocities);
    }

    #[test]
    fn an_output_of_a_later_block_keeps_the_blocks_it_depends_on() {
        let (c, plans) = plans();
        let out = &plans[2];
        assert_eq!(out.blocks, vec![0, 1]);
        assert_eq!(out.unknowns, vec![3]);
        assert_eq!(out.points, vec![1]);
        assert_eq!(out.order, Order::Accelerations);
        assert_eq!(out.solved_unknowns(&c[0]).len(), 4);
    }

    #[test]
    fn columns_follow_the_order() {
        let (c, plans) = plans();
        assert_eq!(plans[0].columns(&c[0]), ["E_x", "E_y"]);
        assert_eq!(plans[1].columns(&c[0]), ["q3", "q3_vel"]);
        assert_eq!(
            plans[2].columns(&c[0]),
            [
                "q6", "q6_vel", "q6_acc", "F_x", "F_y", "F_vx", "F_vy", "F_ax", "F_ay"
            ]
        );
    }

    #[test]
    fn kept_blocks_are_closed_under_dependencies() {
        let (c, plans) = plans();
        for p in &plans {
            for &b in &p.blocks {
                for &e in &c[0].blocks[b].block.equations {
                    for (k, &d) in c[0].derivatives.jacobian[e].iter().enumerate() {
                        if !c[0].system.dag.is_zero(d) {
                            assert!(p.solved_unknowns(&c[0]).contains(&k), "{p:?} needs {k}");
                        }
                    }
                }
            }
        }
    }
}
