//! What analysis hands on ([`Compiled`]): one mechanism through every stage, its model, lowered
//! system, derivatives, blocks in solve order and scene plans; what code generation and the
//! generic engine read.

use super::plan::BlockForms;
use super::scene::ScenePlan;
use super::structure::BlockId;
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
    pub blocks: Vec<BlockForms>,
    /// The plan of each of the mechanism's scenes, in file order (computed once, here).
    pub scenes: Vec<ScenePlan>,
}

impl Compiled {
    /// Block `id`'s forms.
    pub fn block(&self, id: BlockId) -> &BlockForms {
        &self.blocks[id.index()]
    }

    /// Every block's id, in solve order.
    pub fn block_ids(&self) -> impl Iterator<Item = BlockId> + use<> {
        (0..self.blocks.len()).map(BlockId::new)
    }
}

/// The plans of every scene of the file, mechanism by mechanism, in file order (as each
/// [`Compiled`] carries them).
pub fn plan_scenes(compiled: &[Compiled]) -> Vec<ScenePlan> {
    compiled
        .iter()
        .flat_map(|c| c.scenes.iter().cloned())
        .collect()
}
