//! Part of stage 2 (semantics): the resolved expression tree, what checking hands to lowering.
//! Every name is a typed id, every call a built-in with exactly its arguments, and scalar and
//! vector expressions are different types, so lowering is a total match: it cannot meet an
//! undefined name, a wrong arity or a vector where a scalar belongs, and never defaults.

/// An input of its mechanism (index into `Model::inputs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct InputId(pub u16);

/// An unknown of its mechanism (index into `Model::unknowns`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct UnknownId(pub u16);

/// A base param of its mechanism (index into `Model::params`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ParamId(pub u16);

/// A derived param of its mechanism (index into `Model::derived`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct DerivedId(pub u16);

// The parser caps every list of a mechanism at `MAX_ITEMS`, so every index fits an id.
const _: () = assert!(crate::front::parse::MAX_ITEMS <= u16::MAX as usize);

macro_rules! index {
    ($($id:ident),*) => {$(
        impl $id {
            /// The id of entry `i` (below the parser's `MAX_ITEMS`).
            pub fn new(i: usize) -> Self {
                $id(i as u16)
            }
            pub fn index(self) -> usize {
                usize::from(self.0)
            }
        }

    )*};
}
index!(InputId, UnknownId, ParamId, DerivedId);

/// A scalar function of one argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Fn1 {
    Sin,
    Cos,
    Tan,
    Sqrt,
    /// Degrees to radians.
    Deg,
    /// Params only (the checker allows them in param expressions alone).
    Asin,
    Acos,
    Atan,
    Abs,
}

/// A scalar function of two arguments (params only).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Fn2 {
    /// `atan2(y, x)`.
    Atan2,
    Hypot,
}

/// The four arithmetic operations.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Op {
    Add,
    Sub,
    Mul,
    Div,
}

/// A resolved scalar expression.
#[derive(Clone, Debug, PartialEq)]
pub enum Scalar {
    Number(f64),
    Input(InputId),
    Unknown(UnknownId),
    Param(ParamId),
    /// A derived param: lowering substitutes its expression (`Model::derived[j].resolved`).
    Derived(DerivedId),
    Neg(Box<Scalar>),
    Binary(Op, Box<Scalar>, Box<Scalar>),
    Call1(Fn1, Box<Scalar>),
    Call2(Fn2, Box<Scalar>, Box<Scalar>),
}

/// A resolved planar vector expression.
#[derive(Clone, Debug, PartialEq)]
pub enum Vector {
    /// `e(θ)`: (cos θ, sin θ).
    E(Box<Scalar>),
    /// `c(x, y)`.
    C(Box<Scalar>, Box<Scalar>),
    /// A scalar term of a vector sum: (s, 0).
    Real(Box<Scalar>),
    Neg(Box<Vector>),
    Add(Box<Vector>, Box<Vector>),
    Sub(Box<Vector>, Box<Vector>),
    /// `s * v`.
    Scale(Box<Scalar>, Box<Vector>),
    /// `v * s`.
    Times(Box<Vector>, Box<Scalar>),
    /// `v / s`.
    Div(Box<Vector>, Box<Scalar>),
}

/// A resolved expression of either type: what the checker's typing pass gives.
#[derive(Clone, Debug, PartialEq)]
pub enum Resolved {
    Scalar(Scalar),
    Vector(Vector),
}

impl Resolved {
    /// As a vector (a scalar is the vector (s, 0), as in a vector sum).
    pub fn into_vector(self) -> Vector {
        match self {
            Resolved::Vector(v) => v,
            Resolved::Scalar(s) => Vector::Real(Box::new(s)),
        }
    }

    /// As a scalar, when it is one.
    pub fn into_scalar(self) -> Option<Scalar> {
        match self {
            Resolved::Scalar(s) => Some(s),
            Resolved::Vector(_) => None,
        }
    }

    /// `a op b` when the types allow it (the checker reports the others).
    pub fn binary(op: Op, a: Resolved, b: Resolved) -> Option<Resolved> {
        use Resolved::{Scalar as S, Vector as V};
        Some(match (op, a, b) {
            (op, S(x), S(y)) => S(Scalar::Binary(op, Box::new(x), Box::new(y))),
            (Op::Add, a, b) => V(Vector::Add(
                Box::new(a.into_vector()),
                Box::new(b.into_vector()),
            )),
            (Op::Sub, a, b) => V(Vector::Sub(
                Box::new(a.into_vector()),
                Box::new(b.into_vector()),
            )),
            (Op::Mul, S(s), V(v)) => V(Vector::Scale(Box::new(s), Box::new(v))),
            (Op::Mul, V(v), S(s)) => V(Vector::Times(Box::new(v), Box::new(s))),
            (Op::Div, V(v), S(s)) => V(Vector::Div(Box::new(v), Box::new(s))),
            (Op::Mul, V(_), V(_)) | (Op::Div, _, V(_)) => return None,
        })
    }

