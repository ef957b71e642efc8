//! Stage 5c (beside `dyad`): closed-form blocks. A block of one loop's x and y in two unknowns,
//! or of one equation in one unknown, whose equations are polynomials of low degree in the
//! unknowns' sines and cosines (angles) and in the unknowns themselves (lengths), with
//! coefficients (DAG nodes) free of the block's unknowns, is one of the kinds below; the runtime
//! solves it exactly (`mechgen::closed_form`, `mechgen::solve_dyad`). Anything else stays Newton.
//!
//! | kind | equation (`e(q) = (cos q, sin q)`, `M`, `N` rotation-scalings) | roots |
//! | --- | --- | --- |
//! | `Rrr` | `K + M_a e(q_a) + M_b e(q_b) = 0` (see `dyad`) | `Kx Ky pa ra pb rb` |
//! | `Rrp` | `K + M e(q) + s u = 0` | `Kx Ky p r ux uy` |
//! | `Rpr` | `K + (M + s N) e(q) = 0` | `Kx Ky mp mr np nr` |
//! | `Linear2` | `K + s1 u1 + s2 u2 = 0` | `Kx Ky u1x u1y u2x u2y` |
//! | `Angle1` | `K + P cos q + Q sin q = 0` | `K P Q` |
//! | `Length1` | `K + a s = 0` | `K a` |

use mechgen_runtime::closed_form::ClosedKind;
use std::collections::HashMap;

use crate::analysis::dyad::{Dyad, coefficient, zeroed};
use crate::analysis::structure::Block;
use crate::ir::dag::{Dag, Node, NodeId, Var};
use crate::ir::lower::Equation;
use crate::sema::model::{Kind, Model};

/// A closed-form block; unknowns are indices into the mechanism's unknowns, roots DAG nodes at
/// the current state (free of the block's unknowns).
#[derive(Clone, Debug, PartialEq)]
pub enum ClosedForm {
    /// Two angles (a dyad).
    Rrr(Dyad),
    /// An angle and a length along a fixed direction: `K + M e(q) + s u = 0`,
    /// roots `[Kx, Ky, p, r, ux, uy]` with `M = [[p, −r], [r, p]]`.
    Rrp {
        q: usize,
        s: usize,
        roots: [NodeId; 6],
    },
    /// An angle and a length along the angle's own direction (with an offset):
    /// `K + (M + s N) e(q) = 0`, roots `[Kx, Ky, mp, mr, np, nr]`.
    Rpr {
        q: usize,
        s: usize,
        roots: [NodeId; 6],
    },
    /// Two lengths: `K + s1 u1 + s2 u2 = 0`, roots `[Kx, Ky, u1x, u1y, u2x, u2y]`.
    Linear2 {
        s1: usize,
        s2: usize,
        roots: [NodeId; 6],
    },
    /// One equation in one angle: `K + P cos q + Q sin q = 0`, roots `[K, P, Q]`.
    Angle1 { q: usize, roots: [NodeId; 3] },
    /// One equation in one length: `K + a s = 0`, roots `[K, a]`.
    Length1 { s: usize, roots: [NodeId; 2] },
}

impl ClosedForm {
    /// The DAG nodes the kernel takes, in the order of the variant's documentation.
    pub fn roots(&self) -> &[NodeId] {
        match self {
            ClosedForm::Rrr(d) => &d.roots,
            ClosedForm::Rrp { roots, .. }
            | ClosedForm::Rpr { roots, .. }
            | ClosedForm::Linear2 { roots, .. } => roots,
            ClosedForm::Angle1 { roots, .. } => roots,
            ClosedForm::Length1 { roots, .. } => roots,
        }
    }

