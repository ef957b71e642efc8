//! Stage 6: the sine and cosine caches of generated solvers: which inputs, unknowns and params
//! appear as the argument of a sine or cosine (`trig_masks`), and a [`VarSource`] that reads those
//! from the caches `tx`, `tq` and `tp` (`Cached`).

use proc_macro2::{Ident, TokenStream};
use quote::quote;

use crate::analysis::Compiled;
use crate::emit::args::Args;
use crate::emit::body::VarSource;
use crate::ir::dag::{Node, Var};

/// Variables whose sine and cosine come from caches.
pub(crate) struct Cached<'a> {
    pub(crate) args: &'a Args<'a>,
    /// Inputs, unknowns and params that appear as the argument of a sin or cos.
    pub(crate) x: Vec<bool>,
    pub(crate) q: Vec<bool>,
    pub(crate) p: Vec<bool>,
}

impl VarSource for Cached<'_> {
    fn read(&self, v: Var) -> TokenStream {
        self.args.read(v)
    }
    fn hint(&self, v: Var) -> String {
        self.args.hint(v)
    }
    fn scalar(&self) -> &Ident {
        self.args.scalar()
    }
    fn trig(&self, v: Var) -> Option<TokenStream> {
        let (mask, arr, i) = match v {
            Var::X(i) => (&self.x, quote!(tx), i as usize),
            Var::Q(i) => (&self.q, quote!(tq), i as usize),
            Var::P(i) => (&self.p, quote!(tp), i as usize),
            _ => return None,
        };
        mask[i].then(|| quote!(#arr[#i]))
    }
}

pub(crate) fn trig_masks(c: &Compiled) -> (Vec<bool>, Vec<bool>, Vec<bool>) {
    let m = &c.model;
    let (mut x, mut q, mut p) = (
        vec![false; m.inputs.len()],
        vec![false; m.unknowns.len()],
        vec![false; m.params.len()],
    );
    let dag = &c.system.dag;
    for n in dag.nodes() {
        if let Node::Sin(a) | Node::Cos(a) = *n {
            match dag.node(a) {
                Node::Var(Var::X(i)) => x[i as usize] = true,
                Node::Var(Var::Q(i)) => q[i as usize] = true,
                Node::Var(Var::P(i)) => p[i as usize] = true,
                _ => {}
            }
        }
    }
    (x, q, p)
}
