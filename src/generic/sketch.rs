//! Generic engine, drawing geometry (feature `runtime`): the output of [`super::Linkage::sketch`]
//! ([`Sketch`], [`SliderAt`]), the f64 evaluation of a term at a configuration, and the plane
//! geometry the structure needs (edges, bodies as groups of edges, outlines as convex hulls).

use std::collections::HashMap;

use mechgen_codegen::{BinOp, Expr, ExprKind};
use mechgen_codegen::{Builtin, Symbol};

use super::terms::Motion;

/// The mechanism at one configuration, in file units.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sketch {
    /// Bodies: a bar (two joints) or a closed outline of three or more joints (the first repeated
    /// at the end).
    pub links: Vec<Vec<[f64; 2]>>,
    /// Joints of the ground that a body or a turning guide turns about.
    pub pivots: Vec<[f64; 2]>,
    /// Sliders, in the order of their first term (the same at every configuration).
    pub sliders: Vec<SliderAt>,
}

/// A slider at one configuration: a block at `block` on a guide through `base` along `direction`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SliderAt {
    /// Where the slider's length is measured from (a point of the guide).
    pub base: [f64; 2],
    pub block: [f64; 2],
    /// Unit vector along the guide.
    pub direction: [f64; 2],
    /// The guide is fixed to the ground (its direction turns with no coordinate).
    pub ground: bool,
}

/// A term at one configuration, oriented as written with a plus sign: `to - from` is its value.
/// For a slider, `from` is the base on the guide and `to` the block.
#[derive(Clone, Debug)]
pub(super) struct Edge {
    pub motion: Motion,
    pub from: [f64; 2],
    pub to: [f64; 2],
    /// A slider's unit direction.
    pub direction: Option<[f64; 2]>,
}

pub(super) fn add(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] + b[0], a[1] + b[1]]
}

pub(super) fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// Coordinate ids: inputs first, then unknowns.
pub(super) struct Values<'a> {
    pub symbols: &'a HashMap<String, Symbol>,
    pub inputs: usize,
    pub x: &'a [f64],
    pub q: &'a [f64],
    pub p: &'a [f64],
    /// The derived params' expressions (`Symbol::Derived`), in file order.
    pub derived: &'a [Expr],
}

enum Value {
    S(f64),
    V([f64; 2]),
}

impl Values<'_> {
    /// The vector value of `e` (a scalar `s` is `(s, 0)`), with coordinate `set.0` replaced by
    /// `set.1` when given. A name out of range reads as NaN.
    pub fn vector(&self, e: &Expr, set: Option<(usize, f64)>) -> [f64; 2] {
        match self.value(e, set) {
            Value::S(s) => [s, 0.0],
            Value::V(v) => v,
        }
    }

    fn scalar(&self, e: &Expr, set: Option<(usize, f64)>) -> f64 {
        match self.value(e, set) {
            Value::S(s) => s,
            Value::V(v) => v[0],
        }
    }

    fn value(&self, e: &Expr, set: Option<(usize, f64)>) -> Value {
        use Value::{S, V};
        let get = |v: &[f64], i: usize| v.get(i).copied().unwrap_or(f64::NAN);
        match &e.kind {
            ExprKind::Number(x) => S(*x),
            ExprKind::Name(n) if Builtin::from_name(n) == Some(Builtin::Pi) => {
                S(std::f64::consts::PI)
            }
            ExprKind::Name(n) => S(match self.symbols.get(n) {
                Some(Symbol::Input(i)) if set.is_some_and(|s| s.0 == i.index()) => {
                    set.map_or(0.0, |s| s.1)
                }
                Some(Symbol::Unknown(i)) if set.is_some_and(|s| s.0 == self.inputs + i.index()) => {
                    set.map_or(0.0, |s| s.1)
                }
                Some(Symbol::Input(i)) => get(self.x, i.index()),
                Some(Symbol::Unknown(i)) => get(self.q, i.index()),
                Some(Symbol::Param(i)) => get(self.p, i.index()),
                Some(Symbol::Derived(j)) => self
                    .derived
                    .get(j.index())
                    .map_or(f64::NAN, |d| self.scalar(d, set)),
                None => f64::NAN,
            }),
            ExprKind::Neg(a) => match self.value(a, set) {
                S(s) => S(-s),
                V(v) => V([-v[0], -v[1]]),
            },
            ExprKind::Binary(op, a, b) => match (self.value(a, set), self.value(b, set), op) {
                (S(a), S(b), BinOp::Add) => S(a + b),
                (S(a), S(b), BinOp::Sub) => S(a - b),
                (S(a), S(b), BinOp::Mul) => S(a * b),
                (S(a), S(b), BinOp::Div) => S(a / b),
                (S(s), V(v), BinOp::Mul) | (V(v), S(s), BinOp::Mul) => V([s * v[0], s * v[1]]),
                (V(v), S(s), BinOp::Div) => V([v[0] / s, v[1] / s]),
                (a, b, BinOp::Add | BinOp::Sub) => {
                    let as_v = |x: Value| match x {
                        S(s) => [s, 0.0],
                        V(v) => v,
                    };
                    let (a, b) = (as_v(a), as_v(b));
                    V(if *op == BinOp::Add {
                        add(a, b)
                    } else {
                        sub(a, b)
                    })
                }
                // Rejected by the checker (vector × vector, division by a vector).
                _ => S(f64::NAN),
            },
            ExprKind::Call(f, args) => {
                let arg = |i: usize| args.get(i).map_or(f64::NAN, |a| self.scalar(a, set));
                match Builtin::from_name(&f.text) {
                    Some(Builtin::E) => {
                        let (s, c) = arg(0).sin_cos();
                        V([c, s])
                    }
                    Some(Builtin::C) => V([arg(0), arg(1)]),
                    Some(b) => S(b.eval(&[arg(0), arg(1)]).unwrap_or(f64::NAN)),
                    None => S(f64::NAN),
                }
            }
        }
    }
}

