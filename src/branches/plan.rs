//! Branch identification, the plan: how every configuration of each diagonal block is enumerated.
//! A closed-form block (codegen's classification) lists its modes with the runtime's `*_modes`
//! kernels. Any other block is torn: one angle unknown is cut, the block's other loops must then
//! be closed-form blocks in turn (classified by the same codegen stage on the sub-system), and
//! the last loop, left with one unknown, gives one scalar equation in the cut (its two components
//! linear in that unknown's cos and sin, or in the length: their compatibility). A one-angle block
//! that is not closed-form is its own cut. Anything else is "not supported".

use mechgen_codegen::{
    Block, ClosedForm, Compiled, Dag, Equation, Kind, NodeId, UnknownId, classify_closed_form,
};

use crate::generic::tape::Tape;

/// A closed-form (sub-)block and the tape of its roots (in the kind's order).
#[derive(Clone, Debug)]
pub(super) struct Form {
    pub form: ClosedForm,
    pub roots: Tape,
}

/// The last loop of a torn block, left with one unknown.
#[derive(Clone, Debug)]
pub(super) enum Last {
    /// An angle: roots `[Kx, Px, Qx, Ky, Py, Qy]` of `K + P cos q + Q sin q = 0` per component.
    Angle { q: usize, roots: Tape },
    /// A length: roots `[Kx, ax, Ky, ay]` of `K + a s = 0` per component.
    Length { s: usize, roots: Tape },
    /// The cut is the block's only unknown: its residual.
    Scalar { roots: Tape },
}

/// A torn block: the cut angle, the closed-form sub-blocks in order, the last loop.
#[derive(Clone, Debug)]
pub(super) struct Torn {
    pub cut: usize,
    pub subs: Vec<Form>,
    pub last: Last,
}

/// How one diagonal block is enumerated.
#[derive(Clone, Debug)]
pub(super) enum Step {
    Closed(Form),
    Torn(Torn),
}

/// Whether `(residual e)` depends on unknown `k`.
fn touches(c: &Compiled, e: usize, k: usize) -> bool {
    !c.system.dag.is_zero(c.derivatives.jacobian[e][k])
}

/// The plan of every block, or why a block cannot be enumerated.
pub(super) fn plan(c: &Compiled) -> Result<Vec<Step>, String> {
    let mut dag = c.system.dag.clone();
    let mut steps = Vec::new();
    for (i, b) in c.blocks.iter().enumerate() {
        if let Some(form) = &b.closed_form {
            steps.push(Step::Closed(Form {
                form: form.clone(),
                roots: Tape::new(&dag, form.roots()),
            }));
            continue;
        }
        let torn = b
            .block
            .unknowns
            .iter()
            .filter(|&&k| c.model.unknowns[k.index()].kind == Kind::Angle)
            .find_map(|&cut| tear(c, &mut dag, &b.block, cut))
            .ok_or_else(|| {
                let names: Vec<&str> = b
                    .block
                    .unknowns
                    .iter()
                    .map(|&k| c.model.unknowns[k.index()].name.text.as_str())
                    .collect();
                format!(
                    "branch identification is not supported for block {i} ({}) of `{}`: no angle \
                     cut leaves closed-form loops and one scalar equation",
                    names.join(", "),
                    c.model.name.text
                )
            })?;
        steps.push(Step::Torn(torn));
    }
    Ok(steps)
}

/// Tears `block` at the angle `cut`, or `None` when the rest is not closed-form loops.
fn tear(c: &Compiled, dag: &mut Dag, block: &Block, cut: UnknownId) -> Option<Torn> {
    let (cut, res) = (cut.index(), &c.system.residuals);
    let equations: Vec<usize> = block.equations.iter().map(|e| e.index()).collect();
    let unknowns: Vec<usize> = block.unknowns.iter().map(|u| u.index()).collect();
    if block.unknowns.len() == 1 {
        let e = block.equations[0];
        return Some(Torn {
            cut,
            subs: Vec::new(),
            last: Last::Scalar {
                roots: Tape::new(dag, &[res[e.index()]]),
            },
        });
    }
    // The block's loops: both components of each must be in the block.
    let mut loops: Vec<usize> = Vec::new();
    for &e in &equations {
        if e % 2 == 0 && equations.contains(&(e + 1)) {
            loops.push(e);
        } else if !(e % 2 == 1 && equations.contains(&(e - 1))) {
            return None;
        }
    }
    let mut solved = vec![cut];
    let mut subs = Vec::new();
    let free = |solved: &[usize], ex: usize| -> Vec<usize> {
        unknowns
            .iter()
            .copied()
            .filter(|&k| !solved.contains(&k) && (touches(c, ex, k) || touches(c, ex + 1, k)))
            .collect()
    };
    while loops.len() > 1 {
        let found = loops.iter().enumerate().find_map(|(li, &ex)| {
            let us = free(&solved, ex);
            if us.len() != 2 {
                return None;
            }
            let sub = Block {
                equations: vec![Equation(ex), Equation(ex + 1)],
                unknowns: us.iter().map(|&k| UnknownId::new(k)).collect(),
            };
            classify_closed_form(dag, &c.model, res, &sub).map(|f| (li, us, f))
        });
        let (li, us, form) = found?;
        loops.remove(li);
        solved.extend(us);
        subs.push(Form {
            roots: Tape::new(dag, form.roots()),
            form,
        });
    }
    let ex = loops[0];
    let us = free(&solved, ex);
    if us.len() != 1 || solved.len() + 1 != unknowns.len() {
        return None;
    }
    let u = us[0];
    let zero = dag.constant(0.0);
    // Each component as K + P cos u + Q sin u (angle) or K + a u (length).
    let mut roots: Vec<NodeId> = Vec::new();
    for e in [ex, ex + 1] {
        if !touches(c, e, u) {
            roots.push(res[e]);
            roots.push(zero);
            if c.model.unknowns[u].kind == Kind::Angle {
                roots.push(zero);
            }
            continue;
        }
        let one = Block {
            equations: vec![Equation(e)],
            unknowns: vec![UnknownId::new(u)],
        };
        // One unknown in one loop: the one-angle or one-length kind, whose roots are the
        // equation's coefficients.
        let form = classify_closed_form(dag, &c.model, res, &one)?;
        if form.kind().unknowns() != 1 {
            return None;
        }
        roots.extend(form.roots());
    }
    let roots = Tape::new(dag, &roots);
    let last = if c.model.unknowns[u].kind == Kind::Angle {
        Last::Angle { q: u, roots }
    } else {
        Last::Length { s: u, roots }
    };
    Some(Torn { cut, subs, last })
}
