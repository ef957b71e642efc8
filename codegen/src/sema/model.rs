//! Part of stage 2 (semantics): what checking produces. A [`Model`] is one mechanism with every
//! name resolved to a [`Symbol`], every coordinate and param classified as angle or length, and
//! its params and start values evaluated.

use std::collections::HashMap;

use super::resolved::{DerivedId, InputId, ParamId, Scalar, UnknownId, Vector};
use crate::diagnostic::Span;
use crate::front::ast::{Expr, Name};

/// Angle (radians) or length (file units), inferred from use: the runtime's one `Kind`, which
/// generated code and run-time engines name too.
pub use mechgen_runtime::Kind;

/// What a name refers to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Symbol {
    Input(InputId),
    Unknown(UnknownId),
    Param(ParamId),
    /// A derived param: defined by an expression of other params.
    Derived(DerivedId),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Coord {
    pub name: Name,
    pub kind: Kind,
    /// Value in the `start` configuration.
    pub start: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    pub name: Name,
    pub kind: Kind,
    /// Default value (the file's expression evaluated in f64).
    pub value: f64,
    /// The expression as written when it was not a plain number.
    pub source: Option<String>,
    /// The params its expression uses (earlier params, base or derived). A param that uses others
    /// is derived: its value follows from theirs.
    pub uses: Vec<Symbol>,
    /// Its expression (a number for a plain param), as written and resolved.
    pub expr: Expr,
    pub resolved: Scalar,
}

impl Param {
    /// Whether its value follows from other params.
    pub fn is_derived(&self) -> bool {
        !self.uses.is_empty()
    }
}

/// A checked scene: which unknowns and points it reads, and up to which derivative order.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub name: Name,
    pub unknowns: Vec<usize>,
    pub points: Vec<usize>,
    pub order: u8,
}

/// A checked mechanism: every name resolved, every expression well typed.
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    pub name: Name,
    pub description: String,
    pub inputs: Vec<Coord>,
    pub unknowns: Vec<Coord>,
    /// The base params: free values, the fields of the generated `Params` (`Symbol::Param`).
    pub params: Vec<Param>,
    /// The derived params, in file order (`Symbol::Derived`): not free values. Lowering
    /// substitutes their expressions, so the solvers recompute them from the base params and a
    /// change of a base param at run time carries through.
    pub derived: Vec<Param>,
    /// The loops and points as written (spans, drawing) and resolved (what lowering reads).
    pub loops: Vec<Expr>,
    pub points: Vec<(Name, Expr)>,
    pub loop_vectors: Vec<Vector>,
    pub point_vectors: Vec<Vector>,
    pub scenes: Vec<Scene>,
    pub symbols: HashMap<String, Symbol>,
    /// Where the `start` values are written (the mechanism name when there are none).
    pub start_span: Span,
    /// The moving bodies' mass properties and gravity, for dynamics (the kinematics never read
    /// them); `None` without a `gravity` key.
    pub bodies: Vec<Body>,
    pub gravity: Option<Vector>,
    /// The bodies' and gravity's expressions as written (which params they name).
    pub dynamics_written: Vec<Expr>,
}

/// A checked body: its orientation, centre of mass, mass and inertia about the centre.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub name: Name,
    pub angle: Scalar,
    pub com: Centre,
    /// Mass and inertia at the file's params (checked finite and at least zero).
    pub mass: f64,
    pub inertia: f64,
    /// Their expressions of params, which the solvers evaluate (so they follow a param change).
    pub mass_expr: Scalar,
    pub inertia_expr: Scalar,
}

/// A body's centre of mass: one of the mechanism's points (by index) or a vector expression.
#[derive(Clone, Debug, PartialEq)]
pub enum Centre {
    Point(usize),
    Vector(Vector),
}