/// The bodies: rigid edges turning with the same angles, joined where they share a joint; each
/// body as its joints.
pub(super) fn bodies(
    edges: &[Edge],
    near: &dyn Fn([f64; 2], [f64; 2]) -> bool,
) -> Vec<Vec<[f64; 2]>> {
    let mut groups: Vec<(Vec<usize>, Vec<[f64; 2]>)> = Vec::new();
    for e in edges {
        let Motion::Rigid(key) = &e.motion else {
            continue;
        };
        if !(finite(e.from) && finite(e.to)) {
            continue;
        }
        let touches = |g: &(Vec<usize>, Vec<[f64; 2]>)| {
            &g.0 == key && g.1.iter().any(|p| near(*p, e.from) || near(*p, e.to))
        };
        // Every group this edge touches merges into the first.
        let mut hit: Vec<usize> = (0..groups.len()).filter(|&i| touches(&groups[i])).collect();
        let mut joints = vec![e.from, e.to];
        while let Some(i) = hit.pop() {
            joints.extend(groups.swap_remove(i).1);
        }
        let mut unique: Vec<[f64; 2]> = Vec::new();
        for p in joints {
            if !unique.iter().any(|q| near(*q, p)) {
                unique.push(p);
            }
        }
        groups.push((key.clone(), unique));
    }
    groups.into_iter().map(|g| g.1).collect()
}

pub(super) fn finite(p: [f64; 2]) -> bool {
    p[0].is_finite() && p[1].is_finite()
}

/// The outline of a body's joints: their convex hull, closed (first joint repeated) when it has
/// three or more corners; two joints (or collinear ones) are a bar between the extremes.
pub(super) fn hull(mut joints: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    joints.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    joints.dedup();
    if joints.len() < 3 {
        return joints;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let span = joints
        .iter()
        .flat_map(|p| [p[0].abs(), p[1].abs()])
        .fold(0.0, f64::max);
    // Corners that turn by less than this (relative to the size squared) are collinear.
    let flat = 1e-9 * span * span;
    let chain = |points: &mut dyn Iterator<Item = [f64; 2]>| {
        let mut h: Vec<[f64; 2]> = Vec::new();
        for p in points {
            while h.len() >= 2 && cross(h[h.len() - 2], h[h.len() - 1], p) <= flat {
                h.pop();
            }
            h.push(p);
        }
        h
    };
    let lower = chain(&mut joints.iter().copied());
    let upper = chain(&mut joints.iter().rev().copied());
    let mut outline: Vec<[f64; 2]> = lower[..lower.len() - 1].to_vec();
    outline.extend(&upper[..upper.len() - 1]);
    match outline.len() {
        0 | 1 => joints,
        2 => outline,
        _ => {
            outline.push(outline[0]);
            outline
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hulls_of_bars_triangles_and_collinear_joints() {
        assert_eq!(
            hull(vec![[1.0, 0.0], [0.0, 0.0]]),
            vec![[0.0, 0.0], [1.0, 0.0]]
        );
        let bar = hull(vec![[0.0, 0.0], [2.0, 0.0], [1.0, 0.0]]);
        assert_eq!(bar, vec![[0.0, 0.0], [2.0, 0.0]]);
        let tri = hull(vec![[0.0, 0.0], [1.0, 1.0], [2.0, 0.0], [1.0, 0.2]]);
        assert_eq!(tri.len(), 4);
        assert_eq!(tri.first(), tri.last());
        assert!(!tri.contains(&[1.0, 0.2]));
    }
}
