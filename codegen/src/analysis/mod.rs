//! Stage 5 (analysis): how each mechanism is solved. [`structure`] orders the Jacobian into
//! diagonal blocks (matching, then strongly connected components); [`plan`] builds each block's
//! residual, Jacobian and rate right-hand sides and picks its position solver ([`dyad`]: the
//! closed-form blocks). The result, [`Compiled`], is what the emitters and the generic engine
//! read.

pub mod closed_form;
pub mod dyad;
pub mod plan;
pub mod scene;
pub mod structure;

use crate::ir::dag::Dag;
use crate::ir::differentiate::Derivatives;
use crate::ir::lower::System;
use crate::sema::model::Model;

/// One mechanism through every analysis stage: what code generation and the generic engine need.
#[derive(Clone, Debug)]
pub struct Compiled {
    pub model: Model,
    pub system: System,
    pub derivatives: Derivatives,
    /// The diagonal blocks in solve order, each with its forms and position solver.
    pub blocks: Vec<plan::BlockForms>,
    /// The plan of each of the mechanism's scenes, in file order (computed once, here).
    pub scenes: Vec<scene::ScenePlan>,
}

impl Compiled {
    /// Block `id`'s forms.
    pub fn block(&self, id: structure::BlockId) -> &plan::BlockForms {
        &self.blocks[id.index()]
    }

    /// Every block's id, in solve order.
    pub fn block_ids(&self) -> impl Iterator<Item = structure::BlockId> + use<> {
        (0..self.blocks.len()).map(structure::BlockId::new)
    }
}

/// The block structure of a lowered system: which unknowns each equation's row of J touches.
pub fn blocks(
    derivatives: &Derivatives,
    dag: &Dag,
    n_unknowns: usize,
) -> Result<Vec<structure::Block>, structure::StructureError> {
    let incidence: Vec<Vec<usize>> = derivatives
        .jacobian
        .iter()
        .map(|row| (0..n_unknowns).filter(|&k| !dag.is_zero(row[k])).collect())
        .collect();
    structure::blocks(&incidence, n_unknowns)
}
