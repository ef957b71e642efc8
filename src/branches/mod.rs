//! Branch identification (feature `runtime`): the whole configuration space of a mechanism along
//! one input, from the generator's analysis ([`Compiled`]), the same for both engines. Every
//! assembly configuration at an input (closed-form blocks by their modes, other blocks torn at a
//! cut angle: `plan`, `solve`, `roots`), the dead points, the circuits and the branches (`trace`),
//! and the configurations at chosen inputs labelled with their circuit and branch.

mod crossing;
mod dead;
mod grid;
mod plan;
mod report;
mod roots;
mod setup;
mod singular;
mod solve;
mod trace;

use std::cell::RefCell;
use std::f64::consts::TAU;

use mechgen_codegen::{Compiled, Kind};

use dead::Dead;
pub use setup::Setup;
use setup::Solved;
pub use solve::{Enumeration, MAX_CONFIGURATIONS, Solver};
use trace::{Interval, Traced};

/// Where a mechanism assembles, for sweeps on any thread: a [`Setup`] kept as a template, each
/// sweep (each param set) taking its own copy with its params ([`Assembly::with_params`]) when it
/// first meets a row past the dead point that ends its branch.
pub struct Assembly(std::sync::Mutex<Setup>);

impl Assembly {
    /// Mechanism `c` along input `index` (the file's params).
    pub fn new(c: &Compiled, index: usize) -> Option<Assembly> {
        Setup::new(c, index)
            .ok()
            .map(|s| Assembly(std::sync::Mutex::new(s)))
    }

    /// Mechanism `name` of the file text `text` (named `file` in messages) along input `index`;
    /// `None` where the file does not analyse.
    pub fn from_text(file: &str, text: &str, name: &str, index: usize) -> Option<Assembly> {
        let source = mechgen_codegen::SourceFile::new(file, text);
        let (compiled, _) = mechgen_codegen::analyze(&source);
        let c = compiled.iter().find(|c| c.model.name.text == name)?;
        Assembly::new(c, index)
    }

    /// A copy with the base params `params` (in `MechanismInfo::params` order); `None` for a
    /// wrong count.
    pub fn with_params(&self, params: &[f64]) -> Option<Setup> {
        let mut s = self.0.lock().unwrap_or_else(|e| e.into_inner()).clone();
        s.set_params(params).then_some(s)
    }
}

/// A dead point: the input where the configuration curve turns back, its configuration, circuit.
#[derive(Clone, Debug, PartialEq)]
pub struct DeadPoint {
    pub input: f64,
    pub q: Vec<f64>,
    pub circuit: usize,
}

/// A crossing: a singular configuration where two branches of different assembly modes meet
/// and both go on (the curve does not turn back there, unlike at a dead point).
#[derive(Clone, Debug, PartialEq)]
pub struct Crossing {
    pub input: f64,
    pub q: Vec<f64>,
    pub circuit: usize,
    /// The branches that meet there (their indices in [`Analysis::branches`], ascending).
    pub branches: Vec<usize>,
}

/// A branch: a circuit's piece between dead points (or range ends) along which the input drives
/// the motion one way. It covers the inputs from `from` going up to `to` (`to` may pass a full
/// turn), or the whole turn (`full_turn`, no dead point on it).
#[derive(Clone, Debug, PartialEq)]
pub struct Branch {
    pub circuit: usize,
    pub from: f64,
    pub to: f64,
    pub full_turn: bool,
    /// Indices into [`Analysis::dead_points`] of the dead points at its ends.
    pub dead: [Option<usize>; 2],
    /// Traced samples `(input, configuration)` in increasing input (for plots).
    pub curve: Vec<(f64, Vec<f64>)>,
}

/// One assembly configuration at an `at` input, with its labels.
#[derive(Clone, Debug, PartialEq)]
pub struct Labelled {
    pub input: f64,
    pub q: Vec<f64>,
    pub circuit: usize,
    pub branch: usize,
}

/// The configuration space along the input over a range.
#[derive(Clone, Debug, PartialEq)]
pub struct Analysis {
    pub from: f64,
    pub to: f64,
    /// The range is a whole turn of an angle input (a circle).
    pub full_turn: bool,
    pub circuits: usize,
    pub branches: Vec<Branch>,
    pub dead_points: Vec<DeadPoint>,
    /// Crossings, by input.
    pub crossings: Vec<Crossing>,
    /// The `at` inputs, as asked.
    pub at_inputs: Vec<f64>,
    /// Every configuration at each `at` input, in the order asked, then by circuit and branch.
    pub at: Vec<Labelled>,
    /// The mode combinations left out because they make a block degenerate (two of its points
    /// coincide for every input): (that block, the earlier blocks' mode indices).
    pub degenerate: Vec<(usize, Vec<u8>)>,
}