    pub fn neg(self) -> Resolved {
        match self {
            Resolved::Scalar(s) => Resolved::Scalar(Scalar::Neg(Box::new(s))),
            Resolved::Vector(v) => Resolved::Vector(Vector::Neg(Box::new(v))),
        }
    }
}

/// One term of a vector sum: a vector, or a scalar read as (s, 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Term<'a> {
    Vector(&'a Vector),
    Scalar(&'a Scalar),
}

impl Vector {
    /// The terms of a sum with their signs (`true` = added), through sums, differences and
    /// negations, of vectors and of the scalars in it (a loop's links, for drawing).
    pub fn terms<'a>(&'a self, sign: bool, out: &mut Vec<(Term<'a>, bool)>) {
        match self {
            Vector::Add(a, b) => {
                a.terms(sign, out);
                b.terms(sign, out);
            }
            Vector::Sub(a, b) => {
                a.terms(sign, out);
                b.terms(!sign, out);
            }
            Vector::Neg(a) => a.terms(!sign, out),
            Vector::Real(s) => s.terms(sign, out),
            _ => out.push((Term::Vector(self), sign)),
        }
    }
}

impl Scalar {
    fn terms<'a>(&'a self, sign: bool, out: &mut Vec<(Term<'a>, bool)>) {
        match self {
            Scalar::Binary(Op::Add, a, b) => {
                a.terms(sign, out);
                b.terms(sign, out);
            }
            Scalar::Binary(Op::Sub, a, b) => {
                a.terms(sign, out);
                b.terms(!sign, out);
            }
            Scalar::Neg(a) => a.terms(!sign, out),
            _ => out.push((Term::Scalar(self), sign)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{SourceFile, analyze};

    const FILE: &str = r#"
[mechanism.m]
inputs = ["x"]
unknowns = ["q", "s"]
loops = ["r*e(q) - s*c(1, 0) - 2*k + x/2"]
points = { P = "e(q)*r" }
[mechanism.m.params]
r = 0.3
k = "r + 1"
[mechanism.m.start]
x = 0.0
q = 0.0
s = -2.3
"#;

    fn b<T>(t: T) -> Box<T> {
        Box::new(t)
    }

    /// Names become typed ids, scalar terms of a vector sum `Real`, the operands of `*` keep
    /// their order, and a derived param resolves to its own tree.
    #[test]
    fn loops_points_and_derived_params_resolve_to_typed_trees() {
        let (mechs, diags) = analyze(&SourceFile::new("m.toml", FILE));
        assert!(diags.iter().all(|d| !d.is_error()), "{diags:?}");
        let m = &mechs[0].model;
        let (q, s, x) = (
            Scalar::Unknown(UnknownId(0)),
            Scalar::Unknown(UnknownId(1)),
            Scalar::Input(InputId(0)),
        );
        let (r, k) = (Scalar::Param(ParamId(0)), Scalar::Derived(DerivedId(0)));
        let rq = Vector::Scale(b(r.clone()), b(Vector::E(b(q.clone()))));
        let s_c = Vector::Scale(
            b(s),
            b(Vector::C(b(Scalar::Number(1.0)), b(Scalar::Number(0.0)))),
        );
        let two_k = Scalar::Binary(Op::Mul, b(Scalar::Number(2.0)), b(k));
        let half_x = Scalar::Binary(Op::Div, b(x), b(Scalar::Number(2.0)));
        let want = Vector::Add(
            b(Vector::Sub(
                b(Vector::Sub(b(rq), b(s_c))),
                b(Vector::Real(b(two_k))),
            )),
            b(Vector::Real(b(half_x))),
        );
        assert_eq!(m.loop_vectors, [want]);
        assert_eq!(
            m.point_vectors,
            [Vector::Times(b(Vector::E(b(q))), b(r.clone()))]
        );
        let one = Scalar::Number(1.0);
        assert_eq!(m.derived[0].resolved, Scalar::Binary(Op::Add, b(r), b(one)));
        // The drawing terms: signs through the sums, scalar terms split.
        let mut terms = Vec::new();
        m.loop_vectors[0].terms(true, &mut terms);
        let signs: Vec<bool> = terms.iter().map(|t| t.1).collect();
        assert_eq!(signs, [true, false, false, true]);
    }
}