    /// Its kind, as the runtime knows it (kernel, modes, margin).
    pub fn kind(&self) -> ClosedKind {
        match self {
            ClosedForm::Rrr(_) => ClosedKind::Rrr,
            ClosedForm::Rrp { .. } => ClosedKind::Rrp,
            ClosedForm::Rpr { .. } => ClosedKind::Rpr,
            ClosedForm::Linear2 { .. } => ClosedKind::Linear2,
            ClosedForm::Angle1 { .. } => ClosedKind::Angle1,
            ClosedForm::Length1 { .. } => ClosedKind::Length1,
        }
    }

    /// The unknowns it solves, in the kernel's order (a one-unknown kind repeats its unknown).
    pub fn slots(&self) -> [usize; 2] {
        match *self {
            ClosedForm::Rrr(ref d) => [d.a, d.b],
            ClosedForm::Rrp { q, s, .. } | ClosedForm::Rpr { q, s, .. } => [q, s],
            ClosedForm::Linear2 { s1, s2, .. } => [s1, s2],
            ClosedForm::Angle1 { q, .. } => [q, q],
            ClosedForm::Length1 { s, .. } => [s, s],
        }
    }

    /// Short name of the kind, as `mechgen check` will print it.
    pub fn name(&self) -> &'static str {
        match self {
            ClosedForm::Rrr(_) => "RRR",
            ClosedForm::Rrp { .. } => "RRP",
            ClosedForm::Rpr { .. } => "RPR",
            ClosedForm::Linear2 { .. } => "linear 2x2",
            ClosedForm::Angle1 { .. } => "one angle",
            ClosedForm::Length1 { .. } => "one length",
        }
    }
}

/// Degrees of a residual: in the atoms of block unknown 0, of unknown 1, and in all together.
type Degree = [u8; 3];

/// The atoms of the block's unknowns: `cos q`, `sin q` of an angle (whose bare variable must not
/// appear), the variable of a length.
struct Atoms {
    of: [Vec<NodeId>; 2],
    forbidden: Vec<NodeId>,
}

impl Atoms {
    fn new(dag: &mut Dag, model: &Model, unknowns: &[usize]) -> Atoms {
        let mut atoms = Atoms {
            of: [Vec::new(), Vec::new()],
            forbidden: Vec::new(),
        };
        for (slot, &k) in unknowns.iter().enumerate() {
            let v = dag.var(Var::Q(k as u16));
            if model.unknowns[k].kind == Kind::Angle {
                atoms.of[slot] = vec![dag.cos(v), dag.sin(v)];
                atoms.forbidden.push(v);
            } else {
                atoms.of[slot] = vec![v];
            }
        }
        atoms
    }

    fn all(&self) -> Vec<NodeId> {
        self.of.concat()
    }
}

/// Degree of `f` in the atoms; `None` when a block unknown appears other than through them (in a
/// denominator, a square root, a sine of a multiple, bare for an angle).
fn degree(
    dag: &Dag,
    f: NodeId,
    a: &Atoms,
    memo: &mut HashMap<NodeId, Option<Degree>>,
) -> Option<Degree> {
    if let Some(&d) = memo.get(&f) {
        return d;
    }
    let d = if let Some(slot) = (0..2).find(|&s| a.of[s].contains(&f)) {
        let mut d = [0, 0, 1];
        d[slot] = 1;
        Some(d)
    } else if a.forbidden.contains(&f) {
        None
    } else {
        let zero = |d: Degree| d == [0; 3];
        match dag.node(f) {
            Node::Const(_) | Node::Var(_) => Some([0; 3]),
            Node::Add(x, y) | Node::Sub(x, y) => {
                let (dx, dy) = (degree(dag, x, a, memo)?, degree(dag, y, a, memo)?);
                Some([0, 1, 2].map(|i| dx[i].max(dy[i])))
            }
            Node::Mul(x, y) => {
                let (dx, dy) = (degree(dag, x, a, memo)?, degree(dag, y, a, memo)?);
                Some([0, 1, 2].map(|i| dx[i].saturating_add(dy[i]).min(9)))
            }
            Node::Div(x, y) => match degree(dag, y, a, memo)? {
                dy if zero(dy) => degree(dag, x, a, memo),
                _ => None,
            },
            Node::Neg(x) => degree(dag, x, a, memo),
            Node::Sin(x) | Node::Cos(x) | Node::Tan(x) | Node::Sqrt(x) => {
                zero(degree(dag, x, a, memo)?).then_some([0; 3])
            }
            // Params only: constant.
            Node::Func(..) => Some([0; 3]),
        }
    };
    memo.insert(f, d);
    d
}

