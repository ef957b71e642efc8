//! A scene's part of a loaded mechanism ([`SceneTapes`]): the scene's description, the unknowns it
//! reads and a tape of its points only (positions, then rates up to its order), built once at load
//! from the same [`ScenePlan`] as the generated scene solvers.

use mechgen_codegen::{Compiled, Dag, ScenePlan};
use mechgen_runtime::scene::SceneDescription;

use super::tape::Tape;

/// One scene's plan and its points' tape (per point: positions, then rates up to the order).
#[derive(Clone, Debug)]
pub(super) struct SceneTapes {
    pub(super) desc: SceneDescription,
    pub(super) unknowns: Vec<usize>,
    pub(super) points: Tape,
    pub(super) point_values: usize,
    /// The base params the scene's code reads: its tolerances are relative to the largest
    /// length among them (`ScenePlan::params_read`, as the generated scene's).
    pub(super) params_read: Vec<bool>,
}

impl SceneTapes {
    pub(super) fn new(c: &Compiled, dag: &Dag, plan: &ScenePlan) -> SceneTapes {
        let order = plan.order.as_number();
        let mut roots = Vec::new();
        for &p in &plan.points {
            roots.extend(c.system.points[p]);
            if order >= 1 {
                roots.extend(c.derivatives.point_velocity[p]);
            }
            if order >= 2 {
                roots.extend(c.derivatives.point_acceleration[p]);
            }
        }
        let m = &c.model;
        SceneTapes {
            desc: SceneDescription {
                name: plan.name.clone(),
                mechanism: plan.mechanism.clone(),
                order,
                blocks: plan.block_indices(),
                solved: plan.solved.clone(),
                // The generic engine computes every angle; what a generated tick skips is listed
                // all the same, so that `check` describes the scene the same way.
                angles_skipped: plan.angles_skipped.clone(),
                unknowns: plan
                    .unknowns
                    .iter()
                    .map(|&u| m.unknowns[u].name.text.clone())
                    .collect(),
                points: plan
                    .points
                    .iter()
                    .map(|&p| m.points[p].0.text.clone())
                    .collect(),
                columns: plan.columns.clone(),
            },
            unknowns: plan.unknowns.clone(),
            points: Tape::new(dag, &roots),
            point_values: roots.len(),
            params_read: plan.params_read.clone(),
        }
    }
}
