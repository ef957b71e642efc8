//! Generic engine, drawing structure (feature `runtime`): what a mechanism looks like, from the
//! checked model's loop terms rather than from their written order. Each term (`terms.rs`) is
//! ground (params only), a rigid vector on a body (the angles it turns with) or a slider (one
//! length coordinate along a fixed or turning direction). A loop with ground terms is a closed
//! walk out of the origin through its moving terms and back: read as written, as two sides, or
//! backwards, whichever leaves and rejoins the ground at the tails of its end links (and, among
//! those, passes through the most named points). A loop without ground terms is walked as written
//! and placed where it shares an edge (same motion, same vector) with a loop already placed.
//! Points off every loop hang on the bodies their last terms move with. [`Linkage::sketch`]
//! evaluates it all at one configuration (geometry in `sketch.rs`).

use std::collections::HashMap;

use mechgen_codegen::Expr;
use mechgen_codegen::{Model, Symbol};

use super::sketch::{Edge, Sketch, SliderAt, Values, add, bodies, hull, sub};
use super::terms::{Motion, Term, tails, terms_of};

/// The drawing structure of one mechanism.
#[derive(Clone, Debug)]
pub struct Linkage {
    symbols: HashMap<String, Symbol>,
    derived: Vec<Expr>,
    inputs: usize,
    /// Each loop's readings as a closed walk (see `new`), the preferred first: its added ground
    /// terms (out from the origin), its moving terms, its subtracted ground terms (back to it).
    readings: Vec<Vec<Vec<Term>>>,
    /// Each point's terms, ground terms first.
    points: Vec<Vec<Term>>,
}

impl Linkage {
    pub fn new(model: &Model) -> Linkage {
        let terms_of = |e: &Expr| terms_of(e, model);
        let readings = model
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
                let moving: Vec<Term> = terms
                    .iter()
                    .filter(|t| t.motion != Motion::Ground)
                    .cloned()
                    .collect();
                let wrap = |m: Vec<Term>| -> Vec<Term> {
                    ground(true).chain(m).chain(ground(false)).collect()
                };
                // No ground terms: a closed walk, whose joints depend on the order of its terms
                // (`L*e(qB) + s*e(qBP) - L*e(qD) - s*e(qDP)` as written passes P − D, no joint):
                // every reading below is kept, and the sketch takes the one through the most
                // named points.
                let floating = moving.len() == terms.len();
                // As written; as two sides (added terms out in either order, subtracted ones
                // back in either order); each backwards. Kept: those that leave and rejoin the ground at the
                // tails of their end links (any, for a loop without ground terms), in this order
                // of preference.
                let (plus, minus): (Vec<Term>, Vec<Term>) =
                    moving.iter().cloned().partition(|t| t.sign > 0.0);
                let sides = |reverse_plus: bool, reverse: bool| {
                    let (mut p, mut m) = (plus.clone(), minus.clone());
                    if reverse_plus {
                        p.reverse();
                    }
                    if reverse {
                        m.reverse();
                    }
                    p.into_iter().chain(m).collect::<Vec<Term>>()
                };
                let mut readings = vec![
                    moving.clone(),
                    sides(false, false),
                    sides(false, true),
                    sides(true, false),
                    sides(true, true),
                ];
                let backwards: Vec<Vec<Term>> = readings
                    .iter()
                    .map(|r| r.iter().rev().cloned().collect())
                    .collect();
                readings.extend(backwards);
                let best = readings.iter().map(|r| tails(r)).max().unwrap_or(0);
                let mut kept: Vec<Vec<Term>> = Vec::new();
                for r in readings
                    .into_iter()
                    .filter(|r| floating || tails(r) == best)
                {
                    let w = wrap(r);
                    if !kept.contains(&w) {
                        kept.push(w);
                    }
                }
                kept
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
            derived: model.derived.iter().map(|d| d.expr.clone()).collect(),
            inputs: model.inputs.len(),
            readings,
            points,
        }
    }

    /// The mechanism at inputs `x`, unknowns `q` and params `p`. Non-finite values give
    /// non-finite coordinates (which drawings skip), never a panic.
    pub fn sketch(&self, x: &[f64], q: &[f64], p: &[f64]) -> Sketch {
        let env = Values {
            symbols: &self.symbols,
            derived: &self.derived,
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
        // The loops' size, from their first readings.
        let scale = self
            .readings
            .iter()
            .filter_map(|r| r.first())
            .flat_map(|r| walk(r, [0.0; 2]))
            .map(|e| (e.to[0] - e.from[0]).hypot(e.to[1] - e.from[1]))
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max);
        let tol = 1e-6 * scale;
        let near = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) <= tol;
        // Each loop read the way whose joints are the most named points (the first on a tie).
        let end = |terms: &[Term]| terms.iter().fold([0.0; 2], |at, t| edge(t, at).1);
        let named: Vec<[f64; 2]> = self.points.iter().map(|p| end(p)).collect();
        let loops: Vec<&[Term]> = self
            .readings
            .iter()
            .map(|readings| {
                let mut best: (usize, &[Term]) = (0, readings.first().map_or(&[], |r| r));
                for r in readings {
                    let mut at = [0.0; 2];
                    let mut on = 0;
                    for t in r {
                        at = edge(t, at).1;
                        on += usize::from(named.iter().any(|p| near(*p, at)));
                    }
                    if on > best.0 {
                        best = (on, r);
                    }
                }
                best.1
            })
            .collect();
        // Each loop's walk from the origin, for the edges it could share.
        let relative: Vec<Vec<Edge>> = loops.iter().map(|l| walk(l, [0.0; 2])).collect();

        // Place the loops: through their ground terms at the origin, else on a shared edge, else
        // (nothing shared) at the origin as written.
        let has_ground = |l: &[Term]| l.iter().any(|t| t.motion == Motion::Ground);
        let mut start: Vec<Option<[f64; 2]>> = loops
            .iter()
            .map(|l| has_ground(l).then_some([0.0; 2]))
            .collect();
        let mut at_origin: Vec<bool> = start.iter().map(Option::is_some).collect();
        let mut placed: Vec<Option<Vec<Edge>>> = vec![None; loops.len()];
        loop {
            for l in 0..loops.len() {
                if let (Some(s), None) = (start[l], &placed[l]) {
                    placed[l] = Some(walk(loops[l], s));
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
            let open = (0..loops.len()).filter(|&l| start[l].is_none());
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
        for (l, terms) in loops.iter().enumerate() {
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