/// Coefficient extraction for one block: derivatives by atoms, atoms set to zero.
struct Extract<'a> {
    dag: &'a mut Dag,
    coef: HashMap<(NodeId, NodeId), NodeId>,
}

impl Extract<'_> {
    fn d(&mut self, f: NodeId, t: NodeId) -> NodeId {
        coefficient(self.dag, f, t, &mut self.coef)
    }

    fn at_zero(&mut self, f: NodeId, atoms: &[NodeId]) -> NodeId {
        // One memo per atom set; sets differ between calls.
        zeroed(self.dag, f, atoms, &mut HashMap::new())
    }

    /// `(p, r)` when `(cx, cy)` (coefficients of cos) and `(sx, sy)` (of sin) form `M e(q)`.
    fn rotation(
        &mut self,
        (cx, cy): (NodeId, NodeId),
        (sx, sy): (NodeId, NodeId),
    ) -> Option<(NodeId, NodeId)> {
        (cy == self.dag.neg(sx) && sy == cx).then_some((cx, cy))
    }
}

/// Recognises a closed-form block; `None` when the block must be solved by Newton.
pub fn closed_form(
    dag: &mut Dag,
    model: &Model,
    residuals: &[NodeId],
    block: &Block,
) -> Option<ClosedForm> {
    let kinds: Vec<Kind> = block
        .unknowns
        .iter()
        .map(|&k| model.unknowns[k.index()].kind)
        .collect();
    let residual = |e: Equation| residuals[e.index()];
    match (block.unknowns.as_slice(), block.equations.as_slice()) {
        (&[k], &[e]) => one(dag, model, residual(e), k.index()),
        (&[a, b], &[ex, ey]) if Equation::one_loop(ex, ey) => match (kinds[0], kinds[1]) {
            (Kind::Angle, Kind::Angle) => {
                crate::analysis::dyad::dyad(dag, model, residuals, block).map(ClosedForm::Rrr)
            }
            (Kind::Length, Kind::Length) => linear2(
                dag,
                model,
                [residual(ex), residual(ey)],
                [a.index(), b.index()],
            ),
            (Kind::Angle, Kind::Length) => angle_length(
                dag,
                model,
                [residual(ex), residual(ey)],
                a.index(),
                b.index(),
            ),
            (Kind::Length, Kind::Angle) => angle_length(
                dag,
                model,
                [residual(ex), residual(ey)],
                b.index(),
                a.index(),
            ),
            // A kind the runtime may add later has no closed form.
            _ => None,
        },
        _ => None,
    }
}

/// Degrees of both residuals, the largest of each.
fn degrees(dag: &Dag, fs: &[NodeId], atoms: &Atoms) -> Option<Degree> {
    let mut memo = HashMap::new();
    let mut out = [0; 3];
    for &f in fs {
        let d = degree(dag, f, atoms, &mut memo)?;
        out = [0, 1, 2].map(|i| out[i].max(d[i]));
    }
    Some(out)
}

fn one(dag: &mut Dag, model: &Model, f: NodeId, k: usize) -> Option<ClosedForm> {
    let atoms = Atoms::new(dag, model, &[k]);
    if degrees(dag, &[f], &atoms)?[2] > 1 {
        return None;
    }
    let all = atoms.all();
    let mut x = Extract {
        dag,
        coef: HashMap::new(),
    };
    let konst = x.at_zero(f, &all);
    let c: Vec<NodeId> = all.iter().map(|&t| x.d(f, t)).collect();
    if c.iter().all(|&n| x.dag.is_zero(n)) {
        return None;
    }
    Some(if model.unknowns[k].kind == Kind::Angle {
        ClosedForm::Angle1 {
            q: k,
            roots: [konst, c[0], c[1]],
        }
    } else {
        ClosedForm::Length1 {
            s: k,
            roots: [konst, c[0]],
        }
    })
}

