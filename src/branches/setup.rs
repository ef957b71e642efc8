//! The mechanism prepared for branch identification ([`Setup`]): its solver and tapes, the
//! analysed input and the cache of configurations, and the refinement of a dead point by the
//! bordered system ([`Tapes::fold`]). Its other methods live with the part of the analysis that
//! uses them (`mod.rs`, `crossing`, `grid`, `trace`).

use std::cell::RefCell;
use std::collections::HashMap;

use super::singular::Tapes;
use super::solve::Solver;

/// The configurations at an input and the closed-form blocks' margins met on the way.
pub(super) type Solved = (Vec<Vec<f64>>, Vec<f64>);

/// A mechanism prepared for branch identification along one input (the others held).
#[derive(Clone, Debug)]
pub struct Setup {
    pub(super) solver: Solver,
    /// The whole mechanism's residuals and Jacobians (for singular configurations).
    pub(super) tapes: Tapes,
    pub(super) inputs: Vec<f64>,
    /// Index of the analysed input.
    pub input: usize,
    pub input_is_angle: bool,
    /// Per unknown: whether it is an angle.
    pub angle: Vec<bool>,
    /// The largest length param (or 1): lengths are compared relative to it.
    pub scale: f64,
    pub name: String,
    pub input_name: String,
    pub unknown_names: Vec<String>,
    /// Configurations already computed in this analysis, by the input's bits.
    pub(super) cache: RefCell<HashMap<u64, Solved>>,
}

impl Setup {
    /// The dead point near the bisected `(x0, q0)` to rounding level, or `(x0, q0)` itself when
    /// the bordered system does not settle there.
    pub(super) fn refine_fold(&self, x0: f64, q0: Vec<f64>) -> (f64, Vec<f64>) {
        let unit = |angle: bool| if angle { 1.0 } else { 1.0 / self.scale };
        let weights: Vec<f64> = (self.angle.iter().map(|&a| unit(a)))
            .chain([unit(self.input_is_angle)])
            .collect();
        match self.tapes.fold(
            &self.inputs,
            self.input,
            x0,
            &q0,
            &self.solver.params,
            &weights,
        ) {
            Some((x, q)) => (x, q),
            None => (x0, q0),
        }
    }
}
