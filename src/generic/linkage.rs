//! Generic engine, drawing structure (feature `runtime`): what a mechanism looks like, from the
//! checked model's loop terms rather than from their written order. Each term is ground (params
//! only), a rigid vector on a body (the angles it turns with) or a slider (one length coordinate
//! along a fixed or turning direction). A loop is a closed walk through its moving terms as
//! written (signed), its ground terms gathered where it leaves and rejoins the origin; a loop without ground terms is placed where it shares an edge (same motion, same
//! vector) with a loop already placed. Points off every loop hang on the bodies their last terms
//! move with. [`Linkage::sketch`] evaluates it all at one configuration (geometry in `sketch.rs`).

use std::collections::HashMap;

use mechgen_codegen::ast::{BinOp, Expr, ExprKind};
use mechgen_codegen::check::{Kind, Model, Symbol};

use super::sketch::{Edge, Motion, Sketch, SliderAt, Values, add, bodies, hull, sub};

/// One term of a loop or point with its sign.
#[derive(Clone, Debug)]
struct Term {
    expr: Expr,
    sign: f64,
    motion: Motion,
}

/// The drawing structure of one mechanism.
#[derive(Clone, Debug)]
pub struct Linkage {
    symbols: HashMap<String, Symbol>,
    inputs: usize,
    /// Each loop as a closed walk: its added ground terms (out from the origin), its moving terms
    /// as written, its subtracted ground terms (back to the origin).
    loops: Vec<Vec<Term>>,
    /// Each point's terms, ground terms first.
    points: Vec<Vec<Term>>,
}

impl Linkage {
    pub fn new(model: &Model) -> Linkage {
        let inputs = model.inputs.len();
        let kind_of = |id: usize| match id.checked_sub(inputs) {
            None => model.inputs[id].kind,
            Some(k) => model.unknowns.get(k).map_or(Kind::Angle, |c| c.kind),
        };
        let terms_of = |e: &Expr| {
            let mut terms = Vec::new();
            flatten(e, 1.0, &mut terms);
            terms
                .into_iter()
                .map(|(expr, sign)| {
                    let mut ids = Vec::new();
                    coordinates(expr, &model.symbols, inputs, &mut ids);
                    ids.sort_unstable();
                    ids.dedup();
                    let (lengths, angles): (Vec<usize>, Vec<usize>) =
                        ids.into_iter().partition(|&id| kind_of(id) == Kind::Length);
                    let motion = match lengths.as_slice() {
                        [] if angles.is_empty() => Motion::Ground,
                        [] => Motion::Rigid(angles),
                        [length] => Motion::Slider {
                            length: *length,
                            guide: angles,
                        },
                        _ => Motion::Other,
                    };
                    Term {
                        expr: expr.clone(),
                        sign,
                        motion,
                    }
                })
                .collect::<Vec<Term>>()
        };
        let loops = model
            .loops
            .iter()
            .map(|l| {
                let terms = terms_of(l);
                let ground = |plus: bool| {
                    terms
                        .iter()
                        .filter(move |t| t.motion == Motion::Ground && (t.sign > 0.0) == plus)
                        .cloned()
                };
                let moving = terms.iter().filter(|t| t.motion != Motion::Ground).cloned();
                ground(true).chain(moving).chain(ground(false)).collect()
            })
            .collect();
        let points = model
            .points
            .iter()
            .map(|(_, e)| {
                let mut terms = terms_of(e);
                terms.sort_by_key(|t| t.motion != Motion::Ground);
                terms
            })
            .collect();
        Linkage {
            symbols: model.symbols.clone(),
            inputs,
            loops,
            points,
        }
    }