impl Setup {
    /// Prepares mechanism `c` along input `input`, the other inputs held at their start values.
    pub fn new(c: &Compiled, input: usize) -> Result<Setup, String> {
        let m = &c.model;
        if input >= m.inputs.len() {
            return Err(format!("`{}` has no input {input}", m.name.text));
        }
        let steps = plan::plan(c)?;
        let scale = m
            .params
            .iter()
            .filter(|p| p.kind == Kind::Length && p.value.is_finite())
            .map(|p| p.value.abs())
            .fold(0.0, f64::max);
        Ok(Setup {
            solver: Solver {
                steps,
                params: m.params.iter().map(|p| p.value).collect(),
                unknowns: m.unknowns.len(),
                degenerate: Default::default(),
            },
            tapes: singular::Tapes::new(c),
            inputs: m.inputs.iter().map(|i| i.start).collect(),
            input,
            input_is_angle: m.inputs[input].kind == Kind::Angle,
            angle: m.unknowns.iter().map(|u| u.kind == Kind::Angle).collect(),
            scale: if scale > 0.0 { scale } else { 1.0 },
            name: m.name.text.clone(),
            input_name: m.inputs[input].name.text.clone(),
            unknown_names: m.unknowns.iter().map(|u| u.name.text.clone()).collect(),
            cache: RefCell::default(),
        })
    }

    /// Whether the linkage assembles at the inputs `x` (every input, radians or file units): one
    /// configuration at least (a mode combination that leaves a block degenerate does not count).
    /// What a sweep asks for the rows past the dead point that ended its branch
    /// ([`crate::sweep::sweep_each_with`]).
    /// `None` where it cannot tell (see [`Solver::assembles`]).
    pub fn assembles(&self, x: &[f64]) -> Option<bool> {
        if x.len() != self.inputs.len() {
            return None;
        }
        self.solver.assembles(x)
    }

    /// Holds input `i` (not the one analysed along) at `value` (radians or file units) instead of
    /// its start value; false (nothing changed) for the analysed input or one the mechanism lacks.
    pub fn hold(&mut self, i: usize, value: f64) -> bool {
        if i == self.input || i >= self.inputs.len() || !value.is_finite() {
            return false;
        }
        self.inputs[i] = value;
        self.cache.borrow_mut().clear();
        true
    }

    /// The same mechanism with the base params `values` (in the file's order, as
    /// `MechanismInfo::params`); false (nothing changed) for a wrong count.
    pub fn set_params(&mut self, values: &[f64]) -> bool {
        if values.len() != self.solver.params.len() {
            return false;
        }
        self.solver.params.copy_from_slice(values);
        self.cache.borrow_mut().clear();
        true
    }

    /// Every assembly configuration at input value `x` (radians or file units).
    pub fn configurations(&self, x: f64) -> Result<Vec<Vec<f64>>, String> {
        self.solve_at(x).map(|r| r.0)
    }

    /// [`Setup::configurations`] with the closed-form blocks' margins.
    fn solve_at(&self, x: f64) -> Result<Solved, String> {
        if !x.is_finite() {
            return Err(format!("input {x} is not finite"));
        }
        let mut inputs = self.inputs.clone();
        inputs[self.input] = x;
        self.solver.with_margins(&inputs).map_err(|e| {
            let at = self.show_input(x);
            format!("`{}` at {} = {at}: {e}", self.name, self.input_name)
        })
    }

    /// Pairs of `a` and `b` matched by increasing distance (each used once).
    fn greedy(&self, a: &[Vec<f64>], b: &[Vec<f64>]) -> Vec<(usize, usize)> {
        let mut d: Vec<(f64, usize, usize)> = Vec::new();
        for (i, x) in a.iter().enumerate() {
            for (j, y) in b.iter().enumerate() {
                d.push((self.dist(x, y), i, j));
            }
        }
        d.sort_by(|x, y| x.0.total_cmp(&y.0));
        let (mut ua, mut ub) = (vec![false; a.len()], vec![false; b.len()]);
        let mut out = Vec::new();
        for (_, i, j) in d {
            if !ua[i] && !ub[j] {
                (ua[i], ub[j]) = (true, true);
                out.push((i, j));
            }
        }
        out
    }

