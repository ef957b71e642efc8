//! Branch identification, structure: the traced intervals joined at their ends. At a dead point
//! the two tracks on the side with more configurations that meet (the closest pair) are a fold:
//! one circuit, two branches; every other track continues into the nearest one on the other side
//! (same branch). Branches are the components under continuation, circuits under all joins.
//! Circuits are numbered by their lowest branch, branches by circuit, then lower end.

use std::f64::consts::TAU;

use super::crossing::Found;
use super::dead::{Dead, GUARD};
use super::trace::Interval;
use super::{Analysis, Branch, Crossing, DeadPoint, Labelled, Setup};

/// Union-find over track nodes.
struct Sets(Vec<usize>);

impl Sets {
    fn find(&mut self, mut a: usize) -> usize {
        while self.0[a] != a {
            self.0[a] = self.0[self.0[a]];
            a = self.0[a];
        }
        a
    }

    fn join(&mut self, a: usize, b: usize) {
        let (a, b) = (self.find(a), self.find(b));
        self.0[a.max(b)] = a.min(b);
    }
}

impl Setup {
    pub(super) fn structure(
        &self,
        ivs: &[Interval],
        dead: Vec<Dead>,
        crossings: &[Found],
        circular: bool,
        (from, to): (f64, f64),
        at: &[f64],
    ) -> Result<Analysis, String> {
        let offset: Vec<usize> = ivs
            .iter()
            .scan(0, |s, v| {
                let o = *s;
                *s += v.tracks.len();
                Some(o)
            })
            .collect();
        let nodes = offset
            .last()
            .map_or(0, |o| o + ivs[ivs.len() - 1].tracks.len());
        let (mut branch, mut circuit) = (Sets((0..nodes).collect()), Sets((0..nodes).collect()));
        let mut next = vec![None; nodes];
        let mut fold = vec![[false; 2]; nodes];
        let mut dead_circuit_node = vec![None; dead.len()];
        let n = ivs.len();
        for i in 0..n {
            let j = if i + 1 < n {
                i + 1
            } else if circular {
                0
            } else {
                break;
            };
            let ends: Vec<Vec<f64>> = ivs[i]
                .tracks
                .iter()
                .map(|t| t[t.len() - 1].1.clone())
                .collect();
            let starts: Vec<Vec<f64>> = ivs[j].tracks.iter().map(|t| t[0].1.clone()).collect();
            let (mut left, mut right): (Vec<usize>, Vec<usize>) =
                ((0..ends.len()).collect(), (0..starts.len()).collect());
            // Folds on the side with more tracks.
            while left.len() >= right.len() + 2 || right.len() >= left.len() + 2 {
                let (side, qs, iv, end) = if left.len() > right.len() {
                    (&mut left, &ends, i, 1)
                } else {
                    (&mut right, &starts, j, 0)
                };
                let sub: Vec<Vec<f64>> = side.iter().map(|&k| qs[k].clone()).collect();
                let (a, b) = self.closest_pair(&sub).ok_or("no fold pair")?;
                let (na, nb) = (offset[iv] + side[a], offset[iv] + side[b]);
                circuit.join(na, nb);
                fold[na][end] = true;
                fold[nb][end] = true;
                if let Some(d) = ivs[i].dead[1] {
                    dead_circuit_node[d] = Some(na);
                }
                let (ka, kb) = (side[a], side[b]);
                side.retain(|&k| k != ka && k != kb);
            }
            let l: Vec<Vec<f64>> = left.iter().map(|&k| ends[k].clone()).collect();
            let r: Vec<Vec<f64>> = right.iter().map(|&k| starts[k].clone()).collect();
            for (a, b) in self.greedy(&l, &r) {
                let (na, nb) = (offset[i] + left[a], offset[j] + right[b]);
                branch.join(na, nb);
                circuit.join(na, nb);
                next[na] = Some(nb);
            }
        }
        // A crossing joins the circuits of the two tracks that meet there.
        for c in crossings {
            let [a, b] = c.tracks.map(|k| offset[c.iv] + k);
            circuit.join(a, b);
        }
        // Branches: walk each continuation component from its lower end.
        let mut seen = vec![false; nodes];
        let mut raw: Vec<(usize, usize, Branch)> = Vec::new();
        let iv_of = |node: usize| offset.iter().rposition(|&o| o <= node).unwrap_or(0);
        let starts: Vec<usize> = (0..nodes)
            .filter(|&k| fold[k][0] || (!circular && iv_of(k) == 0))
            .chain(0..nodes)
            .collect();
        for s in starts {
            if seen[s] {
                continue;
            }
            let full_turn = !(fold[s][0] || (!circular && iv_of(s) == 0));
            let (mut cur, mut wraps) = (s, 0.0);
            let mut curve = Vec::new();
            let lo_iv = iv_of(s);
            let mut hi;
            let mut dead_end = [if fold[s][0] { ivs[lo_iv].dead[0] } else { None }, None];
            if let Some(d) = dead_end[0] {
                curve.push((dead[d].input, dead[d].q.clone()));
            }
            loop {
                seen[cur] = true;
                let iv = iv_of(cur);
                let t = &ivs[iv].tracks[cur - offset[iv]];
                curve.extend(t.iter().map(|(x, q)| (x + wraps, q.clone())));
                hi = ivs[iv].hi + wraps;
                if fold[cur][1] {
                    dead_end[1] = ivs[iv].dead[1];
                }
                match next[cur] {
                    Some(nx) if !seen[nx] && !fold[cur][1] => {
                        if iv_of(nx) < iv {
                            wraps += TAU;
                        }
                        cur = nx;
                    }
                    _ => break,
                }
            }
            if let Some(d) = dead_end[1] {
                curve.push((dead[d].input + wraps, dead[d].q.clone()));
            }
            raw.push((
                circuit.find(s),
                branch.find(s),
                Branch {
                    circuit: 0,
                    from: ivs[lo_iv].lo,
                    to: if full_turn { ivs[lo_iv].lo + TAU } else { hi },
                    full_turn,
                    dead: dead_end,
                    curve,
                },
            ));
        }
        // Numbering: circuits by their lowest branch, branches by circuit then lower end.
        let key = |b: &Branch| {
            if circular {
                (b.from - from).rem_euclid(TAU)
            } else {
                b.from
            }
        };
        raw.sort_by(|a, b| {
            key(&a.2)
                .total_cmp(&key(&b.2))
                .then(first(&a.2).total_cmp(&first(&b.2)))
        });
        let mut roots: Vec<usize> = Vec::new();
        for (r, _, _) in &raw {
            if !roots.contains(r) {
                roots.push(*r);
            }
        }
        let mut branches: Vec<(usize, Branch)> = raw
            .into_iter()
            .map(|(r, br, mut b)| {
                b.circuit = roots.iter().position(|&x| x == r).unwrap_or(0);
                (br, b)
            })
            .collect();
        branches.sort_by_key(|(_, b)| b.circuit);
        let dead_points = dead
            .iter()
            .zip(&dead_circuit_node)
            .map(|(d, node)| DeadPoint {
                input: d.input,
                q: d.q.clone(),
                circuit: node
                    .map(|k| circuit.find(k))
                    .and_then(|r| roots.iter().position(|&x| x == r))
                    .unwrap_or(0),
            })
            .collect();
        let labels: Vec<usize> = branches.iter().map(|(r, _)| *r).collect();
        let circuits_of: Vec<usize> = branches.iter().map(|(_, b)| b.circuit).collect();
        let branch_of =
            |branch: &mut Sets, node: usize| labels.iter().position(|&l| l == branch.find(node));
        let mut crossing_list: Vec<(Crossing, [Vec<f64>; 2])> = Vec::new();
        for c in crossings {
            let mut meet = Vec::new();
            for (k, s) in c.tracks.iter().zip(&c.slopes) {
                let b = branch_of(&mut branch, offset[c.iv] + k).ok_or("crossing off a branch")?;
                meet.push((b, s.clone()));
            }
            meet.sort_by_key(|m| m.0);
            crossing_list.push((
                Crossing {
                    input: c.input,
                    q: c.q.clone(),
                    circuit: circuits_of[meet[0].0],
                    branches: meet.iter().map(|m| m.0).collect(),
                },
                [meet[0].1.clone(), meet[1].1.clone()],
            ));
        }
        crossing_list.sort_by(|a, b| a.0.input.total_cmp(&b.0.input));
        let labelled = self.label(
            ivs,
            &offset,
            &labels,
            &circuits_of,
            &mut branch,
            circular,
            at,
            &crossing_list,
        )?;
        Ok(Analysis {
            from,
            to,
            full_turn: circular,
            circuits: roots.len(),
            branches: branches.into_iter().map(|(_, b)| b).collect(),
            dead_points,
            crossings: crossing_list.into_iter().map(|c| c.0).collect(),
            at_inputs: at.to_vec(),
            at: labelled,
            degenerate: self.solver.degenerate(),
        })
    }
}

