//! Part of stage 2 (semantics): the built-in names of the expression language, as one enum. Every
//! stage that meets a call or the name `pi` resolves it here once and matches on [`Builtin`]; no
//! stage compares the text of a built-in name.

use crate::diagnostic::{Diagnostic, Span};

/// A built-in function or constant of mechanism expressions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Builtin {
    /// `e(θ)`: the unit vector (cos θ, sin θ).
    E,
    /// `c(x, y)`: the vector (x, y).
    C,
    /// `deg(x)`: x degrees in radians.
    Deg,
    /// `pi`, a constant (not a function).
    Pi,
    Sin,
    Cos,
    Tan,
    Sqrt,
    /// Params only (from here on): functions of values that are fixed for a solve.
    Asin,
    Acos,
    Atan,
    /// `atan2(y, x)`.
    Atan2,
    Abs,
    /// `hypot(x, y)`.
    Hypot,
}

/// What a built-in function takes and gives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Signature {
    pub arity: usize,
    /// Its arguments are angles (radians): `e`, `sin`, `cos`, `tan`.
    pub angle_arguments: bool,
    /// It gives a vector (`e`, `c`); the others give a scalar.
    pub vector_result: bool,
}

impl Builtin {
    /// Every built-in, in the order the format spec lists them.
    pub const ALL: [Builtin; 14] = [
        Builtin::E,
        Builtin::C,
        Builtin::Deg,
        Builtin::Pi,
        Builtin::Sin,
        Builtin::Cos,
        Builtin::Tan,
        Builtin::Sqrt,
        Builtin::Asin,
        Builtin::Acos,
        Builtin::Atan,
        Builtin::Atan2,
        Builtin::Abs,
        Builtin::Hypot,
    ];

    pub fn from_name(name: &str) -> Option<Builtin> {
        Builtin::ALL.into_iter().find(|b| b.name() == name)
    }

    pub fn name(self) -> &'static str {
        match self {
            Builtin::E => "e",
            Builtin::C => "c",
            Builtin::Deg => "deg",
            Builtin::Pi => "pi",
            Builtin::Sin => "sin",
            Builtin::Cos => "cos",
            Builtin::Tan => "tan",
            Builtin::Sqrt => "sqrt",
            Builtin::Asin => "asin",
            Builtin::Acos => "acos",
            Builtin::Atan => "atan",
            Builtin::Atan2 => "atan2",
            Builtin::Abs => "abs",
            Builtin::Hypot => "hypot",
        }
    }

    /// Whether a declared name may not be this one: every built-in is reserved.
    pub fn is_reserved(name: &str) -> bool {
        Builtin::from_name(name).is_some()
    }

    /// `None` for the constant `pi`.
    pub fn signature(self) -> Option<Signature> {
        let f = |arity, angle_arguments, vector_result| {
            Some(Signature {
                arity,
                angle_arguments,
                vector_result,
            })
        };
        match self {
            Builtin::Pi => None,
            Builtin::E => f(1, true, true),
            Builtin::C => f(2, false, true),
            Builtin::Sin | Builtin::Cos | Builtin::Tan => f(1, true, false),
            Builtin::Atan2 | Builtin::Hypot => f(2, false, false),
            Builtin::Deg
            | Builtin::Sqrt
            | Builtin::Asin
            | Builtin::Acos
            | Builtin::Atan
            | Builtin::Abs => f(1, false, false),
        }
    }

    /// Allowed in param expressions only: loops and points are differentiated, and these are
    /// either not smooth (`abs`) or not needed there.
    pub fn params_only(self) -> bool {
        matches!(
            self,
            Builtin::Asin
                | Builtin::Acos
                | Builtin::Atan
                | Builtin::Atan2
                | Builtin::Abs
                | Builtin::Hypot
        )
    }

    /// The value of a scalar built-in at `args` (already checked for arity); `None` for the
    /// vector built-ins.
    pub fn eval(self, args: &[f64]) -> Option<f64> {
        let x = args.first().copied().unwrap_or(0.0);
        let y = args.get(1).copied().unwrap_or(0.0);
        Some(match self {
            Builtin::E | Builtin::C => return None,
            Builtin::Pi => std::f64::consts::PI,
            Builtin::Deg => x.to_radians(),
            Builtin::Sin => x.sin(),
            Builtin::Cos => x.cos(),
            Builtin::Tan => x.tan(),
            Builtin::Sqrt => x.sqrt(),
            Builtin::Asin => x.asin(),
            Builtin::Acos => x.acos(),
            Builtin::Atan => x.atan(),
            Builtin::Atan2 => x.atan2(y),
            Builtin::Abs => x.abs(),
            Builtin::Hypot => x.hypot(y),
        })
    }

    /// The functions allowed where `params_only` says, as a note lists them.
    pub fn function_list(in_params: bool) -> String {
        Builtin::ALL
            .into_iter()
            .filter(|b| b.signature().is_some() && (in_params || !b.params_only()))
            .map(Builtin::name)
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The error for a call of a name that is no function.
pub fn undefined_function(name: &str, span: Span, in_params: bool) -> Diagnostic {
    Diagnostic::error(span, format!("undefined function `{name}`"))
        .with_note(format!("functions: {}", Builtin::function_list(in_params)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_are_distinct() {
        for b in Builtin::ALL {
            assert_eq!(Builtin::from_name(b.name()), Some(b));
        }
        let mut names: Vec<_> = Builtin::ALL.iter().map(|b| b.name()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), Builtin::ALL.len());
        assert_eq!(Builtin::from_name("exp"), None);
    }

    #[test]
    fn params_only_functions_are_left_out_of_loop_notes() {
        assert_eq!(
            Builtin::function_list(false),
            "e, c, deg, sin, cos, tan, sqrt"
        );
        assert!(Builtin::function_list(true).ends_with("atan2, abs, hypot"));
    }

    #[test]
    fn scalar_functions_evaluate() {
        assert_eq!(
            Builtin::Atan2.eval(&[1.0, 0.0]),
            Some(std::f64::consts::FRAC_PI_2)
        );
        assert_eq!(Builtin::Hypot.eval(&[3.0, 4.0]), Some(5.0));
        assert_eq!(Builtin::Abs.eval(&[-2.5]), Some(2.5));
        assert_eq!(Builtin::Deg.eval(&[180.0]), Some(std::f64::consts::PI));
        assert_eq!(Builtin::E.eval(&[0.0]), None);
        // asin outside [-1, 1] is NaN: the caller's finiteness check reports it.
        assert!(Builtin::Asin.eval(&[2.0]).is_some_and(f64::is_nan));
    }
}
