//! Stage 1 output: the syntax tree of a mechanism file, every node with its byte span in the file.

use crate::diagnostic::Span;

/// A name as written, with where it was written.
#[derive(Clone, Debug, PartialEq)]
pub struct Name {
    pub text: String,
    pub span: Span,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
}

#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    Number(f64),
    Name(String),
    Neg(Box<Expr>),
    Binary(BinOp, Box<Expr>, Box<Expr>),
    /// `e(θ)`, `c(x, y)`, `deg(x)`, `sin(x)`, … (the callee is checked later).
    Call(Name, Vec<Expr>),
}

/// An expression of the file: a TOML number or a parsed expression string.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

/// `[mechanism.NAME]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Mechanism {
    pub name: Name,
    pub description: Option<String>,
    pub inputs: Vec<Name>,
    pub unknowns: Vec<Name>,
    pub loops: Vec<Expr>,
    /// How many loop strings the file gives (parsed or not); `None` without a `loops` key.
    pub loop_count: Option<usize>,
    /// The parser reported errors inside this table (it is still checked, but yields no model).
    pub parse_errors: bool,
    pub params: Vec<(Name, Expr)>,
    pub points: Vec<(Name, Expr)>,
    pub start: Vec<(Name, Expr)>,
    /// `gravity = "c(0, -9.81)"`: the acceleration of gravity (for dynamics only).
    pub gravity: Option<Expr>,
    /// `[mechanism.NAME.bodies.B]`: the moving bodies' mass properties (for dynamics only).
    pub bodies: Vec<Body>,
}

/// `[mechanism.NAME.bodies.B]`: a body's orientation, mass, centre of mass and inertia as written
/// (each `None` where the table does not give it).
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub name: Name,
    pub angle: Option<Expr>,
    pub mass: Option<Expr>,
    pub com: Option<Expr>,
    pub inertia: Option<Expr>,
}

/// `[scene.NAME]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub name: Name,
    pub mechanism: Option<Name>,
    pub outputs: Vec<Name>,
    pub order: Option<(i64, Span)>,
}

/// A whole mechanism file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct File {
    pub mechanisms: Vec<Mechanism>,
    pub scenes: Vec<Scene>,
    /// The TOML itself did not parse; nothing was read.
    pub syntax_errors: bool,
}
