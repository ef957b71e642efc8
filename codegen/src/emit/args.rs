//! What every emitter of a mechanism's module shares: [`Args`] (variables read from the generated
//! functions' arguments, the runtime path and the module's item names), the array sizes, the
//! length-scale body, the type's name and equation labels. A leaf of `emit`: the emitters use it,
//! it uses none of them.

use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

use super::body::VarSource;
use super::names::ModuleItems;
use crate::ir::dag::Var;
use crate::ir::lower::Equation;
use crate::sema::model::Model;

/// The body of a length scale: the largest `|value|` of `lengths` (expressions), or 1 when there
/// is none or all are zero (a mechanism's `length_scale`, a scene's over the params it reads).
pub(crate) fn largest_length(gt: &Ident, lengths: &[TokenStream]) -> TokenStream {
    if lengths.is_empty() {
        return quote!(#gt::one());
    }
    quote! {
        let mut s = #gt::zero();
        #( s = s.max(#lengths.abs()); )*
        if s > #gt::zero() { s } else { #gt::one() }
    }
}

/// The mechanism's type: `four_bar` → `FourBar` (see [`ModuleItems`] for the rare exception).
pub fn type_ident(model: &Model) -> Ident {
    ModuleItems::new(&model.name.text).ty
}

/// Reads variables from the generated functions' arguments `x, q, xd, qd, xdd, qdd` and
/// `self.params`; carries what every emitter of the module needs: the runtime path (`rt`,
/// ending in `__private`) and the module's item names.
pub(crate) struct Args<'a> {
    pub model: &'a Model,
    pub rt: TokenStream,
    pub items: ModuleItems,
}

impl VarSource for Args<'_> {
    fn read(&self, v: Var) -> TokenStream {
        let (arr, i) = match v {
            Var::X(i) => (quote!(x), i),
            Var::Q(i) => (quote!(q), i),
            Var::Xd(i) => (quote!(xd), i),
            Var::Qd(i) => (quote!(qd), i),
            Var::Xdd(i) => (quote!(xdd), i),
            Var::Qdd(i) => (quote!(qdd), i),
            Var::P(i) => {
                let f = format_ident!("{}", self.model.params[i as usize].name.text);
                return quote!(self.params.#f);
            }
        };
        let i = i as usize;
        quote!(#arr[#i])
    }
    fn hint(&self, v: Var) -> String {
        let m = self.model;
        let (name, what) = match v {
            Var::X(i) => (&m.inputs[i as usize].name.text, ""),
            Var::Q(i) => (&m.unknowns[i as usize].name.text, ""),
            Var::Xd(i) => (&m.inputs[i as usize].name.text, "_d"),
            Var::Qd(i) => (&m.unknowns[i as usize].name.text, "_d"),
            Var::Xdd(i) => (&m.inputs[i as usize].name.text, "_dd"),
            Var::Qdd(i) => (&m.unknowns[i as usize].name.text, "_dd"),
            Var::P(i) => return format!("p_{}", m.params[i as usize].name.text),
        };
        // A readable proposal only: the names table keeps `a_d` and the rate of `a` apart.
        format!("v_{name}{what}")
    }
    fn scalar(&self) -> &Ident {
        &self.items.scalar
    }
}

/// How many inputs, unknowns, points and params a mechanism has (the sizes of its arrays).
pub(crate) fn sizes(m: &Model) -> (usize, usize, usize, usize) {
    (
        m.inputs.len(),
        m.unknowns.len(),
        m.points.len(),
        m.params.len(),
    )
}

/// `loop 2, y` for equation 3.
pub(crate) fn equation_name(m: &Model, e: usize) -> String {
    let _ = m;
    let e = crate::ir::lower::Equation(e);
    format!("loop {}, {}", e.loop_index() + 1, e.axis().name())
}

/// `loop 1 (x, y), loop 2 (x)` for a block's equations.
pub(crate) fn equations_text(eqs: &[Equation]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < eqs.len() {
        let l = eqs[i].loop_index();
        let comps: Vec<&str> = eqs[i..]
            .iter()
            .take_while(|e| e.loop_index() == l)
            .map(|e| e.axis().name())
            .collect();
        i += comps.len();
        parts.push(format!("loop {} ({})", l + 1, comps.join(", ")));
    }
    parts.join(", ")
}