/// The first unknown at a branch's lower end (a tie-break of the numbering).
fn first(b: &Branch) -> f64 {
    b.curve
        .first()
        .and_then(|c| c.1.first().copied())
        .unwrap_or(0.0)
}

impl Setup {
    /// Every configuration at each `at` input, labelled by the track sample it is nearest to (the
    /// `at` inputs are samples of the traced tracks).
    #[allow(clippy::too_many_arguments)]
    fn label(
        &self,
        ivs: &[Interval],
        offset: &[usize],
        labels: &[usize],
        circuits: &[usize],
        branch: &mut Sets,
        circular: bool,
        at: &[f64],
        crossings: &[(Crossing, [Vec<f64>; 2])],
    ) -> Result<Vec<Labelled>, String> {
        let shifts: &[f64] = if circular {
            &[-TAU, 0.0, TAU, 2.0 * TAU]
        } else {
            &[0.0]
        };
        let width = ivs.last().map_or(1.0, |v| v.hi) - ivs.first().map_or(0.0, |v| v.lo);
        let mut out = Vec::new();
        for &x in at {
            let mut here: Vec<Labelled> = Vec::new();
            let mut qs = self.configurations(x)?;
            // At (or within the guard of) a crossing: its configuration once per branch through
            // it, each on its own track's tangent; the solver's configurations there are dropped.
            let away = GUARD * if self.input_is_angle { 1.0 } else { width };
            for (c, slopes) in crossings {
                let Some(dx) = shifts
                    .iter()
                    .map(|s| x + s - c.input)
                    .find(|d| d.abs() <= away)
                else {
                    continue;
                };
                let along: Vec<Vec<f64>> = slopes
                    .iter()
                    .map(|s| c.q.iter().zip(s).map(|(q, s)| q + s * dx).collect())
                    .collect();
                let reach = 2.0 * self.dist(&along[0], &along[1]) + 1e-7;
                qs.retain(|q| self.dist(q, &c.q) > reach);
                for (b, q) in c.branches.iter().zip(along) {
                    here.push(Labelled {
                        input: x,
                        q,
                        circuit: c.circuit,
                        branch: *b,
                    });
                }
            }
            for q in qs {
                let mut best: Option<(f64, f64, usize)> = None;
                for (i, v) in ivs.iter().enumerate() {
                    for (j, t) in v.tracks.iter().enumerate() {
                        for (xt, qt) in t {
                            let dx = shifts
                                .iter()
                                .map(|s| (xt - (x + s)).abs())
                                .fold(f64::INFINITY, f64::min);
                            if dx > 10.0 * GUARD * width.max(1.0) {
                                continue;
                            }
                            let d = self.dist(&q, qt);
                            if best.is_none_or(|b| (dx, d) < (b.0, b.1)) {
                                best = Some((dx, d, offset[i] + j));
                            }
                        }
                    }
                }
                let (_, _, node) =
                    best.ok_or_else(|| format!("--at {x}: no traced branch passes there"))?;
                let r = branch.find(node);
                let b = labels.iter().position(|&l| l == r).unwrap_or(0);
                here.push(Labelled {
                    input: x,
                    q,
                    circuit: circuits[b],
                    branch: b,
                });
            }
            here.sort_by_key(|l| (l.circuit, l.branch));
            out.extend(here);
        }
        Ok(out)
    }
}