fn linear2(
    dag: &mut Dag,
    model: &Model,
    fs: [NodeId; 2],
    [a, b]: [usize; 2],
) -> Option<ClosedForm> {
    let atoms = Atoms::new(dag, model, &[a, b]);
    if degrees(dag, &fs, &atoms)?[2] > 1 {
        return None;
    }
    let all = atoms.all();
    let mut x = Extract {
        dag,
        coef: HashMap::new(),
    };
    let [kx, ky] = fs.map(|f| x.at_zero(f, &all));
    let [u1x, u1y] = fs.map(|f| x.d(f, all[0]));
    let [u2x, u2y] = fs.map(|f| x.d(f, all[1]));
    let zero = |dag: &Dag, v: [NodeId; 2]| v.iter().all(|&n| dag.is_zero(n));
    if zero(x.dag, [u1x, u1y]) || zero(x.dag, [u2x, u2y]) {
        return None;
    }
    Some(ClosedForm::Linear2 {
        s1: a,
        s2: b,
        roots: [kx, ky, u1x, u1y, u2x, u2y],
    })
}

/// RRP or RPR: `K + s u + (M + s N) e(q)` with one of `u`, `N` structurally zero.
fn angle_length(
    dag: &mut Dag,
    model: &Model,
    fs: [NodeId; 2],
    q: usize,
    s: usize,
) -> Option<ClosedForm> {
    let atoms = Atoms::new(dag, model, &[q, s]);
    let [dq, ds, _] = degrees(dag, &fs, &atoms)?;
    if dq > 1 || ds > 1 {
        return None;
    }
    let (c, sn, l) = (atoms.of[0][0], atoms.of[0][1], atoms.of[1][0]);
    let mut x = Extract {
        dag,
        coef: HashMap::new(),
    };
    let [kx, ky] = fs.map(|f| x.at_zero(f, &[c, sn, l]));
    let ds_: [NodeId; 2] = fs.map(|f| x.d(f, l));
    let [ux, uy] = ds_.map(|g| x.at_zero(g, &[c, sn]));
    let dc: [NodeId; 2] = fs.map(|f| x.d(f, c));
    let dsn: [NodeId; 2] = fs.map(|f| x.d(f, sn));
    let [mcx, mcy] = dc.map(|g| x.at_zero(g, &[l]));
    let [msx, msy] = dsn.map(|g| x.at_zero(g, &[l]));
    let [ncx, ncy] = dc.map(|g| x.d(g, l));
    let [nsx, nsy] = dsn.map(|g| x.d(g, l));
    let (mp, mr) = x.rotation((mcx, mcy), (msx, msy))?;
    let (np, nr) = x.rotation((ncx, ncy), (nsx, nsy))?;
    let zero = |dag: &Dag, v: [NodeId; 2]| v.iter().all(|&n| dag.is_zero(n));
    let (u0, m0, n0) = (
        zero(x.dag, [ux, uy]),
        zero(x.dag, [mp, mr]),
        zero(x.dag, [np, nr]),
    );
    match (u0, m0, n0) {
        (false, false, true) => Some(ClosedForm::Rrp {
            q,
            s,
            roots: [kx, ky, mp, mr, ux, uy],
        }),
        (true, _, false) => Some(ClosedForm::Rpr {
            q,
            s,
            roots: [kx, ky, mp, mr, np, nr],
        }),
        _ => None,
    }
}

#[cfg(test)]
#[path = "closed_form_tests.rs"]
mod tests;
