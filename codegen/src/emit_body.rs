//! Stage 6a: straight-line code for a set of DAG roots. Every reachable node becomes one
//! `let tN = …;` in DAG order (children first, so CSE is already done); a sine and cosine of one
//! argument become one `sin_cos()` call; constants and variables are written inline.

use std::collections::HashMap;

use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

use crate::dag::{Dag, Node, NodeId, Var};

/// How variables are read inside an emitted function.
pub trait VarSource {
    /// The local name a variable is bound to, and the expression that reads it from the arguments.
    fn bind(&self, v: Var) -> (Ident, TokenStream);
    /// An expression giving `(sin v, cos v)` without computing them (a cache), if there is one.
    fn trig(&self, v: Var) -> Option<TokenStream> {
        let _ = v;
        None
    }
}

/// Statements computing `roots`, and the expression (an identifier or a literal) of each root.
pub struct Body {
    pub stmts: TokenStream,
    pub roots: Vec<TokenStream>,
}

/// Emits the code for `roots`. Only nodes reachable from them are computed.
pub fn body(dag: &Dag, roots: &[NodeId], vars: &dyn VarSource) -> Body {
    Builder::new(dag, vars).segment(roots)
}

/// Straight-line code in segments that share one scope: a node computed by an earlier segment
/// is reused by name, not recomputed (CSE across the segments of one function). Between
/// segments the caller emits its own statements (a block solve), which may write the arrays
/// later segments read: a variable is bound where it is first used.
pub struct Builder<'a> {
    dag: &'a Dag,
    vars: &'a dyn VarSource,
    names: Vec<Option<TokenStream>>,
    temp: usize,
}

impl<'a> Builder<'a> {
    pub fn new(dag: &'a Dag, vars: &'a dyn VarSource) -> Self {
        Builder {
            dag,
            vars,
            names: vec![None; dag.nodes().len()],
            temp: 0,
        }
    }

    /// The statements computing `roots` that earlier segments did not, and each root's
    /// expression.
    pub fn segment(&mut self, roots: &[NodeId]) -> Body {
        let (dag, vars) = (self.dag, self.vars);
        let n = roots.iter().map(|r| r.index() + 1).max().unwrap_or(0);
        let mut live = vec![false; n];
        let mut stack: Vec<NodeId> = roots.to_vec();
        while let Some(id) = stack.pop() {
            if self.names[id.index()].is_none() && !std::mem::replace(&mut live[id.index()], true) {
                stack.extend(dag.node(id).children());
            }
        }
        // Sine and cosine of the same argument, both live: one sin_cos.
        let mut sin_of: HashMap<NodeId, NodeId> = HashMap::new();
        let mut cos_of: HashMap<NodeId, NodeId> = HashMap::new();
        for (i, node) in dag.nodes()[..n].iter().enumerate() {
            if !live[i] {
                continue;
            }
            match *node {
                Node::Sin(a) => {
                    sin_of.insert(a, NodeId(i as u32));
                }
                Node::Cos(a) => {
                    cos_of.insert(a, NodeId(i as u32));
                }
                _ => {}
            }
        }

        let names = &mut self.names;
        let mut stmts = TokenStream::new();
        let mut var_binds: Vec<(Var, TokenStream)> = Vec::new();
        for (i, node) in dag.nodes()[..n].iter().enumerate() {
            if !live[i] || names[i].is_some() {
                continue;
            }
            let name = |id: NodeId, names: &[Option<TokenStream>]| {
                names[id.index()].clone().unwrap_or_default()
            };
            let expr = match *node {
                Node::Const(b) => {
                    names[i] = Some(literal(f64::from_bits(b)));
                    continue;
                }
                Node::Var(v) => {
                    let (ident, read) = vars.bind(v);
                    var_binds.push((v, quote!(let #ident = #read;)));
                    names[i] = Some(quote!(#ident));
                    continue;
                }
                Node::Sin(a) | Node::Cos(a) if matches!(dag.node(a), Node::Var(v) if vars.trig(v).is_some()) =>
                {
                    let Node::Var(v) = dag.node(a) else { continue };
                    let (ident, _) = vars.bind(v);
                    let (sn, cn) = (format_ident!("s_{}", ident), format_ident!("c_{}", ident));
                    let src = vars.trig(v).unwrap_or_default();
                    stmts.extend(quote!(let (#sn, #cn) = #src;));
                    // Both names are bound, whichever a later segment asks for.
                    let (s, c) = (dag.find(&Node::Sin(a)), dag.find(&Node::Cos(a)));
                    for (id, nm) in [(s, &sn), (c, &cn)] {
                        if let Some(id) = id {
                            names[id.index()] = Some(quote!(#nm));
                        }
                    }
                    continue;
                }
                Node::Sin(a) | Node::Cos(a)
                    if sin_of.contains_key(&a) && cos_of.contains_key(&a) =>
                {
                    let (s, c) = (sin_of[&a], cos_of[&a]);
                    let (sn, cn) = match dag.node(a) {
                        Node::Var(v) => {
                            let (ident, _) = vars.bind(v);
                            (format_ident!("s_{}", ident), format_ident!("c_{}", ident))
                        }
                        _ => (
                            format_ident!("s{}", self.temp),
                            format_ident!("c{}", self.temp),
                        ),
                    };
                    self.temp += 1;
                    let arg = name(a, names);
                    stmts.extend(quote!(let (#sn, #cn) = #arg.sin_cos();));
                    names[s.index()] = Some(quote!(#sn));
                    names[c.index()] = Some(quote!(#cn));
                    continue;
                }
                Node::Add(a, b) => {
                    let (a, b) = (name(a, names), name(b, names));
                    quote!(#a + #b)
                }
                Node::Sub(a, b) => {
                    let (a, b) = (name(a, names), name(b, names));
                    quote!(#a - #b)
                }
                Node::Mul(a, b) => {
                    let (a, b) = (name(a, names), name(b, names));
                    quote!(#a * #b)
                }
                Node::Div(a, b) => {
                    let (a, b) = (name(a, names), name(b, names));
                    quote!(#a / #b)
                }
                Node::Neg(a) => {
                    let a = name(a, names);
                    quote!(-#a)
                }
                Node::Sin(a) => {
                    let a = name(a, names);
                    quote!(#a.sin())
                }
                Node::Cos(a) => {
                    let a = name(a, names);
                    quote!(#a.cos())
                }
                Node::Tan(a) => {
                    let a = name(a, names);
                    quote!(#a.tan())
                }
                Node::Sqrt(a) => {
                    let a = name(a, names);
                    quote!(#a.sqrt())
                }
            };
            let t = format_ident!("t{}", self.temp);
            self.temp += 1;
            stmts.extend(quote!(let #t = #expr;));
            names[i] = Some(quote!(#t));
        }
        var_binds.sort_by_key(|(v, _)| *v);
        let mut all: TokenStream = var_binds.into_iter().map(|(_, s)| s).collect();
        all.extend(stmts);
        let roots = roots
            .iter()
            .map(|r| names[r.index()].clone().unwrap_or_default())
            .collect();
        Body { stmts: all, roots }
    }
}

/// A constant in generic scalar code.
pub fn literal(x: f64) -> TokenStream {
    if x == 0.0 {
        return quote!(T::zero());
    }
    if x == 1.0 {
        return quote!(T::one());
    }
    let lit = Literal::f64_unsuffixed(x.abs());
    if x < 0.0 {
        quote!(T::lit(-#lit))
    } else {
        quote!(T::lit(#lit))
    }
}
