//! Stage 5b: the per-block forms the block solvers need, built in the same DAG: for each
//! diagonal block its residual and Jacobian, and its velocity and acceleration right-hand sides
//! with the unknowns of earlier blocks already substituted as known rates.

use crate::analysis::closed_form::ClosedForm;
use crate::analysis::dyad::Dyad;
use crate::analysis::structure::Block;
use crate::ir::dag::{NodeId, Var};
use crate::ir::differentiate::{Derivatives, Differentiator};
use crate::ir::lower::System;
use crate::sema::model::Model;
use crate::sema::resolved::UnknownId;

/// Everything one diagonal block's solvers evaluate.
#[derive(Clone, Debug)]
pub struct BlockForms {
    pub block: Block,
    /// Residuals of the block's equations.
    pub residual: Vec<NodeId>,
    /// `jacobian[r][c]`: ∂(equation r of the block)/∂(unknown c of the block).
    pub jacobian: Vec<Vec<NodeId>>,
    /// J_bb q̇_b = velocity_rhs: −Φx ẋ − Σ J_bk q̇_k over the other blocks' unknowns.
    pub velocity_rhs: Vec<NodeId>,
    /// J_bb q̈_b = acceleration_rhs: γ − Σ J_bk q̈_k over the other blocks' unknowns.
    pub acceleration_rhs: Vec<NodeId>,
    /// The closed form of the positions when the block is a dyad; Newton otherwise. (What the
    /// emitters solve in closed form today; the same dyad as `closed_form`'s `Rrr`.)
    pub dyad: Option<Dyad>,
    /// The closed form of the positions when the block is of a kind the runtime solves exactly
    /// (`closed_form` stage); Newton otherwise. The generic engine solves every kind from it.
    pub closed_form: Option<ClosedForm>,
}

pub fn block_forms(
    sys: &mut System,
    model: &Model,
    der: &Derivatives,
    blocks: &[Block],
) -> Vec<BlockForms> {
    let residuals = sys.residuals.clone();
    let dyads: Vec<Option<Dyad>> = blocks
        .iter()
        .map(|b| crate::analysis::dyad::dyad(&mut sys.dag, model, &residuals, b))
        .collect();
    let mut d = Differentiator::new(&mut sys.dag);
    let n = der.jacobian.first().map_or(0, Vec::len);
    let mut forms: Vec<BlockForms> = blocks
        .iter()
        .enumerate()
        .map(|(bi, b)| {
            let others: Vec<usize> = (0..n)
                .filter(|&k| !b.unknowns.contains(&UnknownId::new(k)))
                .collect();
            let coupling = |d: &mut Differentiator, i: usize, rate: fn(u16) -> Var| -> NodeId {
                let row: Vec<NodeId> = others.iter().map(|&k| der.jacobian[i][k]).collect();
                let vars: Vec<NodeId> = others.iter().map(|&k| d.dag.var(rate(k as u16))).collect();
                d.dot(&row, &vars)
            };
            let velocity_rhs = b
                .equations
                .iter()
                .map(|&e| {
                    let c = coupling(&mut d, e.index(), Var::Qd);
                    d.dag.sub(der.velocity_rhs[e.index()], c)
                })
                .collect();
            let acceleration_rhs = b
                .equations
                .iter()
                .map(|&e| {
                    let c = coupling(&mut d, e.index(), Var::Qdd);
                    d.dag.sub(der.acceleration_rhs[e.index()], c)
                })
                .collect();
            BlockForms {
                block: b.clone(),
                residual: b.equations.iter().map(|&e| residuals[e.index()]).collect(),
                jacobian: b
                    .equations
                    .iter()
                    .map(|&e| {
                        let row = &der.jacobian[e.index()];
                        b.unknowns.iter().map(|&k| row[k.index()]).collect()
                    })
                    .collect(),
                velocity_rhs,
                acceleration_rhs,
                dyad: dyads[bi].clone(),
                closed_form: None,
            }
        })
        .collect();
    // Last, so that the nodes the classification adds come after every node the emitters read.
    for f in &mut forms {
        f.closed_form =
            crate::analysis::closed_form::closed_form(&mut sys.dag, model, &residuals, &f.block);
    }
    forms
}
