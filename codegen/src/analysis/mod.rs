//! Stage 5 (analysis): how each mechanism is solved. [`structure`] orders the Jacobian into
//! diagonal blocks (matching, then strongly connected components); [`plan`] builds each block's
//! residual, Jacobian and rate right-hand sides and picks its position solver ([`dyad`]: the
//! closed-form blocks). The result, [`Compiled`], is what the emitters and the generic engine
//! read.

pub mod closed_form;
pub mod compiled;
pub mod dyad;
pub mod plan;
pub mod scene;
pub mod structure;

pub use compiled::Compiled;

use crate::ir::dag::Dag;
use crate::ir::differentiate::Derivatives;

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