    /// The mechanism at inputs `x`, unknowns `q` and params `p`. Non-finite values give
    /// non-finite coordinates (which drawings skip), never a panic.
    pub fn sketch(&self, x: &[f64], q: &[f64], p: &[f64]) -> Sketch {
        let env = Values {
            symbols: &self.symbols,
            inputs: self.inputs,
            x,
            q,
            p,
        };
        // An edge for a term whose walk reaches `at` before it; and where the walk goes next.
        let edge = |t: &Term, at: [f64; 2]| {
            let v = env.vector(&t.expr, None);
            let next = add(at, [t.sign * v[0], t.sign * v[1]]);
            let (from, to) = if t.sign > 0.0 { (at, next) } else { (next, at) };
            let direction = match &t.motion {
                Motion::Slider { length, .. } => {
                    let step = sub(
                        env.vector(&t.expr, Some((*length, 1.0))),
                        env.vector(&t.expr, Some((*length, 0.0))),
                    );
                    let norm = step[0].hypot(step[1]);
                    (norm > 0.0 && norm.is_finite()).then(|| [step[0] / norm, step[1] / norm])
                }
                _ => None,
            };
            let motion = t.motion.clone();
            (
                Edge {
                    motion,
                    from,
                    to,
                    direction,
                },
                next,
            )
        };
        let walk = |terms: &[Term], start: [f64; 2]| {
            let mut at = start;
            let mut out = Vec::with_capacity(terms.len());
            for t in terms {
                let (e, next) = edge(t, at);
                out.push(e);
                at = next;
            }
            out
        };
        // Each loop's walk from the origin, to find its size and the edges it could share.
        let relative: Vec<Vec<Edge>> = self.loops.iter().map(|l| walk(l, [0.0; 2])).collect();
        let scale = relative
            .iter()
            .flatten()
            .map(|e| (e.to[0] - e.from[0]).hypot(e.to[1] - e.from[1]))
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max);
        let tol = 1e-6 * scale;
        let near = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) <= tol;

        // Place the loops: through their ground terms at the origin, else on a shared edge, else
        // (nothing shared) at the origin as written.
        let has_ground = |l: &[Term]| l.iter().any(|t| t.motion == Motion::Ground);
        let mut start: Vec<Option<[f64; 2]>> = self
            .loops
            .iter()
            .map(|l| has_ground(l).then_some([0.0; 2]))
            .collect();
        let mut at_origin: Vec<bool> = start.iter().map(Option::is_some).collect();
        let mut placed: Vec<Option<Vec<Edge>>> = vec![None; self.loops.len()];
        loop {
            for l in 0..self.loops.len() {
                if let (Some(s), None) = (start[l], &placed[l]) {
                    placed[l] = Some(walk(&self.loops[l], s));
                }
            }
            let shared = |l: usize| {
                relative[l].iter().find_map(|r| {
                    let known = placed.iter().flatten().flatten().find(|e| {
                        e.motion == r.motion
                            && e.motion != Motion::Ground
                            && near(sub(e.to, e.from), sub(r.to, r.from))
                    })?;
                    Some(sub(known.from, r.from))
                })
            };
            let open = (0..self.loops.len()).filter(|&l| start[l].is_none());
            let found = open.clone().find_map(|l| Some((l, shared(l)?)));
            match (found, open.min()) {
                (Some((l, s)), _) => start[l] = Some(s),
                (None, Some(l)) => {
                    start[l] = Some([0.0; 2]);
                    at_origin[l] = true;
                }
                (None, None) => break,
            }
        }

        // Ground pivots: where a walk placed at the origin leaves its ground run at the origin
        // on a body, or on a guide that turns.
        let mut pivots: Vec<[f64; 2]> = Vec::new();
        for (l, terms) in self.loops.iter().enumerate() {
            let (Some(placed_edges), true) = (&placed[l], at_origin[l]) else {
                continue;
            };
            let n = terms.len();
            let is_ground = |t: &Term| t.motion == Motion::Ground;
            let lead = terms.iter().take_while(|t| is_ground(t)).count();
            let trail = terms.iter().rev().take_while(|t| is_ground(t)).count();
            // Walk vertex i (0..=n) lies on the ground run through the origin.
            let grounded = |i: usize| i <= lead || i + trail >= n;
            for (i, (t, e)) in terms.iter().zip(placed_edges).enumerate() {
                let (from, to) = if t.sign > 0.0 { (i, i + 1) } else { (i + 1, i) };
                let pivot = match &t.motion {
                    Motion::Rigid(_) if grounded(from) => Some(e.from),
                    Motion::Rigid(_) if grounded(to) => Some(e.to),
                    Motion::Slider { guide, .. } if !guide.is_empty() && grounded(from) => {
                        Some(e.from)
                    }
                    _ => None,
                };
                if let Some(p) = pivot.filter(|p| !pivots.iter().any(|q| near(*p, *q))) {
                    pivots.push(p);
                }
            }
        }

        // Points off the loops: the rest of their path from the last joint already known.
        let mut edges: Vec<Edge> = placed.into_iter().flatten().flatten().collect();
        let mut extra = Vec::new();
        for terms in &self.points {
            let path = walk(terms, [0.0; 2]);
            let known = |p: [f64; 2]| edges.iter().any(|e| near(e.from, p) || near(e.to, p));
            let end = |e: &Edge, t: &Term| if t.sign > 0.0 { e.to } else { e.from };
            let begin = |e: &Edge, t: &Term| if t.sign > 0.0 { e.from } else { e.to };
            let Some((last, lt)) = path.last().zip(terms.last()) else {
                continue;
            };
            if known(end(last, lt)) {
                continue;
            }
            let from = path
                .iter()
                .zip(terms)
                .rposition(|(e, t)| known(begin(e, t)));
            extra.extend(path.into_iter().skip(from.unwrap_or(0)));
        }
        edges.extend(extra);

        // Sliders, each once.
        let mut sliders: Vec<SliderAt> = Vec::new();
        for e in &edges {
            let (Motion::Slider { guide, .. }, Some(direction)) = (&e.motion, e.direction) else {
                continue;
            };
            let slider = SliderAt {
                base: e.from,
                block: e.to,
                direction,
                ground: guide.is_empty(),
            };
            let same = |s: &SliderAt| near(s.base, slider.base) && near(s.block, slider.block);
            if !sliders.iter().any(same) {
                sliders.push(slider);
            }
        }

        Sketch {
            links: bodies(&edges, &near).into_iter().map(hull).collect(),
            pivots,
            sliders,
        }
    }
}

