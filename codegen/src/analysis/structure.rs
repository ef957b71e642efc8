//! Stage 5: structure of the Jacobian. Matches equations to unknowns (augmenting paths) and orders
//! the matched graph block-triangular (Tarjan's strongly connected components), so that solvers
//! work block by block, each block needing only unknowns of the blocks before it.

use crate::ir::lower::Equation;
use crate::sema::resolved::UnknownId;

/// A diagonal block of its mechanism (index into `Compiled::blocks`, in solve order).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BlockId(pub u16);

impl BlockId {
    /// The id of block `i` (a mechanism has fewer blocks than unknowns, which the parser caps).
    pub fn new(i: usize) -> Self {
        BlockId(i as u16)
    }
    pub fn index(self) -> usize {
        usize::from(self.0)
    }
}

/// One diagonal block: the equations and the unknowns it solves, both sorted.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Block {
    pub equations: Vec<Equation>,
    pub unknowns: Vec<UnknownId>,
}

/// Why the system is structurally singular.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum StructureError {
    /// Equations that depend on no unknown.
    EmptyEquations(Vec<usize>),
    /// Unknowns that appear in no equation.
    UnusedUnknowns(Vec<usize>),
    /// No perfect matching: these unknowns could not be given an equation of their own.
    Unmatched(Vec<usize>),
}

/// `incidence[i]` lists the unknowns equation `i` depends on. Returns the blocks in solve order.
pub fn blocks(incidence: &[Vec<usize>], n_unknowns: usize) -> Result<Vec<Block>, StructureError> {
    let empty: Vec<usize> = (0..incidence.len())
        .filter(|&i| incidence[i].is_empty())
        .collect();
    if !empty.is_empty() {
        return Err(StructureError::EmptyEquations(empty));
    }
    let unused: Vec<usize> = (0..n_unknowns)
        .filter(|&k| !incidence.iter().any(|row| row.contains(&k)))
        .collect();
    if !unused.is_empty() {
        return Err(StructureError::UnusedUnknowns(unused));
    }
    let eq_of = matching(incidence, n_unknowns);
    let unmatched: Vec<usize> = (0..n_unknowns).filter(|&k| eq_of[k].is_none()).collect();
    if !unmatched.is_empty() || incidence.len() != n_unknowns {
        return Err(StructureError::Unmatched(unmatched));
    }
    // Equation i depends on equation eq_of[k] for each unknown k it uses.
    let graph: Vec<Vec<usize>> = incidence
        .iter()
        .map(|row| row.iter().filter_map(|&k| eq_of[k]).collect())
        .collect();
    let mut unknown_of = vec![0; incidence.len()];
    for (k, e) in eq_of.iter().enumerate() {
        if let Some(e) = e {
            unknown_of[*e] = k;
        }
    }
    Ok(tarjan(&graph)
        .into_iter()
        .map(|mut eqs| {
            eqs.sort_unstable();
            let mut unknowns: Vec<UnknownId> =
                eqs.iter().map(|&e| UnknownId::new(unknown_of[e])).collect();
            unknowns.sort_unstable();
            Block {
                equations: eqs.into_iter().map(Equation).collect(),
                unknowns,
            }
        })
        .collect())
}

/// Maximum bipartite matching; `result[k]` is the equation matched to unknown `k`.
fn matching(incidence: &[Vec<usize>], n_unknowns: usize) -> Vec<Option<usize>> {
    fn augment(
        i: usize,
        inc: &[Vec<usize>],
        seen: &mut [bool],
        eq_of: &mut [Option<usize>],
    ) -> bool {
        for &k in &inc[i] {
            if k >= seen.len() || std::mem::replace(&mut seen[k], true) {
                continue;
            }
            if eq_of[k].is_none_or(|j| augment(j, inc, seen, eq_of)) {
                eq_of[k] = Some(i);
                return true;
            }
        }
        false
    }
    let mut eq_of = vec![None; n_unknowns];
    for i in 0..incidence.len() {
        let mut seen = vec![false; n_unknowns];
        augment(i, incidence, &mut seen, &mut eq_of);
    }
    eq_of
}

/// Strongly connected components, each emitted after every component it reaches (dependencies
/// first). Iterative, deterministic in vertex order.
fn tarjan(graph: &[Vec<usize>]) -> Vec<Vec<usize>> {
    let n = graph.len();
    let (mut index, mut low, mut on_stack) = (vec![usize::MAX; n], vec![0; n], vec![false; n]);
    let (mut stack, mut out, mut counter) = (Vec::new(), Vec::new(), 0);
    for root in 0..n {
        if index[root] != usize::MAX {
            continue;
        }
        let mut work = vec![(root, 0usize)];
        while let Some(&mut (v, ref mut next)) = work.last_mut() {
            if *next == 0 {
                index[v] = counter;
                low[v] = counter;
                counter += 1;
                stack.push(v);
                on_stack[v] = true;
            }
            if let Some(&w) = graph[v].get(*next) {
                *next += 1;
                if index[w] == usize::MAX {
                    work.push((w, 0));
                } else if on_stack[w] {
                    low[v] = low[v].min(index[w]);
                }
                continue;
            }
            work.pop();
            if let Some(&(parent, _)) = work.last() {
                low[parent] = low[parent].min(low[v]);
            }
            if low[v] == index[v] {
                let mut comp = Vec::new();
                while let Some(w) = stack.pop() {
                    on_stack[w] = false;
                    comp.push(w);
                    if w == v {
                        break;
                    }
                }
                out.push(comp);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_sixbar_is_two_2x2_blocks() {
        // loop 1 (eqs 0, 1) in q2, q3; loop 2 (eqs 2, 3) in q2, q5, q6.
        let inc = vec![vec![0, 1], vec![0, 1], vec![0, 2, 3], vec![0, 2, 3]];
        let b = blocks(&inc, 4).unwrap();
        assert_eq!(
            b,
            vec![
                Block {
                    equations: vec![Equation(0), Equation(1)],
                    unknowns: vec![UnknownId(0), UnknownId(1)]
                },
                Block {
                    equations: vec![Equation(2), Equation(3)],
                    unknowns: vec![UnknownId(2), UnknownId(3)]
                },
            ]
        );
    }

    #[test]
    fn dyad_driven_sixbar_is_one_4x4_block() {
        // unknowns q1, q2, q3, q5: loop 1 in q1, q2, q3; loop 2 in q1, q2, q5.
        let inc = vec![vec![0, 1, 2], vec![0, 1, 2], vec![0, 1, 3], vec![0, 1, 3]];
        let b = blocks(&inc, 4).unwrap();
        assert_eq!(b.len(), 1);
        assert_eq!(b[0].unknowns, [0, 1, 2, 3].map(UnknownId));
    }

    #[test]
    fn dependencies_come_first_whatever_the_order() {
        // eq 0 needs unknown 1 solved by eq 1 alone.
        let inc = vec![vec![0, 1], vec![1]];
        let b = blocks(&inc, 2).unwrap();
        assert_eq!(b[0].equations, [Equation(1)]);
        assert_eq!(b[1].equations, [Equation(0)]);
    }

    #[test]
    fn structural_errors() {
        assert_eq!(
            blocks(&[vec![0], vec![]], 2),
            Err(StructureError::EmptyEquations(vec![1]))
        );
        assert_eq!(
            blocks(&[vec![0], vec![0]], 2),
            Err(StructureError::UnusedUnknowns(vec![1]))
        );
        assert_eq!(
            blocks(&[vec![0], vec![0], vec![1, 2]], 3),
            Err(StructureError::Unmatched(vec![2]))
        );
    }
}