    /// Analyses the range `[from, to]` of the input (a full turn of an angle input is a circle)
    /// and labels every configuration at each of `at`.
    pub fn analyze(&self, from: f64, to: f64, at: &[f64]) -> Result<Analysis, String> {
        if !(from.is_finite() && to.is_finite() && to > from) {
            return Err(format!("the range {from} to {to} is empty or not finite"));
        }
        self.cache.borrow_mut().clear();
        self.solver.degenerate.borrow_mut().clear();
        let circular = self.input_is_angle && to - from >= TAU * (1.0 - 1e-12);
        let to = if circular { from + TAU } else { to };
        for &x in at {
            if !x.is_finite() || (!circular && !(from..=to).contains(&x)) {
                return Err(format!("--at {x} is outside the range {from} to {to}"));
            }
        }
        // An angle's inputs taken into the range's turn (`at` reported as given).
        let reduce = |x: f64| {
            if circular {
                from + (x - from).rem_euclid(TAU)
            } else {
                x
            }
        };
        let reduced: Vec<f64> = at.iter().map(|&x| reduce(x)).collect();
        // The grid: uniform cells, the start input and the `at` inputs (each a point where the
        // count is known), then the inputs where a cell hides a change of the count.
        let start = reduce(self.inputs[self.input]);
        let extra: Vec<f64> = reduced.iter().copied().chain([start]).collect();
        let width = if self.input_is_angle { 1.0 } else { to - from };
        let mut xs = grid::merged(&grid::uniform(from, to), &extra);
        for _ in 0..grid::ROUNDS {
            // Hidden changes, again on the cells they split (a second one in the same cell).
            for _ in 0..grid::PASSES {
                let found = self.hidden(&xs)?;
                if found.is_empty() {
                    break;
                }
                xs = grid::merged(&xs, &found);
            }
            let counts = xs
                .iter()
                .map(|&x| self.count(x))
                .collect::<Result<Vec<_>, _>>()?;
            let dead = self.dead_points(&xs, &counts)?;
            let (dead, zones) = dead::zones(dead, circular, width);
            // A whole turn without dead points starts away from any crossing's zone.
            let mut lo = from;
            while circular && dead::near_zone(&zones, lo, 2.0 * dead::GUARD * width, true) {
                lo += 3.0 * dead::GUARD * width;
            }
            let mut ivs = intervals(
                &dead,
                circular,
                lo,
                if dead.is_empty() { lo + to - from } else { to },
            );
            let mut changes = None;
            for v in &mut ivs {
                let samples = trace::samples(v, &xs, &reduced, width, circular, &zones);
                match self.track(&samples)? {
                    Traced::Tracks(t) => v.tracks = t,
                    Traced::Changes(x) => {
                        changes = Some(x);
                        break;
                    }
                }
            }
            if let Some(x) = changes {
                // A dead point the grid did not see: that input joins the grid.
                xs = grid::merged(&xs, &[reduce(x)]);
                continue;
            }
            let crossings = ivs
                .iter()
                .enumerate()
                .flat_map(|(i, v)| self.crossings(i, v, width))
                .collect();
            return self.finish(&ivs, dead, crossings, circular, (from, to), at, &reduced);
        }
        Err(format!(
            "the number of configurations of `{}` still changes inside an interval after {} \
             refinements of the grid: dead points too close to be told apart",
            self.name,
            grid::ROUNDS
        ))
    }

    /// The analysis from the traced intervals, the `at` inputs reported as given.
    #[allow(clippy::too_many_arguments)]
    fn finish(
        &self,
        ivs: &[Interval],
        dead: Vec<Dead>,
        crossings: Vec<crossing::Found>,
        circular: bool,
        (from, to): (f64, f64),
        at: &[f64],
        reduced: &[f64],
    ) -> Result<Analysis, String> {
        let mut a = self.structure(ivs, dead, &crossings, circular, (from, to), reduced)?;
        a.at_inputs = at.to_vec();
        if circular {
            for c in &mut a.crossings {
                // Into the range's turn; within rounding of its end, at its start.
                let r = (c.input - from).rem_euclid(TAU);
                c.input = from + if TAU - r <= 1e-9 { r - TAU } else { r };
            }
            a.crossings.sort_by(|x, y| x.input.total_cmp(&y.input));
        }
        for l in &mut a.at {
            if let Some(k) = reduced
                .iter()
                .position(|r| r.to_bits() == l.input.to_bits())
            {
                l.input = at[k];
            }
        }
        Ok(a)
    }
}

/// The intervals between the dead points (or range ends); around the circle for a full turn.
fn intervals(dead: &[Dead], circular: bool, from: f64, to: f64) -> Vec<Interval> {
    let iv = |lo: f64, hi: f64, a: Option<usize>, b: Option<usize>| Interval {
        lo,
        hi,
        dead: [a, b],
        tracks: Vec::new(),
    };
    let m = dead.len();
    let mut ivs = Vec::new();
    if circular && m > 0 {
        for k in 0..m {
            let hi = if k + 1 < m {
                dead[k + 1].input
            } else {
                dead[0].input + TAU
            };
            ivs.push(iv(dead[k].input, hi, Some(k), Some((k + 1) % m)));
        }
    } else {
        let mut lo = (from, None);
        for (k, d) in dead.iter().enumerate() {
            ivs.push(iv(lo.0, d.input, lo.1, Some(k)));
            lo = (d.input, Some(k));
        }
        ivs.push(iv(lo.0, to, lo.1, None));
    }
    ivs
}

mod structure;