/// The terms of a sum with their signs (+1 added, −1 subtracted).
fn flatten<'e>(e: &'e Expr, sign: f64, out: &mut Vec<(&'e Expr, f64)>) {
    match &e.kind {
        ExprKind::Binary(BinOp::Add, a, b) => {
            flatten(a, sign, out);
            flatten(b, sign, out);
        }
        ExprKind::Binary(BinOp::Sub, a, b) => {
            flatten(a, sign, out);
            flatten(b, -sign, out);
        }
        ExprKind::Neg(a) => flatten(a, -sign, out),
        _ => out.push((e, sign)),
    }
}

/// The coordinates (inputs, then unknowns, as one id range) a term depends on.
fn coordinates(e: &Expr, symbols: &HashMap<String, Symbol>, inputs: usize, out: &mut Vec<usize>) {
    match &e.kind {
        ExprKind::Number(_) => {}
        ExprKind::Name(n) => match symbols.get(n) {
            Some(Symbol::Input(i)) => out.push(*i),
            Some(Symbol::Unknown(i)) => out.push(inputs + i),
            _ => {}
        },
        ExprKind::Neg(a) => coordinates(a, symbols, inputs, out),
        ExprKind::Binary(_, a, b) => {
            coordinates(a, symbols, inputs, out);
            coordinates(b, symbols, inputs, out);
        }
        ExprKind::Call(_, args) => {
            for a in args {
                coordinates(a, symbols, inputs, out);
            }
        }
    }
}
